//! Dormand-Prince 5(4) (Hairer, Nørsett & Wanner, *Solving ODEs I*, §II.5; the coefficients and
//! the 4th-order continuous extension of their DOPRI5 code).
//!
//! The state y = [q; v] (7 + 6 per body) obeys ṙ = ṙ, ṗ = ½ Lᵀ ω', v̇ from the augmented system
//! (with Baumgarte terms if asked). Error control: err = ‖e / (atol + rtol max(|y₀|, |y₁|))‖_RMS,
//! e the difference of the 5th- and 4th-order solutions; PI step-size control, factor
//! 0.9 err^(−0.17) err_old^0.04 within [0.2, 10] (no growth right after a rejection), or
//! Gustafsson's predictive factor when that is smaller (a rising error trend), a last
//! step stretched by up to 10 % to land on t_end, and a starting step from repeated Euler probes
//! (`starting_step`). Output times inside a step come from the dense
//! output (then projected, like every accepted step end). Projection breaks FSAL, so a step costs
//! seven evaluations. Euler parameters are normalized whenever the state is evaluated.

use crate::options::{Dopri5Options, SimulationOptions, StepControl};
use crate::record::Recorder;
use crate::results::IntegrationStats;
use crate::state::State;
use crate::system::Dynamics;
use crate::work::Multipliers;
use crate::DynamicsError;
use cardan_eulerparam::p_dot_from_local;
use nalgebra::{Vector3, Vector4};
use std::ops::ControlFlow;

const C: [f64; 7] = [0.0, 0.2, 0.3, 0.8, 8.0 / 9.0, 1.0, 1.0];
const A: [[f64; 6]; 7] = [
    [0.0; 6],
    [0.2, 0.0, 0.0, 0.0, 0.0, 0.0],
    [3.0 / 40.0, 9.0 / 40.0, 0.0, 0.0, 0.0, 0.0],
    [44.0 / 45.0, -56.0 / 15.0, 32.0 / 9.0, 0.0, 0.0, 0.0],
    [
        19372.0 / 6561.0,
        -25360.0 / 2187.0,
        64448.0 / 6561.0,
        -212.0 / 729.0,
        0.0,
        0.0,
    ],
    [
        9017.0 / 3168.0,
        -355.0 / 33.0,
        46732.0 / 5247.0,
        49.0 / 176.0,
        -5103.0 / 18656.0,
        0.0,
    ],
    [
        35.0 / 384.0,
        0.0,
        500.0 / 1113.0,
        125.0 / 192.0,
        -2187.0 / 6784.0,
        11.0 / 84.0,
    ],
];
const E: [f64; 7] = [
    71.0 / 57600.0,
    0.0,
    -71.0 / 16695.0,
    71.0 / 1920.0,
    -17253.0 / 339200.0,
    22.0 / 525.0,
    -1.0 / 40.0,
];
const D: [f64; 7] = [
    -12715105075.0 / 11282082432.0,
    0.0,
    87487479700.0 / 32700410799.0,
    -10690763975.0 / 1880347072.0,
    701980252875.0 / 199316789632.0,
    -1453857185.0 / 822651844.0,
    69997945.0 / 29380423.0,
];

/// Preallocated buffers of the integrator.
struct Buffers {
    k: [Vec<f64>; 7],
    y0: Vec<f64>,
    y1: Vec<f64>,
    yt: Vec<f64>,
    cont: [Vec<f64>; 5],
    scratch: State,
    /// The work quadrature ([`crate::work`]): the power of each channel at each stage, the
    /// work at the step's start and end, at an output, and its dense-output coefficients.
    kw: [Vec<f64>; 7],
    w0: Vec<f64>,
    w1: Vec<f64>,
    wt: Vec<f64>,
    wcont: [Vec<f64>; 5],
}

fn to_state(y: &[f64], t: f64, s: &mut State) {
    let nq = s.q.len();
    s.t = t;
    s.q.copy_from_slice(&y[..nq]);
    s.v.copy_from_slice(&y[nq..]);
    for k in 0..s.v.len() / 6 {
        let p = Vector4::from_column_slice(&s.q[7 * k + 3..7 * k + 7]);
        let n = p.norm();
        for c in 0..4 {
            s.q[7 * k + 3 + c] = p[c] / n;
        }
    }
}

fn from_state(s: &State, y: &mut [f64]) {
    let nq = s.q.len();
    y[..nq].copy_from_slice(&s.q);
    y[nq..].copy_from_slice(&s.v);
}

