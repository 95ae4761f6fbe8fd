//! Scaled convergence tests for Newton-Raphson.
//!
//! A model in millimetres and the same model in kilometres must converge alike, so both tests are
//! made on scaled quantities:
//!
//! ```text
//!   residual test:  ‖Φ‖_w = max_i |Φ_i| / e_i  ≤ residual_tolerance
//!   step test:      ‖Δq‖_w = max_j |Δq_j| / u_j ≤ step_tolerance
//! ```
//!
//! with equation scales `e_i` and unknown scales `u_j` supplied by the
//! [`NonlinearSystem`](crate::NonlinearSystem) (default 1). For a mechanism with characteristic
//! length `L`: `u = L` for positions and `1` for Euler parameters (or rotations); `e = L` for
//! equations that are lengths (spherical, n2, p2), `L²` for the squared distance constraint and
//! `1` for direction equations (n1, p1) and normalization rows. With those scales the iterates of
//! the mm and km models are the same numbers times `L`, and the tests see identical values.
//!
//! Newton-Raphson has converged when the residual test holds and either no step has been taken
//! yet (the starting point already satisfies the equations) or the last step passed the step test.
//! With quadratic convergence a last step of `1e-6` (scaled) leaves an error of about `1e-12`,
//! hence the default step tolerance.

/// Tolerances of the scaled tests.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Tolerances {
    /// Bound on `max_i |Φ_i| / e_i`. Default `1e-10`.
    pub residual: f64,
    /// Bound on `max_j |Δq_j| / u_j` for the last step. Default `1e-6`.
    pub step: f64,
}

impl Default for Tolerances {
    fn default() -> Self {
        Self {
            residual: 1e-10,
            step: 1e-6,
        }
    }
}

impl Tolerances {
    /// Refuses tolerances that cannot give a meaningful solution: the residual tolerance must
    /// be in [1e-14, 1e-6] (a looser one leaves the equations visibly open, a tighter one asks
    /// for less than roundoff), the step tolerance in [1e-14, 1e-2].
    ///
    /// # Errors
    /// A sentence naming the tolerance, its value and its range.
    pub fn validate(&self) -> Result<(), String> {
        let check = |name: &str, v: f64, hi: f64, default: f64| {
            if (1e-14..=hi).contains(&v) {
                Ok(())
            } else {
                let value = if v == 0.0 || (1e-3..1e6).contains(&v.abs()) {
                    format!("{v}")
                } else {
                    format!("{v:e}")
                };
                Err(format!(
                    "{name} tolerance = {value} is outside its sensible range [1e-14, {hi:e}] \
                     (default {default:e}): a looser one leaves the equations visibly open, a \
                     tighter one asks for less than roundoff"
                ))
            }
        };
        check("residual", self.residual, 1e-6, 1e-10)?;
        check("step", self.step, 1e-2, 1e-6)
    }
}

impl Tolerances {
    /// The convergence test of Newton-Raphson: the residual test holds, and either no step has
    /// been taken (`first`) or the estimated error left by the last step is `≤ τ_step²`.
    pub(crate) fn converged(&self, residual_norm: f64, first: bool, step_error: f64) -> bool {
        residual_norm <= self.residual && (first || step_error <= self.step * self.step)
    }

    /// The error estimate of a Newton step of scaled length `step` (factors made where it
    /// starts), for [`converged`](Self::converged): it leaves about `step²`, which passes when
    /// `step ≤ τ_step` (0) and does not otherwise (∞).
    pub(crate) fn newton_step_error(&self, step: f64) -> f64 {
        if step <= self.step {
            0.0
        } else {
            f64::INFINITY
        }
    }
}

/// `max_i |v_i| · w_i` and its index (weights are reciprocal scales). No allocation.
pub fn weighted_inf_norm(v: &[f64], weights: &[f64]) -> (f64, usize) {
    let mut best = 0.0;
    let mut arg = 0;
    for (i, (a, w)) in v.iter().zip(weights).enumerate() {
        let s = (a * w).abs();
        if s > best || s.is_nan() {
            best = s;
            arg = i;
            if s.is_nan() {
                break;
            }
        }
    }
    (best, arg)
}

/// `Σ_i (v_i w_i)²`, the merit function of the line search (without the ½). No allocation.
pub fn weighted_sum_squares(v: &[f64], weights: &[f64]) -> f64 {
    v.iter().zip(weights).map(|(a, w)| (a * w) * (a * w)).sum()
}

/// The `count` largest `|v_i| w_i` as `(i, |v_i| w_i)`, largest first. Allocates: error path only.
pub fn worst_entries(v: &[f64], weights: &[f64], count: usize) -> Vec<(usize, f64)> {
    let mut all: Vec<(usize, f64)> = v
        .iter()
        .zip(weights)
        .enumerate()
        .map(|(i, (a, w))| (i, (a * w).abs()))
        .collect();
    all.sort_by(|a, b| b.1.total_cmp(&a.1).then(a.0.cmp(&b.0)));
    all.truncate(count);
    all
}

/// Reciprocals of positive scales (non-positive or non-finite scales count as 1).
pub(crate) fn reciprocal_in_place(s: &mut [f64]) {
    for v in s {
        *v = if *v > 0.0 && v.is_finite() {
            1.0 / *v
        } else {
            1.0
        };
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn norms_and_worst() {
        let v = [1.0, -4.0, 2.0];
        let w = [1.0, 0.5, 2.0];
        assert_eq!(weighted_inf_norm(&v, &w), (4.0, 2));
        assert_eq!(weighted_sum_squares(&v, &w), 1.0 + 4.0 + 16.0);
        assert_eq!(worst_entries(&v, &w, 2), vec![(2, 4.0), (1, 2.0)]);
        let mut s = [2.0, 0.0, f64::NAN];
        reciprocal_in_place(&mut s);
        assert_eq!(s, [0.5, 1.0, 1.0]);
    }
}
