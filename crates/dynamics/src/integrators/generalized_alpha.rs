//! Index-3 generalized-α (Arnold & Brüls 2007; Chung & Hulbert 1993 parameters) with Newton on
//! [v̇_{n+1}, λ_{n+1}] and the rotation update p ⊗ exp(Δπ'/2) (formulas in the crate docs).
//!
//! Steps: each output interval is divided into equal steps of at most `h`, so results land on
//! the output times. A step whose Newton iteration fails (no convergence, singular matrix,
//! non-finite values) is retried with half the step, up to `max_halvings` times, and the rest
//! of the interval is divided again after it, so the retried steps do not aim at the end point
//! that failed (a configuration singular to working precision is stepped over).
//!
//! Iteration matrix [M + γ' C_t + β' K_t, Φ_vᵀ; Φ_v, 0]: Φ_v and M exact (but for the
//! Jacobian of the rotation update, about h|ω|/2 relative, see `THETA_REFRESH`), the force tangents
//! by finite differences at the iterate where the matrix is factored (block-sparse and
//! coloured, see `tangents`: 12 evaluations of h per colour of the force-coupling graph). With
//! [`GeneralizedAlphaOptions::reuse_factorization`] (the default) the iteration is a modified
//! Newton: the last factorization (of an earlier iteration or step, or of the velocity
//! projection or output solve, all of the same layout) is kept while the residual contracts by
//! at least 4× per iteration, and refactored at the current iterate when it does not; it is
//! also refreshed at a step's predictor once it has aged so far that two updates no longer pass
//! the acceptance test (`THETA_REFRESH`: 3.3 → 2.2 updates per step on the slider-crank). The
//! velocity projection after a step solves its exact system by iterative refinement on that
//! same factorization. Mass-only steps of a smooth model then cost one factorization every
//! few steps instead of two per step (A02 N = 2 at h = 0.1 ms: 0.14 per step instead of 2).
//! Tangent steps keep their factorization across steps the same way, as long as it is a
//! tangent matrix for the same h, or any held one when the tangent terms are small against M
//! (`TANGENT_SMALL`: a chain's gyroscopic terms); before, every tangent step factored at least
//! once (a 200-link chain: 1.05 factorizations per step, each a sparse LU, since the
//! gyroscopic blocks are unsymmetric and the Schur path needs symmetric ones).
//!
//! Predictor: v̇ and λ extrapolated linearly from the last two steps (`predict`), whose error
//! O(h² x⃛) does not grow with the motion as the constant predictor's h ẍ did.
//!
//! Convergence (`attempt`): the constraint residual, and one of: the residual of the equations
//! of motion relative to the size of their terms; for a matrix factored in the current step,
//! the scaled position increment (as full Newton); for a stale matrix, the contraction
//! estimate of the remaining error in v̇ relative to the largest acceleration, or relative to
//! the first update (the predictor's distance from the step's solution: `NEWTON_FRACTION`),
//! whichever is looser (the latter only when no redundant row is dropped: a dropped row is
//! held through the accelerations alone). The increment tests need only the updates, so they
//! are decided before the residual of the equations of motion is evaluated. Near singular
//! configurations, roundoff stagnation of a fresh matrix within bounds. The iteration's
//! solves are not refined (`Kkt::solve_unrefined`): each residual is of the exact system, so
//! the next iteration corrects a solve's error, and a Schur solve's backward error is a few
//! 1e-12. (Refining them, as before, cost a second solve and a residual per iteration for
//! every chain longer than ~100 links, and did not make the A02 N = 40 tight run more
//! accurate: its error past the first passages is decided by roundoff, see
//! `tests/tests/benchmark_a02_fourbar.rs`.) A stale matrix is never trusted on the β'-scaled
//! position increment alone: after one update with it that increment is small whatever the
//! remaining error in v̇ (A02 N = 2: 6.5e-3 m instead of 2e-6 m).
//!
//! Stored outputs (accelerations, λ, reactions) are those of the augmented system solved at the
//! stored state (index-1 consistent), not the integrator's internal v̇ and λ, which carry the
//! O(h) start-up error of index-3 schemes.
//!
//! After setup a step does not allocate; the tangents are stored as the 6×6 blocks the KKT
//! layout reserves (O(n) memory).

use super::tangents::Tangents;
use crate::kkt::{eval_rows, Kkt, Rhs};
use crate::options::{GeneralizedAlphaOptions, IterationMatrix, SimulationOptions};
use crate::record::Recorder;
use crate::results::IntegrationStats;
use crate::state::State;
use crate::system::Dynamics;
use crate::work::{trapezoid, Multipliers};
use crate::DynamicsError;
use cardan_mechanism::apply_rotation_step;
use std::ops::ControlFlow;

/// The four parameters (αm, αf, γ, β) from ρ∞.
pub fn parameters(rho_inf: f64) -> (f64, f64, f64, f64) {
    let am = (2.0 * rho_inf - 1.0) / (rho_inf + 1.0);
    let af = rho_inf / (rho_inf + 1.0);
    let g = 0.5 + af - am;
    let b = 0.25 * (g + 0.5) * (g + 0.5);
    (am, af, g, b)
}