/// dy = f(t, y), and the power of each work channel there into `pw` ([`crate::work`]). No
/// allocation.
fn rhs(
    d: &mut Dynamics,
    t: f64,
    y: &[f64],
    dy: &mut [f64],
    s: &mut State,
    baum: (f64, f64),
    pw: &mut [f64],
) -> Result<(), DynamicsError> {
    if y.iter().any(|v| !v.is_finite()) {
        return Err(DynamicsError::NonFinite {
            time: t,
            what: "the state",
        });
    }
    to_state(y, t, s);
    d.sync(s);
    d.solve_eom(t, baum)?;
    let nb = s.v.len() / 6;
    let nq = 7 * nb;
    let sol = &d.kkt.as_ref().expect("prepared").sol;
    for k in 0..nb {
        let p = Vector4::from_column_slice(&y[7 * k + 3..7 * k + 7]);
        let w = Vector3::from_column_slice(&y[nq + 6 * k + 3..nq + 6 * k + 6]);
        let pd = p_dot_from_local(&p, &w);
        for c in 0..3 {
            dy[7 * k + c] = y[nq + 6 * k + c];
        }
        for c in 0..4 {
            dy[7 * k + 3 + c] = pd[c];
        }
    }
    dy[nq..].copy_from_slice(&sol[..6 * nb]);
    d.powers(t, Multipliers::Solution, pw);
    Ok(())
}

fn err_norm(y0: &[f64], y1: &[f64], e: &[f64], o: &Dopri5Options) -> f64 {
    let mut s = 0.0;
    for i in 0..e.len() {
        let sc = o.atol + o.rtol * y0[i].abs().max(y1[i].abs());
        s += (e[i] / sc).powi(2);
    }
    (s / e.len().max(1) as f64).sqrt()
}

/// β of the PI step-size controller (Hairer, Nørsett & Wanner, *Solving ODEs II*, §IV.2, and
/// the default of their DOPRI5 code): it damps the step-size oscillation an I controller
/// shows where accuracy is limited by a fast mode (a long chain: error estimates growing like
/// h¹⁰ near h = 3e-2, so that each attempt to grow is rejected).
const PI_BETA: f64 = 0.04;

/// Largest factor by which a step is stretched to land on t_end.
const STRETCH: f64 = 1.1;

/// Probes of [`starting_step`] beyond Hairer's first (each one evaluation of the equations
/// of motion).
const EXTRA_PROBES: usize = 2;

/// The first step size: Hairer's estimate (*Solving ODEs I*, §II.4, and `hinit` of DOPRI5),
/// h₀ = 0.01 ‖y₀‖/‖f₀‖, one explicit Euler probe at h₀ for the second derivative
/// d₂ ≈ ‖f(y₀ + h₀ f₀) − f₀‖/h₀, and h = min(100 h₀, (0.01 / max(‖f₀‖, d₂))^(1/5)) (norms
/// weighted by atol + rtol |y₀|). When the factor 100 is what bounds h, the probe is repeated at
/// that h (up to [`EXTRA_PROBES`] times): h₀ measures the state against its rate, which says
/// little when the state starts at rest (velocities 0 with accelerations from gravity), and a
/// probe at a hundred times h₀ still checks the curvature before a larger step is trusted.
/// 1,000-link chain at rest, rtol 1e-3: h₀ = 1.4e-5, so Hairer's h was 1.4e-3 (error estimate
/// 6e-9, then ten-fold growth and a rejected step); the repeated probe gives 3.3e-2.
fn starting_step(
    d: &mut Dynamics,
    t: f64,
    span: f64,
    b: &mut Buffers,
    o: &Dopri5Options,
    baum: (f64, f64),
    stats: &mut IntegrationStats,
) -> Result<f64, DynamicsError> {
    let len = b.y0.len();
    let sc = |i: usize| o.atol + o.rtol * b.y0[i].abs();
    let norm = |v: &mut dyn FnMut(usize) -> f64| {
        let s: f64 = (0..len).map(|i| (v(i) / sc(i)).powi(2)).sum();
        (s / len.max(1) as f64).sqrt()
    };
    let d0 = norm(&mut |i| b.y0[i]);
    let d1 = norm(&mut |i| b.k[0][i]);
    let mut h = if d0 < 1e-5 || d1 < 1e-5 {
        1e-6
    } else {
        0.01 * d0 / d1
    };
    h = h.min(span);
    for probe in 0..=EXTRA_PROBES {
        for i in 0..len {
            b.yt[i] = b.y0[i] + h * b.k[0][i];
        }
        let (k0, rest) = b.k.split_at_mut(1);
        match rhs(
            d,
            t + h,
            &b.yt,
            &mut rest[0],
            &mut b.scratch,
            baum,
            &mut b.kw[1],
        ) {
            Ok(()) => stats.evaluations += 1,
            // A later probe that fails keeps the step already found.
            Err(_) if probe > 0 => return Ok(h),
            Err(e) => return Err(e),
        }
        let d2 = norm(&mut |i| rest[0][i] - k0[0][i]) / h;
        let h1 = if d1.max(d2) <= 1e-15 {
            (h * 1e-3).max(1e-6)
        } else {
            (0.01 / d1.max(d2)).powf(0.2)
        };
        let capped = 100.0 * h < h1;
        h = (100.0 * h).min(h1).min(span).min(o.h_max);
        if !capped || h >= span || h >= o.h_max {
            break;
        }
    }
    Ok(h)
}

