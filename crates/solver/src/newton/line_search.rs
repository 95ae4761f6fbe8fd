//! Backtracking line search on the scaled residual (Dennis & Schnabel, §6.3).
//!
//! The merit of a state is `f(x) = Σ_i (Φ_i(x) / e_i)²`. The Newton direction `Δ` is a descent
//! direction of `f` with `∇f · Δ = −2 f`, so the Armijo condition for the trial `x ⊕ αΔ` reads
//!
//! ```text
//!   f(x ⊕ αΔ) ≤ (1 − 2 c α) f(x)
//! ```
//!
//! Starting from `α = 1` (or the step cap), `α` is halved until the condition holds. With a
//! direction from a fresh factorization, when no halving satisfies it, the trial with the
//! smallest merit is taken if it decreases `f` at all. A direction from an older factorization
//! (chord step) gets one trial only: if it fails, refactoring gives a better direction than
//! shortening a poor one.

use super::options::LineSearch;
use super::{eval_residual, NonlinearSystem};
use crate::convergence::weighted_sum_squares;
use crate::error::{NonFiniteLocation, SolverError};

/// What the line search found.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) enum Outcome {
    /// A step `x ⊕ αΔ` to take; its state and residual are in the trial buffers.
    Accepted {
        /// The step length `α`.
        alpha: f64,
    },
    /// A chord direction failed its trial: refactor and retry.
    StaleDirection,
    /// No trial decreased the merit.
    NoDecrease,
}

/// The trial state, its step and residual (allocated at setup and at the first solve).
#[derive(Debug)]
pub(super) struct Backtracking {
    /// Trial state `x ⊕ αΔ`.
    pub(super) x: Vec<f64>,
    /// Trial step `αΔ`.
    step: Vec<f64>,
    /// `Φ` at the trial state.
    pub(super) residual: Vec<f64>,
}

/// The fixed inputs of one search.
pub(super) struct Direction<'a> {
    /// The state the step starts from.
    pub(super) x: &'a [f64],
    /// The full step `Δ`.
    pub(super) dx: &'a [f64],
    /// The first `α` (1, or less under a step cap).
    pub(super) alpha: f64,
    /// `f(x)`.
    pub(super) merit: f64,
    /// `Δ` comes from a factorization made at `x` (a Newton step, not a chord step).
    pub(super) fresh: bool,
    /// The Newton iteration (for error messages).
    pub(super) iteration: usize,
}

impl Backtracking {
    /// Buffers for `m` equations and `n` step unknowns; the state buffer is sized by
    /// [`fit_state`](Self::fit_state).
    pub(super) fn new(m: usize, n: usize) -> Self {
        Self {
            x: Vec::new(),
            step: vec![0.0; n],
            residual: vec![0.0; m],
        }
    }

    /// Sizes the trial state to `len`; returns whether it allocated (first call, or another
    /// state length).
    pub(super) fn fit_state(&mut self, len: usize) -> bool {
        if self.x.len() == len {
            return false;
        }
        self.x = vec![0.0; len];
        true
    }

    /// Searches along `dir`, counting residual evaluations in `evaluations`.
    ///
    /// # Errors
    /// [`SolverError::NonFinite`] for a non-finite trial state or residual.
    pub(super) fn search<N: NonlinearSystem + ?Sized>(
        &mut self,
        system: &mut N,
        dir: &Direction<'_>,
        rule: LineSearch,
        eq_weights: &[f64],
        evaluations: &mut usize,
    ) -> Result<Outcome, SolverError> {
        let (max_halvings, c) = match rule {
            LineSearch::None => (0, 0.0),
            LineSearch::Backtracking {
                max_halvings,
                sufficient_decrease,
            } => (max_halvings, sufficient_decrease),
        };
        let mut alpha = dir.alpha;
        let mut halvings = 0;
        let (mut best_alpha, mut best_merit) = (0.0, dir.merit);
        loop {
            self.trial(system, dir, alpha)?;
            *evaluations += 1;
            let trial_merit = weighted_sum_squares(&self.residual, eq_weights);
            let ok = matches!(rule, LineSearch::None)
                || trial_merit <= (1.0 - 2.0 * c * alpha) * dir.merit
                || trial_merit <= f64::MIN_POSITIVE;
            if ok {
                return Ok(Outcome::Accepted { alpha });
            }
            if trial_merit < best_merit {
                (best_alpha, best_merit) = (alpha, trial_merit);
            }
            if !dir.fresh {
                return Ok(Outcome::StaleDirection);
            }
            if halvings >= max_halvings {
                break;
            }
            halvings += 1;
            alpha *= 0.5;
        }
        if best_alpha > 0.0 {
            // No sufficient decrease, but some decrease: take the best trial.
            self.trial(system, dir, best_alpha)?;
            *evaluations += 1;
            return Ok(Outcome::Accepted { alpha: best_alpha });
        }
        Ok(Outcome::NoDecrease)
    }

    /// `x_trial = x ⊕ αΔ` and its residual.
    fn trial<N: NonlinearSystem + ?Sized>(
        &mut self,
        system: &mut N,
        dir: &Direction<'_>,
        alpha: f64,
    ) -> Result<(), SolverError> {
        self.x.copy_from_slice(dir.x);
        for (s, d) in self.step.iter_mut().zip(dir.dx) {
            *s = alpha * d;
        }
        system.apply_step(&mut self.x, &self.step);
        if let Some(index) = self.x.iter().position(|v| !v.is_finite()) {
            return Err(SolverError::NonFinite {
                location: NonFiniteLocation::Unknown { index },
                iteration: Some(dir.iteration),
            });
        }
        eval_residual(system, &self.x, &mut self.residual, dir.iteration)
    }
}