struct Buf {
    /// Accepted state.
    s: State,
    vdot: Vec<f64>,
    a: Vec<f64>,
    lambda: Vec<f64>,
    /// Trial.
    t1: State,
    vdot1: Vec<f64>,
    a1: Vec<f64>,
    lambda1: Vec<f64>,
    dq: Vec<f64>,
    /// v̇ and λ of the step before the accepted one, and that step's size (0 when there is no
    /// such step: the start, or the active rows were chosen again), for the predictor.
    vdot_prev: Vec<f64>,
    lambda_prev: Vec<f64>,
    h_prev: f64,
    /// Force tangents (iteration matrices with tangent terms).
    tan: Option<Tangents>,
    phi: Vec<f64>,
    /// Term sizes of the equations of motion (n).
    scale: Vec<f64>,
    /// Velocity projection: right-hand side (m_a) and solution [Δv; μ] (n + m_a).
    proj_e: Vec<f64>,
    /// The work quadrature ([`crate::work`]): the power of each channel at the step's two
    /// ends, the work, and v̇ and λ (all rows) of the acceleration solve at the step's end that
    /// gives the drivers' power (`work_step`).
    pw0: Vec<f64>,
    pw1: Vec<f64>,
    w: Vec<f64>,
    w_vdot: Vec<f64>,
    w_lambda: Vec<f64>,
    proj_x: Vec<f64>,
    /// The projection's solutions of the two steps before `proj_x`'s (its warm start
    /// extrapolates from them), and how many of them (0–2) count: steps of the same size as
    /// the last, each projected by refinement.
    proj_x_prev: Vec<f64>,
    proj_x_prev2: Vec<f64>,
    proj_history: usize,
    /// State of the solver's factorization (modified Newton).
    factor: Factor,
    /// The step size of the tangent iteration matrix the solver holds, 0 when it holds
    /// another matrix (see `attempt`).
    tangent_h: f64,
    /// The tangent terms of the last tangent evaluation were small against M
    /// ([`TANGENT_SMALL`]), so a held mass-only matrix serves the iteration as well.
    tangent_small: bool,
    /// Contraction of the chord iteration in the last step that measured it (the ratio of its
    /// second update to its first, both with the matrix held at its start), and in the last
    /// step whose matrix was refreshed at its start (0 after any other factorization of an
    /// iteration; see [`THETA_REFRESH`]).
    chord_theta: f64,
    fresh_theta: f64,
}

impl Buf {
    /// The solver holds [M Φ_vᵀ; Φ_v 0] factored at the accepted state (by a velocity
    /// projection or an acceleration solve): a mass-only matrix, with no chord rate measured.
    fn hold_mass_matrix(&mut self, factor: Factor) {
        self.factor = factor;
        self.tangent_h = 0.0;
        self.chord_theta = 0.0;
    }
}

/// Size of the tangent terms γ' C_t + β' K_t relative to M ([`Tangents::relative_size`]) up to
/// which the modified Newton of a tangent iteration uses M instead: a held mass-only
/// factorization (of a velocity projection or an output's acceleration solve) serves, and a
/// refactorization factors M alone. The chord iteration with M then contracts at about this
/// rate, well within the modified Newton's refactoring bound [`THETA_REFACTOR`]. A chain
/// under gravity (gyroscopic terms only, γ'|ω| ≈ 1e-3) is far below; a stiff spring is above
/// and keeps its tangent matrix. The tangents are evaluated again at every refactorization but
/// a refresh ([`THETA_REFRESH`]), so a motion that makes them grow (the chord iteration with
/// M then fails the bound) brings them back.
const TANGENT_SMALL: f64 = 0.05;

/// out = M x with M = diag(m_k I, J'_k) per body (6 entries per body).
fn mass_mul(mass: &[f64], inertia: &[nalgebra::Matrix3<f64>], x: &[f64], out: &mut [f64]) {
    for (k, (o, x)) in out.chunks_mut(6).zip(x.chunks(6)).enumerate() {
        for c in 0..3 {
            o[c] = mass[k] * x[c];
        }
        let jw = inertia[k] * nalgebra::Vector3::new(x[3], x[4], x[5]);
        o[3..].copy_from_slice(jw.as_slice());
    }
}

/// Sets the trial state from v̇_{n+1}: a_{n+1}, v_{n+1}, q_{n+1}.
fn trial(b: &mut Buf, h: f64, p: (f64, f64, f64, f64)) {
    let (am, af, g, be) = p;
    let n = b.a.len();
    for i in 0..n {
        b.a1[i] = ((1.0 - af) * b.vdot1[i] + af * b.vdot[i] - am * b.a[i]) / (1.0 - am);
        b.t1.v[i] = b.s.v[i] + h * (1.0 - g) * b.a[i] + h * g * b.a1[i];
        b.dq[i] = h * b.s.v[i] + h * h * (0.5 - be) * b.a[i] + h * h * be * b.a1[i];
    }
    b.t1.q.copy_from_slice(&b.s.q);
    apply_rotation_step(&mut b.t1.q, &b.dq);
}

