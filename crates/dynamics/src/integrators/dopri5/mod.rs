//! Dormand-Prince 5(4) (Hairer, Nørsett & Wanner, *Solving ODEs I*, §II.5; the coefficients and
//! the 4th-order continuous extension of their DOPRI5 code) as a `Stepper`.
//!
//! The state y = [q; v] (7 + 6 per body) obeys ṙ = ṙ, ṗ = ½ Lᵀ ω', v̇ from the augmented system
//! (with Baumgarte terms if asked; `ode`). Error control and the step sizes: `control` (PI
//! controller, Gustafsson's predictive factor, landing on t_end, the starting step). Output
//! times inside a step come from the dense output (`dense`), then projected like every
//! accepted step end (`projection`). Projection breaks FSAL, so a step costs seven
//! evaluations. Euler parameters are normalized whenever the state is evaluated.
//!
//! One step: `prepare` evaluates the first stage at the accepted state and
//! sets the step size (the starting step, or the controller's from the last step);
//! `attempt` evaluates stages 2–7 and the error estimate, and either fills
//! the dense output of the unprojected step or shrinks the step; `advance`
//! projects the step's end, which becomes the accepted state.
//!
//! The Schur solves of a run are refined by its tolerance (`SchurRefinement::for_rtol`).

mod buffers;
mod control;
mod dense;
mod ode;
mod projection;
mod tableau;

use super::stepper::{Attempt, Sample, Span, Stepper};
use crate::kkt::SchurRefinement;
use crate::options::{Dopri5Options, StepControl};
use crate::results::IntegrationStats;
use crate::state::State;
use crate::system::Dynamics;
use crate::DynamicsError;
use buffers::{Stages, Values};
use control::{err_norm, starting_step, StepSizeControl};
use dense::DenseOutput;
use ode::{from_state, to_state, Eom};
use projection::{project, reselect_at};
use tableau::{A, C, E};

/// The last accepted step: its size, end and error estimate.
#[derive(Debug, Clone, Copy)]
struct Taken {
    h: f64,
    t1: f64,
    err: f64,
}

/// The DOPRI5 stepper.
#[derive(Debug)]
pub(crate) struct Dopri5 {
    o: Dopri5Options,
    t_end: f64,
    eom: Eom,
    /// The time of the accepted state `v.y0`.
    t: f64,
    v: Values,
    st: Stages,
    dense: DenseOutput,
    control: StepSizeControl,
    /// The last accepted step (its dense output is in `dense`); `None` before the first step
    /// after the (re)start.
    taken: Option<Taken>,
    /// Newton iterations of the projection of the accepted state (reported with the outputs
    /// of the step from it).
    proj_it: usize,
    stats: IntegrationStats,
}

impl Dopri5 {
    /// Stages 2–7 of a step of size `hs` from the accepted state; `y1` the 5th-order solution.
    /// On a failed evaluation: the error and the stage's time (`yt` holds its value).
    fn stages(&mut self, d: &mut Dynamics, hs: f64) -> Option<(DynamicsError, f64)> {
        let t = self.t;
        let Self {
            eom, v, st, stats, ..
        } = self;
        for s in 1..7 {
            for i in 0..v.yt.len() {
                let mut acc = 0.0;
                for j in 0..s {
                    acc += A[s][j] * st.k[j][i];
                }
                v.yt[i] = v.y0[i] + hs * acc;
            }
            let ts = t + C[s] * hs;
            match eom.rhs(d, ts, &v.yt, &mut st.k[s], &mut v.scratch, &mut st.kw[s]) {
                Ok(()) => stats.evaluations += 1,
                Err(e) => return Some((e, ts)),
            }
            if s == 6 {
                v.y1.copy_from_slice(&v.yt);
            }
        }
        None
    }

    /// The error estimate of the step of size `hs` (its difference vector into `yt`).
    fn error(&mut self, hs: f64) -> f64 {
        let v = &mut self.v;
        for i in 0..v.yt.len() {
            let mut e = 0.0;
            for j in 0..7 {
                e += E[j] * self.st.k[j][i];
            }
            v.yt[i] = hs * e;
        }
        err_norm(&v.y0, &v.y1, &v.yt, &self.o)
    }

