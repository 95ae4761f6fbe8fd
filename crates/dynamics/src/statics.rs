//! Static and quasi-static analysis: [`Dynamics::static_equilibrium`], [`Dynamics::statics`],
//! [`Dynamics::quasi_statics`].
//!
//! ## Theory
//! A static equilibrium at time t (drivers held at their value at t) is a pose q and
//! multipliers λ with
//!
//! ```text
//! Φ(q, t) = 0,      Φ_vᵀ(q) λ = h(q)      (v = v̇ = 0 in M v̇ + Φ_vᵀλ = h)
//! ```
//!
//! i.e. Q(q) − Φ_vᵀλ = 0 with Q = h the applied generalized forces and −Φ_vᵀλ the constraint
//! reactions (the crate's sign convention); on the redundant rows dropped by the rank analysis
//! λ = 0 (as in the other analyses). It is solved by Newton's method on (q, λ) together
//! (Haug 1989 §13.3; Nikravesh 1988 §13.5 solves the same system):
//!
//! ```text
//! ⎡K_t + μ M   Φ_vᵀ⎤ ⎡δ ⎤     ⎡Φ_vᵀλ − h_s⎤
//! ⎣  Φ_v        0  ⎦ ⎣Δλ⎦ = − ⎣    Φ       ⎦,     q ← q ⊕ α δ,   λ ← λ + α Δλ
//! ```
//!
//! with K_t the tangent stiffness (force elements and the geometric stiffness of the constraint
//! forces, `tangent` module), α from a backtracking line search on the merit
//! ψ = ‖r₁ w / f‖² + ‖Φ / e‖² (w = 1 on forces and 1/L on torques, f the size of the force
//! terms, e the equation scales), and μ ≥ 0 a shift in the metric of the mass matrix M that is
//! 0 for plain Newton and grows (× 10) when the Newton matrix is singular or the line search
//! fails: the pseudo-transient continuation of Kelley & Keyes (1998), which follows the
//! damped motion towards a stable equilibrium where the reduced stiffness is singular or
//! indefinite (a pendulum drawn horizontal: its reduced stiffness m g l cos θ is 0 there).
//! μ shrinks (÷ 4) after each accepted step and returns to 0 near the solution, so the end
//! converges quadratically. Euler parameters stay unit: the increments are rotation vectors
//! (p ← p ⊗ exp(δπ'/2)), there is no normalization row.
//!
//! **Load stepping.** The loads (gravity, point forces and torques, the user callback) are
//! scaled by a load factor s, the springs are not: h_s = s h_loads + h_springs. The solve
//! first tries s = 1 (or the first of `load_steps` equal increments); a load step that fails is
//! halved, up to `max_halvings` times, each solved from the previous equilibrium. When that
//! fails, [`DynamicsError::NoEquilibrium`] reports the last load factor reached.
//!
//! **Stability.** With N a basis of the null space of Φ_v (independent coordinates
//! δ = N z), the reduced stiffness K_r = NᵀK_tN and mass M_r = NᵀMN: the equilibrium is stable
//! when every eigenvalue ω² of K_r x = ω² M_r x is positive (then √ω² are the natural
//! frequencies of the modal analysis), unstable with a negative one, neutral with a zero one (a
//! free degree of freedom without stiffness: a wheel on its axle). By Sylvester's law of
//! inertia the signs are those of the eigenvalues of K_r in any basis. A direction is named by
//! the joint coordinate that moves most along it.
//!
//! **Failures.** A singular configuration (Φ_v loses rank beyond the redundancy dropped at the
//! start): [`DynamicsError::Singular`] naming the dependent equations. A free degree of freedom
//! without stiffness along which the loads push (a slider under gravity along its slide):
//! [`DynamicsError::FreeDirection`] naming it. Otherwise [`DynamicsError::NoEquilibrium`].
//!
//! ## Quasi-static analysis
//! Drivers as functions of time, inertia neglected: the equilibrium at each output time,
//! continued from the one before (an interval that fails is halved, up to `max_halvings`
//! times). The driver efforts are then the holding forces and torques along the motion.

use crate::record::Recorder;
use crate::results::{DynamicResults, IntegrationStats};
use crate::state::State;
use crate::system::Dynamics;
use crate::tangent::null_space;
use crate::DynamicsError;
use cardan_constraints::joints::CoordinateQuantity;
use cardan_constraints::BodyPair;
use cardan_constraints::BodyState;
use cardan_mechanism::{apply_rotation_step, AnalysisError, AssemblyOptions, BodyId, Outputs};
use nalgebra::{DMatrix, DVector};

