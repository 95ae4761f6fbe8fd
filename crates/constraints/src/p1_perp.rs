//! p1 in the always-rank-2 form: two n1 rows with body-fixed vectors f'_i, g'_i ⟂ s'_i.
//!
//! ```text
//! Φ = [f_iᵀ s_j; g_iᵀ s_j]                                          2 rows
//! ```
//! If f'_i, g'_i, s'_i are independent, s_j ∥ s_i ⇔ Φ = 0, and the two rows stay independent in
//! every orientation (there is no row choice to make, so nothing can chatter). Jacobian and γ# are
//! those of [`crate::N1`] for each row (Haug 1989 §9.2: a parallel constraint as two DP1).
//! Joints build f', g' from their marker frames (x and y axes of a frame whose z is s').

use crate::constraint::{Constraint, Dimension};
use crate::jet::{Form, Grad, Motion, Side};
use crate::state::{BlockUse, BodyPair, Footprint};
use nalgebra::Vector3;

/// f_iᵀ s_j = 0 and g_iᵀ s_j = 0.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct P1Perp {
    /// f'_i ⟂ s'_i, body-i components.
    pub f_i: Vector3<f64>,
    /// g'_i ⟂ s'_i, body-i components.
    pub g_i: Vector3<f64>,
    /// s'_j, body-j components.
    pub s_j: Vector3<f64>,
}

impl P1Perp {
    /// p1 as two n1 rows with f'_i, g'_i.
    pub fn new(f_i: Vector3<f64>, g_i: Vector3<f64>, s_j: Vector3<f64>) -> Self {
        Self { f_i, g_i, s_j }
    }
}

impl Constraint for P1Perp {
    fn dimension(&self, _row: usize) -> Dimension {
        Dimension::Dimensionless
    }
    fn name(&self) -> &'static str {
        "p1_perp"
    }
    fn rows(&self) -> usize {
        2
    }
    fn footprint(&self) -> Footprint {
        Footprint {
            i: BlockUse::P,
            j: BlockUse::P,
        }
    }
    fn phi(&self, x: &BodyPair, _t: f64, out: &mut [f64]) {
        let sj = x.j.vector(&self.s_j);
        out[0] = x.i.vector(&self.f_i).dot(&sj);
        out[1] = x.i.vector(&self.g_i).dot(&sj);
    }
    fn jacobian<const N: usize, F: Form<N>>(
        &self,
        x: &BodyPair,
        _t: f64,
        out_i: &mut [[f64; N]],
        out_j: &mut [[f64; N]],
    ) {
        let sj = Grad::dir::<F>(x.i, x.j, Side::J, &self.s_j);
        for (k, v) in [self.f_i, self.g_i].iter().enumerate() {
            let u = Grad::dir::<F>(x.i, x.j, Side::I, v);
            u.dot(&sj).write(&mut out_i[k], &mut out_j[k]);
        }
    }
    fn gamma_sharp<const N: usize, F: Form<N>>(&self, x: &BodyPair, _t: f64, out: &mut [f64]) {
        let sj = Motion::dir::<N, F>(x.i, x.j, Side::J, &self.s_j);
        for (k, v) in [self.f_i, self.g_i].iter().enumerate() {
            out[k] = -Motion::dir::<N, F>(x.i, x.j, Side::I, v).dot(&sj).quad;
        }
    }
}
