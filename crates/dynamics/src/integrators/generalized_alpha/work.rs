//! The work of the drivers and non-conservative forces over generalized-α steps: the
//! trapezoidal rule on each step, second order like the scheme ([`crate::work`]).

use super::policy::{Factor, FactorPolicy};
use crate::kkt::SchurRefinement;
use crate::state::State;
use crate::system::Dynamics;
use crate::work::{trapezoid, Multipliers};
use crate::DynamicsError;

/// The power of each channel at the step's two ends, the work, and v̇ and λ (all rows) of the
/// acceleration solve at a step's end that gives the drivers' power.
#[derive(Debug, Clone)]
pub(super) struct WorkQuadrature {
    p0: Vec<f64>,
    p1: Vec<f64>,
    /// The work W of each channel at the accepted state.
    pub w: Vec<f64>,
    vdot: Vec<f64>,
    /// λ of the last acceleration solve at an accepted state (all rows; also the start's).
    pub lambda: Vec<f64>,
}

impl WorkQuadrature {
    /// No work yet: `channels` channels, `n` unknowns, `m` equations.
    pub fn new(channels: usize, n: usize, m: usize) -> Self {
        Self {
            p0: vec![0.0; channels],
            p1: vec![0.0; channels],
            w: vec![0.0; channels],
            vdot: vec![0.0; n],
            lambda: vec![0.0; m],
        }
    }

    /// The power at the start state (time `t`, the bodies synced there) with the multipliers
    /// in `self.lambda`.
    pub fn start(&mut self, d: &mut Dynamics, t: f64) {
        d.powers(t, Multipliers::Full(&self.lambda), &mut self.p0);
    }

    /// The work after an accepted step of size `h` ending at `s`. The drivers' power takes λ
    /// from the augmented system solved at the step's end (index 1, as the stored outputs), not
    /// the step's own λ_{n+1}: the index-3 λ_{n+1} is off by O(h) (with it, the balance of a
    /// driven crank fell like h, not h²; so did it with the λ that follows the recursion of a).
    /// That solve costs one factorization per step, for models with drivers only; it leaves
    /// [M Φ_vᵀ; Φ_v 0] at the new state factored, which the next step may reuse. No allocation.
    ///
    /// # Errors
    /// The acceleration solve's failure.
    pub fn step(
        &mut self,
        d: &mut Dynamics,
        policy: &mut FactorPolicy,
        s: &State,
        h: f64,
        refine: SchurRefinement,
    ) -> Result<(), DynamicsError> {
        if self.w.is_empty() {
            return Ok(());
        }
        if d.model.drivers().is_empty() {
            d.sync(s);
            d.powers(s.t, Multipliers::Solution, &mut self.p1);
        } else {
            d.accelerations_refined(s, &mut self.vdot, &mut self.lambda, refine)?;
            policy.hold_mass_matrix(Factor::Stale);
            d.powers(s.t, Multipliers::Full(&self.lambda), &mut self.p1);
        }
        trapezoid(&mut self.w, &self.p0, &self.p1, h);
        std::mem::swap(&mut self.p0, &mut self.p1);
        Ok(())
    }
}