/// Options of a static or quasi-static analysis.
#[derive(Debug, Clone, PartialEq)]
pub struct StaticOptions {
    /// Time at which the drivers are held (static analysis; default 0).
    pub time: f64,
    /// Tolerance on the scaled residual: max |r₁ w| / f and max |Φ / e| (module docs), in
    /// [1e-14, 1e-4]; default 1e-10.
    pub tolerance: f64,
    /// Newton iterations per load step (default 100).
    pub max_iterations: usize,
    /// Equal load increments tried first (default 1: the full load at once).
    pub load_steps: usize,
    /// How many times a failing load step (or quasi-static time interval) may be halved
    /// (default 10).
    pub max_halvings: usize,
    /// What the results store (velocities and accelerations are zero in statics; default:
    /// points and joint coordinates).
    pub outputs: Outputs,
}

impl Default for StaticOptions {
    fn default() -> Self {
        Self {
            time: 0.0,
            tolerance: 1e-10,
            max_iterations: 100,
            load_steps: 1,
            max_halvings: 10,
            outputs: Outputs {
                velocity: false,
                acceleration: false,
                points: true,
                joints: true,
            },
        }
    }
}

impl StaticOptions {
    /// Default options with the drivers held at `time`.
    pub fn at(time: f64) -> Self {
        Self {
            time,
            ..Self::default()
        }
    }

    /// Refuses options that cannot give a meaningful solve.
    ///
    /// # Errors
    /// [`DynamicsError::Options`] naming the option.
    pub fn validate(&self) -> Result<(), DynamicsError> {
        let bad = |s: String| Err(DynamicsError::Options(s));
        if !self.time.is_finite() {
            return bad(format!("time must be finite, got {}", self.time));
        }
        if !(1e-14..=1e-4).contains(&self.tolerance) {
            return bad(format!(
                "tolerance must be in [1e-14, 1e-4], got {}",
                self.tolerance
            ));
        }
        if self.max_iterations == 0 || self.load_steps == 0 {
            return bad("max_iterations and load_steps must be at least 1".into());
        }
        if self.max_halvings > 30 {
            return bad(format!(
                "max_halvings must be at most 30, got {}",
                self.max_halvings
            ));
        }
        Ok(())
    }
}

/// Whether an equilibrium is stable (module docs).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Stability {
    /// Every eigenvalue of the reduced stiffness is positive (or the mechanism has no degree of
    /// freedom).
    Stable,
    /// A zero eigenvalue, none negative: a free degree of freedom without stiffness.
    Neutral,
    /// A negative eigenvalue: the equilibrium is unstable.
    Unstable,
}

impl Stability {
    /// `stable`, `neutral` or `unstable`.
    pub fn name(self) -> &'static str {
        match self {
            Stability::Stable => "stable",
            Stability::Neutral => "neutral",
            Stability::Unstable => "unstable",
        }
    }
}

/// One static equilibrium.
#[derive(Debug, Clone, PartialEq)]
pub struct Equilibrium {
    /// The pose (velocities zero) at the time the drivers are held.
    pub state: State,
    /// λ, one per model equation (0 on rows dropped as redundant).
    pub lambda: Vec<f64>,
    /// Newton iterations over all load steps.
    pub iterations: usize,
    /// Load steps taken (1 when the full load converged at once).
    pub load_steps: usize,
    /// Final scaled residual (module docs).
    pub residual: f64,
    /// Eigenvalues ω² (1/s²) of K_r x = ω² M_r x, ascending: the reduced stiffness per unit
    /// modal mass; one per degree of freedom (on the sparse path of large models, only the
    /// [`STABILITY_MODES`] lowest).
    pub eigenvalues: Vec<f64>,
    /// Stable, neutral or unstable.
    pub stability: Stability,
    /// The directions with a zero or negative eigenvalue, each named by the joint coordinate
    /// that moves most along it (`joint "pin" angle`).
    pub soft_directions: Vec<String>,
}

/// The results of a static or quasi-static analysis.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct StaticResults {
    /// Poses, points, joint coordinates, λ, reactions and driver efforts (the holding forces
    /// and torques) at each time, as in the other analyses; velocities and accelerations are
    /// zero and not stored, kinetic energy is zero.
    pub results: DynamicResults,
    /// The equilibrium (with its stability) at each time.
    pub equilibria: Vec<Equilibrium>,
}

/// Why one Newton solve stopped.
enum Fail {
    /// No convergence: the last scaled residual.
    Stalled(f64),
    /// A singular configuration (or a free direction): the error to report.
    Error(DynamicsError),
}

/// The shift μ grows up to this multiple of its start before a solve gives up.
const MU_MAX_FACTOR: f64 = 1e12;

/// Halvings of the line search before the shift μ grows instead: a Newton direction that
/// needs a step shorter than 1/8 is poor (near a minimum of the merit that is not a solution,
/// where plain Newton would creep), and the shifted step is the better move.
const LINE_SEARCH_HALVINGS: usize = 4;

