//! When to refactor the Jacobian ([`JacobianUpdate`]).
//!
//! Full Newton refactors at every iteration. Modified Newton keeps the factors while they earn
//! their keep, and refactors at the current iterate when
//!
//! * they have served `max_age` iterations of this solve;
//! * the scaled residual did not contract by `min_contraction`, `‖Φ_{k+1}‖ > c ‖Φ_k‖`;
//! * the estimated chord rate `θ` (`rate.rs`) exceeds `min_contraction`;
//! * the chord steps left (`max_age − age`) are not expected to pass the step test,
//!   `θ/(1−θ) ‖Δ‖ · θ^left > τ_step²`: Newton converges from here in fewer steps;
//! * a chord direction failed its line-search trial.

use super::options::JacobianUpdate;
use super::rate::chord_error;

/// Jacobian-reuse state of one solve: the age of the factors and a pending refactor request.
#[derive(Debug, Clone, Copy, Default)]
pub(super) struct RefactorPolicy {
    /// Iterations the current factors have served in this solve.
    age: usize,
    /// A check failed: refactor before the next step.
    forced: bool,
}

impl RefactorPolicy {
    /// A new solve (or new factors): age 0, nothing pending.
    pub(super) fn reset(&mut self) {
        *self = Self::default();
    }

    /// New factors: age 0.
    pub(super) fn factored(&mut self) {
        self.age = 0;
    }

    /// A step was made with the current factors.
    pub(super) fn stepped(&mut self) {
        self.age += 1;
    }

    /// Refactor before the next step.
    pub(super) fn force(&mut self) {
        self.forced = true;
    }

    /// Whether the next step needs new factors (`factored`: factors exist); clears a pending
    /// request.
    pub(super) fn take_decision(&mut self, update: JacobianUpdate, factored: bool) -> bool {
        let need = !factored
            || self.forced
            || match update {
                JacobianUpdate::Modified { max_age, .. } => self.age >= max_age.max(1),
                JacobianUpdate::EveryIteration => true,
            };
        self.forced = false;
        need
    }

    /// After a step of scaled length `step` that took the scaled residual from `rn` to
    /// `new_rn`, with the rate estimate `theta` of a chord step (`None` for a Newton step):
    /// requests a refactor when one of the checks fails, and returns the error bound of the
    /// chord step ([`chord_error`]) when its rate is acceptable, infinity otherwise
    /// (`tau2 = τ_step²`). Full Newton: no checks, infinity.
    pub(super) fn after_step(
        &mut self,
        update: JacobianUpdate,
        (rn, new_rn): (f64, f64),
        step: f64,
        theta: Option<f64>,
        tau2: f64,
    ) -> f64 {
        let JacobianUpdate::Modified {
            max_age,
            min_contraction,
        } = update
        else {
            return f64::INFINITY;
        };
        if new_rn > min_contraction * rn {
            self.forced = true;
        }
        let Some(theta) = theta else {
            return f64::INFINITY;
        };
        if theta > min_contraction {
            self.forced = true;
            return f64::INFINITY;
        }
        let error = chord_error(step, theta);
        // Chord steps left with these factors in this solve: if they are not expected to reach
        // the step test, refactor now rather than spend them.
        let left = max_age.max(1).saturating_sub(self.age);
        if error > tau2 && (left == 0 || error * theta.powi(left.min(64) as i32) > tau2) {
            self.forced = true;
        }
        error
    }
}
