//! Curve on curve: two curves, one fixed in body i and one in body j, touch and are tangent at
//! a common point, each curve's parameter an extra coordinate (u on curve i, w on curve j). The
//! bilateral cam–follower pair of Haug 1989 §9.4.2 ("cam-follower"): a cam profile on body i
//! with a roller (a circle on body j), a flat face (a line on body j) or another profile.
//!
//! ```text
//! Φ_1..3 = r_j + A_j c'_j(w) − r_i − A_i c'_i(u)             (the contact points coincide, length)
//! Φ_4    = (A_i n'_i(u))ᵀ (A_j c'_j,w(w)),  n'_i = k' × c'_i,u   (the tangents are parallel)
//! ```
//!
//! k' is the unit normal of curve i's plane (body i's coordinates): n'_i is curve i's in-plane
//! normal, and Φ_4 says that curve j's tangent has no component along it. The four rows fix
//! four of the coordinates (u and w included), so the pair removes two degrees of freedom of the
//! bodies in space; in a planar mechanism Φ_3 (out of the plane) is redundant and the pair
//! removes one, as a higher pair does.
//!
//! Every row is a product of body-fixed vectors whose body coordinates depend on u or w. For
//! s = A_k s'(u) the rate is Ȧ_k s' + A_k s'_u u̇ and the velocity-quadratic part of s̈ is
//! (Ä_k s')_quad + 2 Ȧ_k s'_u u̇ + A_k s'_uu u̇² (ü's term A_k s'_u ü belongs to Φ_u ü):
//! `moving` builds that [`Motion`], and the products ([`Motion::dot`]) carry it into γ#.
//! Φ_u and Φ_w are the rows' derivatives at fixed bodies. Oracle: `gen_curves.py`.

use crate::constraint::{Constraint, Dimension, MAX_EXTRA};
use crate::curves::{Curve, CurveJet};
use crate::error::ConstraintError;
use crate::jet::{write_rows, Form, Grad, Motion, Side};
use crate::state::{BlockUse, BodyPair, Footprint};
use nalgebra::Vector3;

/// A curve of body i and a curve of body j in tangent contact.
#[derive(Debug, Clone, PartialEq)]
pub struct CurveOnCurve {
    /// Curve i (the cam), in body i's coordinates.
    pub curve_i: Curve,
    /// k', the unit normal of curve i's plane, in body i's coordinates.
    pub normal_i: Vector3<f64>,
    /// Curve j (the follower's roller, face or profile), in body j's coordinates.
    pub curve_j: Curve,
    /// The vector areas of curve i and curve j when closed ([`Curve::area_vector`]): which way
    /// each runs about its plane's normal, computed once.
    areas: [Option<Vector3<f64>>; 2],
}

impl CurveOnCurve {
    /// Curve `curve_i` of body i, in the plane of normal `normal_i` (normalized here), touching
    /// `curve_j` of body j. Refused: a zero or non-finite normal, a helix on either side (not a
    /// planar curve).
    pub fn new(
        curve_i: Curve,
        normal_i: Vector3<f64>,
        curve_j: Curve,
    ) -> Result<Self, ConstraintError> {
        let n = normal_i.norm();
        if !(n.is_finite() && n > 0.0) {
            return Err(ConstraintError::Curve(format!(
                "the cam plane's normal must be a nonzero direction, got [{}, {}, {}]",
                normal_i.x, normal_i.y, normal_i.z
            )));
        }
        for c in [&curve_i, &curve_j] {
            if matches!(c, Curve::Helix(_)) {
                return Err(ConstraintError::Curve(
                    "a helix is not a planar curve: a cam pair takes lines, circles and splines"
                        .into(),
                ));
            }
        }
        Ok(Self {
            areas: [curve_i.area_vector(), curve_j.area_vector()],
            curve_i,
            normal_i: normal_i / n,
            curve_j,
        })
    }

    /// The vector areas of curve i and curve j when closed (in their bodies' coordinates).
    pub fn areas(&self) -> [Option<Vector3<f64>>; 2] {
        self.areas
    }

    /// The oracle element's curve-kind pair, `curve_on_curve_<i>_<j>`.
    fn kinds(&self) -> (&'static str, &'static str) {
        (self.curve_i.kind(), self.curve_j.kind())
    }

    /// n'_i(u) = k' × c'_i,u and its first two u-derivatives, as a jet (c = n', c_u = n'_u...).
    fn normal_jet(&self, j: &CurveJet) -> CurveJet {
        let k = &self.normal_i;
        CurveJet {
            c: k.cross(&j.c_u),
            c_u: k.cross(&j.c_uu),
            c_uu: k.cross(&j.c_uuu),
            c_uuu: Vector3::zeros(),
        }
    }
}

