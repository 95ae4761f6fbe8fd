//! One step attempt of generalized-α: Newton (or modified Newton) on [v̇_{n+1}, λ_{n+1}]
//! ([`Newton::attempt`]).
//!
//! The iteration matrix is [M + γ' C_t + β' K_t, Φ_vᵀ; Φ_v, 0] with the position constraint
//! scaled by 1/β' (when to factor it: [`super::policy`]). Converged when the constraint
//! residual holds and one of: the residual of the equations of motion r_v = M v̇ + Φ_vᵀλ − h
//! relative to the size of their terms (|M v̇| + |Φ_vᵀ||λ| + |h| per coordinate); for a matrix
//! factored in the current attempt, the β'-scaled position increment (as full Newton); for a
//! stale matrix, the contraction estimate of the remaining error in v̇ relative to the largest
//! acceleration, or relative to the first update (the predictor's distance from the step's
//! solution: [`NEWTON_FRACTION`]), whichever is looser (the latter only when no redundant row
//! is dropped: a dropped row is held through the accelerations alone). The increment tests
//! need only the updates, so they are decided before the residual of the equations of motion
//! is evaluated. Near singular configurations, roundoff stagnation of a fresh matrix within
//! bounds ([`STAGNATION_MAX_RESIDUAL`]).
//!
//! Residual tests rather than increment tests alone: a β'-scaled increment says little about
//! v̇ when h is small, and a stale iteration matrix leaves an error after the first update that
//! only the residual shows. A stale matrix is never trusted on the β'-scaled position increment
//! alone: after one update with it that increment is small whatever the remaining error in v̇
//! (A02 N = 2: 6.5e-3 m instead of 2e-6 m).
//!
//! The iteration's solves are not refined (`Kkt::solve_unrefined`): each residual is of the
//! exact system, so the next iteration corrects a solve's error, and a Schur solve's backward
//! error is a few 1e-12. (Refining them, as before, cost a second solve and a residual per
//! iteration for every chain longer than ~100 links, and did not make the A02 N = 40 tight
//! run more accurate: its error past the first passages is decided by roundoff, see
//! `tests/tests/benchmark_a02_fourbar.rs`.)

use super::parameters::Parameters;
use super::policy::{Factor, FactorPolicy, Plan};
use super::scheme::{mass_mul, update_trial, Variables};
use super::tangents::Tangents;
use crate::kkt::{eval_rows, Kkt, Rhs};
use crate::options::GeneralizedAlphaOptions;
use crate::results::IntegrationStats;
use crate::state::State;
use crate::system::Dynamics;
use crate::DynamicsError;

/// Largest relative residual of the equations of motion accepted as roundoff stagnation (see
/// the module docs). At A02's horizontal positions it stagnates at 1e-6–1e-5 (N = 2) and about
/// 1e-3 (N = 40); a mass-only matrix diverging on a stiff spring stays far above.
const STAGNATION_MAX_RESIDUAL: f64 = 1e-2;

/// Fraction of the first Newton update (the distance from the predictor to the step's
/// solution, O(h² v⃛)) that the chord iteration's estimated error left in v̇ may reach. The
/// error of a stale matrix is systematic, so it accumulates over the steps: on the
/// slider-crank (h = 1, 0.5, 0.25 ms, 5 s) 1e-2 raised the position error by up to 1.8×,
/// 1e-3 by up to 1.4×, 1e-4 left it as with the tolerance alone (within 6 %) with 3.0 instead
/// of 3.9 iterations per step. Used only when no row is dropped (see the module docs).
pub(super) const NEWTON_FRACTION: f64 = 1e-4;

/// Consecutive stalled iterations of a fresh matrix after which a step attempt fails: the
/// residual reduced by less than 10 % and the update by less than half
/// ([`STALLED_UPDATE_RATIO`]).
const STALLED_MAX: usize = 4;

/// The ratio of an update to the one before above which an iteration of a fresh matrix whose
/// residual did not fall counts as stalled. The largest relative residual stays near 1 while
/// contacts settle (a point whose force changes between iterates is as large as the terms it
/// is measured against) although each Newton update halves or better: counted as stalled,
/// such attempts failed and halved the step (the landing 343-sphere pile's first 0.04 s: 79
/// of 521 attempts; with the updates' test none, 14 % less time).
const STALLED_UPDATE_RATIO: f64 = 0.5;

/// The least size of a 3-row group of the equations of motion in the residual test, relative
/// to the largest group of its kind (see `eom_residual`).
const GROUP_FLOOR: f64 = 1e-13;