/// [`Dynamics::reselect`] at the state held in `y` at time `t` (when finite): whether the
/// independent rows of a mechanism with redundant equations changed.
fn reselect_at(d: &mut Dynamics, y: &[f64], t: f64, s: &mut State) -> bool {
    if d.redundant.is_empty() || y.iter().any(|v| !v.is_finite()) {
        return false;
    }
    to_state(y, t, s);
    d.sync(s);
    d.reselect(t)
}

/// The work at the end of an accepted step of size `hs` and its dense-output coefficients: the
/// step's weights and continuous extension applied to the stage powers, as for the state
/// ([`crate::work`]). No allocation.
fn work_step(b: &mut Buffers, hs: f64) {
    for i in 0..b.w0.len() {
        let mut acc = 0.0;
        for j in 0..6 {
            acc += A[6][j] * b.kw[j][i];
        }
        b.w1[i] = b.w0[i] + hs * acc;
        let wdiff = b.w1[i] - b.w0[i];
        let bspl = hs * b.kw[0][i] - wdiff;
        let mut dd = 0.0;
        for j in 0..7 {
            dd += D[j] * b.kw[j][i];
        }
        b.wcont[0][i] = b.w0[i];
        b.wcont[1][i] = wdiff;
        b.wcont[2][i] = bspl;
        b.wcont[3][i] = wdiff - hs * b.kw[6][i] - bspl;
        b.wcont[4][i] = hs * dd;
    }
}

/// Projects the state held in `y` (positions, then velocities); returns Newton iterations.
fn project(
    d: &mut Dynamics,
    t: f64,
    y: &mut [f64],
    s: &mut State,
    o: &Dopri5Options,
) -> Result<usize, DynamicsError> {
    to_state(y, t, s);
    let it = match d.project_positions(s, o.projection_tolerance) {
        Ok(it) => it,
        // The kept rows of a mechanism with redundant equations may have lost rank here:
        // choose them again at the unprojected state and project again from it.
        Err(e) => {
            if !reselect_at(d, y, t, s) {
                return Err(e);
            }
            to_state(y, t, s);
            d.project_positions(s, o.projection_tolerance)?
        }
    };
    d.project_velocities(s)?;
    from_state(s, y);
    Ok(it)
}