/// The Newton start: v̇ and λ extrapolated linearly from the last two steps,
/// x_{n+1} ≈ x_n + (h / h_{n−1})(x_n − x_{n−1}), or held constant when there is no step
/// before (the start, or after the active rows were chosen again). Its error is
/// O(h² x⃛) instead of the constant predictor's h ẍ, which grows as the motion develops
/// (a swinging chain: h v̈ of the links' accelerations) and decides how many Newton updates
/// a step needs before its acceptance test β'|Δv̇| ≤ tol passes.
fn predict(b: &mut Buf, h: f64) {
    b.vdot1.copy_from_slice(&b.vdot);
    b.lambda1.copy_from_slice(&b.lambda);
    if b.h_prev > 0.0 {
        let r = h / b.h_prev;
        for (x, (v, p)) in b.vdot1.iter_mut().zip(b.vdot.iter().zip(&b.vdot_prev)) {
            *x += r * (v - p);
        }
        for (x, (v, p)) in b
            .lambda1
            .iter_mut()
            .zip(b.lambda.iter().zip(&b.lambda_prev))
        {
            *x += r * (v - p);
        }
    }
}

/// Whether the KKT solver holds a factorization that may serve as the (approximate) iteration
/// matrix: one of the same layout at a nearby state ([M Φ_vᵀ; Φ_v 0] from a projection or an
/// acceleration solve, or an earlier iteration matrix). Modified Newton only.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Factor {
    /// Nothing usable (start, or the last factorization failed).
    None,
    /// Usable, computed before the current step attempt.
    Stale,
    /// Computed in the current step attempt, at one of its iterates.
    Fresh,
}

/// Largest relative residual of the equations of motion accepted as roundoff stagnation (see
/// `attempt`). At A02's horizontal positions it stagnates at 1e-6–1e-5 (N = 2) and about 1e-3
/// (N = 40); a mass-only matrix diverging on a stiff spring stays far above.
const STAGNATION_MAX_RESIDUAL: f64 = 1e-2;

/// Fraction of the first Newton update (the distance from the predictor to the step's
/// solution, O(h² v⃛)) that the chord iteration's estimated error left in v̇ may reach. The
/// error of a stale matrix is systematic, so it accumulates over the steps: on the
/// slider-crank (h = 1, 0.5, 0.25 ms, 5 s) 1e-2 raised the position error by up to 1.8×,
/// 1e-3 by up to 1.4×, 1e-4 left it as with the tolerance alone (within 6 %) with 3.0 instead
/// of 3.9 iterations per step. Used only when no row is dropped (see `attempt`).
const NEWTON_FRACTION: f64 = 1e-4;

/// Consecutive non-contracting iterations of a fresh matrix after which a step attempt fails.
const STALLED_MAX: usize = 4;

/// Contraction rate above which modified Newton refactors at the current iterate.
const THETA_REFACTOR: f64 = 0.25;

/// Contraction rate of the chord iteration above which the next step refactors its matrix at
/// the predictor, before its first update ("refresh"), when that rate is also at least twice
/// the rate of the last refreshed matrix (so that refreshing pays) and the refreshed matrix is
/// mass-only (M, or small tangents: a tangent matrix of a stiff force may be an LU of the
/// full system, dearer than the updates it saves).
///
/// The chord test accepts after two updates while θ²/(1 − θ) ≤ [`NEWTON_FRACTION`], θ ≲ 0.01.
/// A held matrix ages: the iteration matrix misses the Jacobian of the rotation update
/// p ⊗ exp(Δπ'/2) (about h|ω|/2 relative) and the gyroscopic terms (γ'|ω|) even when fresh,
/// and Φ_v moves by about h|ω| per step after it. On the slider-crank at h = 1 ms θ is about
/// 3e-3 for a fresh matrix and grows by 2.8e-3 per step, so a matrix kept until it failed the
/// contraction bound [`THETA_REFACTOR`] made most steps take a third update (3.3 per step).
/// A refresh is one factorization of M (small tangents are not evaluated again) and saves a
/// Newton update in each of the next steps: 2.2 updates and 0.44 factorizations per step,
/// −17 % instructions of the 5 s run; h = 0.5 ms −20 %, the error within 4 %. 0.004 and
/// 0.008 did as well within 3 %. The factor 2 keeps a matrix that cannot be refreshed to
/// below the bound (a fast spin, h|ω| ≫ 0.01, when the matrix ages slowly) from being
/// refactored at every step for nothing; the fresh rate is forgotten at every other
/// factorization of an iteration (the bound's), so a motion that slows down brings the refresh
/// back. It holds refreshes back where a small tangent left out of M decides the rate: a crank
/// falling against a light damper (γ'c/m ≈ 0.01) took 0.26 factorizations per step without it,
/// 0.05 with it, at the same 1.4 updates (`tests/step_policy.rs`). On the slider-crank at
/// h = 2, 4, 8 ms and the 5-link chain up to 16 ms the matrix ages too fast for it to act.
const THETA_REFRESH: f64 = 0.006;