    /// y and W at `t` into `yt` and `wt`: the accepted state before any step, else the step's
    /// end within 1e-12 of the step from it, else the dense output.
    fn dense_at(&mut self, t: f64) {
        let v = &mut self.v;
        match self.taken {
            None => {
                v.yt.copy_from_slice(&v.y0);
                v.wt.copy_from_slice(&v.w0);
            }
            Some(step) if (t - step.t1).abs() <= 1e-12 * step.h.abs() => {
                v.yt.copy_from_slice(&v.y1);
                v.wt.copy_from_slice(&v.w1);
            }
            Some(step) => self.dense.eval((t - self.t) / step.h, v),
        }
    }
}

impl Stepper for Dopri5 {
    type Options = Dopri5Options;

    fn new(
        d: &mut Dynamics,
        state: State,
        o: &Dopri5Options,
        t_end: f64,
    ) -> Result<Self, DynamicsError> {
        // The options' one validation (the same messages as the driver loop's).
        o.validate()
            .map_err(|e| DynamicsError::Options(e.to_string()))?;
        let len = state.q.len() + state.v.len();
        let nw = d.num_work_channels();
        let mut stepper = Self {
            o: *o,
            t_end,
            eom: Eom {
                baumgarte: o.stabilization.baumgarte(),
                refine: SchurRefinement::for_rtol(o.rtol),
            },
            t: state.t,
            v: Values::new(&state, nw),
            st: Stages::new(len, nw),
            dense: DenseOutput::new(len, nw),
            control: StepSizeControl::new(o),
            taken: None,
            proj_it: 0,
            stats: IntegrationStats::default(),
        };
        stepper.restart(d, &state)?;
        Ok(stepper)
    }

    fn refinement(&self) -> SchurRefinement {
        self.eom.refine
    }

    fn time(&self) -> f64 {
        self.t
    }

    fn stats(&self) -> &IntegrationStats {
        &self.stats
    }

    fn finished(&self) -> bool {
        self.t >= self.t_end
    }

    /// The first stage at the accepted state, then the step size: the starting step after the
    /// (re)start, else the controller's after the last accepted step.
    fn prepare(&mut self, d: &mut Dynamics) -> Result<(), DynamicsError> {
        let t = self.t;
        let Self { eom, v, st, .. } = self;
        eom.rhs(d, t, &v.y0, &mut st.k[0], &mut v.scratch, &mut st.kw[0])?;
        self.stats.evaluations += 1;
        match self.taken {
            Some(step) => self.control.accepted(step.h, step.err),
            None => {
                let span = self.t_end - self.t;
                let h = match self.o.step {
                    StepControl::Fixed(h) => h,
                    StepControl::Adaptive { initial: Some(h) } => h,
                    StepControl::Adaptive { initial: None } => starting_step(
                        d,
                        &self.eom,
                        &self.o,
                        self.t,
                        span,
                        &mut self.v,
                        &mut self.st,
                        &mut self.stats,
                    )?,
                };
                self.control.start(h, span);
            }
        }
        Ok(())
    }

