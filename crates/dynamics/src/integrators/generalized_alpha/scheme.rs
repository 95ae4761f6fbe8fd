//! The generalized-α recursion of one step (Arnold & Brüls 2007, eq. (8); the rotation update
//! of Brüls, Cardona & Arnold 2012): from the step's unknown v̇_{n+1},
//!
//! ```text
//! (1 − α_m) a_{n+1} = (1 − α_f) v̇_{n+1} + α_f v̇_n − α_m a_n
//! v_{n+1} = v_n + h (1 − γ) a_n + h γ a_{n+1}
//! Δ = h v_n + h² (½ − β) a_n + h² β a_{n+1},    r_{n+1} = r_n + Δr,   p_{n+1} = p_n ⊗ exp(Δπ'/2)
//! ```

use super::parameters::Parameters;
use crate::state::State;
use cardan_mechanism::apply_rotation_step;
use nalgebra::{Matrix3, Vector3};

/// The scheme's variables at one time: the state, v̇, the algorithmic acceleration a and λ
/// (on the kept rows).
#[derive(Debug, Clone)]
pub(super) struct Variables {
    pub s: State,
    pub vdot: Vec<f64>,
    pub a: Vec<f64>,
    pub lambda: Vec<f64>,
}

impl Variables {
    /// At `state`, the rest zero (`na` kept rows).
    pub fn new(state: &State, na: usize) -> Self {
        let n = state.v.len();
        Self {
            s: state.clone(),
            vdot: vec![0.0; n],
            a: vec![0.0; n],
            lambda: vec![0.0; na],
        }
    }
}

/// Sets the trial x_{n+1} from its v̇ (`trial.vdot`) and x_n: a_{n+1}, v_{n+1}, the increment
/// Δ (into `dq`) and q_{n+1}. No allocation.
pub(super) fn update_trial(
    n: &Variables,
    trial: &mut Variables,
    dq: &mut [f64],
    h: f64,
    p: &Parameters,
) {
    let (am, af, g, be) = (p.alpha_m, p.alpha_f, p.gamma, p.beta);
    for i in 0..n.a.len() {
        trial.a[i] = ((1.0 - af) * trial.vdot[i] + af * n.vdot[i] - am * n.a[i]) / (1.0 - am);
        trial.s.v[i] = n.s.v[i] + h * (1.0 - g) * n.a[i] + h * g * trial.a[i];
        dq[i] = h * n.s.v[i] + h * h * (0.5 - be) * n.a[i] + h * h * be * trial.a[i];
    }
    trial.s.q.copy_from_slice(&n.s.q);
    apply_rotation_step(&mut trial.s.q, dq);
}

/// out = M x with M = diag(m_k I, J'_k) per body (6 entries per body).
pub(super) fn mass_mul(mass: &[f64], inertia: &[Matrix3<f64>], x: &[f64], out: &mut [f64]) {
    for (k, (o, x)) in out.chunks_mut(6).zip(x.chunks(6)).enumerate() {
        for c in 0..3 {
            o[c] = mass[k] * x[c];
        }
        let jw = inertia[k] * Vector3::new(x[3], x[4], x[5]);
        o[3..].copy_from_slice(jw.as_slice());
    }
}
