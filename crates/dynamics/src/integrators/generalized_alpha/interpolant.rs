//! A state inside a generalized-α step, for locating events: the scheme has no continuous
//! extension of its own, so the increment from the step's start is interpolated by the cubic
//! Hermite polynomial of its ends,
//!
//! ```text
//! Δ(θ) = h₁₀(θ) h v₀ + h₀₁(θ) Δ + h₁₁(θ) h v₁,   q(θ) = q₀ ⊕ Δ(θ),   v(θ) = Δ'(θ) / h
//! h₁₀ = θ³ − 2θ² + θ,   h₀₁ = −2θ³ + 3θ²,   h₁₁ = θ³ − θ²
//! ```
//!
//! with θ = (t − t₀)/h, Δ the step's increment (q₁ = q₀ ⊕ Δ) and v₀, v₁ its end velocities. It
//! meets both ends in position and velocity; inside, its error is O(h⁴) in translation and
//! O(h²|ω|²) in rotation (ω'₁, in the frame at t₁, stands for the increment's rate in the frame
//! at t₀), within the scheme's own second-order error.

use crate::state::State;
use cardan_mechanism::apply_rotation_step;

/// The interpolated state and increment (preallocated).
#[derive(Debug, Clone)]
pub(super) struct Interpolant {
    s: State,
    dq: Vec<f64>,
}

impl Interpolant {
    /// Buffers shaped like `state`.
    pub fn new(state: &State) -> Self {
        Self {
            s: state.clone(),
            dq: vec![0.0; state.v.len()],
        }
    }

    /// The state at `t` in the step from `s0` (at `t0`) to `s1` (at `s1.t`) whose increment
    /// was `step_dq`. No allocation.
    pub fn eval(&mut self, s0: &State, s1: &State, step_dq: &[f64], t0: f64, t: f64) -> &State {
        let h = s1.t - t0;
        let th = ((t - t0) / h).clamp(0.0, 1.0);
        let (th2, th3) = (th * th, th * th * th);
        let (h10, h01, h11) = (th3 - 2.0 * th2 + th, -2.0 * th3 + 3.0 * th2, th3 - th2);
        let (d10, d01, d11) = (
            3.0 * th2 - 4.0 * th + 1.0,
            -6.0 * th2 + 6.0 * th,
            3.0 * th2 - 2.0 * th,
        );
        for i in 0..self.dq.len() {
            self.dq[i] = h10 * h * s0.v[i] + h01 * step_dq[i] + h11 * h * s1.v[i];
            self.s.v[i] = d10 * s0.v[i] + d01 * step_dq[i] / h + d11 * s1.v[i];
        }
        self.s.t = t;
        self.s.q.copy_from_slice(&s0.q);
        apply_rotation_step(&mut self.s.q, &self.dq);
        &self.s
    }
}