/// On the sparse path ([`crate::sparse_tangent::SPARSE_MIN_BODIES`]) the stability test and
/// the named soft directions use this many lowest eigenvalues (shift-invert Lanczos), not all.
pub const STABILITY_MODES: usize = 6;

/// Largest scaled increment (|δr| / L, |δπ'| in rad) of one Newton step.
const MAX_STEP: f64 = 0.5;

/// The merit ψ of an iterate of static Newton (module docs) and its parts.
struct Merit {
    /// ψ = |r₁ w / f|² + Σ over the kept rows (Φ / e)².
    psi: f64,
    /// max(max |r₁ w| / f, max |Φ / e| over all rows): the convergence measure.
    worst: f64,
    /// r₁ = Φ_vᵀλ − h_s.
    r1: DVector<f64>,
    /// Φ (all rows).
    phi: Vec<f64>,
}

/// The stability of an equilibrium: the reduced stiffness's eigenvalues, what they mean, and
/// the named soft directions.
struct StabilityCheck {
    eigenvalues: Vec<f64>,
    stability: Stability,
    soft_directions: Vec<String>,
}

/// An iterate of static Newton: the pose and the multipliers (all rows).
struct StaticIterate {
    state: State,
    lambda: Vec<f64>,
}

/// How the merit weighs the residuals at load factor `s` and time `t`: r₁ by the weights `w`
/// (1 on forces, 1/L on torques) over the force scale `f`, Φ by the equation scales.
struct StaticMerit<'w> {
    s: f64,
    t: f64,
    w: &'w [f64],
    f: f64,
}

impl StaticMerit<'_> {
    /// The merit at the pose `st` with multipliers `lam` (`active`: the kept rows).
    fn eval(&self, d: &mut Dynamics, st: &State, lam: &[f64], active: &[usize]) -> Merit {
        let (r1, _) = d.static_residual(st, lam, self.s);
        let phi = d.phi_all(self.t);
        let scales = d.model.equation_scales();
        let rf: Vec<f64> = r1.iter().zip(self.w).map(|(r, w)| r * w / self.f).collect();
        let psi = rf.iter().map(|x| x * x).sum::<f64>()
            + active
                .iter()
                .map(|&r| (phi[r] / scales[r]).powi(2))
                .sum::<f64>();
        let worst_f = rf.iter().fold(0.0f64, |a, x| a.max(x.abs()));
        let worst_p = phi
            .iter()
            .zip(scales)
            .fold(0.0f64, |a, (p, e)| a.max((p / e).abs()));
        Merit {
            psi,
            worst: worst_f.max(worst_p),
            r1,
            phi,
        }
    }

    /// Backtracking along the Newton step `x` = [δ; Δλ] from (`state`, `lambda`): the first of
    /// α = 1, ½, ¼, … ([`LINE_SEARCH_HALVINGS`] tries) whose merit decreases by the Armijo
    /// fraction 1e-4 α of `psi`.
    fn line_search(
        &self,
        d: &mut Dynamics,
        state: &State,
        lambda: &[f64],
        x: &DVector<f64>,
        active: &[usize],
        psi: f64,
    ) -> Option<StaticIterate> {
        let n = state.v.len();
        let mut alpha = 1.0;
        for _ in 0..LINE_SEARCH_HALVINGS {
            let mut trial = state.clone();
            let dq: Vec<f64> = (0..n).map(|c| alpha * x[c]).collect();
            apply_rotation_step(&mut trial.q, &dq);
            let mut lt = lambda.to_vec();
            for (a, &r) in active.iter().enumerate() {
                lt[r] += alpha * x[n + a];
            }
            let pt = self.eval(d, &trial, &lt, active).psi;
            if pt.is_finite() && pt < (1.0 - 1e-4 * alpha) * psi {
                return Some(StaticIterate {
                    state: trial,
                    lambda: lt,
                });
            }
            alpha *= 0.5;
        }
        None
    }
}

