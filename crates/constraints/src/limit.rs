//! A joint-coordinate limit: one unilateral row g(q) ≥ 0 on a coordinate c of a joint
//! ([`Measure`]: an angle, a slide, an offset, a distance, ...), the end stop of a hinge or the
//! stroke of a cylinder.
//!
//! ```text
//! g = c(q) − lo   (lower limit, Bound::Lower)        g = hi − c(q)   (upper limit, Bound::Upper)
//! g_q = ±∇c,   γ# = ∓(velocity-quadratic part of c̈),   ν = 0          1 row
//! ```
//!
//! with d = P_j − P_i and the global marker axes x_k, y_k, z_k (as [`crate::Joint::coordinates`]):
//!
//! | measure | c |
//! |---|---|
//! | angle | atan2(y_iᵀx_j, x_iᵀx_j) |
//! | slide, offset_x, offset_y, offset_z | z_iᵀd, x_iᵀd, y_iᵀd, z_iᵀd |
//! | distance | \|d\| |
//! | cross_angle_i, cross_angle_j | atan2(y_iᵀz_j, x_iᵀz_j), atan2(y_jᵀz_i, x_jᵀz_i) |
//! | bryant_x, bryant_y, bryant_z | atan2(−y_iᵀz_j, z_iᵀz_j), asin(x_iᵀz_j), atan2(−x_iᵀy_j, x_iᵀx_j) |
//! | axis_angle | atan2(−y_iᵀz_j, z_iᵀz_j) |
//! | bend | atan2(\|z_i × z_j\|, z_iᵀz_j) |
//! | azimuth | atan2(y_iᵀd, x_iᵀd) |
//!
//! An atan2 angle ([`Measure::turns`]) is continued over turns from a reference (the angle at
//! the last accepted pose, [`JointLimit::reference`], as the couplers do,
//! [`crate::couplers::angle`]), so a revolute limit of ±270° holds; its derivatives do not
//! depend on the reference. The gradients and γ# come from the jets of the marker vectors
//! ([`crate::jet`]) through ∇atan2, ∇asin and ∇|·|: both forms from one derivation.
//!
//! A limit is not an equation of the mechanism: an analysis watches g and, where it closes
//! (g = 0 with ġ < 0), treats the row as an equality Φ = g = 0 (a persistent contact) or as the
//! row of an impact's impulse equations (Haug 1989 §11.6 (impact), Pfeiffer & Glocker 1996 ch. 6
//! (unilateral constraints)). As a [`Constraint`] it is the row g itself.

use crate::constraint::{Constraint, Dimension};
use crate::couplers::angle::{angle_grad, angle_motion, asin_grad, asin_motion, continued_angle};
use crate::jet::{Form, Grad, Motion, ScalarGrad, ScalarMotion, Side};
use crate::joints::{Axis, CoordinateQuantity, Measure};
use crate::marker::Marker;
use crate::state::{BlockUse, BodyPair, Footprint};

/// Which end of a coordinate's range a limit holds.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Bound {
    /// c ≥ lo: g = c − lo.
    Lower,
    /// c ≤ hi: g = hi − c.
    Upper,
}

impl Bound {
    /// ∂g/∂c: +1 for a lower limit, −1 for an upper one.
    pub fn sign(self) -> f64 {
        match self {
            Bound::Lower => 1.0,
            Bound::Upper => -1.0,
        }
    }

    /// "lower" or "upper".
    pub fn name(self) -> &'static str {
        match self {
            Bound::Lower => "lower",
            Bound::Upper => "upper",
        }
    }
}

/// g = ±(c − value) ≥ 0 for the coordinate c of the two markers ([`Measure`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct JointLimit {
    /// The joint's marker on body i.
    pub marker_i: Marker,
    /// The joint's marker on body j.
    pub marker_j: Marker,
    /// The coordinate limited.
    pub measure: Measure,
    /// Which end.
    pub bound: Bound,
    /// lo or hi (rad or m).
    pub value: f64,
    /// The continued angle at the last accepted pose (angles of [`Measure::turns`] only).
    pub reference: f64,
}

/// The scalars a measure is made of, evaluated in one of three algebras (values, gradients,
/// motions).
enum Terms<T> {
    /// atan2(s, c).
    Atan2(T, T),
    /// asin(s).
    Asin(T),
    /// The value itself.
    Plain(T),
}

impl JointLimit {
    /// A limit on `measure` of the joint with markers `marker_i`, `marker_j`, its angle
    /// continued from 0 (set the drawn angle with [`JointLimit::with_reference`]).
    pub fn new(
        marker_i: Marker,
        marker_j: Marker,
        measure: Measure,
        bound: Bound,
        value: f64,
    ) -> Self {
        Self {
            marker_i,
            marker_j,
            measure,
            bound,
            value,
            reference: 0.0,
        }
    }

