//! The convergence rate of chord steps, and the error they leave.
//!
//! A chord step (modified Newton: factors made at an earlier iterate) converges linearly,
//! `‖Δ_{k+1}‖ ≈ θ ‖Δ_k‖` with `θ ≈ ‖M⁻¹ (M − Φ_q)‖` (Deuflhard, *Newton Methods for Nonlinear
//! Problems*, §2.1.2; the same estimate as in implicit ODE codes, Hairer & Wanner, *Solving
//! Ordinary Differential Equations II*, §IV.8). `θ` is estimated by the largest ratio of
//! consecutive steps made with the current factors (the rate need not be steady: several modes
//! give oscillating ratios), or for the first chord step by the residual ratio. A contracting
//! iteration then leaves an error of at most
//!
//! ```text
//!   ‖x* − x_{k+1}‖ ≤ θ / (1 − θ) ‖Δ_k‖
//! ```
//!
//! which the convergence test compares with `τ_step²`, the error a Newton step of length
//! `τ_step` leaves ([`convergence`](crate::convergence)).

/// The step ratios of the current factorization.
#[derive(Debug, Clone, Copy)]
pub(super) struct ChordRate {
    /// Scaled length of the last step made with the current factors (NaN: none yet).
    last_step: f64,
    /// Largest ratio of consecutive steps made with them (0: none yet).
    theta: f64,
}

impl ChordRate {
    /// No step made yet.
    pub(super) fn new() -> Self {
        Self {
            last_step: f64::NAN,
            theta: 0.0,
        }
    }

    /// New factors (or a new solve): forget the ratios.
    pub(super) fn reset(&mut self) {
        *self = Self::new();
    }

    /// The estimate `θ` after a chord step of scaled length `step` that took the scaled residual
    /// from `rn` to `new_rn`.
    pub(super) fn observe_chord(&mut self, step: f64, rn: f64, new_rn: f64) -> f64 {
        if self.last_step.is_nan() {
            return if rn > 0.0 { new_rn / rn } else { 0.0 };
        }
        let ratio = if step == 0.0 {
            0.0
        } else {
            step / self.last_step
        };
        self.theta = self.theta.max(ratio);
        self.theta
    }

    /// Records the length of a step made with the current factors (Newton or chord).
    pub(super) fn record(&mut self, step: f64) {
        self.last_step = step;
    }
}

/// Error bound `θ / (1 − θ) · step` left by a chord step with rate `θ < 1`.
pub(super) fn chord_error(step: f64, theta: f64) -> f64 {
    step * theta / (1.0 - theta)
}
