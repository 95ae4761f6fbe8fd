//! p1, "parallel type 1", full three-row form: a vector of body i parallel to a vector of body j.
//!
//! ```text
//! Φ = s̃_i s_j = s_i × s_j                                         3 rows, rank 2
//! Φ_q = [0, −s̃_j C_i, 0, s̃_i C_j]
//! Φ_v = [0, s̃_j A_i s̃'_i, 0, −s̃_i A_j s̃'_j]
//! γ#  = −(s̈_i × s_j + 2 ṡ_i × ṡ_j + s_i × s̈_j)
//! ```
//! Nikravesh 1988 §7.2 (eq. 7.19). Only two of the three rows are independent, so a square
//! Newton system cannot use this form directly; joints use [`crate::P1Perp`] (always rank 2) or
//! [`crate::P1Select`] (the seed's two-row selection). This form is the reference the two are
//! checked against, and is available to solvers that handle redundant rows.

use crate::constraint::{Constraint, Dimension};
use crate::jet::{write_rows, Form, Grad, Motion, Side};
use crate::state::{BlockUse, BodyPair, Footprint};
use nalgebra::Vector3;

/// s_i × s_j = 0 (three rows).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct P1 {
    /// s'_i, body-i components.
    pub s_i: Vector3<f64>,
    /// s'_j, body-j components.
    pub s_j: Vector3<f64>,
}

impl P1 {
    /// p1 between s'_i and s'_j.
    pub fn new(s_i: Vector3<f64>, s_j: Vector3<f64>) -> Self {
        Self { s_i, s_j }
    }
}

impl Constraint for P1 {
    fn dimension(&self, _row: usize) -> Dimension {
        Dimension::Dimensionless
    }
    fn name(&self) -> &'static str {
        "p1"
    }
    fn rows(&self) -> usize {
        3
    }
    fn footprint(&self) -> Footprint {
        Footprint {
            i: BlockUse::P,
            j: BlockUse::P,
        }
    }
    fn phi(&self, x: &BodyPair, _t: f64, out: &mut [f64]) {
        let c = x.i.vector(&self.s_i).cross(&x.j.vector(&self.s_j));
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
        let sj = Grad::dir::<F>(x.i, x.j, Side::J, &self.s_j);
        write_rows(&si.cross(&sj), out_i, out_j);
    }
    fn gamma_sharp<const N: usize, F: Form<N>>(&self, x: &BodyPair, _t: f64, out: &mut [f64]) {
        let si = Motion::dir::<N, F>(x.i, x.j, Side::I, &self.s_i);
        let sj = Motion::dir::<N, F>(x.i, x.j, Side::J, &self.s_j);
        let q = si.cross(&sj).quad;
        for k in 0..3 {
            out[k] = -q[k];
        }
    }
}