    /// The same limit continuing its angle from `reference`.
    pub fn with_reference(mut self, reference: f64) -> Self {
        self.reference = reference;
        self
    }

    /// c at the bodies' poses (an angle continued from [`JointLimit::reference`]).
    pub fn coordinate(&self, x: &BodyPair) -> f64 {
        let (mi, mj) = (&self.marker_i, &self.marker_j);
        let d = x.j.point(&mj.point) - x.i.point(&mi.point);
        let ax = |side, m: &Marker, a| match side {
            Side::I => x.i.vector(&axis(m, a)),
            Side::J => x.j.vector(&axis(m, a)),
        };
        match terms(
            self.measure,
            mi,
            mj,
            ax,
            &d,
            |a, b| a.dot(&b),
            |a| a.norm(),
            |a, b| a.cross(&b),
        ) {
            Terms::Atan2(s, c) if self.measure.turns() => continued_angle(self.reference, s, c),
            Terms::Atan2(s, c) => s.atan2(c),
            Terms::Asin(s) => s.asin(),
            Terms::Plain(v) => v,
        }
    }

    /// How well c is defined at the bodies' poses, in [0, 1]: ρ = √(s² + c²) of an
    /// atan2(s, c) of unit vectors (an angle), √(1 − s²) of an asin(s), 1 for a slide or an offset, and
    /// sin(bend) for a bend, |d| (m) for a distance, the distance of P_j from the axis (m) for an azimuth. c and its derivatives are undefined where it is 0 (the universal
    /// joint's cross angle where z_j ∥ z_i, a bend of 0 or π) and ill-conditioned near it.
    pub fn definition(&self, x: &BodyPair) -> f64 {
        let (mi, mj) = (&self.marker_i, &self.marker_j);
        let d = x.j.point(&mj.point) - x.i.point(&mi.point);
        let ax = |side, m: &Marker, a| match side {
            Side::I => x.i.vector(&axis(m, a)),
            Side::J => x.j.vector(&axis(m, a)),
        };
        let t = terms(
            self.measure,
            mi,
            mj,
            ax,
            &d,
            |a, b| a.dot(&b),
            |a| a.norm(),
            |a, b| a.cross(&b),
        );
        match t {
            // |z_i × z_j| = sin(bend): the norm is not differentiable where it vanishes.
            Terms::Atan2(s, _) if self.measure == Measure::Bend => s,
            Terms::Atan2(s, c) => s.hypot(c),
            Terms::Asin(s) => (1.0 - s * s).max(0.0).sqrt(),
            Terms::Plain(v) if self.measure == Measure::Distance => v,
            Terms::Plain(_) => 1.0,
        }
    }

    /// The distance to the limit, g = ±(c − value) (≥ 0 inside the range).
    pub fn gap(&self, x: &BodyPair) -> f64 {
        self.bound.sign() * (self.coordinate(x) - self.value)
    }

    /// Accepts the bodies' poses: the reference becomes the continued angle there.
    pub fn accept(&mut self, x: &BodyPair) {
        if self.measure.turns() {
            self.reference = self.coordinate(x);
        }
    }

    /// ċ from the bodies' velocities (6-coordinate form).
    pub fn rate(&self, x: &BodyPair) -> f64 {
        self.motion::<6, crate::jet::V6>(x).rate
    }

    fn grad<const N: usize, F: Form<N>>(&self, x: &BodyPair) -> ScalarGrad<N> {
        let (mi, mj) = (&self.marker_i, &self.marker_j);
        let d = Grad::between::<F>(x.i, x.j, &mi.point, &mj.point);
        let ax = |side, m: &Marker, a| Grad::dir::<F>(x.i, x.j, side, &axis(m, a));
        match terms(
            self.measure,
            mi,
            mj,
            ax,
            &d,
            |a, b| a.dot(&b),
            |a| a.norm(),
            |a, b| a.cross(&b),
        ) {
            Terms::Atan2(s, c) => angle_grad(&s, &c),
            Terms::Asin(s) => asin_grad(&s),
            Terms::Plain(v) => v,
        }
    }

    fn motion<const N: usize, F: Form<N>>(&self, x: &BodyPair) -> ScalarMotion {
        let (mi, mj) = (&self.marker_i, &self.marker_j);
        let d = Motion::between::<N, F>(x.i, x.j, &mi.point, &mj.point);
        let ax = |side, m: &Marker, a| Motion::dir::<N, F>(x.i, x.j, side, &axis(m, a));
        match terms(
            self.measure,
            mi,
            mj,
            ax,
            &d,
            |a, b| a.dot(&b),
            |a| a.norm(),
            |a, b| a.cross(&b),
        ) {
            Terms::Atan2(s, c) => angle_motion(&s, &c),
            Terms::Asin(s) => asin_motion(&s),
            Terms::Plain(v) => v,
        }
    }
}

