//! The weights of the scaled norms: reciprocals of the system's equation and unknown scales.
//!
//! ```text
//!   w_i = 1 / e_i  (equations),    v_j = 1 / u_j  (step unknowns)
//! ```
//!
//! The residual test, the line search's merit and the scaling of the linear system all use them
//! (see [`convergence`](crate::convergence)). They are recomputed only when the system reports
//! other scales, so the usual solve reads the scales and compares, nothing more.

use super::NonlinearSystem;
use crate::convergence::reciprocal_in_place;

/// Equation and unknown weights, with the scales they came from.
#[derive(Debug)]
pub(super) struct Weights {
    /// `w_i = 1 / e_i`; 0 for a dropped row when convergence is judged on the kept rows only.
    pub(super) eq: Vec<f64>,
    /// `v_j = 1 / u_j`.
    pub(super) unknown: Vec<f64>,
    /// Scratch for the scales just read (then their reciprocals).
    new_eq: Vec<f64>,
    new_unknown: Vec<f64>,
    /// The scales the weights were computed from (NaN before the first read).
    eq_scales: Vec<f64>,
    unknown_scales: Vec<f64>,
}

impl Weights {
    /// Unit weights for `m` equations and `n` unknowns; the first [`update`](Self::update) reads
    /// the system's scales.
    pub(super) fn new(m: usize, n: usize) -> Self {
        Self {
            eq: vec![1.0; m],
            unknown: vec![1.0; n],
            new_eq: vec![1.0; m],
            new_unknown: vec![1.0; n],
            eq_scales: vec![f64::NAN; m],
            unknown_scales: vec![f64::NAN; n],
        }
    }

    /// Forgets the scales, so the next [`update`](Self::update) recomputes the weights.
    pub(super) fn forget_scales(&mut self) {
        self.eq_scales.fill(f64::NAN);
    }

    /// Reads the scales from `system`; when they differ from the last ones, recomputes the
    /// weights, giving the rows `zero_rows` weight 0 (they leave the residual norm and the
    /// merit). Returns whether the weights changed. No allocation.
    pub(super) fn update<N: NonlinearSystem + ?Sized>(
        &mut self,
        system: &N,
        zero_rows: &[usize],
    ) -> bool {
        system.equation_scales(&mut self.new_eq);
        system.unknown_scales(&mut self.new_unknown);
        if self.new_eq == self.eq_scales && self.new_unknown == self.unknown_scales {
            // Same scales as last time (the usual case): same weights.
            return false;
        }
        self.eq_scales.copy_from_slice(&self.new_eq);
        self.unknown_scales.copy_from_slice(&self.new_unknown);
        reciprocal_in_place(&mut self.new_eq);
        reciprocal_in_place(&mut self.new_unknown);
        for &r in zero_rows {
            self.new_eq[r] = 0.0;
        }
        if self.new_eq == self.eq && self.new_unknown == self.unknown {
            return false;
        }
        self.eq.copy_from_slice(&self.new_eq);
        self.unknown.copy_from_slice(&self.new_unknown);
        true
    }
}