impl Dynamics<'_> {
    /// The static equilibrium at `options.time` from the poses of `guess` (assembled first,
    /// drivers included). See the module docs for the method, the stability test and the
    /// failures.
    ///
    /// # Errors
    /// [`DynamicsError::InconsistentPositions`] when the guess cannot be assembled;
    /// [`DynamicsError::NoEquilibrium`], [`DynamicsError::FreeDirection`],
    /// [`DynamicsError::Singular`]; [`DynamicsError::Options`].
    pub fn static_equilibrium(
        &mut self,
        guess: &State,
        options: &StaticOptions,
    ) -> Result<Equilibrium, DynamicsError> {
        options.validate()?;
        let t = options.time;
        let mut state = self.assembled(guess, t)?;
        let mut lambda = vec![0.0; self.model.num_equations()];
        let mut s = 0.0;
        let mut ds = 1.0 / options.load_steps as f64;
        let mut halvings = 0;
        let mut iterations = 0;
        let mut steps = 0;
        while s < 1.0 {
            let target = (s + ds).min(1.0);
            let (saved_q, saved_l) = (state.q.clone(), lambda.clone());
            match self.newton_static(&mut state, &mut lambda, target, options) {
                Ok(it) => {
                    iterations += it;
                    steps += 1;
                    s = target;
                    if halvings > 0 {
                        ds *= 2.0;
                        halvings -= 1;
                    }
                }
                Err(Fail::Error(e)) => return Err(e),
                Err(Fail::Stalled(r)) => {
                    if let Some(e) = self.free_direction(&state, &lambda, target, t) {
                        return Err(e);
                    }
                    state.q = saved_q;
                    lambda = saved_l;
                    halvings += 1;
                    if halvings > options.max_halvings {
                        return Err(DynamicsError::NoEquilibrium {
                            time: t,
                            load_factor: s,
                            residual: r,
                        });
                    }
                    ds *= 0.5;
                }
            }
        }
        self.equilibrium(state, lambda, iterations, steps)
    }

    /// Static analysis from the model's drawn poses: [`static_equilibrium`] at
    /// `options.time`, recorded like the other analyses (one output time).
    ///
    /// [`static_equilibrium`]: Self::static_equilibrium
    ///
    /// # Errors
    /// As [`static_equilibrium`](Self::static_equilibrium).
    pub fn statics(&mut self, options: &StaticOptions) -> Result<StaticResults, DynamicsError> {
        let start = std::time::Instant::now();
        let mut guess = self.initial_guess();
        guess.t = options.time;
        let eq = self.static_equilibrium(&guess, options)?;
        Ok(self.record_equilibria(vec![eq], options.outputs, start))
    }

    /// Quasi-static analysis at the `times` (increasing): the equilibrium at each, continued
    /// from the previous one (the first from the drawn poses). `options.time` is ignored.
    ///
    /// # Errors
    /// As [`static_equilibrium`](Self::static_equilibrium); a failure after the first time is
    /// [`DynamicsError::MidRun`] with the equilibria found before it.
    pub fn quasi_statics(
        &mut self,
        times: &[f64],
        options: &StaticOptions,
    ) -> Result<StaticResults, DynamicsError> {
        let start = std::time::Instant::now();
        if times.is_empty() || times.windows(2).any(|w| w[1] <= w[0]) {
            return Err(DynamicsError::Options(
                "quasi-static times must be increasing and at least one".into(),
            ));
        }
        let mut eqs: Vec<Equilibrium> = Vec::with_capacity(times.len());
        let mut guess = self.initial_guess();
        for &t in times {
            let r = match eqs.last() {
                None => {
                    guess.t = t;
                    self.static_equilibrium(
                        &guess,
                        &StaticOptions {
                            time: t,
                            ..options.clone()
                        },
                    )
                }
                Some(prev) => self.continue_in_time(prev, t, options),
            };
            match r {
                Ok(eq) => {
                    guess = eq.state.clone();
                    eqs.push(eq);
                }
                Err(e) if eqs.is_empty() => return Err(e),
                Err(e) => {
                    let last_time = eqs.last().map_or(f64::NAN, |q| q.state.t);
                    let partial = self.record_equilibria(eqs, options.outputs, start);
                    return Err(DynamicsError::MidRun {
                        source: Box::new(e),
                        last_time,
                        partial: Box::new(partial.results),
                    });
                }
            }
        }
        Ok(self.record_equilibria(eqs, options.outputs, start))
    }

    /// The equilibrium at `t` from the one at `prev.state.t`, halving the interval when Newton
    /// fails from the previous equilibrium.
    fn continue_in_time(
        &mut self,
        prev: &Equilibrium,
        t: f64,
        options: &StaticOptions,
    ) -> Result<Equilibrium, DynamicsError> {
        let mut state = prev.state.clone();
        let mut lambda = prev.lambda.clone();
        let mut tc = prev.state.t;
        let mut dt = t - tc;
        let mut halvings = 0;
        let mut iterations = 0;
        while tc < t {
            let target = if tc + dt >= t - 1e-12 * dt.abs() {
                t
            } else {
                tc + dt
            };
            let (saved_q, saved_l) = (state.q.clone(), lambda.clone());
            state.t = target;
            let o = StaticOptions {
                time: target,
                ..options.clone()
            };
            match self.newton_static(&mut state, &mut lambda, 1.0, &o) {
                Ok(it) => {
                    iterations += it;
                    tc = target;
                }
                Err(Fail::Error(e)) => return Err(e),
                Err(Fail::Stalled(r)) => {
                    if let Some(e) = self.free_direction(&state, &lambda, 1.0, target) {
                        return Err(e);
                    }
                    state.q = saved_q;
                    state.t = tc;
                    lambda = saved_l;
                    halvings += 1;
                    if halvings > options.max_halvings {
                        return Err(DynamicsError::NoEquilibrium {
                            time: target,
                            load_factor: 1.0,
                            residual: r,
                        });
                    }
                    dt *= 0.5;
                }
            }
        }
        self.equilibrium(state, lambda, iterations, 1)
    }

    /// The [`Equilibrium`] found at `state` with multipliers `lambda`: its residual and stability.
    fn equilibrium(
        &mut self,
        state: State,
        lambda: Vec<f64>,
        iterations: usize,
        load_steps: usize,
    ) -> Result<Equilibrium, DynamicsError> {
        let residual = self.scaled_residual(&state, &lambda, 1.0);
        let check = self.stability(&state, &lambda)?;
        Ok(Equilibrium {
            state,
            lambda,
            iterations,
            load_steps,
            residual,
            eigenvalues: check.eigenvalues,
            stability: check.stability,
            soft_directions: check.soft_directions,
        })
    }

    /// Records the equilibria (poses, reactions, efforts) as [`StaticResults`].
    fn record_equilibria(
        &mut self,
        eqs: Vec<Equilibrium>,
        outputs: Outputs,
        start: std::time::Instant,
    ) -> StaticResults {
        let outputs = Outputs {
            velocity: false,
            acceleration: false,
            ..outputs
        };
        let mut rec = Recorder::new(self, eqs.len(), outputs);
        for e in &eqs {
            self.sync(&e.state);
            self.accept_turns();
            rec.record_static(self, &e.state, &e.lambda, e.iterations);
        }
        let stats = IntegrationStats {
            steps: eqs.len(),
            newton_iterations: eqs.iter().map(|e| e.iterations).sum(),
            wall_time: start.elapsed().as_secs_f64(),
            ..IntegrationStats::default()
        };
        StaticResults {
            results: rec.finish(self, stats),
            equilibria: eqs,
        }
    }

    /// The poses of `guess` assembled at `t` (drivers included), velocities zero; lays out the
    /// rows (rank analysis: redundant rows dropped).
    fn assembled(&mut self, guess: &State, t: f64) -> Result<State, DynamicsError> {
        let mut ws = self.model.workspace();
        for k in 0..self.model.num_bodies() {
            ws.set_pose(k, guess.r(k), guess.p(k));
        }
        match self.model.assemble(&mut ws, &AssemblyOptions::at(t)) {
            Ok(_) => {}
            Err(AnalysisError::AssemblyFailed { open, .. }) => {
                return Err(DynamicsError::InconsistentPositions { open })
            }
            Err(e) => return Err(e.into()),
        }
        let state = self.adopt_assembly(&ws, t, vec![0.0; guess.v.len()]);
        self.kkt = None;
        self.prepare(&state)?;
        Ok(state)
    }

    /// The active (independent) rows of the current layout.
    fn active_rows(&self) -> Vec<usize> {
        self.kkt
            .as_ref()
            .map(|k| k.active.clone())
            .unwrap_or_default()
    }

    /// The multipliers of the mechanism at rest at `state` under the load factor `s` (full
    /// rows): the least-squares balance λ = (Φ_v M⁻¹Φ_vᵀ)⁻¹Φ_v M⁻¹h_s, the start of Newton.
    fn rest_multipliers(&mut self, state: &State, s: f64) -> Vec<f64> {
        let active = self.active_rows();
        if self.sparse_path() {
            return self.rest_multipliers_sparse(state, s, &active);
        }
        self.sync(state);
        self.eval_static_forces(state.t, s);
        let h = DVector::from_column_slice(&self.h);
        let m = self.mass_matrix();
        let j = self.phi_v_dense(state.t, &active);
        let (n, ma) = (h.len(), active.len());
        let mut a = DMatrix::zeros(n + ma, n + ma);
        a.view_mut((0, 0), (n, n)).copy_from(&m);
        a.view_mut((n, 0), (ma, n)).copy_from(&j);
        a.view_mut((0, n), (n, ma)).copy_from(&j.transpose());
        let mut rhs = DVector::zeros(n + ma);
        rhs.rows_mut(0, n).copy_from(&h);
        let mut lambda = vec![0.0; self.model.num_equations()];
        if let Some(x) = a.lu().solve(&rhs) {
            if x.iter().all(|v| v.is_finite()) {
                for (k, &r) in active.iter().enumerate() {
                    lambda[r] = x[n + k];
                }
            }
        }
        lambda
    }

    /// Weights of r₁: 1 on forces, 1/L on torques.
    fn residual_weights(&self) -> Vec<f64> {
        let l = self.model.characteristic_length();
        (0..self.model.num_unknowns())
            .map(|c| if c % 6 < 3 { 1.0 } else { 1.0 / l })
            .collect()
    }

    /// max(max |r₁ w| / f, max |Φ / e| over all rows) at `state`.
    fn scaled_residual(&mut self, state: &State, lambda: &[f64], s: f64) -> f64 {
        let (r1, size) = self.static_residual(state, lambda, s);
        let w = self.residual_weights();
        let f = force_scale(&size, &w);
        let phi = self.phi_all(state.t);
        let scales = self.model.equation_scales();
        let rf = r1
            .iter()
            .zip(&w)
            .fold(0.0f64, |a, (r, w)| a.max((r * w).abs()))
            / f;
        let rp = phi
            .iter()
            .zip(scales)
            .fold(0.0f64, |a, (p, e)| a.max((p / e).abs()));
        rf.max(rp)
    }

    /// Newton on (q, λ) at load factor `s` (module docs); returns the iterations.
    fn newton_static(
        &mut self,
        state: &mut State,
        lambda: &mut [f64],
        s: f64,
        options: &StaticOptions,
    ) -> Result<usize, Fail> {
        let t = state.t;
        let n = state.v.len();
        let model = self.model;
        let w = self.residual_weights();
        let sparse = self.sparse_path();
        let graph = sparse.then(|| self.body_graph());
        let m = if sparse {
            DMatrix::zeros(0, 0)
        } else {
            self.mass_matrix()
        };
        let uscale = model.unknown_scales().to_vec();
        let rest = self.rest_multipliers(state, s);
        lambda.copy_from_slice(&rest);
        let (_, size0) = self.static_residual(state, lambda, s);
        let f = force_scale(&size0, &w);
        let mut mu = 0.0;
        let mut mu0 = 0.0;
        let mut active = self.active_rows();
        let mut it = 0;
        let merit = StaticMerit { s, t, w: &w, f };
        loop {
            let Merit {
                psi,
                worst,
                r1,
                phi,
            } = merit.eval(self, state, lambda, &active);
            if !psi.is_finite() {
                return Err(Fail::Error(DynamicsError::NonFinite {
                    time: t,
                    what: "the static residual",
                }));
            }
            if worst <= options.tolerance {
                self.sync(state);
                self.accept_turns();
                return Ok(it);
            }
            if it == options.max_iterations {
                return Err(Fail::Stalled(worst));
            }
            it += 1;
            // The sparse path (large models): sparse tangent and saddle-point LU.
            let mut newton = match &graph {
                Some(g) => Some(
                    self.sparse_newton(g, state, lambda, s, &active, f)
                        .map_err(Fail::Error)?,
                ),
                None => None,
            };
            let (k, j) = if newton.is_some() {
                (DMatrix::zeros(0, 0), DMatrix::zeros(0, 0))
            } else {
                let k = self.static_tangent(state, lambda, s);
                self.sync(state);
                (k, self.phi_v_dense(t, &active))
            };
            if mu0 == 0.0 {
                mu0 = match &newton {
                    Some(nw) => nw.shift_scale,
                    None => shift_scale(&k, &m, f, model.characteristic_length()),
                };
            }
            let ma = active.len();
            let mut rhs = DVector::zeros(n + ma);
            rhs.rows_mut(0, n).copy_from(&(-&r1));
            for (a, &r) in active.iter().enumerate() {
                rhs[n + a] = -phi[r];
            }
            // Shift loop: plain Newton first, then μ M growing until a step decreases ψ.
            let accepted = loop {
                let sol = match &mut newton {
                    Some(nw) => nw.solve_shifted(mu, &rhs),
                    None => {
                        let mut a = DMatrix::zeros(n + ma, n + ma);
                        a.view_mut((0, 0), (n, n)).copy_from(&(&k + &m * mu));
                        a.view_mut((n, 0), (ma, n)).copy_from(&j);
                        a.view_mut((0, n), (n, ma)).copy_from(&j.transpose());
                        a.lu().solve(&rhs)
                    }
                }
                .filter(|x| x.iter().all(|v| v.is_finite()));
                if let Some(mut x) = sol {
                    let big = (0..n).fold(0.0f64, |b, c| b.max((x[c] / uscale[c]).abs()));
                    if big > MAX_STEP {
                        x *= MAX_STEP / big;
                    }
                    if let Some(f) = merit.line_search(self, state, lambda, &x, &active, psi) {
                        break Some(f);
                    }
                } else if mu == 0.0 && newton.is_none() {
                    // Singular Newton matrix: a singular configuration, or a reduced stiffness
                    // that is singular here (shifted below).
                    let (_, ratio) = null_space(
                        &j,
                        model.equation_scales(),
                        &active,
                        model.characteristic_length(),
                    );
                    if ratio < 1e-10 {
                        if self.reselect(t) {
                            active = self.active_rows();
                            break None;
                        }
                        return Err(Fail::Error(self.singular_at(t, &active)));
                    }
                }
                mu = if mu == 0.0 { mu0 } else { mu * 10.0 };
                if mu > MU_MAX_FACTOR * mu0 {
                    return Err(Fail::Stalled(worst));
                }
            };
            if let Some(iterate) = accepted {
                state.q = iterate.state.q;
                lambda.copy_from_slice(&iterate.lambda);
                mu = if mu < 1e-6 * mu0 { 0.0 } else { mu * 0.25 };
            }
        }
    }

    /// The error of a singular configuration at the synced bodies: the dependent equations.
    fn singular_at(&mut self, t: f64, active: &[usize]) -> DynamicsError {
        let independent = self.independent_rows(t).unwrap_or_default();
        let dependent = active
            .iter()
            .filter(|r| !independent.contains(r))
            .filter_map(|&r| self.model.equation(r))
            .collect();
        DynamicsError::Singular { time: t, dependent }
    }

    /// The reduced stiffness's eigenvalues, the stability and the named soft directions at an
    /// equilibrium.
    fn stability(
        &mut self,
        state: &State,
        lambda: &[f64],
    ) -> Result<StabilityCheck, DynamicsError> {
        let (values, vectors) = self.reduced_eigen(state, lambda, 1.0)?;
        let thr = soft_threshold(&values);
        let mut soft = Vec::new();
        let mut stability = Stability::Stable;
        for (i, &v) in values.iter().enumerate() {
            if v < -thr {
                stability = Stability::Unstable;
            } else if v <= thr && stability == Stability::Stable {
                stability = Stability::Neutral;
            }
            if v <= thr {
                soft.push(self.direction_name(state, vectors.column(i).as_slice()));
            }
        }
        Ok(StabilityCheck {
            eigenvalues: values,
            stability,
            soft_directions: soft,
        })
    }

    /// Eigenvalues ω² (ascending) of K_r x = ω² M_r x at `state` and their directions δ = N x
    /// (columns, n each).
    pub(crate) fn reduced_eigen(
        &mut self,
        state: &State,
        lambda: &[f64],
        s: f64,
    ) -> Result<(Vec<f64>, DMatrix<f64>), DynamicsError> {
        let active = self.active_rows();
        if self.sparse_path() {
            return self.reduced_eigen_sparse(state, lambda, s, &active, STABILITY_MODES);
        }
        let k = self.static_tangent(state, lambda, s);
        let basis = self.constraint_null_space(state, &active);
        let m = self.mass_matrix();
        let mr = basis.transpose() * &m * &basis;
        let kr = basis.transpose() * &k * &basis;
        let (values, x) = generalized_symmetric(&kr, &mr).ok_or(DynamicsError::NonFinite {
            time: state.t,
            what: "the reduced mass matrix",
        })?;
        Ok((values, &basis * x))
    }

    /// Names the direction δ (n): the joint coordinate that moves most along it (angles
    /// weighted by L), else the body that moves most.
    pub(crate) fn direction_name(&mut self, state: &State, delta: &[f64]) -> String {
        let l = self.model.characteristic_length();
        let mut moving = state.clone();
        moving.v.copy_from_slice(delta);
        let nb = state.v.len() / 6;
        let bodies: Vec<BodyState> = (0..nb).map(|k| moving.body_state(k)).collect();
        let g = BodyState::ground();
        let st = |id: BodyId| match id {
            BodyId::Ground => &g,
            BodyId::Moving(k) => &bodies[k],
        };
        let mut best: Option<(f64, String)> = None;
        let zero = Default::default();
        for j in self.model.joints() {
            let pair = BodyPair::new(st(j.body_i), st(j.body_j));
            let rates = j.joint.coordinate_rates(&pair, &zero, &zero);
            for (i, c) in j.joint.kind().info().coordinates.iter().enumerate() {
                let w = match c.measure.quantity() {
                    CoordinateQuantity::Angle => l,
                    _ => 1.0,
                };
                let score = (rates.rates[i] * w).abs();
                if best.as_ref().is_none_or(|(b, _)| score > *b) {
                    best = Some((score, format!("joint \"{}\" {}", j.name, c.name)));
                }
            }
        }
        let body_best = (0..nb)
            .map(|k| {
                let t = Vector3Norm::norm3(&delta[6 * k..6 * k + 3]);
                let r = Vector3Norm::norm3(&delta[6 * k + 3..6 * k + 6]) * l;
                (t.max(r), k)
            })
            .max_by(|a, b| a.0.total_cmp(&b.0));
        match (best, body_best) {
            (Some((s, name)), Some((b, _))) if s > 1e-3 * b => name,
            (_, Some((_, k))) => format!("body \"{}\"", self.model.bodies()[k].name),
            _ => "no direction".into(),
        }
    }

    /// At a failed solve: a zero-stiffness direction along which the loads push, as
    /// [`DynamicsError::FreeDirection`].
    fn free_direction(
        &mut self,
        state: &State,
        lambda: &[f64],
        s: f64,
        t: f64,
    ) -> Option<DynamicsError> {
        let (values, vectors) = self.reduced_eigen(state, lambda, s).ok()?;
        let thr = soft_threshold(&values);
        let (r1, size) = self.static_residual(state, lambda, s);
        let w = self.residual_weights();
        let f = force_scale(&size, &w);
        let l = self.model.characteristic_length();
        for (i, &v) in values.iter().enumerate() {
            if v.abs() > thr {
                continue;
            }
            let x = vectors.column(i);
            // Scaled size of the direction: |δr|/L, |δπ'|.
            let norm = (0..x.len())
                .map(|c| if c % 6 < 3 { x[c] / l } else { x[c] })
                .fold(0.0f64, |a, v| a.max(v.abs()));
            if norm == 0.0 {
                continue;
            }
            // The virtual work of the unbalanced force along it, per unit scaled motion, over L.
            let work = r1.dot(&x) / (norm * l * f);
            if work.abs() > 1e-6 {
                let direction = self.direction_name(state, x.as_slice());
                return Some(DynamicsError::FreeDirection { time: t, direction });
            }
        }
        None
    }
}