/// One step attempt of size h from `b.s`; on success the trial holds the new state.
///
/// Newton (or modified Newton, see [`GeneralizedAlphaOptions::reuse_factorization`]) on
/// [v̇, λ]. Converged when both residuals at the current iterate are below the tolerance:
/// the equations of motion r_v = M v̇ + Φ_vᵀλ − h relative to the size of their terms
/// (|M v̇| + |Φ_vᵀ||λ| + |h| per coordinate), and the constraints Φ scaled by the equation
/// scales (10 × tolerance). Residual tests rather than increment tests: a β'-scaled increment
/// says little about v̇ when h is small, and a stale iteration matrix leaves an error after the
/// first update that only the residual shows. Near a singular configuration (A02's horizontal
/// positions) the residual of a fresh Newton matrix can stagnate at the roundoff level of the
/// ill-conditioned solve; that is accepted when within 1000 × tolerance.
fn attempt(
    d: &mut Dynamics,
    b: &mut Buf,
    h: f64,
    o: &GeneralizedAlphaOptions,
    tangent: bool,
    stats: &mut IntegrationStats,
) -> Result<bool, DynamicsError> {
    let p = parameters(o.rho_inf);
    let (am, af, g, be) = p;
    let beta_p = h * h * be * (1.0 - af) / (1.0 - am);
    let gamma_p = h * g * (1.0 - af) / (1.0 - am);
    let t1 = b.s.t + h;
    b.t1.t = t1;
    predict(b, h);
    let model = d.model;
    let escale = model.equation_scales();
    let n = b.a.len();
    let mut mu_prev = f64::INFINITY;
    // Consecutive iterations in which a fresh matrix did not reduce the residual.
    let mut stalled = 0;
    // Scaled position increment β'|Δv̇| of the last update.
    let mut inc = f64::INFINITY;
    // Largest increment of v̇ (scaled by the unknown scales) of the last two updates, and the
    // largest scaled |v̇|.
    let (mut dv, mut dv_prev, mut acc) = (f64::INFINITY, f64::INFINITY, 0.0f64);
    // The first update's size: how far the predictor was from the step's solution, the
    // measure of the step's truncation error that the Newton error is held below.
    let mut dv_first = f64::INFINITY;
    let uscale = model.unknown_scales();
    // A tangent iteration matrix is kept across steps like the mass-only one, as long as it
    // is one (not the mass-only matrix of a projection or an output solve) for this h (γ' and
    // β' depend on h).
    let mut refactor = !o.reuse_factorization
        || b.factor == Factor::None
        || (tangent && b.tangent_h.to_bits() != h.to_bits() && !b.tangent_small);
    // A held matrix that has aged (see `THETA_REFRESH`) is refreshed at the predictor, when
    // the refreshed matrix is mass-only (a tangent one may be an LU of the full system).
    let mut refresh = o.reuse_factorization
        && !refactor
        && (!tangent || b.tangent_small)
        && b.chord_theta > THETA_REFRESH.max(2.0 * b.fresh_theta);
    refactor |= refresh;
    if refresh {
        // Measured again with the refreshed matrix.
        b.chord_theta = 0.0;
    }
    // The iteration of this attempt at which the matrix held was factored (MAX: before it),
    // and whether that was a refresh.
    let mut factored_at = usize::MAX;
    let mut refreshed = false;
    if b.factor == Factor::Fresh {
        b.factor = Factor::Stale;
    }
    let tol = o.tolerance.max(1e-14);
    // The fraction of the first update (see `chord_small` below) only without dropped
    // (redundant) rows: the kept rows hold to the tolerance at every iterate, but a dropped row
    // is held only through the accelerations, and near a singular configuration an error of
    // κ·|Δv̇₀| in v̇ drifts it (2e-8 m on the re-selection test's gen-α run, against 8e-13 m).
    let fraction = if d.kkt.as_ref().is_some_and(Kkt::keeps_all_rows) {
        NEWTON_FRACTION
    } else {
        0.0
    };
    for it in 0..o.max_iterations {
        trial(b, h, p);
        d.sync(&b.t1);
        d.eval_forces(t1);
        d.check_forces(t1)?;
        let kkt = d.kkt.as_mut().expect("prepared");
        // Φ_v at the iterate (for Φ_vᵀλ; its slots serve a refactorization below).
        kkt.eval_jacobian(model, &d.elements, &d.bodies, t1);
        // The constraint residual r_c = Φ / β' (into rhs).
        eval_rows(
            model,
            &d.elements,
            &d.bodies,
            &d.turns,
            t1,
            Rhs::Phi,
            &mut b.phi,
        );
        let mut res_c = 0.0f64;
        for (a, &r) in kkt.active.iter().enumerate() {
            kkt.rhs[n + a] = -b.phi[r] / beta_p;
            res_c = res_c.max((b.phi[r] / escale[r]).abs());
        }
        // Converged: the constraints hold and either the equations of motion hold to the
        // tolerance, or the last update of a matrix factored in this step (Newton, or a chord
        // iteration on it) moved the positions by less than the tolerance (scaled).
        let constraints_ok = res_c <= 10.0 * tol;
        let fresh_small = b.factor == Factor::Fresh && !refreshed && inc <= tol;
        // A stale (chord) matrix: the remaining error of v̇ estimated from the contraction of
        // the last two increments, θ/(1 − θ)·|Δv̇| (Hairer & Wanner IV.8; needs two updates),
        // relative to the largest acceleration. At the acceleration level, not the β'-scaled
        // position level: an error e in v̇ left at every step grows into a position error of
        // about e t²/4 over a run, whatever h.
        let theta_dv = dv / dv_prev;
        if it == 2 && factored_at != 1 {
            b.chord_theta = theta_dv;
            if refreshed {
                b.fresh_theta = theta_dv;
            }
        }
        let chord_small = it >= 2
            && theta_dv < 1.0
            && theta_dv / (1.0 - theta_dv) * dv <= (tol * acc).max(fraction * dv_first);
        // Both increment tests are decided by the updates alone: the residual of the equations
        // of motion is not needed then (the slider-crank: 1.5 % of a whole run's instructions).
        // A non-finite force or multiplier, which that residual would show, still rejects.
        if constraints_ok
            && (fresh_small || chord_small)
            && d.h.iter().chain(&b.lambda1).all(|v| v.is_finite())
        {
            return Ok(true);
        }
        // The residual of the equations of motion r_v = M v̇ + Φ_vᵀλ − h (into rhs, negated);
        // the term sizes |M v̇| + |Φ_vᵀ||λ| + |h| into `scale`.
        mass_mul(&d.mass, &d.inertia, &b.vdot1, &mut kkt.rhs[..n]);
        let mut top = std::mem::take(&mut kkt.work_n);
        top.copy_from_slice(&kkt.rhs[..n]);
        for i in 0..n {
            b.scale[i] = top[i].abs() + d.h[i].abs();
        }
        kkt.phi_v_t_mul_add_with_size(&b.lambda1, &mut top, &mut b.scale);
        // Relative to the largest term size of the body's force (or torque) triplet: a
        // component whose own terms all vanish (the torque about a rod's axis) is measured
        // against its neighbours, not against its roundoff.
        let mut res_v = 0.0f64;
        for (k3, tri) in b.scale.chunks(3).enumerate() {
            let size = tri[0].max(tri[1]).max(tri[2]) + f64::MIN_POSITIVE;
            for i in 3 * k3..3 * k3 + 3 {
                let r = top[i] - d.h[i];
                kkt.rhs[i] = -r;
                res_v = res_v.max(r.abs() / size);
            }
        }
        kkt.work_n = top;
        let mu = res_v.max(0.1 * res_c);
        if !mu.is_finite() || kkt.rhs.iter().any(|v| !v.is_finite()) {
            return Ok(false);
        }
        let theta = mu / mu_prev;
        mu_prev = mu;
        // Stagnation at a singular configuration: a fresh matrix no longer reduces the
        // residual, the constraints hold, the equations of motion hold to 1e-4 of their terms
        // (a diverging iteration, e.g. a mass-only matrix on a stiff spring, does not) and the
        // last update moved the positions by less than 100 × tolerance (scaled).
        let stagnated = b.factor == Factor::Fresh
            && it >= 2
            && theta > 0.5
            && res_c <= 10.0 * tol
            && res_v <= STAGNATION_MAX_RESIDUAL
            && inc <= 100.0 * tol;
        if (constraints_ok && res_v <= tol) || stagnated {
            return Ok(true);
        }
        // A fresh matrix that no longer reduces the residual will not converge: give up early
        // (the caller halves the step) instead of refactoring up to `max_iterations` times.
        if b.factor == Factor::Fresh && it >= 1 && theta > 0.9 {
            stalled += 1;
            if stalled >= STALLED_MAX {
                return Ok(false);
            }
        } else {
            stalled = 0;
        }
        if !o.reuse_factorization || (it >= 1 && theta > THETA_REFACTOR) {
            refactor = true;
        }
        if refactor {
            // The top-left only when factoring: M + γ' C_t + β' K_t, the tangents at this
            // iterate (full Newton: at the predictor, once per attempt).
            // Modified Newton factors M alone when the tangent terms are small against it
            // (`TANGENT_SMALL`): the chord iteration contracts as fast, and the Schur path,
            // which needs symmetric blocks, takes M where the gyroscopic terms would send the
            // matrix to the LU of the full system (a 200-link chain: 8.2 → 2.3 ms per step).
            let tangents = b.tan.as_mut().filter(|_| tangent);
            let mut with_tangents = false;
            if let Some(tan) = tangents {
                // A refresh keeps tangents found small: they are not evaluated again.
                if (o.reuse_factorization || it == 0) && !(refresh && b.tangent_small) {
                    tan.eval(d, &b.t1);
                    b.tangent_small =
                        tan.relative_size(gamma_p, beta_p, &d.mass, &d.inertia) <= TANGENT_SMALL;
                }
                with_tangents = !(o.reuse_factorization && b.tangent_small);
            }
            let kkt = d.kkt.as_mut().expect("prepared");
            kkt.set_mass(&d.mass, &d.inertia);
            if let (true, Some(tan)) = (with_tangents, b.tan.as_ref()) {
                kkt.add_top(|r, c| tan.entry(r, c, gamma_p, beta_p));
            }
            if kkt.factor().is_err() {
                b.factor = Factor::None;
                b.tangent_h = 0.0;
                return Ok(false);
            }
            b.factor = Factor::Fresh;
            b.tangent_h = if with_tangents { h } else { 0.0 };
            factored_at = it;
            refreshed = refresh;
            if !refresh {
                b.fresh_theta = 0.0;
            }
            refactor = false;
            refresh = false;
        }
        let kkt = d.kkt.as_mut().expect("prepared");
        if kkt.solve_unrefined().is_err() {
            b.factor = Factor::None;
            b.tangent_h = 0.0;
            return Ok(false);
        }
        stats.newton_iterations += 1;
        dv_prev = dv;
        dv = 0.0;
        acc = 0.0;
        for i in 0..n {
            b.vdot1[i] += kkt.sol[i];
            dv = dv.max((kkt.sol[i] / uscale[i]).abs());
            acc = acc.max((b.vdot1[i] / uscale[i]).abs());
        }
        inc = beta_p * dv;
        if it == 0 {
            dv_first = dv;
        }
        for a in 0..b.lambda1.len() {
            b.lambda1[a] += kkt.sol[n + a];
        }
    }
    Ok(false)
}

