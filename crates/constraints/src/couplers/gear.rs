//! Gear coupler: the rotations of two gears on a common carrier, as one equation between the
//! two gear bodies (OndselSolver's `GearConstraintIJ`, written from its definition).
//!
//! Marker i sits on gear body i at a point of its axis (z_i the axis), marker j likewise on
//! gear body j; d = P_j − P_i. The *orbit angles* are the direction of the other gear's centre
//! seen in each gear's own frame:
//!
//! ```text
//! ψ_i = atan2(y_iᵀ d, x_iᵀ d)          (P_j seen from gear i)
//! ψ_j = atan2(−y_jᵀ d, −x_jᵀ d)        (P_i seen from gear j)
//! Φ   = k_i ψ_i + k_j ψ_j − c          1 row, dimensionless (rad)
//! ```
//!
//! each ψ continued over turns from its reference angle ([`continued_angle`]). When both axes
//! are fixed in one carrier body C (the shared body of the two revolute joints: ground, a
//! housing, a planet carrier) and P_j stays off axis i, ψ_i = β_i − φ_i with φ_i the rotation of
//! gear i relative to C about z_i and β_i a constant of the carrier's geometry, whatever C does;
//! likewise ψ_j. So Φ = 0 is the linear law k_i φ_i + k_j φ_j = const between the two joint
//! angles. With k_i = −r_i/r_j (scaled, see the mechanism builder) it is the mesh of two gears
//! of pitch radii r_i, r_j: ω_j = −(r_i/r_j) ω_i relative to the carrier.
//!
//! The gradients come from the dot products x_iᵀ d, y_iᵀ d, x_jᵀ d, y_jᵀ d ([`crate::jet`])
//! through ∇atan2 ([`super::angle`]); γ# = −(k_i ψ̈_i + k_j ψ̈_j) with the velocity-quadratic
//! parts. Footprint: r and p of both bodies. Reference: OndselSolver `GearConstraintIJ`,
//! `OrbitAngleZIecJec` (the orbit angle), ASMT notes §3 of the project.

use super::angle::{angle_grad, angle_motion, continued_angle};
use crate::constraint::{Constraint, Dimension};
use crate::jet::{Form, Grad, Motion, ScalarGrad, ScalarMotion, Side};
use crate::marker::Marker;
use crate::state::{BlockUse, BodyPair, Footprint};

/// k_i ψ_i + k_j ψ_j − c = 0 (orbit angles of each gear centre seen from the other gear).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Gear {
    /// Marker on gear body i: a point on its axis, z the axis.
    pub marker_i: Marker,
    /// Marker on gear body j.
    pub marker_j: Marker,
    /// k_i, the coefficient of ψ_i.
    pub k_i: f64,
    /// k_j, the coefficient of ψ_j.
    pub k_j: f64,
    /// c (rad).
    pub constant: f64,
    /// The continued values of ψ_i and ψ_j at the last accepted pose.
    pub reference: [f64; 2],
}

impl Gear {
    /// The orbit angles (principal values) at the bodies' poses.
    pub fn orbit_angles(&self, x: &BodyPair) -> [f64; 2] {
        let d = x.j.point(&self.marker_j.point) - x.i.point(&self.marker_i.point);
        let (xi, yi) = (
            x.i.vector(&self.marker_i.x()),
            x.i.vector(&self.marker_i.y()),
        );
        let (xj, yj) = (
            x.j.vector(&self.marker_j.x()),
            x.j.vector(&self.marker_j.y()),
        );
        [
            yi.dot(&d).atan2(xi.dot(&d)),
            (-yj.dot(&d)).atan2(-xj.dot(&d)),
        ]
    }

    /// ψ_i and ψ_j continued from [`Gear::reference`].
    pub fn angles(&self, x: &BodyPair) -> [f64; 2] {
        let [a, b] = self.orbit_angles(x);
        [
            continued_angle(self.reference[0], a.sin(), a.cos()),
            continued_angle(self.reference[1], b.sin(), b.cos()),
        ]
    }

    fn grads<const N: usize, F: Form<N>>(&self, x: &BodyPair) -> [ScalarGrad<N>; 2] {
        let (mi, mj) = (&self.marker_i, &self.marker_j);
        let d = Grad::between::<F>(x.i, x.j, &mi.point, &mj.point);
        let dir = |side, v| Grad::dir::<F>(x.i, x.j, side, &v).dot(&d);
        let psi_i = angle_grad(&dir(Side::I, mi.y()), &dir(Side::I, mi.x()));
        let psi_j = angle_grad(&dir(Side::J, -mj.y()), &dir(Side::J, -mj.x()));
        [psi_i, psi_j]
    }

    fn motions<const N: usize, F: Form<N>>(&self, x: &BodyPair) -> [ScalarMotion; 2] {
        let (mi, mj) = (&self.marker_i, &self.marker_j);
        let d = Motion::between::<N, F>(x.i, x.j, &mi.point, &mj.point);
        let dir = |side, v| Motion::dir::<N, F>(x.i, x.j, side, &v).dot(&d);
        let psi_i = angle_motion(&dir(Side::I, mi.y()), &dir(Side::I, mi.x()));
        let psi_j = angle_motion(&dir(Side::J, -mj.y()), &dir(Side::J, -mj.x()));
        [psi_i, psi_j]
    }
}

impl Constraint for Gear {
    fn name(&self) -> &'static str {
        "gear"
    }
    fn rows(&self) -> usize {
        1
    }
    fn dimension(&self, _row: usize) -> Dimension {
        Dimension::Dimensionless
    }
    fn footprint(&self) -> Footprint {
        Footprint {
            i: BlockUse::RP,
            j: BlockUse::RP,
        }
    }
    fn phi(&self, x: &BodyPair, _t: f64, out: &mut [f64]) {
        let [a, b] = self.angles(x);
        out[0] = self.k_i * a + self.k_j * b - self.constant;
    }
    fn jacobian<const N: usize, F: Form<N>>(
        &self,
        x: &BodyPair,
        _t: f64,
        out_i: &mut [[f64; N]],
        out_j: &mut [[f64; N]],
    ) {
        let [a, b] = self.grads::<N, F>(x);
        let g = ScalarGrad {
            v: 0.0,
            di: a.di * self.k_i + b.di * self.k_j,
            dj: a.dj * self.k_i + b.dj * self.k_j,
        };
        g.write(&mut out_i[0], &mut out_j[0]);
    }
    fn gamma_sharp<const N: usize, F: Form<N>>(&self, x: &BodyPair, _t: f64, out: &mut [f64]) {
        let [a, b] = self.motions::<N, F>(x);
        out[0] = -(self.k_i * a.quad + self.k_j * b.quad);
    }
}
