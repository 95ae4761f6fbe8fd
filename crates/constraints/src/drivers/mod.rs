//! Drivers: time-dependent equations that prescribe a joint coordinate or a position.
//!
//! A driver Φ^D(q, t) = 0 adds one row. Unlike the joints, its Φ_t and Φ_tt are nonzero, so
//! ν = −Φ_t ≠ 0 and γ# contains −Φ_tt and, when the time function multiplies coordinate terms,
//! −2 Φ_qt q̇ (Nikravesh 1988 §7.5, Haug 1989 §9.5). Each driver takes a [`TimeFunction`] with
//! exact derivatives.
//!
//! | driver | Φ |
//! |---|---|
//! | [`RotationDriver`] | cos θ(t) · (y_iᵀ x_j) − sin θ(t) · (x_iᵀ x_j) = sin(φ − θ(t)) |
//! | [`TranslationDriver`] | z_iᵀ d − s(t) |
//! | [`DistanceDriver`] | dᵀd − ℓ(t)² |
//! | [`CoordinateDriver`] | (r_i + A_i s'^P_i)\[k\] − c(t) |
//! | [`PoseDriver`] | one of six rows: x_Iᵀ d − f_k(t) (k = 1..3), or a fixed-joint row to the frame A_I R(t) |

mod coordinate;
mod distance;
mod pose;
mod rotation;
mod translation;

pub use coordinate::CoordinateDriver;
pub use distance::DistanceDriver;
pub use pose::{PoseDriver, RotationOrder, POSE_ROWS};
pub use rotation::RotationDriver;
pub use translation::TranslationDriver;

use crate::state::BodyPair;
use crate::time_function::TimeFunction;

/// One driver (static dispatch).
#[derive(Debug, Clone, PartialEq)]
pub enum Driver {
    /// Rotation angle of a revolute or cylindrical joint.
    Rotation(RotationDriver),
    /// Slide of a prismatic or cylindrical joint.
    Translation(TranslationDriver),
    /// Distance between two points.
    Distance(DistanceDriver),
    /// One global coordinate of a body point.
    Coordinate(CoordinateDriver),
    /// One row of a full pose prescription (general motion).
    Pose(PoseDriver),
}

macro_rules! dispatch {
    ($self:ident, $c:ident => $e:expr) => {
        match $self {
            Driver::Rotation($c) => $e,
            Driver::Translation($c) => $e,
            Driver::Distance($c) => $e,
            Driver::Coordinate($c) => $e,
            Driver::Pose($c) => $e,
        }
    };
}

impl Driver {
    /// The time function.
    pub fn function(&self) -> &TimeFunction {
        match self {
            Driver::Pose(p) => &p.functions[p.row],
            Driver::Rotation(c) => &c.function,
            Driver::Translation(c) => &c.function,
            Driver::Distance(c) => &c.function,
            Driver::Coordinate(c) => &c.function,
        }
    }

    /// Replaces the time function (assembly's continuation holds each driver at intermediate
    /// constant values on the way to f(t)).
    pub fn set_function(&mut self, function: TimeFunction) {
        match self {
            Driver::Pose(p) => p.functions[p.row] = function,
            Driver::Rotation(c) => c.function = function,
            Driver::Translation(c) => c.function = function,
            Driver::Distance(c) => c.function = function,
            Driver::Coordinate(c) => c.function = function,
        }
    }

    /// The driven coordinate c at the bodies' poses: the joint angle atan2(y_iᵀ x_j, x_iᵀ x_j)
    /// (principal value, rad), the slide z_iᵀ d, the distance |d| (m) or the point's global
    /// coordinate (m), a pose driver's translation x_Iᵀ d (rows 0–2; for its rotation rows the
    /// angles are not separable: [`PoseDriver::coordinate`]). The driver's equation holds when
    /// c = f(t) (mod 2π for an angle).
    pub fn coordinate(&self, x: &BodyPair) -> f64 {
        match self {
            Driver::Rotation(d) => {
                let xj = x.j.vector(&d.marker_j.x());
                x.i.vector(&d.marker_i.y())
                    .dot(&xj)
                    .atan2(x.i.vector(&d.marker_i.x()).dot(&xj))
            }
            Driver::Translation(d) => {
                let dv = x.j.point(&d.marker_j.point) - x.i.point(&d.marker_i.point);
                x.i.vector(&d.marker_i.z()).dot(&dv)
            }
            Driver::Distance(d) => (x.j.point(&d.point_j) - x.i.point(&d.point_i)).norm(),
            Driver::Coordinate(d) => x.i.point(&d.point_i)[d.axis],
            Driver::Pose(d) => d.coordinate(x),
        }
    }

    /// How far the bodies' poses are from the branch the prescription means, where the
    /// driver's equations also hold on a spurious root: 0 on the meant branch, ≥ 1 on a
    /// spurious one. A rotation driver's sin(φ − θ) = 0 also holds at φ = θ ± π: 1 − cos(φ − θ)
    /// when cos(φ − θ) ≤ 0; a pose driver's rotation rows also hold on half-turn flips of the
    /// moved frame ([`PoseDriver::branch_error`]); the other drivers have no spurious roots (a
    /// distance driver's ℓ ≥ 0 is checked when it is built). For a solver to refuse a pose
    /// whose equations hold but whose motion is not the one prescribed.
    pub fn branch_error(&self, x: &BodyPair, t: f64) -> f64 {
        match self {
            Driver::Rotation(d) => {
                let c = (self.coordinate(x) - d.function.eval(t).0).cos();
                if c > 0.0 {
                    0.0
                } else {
                    1.0 - c
                }
            }
            Driver::Pose(p) => p.branch_error(x, t),
            Driver::Translation(_) | Driver::Distance(_) | Driver::Coordinate(_) => 0.0,
        }
    }

    /// ∂Φ/∂c at time `t` on the solution: how fast the driver's equation grows with its driven
    /// coordinate c (the angle, slide, distance or global coordinate). 1 for every driver written
    /// as c − f(t) (rotation: sin(φ − θ) has slope cos 0 = 1 on its branch), 2ℓ(t) for the
    /// distance driver dᵀd − ℓ(t)². The physical effort along c (a force in N or a torque in
    /// N m, with effort × ċ = power) is −λ · ∂Φ/∂c.
    pub fn coordinate_slope(&self, t: f64) -> f64 {
        match self {
            Driver::Distance(d) => 2.0 * d.function.eval(t).0,
            Driver::Rotation(_)
            | Driver::Translation(_)
            | Driver::Coordinate(_)
            | Driver::Pose(_) => 1.0,
        }
    }
}

forward_constraint_by_match!(Driver, dispatch);

macro_rules! from_variant {
    ($($v:ident => $t:ident),*) => {$(
        impl From<$t> for Driver {
            fn from(c: $t) -> Self {
                Driver::$v(c)
            }
        }
    )*};
}
from_variant!(Rotation => RotationDriver, Translation => TranslationDriver, Distance => DistanceDriver, Coordinate => CoordinateDriver, Pose => PoseDriver);