/// Velocity projection onto Φ_v v = ν at `b.s` (the M-metric least-change projection of
/// [`Dynamics::project_velocities`]) that reuses the factorization held by the solver when
/// there is one: the exact system K [Δv; μ] = [0; ν − Φ_v v], K = [M Φ_vᵀ; Φ_v 0] at the new
/// state, is solved by iterative refinement with the factored nearby matrix K̃ (residual with
/// the exact K, correction with K̃⁻¹), which converges at the rate ‖K̃⁻¹(K − K̃)‖; a fresh
/// factorization when it does not contract fast enough.
///
/// Called right after a step is accepted: the bodies and Φ_v in the solver are those of the
/// step's last iterate, which is `b.s` (`attempt` converges on the residual it evaluated
/// there), so neither is evaluated again.
///
/// `exact`: the step ends on an output time, whose velocities are stored, so the refinement
/// runs to roundoff (the last correction below 1e-6 of the total or 1e-10 of the largest
/// velocity). Between outputs it stops once the last correction is below
/// [`PROJECTION_FRACTION`] of the total: what is left, a fraction of one step's drift, is
/// removed with the next step's drift by the next projection (each projection corrects the
/// whole residual ν − Φ_v v), so it does not accumulate.
fn project_velocities(
    d: &mut Dynamics,
    b: &mut Buf,
    h: f64,
    exact: bool,
) -> Result<(), DynamicsError> {
    // The warm start extrapolates only over equal steps (the step before of the same size, up
    // to the roundoff of the steps that divide an output interval), and only when no redundant
    // row is dropped: near a configuration where the kept rows lose rank the corrections jump,
    // and an extrapolated start sent the refinement of the Bennett linkage in
    // `tests/reselection.rs` to 1e8 m/s (its steps land on such configurations).
    let same = (h - b.h_prev).abs() <= 1e-9 * h;
    let all_rows = d.kkt.as_ref().is_some_and(Kkt::keeps_all_rows);
    let history = if same && all_rows { b.proj_history } else { 0 };
    b.proj_history = 0;
    if b.factor == Factor::None {
        d.project_velocities(&mut b.s)?;
        b.hold_mass_matrix(Factor::Fresh);
        return Ok(());
    }
    let model = d.model;
    let t = b.s.t;
    let kkt = d.kkt.as_mut().expect("prepared");
    eval_rows(
        model,
        &d.elements,
        &d.bodies,
        &d.turns,
        t,
        Rhs::Nu,
        &mut kkt.full,
    );
    let n = kkt.n;
    let na = kkt.active.len();
    // e = ν − Φ_v v (the right-hand side), kept in `b.proj_e`.
    kkt.phi_v_mul(&b.s.v, &mut b.proj_e);
    for (a, &r) in kkt.active.iter().enumerate() {
        b.proj_e[a] = kkt.full[r] - b.proj_e[a];
    }
    let e_max = b.proj_e.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    if e_max == 0.0 {
        return Ok(());
    }
    // Started from the last steps' corrections, extrapolated (quadratically from three equal
    // steps, linearly from two): the drift a step leaves changes slowly and smoothly (the
    // slider-crank: 5.89e-5, 5.92e-5, 5.95e-5 m/s in three steps), so the first residual is a
    // small fraction of the whole and the first refinement usually ends it. The last
    // correction alone left about 1 %, and a second refinement was needed (the slider-crank
    // at h = 1 ms: 1.8 instead of 2.5 solves per step, −7.5 % instructions of a whole run).
    for ((x, p), p2) in b
        .proj_x
        .iter_mut()
        .zip(b.proj_x_prev.iter_mut())
        .zip(b.proj_x_prev2.iter_mut())
    {
        let last = *x;
        if history >= 2 {
            *x = 3.0 * last - 3.0 * *p + *p2;
        } else if history == 1 {
            *x = 2.0 * last - *p;
        }
        *p2 = *p;
        *p = last;
    }
    // Converged: the last correction is below 1e-6 of the total (itself a small drift
    // correction) or below 1e-10 of the largest velocity.
    let vmax = b.s.v.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    let mut done = false;
    let mut d_prev = f64::INFINITY;
    for _ in 0..6 {
        // Residual of the exact system at x: [−(M x_v + Φ_vᵀ x_μ); e − Φ_v x_v].
        let (xv, xm) = b.proj_x.split_at(n);
        mass_mul(&d.mass, &d.inertia, xv, &mut kkt.rhs[..n]);
        let mut top = std::mem::take(&mut kkt.work_n);
        top.fill(0.0);
        kkt.phi_v_t_mul_add(xm, &mut top);
        for i in 0..n {
            kkt.rhs[i] = -(kkt.rhs[i] + top[i]);
        }
        kkt.work_n = top;
        let mut wa = std::mem::take(&mut kkt.work_a);
        kkt.phi_v_mul(xv, &mut wa);
        for a in 0..na {
            kkt.rhs[n + a] = b.proj_e[a] - wa[a];
        }
        kkt.work_a = wa;
        if kkt.solve_unrefined().is_err() {
            break;
        }
        let mut dmax = 0.0f64;
        let mut xmax = 0.0f64;
        for i in 0..n + na {
            b.proj_x[i] += kkt.sol[i];
            if i < n {
                dmax = dmax.max(kkt.sol[i].abs());
                xmax = xmax.max(b.proj_x[i].abs());
            }
        }
        let fraction = if exact { 1e-6 } else { PROJECTION_FRACTION };
        if dmax <= fraction * xmax || dmax <= 1e-10 * vmax || dmax == 0.0 {
            done = true;
            break;
        }
        if dmax > THETA_REFACTOR * d_prev {
            break;
        }
        d_prev = dmax;
    }
    if done {
        for c in 0..n {
            b.s.v[c] += b.proj_x[c];
        }
        // The solutions before count for the next step if this step had their size.
        b.proj_history = if same { (history + 1).min(2) } else { 0 };
    } else {
        // The refinement's last iterate is no warm start for the next step: near a singular
        // configuration it can be far off (the Bennett linkage of the re-selection test:
        // 1e8 m/s, and the steps after it diverged).
        b.proj_x.fill(0.0);
        d.project_velocities(&mut b.s)?;
        b.hold_mass_matrix(Factor::Fresh);
    }
    Ok(())
}

