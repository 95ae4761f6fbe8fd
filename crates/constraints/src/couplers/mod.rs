//! Couplers: one equation relating the coordinates of two joints (gears, rack and pinion,
//! screw), each written as an equation between **two bodies** so that it is a [`Constraint`]
//! like every other element (one row, the existing sparse structure, the 2-body oracle gate).
//!
//! | coupler | bodies i, j | Φ (1 row) | law in joint coordinates |
//! |---|---|---|---|
//! | [`Gear`] | the two gears | k_i ψ_i + k_j ψ_j − c, ψ the orbit angles | θ_j = −(r_i/r_j) θ_i + c |
//! | [`RackPinion`] | rack, pinion | k_s x_iᵀd + k_θ θ(i→j) − c | s = −r θ + c |
//! | [`Screw`] | nut, screw (or the cylindrical joint's bodies) | k_s z_iᵀd + k_θ θ(i→j) − c | s = (pitch/2π) θ + c |
//!
//! ## Why two bodies suffice
//! A joint coordinate involves the two bodies of its joint, so a law between two joints' angles
//! touches up to four bodies. When the two joints share a body C (ground, a housing, a carrier),
//! each joint coordinate is, up to sign and a constant, a relative coordinate of its *other*
//! body seen from the other joint's other body: the direction of a gear centre seen in the
//! other gear's frame turns exactly by minus that gear's angle relative to C, whatever C does
//! (OndselSolver's orbit-angle formulation); a rack that only slides relative to C and a pinion
//! that only turns relative to C have their slide and angle as the rack's offset along itself
//! and the angle between the two bodies' frames. The mechanism builder checks the shared body,
//! picks the markers and the coefficients k (with the signs that make Φ exactly the stated law
//! in the joints' own coordinates) and the constant c, and says so when the joints share no
//! body.
//!
//! ## Angles over many turns
//! An angle θ = atan2(s, c) is defined modulo 2π, and a gear law with a non-integer ratio needs
//! the angle itself. Each coupler holds the continued angle(s) at the last accepted pose
//! ([`Coupler::reference`]) and evaluates θ as the value nearest to it
//! ([`angle::continued_angle`]); the derivatives do not depend on the reference. The mechanism
//! keeps the references with its poses and updates them ([`Coupler::accept`]) at each accepted
//! pose (assembly, each kinematic frame, each accepted dynamic step), so an angle may change by
//! up to π between two accepted poses.
//!
//! Reference: OndselSolver (`GearConstraintIJ`, `RackPinConstraintIJ`, `ScrewConstraintIJ`);
//! Haug 1989 §3.5 (gear and rack-and-pinion pairs as constraints in planar mechanisms).

pub mod angle;
mod gear;
mod rack_pinion;
mod screw;
mod slide_angle;

pub use gear::Gear;
pub use rack_pinion::RackPinion;
pub use screw::Screw;
pub use slide_angle::SlideAngle;

use crate::constraint::Constraint;
use crate::state::BodyPair;

/// One coupler (static dispatch). `Copy`, so a mechanism evaluates a copy that carries the
/// references of its workspace without allocating.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Coupler {
    /// Two gears.
    Gear(Gear),
    /// A rack and a pinion.
    RackPinion(RackPinion),
    /// A screw and its nut.
    Screw(Screw),
}

macro_rules! dispatch {
    ($self:ident, $c:ident => $e:expr) => {
        match $self {
            Coupler::Gear($c) => $e,
            Coupler::RackPinion($c) => $e,
            Coupler::Screw($c) => $e,
        }
    };
}

forward_constraint_by_match!(Coupler, dispatch);

impl Coupler {
    /// The continued angles at the last accepted pose (a rack or screw uses only the first).
    pub fn reference(&self) -> [f64; 2] {
        match self {
            Coupler::Gear(g) => g.reference,
            Coupler::RackPinion(c) => [c.inner.reference, 0.0],
            Coupler::Screw(c) => [c.inner.reference, 0.0],
        }
    }

    /// The same coupler continuing its angles from `reference`.
    pub fn with_reference(mut self, reference: [f64; 2]) -> Self {
        match &mut self {
            Coupler::Gear(g) => g.reference = reference,
            Coupler::RackPinion(c) => c.inner.reference = reference[0],
            Coupler::Screw(c) => c.inner.reference = reference[0],
        }
        self
    }

    /// The continued angles at the bodies' poses (what [`Coupler::reference`] becomes when this
    /// pose is accepted).
    pub fn angles(&self, x: &BodyPair) -> [f64; 2] {
        match self {
            Coupler::Gear(g) => g.angles(x),
            Coupler::RackPinion(c) => [c.inner.angle(x), 0.0],
            Coupler::Screw(c) => [c.inner.angle(x), 0.0],
        }
    }

    /// Accepts the bodies' poses: the references become the continued angles there.
    pub fn accept(&mut self, x: &BodyPair) {
        *self = self.with_reference(self.angles(x));
    }

    /// The marker points P_i, P_j (body frames): where reactions are reported.
    pub fn points(&self) -> (nalgebra::Vector3<f64>, nalgebra::Vector3<f64>) {
        let (mi, mj) = match self {
            Coupler::Gear(g) => (&g.marker_i, &g.marker_j),
            Coupler::RackPinion(c) => (&c.inner.marker_i, &c.inner.marker_j),
            Coupler::Screw(c) => (&c.inner.marker_i, &c.inner.marker_j),
        };
        (mi.point, mj.point)
    }

    /// The constant c.
    pub fn constant(&self) -> f64 {
        match self {
            Coupler::Gear(g) => g.constant,
            Coupler::RackPinion(c) => c.inner.constant,
            Coupler::Screw(c) => c.inner.constant,
        }
    }

    /// The same coupler with constant c.
    pub fn with_constant(mut self, constant: f64) -> Self {
        match &mut self {
            Coupler::Gear(g) => g.constant = constant,
            Coupler::RackPinion(c) => c.inner.constant = constant,
            Coupler::Screw(c) => c.inner.constant = constant,
        }
        self
    }

    /// Φ without the constant (k_i ψ_i + k_j ψ_j, or k_s u + k_θ θ) at the bodies' poses.
    pub fn value(&self, x: &BodyPair) -> f64 {
        let mut out = [0.0];
        self.with_constant(0.0).phi(x, 0.0, &mut out);
        out[0]
    }
}

macro_rules! from_variant {
    ($($v:ident => $t:ident),*) => {$(
        impl From<$t> for Coupler {
            fn from(c: $t) -> Self {
                Coupler::$v(c)
            }
        }
    )*};
}
from_variant!(Gear => Gear, RackPinion => RackPinion, Screw => Screw);
