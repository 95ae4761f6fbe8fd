//! Index-3 generalized-α (Arnold & Brüls 2007; Chung & Hulbert 1993 parameters) with Newton on
//! [v̇_{n+1}, λ_{n+1}] and the rotation update p ⊗ exp(Δπ'/2) (formulas in the crate docs).
//!
//! Steps: each output interval is divided into equal steps of at most `h`, so results land on
//! the output times. A step whose Newton iteration fails (no convergence, singular matrix,
//! non-finite values) is retried with half the step, up to `max_halvings` times. The iteration
//! matrix [M + γ' C_t + β' K_t, Φ_vᵀ; Φ_v, 0] is rebuilt at every iteration (Φ_v and M exactly,
//! the force tangents by finite differences once per step attempt, at the predictor).
//! Convergence: the scaled position increment β'|Δv̇| (per unknown, divided by its scale) and the
//! scaled constraint residual both below the tolerance.
//!
//! Stored outputs (accelerations, λ, reactions) are those of the augmented system solved at the
//! stored state (index-1 consistent), not the integrator's internal v̇ and λ, which carry the
//! O(h) start-up error of index-3 schemes.
//!
//! After setup a step does not allocate (dense n × n tangent buffers are reserved once; fine for
//! the models of interest, O(n²) memory for very large ones).

use crate::kkt::{eval_rows, Rhs};
use crate::options::{GeneralizedAlphaOptions, IterationMatrix, SimulationOptions};
use crate::record::Recorder;
use crate::results::IntegrationStats;
use crate::state::State;
use crate::system::Dynamics;
use crate::DynamicsError;
use cardan_mechanism::apply_rotation_step;

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
    /// Perturbed state for tangents.
    pert: State,
    h0: Vec<f64>,
    /// −∂h/∂v and −∂h/∂q, column-major n × n.
    ct: Vec<f64>,
    kt: Vec<f64>,
    phi: Vec<f64>,
}