pub(crate) fn run(
    d: &mut Dynamics,
    state: State,
    times: &[f64],
    o: &Dopri5Options,
    options: &SimulationOptions,
    rec: &mut Recorder,
    stats: &mut IntegrationStats,
    progress: &mut dyn FnMut(f64) -> ControlFlow<()>,
) -> Result<(), DynamicsError> {
    if !(o.rtol > 0.0 && o.atol > 0.0 && o.rtol.is_finite() && o.atol.is_finite()) {
        return Err(DynamicsError::Options(format!(
            "DOPRI5 tolerances must be positive (rtol = {}, atol = {})",
            o.rtol, o.atol
        )));
    }
    if let StepControl::Fixed(h) = o.step {
        if !(h > 0.0 && h.is_finite()) {
            return Err(DynamicsError::Options(format!(
                "fixed step must be positive, got {h}"
            )));
        }
    }
    let len = state.q.len() + state.v.len();
    let nw = d.num_work_channels();
    let z = || vec![0.0; len];
    let mut b = Buffers {
        k: [z(), z(), z(), z(), z(), z(), z()],
        y0: z(),
        y1: z(),
        yt: z(),
        cont: [z(), z(), z(), z(), z()],
        scratch: state.clone(),
        kw: std::array::from_fn(|_| vec![0.0; nw]),
        w0: vec![0.0; nw],
        w1: vec![0.0; nw],
        wt: vec![0.0; nw],
        wcont: std::array::from_fn(|_| vec![0.0; nw]),
    };
    let baum = o.stabilization.baumgarte();
    let projects = o.stabilization.projects();

    let mut t = state.t;
    let t_end = options.t_end;
    from_state(&state, &mut b.y0);
    let mut next = 0;
    while next < times.len() && times[next] <= t {
        to_state(&b.y0, times[next], &mut b.scratch);
        rec.record(d, &b.scratch, 0, Some(&b.w0))?;
        next += 1;
    }
    if next == times.len() || t >= t_end {
        return Ok(());
    }

    rhs(d, t, &b.y0, &mut b.k[0], &mut b.scratch, baum, &mut b.kw[0])?;
    stats.evaluations += 1;
    let span = t_end - t;
    let mut h = match o.step {
        StepControl::Fixed(h) => h,
        StepControl::Adaptive { initial: Some(h) } => h,
        StepControl::Adaptive { initial: None } => {
            starting_step(d, t, span, &mut b, o, baum, stats)?
        }
    };
    h = h.min(o.h_max).min(span);
    let fixed = matches!(o.step, StepControl::Fixed(_));
    let mut last_rejected = false;
    // Error of the last accepted step, for the PI controller (Hairer's initial value).
    let mut err_old: f64 = 1e-4;
    // The last accepted step and its error (at least 1e-2), for Gustafsson's predictive
    // factor (Hairer & Wanner, *Solving ODEs II*, §IV.8, as in their RADAU5).
    let mut last_accepted: Option<(f64, f64)> = None;
    let mut proj_it = 0;

    loop {
        if stats.steps + stats.rejected >= options.max_steps {
            return Err(DynamicsError::TooManySteps {
                time: t,
                max_steps: options.max_steps,
            });
        }
        if progress(t).is_break() {
            return Err(DynamicsError::Stopped { time: t });
        }
        // Land on t_end in one step when the rest is at most STRETCH h (adaptive steps; a
        // fixed step only by roundoff), instead of leaving a sliver of a step (seven
        // evaluations for a few percent of h).
        let rest = t_end - t;
        let stretch = if fixed { 1.0 + 1e-9 } else { STRETCH };
        let hs = if rest <= stretch * h && rest <= o.h_max {
            rest
        } else {
            h.min(rest)
        };
        // Stages 2..7.
        let mut failed = None;
        let mut failed_at = t + hs;
        for s in 1..7 {
            for i in 0..len {
                let mut acc = 0.0;
                for j in 0..s {
                    acc += A[s][j] * b.k[j][i];
                }
                b.yt[i] = b.y0[i] + hs * acc;
            }
            let (done, rest) = b.k.split_at_mut(s);
            let _ = done;
            match rhs(
                d,
                t + C[s] * hs,
                &b.yt,
                &mut rest[0],
                &mut b.scratch,
                baum,
                &mut b.kw[s],
            ) {
                Ok(()) => stats.evaluations += 1,
                Err(e) => {
                    failed = Some(e);
                    failed_at = t + C[s] * hs;
                    break;
                }
            }
            if s == 6 {
                b.y1.copy_from_slice(&b.yt);
            }
        }
        let err = if failed.is_some() {
            f64::INFINITY
        } else if fixed {
            0.0
        } else {
            for i in 0..len {
                let mut e = 0.0;
                for j in 0..7 {
                    e += E[j] * b.k[j][i];
                }
                b.yt[i] = hs * e;
            }
            err_norm(&b.y0, &b.y1, &b.yt, o)
        };
        if !(err <= 1.0 && err.is_finite()) {
            // Redundant equations: the kept rows may have lost rank within the step where the
            // full set has not. Choose them again where the step went wrong and retry it. This
            // runs a dense rank analysis (which allocates) on every rejected step of a model with
            // redundant equations; waiting for a second rejection in a row missed Bennett's
            // singular point (the shorter retry ends too far from it to change the choice).
            let y = if failed.is_some() { &b.yt } else { &b.y1 };
            if reselect_at(d, y, failed_at, &mut b.scratch) {
                stats.rejected += 1;
                continue;
            }
        }
        if fixed {
            if let Some(e) = failed {
                return Err(e);
            }
        }
        if err <= 1.0 && err.is_finite() {
            // Accept: dense output coefficients from the unprojected step.
            let t1 = t + hs;
            for i in 0..len {
                let ydiff = b.y1[i] - b.y0[i];
                let bspl = hs * b.k[0][i] - ydiff;
                b.cont[0][i] = b.y0[i];
                b.cont[1][i] = ydiff;
                b.cont[2][i] = bspl;
                b.cont[3][i] = ydiff - hs * b.k[6][i] - bspl;
                let mut dd = 0.0;
                for j in 0..7 {
                    dd += D[j] * b.k[j][i];
                }
                b.cont[4][i] = hs * dd;
            }
            work_step(&mut b, hs);
            stats.steps += 1;
            // Outputs inside (t, t1].
            while next < times.len() && times[next] <= t1 + 1e-12 * hs.abs() {
                let tt = times[next];
                if (tt - t1).abs() <= 1e-12 * hs.abs() {
                    b.yt.copy_from_slice(&b.y1);
                    b.wt.copy_from_slice(&b.w1);
                } else {
                    let th = (tt - t) / hs;
                    let th1 = 1.0 - th;
                    for i in 0..len {
                        b.yt[i] = b.cont[0][i]
                            + th * (b.cont[1][i]
                                + th1 * (b.cont[2][i] + th * (b.cont[3][i] + th1 * b.cont[4][i])));
                    }
                    for i in 0..b.wt.len() {
                        let c = &b.wcont;
                        b.wt[i] = c[0][i]
                            + th * (c[1][i] + th1 * (c[2][i] + th * (c[3][i] + th1 * c[4][i])));
                    }
                }
                let mut it = 0;
                if projects {
                    it = project(d, tt, &mut b.yt, &mut b.scratch, o)?;
                    stats.newton_iterations += it;
                } else {
                    to_state(&b.yt, tt, &mut b.scratch);
                }
                to_state(&b.yt, tt, &mut b.scratch);
                rec.record(d, &b.scratch, it + proj_it, Some(&b.wt))?;
                next += 1;
            }
            t = t1;
            b.y0.copy_from_slice(&b.y1);
            b.w0.copy_from_slice(&b.w1);
            if projects {
                proj_it = project(d, t, &mut b.y0, &mut b.scratch, o)?;
                stats.newton_iterations += proj_it;
            }
            if t >= t_end || next == times.len() {
                break;
            }
            rhs(d, t, &b.y0, &mut b.k[0], &mut b.scratch, baum, &mut b.kw[0])?;
            stats.evaluations += 1;
            if !fixed {
                // PI control: 0.9 err^−(1/5 − 0.75 β) err_old^β.
                let fac =
                    0.9 * err.max(1e-300).powf(-(0.2 - 0.75 * PI_BETA)) * err_old.powf(PI_BETA);
                let mut fac = fac.clamp(0.2, if last_rejected { 1.0 } else { 10.0 });
                // Gustafsson's predictive factor, 0.9 (h/h_prev) (err_prev/err²)^(1/5), when
                // smaller: it extrapolates a rising error instead of meeting it with a
                // rejection.
                if let Some((h_prev, err_prev)) = last_accepted {
                    let e = err.max(1e-300);
                    let gus = 0.9 * (hs / h_prev) * (err_prev / (e * e)).powf(0.2);
                    fac = fac.min(gus.clamp(0.2, 10.0));
                }
                last_accepted = Some((hs, err.max(1e-2)));
                h = (hs * fac).min(o.h_max);
                err_old = err.max(1e-4);
            }
            last_rejected = false;
        } else {
            stats.rejected += 1;
            last_rejected = true;
            let fac = if err.is_finite() {
                (0.9 * err.powf(-(0.2 - 0.75 * PI_BETA))).clamp(0.2, 1.0)
            } else {
                0.2
            };
            h = hs * fac;
            if h < o.h_min {
                return Err(match failed {
                    Some(e) => e,
                    None => DynamicsError::StepTooSmall {
                        time: t,
                        step: h,
                        reason: format!("error estimate {err:.3e}"),
                    },
                });
            }
        }
    }
    Ok(())
}