/// The Newton iteration's buffers and the force tangents.
#[derive(Debug)]
pub(super) struct Newton {
    /// Φ at the iterate (all rows).
    phi: Vec<f64>,
    /// Term sizes of the equations of motion (n).
    scale: Vec<f64>,
    /// The increment Δ of the last trial (after an accepted attempt: the step's).
    pub dq: Vec<f64>,
    /// Force tangents (iteration matrices with tangent terms).
    tangents: Option<Tangents>,
}

/// The sizes of the updates of v̇ (scaled by the unknown scales) that the convergence tests
/// read.
#[derive(Debug, Clone, Copy)]
struct Updates {
    /// Largest increment of the last update and of the one before.
    dv: f64,
    dv_prev: f64,
    /// The largest scaled |v̇| after the last update.
    acc: f64,
    /// The first update's size: how far the predictor was from the step's solution, the
    /// measure of the step's truncation error that the Newton error is held below.
    dv_first: f64,
    /// Scaled position increment β'|Δv̇| of the last update.
    inc: f64,
}

/// The scalings of one step of size h.
#[derive(Debug, Clone, Copy)]
struct Scales {
    h: f64,
    beta_p: f64,
    gamma_p: f64,
}

impl Newton {
    /// The tangents' blocks and colours for a new layout of `d` (bodies newly in contact).
    pub fn new_layout(&mut self, d: &Dynamics, state: &State) {
        if self.tangents.is_some() {
            self.tangents = Some(Tangents::new(d, state));
        }
    }

    /// Buffers for `n` unknowns and `m` equations; `tangents` when the iteration matrix may
    /// have tangent terms.
    pub fn new(n: usize, m: usize, tangents: Option<Tangents>) -> Self {
        Self {
            phi: vec![0.0; m],
            scale: vec![0.0; n],
            dq: vec![0.0; n],
            tangents,
        }
    }

