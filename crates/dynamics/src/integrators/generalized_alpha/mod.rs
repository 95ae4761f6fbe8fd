//! Index-3 generalized-α (Arnold & Brüls 2007; Chung & Hulbert 1993 parameters) with Newton on
//! [v̇_{n+1}, λ_{n+1}] and the rotation update p ⊗ exp(Δπ'/2) (formulas in the crate docs and
//! in `scheme`) as a `Stepper`.
//!
//! Steps: each output interval is divided into equal steps of at most `h`, so results land on
//! the output times. A step whose Newton iteration fails (no convergence, singular matrix,
//! non-finite values) is retried with half the step, up to `max_halvings` times, and the rest
//! of the interval is divided again after it, so the retried steps do not aim at the end point
//! that failed (a configuration singular to working precision is stepped over).
//!
//! The parts, one job each: [`Parameters`] (α_m, α_f, γ, β from ρ∞; β', γ'), `scheme` (the
//! recursion from v̇_{n+1} to the trial state), `predictor` (the Newton start, linear
//! extrapolation from the last two steps: its error O(h² x⃛) does not grow with the motion as
//! the constant predictor's h ẍ did), `newton` (one step attempt and its convergence tests),
//! `policy` (when the iteration matrix is factored: modified Newton, the refresh at the
//! predictor, the chord rate), `tangents` (the force tangents C_t, K_t by coloured finite
//! differences), `projection` (the velocity projection after a step on the held
//! factorization) and `work` (the trapezoidal work of the drivers and forces).
//!
//! Iteration matrix [M + γ' C_t + β' K_t, Φ_vᵀ; Φ_v, 0]: Φ_v and M exact (but for the
//! Jacobian of the rotation update, about h|ω|/2 relative), the force tangents by finite
//! differences at the iterate where the matrix is factored. With
//! [`GeneralizedAlphaOptions::reuse_factorization`] (the default) the iteration is a modified
//! Newton: the last factorization (of an earlier iteration or step, or of the velocity
//! projection or output solve, all of the same layout) is kept while the residual contracts
//! fast enough. Mass-only steps of a smooth model then cost one factorization every few steps
//! instead of two per step (A02 N = 2 at h = 0.1 ms: 0.14 per step instead of 2). Tangent steps
//! keep their factorization across steps the same way, as long as it is a tangent matrix for
//! the same h, or any held one when the tangent terms are small against M (a chain's
//! gyroscopic terms); before, every tangent step factored at least once (a 200-link chain:
//! 1.05 factorizations per step, each a sparse LU, since the gyroscopic blocks are unsymmetric
//! and the Schur path needs symmetric ones).
//!
//! Stored outputs (accelerations, λ, reactions) are those of the augmented system solved at the
//! stored state (index-1 consistent), not the integrator's internal v̇ and λ, which carry the
//! O(h) start-up error of index-3 schemes. The scheme has no continuous extension of its own:
//! `Stepper::interpolate` inside a step is a cubic Hermite interpolant in the increment
//! space (module `interpolant`), for locating events; outputs land on step ends.
//!
//! After setup a step does not allocate; the tangents are stored as the 6×6 blocks the KKT
//! layout reserves (O(n) memory).

mod interpolant;
mod newton;
mod parameters;
mod policy;
mod predictor;
mod projection;
mod scheme;
mod tangents;
mod work;

pub use parameters::Parameters;

use super::stepper::{Attempt, Sample, Span, Stepper};
use crate::kkt::SchurRefinement;
use crate::options::{GeneralizedAlphaOptions, IterationMatrix};
use crate::results::IntegrationStats;
use crate::state::State;
use crate::system::Dynamics;
use crate::DynamicsError;
use interpolant::Interpolant;
use newton::Newton;
use policy::{Factor, FactorPolicy};
use predictor::{predict, History};
use projection::VelocityProjection;
use scheme::Variables;
use tangents::Tangents;
use work::WorkQuadrature;

/// The generalized-α stepper.
#[derive(Debug)]
pub(crate) struct GeneralizedAlpha {
    o: GeneralizedAlphaOptions,
    p: Parameters,
    /// x_n: the accepted state and the scheme's variables there.
    n: Variables,
    /// x_{n+1} during an attempt; after an accepted step, the state it started from.
    trial: Variables,
    /// The step before, for the predictor.
    history: History,
    newton: Newton,
    policy: FactorPolicy,
    projection: VelocityProjection,
    work: WorkQuadrature,
    interpolant: Interpolant,
    /// Start of the last accepted step (`None` before the first step after the (re)start).
    t0: Option<f64>,
    /// Newton iterations since the last output.
    iterations: usize,
    stats: IntegrationStats,
}