/// |x| of a 3-slice.
struct Vector3Norm;
impl Vector3Norm {
    fn norm3(x: &[f64]) -> f64 {
        (x[0] * x[0] + x[1] * x[1] + x[2] * x[2]).sqrt()
    }
}

/// The force scale f: max of the weighted sizes of the force terms, 1 when there are none.
fn force_scale(size: &DVector<f64>, w: &[f64]) -> f64 {
    let f = size.iter().zip(w).fold(0.0f64, |a, (s, w)| a.max(s * w));
    if f > 0.0 {
        f
    } else {
        1.0
    }
}

/// The start of the shift μ (1/s²): a tenth of the largest ratio of diagonal stiffness to
/// diagonal mass, or f / (L m_max) when the stiffness is zero.
fn shift_scale(k: &DMatrix<f64>, m: &DMatrix<f64>, f: f64, l: f64) -> f64 {
    let n = k.nrows();
    let ratio = (0..n).fold(0.0f64, |a, c| a.max((k[(c, c)] / m[(c, c)]).abs()));
    let mmax = (0..n).fold(0.0f64, |a, c| a.max(m[(c, c)]));
    let r = if ratio > 0.0 { ratio } else { f / (l * mmax) };
    0.1 * r.max(1e-12)
}

/// Eigenvalues below this magnitude count as zero: 1e-6 of the largest, and at least 1e-9 1/s².
pub(crate) fn soft_threshold(values: &[f64]) -> f64 {
    let big = values.iter().fold(0.0f64, |a, v| a.max(v.abs()));
    1e-6 * big + 1e-9
}

