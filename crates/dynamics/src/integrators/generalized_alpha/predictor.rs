//! The Newton start of a step: v̇ and λ extrapolated linearly from the last two steps.

use super::scheme::Variables;

/// v̇ and λ of the step before the accepted one, and that step's size (0 when there is no such
/// step: the start, or the kept rows were chosen again).
#[derive(Debug, Clone)]
pub(super) struct History {
    pub vdot: Vec<f64>,
    pub lambda: Vec<f64>,
    pub h: f64,
}

impl History {
    /// No step before (`n` unknowns, `na` kept rows).
    pub fn new(n: usize, na: usize) -> Self {
        Self {
            vdot: vec![0.0; n],
            lambda: vec![0.0; na],
            h: 0.0,
        }
    }
}

/// The Newton start of the trial: v̇ and λ extrapolated linearly from the last two steps,
/// x_{n+1} ≈ x_n + (h / h_{n−1})(x_n − x_{n−1}), or held constant when there is no step
/// before (the start, or after the kept rows were chosen again). Its error is O(h² x⃛)
/// instead of the constant predictor's h ẍ, which grows as the motion develops (a swinging
/// chain: h v̈ of the links' accelerations) and decides how many Newton updates a step needs
/// before its acceptance test β'|Δv̇| ≤ tol passes.
pub(super) fn predict(n: &Variables, trial: &mut Variables, history: &History, h: f64) {
    trial.vdot.copy_from_slice(&n.vdot);
    trial.lambda.copy_from_slice(&n.lambda);
    if history.h > 0.0 {
        let r = h / history.h;
        for (x, (v, p)) in trial.vdot.iter_mut().zip(n.vdot.iter().zip(&history.vdot)) {
            *x += r * (v - p);
        }
        for (x, (v, p)) in trial
            .lambda
            .iter_mut()
            .zip(n.lambda.iter().zip(&history.lambda))
        {
            *x += r * (v - p);
        }
    }
}
