//! homokinetic: the relative rotation of two frames has no component about their z axes, the
//! condition that makes a constant-velocity (CV) joint transmit equal speeds.
//!
//! ```text
//! Φ = x_iᵀ y_j − y_iᵀ x_j                                           1 row
//! Φ_q = ∂(x_iᵀ y_j)/∂q − ∂(y_iᵀ x_j)/∂q                  (each an n1 row, Nikravesh 1988 eq. 7.12)
//! γ#  = −(quadratic part of (x_iᵀ y_j)¨ − quadratic part of (y_iᵀ x_j)¨)
//! ```
//! With R = A_iᵀ A_j the rotation from frame i to frame j (marker frames), Φ = R₁₂ − R₂₁ =
//! −2 sin φ m_z for a rotation by φ about the unit axis m (m_z its component along z_i): Φ = 0
//! holds exactly when the relative rotation is a pure bend about an axis in the x–y plane of
//! frame i (or a half turn). Two shafts along z_i and z_j joined at a point with this condition
//! turn at equal speeds at every bend angle β: if shaft i turns by θ about z_i and shaft j by ψ
//! about z_j, R = C R_z(ψ − θ) with C a pure bend, and Φ = −2 cos²(β/2) sin(ψ − θ), zero for
//! ψ = θ (the branch the drawn pose selects; the other is ψ = θ + π). Its slope −2 cos²(β/2)
//! keeps the row well conditioned for every bend short of folding back (β → 180°).
//! (OndselSolver's `ConstVelConstraintIJ` writes x_iᵀ y_j + y_iᵀ x_j
//! for marker frames facing each other, z_j = −z_i when straight; with z_i and z_j in the same
//! sense, as here, the sign changes.) Footprint: p of both bodies.

use crate::constraint::{Constraint, Dimension};
use crate::jet::{Form, Grad, Motion, Side};
use crate::state::{BlockUse, BodyPair, Footprint};
use nalgebra::Vector3;

/// x_iᵀ y_j − y_iᵀ x_j = 0.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Homokinetic {
    /// x'_i, body-i components.
    pub x_i: Vector3<f64>,
    /// y'_i, body-i components.
    pub y_i: Vector3<f64>,
    /// x'_j, body-j components.
    pub x_j: Vector3<f64>,
    /// y'_j, body-j components.
    pub y_j: Vector3<f64>,
}

impl Homokinetic {
    /// The condition between frames (x'_i, y'_i) and (x'_j, y'_j).
    pub fn new(x_i: Vector3<f64>, y_i: Vector3<f64>, x_j: Vector3<f64>, y_j: Vector3<f64>) -> Self {
        Self { x_i, y_i, x_j, y_j }
    }
}

impl Constraint for Homokinetic {
    fn dimension(&self, _row: usize) -> Dimension {
        Dimension::Dimensionless
    }
    fn name(&self) -> &'static str {
        "homokinetic"
    }
    fn rows(&self) -> usize {
        1
    }
    fn footprint(&self) -> Footprint {
        Footprint {
            i: BlockUse::P,
            j: BlockUse::P,
        }
    }
    fn phi(&self, x: &BodyPair, _t: f64, out: &mut [f64]) {
        let (xi, yi) = (x.i.vector(&self.x_i), x.i.vector(&self.y_i));
        let (xj, yj) = (x.j.vector(&self.x_j), x.j.vector(&self.y_j));
        out[0] = xi.dot(&yj) - yi.dot(&xj);
    }
    fn jacobian<const N: usize, F: Form<N>>(
        &self,
        x: &BodyPair,
        _t: f64,
        out_i: &mut [[f64; N]],
        out_j: &mut [[f64; N]],
    ) {
        let g = |side, v| Grad::dir::<F>(x.i, x.j, side, v);
        let a = g(Side::I, &self.x_i).dot(&g(Side::J, &self.y_j));
        let b = g(Side::I, &self.y_i).dot(&g(Side::J, &self.x_j));
        a.sub(&b).write(&mut out_i[0], &mut out_j[0]);
    }
    fn gamma_sharp<const N: usize, F: Form<N>>(&self, x: &BodyPair, _t: f64, out: &mut [f64]) {
        let m = |side, v| Motion::dir::<N, F>(x.i, x.j, side, v);
        let a = m(Side::I, &self.x_i).dot(&m(Side::J, &self.y_j));
        let b = m(Side::I, &self.y_i).dot(&m(Side::J, &self.x_j));
        out[0] = -a.sub(&b).quad;
    }
}