/// The motion of A_k s'(u) (a direction, `point` false) or r_k + A_k s'(u) (a point) of body
/// `side` whose body coordinates s' = `jet.c` move with the parameter at rate `u_dot` (module
/// docs).
fn moving<const N: usize, F: Form<N>>(
    x: &BodyPair,
    side: Side,
    jet: &CurveJet,
    u_dot: f64,
    point: bool,
) -> Motion {
    let mut m = if point {
        Motion::point::<N, F>(x.i, x.j, side, &jet.c)
    } else {
        Motion::dir::<N, F>(x.i, x.j, side, &jet.c)
    };
    let tangent = Motion::dir::<N, F>(x.i, x.j, side, &jet.c_u);
    let curvature = Motion::dir::<N, F>(x.i, x.j, side, &jet.c_uu);
    m.rate += tangent.v * u_dot;
    m.quad += tangent.rate * (2.0 * u_dot) + curvature.v * (u_dot * u_dot);
    m
}

impl Constraint for CurveOnCurve {
    fn name(&self) -> &'static str {
        match self.kinds() {
            ("line", "line") => "curve_on_curve_line_line",
            ("line", "circle") => "curve_on_curve_line_circle",
            ("line", "cubic") => "curve_on_curve_line_cubic",
            ("line", _) => "curve_on_curve_line_cubic_closed",
            ("circle", "line") => "curve_on_curve_circle_line",
            ("circle", "circle") => "curve_on_curve_circle_circle",
            ("circle", "cubic") => "curve_on_curve_circle_cubic",
            ("circle", _) => "curve_on_curve_circle_cubic_closed",
            ("cubic", "line") => "curve_on_curve_cubic_line",
            ("cubic", "circle") => "curve_on_curve_cubic_circle",
            ("cubic", "cubic") => "curve_on_curve_cubic_cubic",
            ("cubic", _) => "curve_on_curve_cubic_cubic_closed",
            (_, "line") => "curve_on_curve_cubic_closed_line",
            (_, "circle") => "curve_on_curve_cubic_closed_circle",
            (_, "cubic") => "curve_on_curve_cubic_closed_cubic",
            _ => "curve_on_curve_cubic_closed_cubic_closed",
        }
    }

    fn rows(&self) -> usize {
        4
    }

    fn dimension(&self, row: usize) -> Dimension {
        if row < 3 {
            Dimension::Length
        } else {
            Dimension::Dimensionless
        }
    }

    fn footprint(&self) -> Footprint {
        Footprint {
            i: BlockUse::RP,
            j: BlockUse::RP,
        }
    }

    fn extra(&self) -> usize {
        2
    }

    fn phi(&self, x: &BodyPair, _t: f64, out: &mut [f64]) {
        let (ji, jj) = (self.curve_i.jet(x.u[0]), self.curve_j.jet(x.u[1]));
        let d = x.j.point(&jj.c) - x.i.point(&ji.c);
        out[..3].copy_from_slice(d.as_slice());
        out[3] =
            x.i.vector(&self.normal_i.cross(&ji.c_u))
                .dot(&x.j.vector(&jj.c_u));
    }

    fn jacobian<const N: usize, F: Form<N>>(
        &self,
        x: &BodyPair,
        _t: f64,
        out_i: &mut [[f64; N]],
        out_j: &mut [[f64; N]],
    ) {
        let (ji, jj) = (self.curve_i.jet(x.u[0]), self.curve_j.jet(x.u[1]));
        let d = Grad::between::<F>(x.i, x.j, &ji.c, &jj.c);
        write_rows(&d, &mut out_i[..3], &mut out_j[..3]);
        let n = Grad::dir::<F>(x.i, x.j, Side::I, &self.normal_i.cross(&ji.c_u));
        let t = Grad::dir::<F>(x.i, x.j, Side::J, &jj.c_u);
        n.dot(&t).write(&mut out_i[3], &mut out_j[3]);
    }

    fn jacobian_extra(&self, x: &BodyPair, _t: f64, out: &mut [[f64; MAX_EXTRA]]) {
        let (ji, jj) = (self.curve_i.jet(x.u[0]), self.curve_j.jet(x.u[1]));
        let (ti, tj) = (x.i.vector(&ji.c_u), x.j.vector(&jj.c_u));
        for r in 0..3 {
            out[r] = [-ti[r], tj[r]];
        }
        let nj = self.normal_jet(&ji);
        let (n, n_u) = (x.i.vector(&nj.c), x.i.vector(&nj.c_u));
        out[3] = [n_u.dot(&tj), n.dot(&x.j.vector(&jj.c_uu))];
    }

    fn gamma_sharp<const N: usize, F: Form<N>>(&self, x: &BodyPair, _t: f64, out: &mut [f64]) {
        let (ji, jj) = (self.curve_i.jet(x.u[0]), self.curve_j.jet(x.u[1]));
        let (u_dot, w_dot) = (x.u_dot[0], x.u_dot[1]);
        let pi = moving::<N, F>(x, Side::I, &ji, u_dot, true);
        let pj = moving::<N, F>(x, Side::J, &jj, w_dot, true);
        out[..3].copy_from_slice((-pj.sub(&pi).quad).as_slice());
        let n = moving::<N, F>(x, Side::I, &self.normal_jet(&ji), u_dot, false);
        let tj = CurveJet {
            c: jj.c_u,
            c_u: jj.c_uu,
            c_uu: jj.c_uuu,
            c_uuu: Vector3::zeros(),
        };
        let t = moving::<N, F>(x, Side::J, &tj, w_dot, false);
        out[3] = -n.dot(&t).quad;
    }
}
