//! n2, "normal type 2" (Haug's DP2): a vector of body i perpendicular to the vector d between
//! a point of body i and a point of body j.
//!
//! ```text
//! d = r_j + A_j s'^P_j − r_i − A_i s'^P_i
//! Φ = s_iᵀ d − h                   (h a constant offset, 0 for the plain n2)    1 row
//! Φ_q = [−s_iᵀ, −s_iᵀ B_i + dᵀ C_i, s_iᵀ, s_iᵀ B_j]     B_k = ∂(A_k s'^P_k)/∂p_k, C_i = ∂(A_i s'_i)/∂p_i
//! Φ_v = [−s_iᵀ, s_iᵀ A_i s̃'^P_i − dᵀ A_i s̃'_i, s_iᵀ, −s_iᵀ A_j s̃'^P_j]
//! γ#  = −(s̈_iᵀ d + 2 ṡ_iᵀ ḋ + s_iᵀ d̈)      (velocity-quadratic parts, as in n1)
//! ```
//! Nikravesh 1988 §7.2 (eq. 7.16), Haug 1989 §9.2 (DP2). Footprint: r and p of both bodies.

use crate::constraint::{Constraint, Dimension};
use crate::jet::{Form, Grad, Motion, Side};
use crate::state::{BlockUse, BodyPair, Footprint};
use nalgebra::Vector3;

/// s_iᵀ d − h = 0.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct N2 {
    /// s'_i, body-i components.
    pub s_i: Vector3<f64>,
    /// s'^P_i, the point of body i where d starts.
    pub sp_i: Vector3<f64>,
    /// s'^P_j, the point of body j where d ends.
    pub sp_j: Vector3<f64>,
    /// h: the constant the product equals (a plane moved along s_i; constant, so it drops out
    /// of Φ_q and γ#).
    pub offset: f64,
}

impl N2 {
    /// n2 with direction s'_i and points s'^P_i, s'^P_j.
    pub fn new(s_i: Vector3<f64>, sp_i: Vector3<f64>, sp_j: Vector3<f64>) -> Self {
        Self::with_offset(s_i, sp_i, sp_j, 0.0)
    }

    /// s_iᵀ d = h.
    pub fn with_offset(s_i: Vector3<f64>, sp_i: Vector3<f64>, sp_j: Vector3<f64>, h: f64) -> Self {
        Self {
            s_i,
            sp_i,
            sp_j,
            offset: h,
        }
    }
}

impl Constraint for N2 {
    fn dimension(&self, _row: usize) -> Dimension {
        Dimension::Length
    }
    fn name(&self) -> &'static str {
        "n2"
    }
    fn rows(&self) -> usize {
        1
    }
    fn footprint(&self) -> Footprint {
        Footprint {
            i: BlockUse::RP,
            j: BlockUse::RP,
        }
    }
    fn phi(&self, x: &BodyPair, _t: f64, out: &mut [f64]) {
        let d = x.j.point(&self.sp_j) - x.i.point(&self.sp_i);
        out[0] = x.i.vector(&self.s_i).dot(&d) - self.offset;
    }
    fn jacobian<const N: usize, F: Form<N>>(
        &self,
        x: &BodyPair,
        _t: f64,
        out_i: &mut [[f64; N]],
        out_j: &mut [[f64; N]],
    ) {
        let si = Grad::dir::<F>(x.i, x.j, Side::I, &self.s_i);
        let d = Grad::between::<F>(x.i, x.j, &self.sp_i, &self.sp_j);
        si.dot(&d).write(&mut out_i[0], &mut out_j[0]);
    }
    fn gamma_sharp<const N: usize, F: Form<N>>(&self, x: &BodyPair, _t: f64, out: &mut [f64]) {
        let si = Motion::dir::<N, F>(x.i, x.j, Side::I, &self.s_i);
        let d = Motion::between::<N, F>(x.i, x.j, &self.sp_i, &self.sp_j);
        out[0] = -si.dot(&d).quad;
    }
}