/// Fraction of the velocity projection's total correction below which its last refinement
/// step ends the refinement between outputs (see `project_velocities`); the part left is
/// about the contraction rate (≤ 0.05 for a held tangent matrix) times this of the total.
/// The slider-crank (h = 1 ms, 2 s): 3.8 refinement solves per step at 1e-6, 2.4 at 1e-3,
/// 1.9 at 1e-2, the same error (2.19e-4, 2.21e-4, 2.19e-4 m). The 5-link chain of
/// `tests/step_policy.rs` against full Newton with exact projections: 1.8e-10 m at 1e-6,
/// 4.6e-10 m at 1e-3, 2.0e-8 m at 1e-2 (the warm start's first correction then often ends
/// the refinement unchecked), against a discretization error of 6.0e-7 m.
const PROJECTION_FRACTION: f64 = 1e-3;

/// The work after an accepted step of size `h` (ending at `b.s`): the trapezoidal rule,
/// second order like the scheme ([`crate::work`]). The drivers' power takes λ from the augmented
/// system solved at the step's end (index 1, as the stored outputs), not the step's own
/// λ_{n+1}: the index-3 λ_{n+1} is off by O(h) (with it, the balance of a driven crank fell like
/// h, not h²; so did it with the λ that follows the recursion of a). That solve costs one
/// factorization per step, for models with drivers only; it leaves [M Φ_vᵀ; Φ_v 0] at the new
/// state factored, which the next step may reuse. No allocation.
fn work_step(d: &mut Dynamics, b: &mut Buf, h: f64) -> Result<(), DynamicsError> {
    if b.w.is_empty() {
        return Ok(());
    }
    if d.model.drivers().is_empty() {
        d.sync(&b.s);
        d.powers(b.s.t, Multipliers::Solution, &mut b.pw1);
    } else {
        d.accelerations(&b.s, &mut b.w_vdot, &mut b.w_lambda)?;
        b.hold_mass_matrix(Factor::Stale);
        d.powers(b.s.t, Multipliers::Full(&b.w_lambda), &mut b.pw1);
    }
    trapezoid(&mut b.w, &b.pw0, &b.pw1, h);
    std::mem::swap(&mut b.pw0, &mut b.pw1);
    Ok(())
}