    /// One step attempt of size `h` from `n` with the trial's predictor in `trial` (its v̇ and
    /// λ); `tangent`: an iteration matrix with tangent terms. `true` when converged: the trial
    /// then holds x_{n+1} and the bodies of `d` its state.
    pub fn attempt(
        &mut self,
        d: &mut Dynamics,
        policy: &mut FactorPolicy,
        n: &Variables,
        trial: &mut Variables,
        o: &GeneralizedAlphaOptions,
        p: &Parameters,
        h: f64,
        tangent: bool,
        stats: &mut IntegrationStats,
    ) -> Result<bool, DynamicsError> {
        let sc = Scales {
            h,
            beta_p: p.beta_prime(h),
            gamma_p: p.gamma_prime(h),
        };
        let t1 = n.s.t + h;
        trial.s.t = t1;
        let reuse = o.reuse_factorization;
        let mut mu_prev = f64::INFINITY;
        // Consecutive iterations in which a fresh matrix did not reduce the residual.
        let mut stalled = 0;
        let mut up = Updates {
            dv: f64::INFINITY,
            dv_prev: f64::INFINITY,
            acc: 0.0,
            dv_first: f64::INFINITY,
            inc: f64::INFINITY,
        };
        let mut plan = policy.plan(reuse, tangent, h);
        let tol = o.newton_tolerance.max(1e-14);
        // The fraction of the first update (see `chord_small` below) only without dropped
        // (redundant) rows: the kept rows hold to the tolerance at every iterate, but a dropped
        // row is held only through the accelerations, and near a singular configuration an
        // error of κ·|Δv̇₀| in v̇ drifts it (2e-8 m on the re-selection test's gen-α run,
        // against 8e-13 m).
        let fraction = if d.kkt.as_ref().is_some_and(Kkt::keeps_all_rows) {
            NEWTON_FRACTION
        } else {
            0.0
        };
        for it in 0..o.max_iterations {
            update_trial(n, trial, &mut self.dq, h, p);
            d.sync(&trial.s);
            d.freeze_friction(&trial.lambda);
            d.eval_implicit_forces(t1);
            d.check_forces(t1)?;
            let res_c = constraint_residual(d, &mut self.phi, t1, sc.beta_p);
            // Converged: the constraints hold and either the equations of motion hold to the
            // tolerance, or the last update of a matrix factored in this step (Newton, or a
            // chord iteration on it) moved the positions by less than the tolerance (scaled).
            let constraints_ok = res_c <= 10.0 * tol;
            // Not with joint friction: the iteration matrix lacks the friction's dependence on
            // λ, so a fresh matrix is not exact Newton there and a small increment does not
            // bound the remaining error (the residual decides).
            let fresh_small = policy.factor == Factor::Fresh
                && !plan.refreshed
                && up.inc <= tol
                && d.friction.hf.is_empty();
            // A stale (chord) matrix: the remaining error of v̇ estimated from the contraction
            // of the last two increments, θ/(1 − θ)·|Δv̇| (Hairer & Wanner IV.8; needs two
            // updates), relative to the largest acceleration. At the acceleration level, not
            // the β'-scaled position level: an error e in v̇ left at every step grows into a
            // position error of about e t²/4 over a run, whatever h.
            let theta_dv = up.dv / up.dv_prev;
            policy.measure_chord(&plan, it, theta_dv);
            let chord_small = it >= 2
                && theta_dv < 1.0
                && theta_dv / (1.0 - theta_dv) * up.dv
                    <= (tol * up.acc).max(fraction * up.dv_first);
            // Both increment tests are decided by the updates alone: the residual of the
            // equations of motion is not needed then (the slider-crank: 1.5 % of a whole run's
            // instructions). A non-finite force or multiplier, which that residual would show,
            // still rejects.
            if constraints_ok
                && (fresh_small || chord_small)
                && d.h.iter().chain(&trial.lambda).all(|v| v.is_finite())
            {
                return Ok(true);
            }
            let res_v = eom_residual(d, trial, &mut self.scale);
            let mu = res_v.max(0.1 * res_c);
            let kkt = d.kkt.as_ref().expect("prepared");
            if !mu.is_finite() || kkt.rhs.iter().any(|v| !v.is_finite()) {
                return Ok(false);
            }
            let theta = mu / mu_prev;
            mu_prev = mu;
            // Stagnation at a singular configuration: a fresh matrix no longer reduces the
            // residual, the constraints hold, the equations of motion hold to 1e-2 of their
            // terms (a diverging iteration, e.g. a mass-only matrix on a stiff spring, does
            // not) and the last update moved the positions by less than 100 × tolerance
            // (scaled).
            let fresh = policy.factor == Factor::Fresh;
            let stagnated = fresh
                && it >= 2
                && theta > 0.5
                && res_c <= 10.0 * tol
                && res_v <= STAGNATION_MAX_RESIDUAL
                && up.inc <= 100.0 * tol;
            if (constraints_ok && res_v <= tol) || stagnated {
                return Ok(true);
            }
            // A fresh matrix that no longer reduces the residual nor its updates will not
            // converge: give up early (the caller halves the step) instead of refactoring up to
            // `max_iterations` times.
            if fresh && it >= 1 && theta > 0.9 && up.dv > STALLED_UPDATE_RATIO * up.dv_prev {
                stalled += 1;
                if stalled >= STALLED_MAX {
                    return Ok(false);
                }
            } else {
                stalled = 0;
            }
            plan.after_residual(reuse, it, theta);
            if plan.refactor
                && !self.factor(d, policy, &mut plan, &trial.s, reuse, it, &sc, tangent)
            {
                return Ok(false);
            }
            if !update(d, policy, trial, &mut up, it, sc.beta_p) {
                return Ok(false);
            }
            stats.newton_iterations += 1;
        }
        Ok(false)
    }

    /// Factors the iteration matrix at the iterate `at` (iteration `it`): the top-left
    /// M + γ' C_t + β' K_t with the tangents evaluated there (full Newton: at the predictor,
    /// once per attempt). Modified Newton factors M alone when the tangent terms are small
    /// against it ([`super::policy::TANGENT_SMALL`]): the chord iteration contracts as fast,
    /// and the Schur path, which needs symmetric blocks, takes M where the gyroscopic terms
    /// would send the matrix to the LU of the full system (a 200-link chain: 8.2 → 2.3 ms per
    /// step). `false` when the factorization fails.
    fn factor(
        &mut self,
        d: &mut Dynamics,
        policy: &mut FactorPolicy,
        plan: &mut Plan,
        at: &State,
        reuse: bool,
        it: usize,
        sc: &Scales,
        tangent: bool,
    ) -> bool {
        let (gamma_p, beta_p) = (sc.gamma_p, sc.beta_p);
        let mut with_tangents = false;
        if let Some(tan) = self.tangents.as_mut().filter(|_| tangent) {
            if policy.evaluates_tangents(plan, reuse, it) {
                // `at` is the iterate whose forces the attempt has just evaluated.
                tan.eval(d, at, true);
                policy.tangents_evaluated(tan.relative_size(gamma_p, beta_p, &d.mass, &d.inertia));
            }
            with_tangents = policy.with_tangents(reuse);
        }
        let kkt = d.kkt.as_mut().expect("prepared");
        kkt.set_mass(&d.mass, &d.inertia);
        if let (true, Some(tan)) = (with_tangents, self.tangents.as_ref()) {
            kkt.add_top(|r, c| tan.entry(r, c, gamma_p, beta_p));
        }
        if kkt.factor().is_err() {
            policy.lost();
            return false;
        }
        policy.factored(plan, it, if with_tangents { sc.h } else { 0.0 });
        true
    }
}

