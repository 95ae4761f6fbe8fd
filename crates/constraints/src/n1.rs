//! n1, "normal type 1" (Haug's DP1): a vector of body i perpendicular to a vector of body j, or,
//! with a value c, at a fixed dot product with it (Haug's DP1 with its f(t) held constant).
//!
//! ```text
//! Φ = s_iᵀ s_j − c = s'_iᵀ A_iᵀ A_j s'_j − c                      1 row
//! Φ_q = [0, s_jᵀ C_i, 0, s_iᵀ C_j]        C_k = ∂(A_k s'_k)/∂p_k = 2 (G_k s̄'_k + s'_k p_kᵀ)
//! Φ_v = [0, −s_jᵀ A_i s̃'_i, 0, −s_iᵀ A_j s̃'_j]
//! γ#  = −(s̈_iᵀ s_j + 2 ṡ_iᵀ ṡ_j + s_iᵀ s̈_j)  with s̈ the velocity-quadratic part:
//!       7-coordinate: s̈_k = C_k(ṗ_k) ṗ_k;  6-coordinate: s̈_k = A_k ω̃'_k ω̃'_k s'_k
//! ```
//! The constant c changes Φ only: Φ_q, Φ_v and γ# are those of c = 0. With unit s_i, s_j and
//! c = cos α the row holds the angle α between them (a cone of s_j about s_i); its gradient
//! vanishes where s_i ∥ s_j, so c = ±1 is a singular row.
//! Nikravesh 1988 §7.2 (eq. 7.13), Haug 1989 §9.2 (DP1). Footprint: the p blocks of i and j.

use crate::constraint::{Constraint, Dimension};
use crate::jet::{Form, Grad, Motion, Side};
use crate::state::{BlockUse, BodyPair, Footprint};
use nalgebra::Vector3;

/// s_iᵀ s_j − c = 0 with s'_i fixed in body i and s'_j fixed in body j (c = 0: perpendicular).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct N1 {
    /// s'_i, body-i components.
    pub s_i: Vector3<f64>,
    /// s'_j, body-j components.
    pub s_j: Vector3<f64>,
    /// c, the value held (0 for perpendicular vectors).
    pub c: f64,
}

impl N1 {
    /// n1 between s'_i (body i) and s'_j (body j): s_iᵀ s_j = 0.
    pub fn new(s_i: Vector3<f64>, s_j: Vector3<f64>) -> Self {
        Self::with_value(s_i, s_j, 0.0)
    }

    /// s_iᵀ s_j = c (for unit vectors and c = cos α: the angle α between them).
    pub fn with_value(s_i: Vector3<f64>, s_j: Vector3<f64>, c: f64) -> Self {
        Self { s_i, s_j, c }
    }
}

impl Constraint for N1 {
    fn dimension(&self, _row: usize) -> Dimension {
        Dimension::Dimensionless
    }
    fn name(&self) -> &'static str {
        "n1"
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
        out[0] = x.i.vector(&self.s_i).dot(&x.j.vector(&self.s_j)) - self.c;
    }
    fn jacobian<const N: usize, F: Form<N>>(
        &self,
        x: &BodyPair,
        _t: f64,
        out_i: &mut [[f64; N]],
        out_j: &mut [[f64; N]],
    ) {
        let si = Grad::dir::<F>(x.i, x.j, Side::I, &self.s_i);
        let sj = Grad::dir::<F>(x.i, x.j, Side::J, &self.s_j);
        si.dot(&sj).write(&mut out_i[0], &mut out_j[0]);
    }
    fn gamma_sharp<const N: usize, F: Form<N>>(&self, x: &BodyPair, _t: f64, out: &mut [f64]) {
        let si = Motion::dir::<N, F>(x.i, x.j, Side::I, &self.s_i);
        let sj = Motion::dir::<N, F>(x.i, x.j, Side::J, &self.s_j);
        out[0] = -si.dot(&sj).quad;
    }
}
