//! Iterative refinement of `Φ_q(x) v = rhs` with factors made at a nearby point.
//!
//! After a converged [`Newton::solve`](super::Newton::solve) the factors are usually those of
//! the last iteration, a tiny step `δ` away from the solution `x`. Instead of refactoring there
//! for the velocity and acceleration solves, correct with the exact Jacobian `A = Φ_q(x)` and the
//! old factors `M` (Golub & Van Loan, §3.5.3):
//!
//! ```text
//!   v ← v + M⁻¹ (rhs − A v)
//! ```
//!
//! The error contracts by about `‖M⁻¹ (M − A)‖`, the relative change of the Jacobian over `δ`.
//! The test is the backward error
//!
//! ```text
//!   β = max_i w_i |rhs − A v|_i / max_i w_i (|A| |v| + |rhs|)_i
//! ```
//!
//! over the solved rows, in the units of the equation scales: the relative change of `A` and
//! `rhs` that makes `v` exact. A fresh factorization delivers a few ε; unlike the size of the last
//! correction it does not depend on the conditioning (a long chain's corrections stall at about
//! `κ ε ‖v‖` while its backward error is already ε).

use super::factorization::Factorization;
use super::weights::Weights;
use crate::error::SolverError;
use crate::linear::LinearSolver;

/// Largest scaled distance between the point of the factorization and the current state at
/// which [`Newton::solve_linear_at`](super::Newton::solve_linear_at) refines instead of
/// refactoring: the refinement contracts by about the relative change of the Jacobian, so a few
/// corrections then reach rounding level.
pub const REFINE_MAX_DRIFT: f64 = 1e-5;

/// Corrections [`Newton::solve_linear_at`](super::Newton::solve_linear_at) makes before it gives
/// up and refactors.
pub const REFINE_MAX_CORRECTIONS: usize = 4;

/// Backward error at which [`Newton::solve_linear_at`](super::Newton::solve_linear_at) accepts a
/// refined solution: `‖rhs − Φ_q v‖ ≤ 8ε ‖|Φ_q| |v| + |rhs|‖` in the max norm over rows weighted
/// by their equation scales, about what the residual of a few-entry constraint row resolves in
/// floating point.
pub const REFINE_BACKWARD_ERROR: f64 = 8.0 * f64::EPSILON;

/// The buffers of the refinement: residual and its scale (length `m`), correction (length `n`).
#[derive(Debug)]
pub(super) struct Refinement {
    r: Vec<f64>,
    s: Vec<f64>,
    dy: Vec<f64>,
}

impl Refinement {
    /// Buffers for `m` equations and `n` unknowns.
    pub(super) fn new(m: usize, n: usize) -> Self {
        Self {
            r: vec![0.0; m],
            s: vec![0.0; m],
            dy: vec![0.0; n],
        }
    }

    /// Solves `A v = rhs` into `out` with the factors of `fact` and refines against the exact
    /// Jacobian in `fact.full_slots`: `Ok(true)` once `β ≤` [`REFINE_BACKWARD_ERROR`],
    /// `Ok(false)` when it does not get there (a correction that does not halve `β`, or
    /// [`REFINE_MAX_CORRECTIONS`] spent). No allocation.
    pub(super) fn run<S: LinearSolver>(
        &mut self,
        fact: &mut Factorization<S>,
        weights: &Weights,
        scaled: bool,
        rhs: &[f64],
        out: &mut [f64],
    ) -> Result<bool, SolverError> {
        fact.solve(rhs, 1.0, out, weights, scaled)?;
        let mut last = f64::INFINITY;
        for correction in 0..=REFINE_MAX_CORRECTIONS {
            let berr = self.backward_error(fact, weights, rhs, out);
            if berr <= REFINE_BACKWARD_ERROR {
                return Ok(true);
            }
            // (A NaN backward error, after an overflow, also ends here: refactor.)
            if correction == REFINE_MAX_CORRECTIONS || berr.is_nan() || berr > 0.5 * last {
                return Ok(false);
            }
            last = berr;
            fact.solve(&self.r, 1.0, &mut self.dy, weights, scaled)?;
            for (o, d) in out.iter_mut().zip(&self.dy) {
                *o += d;
            }
        }
        Ok(false)
    }

    /// `β` of `v`, leaving `r = rhs − A v` in `self.r`.
    fn backward_error<S>(
        &mut self,
        fact: &Factorization<S>,
        weights: &Weights,
        rhs: &[f64],
        v: &[f64],
    ) -> f64 {
        // r = rhs − A v and s = |rhs| + |A| |v| on the solved rows.
        self.r.copy_from_slice(rhs);
        for (si, ri) in self.s.iter_mut().zip(rhs) {
            *si = ri.abs();
        }
        fact.map
            .residual_and_scale(&fact.full_slots, v, &mut self.r, &mut self.s);
        let (mut r_max, mut s_max) = (0.0f64, 0.0f64);
        for &i in &fact.map.solve_rows {
            let w = weights.eq[i];
            r_max = r_max.max(self.r[i].abs() * w);
            s_max = s_max.max(self.s[i] * w);
        }
        if r_max == 0.0 {
            0.0
        } else {
            r_max / s_max
        }
    }
}