/// Finite-difference tangents at `b.t1`: ct = −∂h/∂v, kt = −∂h/∂q.
fn tangents(d: &mut Dynamics, b: &mut Buf) {
    let n = b.h0.len();
    let l = d.model.characteristic_length();
    d.sync(&b.t1);
    d.eval_forces(b.t1.t);
    b.h0.copy_from_slice(&d.h);
    for c in 0..n {
        // Velocity column.
        b.pert.t = b.t1.t;
        b.pert.q.copy_from_slice(&b.t1.q);
        b.pert.v.copy_from_slice(&b.t1.v);
        let ev = 1e-7 * (1.0 + b.t1.v[c].abs());
        b.pert.v[c] += ev;
        d.sync(&b.pert);
        d.eval_forces(b.t1.t);
        for r in 0..n {
            b.ct[c * n + r] = -(d.h[r] - b.h0[r]) / ev;
        }
        // Position column (r or π').
        b.pert.v.copy_from_slice(&b.t1.v);
        let eq = if c % 6 < 3 { 1e-7 * l } else { 1e-7 };
        b.dq.fill(0.0);
        b.dq[c] = eq;
        apply_rotation_step(&mut b.pert.q, &b.dq);
        d.sync(&b.pert);
        d.eval_forces(b.t1.t);
        for r in 0..n {
            b.kt[c * n + r] = -(d.h[r] - b.h0[r]) / eq;
        }
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

/// One step attempt of size h from `b.s`; on success the trial holds the new state.
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
    b.vdot1.copy_from_slice(&b.vdot);
    b.lambda1.copy_from_slice(&b.lambda);
    let model = d.model;
    let uscale = model.unknown_scales();
    let escale = model.equation_scales();
    let n = b.a.len();
    for it in 0..o.max_iterations {
        trial(b, h, p);
        if it == 0 && tangent {
            tangents(d, b);
        }
        d.sync(&b.t1);
        d.eval_forces(t1);
        let kkt = d.kkt.as_mut().expect("prepared");
        kkt.eval_jacobian(model, &d.elements, &d.bodies, t1);
        kkt.set_mass(&d.mass, &d.inertia);
        if tangent {
            let (ct, kt) = (&b.ct, &b.kt);
            kkt.add_top(|r, c| gamma_p * ct[c * n + r] + beta_p * kt[c * n + r]);
        }
        // Residuals: r_v = M v̇ + Φ_vᵀλ − h, r_c = Φ / β'.
        for k in 0..n / 6 {
            for c in 0..3 {
                kkt.rhs[6 * k + c] = d.mass[k] * b.vdot1[6 * k + c];
            }
            let wd = nalgebra::Vector3::from_column_slice(&b.vdot1[6 * k + 3..6 * k + 6]);
            let jw = d.inertia[k] * wd;
            for c in 0..3 {
                kkt.rhs[6 * k + 3 + c] = jw[c];
            }
        }
        let mut top = std::mem::take(&mut kkt.work_n);
        top.copy_from_slice(&kkt.rhs[..n]);
        kkt.phi_v_t_mul_add(&b.lambda1, &mut top);
        for i in 0..n {
            kkt.rhs[i] = -(top[i] - d.h[i]);
        }
        kkt.work_n = top;
        eval_rows(model, &d.elements, &d.bodies, t1, Rhs::Phi, &mut b.phi);
        let mut res_c = 0.0f64;
        for (a, &r) in kkt.active.iter().enumerate() {
            kkt.rhs[n + a] = -b.phi[r] / beta_p;
            res_c = res_c.max((b.phi[r] / escale[r]).abs());
        }
        if !res_c.is_finite() || kkt.rhs.iter().any(|v| !v.is_finite()) {
            return Ok(false);
        }
        if kkt.factor().is_err() || kkt.solve().is_err() {
            return Ok(false);
        }
        stats.newton_iterations += 1;
        let mut inc = 0.0f64;
        for i in 0..n {
            let dv = kkt.sol[i];
            b.vdot1[i] += dv;
            inc = inc.max((beta_p * dv / uscale[i]).abs());
        }
        for a in 0..b.lambda1.len() {
            b.lambda1[a] += kkt.sol[n + a];
        }
        if inc <= o.tolerance && res_c <= o.tolerance.max(1e-12) * 10.0 {
            trial(b, h, p);
            return Ok(true);
        }
    }
    Ok(false)
}

pub(crate) fn run(
    d: &mut Dynamics,
    state: State,
    times: &[f64],
    o: &GeneralizedAlphaOptions,
    options: &SimulationOptions,
    rec: &mut Recorder,
    stats: &mut IntegrationStats,
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
        pert: state.clone(),
        h0: vec![0.0; n],
        ct: vec![
            0.0;
            if o.iteration_matrix != IterationMatrix::MassOnly {
                n * n
            } else {
                0
            }
        ],
        kt: vec![
            0.0;
            if o.iteration_matrix != IterationMatrix::MassOnly {
                n * n
            } else {
                0
            }
        ],
        phi: vec![0.0; m],
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
    let mut next = 0;
    while next < times.len() && times[next] <= b.s.t {
        let mut s0 = b.s.clone();
        s0.t = times[next];
        rec.record(d, &s0, 0)?;
        next += 1;
    }
    let mut iters_since = 0;
    while next < times.len() {
        let target = times[next];
        let span = target - b.s.t;
        let nsub = ((span / o.h) - 1e-9).ceil().max(1.0) as usize;
        let hs = span / nsub as f64;
        for sub in 0..nsub {
            if stats.steps + stats.rejected >= options.max_steps {
                return Err(DynamicsError::TooManySteps {
                    time: b.s.t,
                    max_steps: options.max_steps,
                });
            }
            let t_goal = if sub + 1 == nsub { target } else { b.s.t + hs };
            // Reach t_goal, halving on failure.
            while b.s.t < t_goal {
                let mut h = t_goal - b.s.t;
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
                // Accept.
                std::mem::swap(&mut b.s, &mut b.t1);
                if (b.s.t - t_goal).abs() <= 1e-12 * (1.0 + t_goal.abs()) {
                    b.s.t = t_goal;
                }
                std::mem::swap(&mut b.vdot, &mut b.vdot1);
                std::mem::swap(&mut b.a, &mut b.a1);
                std::mem::swap(&mut b.lambda, &mut b.lambda1);
                if o.project_velocities {
                    d.project_velocities(&mut b.s)?;
                }
                stats.steps += 1;
            }
        }
        rec.record(d, &b.s, iters_since)?;
        iters_since = 0;
        next += 1;
    }
    Ok(())
}
