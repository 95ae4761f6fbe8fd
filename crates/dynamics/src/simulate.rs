//! Forward dynamics over time: [`Dynamics::simulate`], and streamed to a [`DynamicSink`]
//! ([`Dynamics::simulate_into`]) so that memory does not grow with the output times.

use crate::integrators::dopri5::Dopri5;
use crate::integrators::driver::integrate;
use crate::integrators::generalized_alpha::GeneralizedAlpha;
use crate::options::{Integrator, SimulationOptions};
use crate::record::Recorder;
use crate::results::{DynamicResults, DynamicSink, IntegrationStats};
use crate::state::State;
use crate::system::Dynamics;
use crate::DynamicsError;
use std::ops::ControlFlow;

impl Dynamics<'_> {
    /// Forward dynamics from a rough initial guess: the guess is made consistent
    /// ([`Dynamics::consistent_state`]), then integrated from `initial.t` to `options.t_end`
    /// with the chosen [`Integrator`]; results are stored at the requested output times.
    ///
    /// # Errors
    /// Inconsistent initial conditions, options, singular configurations, step-size failures.
    /// A failure after the first stored output is wrapped in [`DynamicsError::MidRun`], which
    /// keeps the results so far ([`DynamicsError::partial_results`]).
    pub fn simulate(
        &mut self,
        initial: &State,
        options: &SimulationOptions,
    ) -> Result<DynamicResults, DynamicsError> {
        let state = self.consistent_state(initial)?;
        self.simulate_consistent(state, options)
    }

    /// [`simulate`](Self::simulate) from a state that is already consistent (no assembly; the
    /// layout is prepared at `state` if needed).
    ///
    /// # Errors
    /// As [`simulate`](Self::simulate).
    pub fn simulate_consistent(
        &mut self,
        state: State,
        options: &SimulationOptions,
    ) -> Result<DynamicResults, DynamicsError> {
        self.simulate_consistent_with_progress(state, options, |_| ControlFlow::Continue(()))
    }

    /// [`simulate`](Self::simulate), calling `progress(t)` before each integration step with
    /// the time reached (e.g. to drive a progress bar). When it returns
    /// [`ControlFlow::Break`], the run stops there with [`DynamicsError::Stopped`] wrapped in
    /// [`DynamicsError::MidRun`], which keeps the results stored so far. The callback is the
    /// only cost (no allocation).
    ///
    /// # Errors
    /// As [`simulate`](Self::simulate); [`DynamicsError::Stopped`] when asked to stop.
    pub fn simulate_with_progress(
        &mut self,
        initial: &State,
        options: &SimulationOptions,
        progress: impl FnMut(f64) -> ControlFlow<()>,
    ) -> Result<DynamicResults, DynamicsError> {
        let state = self.consistent_state(initial)?;
        self.simulate_consistent_with_progress(state, options, progress)
    }

    /// [`simulate_consistent`](Self::simulate_consistent) with the progress callback of
    /// [`simulate_with_progress`](Self::simulate_with_progress).
    ///
    /// # Errors
    /// As [`simulate_with_progress`](Self::simulate_with_progress).
    pub fn simulate_consistent_with_progress(
        &mut self,
        state: State,
        options: &SimulationOptions,
        mut progress: impl FnMut(f64) -> ControlFlow<()>,
    ) -> Result<DynamicResults, DynamicsError> {
        self.run(state, options, None, &mut progress)
    }

    /// [`simulate_with_progress`](Self::simulate_with_progress), streamed: each output time
    /// goes to `sink` as it is recorded ([`DynamicSink`]), in storage reused from one time to
    /// the next, and none is kept. Returns the run's counters, redundant equations and dropped
    /// rows in a [`DynamicResults`] without times. When the sink breaks, the run stops there
    /// with [`DynamicsError::Stopped`] (in [`DynamicsError::MidRun`], as a break of `progress`).
    ///
    /// # Errors
    /// As [`simulate_with_progress`](Self::simulate_with_progress); the partial results of
    /// [`DynamicsError::MidRun`] hold no time either (they went to the sink).
    pub fn simulate_into(
        &mut self,
        initial: &State,
        options: &SimulationOptions,
        sink: &mut dyn DynamicSink,
        mut progress: impl FnMut(f64) -> ControlFlow<()>,
    ) -> Result<DynamicResults, DynamicsError> {
        let state = self.consistent_state(initial)?;
        self.run(state, options, Some(sink), &mut progress)
    }

    /// [`simulate_into`](Self::simulate_into) from a state that is already consistent.
    ///
    /// # Errors
    /// As [`simulate_into`](Self::simulate_into).
    pub fn simulate_consistent_into(
        &mut self,
        state: State,
        options: &SimulationOptions,
        sink: &mut dyn DynamicSink,
        mut progress: impl FnMut(f64) -> ControlFlow<()>,
    ) -> Result<DynamicResults, DynamicsError> {
        self.run(state, options, Some(sink), &mut progress)
    }

    /// The integration (the chosen stepper in the driver loop, [`crate::integrators`]), the
    /// times kept (`sink` `None`) or streamed.
    fn run(
        &mut self,
        state: State,
        options: &SimulationOptions,
        sink: Option<&mut dyn DynamicSink>,
        progress: &mut dyn FnMut(f64) -> ControlFlow<()>,
    ) -> Result<DynamicResults, DynamicsError> {
        let times = options.times(state.t);
        check_times(state.t, options.t_end, &times)?;
        options
            .integrator
            .validate()
            .map_err(|e| DynamicsError::Options(e.to_string()))?;
        if self.kkt.is_none() {
            self.prepare(&state)?;
        }
        self.start_stops(&state)?;
        self.start_contacts(&state)?;
        self.reset_friction_history();
        let mut rec = match sink {
            Some(sink) => Recorder::streamed(self, options.outputs, sink),
            None => Recorder::new(self, times.len(), options.outputs),
        };
        // The joint angles continue from the start's principal values (the first output's).
        self.joint_angles.start(options.outputs.joints);
        self.sync(&state);
        self.joint_angles.accept(self.model, &self.bodies);
        let mut stats = IntegrationStats::default();
        let f0 = self.kkt.as_ref().map_or(0, |k| k.factorizations);
        let reselections = self.reselections;
        let start = std::time::Instant::now();
        let r = match &options.integrator {
            Integrator::Dopri5(o) => integrate::<Dopri5>(
                self, state, o, options, &times, &mut rec, &mut stats, progress,
            ),
            Integrator::GeneralizedAlpha(o) => integrate::<GeneralizedAlpha>(
                self, state, o, options, &times, &mut rec, &mut stats, progress,
            ),
        };
        self.joint_angles.start(false);
        stats.factorizations = self.kkt.as_ref().map_or(0, |k| k.factorizations) - f0;
        stats.row_reselections = self.reselections - reselections;
        stats.wall_time = start.elapsed().as_secs_f64();
        match r {
            Ok(()) => Ok(rec.finish(self, stats)),
            Err(e) if rec.len() > 0 => {
                let last_time = rec.last_time().unwrap_or(f64::NAN);
                let partial = rec.finish(self, stats);
                Err(DynamicsError::MidRun {
                    last_time,
                    source: Box::new(e),
                    partial: Box::new(partial),
                })
            }
            Err(e) => Err(e),
        }
    }
}

