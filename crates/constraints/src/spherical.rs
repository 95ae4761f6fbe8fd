//! s, the spherical (coincident-point) primitive: a point of body i on a point of body j.
//!
//! ```text
//! Φ = r^P_i − r^P_j = r_i + A_i s'^P_i − r_j − A_j s'^P_j         3 rows
//! Φ_q = [I, B_i, −I, −B_j]                 B_k = ∂(A_k s'^P_k)/∂p_k = 2 (G_k s̄'^P_k + s'^P_k p_kᵀ)
//! Φ_v = [I, −A_i s̃'^P_i, −I, A_j s̃'^P_j]
//! γ#  = −s̈^P_i + s̈^P_j      6-coordinate: −ω̃_i ω̃_i s^P_i + ω̃_j ω̃_j s^P_j
//!                            7-coordinate: −B_i(ṗ_i) ṗ_i + B_j(ṗ_j) ṗ_j
//! ```
//! Nikravesh 1988 §7.3 (eq. 7.26), Haug 1989 §9.2 (SPH). Footprint: r and p of both bodies.

use crate::constraint::{Constraint, Dimension};
use crate::jet::{write_rows, Form, Grad, Motion, Side};
use crate::state::{BlockUse, BodyPair, Footprint};
use nalgebra::Vector3;

/// r^P_i − r^P_j = 0.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Spherical {
    /// s'^P_i, the point in body i.
    pub sp_i: Vector3<f64>,
    /// s'^P_j, the point in body j.
    pub sp_j: Vector3<f64>,
}

impl Spherical {
    /// Coincident points s'^P_i (body i) and s'^P_j (body j).
    pub fn new(sp_i: Vector3<f64>, sp_j: Vector3<f64>) -> Self {
        Self { sp_i, sp_j }
    }
}

impl Constraint for Spherical {
    fn dimension(&self, _row: usize) -> Dimension {
        Dimension::Length
    }
    fn name(&self) -> &'static str {
        "s"
    }
    fn rows(&self) -> usize {
        3
    }
    fn footprint(&self) -> Footprint {
        Footprint {
            i: BlockUse::RP,
            j: BlockUse::RP,
        }
    }
    fn phi(&self, x: &BodyPair, _t: f64, out: &mut [f64]) {
        let v = x.i.point(&self.sp_i) - x.j.point(&self.sp_j);
        out[..3].copy_from_slice(v.as_slice());
    }
    fn jacobian<const N: usize, F: Form<N>>(
        &self,
        x: &BodyPair,
        _t: f64,
        out_i: &mut [[f64; N]],
        out_j: &mut [[f64; N]],
    ) {
        let pi = Grad::point::<F>(x.i, x.j, Side::I, &self.sp_i);
        let pj = Grad::point::<F>(x.i, x.j, Side::J, &self.sp_j);
        write_rows(&pi.sub(&pj), out_i, out_j);
    }
    fn gamma_sharp<const N: usize, F: Form<N>>(&self, x: &BodyPair, _t: f64, out: &mut [f64]) {
        let pi = Motion::point::<N, F>(x.i, x.j, Side::I, &self.sp_i);
        let pj = Motion::point::<N, F>(x.i, x.j, Side::J, &self.sp_j);
        let q = pi.sub(&pj).quad;
        for k in 0..3 {
            out[k] = -q[k];
        }
    }
}