/// The Schur refinement of a generalized-α run: that of one-shot solves (its iterations are
/// not refined, `Kkt::solve_unrefined`).
const REFINE: SchurRefinement = SchurRefinement::ONE_SHOT;

impl GeneralizedAlpha {
    /// One try of a step of size `h` from x_n: the predictor, then Newton (`tangent`: with
    /// the tangent iteration matrix). `true` when it converged.
    fn try_step(&mut self, d: &mut Dynamics, h: f64, tangent: bool) -> Result<bool, DynamicsError> {
        predict(&self.n, &mut self.trial, &self.history, h);
        self.newton.attempt(
            d,
            &mut self.policy,
            &self.n,
            &mut self.trial,
            &self.o,
            &self.p,
            h,
            tangent,
            &mut self.stats,
        )
    }

    /// A step of size `h` from x_n, retried with the full tangent (`MassOnlyThenTangent`),
    /// after choosing the kept rows again, and with half the step, until one converges. The
    /// Newton iterations of the tries at the converged size count for the next output.
    ///
    /// # Errors
    /// [`DynamicsError::StepTooSmall`] after `max_halvings` halvings.
    fn converge(&mut self, d: &mut Dynamics, mut h: f64) -> Result<(), DynamicsError> {
        let o = self.o;
        let mut halvings = 0;
        loop {
            // Bodies that touched for the first time (at the last step or the failed try)
            // couple: the iteration matrix gets their blocks, the tangents their colours.
            if d.lay_out_new_contacts(self.n.s.t)? {
                self.newton.new_layout(d, &self.n.s);
                self.policy = FactorPolicy::new();
            }
            let before = self.stats.newton_iterations;
            let tangent = o.iteration_matrix == IterationMatrix::Tangent;
            if self.try_step(d, h, tangent)?
                || (o.iteration_matrix == IterationMatrix::MassOnlyThenTangent
                    && self.try_step(d, h, true)?)
            {
                self.iterations += self.stats.newton_iterations - before;
                return Ok(());
            }
            // Redundant equations: the kept rows may have lost rank at the step's end where
            // the full set has not; choose them again at the failed iterate and retry.
            if self.trial.s.q.iter().all(|v| v.is_finite()) {
                d.sync(&self.trial.s);
                if d.reselect(self.trial.s.t) {
                    // λ is over the new kept rows: no history for the predictor.
                    self.history.h = 0.0;
                    continue;
                }
            }
            self.stats.rejected += 1;
            halvings += 1;
            if halvings > o.max_halvings {
                return Err(DynamicsError::StepTooSmall {
                    time: self.n.s.t,
                    step: h,
                    reason: "Newton iteration of generalized-α failed".into(),
                });
            }
            h *= 0.5;
        }
    }

    /// The converged trial becomes x_n (its time `target` when within roundoff of it); then
    /// the velocity projection and the work of the step.
    fn accept(&mut self, d: &mut Dynamics, target: f64) -> Result<(), DynamicsError> {
        // The bodies hold the trial already: the attempt converged on the residual it
        // evaluated there.
        let t_before = self.n.s.t;
        std::mem::swap(&mut self.n, &mut self.trial);
        d.accept_turns();
        if (self.n.s.t - target).abs() <= 1e-12 * (1.0 + target.abs()) {
            self.n.s.t = target;
        }
        // The step before, for the predictor (the trial's v̇ and λ are written anew).
        std::mem::swap(&mut self.history.vdot, &mut self.trial.vdot);
        std::mem::swap(&mut self.history.lambda, &mut self.trial.lambda);
        if self.o.project_velocities {
            if self.o.reuse_factorization {
                let at_output = self.n.s.t == target;
                let h_step = self.n.s.t - t_before;
                self.projection.project(
                    d,
                    &mut self.policy,
                    &mut self.n.s,
                    h_step,
                    self.history.h,
                    at_output,
                    REFINE,
                )?;
            } else {
                d.project_velocities_refined(&mut self.n.s, REFINE)?;
            }
        }
        let h_accepted = self.n.s.t - t_before;
        self.history.h = h_accepted;
        if let Some(c) = &d.collisions {
            // The step against the shapes' cap (no shape should move more than its margin).
            let ratio = h_accepted / c.step_cap(&d.bodies);
            if ratio > self.stats.contact_step_ratio.0 {
                self.stats.contact_step_ratio = (ratio, self.n.s.t);
            }
        }
        self.work
            .step(d, &mut self.policy, &self.n.s, h_accepted, REFINE)?;
        self.stats.steps += 1;
        self.t0 = Some(t_before);
        Ok(())
    }
}

impl Stepper for GeneralizedAlpha {
    type Options = GeneralizedAlphaOptions;

