//! p2 in the always-rank-2 form: two n2 rows with body-fixed vectors f'_i, g'_i ⟂ s'_i.
//!
//! ```text
//! d = r^P_j − r^P_i
//! Φ = [f_iᵀ d; g_iᵀ d]                                              2 rows
//! ```
//! d ∥ s_i ⇔ Φ = 0 when f'_i, g'_i, s'_i are independent. Jacobian and γ# are those of
//! [`crate::N2`] for each row (Haug 1989 §9.2: two DP2).

use crate::constraint::{Constraint, Dimension};
use crate::jet::{Form, Grad, Motion, Side};
use crate::state::{BlockUse, BodyPair, Footprint};
use nalgebra::Vector3;

/// f_iᵀ d = 0 and g_iᵀ d = 0.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct P2Perp {
    /// f'_i ⟂ s'_i, body-i components.
    pub f_i: Vector3<f64>,
    /// g'_i ⟂ s'_i, body-i components.
    pub g_i: Vector3<f64>,
    /// s'^P_i.
    pub sp_i: Vector3<f64>,
    /// s'^P_j.
    pub sp_j: Vector3<f64>,
}

impl P2Perp {
    /// p2 as two n2 rows with f'_i, g'_i and points s'^P_i, s'^P_j.
    pub fn new(
        f_i: Vector3<f64>,
        g_i: Vector3<f64>,
        sp_i: Vector3<f64>,
        sp_j: Vector3<f64>,
    ) -> Self {
        Self {
            f_i,
            g_i,
            sp_i,
            sp_j,
        }
    }
}

impl Constraint for P2Perp {
    fn dimension(&self, _row: usize) -> Dimension {
        Dimension::Length
    }
    fn name(&self) -> &'static str {
        "p2_perp"
    }
    fn rows(&self) -> usize {
        2
    }
    fn footprint(&self) -> Footprint {
        Footprint {
            i: BlockUse::RP,
            j: BlockUse::RP,
        }
    }
    fn phi(&self, x: &BodyPair, _t: f64, out: &mut [f64]) {
        let d = x.j.point(&self.sp_j) - x.i.point(&self.sp_i);
        out[0] = x.i.vector(&self.f_i).dot(&d);
        out[1] = x.i.vector(&self.g_i).dot(&d);
    }
    fn jacobian<const N: usize, F: Form<N>>(
        &self,
        x: &BodyPair,
        _t: f64,
        out_i: &mut [[f64; N]],
        out_j: &mut [[f64; N]],
    ) {
        let d = Grad::between::<F>(x.i, x.j, &self.sp_i, &self.sp_j);
        for (k, v) in [self.f_i, self.g_i].iter().enumerate() {
            let u = Grad::dir::<F>(x.i, x.j, Side::I, v);
            u.dot(&d).write(&mut out_i[k], &mut out_j[k]);
        }
    }
    fn gamma_sharp<const N: usize, F: Form<N>>(&self, x: &BodyPair, _t: f64, out: &mut [f64]) {
        let d = Motion::between::<N, F>(x.i, x.j, &self.sp_i, &self.sp_j);
        for (k, v) in [self.f_i, self.g_i].iter().enumerate() {
            out[k] = -Motion::dir::<N, F>(x.i, x.j, Side::I, v).dot(&d).quad;
        }
    }
}
