//! Step-size control of DOPRI5: the error norm, the PI controller with Gustafsson's predictive
//! factor, the landing on t_end, and the starting step.
//!
//! err = ‖e / (atol + rtol max(|y₀|, |y₁|))‖_RMS with e the difference of the 5th- and
//! 4th-order solutions; a step is accepted when err ≤ 1. Next step: factor
//! 0.9 err^(−0.17) err_old^0.04 within [0.2, 10] (no growth right after a rejection), or
//! Gustafsson's predictive factor when that is smaller (a rising error trend); after a
//! rejection 0.9 err^(−0.17) within [0.2, 1]. A last step is stretched by up to 10 % to land on
//! t_end. The first step from repeated Euler probes ([`starting_step`]).

use super::buffers::{Stages, Values};
use super::ode::Eom;
use crate::options::{Dopri5Options, StepControl};
use crate::results::IntegrationStats;
use crate::system::Dynamics;
use crate::DynamicsError;

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

/// The error norm ‖e / (atol + rtol max(|y₀|, |y₁|))‖_RMS.
pub(super) fn err_norm(y0: &[f64], y1: &[f64], e: &[f64], o: &Dopri5Options) -> f64 {
    let mut s = 0.0;
    for i in 0..e.len() {
        let sc = o.atol + o.rtol * y0[i].abs().max(y1[i].abs());
        s += (e[i] / sc).powi(2);
    }
    (s / e.len().max(1) as f64).sqrt()
}

/// The last accepted step and its error (at least 1e-2), for Gustafsson's predictive factor
/// (Hairer & Wanner, *Solving ODEs II*, §IV.8, as in their RADAU5).
#[derive(Debug, Clone, Copy)]
struct LastAccepted {
    h: f64,
    err: f64,
}

/// The step size and the controller's memory of the steps before.
#[derive(Debug, Clone)]
pub(super) struct StepSizeControl {
    /// The step size the next attempt aims at.
    pub h: f64,
    fixed: bool,
    h_max: f64,
    last_rejected: bool,
    /// Error of the last accepted step, for the PI controller (Hairer's initial value 1e-4).
    err_old: f64,
    last_accepted: Option<LastAccepted>,
}

impl StepSizeControl {
    /// A controller with no history (`h` set by [`start`](Self::start)).
    pub fn new(o: &Dopri5Options) -> Self {
        Self {
            h: 0.0,
            fixed: matches!(o.step, StepControl::Fixed(_)),
            h_max: o.h_max,
            last_rejected: false,
            err_old: 1e-4,
            last_accepted: None,
        }
    }

    /// Whether the steps are fixed (no error control).
    pub fn fixed(&self) -> bool {
        self.fixed
    }

    /// The first step `h`, within h_max and the `span` left. Forgets the steps before.
    pub fn start(&mut self, h: f64, span: f64) {
        self.h = h.min(self.h_max).min(span);
        self.last_rejected = false;
        self.err_old = 1e-4;
        self.last_accepted = None;
    }

    /// The size of the next attempt with `rest` left to t_end: all of it when that is at most
    /// [`STRETCH`] h (adaptive steps; a fixed step only by roundoff) instead of leaving a
    /// sliver of a step (seven evaluations for a few percent of h).
    pub fn step_size(&self, rest: f64) -> f64 {
        let stretch = if self.fixed { 1.0 + 1e-9 } else { STRETCH };
        if rest <= stretch * self.h && rest <= self.h_max {
            rest
        } else {
            self.h.min(rest)
        }
    }

    /// After the step of size `hs` with error `err` was accepted: the next step size
    /// (adaptive steps).
    pub fn accepted(&mut self, hs: f64, err: f64) {
        if !self.fixed {
            // PI control: 0.9 err^−(1/5 − 0.75 β) err_old^β.
            let fac =
                0.9 * err.max(1e-300).powf(-(0.2 - 0.75 * PI_BETA)) * self.err_old.powf(PI_BETA);
            let mut fac = fac.clamp(0.2, if self.last_rejected { 1.0 } else { 10.0 });
            // Gustafsson's predictive factor, 0.9 (h/h_prev) (err_prev/err²)^(1/5), when
            // smaller: it extrapolates a rising error instead of meeting it with a rejection.
            if let Some(last) = self.last_accepted {
                let e = err.max(1e-300);
                let gus = 0.9 * (hs / last.h) * (last.err / (e * e)).powf(0.2);
                fac = fac.min(gus.clamp(0.2, 10.0));
            }
            self.last_accepted = Some(LastAccepted {
                h: hs,
                err: err.max(1e-2),
            });
            self.h = (hs * fac).min(self.h_max);
            self.err_old = err.max(1e-4);
        }
        self.last_rejected = false;
    }

    /// After the step of size `hs` with error `err` (infinite: an evaluation failed) was
    /// rejected: the smaller step to try.
    pub fn rejected(&mut self, hs: f64, err: f64) {
        self.last_rejected = true;
        let fac = if err.is_finite() {
            (0.9 * err.powf(-(0.2 - 0.75 * PI_BETA))).clamp(0.2, 1.0)
        } else {
            0.2
        };
        self.h = hs * fac;
    }
}

/// The first step size: Hairer's estimate (*Solving ODEs I*, §II.4, and `hinit` of DOPRI5),
/// h₀ = 0.01 ‖y₀‖/‖f₀‖, one explicit Euler probe at h₀ for the second derivative
/// d₂ ≈ ‖f(y₀ + h₀ f₀) − f₀‖/h₀, and h = min(100 h₀, (0.01 / max(‖f₀‖, d₂))^(1/5)) (norms
/// weighted by atol + rtol |y₀|). When the factor 100 is what bounds h, the probe is repeated at
/// that h (up to [`EXTRA_PROBES`] times): h₀ measures the state against its rate, which says
/// little when the state starts at rest (velocities 0 with accelerations from gravity), and a
/// probe at a hundred times h₀ still checks the curvature before a larger step is trusted.
/// 1,000-link chain at rest, rtol 1e-3: h₀ = 1.4e-5, so Hairer's h was 1.4e-3 (error estimate
/// 6e-9, then ten-fold growth and a rejected step); the repeated probe gives 3.3e-2.
///
/// `st.k[0]` holds f₀ at (`t`, `v.y0`); the probes use `v.yt`, `st.k[1]` and `st.kw[1]`.
pub(super) fn starting_step(
    d: &mut Dynamics,
    eom: &Eom,
    o: &Dopri5Options,
    t: f64,
    span: f64,
    v: &mut Values,
    st: &mut Stages,
    stats: &mut IntegrationStats,
) -> Result<f64, DynamicsError> {
    let len = v.y0.len();
    let y0 = &v.y0;
    let sc = |i: usize| o.atol + o.rtol * y0[i].abs();
    let norm = |x: &mut dyn FnMut(usize) -> f64| {
        let s: f64 = (0..len).map(|i| (x(i) / sc(i)).powi(2)).sum();
        (s / len.max(1) as f64).sqrt()
    };
    let d0 = norm(&mut |i| y0[i]);
    let d1 = norm(&mut |i| st.k[0][i]);
    let mut h = if d0 < 1e-5 || d1 < 1e-5 {
        1e-6
    } else {
        0.01 * d0 / d1
    };
    h = h.min(span);
    for probe in 0..=EXTRA_PROBES {
        for i in 0..len {
            v.yt[i] = y0[i] + h * st.k[0][i];
        }
        let (k0, rest) = st.k.split_at_mut(1);
        match eom.rhs(d, t + h, &v.yt, &mut rest[0], &mut v.scratch, &mut st.kw[1]) {
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
