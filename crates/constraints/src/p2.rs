//! p2, "parallel type 2", full three-row form: the vector d between a point of body i and a
//! point of body j stays parallel to a vector of body i.
//!
//! ```text
//! d = r_j + A_j s'^P_j − r_i − A_i s'^P_i
//! Φ = s̃_i d = s_i × d                                             3 rows, rank 2
//! Φ_q = [−s̃_i, −s̃_i B_i − d̃ C_i, s̃_i, s̃_i B_j]
//! γ#  = −(s̈_i × d + 2 ṡ_i × ḋ + s_i × d̈)
//! ```
//! Nikravesh 1988 §7.2 (eq. 7.21). As for [`crate::P1`], joints use the two-row forms
//! [`crate::P2Perp`] or [`crate::P2Select`].

use crate::constraint::{Constraint, Dimension};
use crate::jet::{write_rows, Form, Grad, Motion, Side};
use crate::state::{BlockUse, BodyPair, Footprint};
use nalgebra::Vector3;

/// s_i × d = 0 (three rows).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct P2 {
    /// s'_i, body-i components.
    pub s_i: Vector3<f64>,
    /// s'^P_i.
    pub sp_i: Vector3<f64>,
    /// s'^P_j.
    pub sp_j: Vector3<f64>,
}

impl P2 {
    /// p2 with direction s'_i and points s'^P_i, s'^P_j.
    pub fn new(s_i: Vector3<f64>, sp_i: Vector3<f64>, sp_j: Vector3<f64>) -> Self {
        Self { s_i, sp_i, sp_j }
    }
}

impl Constraint for P2 {
    fn dimension(&self, _row: usize) -> Dimension {
        Dimension::Length
    }
    fn name(&self) -> &'static str {
        "p2"
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
        let d = x.j.point(&self.sp_j) - x.i.point(&self.sp_i);
        let c = x.i.vector(&self.s_i).cross(&d);
        out[..3].copy_from_slice(c.as_slice());
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
        write_rows(&si.cross(&d), out_i, out_j);
    }
    fn gamma_sharp<const N: usize, F: Form<N>>(&self, x: &BodyPair, _t: f64, out: &mut [f64]) {
        let si = Motion::dir::<N, F>(x.i, x.j, Side::I, &self.s_i);
        let d = Motion::between::<N, F>(x.i, x.j, &self.sp_i, &self.sp_j);
        let q = si.cross(&d).quad;
        for k in 0..3 {
            out[k] = -q[k];
        }
    }
}