/// Φ_v at the synced iterate (for Φ_vᵀλ; its slots serve a refactorization) into the solver,
/// and the constraint residual r_c = Φ / β' into its right-hand side (Φ of all rows into
/// `phi`); returns the largest scaled |Φ| over the kept rows.
fn constraint_residual(d: &mut Dynamics, phi: &mut [f64], t1: f64, beta_p: f64) -> f64 {
    let model = d.model;
    let escale = model.equation_scales();
    let kkt = d.kkt.as_mut().expect("prepared");
    kkt.eval_jacobian(model, &d.elements, &d.bodies, &d.curves, t1);
    eval_rows(
        model,
        &d.elements,
        &d.bodies,
        &d.turns,
        &d.curves,
        t1,
        Rhs::Phi,
        phi,
    );
    let n = kkt.n;
    let mut res_c = 0.0f64;
    for (a, &r) in kkt.active.iter().enumerate() {
        kkt.rhs[n + a] = -phi[r] / beta_p;
        res_c = res_c.max((phi[r] / escale[r]).abs());
    }
    res_c
}

/// The residual of the equations of motion r_v = M v̇ + Φ_vᵀλ − h at the trial into the
/// solver's right-hand side (negated), the term sizes |M v̇| + |Φ_vᵀ||λ| + |h| into `scale`;
/// returns the largest |r_v| relative to the largest term size of the body's force (or
/// torque) triplet: a component whose own terms all vanish (the torque about a rod's axis) is
/// measured against its neighbours, not against its roundoff.
fn eom_residual(d: &mut Dynamics, trial: &Variables, scale: &mut [f64]) -> f64 {
    let kkt = d.kkt.as_mut().expect("prepared");
    let n = kkt.n;
    mass_mul(&d.mass, &d.inertia, &trial.vdot, &mut kkt.rhs[..n]);
    let mut top = std::mem::take(&mut kkt.work_n);
    top.copy_from_slice(&kkt.rhs[..n]);
    for i in 0..n {
        scale[i] = top[i].abs() + d.h[i].abs();
    }
    kkt.phi_v_t_mul_add_with_size(&trial.lambda, &mut top, scale);
    // A group whose terms are all roundoff (a free body's torque-free rotation, its ω̇ a
    // residue of the solve coupled to bodies in contact) is measured against the largest
    // group of its kind (forces, torques), not against its own roundoff.
    let mut floor = [0.0f64; 2];
    for (k3, tri) in scale.chunks(3).enumerate() {
        let f = &mut floor[k3 % 2];
        *f = f.max(tri[0].max(tri[1]).max(tri[2]));
    }
    let floor = floor.map(|f| GROUP_FLOOR * f);
    let mut res_v = 0.0f64;
    for (k3, tri) in scale.chunks(3).enumerate() {
        let size = tri[0].max(tri[1]).max(tri[2]).max(floor[k3 % 2]) + f64::MIN_POSITIVE;
        for i in 3 * k3..3 * k3 + 3 {
            let r = top[i] - d.h[i];
            kkt.rhs[i] = -r;
            res_v = res_v.max(r.abs() / size);
        }
    }
    kkt.work_n = top;
    res_v
}

/// Solves with the held factorization (unrefined) and updates the trial's v̇ and λ (iteration
/// `it`) and the update sizes; `false` when the solve fails.
fn update(
    d: &mut Dynamics,
    policy: &mut FactorPolicy,
    trial: &mut Variables,
    up: &mut Updates,
    it: usize,
    beta_p: f64,
) -> bool {
    let uscale = d.model.unknown_scales();
    let kkt = d.kkt.as_mut().expect("prepared");
    if kkt.solve_unrefined().is_err() {
        policy.lost();
        return false;
    }
    let n = kkt.n;
    up.dv_prev = up.dv;
    let (mut dv, mut acc) = (0.0f64, 0.0f64);
    for i in 0..n {
        trial.vdot[i] += kkt.sol[i];
        dv = dv.max((kkt.sol[i] / uscale[i]).abs());
        acc = acc.max((trial.vdot[i] / uscale[i]).abs());
    }
    up.dv = dv;
    up.acc = acc;
    up.inc = beta_p * dv;
    if it == 0 {
        up.dv_first = dv;
    }
    for a in 0..trial.lambda.len() {
        trial.lambda[a] += kkt.sol[n + a];
    }
    true
}