/// A marker axis (body components), negated when asked.
fn axis(m: &Marker, a: Signed) -> nalgebra::Vector3<f64> {
    let v = match a.0 {
        Axis::X => m.x(),
        Axis::Y => m.y(),
        Axis::Z => m.z(),
    };
    if a.1 {
        -v
    } else {
        v
    }
}

/// An axis and whether it is negated.
#[derive(Clone, Copy)]
struct Signed(Axis, bool);

const X: Signed = Signed(Axis::X, false);
const Y: Signed = Signed(Axis::Y, false);
const Z: Signed = Signed(Axis::Z, false);
const MINUS_X: Signed = Signed(Axis::X, true);
const MINUS_Y: Signed = Signed(Axis::Y, true);

/// The scalars of `measure` (module table) in any algebra: `ax(side, marker, axis)` a marker
/// axis, `d` = P_j − P_i, with the algebra's dot, norm and cross.
#[allow(clippy::too_many_arguments)]
fn terms<V: Copy, S>(
    measure: Measure,
    mi: &Marker,
    mj: &Marker,
    ax: impl Fn(Side, &Marker, Signed) -> V,
    d: &V,
    dot: impl Fn(V, V) -> S,
    norm: impl Fn(V) -> S,
    cross: impl Fn(V, V) -> V,
) -> Terms<S> {
    let i = |a| ax(Side::I, mi, a);
    let j = |a| ax(Side::J, mj, a);
    match measure {
        Measure::Angle => Terms::Atan2(dot(i(Y), j(X)), dot(i(X), j(X))),
        Measure::Slide | Measure::Offset(Axis::Z) => Terms::Plain(dot(i(Z), *d)),
        Measure::Offset(Axis::X) => Terms::Plain(dot(i(X), *d)),
        Measure::Offset(Axis::Y) => Terms::Plain(dot(i(Y), *d)),
        Measure::Distance => Terms::Plain(norm(*d)),
        Measure::CrossAngleI => Terms::Atan2(dot(i(Y), j(Z)), dot(i(X), j(Z))),
        Measure::CrossAngleJ => Terms::Atan2(dot(j(Y), i(Z)), dot(j(X), i(Z))),
        Measure::Bryant(0) | Measure::AxisAngle => {
            Terms::Atan2(dot(i(MINUS_Y), j(Z)), dot(i(Z), j(Z)))
        }
        Measure::Bryant(1) => Terms::Asin(dot(i(X), j(Z))),
        Measure::Bryant(_) => Terms::Atan2(dot(i(MINUS_X), j(Y)), dot(i(X), j(X))),
        Measure::Bend => Terms::Atan2(norm(cross(i(Z), j(Z))), dot(i(Z), j(Z))),
        Measure::Azimuth => Terms::Atan2(dot(i(Y), *d), dot(i(X), *d)),
    }
}

impl Constraint for JointLimit {
    fn name(&self) -> &'static str {
        "joint_limit"
    }
    fn rows(&self) -> usize {
        1
    }
    fn dimension(&self, _row: usize) -> Dimension {
        match self.measure.quantity() {
            CoordinateQuantity::Angle => Dimension::Dimensionless,
            CoordinateQuantity::Length => Dimension::Length,
        }
    }
    /// r and p of both bodies for every measure (an angle alone depends on p only, but a limit
    /// is a single row outside the model's sparse pattern, and its value continued over turns
    /// is large enough that finite differences in r see its round-off: the wider footprint
    /// costs nothing).
    fn footprint(&self) -> Footprint {
        Footprint {
            i: BlockUse::RP,
            j: BlockUse::RP,
        }
    }
    fn phi(&self, x: &BodyPair, _t: f64, out: &mut [f64]) {
        out[0] = self.gap(x);
    }
    fn jacobian<const N: usize, F: Form<N>>(
        &self,
        x: &BodyPair,
        _t: f64,
        out_i: &mut [[f64; N]],
        out_j: &mut [[f64; N]],
    ) {
        self.grad::<N, F>(x)
            .scale(self.bound.sign())
            .write(&mut out_i[0], &mut out_j[0]);
    }
    fn gamma_sharp<const N: usize, F: Form<N>>(&self, x: &BodyPair, _t: f64, out: &mut [f64]) {
        out[0] = -self.bound.sign() * self.motion::<N, F>(x).quad;
    }
}