    fn attempt(&mut self, d: &mut Dynamics, _target: f64) -> Result<Attempt, DynamicsError> {
        let t = self.t;
        let mut hs = self.control.step_size(self.t_end - t);
        if let Some(c) = d.collisions.as_ref().filter(|_| !self.control.fixed()) {
            // No shape moves more than its margin in a step (`Collisions::step_cap`): in
            // free flight the error estimate would let a step carry a ball through a wall.
            to_state(&self.v.y0, t, &mut self.v.scratch);
            let bodies = &mut d.bodies;
            self.v.scratch.body_states_into(bodies);
            let cap = c.step_cap(bodies);
            if cap < hs {
                hs = cap;
                self.control.h = cap;
            }
        }
        let failed = self.stages(d, hs);
        let fixed = self.control.fixed();
        let err = if failed.is_some() {
            f64::INFINITY
        } else if fixed {
            0.0
        } else {
            self.error(hs)
        };
        if !(err <= 1.0 && err.is_finite()) {
            // Redundant equations: the kept rows may have lost rank within the step where the
            // full set has not. Choose them again where the step went wrong and retry it. This
            // runs a dense rank analysis (which allocates) on every rejected step of a model with
            // redundant equations; waiting for a second rejection in a row missed Bennett's
            // singular point (the shorter retry ends too far from it to change the choice).
            let (y, at) = match &failed {
                Some((_, at)) => (&self.v.yt, *at),
                None => (&self.v.y1, t + hs),
            };
            if reselect_at(d, y, at, &mut self.v.scratch) {
                self.stats.rejected += 1;
                return Ok(Attempt::Rejected);
            }
        }
        let failed = match (fixed, failed) {
            (true, Some((e, _))) => return Err(e),
            (_, failed) => failed,
        };
        if err <= 1.0 && err.is_finite() {
            // Accept: dense output coefficients from the unprojected step.
            let t1 = t + hs;
            self.dense.fill_state(&self.v, &self.st, hs);
            self.dense.fill_work(&mut self.v, &self.st, hs);
            self.stats.steps += 1;
            self.taken = Some(Taken { h: hs, t1, err });
            return Ok(Attempt::Accepted(Span {
                t0: t,
                t1,
                reach: t1 + 1e-12 * hs.abs(),
            }));
        }
        self.stats.rejected += 1;
        self.control.rejected(hs, err);
        if self.control.h < self.o.h_min {
            return Err(match failed {
                Some((e, _)) => e,
                None => DynamicsError::StepTooSmall {
                    time: t,
                    step: self.control.h,
                    reason: format!("error estimate {err:.3e}"),
                },
            });
        }
        Ok(Attempt::Rejected)
    }

    fn interpolate(&mut self, t: f64) -> &State {
        self.dense_at(t);
        to_state(&self.v.yt, t, &mut self.v.scratch);
        &self.v.scratch
    }

    /// The dense output at `t`, projected (when projection is on) but for the accepted state
    /// before any step; its iterations are the projection's and those of the accepted state's.
    fn output(&mut self, d: &mut Dynamics, t: f64) -> Result<Sample<'_>, DynamicsError> {
        let projects = self.taken.is_some() && self.o.stabilization.projects();
        self.interpolate(t);
        let mut it = 0;
        if projects {
            let v = &mut self.v;
            let tol = self.o.projection_tolerance;
            it = project(d, t, &mut v.yt, &mut v.scratch, tol, self.eom.refine)?;
            self.stats.newton_iterations += it;
            to_state(&v.yt, t, &mut v.scratch);
        }
        Ok(Sample {
            state: &self.v.scratch,
            work: &self.v.wt,
            iterations: it + self.proj_it,
        })
    }

    fn advance(&mut self, d: &mut Dynamics) -> Result<(), DynamicsError> {
        let step = self.taken.expect("an accepted step");
        self.t = step.t1;
        let v = &mut self.v;
        v.y0.copy_from_slice(&v.y1);
        v.w0.copy_from_slice(&v.w1);
        if self.o.stabilization.projects() {
            let tol = self.o.projection_tolerance;
            self.proj_it = project(d, self.t, &mut v.y0, &mut v.scratch, tol, self.eom.refine)?;
            self.stats.newton_iterations += self.proj_it;
        } else {
            // The projection accepts the couplers' turns and the springs' angles; without it
            // the step's end does.
            to_state(&v.y0, self.t, &mut v.scratch);
            d.sync(&v.scratch);
            d.accept_turns();
        }
        Ok(())
    }

    /// The accepted state becomes `state`; the next [`prepare`](Stepper::prepare) chooses a
    /// starting step again.
    fn restart(&mut self, _d: &mut Dynamics, state: &State) -> Result<(), DynamicsError> {
        from_state(state, &mut self.v.y0);
        self.t = state.t;
        self.taken = None;
        self.proj_it = 0;
        Ok(())
    }
}