fn check_times(t0: f64, t_end: f64, times: &[f64]) -> Result<(), DynamicsError> {
    if !(t0.is_finite() && t_end.is_finite()) || t_end < t0 {
        return Err(DynamicsError::Options(format!(
            "need finite t0 ≤ t_end (t0 = {t0}, t_end = {t_end})"
        )));
    }
    let mut prev = t0;
    for &t in times {
        if !(t.is_finite() && t >= prev && t <= t_end + 1e-12 * (1.0 + t_end.abs())) {
            return Err(DynamicsError::Options(format!(
                "output times must be increasing within [{t0}, {t_end}] (got {t})"
            )));
        }
        prev = t;
    }
    Ok(())
}

impl Dynamics<'_> {
    /// Refuses a start where two shapes overlap deeply ([`crate::collision::DEEP_PENETRATION`]).
    ///
    /// # Errors
    /// [`crate::DynamicsError::ShapesOverlap`] naming the deepest pair.
    pub(crate) fn start_contacts(
        &mut self,
        state: &crate::state::State,
    ) -> Result<(), crate::DynamicsError> {
        if self.collisions.is_none() {
            return Ok(());
        }
        self.sync(state);
        self.eval_forces(state.t);
        let model = self.model;
        let shapes = model.shapes();
        let c = self.collisions.as_ref().expect("collisions");
        let worst = (c.points.iter())
            .map(|p| (crate::collision::depth_ratio(model, p), p))
            .filter(|(r, _)| r.is_finite())
            .max_by(|x, y| x.0.total_cmp(&y.0));
        match worst {
            Some((ratio, p)) if ratio > crate::collision::DEEP_PENETRATION => {
                Err(crate::DynamicsError::ShapesOverlap {
                    shape_1: shapes[p.shapes[0]].name.clone(),
                    shape_2: shapes[p.shapes[1]].name.clone(),
                    depth: p.penetration,
                    time: state.t,
                    percent: 100.0 * ratio,
                })
            }
            _ => Ok(()),
        }
    }
}