/// The symmetric generalized eigenproblem K x = ω² M x (M symmetric positive definite): the
/// eigenvalues ascending and M-orthonormal eigenvectors (columns), by the Cholesky factor
/// M = L Lᵀ and the symmetric eigenproblem of L⁻¹ K L⁻ᵀ (K symmetrized). `None` when M is not
/// positive definite.
pub(crate) fn generalized_symmetric(
    k: &DMatrix<f64>,
    m: &DMatrix<f64>,
) -> Option<(Vec<f64>, DMatrix<f64>)> {
    let d = k.nrows();
    if d == 0 {
        return Some((Vec::new(), DMatrix::zeros(0, 0)));
    }
    let chol = m.clone().cholesky()?;
    let l = chol.l();
    let linv = l.clone().try_inverse()?;
    let a = &linv * k * linv.transpose();
    let a = (&a + a.transpose()) * 0.5;
    let eig = a.symmetric_eigen();
    let mut order: Vec<usize> = (0..d).collect();
    order.sort_by(|&i, &j| eig.eigenvalues[i].total_cmp(&eig.eigenvalues[j]));
    let values = order.iter().map(|&i| eig.eigenvalues[i]).collect();
    let mut x = DMatrix::zeros(d, d);
    for (c, &i) in order.iter().enumerate() {
        x.set_column(c, &(linv.transpose() * eig.eigenvectors.column(i)));
    }
    Some((values, x))
}