    fn new(
        d: &mut Dynamics,
        state: State,
        o: &GeneralizedAlphaOptions,
        _t_end: f64,
    ) -> Result<Self, DynamicsError> {
        // The options' one validation (the same messages as the driver loop's).
        o.validate()
            .map_err(|e| DynamicsError::Options(e.to_string()))?;
        let n = state.v.len();
        let na = d.kkt.as_ref().expect("prepared").active.len();
        let m = d.model.num_equations();
        let tangents =
            (o.iteration_matrix != IterationMatrix::MassOnly).then(|| Tangents::new(d, &state));
        let mut stepper = Self {
            o: *o,
            p: Parameters::from_rho_inf(o.rho_inf),
            n: Variables::new(&state, na),
            trial: Variables::new(&state, na),
            history: History::new(n, na),
            newton: Newton::new(n, m, tangents),
            policy: FactorPolicy::new(),
            projection: VelocityProjection::new(n, na),
            work: WorkQuadrature::new(d.num_work_channels(), n, m),
            interpolant: Interpolant::new(&state),
            t0: None,
            iterations: 0,
            stats: IntegrationStats::default(),
        };
        stepper.restart(d, &state)?;
        Ok(stepper)
    }

    fn refinement(&self) -> SchurRefinement {
        REFINE
    }

    fn locates_contact_onsets(&self) -> bool {
        false
    }

    fn time(&self) -> f64 {
        self.n.s.t
    }

    fn stats(&self) -> &IntegrationStats {
        &self.stats
    }

    /// Steps of at most h that land on the output time `target`: the rest of the interval is
    /// divided into equal steps after every accepted step, so a halved step shifts the steps
    /// after it instead of aiming again at the end point that failed (a configuration singular
    /// to working precision, such as A02's horizontal positions, is then stepped over).
    fn attempt(&mut self, d: &mut Dynamics, target: f64) -> Result<Attempt, DynamicsError> {
        // (A step up to 1e-6 longer than h rather than an extra one: the roundoff of the
        // accumulated time, about 1e-8 h after 1000 steps, must not add a step.)
        let rest = target - self.n.s.t;
        let nsub = ((rest / self.o.dt) - 1e-6).ceil().max(1.0);
        let h = if nsub <= 1.0 { rest } else { rest / nsub };
        self.converge(d, h)?;
        self.accept(d, target)?;
        let t1 = self.n.s.t;
        Ok(Attempt::Accepted(Span {
            t0: self.t0.unwrap_or(t1),
            t1,
            reach: t1,
        }))
    }

    fn interpolate(&mut self, t: f64) -> &State {
        match self.t0 {
            Some(_) if t >= self.n.s.t => &self.n.s,
            Some(t0) if t <= t0 => &self.trial.s,
            Some(t0) => {
                let (s0, s1) = (&self.trial.s, &self.n.s);
                self.interpolant.eval(s0, s1, &self.newton.dq, t0, t)
            }
            _ => &self.n.s,
        }
    }

    /// The accepted state (outputs land on step ends), with the Newton iterations since the
    /// last output. The recorder's acceleration solve then refactors [M Φ_vᵀ; Φ_v 0] there.
    fn output(&mut self, _d: &mut Dynamics, _t: f64) -> Result<Sample<'_>, DynamicsError> {
        self.policy.hold_mass_matrix(Factor::Stale);
        Ok(Sample {
            state: &self.n.s,
            work: &self.work.w,
            iterations: std::mem::take(&mut self.iterations),
        })
    }

    /// x_n at `state` with consistent accelerations (and λ) there, no step history, the
    /// held factorization that of the acceleration solve.
    fn restart(&mut self, d: &mut Dynamics, state: &State) -> Result<(), DynamicsError> {
        let n = &mut self.n;
        n.s.t = state.t;
        n.s.q.copy_from_slice(&state.q);
        n.s.v.copy_from_slice(&state.v);
        self.history.h = 0.0;
        self.projection.reset();
        self.policy = FactorPolicy::new();
        self.t0 = None;
        // Consistent accelerations at the state: v̇ = a, λ on the kept rows.
        let lambda = &mut self.work.lambda;
        d.accelerations_refined(&n.s, &mut n.vdot, lambda, REFINE)?;
        let kkt = d.kkt.as_ref().expect("prepared");
        for (a, &r) in kkt.active.iter().enumerate() {
            n.lambda[a] = lambda[r];
        }
        n.a.copy_from_slice(&n.vdot);
        self.work.start(d, n.s.t);
        // The acceleration solve left [M Φ_vᵀ; Φ_v 0] at the state factored.
        self.policy.hold_mass_matrix(Factor::Stale);
        Ok(())
    }
}