pub(crate) fn run(
    d: &mut Dynamics,
    state: State,
    times: &[f64],
    o: &GeneralizedAlphaOptions,
    options: &SimulationOptions,
    rec: &mut Recorder,
    stats: &mut IntegrationStats,
    progress: &mut dyn FnMut(f64) -> ControlFlow<()>,
) -> Result<(), DynamicsError> {
    if !(o.h > 0.0 && o.h.is_finite()) {
        return Err(DynamicsError::Options(format!(
            "generalized-α step must be positive, got {}",
            o.h
        )));
    }
    if !(0.0..=1.0).contains(&o.rho_inf) {
        return Err(DynamicsError::Options(format!(
            "ρ∞ must be in [0, 1], got {}",
            o.rho_inf
        )));
    }
    let n = state.v.len();
    let ma = d.kkt.as_ref().expect("prepared").active.len();
    let m = d.model.num_equations();
    let nw = d.num_work_channels();
    let mut b = Buf {
        s: state.clone(),
        vdot: vec![0.0; n],
        a: vec![0.0; n],
        lambda: vec![0.0; ma],
        t1: state.clone(),
        vdot1: vec![0.0; n],
        a1: vec![0.0; n],
        lambda1: vec![0.0; ma],
        dq: vec![0.0; n],
        tan: (o.iteration_matrix != IterationMatrix::MassOnly).then(|| Tangents::new(d, &state)),
        phi: vec![0.0; m],
        scale: vec![0.0; n],
        proj_e: vec![0.0; ma],
        proj_x: vec![0.0; n + ma],
        proj_x_prev: vec![0.0; n + ma],
        proj_x_prev2: vec![0.0; n + ma],
        proj_history: 0,
        factor: Factor::None,
        tangent_h: 0.0,
        tangent_small: false,
        chord_theta: 0.0,
        fresh_theta: 0.0,
        vdot_prev: vec![0.0; n],
        lambda_prev: vec![0.0; ma],
        h_prev: 0.0,
        pw0: vec![0.0; nw],
        pw1: vec![0.0; nw],
        w: vec![0.0; nw],
        w_vdot: vec![0.0; n],
        w_lambda: vec![0.0; m],
    };
    // Consistent accelerations at t0.
    let mut full = vec![0.0; m];
    d.accelerations(&b.s, &mut b.vdot, &mut full)?;
    {
        let kkt = d.kkt.as_ref().expect("prepared");
        for (a, &r) in kkt.active.iter().enumerate() {
            b.lambda[a] = full[r];
        }
    }
    b.a.copy_from_slice(&b.vdot);
    d.powers(b.s.t, Multipliers::Full(&full), &mut b.pw0);
    // The acceleration solve left [M Φ_vᵀ; Φ_v 0] at t0 factored.
    b.hold_mass_matrix(Factor::Stale);
    let mut next = 0;
    while next < times.len() && times[next] <= b.s.t {
        let mut s0 = b.s.clone();
        s0.t = times[next];
        rec.record(d, &s0, 0, Some(&b.w))?;
        next += 1;
    }
    let mut iters_since = 0;
    while next < times.len() {
        let target = times[next];
        // Steps of at most h that land on the output time: the rest of the interval is divided
        // into equal steps after every accepted step, so a halved step shifts the steps after
        // it instead of aiming again at the end point that failed (a configuration singular to
        // working precision, such as A02's horizontal positions, is then stepped over).
        while b.s.t < target {
            if stats.steps + stats.rejected >= options.max_steps {
                return Err(DynamicsError::TooManySteps {
                    time: b.s.t,
                    max_steps: options.max_steps,
                });
            }
            if progress(b.s.t).is_break() {
                return Err(DynamicsError::Stopped { time: b.s.t });
            }
            // (A step up to 1e-6 longer than h rather than an extra one: the roundoff of the
            // accumulated time, about 1e-8 h after 1000 steps, must not add a step.)
            let rest = target - b.s.t;
            let nsub = ((rest / o.h) - 1e-6).ceil().max(1.0);
            let mut h = if nsub <= 1.0 { rest } else { rest / nsub };
            let mut halvings = 0;
            loop {
                let before = stats.newton_iterations;
                let tangent = o.iteration_matrix == IterationMatrix::Tangent;
                if attempt(d, &mut b, h, o, tangent, stats)? {
                    iters_since += stats.newton_iterations - before;
                    break;
                }
                if o.iteration_matrix == IterationMatrix::MassOnlyThenTangent
                    && attempt(d, &mut b, h, o, true, stats)?
                {
                    iters_since += stats.newton_iterations - before;
                    break;
                }
                // Redundant equations: the kept rows may have lost rank at the step's end where
                // the full set has not; choose them again at the failed iterate and retry.
                if b.t1.q.iter().all(|v| v.is_finite()) {
                    d.sync(&b.t1);
                    if d.reselect(b.t1.t) {
                        // λ is over the new active rows: no history for the predictor.
                        b.h_prev = 0.0;
                        continue;
                    }
                }
                stats.rejected += 1;
                halvings += 1;
                if halvings > o.max_halvings {
                    return Err(DynamicsError::StepTooSmall {
                        time: b.s.t,
                        step: h,
                        reason: "Newton iteration of generalized-α failed".into(),
                    });
                }
                h *= 0.5;
            }
            // Accept. The bodies hold the trial already: `attempt` converged on the residual
            // it evaluated there.
            let t_before = b.s.t;
            std::mem::swap(&mut b.s, &mut b.t1);
            d.accept_turns();
            if (b.s.t - target).abs() <= 1e-12 * (1.0 + target.abs()) {
                b.s.t = target;
            }
            std::mem::swap(&mut b.vdot, &mut b.vdot1);
            std::mem::swap(&mut b.a, &mut b.a1);
            std::mem::swap(&mut b.lambda, &mut b.lambda1);
            // The step before, for the predictor (the trial buffers are written anew).
            std::mem::swap(&mut b.vdot_prev, &mut b.vdot1);
            std::mem::swap(&mut b.lambda_prev, &mut b.lambda1);
            if o.project_velocities {
                if o.reuse_factorization {
                    let at_output = b.s.t == target;
                    let h_step = b.s.t - t_before;
                    project_velocities(d, &mut b, h_step, at_output)?;
                } else {
                    d.project_velocities(&mut b.s)?;
                }
            }
            let h_accepted = b.s.t - t_before;
            b.h_prev = h_accepted;
            work_step(d, &mut b, h_accepted)?;
            stats.steps += 1;
        }
        rec.record(d, &b.s, iters_since, Some(&b.w))?;
        // The recorder's acceleration solve refactored [M Φ_vᵀ; Φ_v 0] at the output state.
        b.hold_mass_matrix(Factor::Stale);
        iters_since = 0;
        next += 1;
    }
    Ok(())
}
