//! Inverse dynamics of a kinematically driven mechanism: [`Dynamics::inverse_dynamics`].

use crate::forces::Resolved;
use crate::kkt::SchurRefinement;
use crate::record::Recorder;
use crate::results::{DynamicResults, DynamicSink, IntegrationStats};
use crate::state::State;
use crate::system::Dynamics;
use crate::DynamicsError;
use cardan_mechanism::{AnalysisError, KinematicOptions, Outputs, Results, RunTotals};
use std::ops::ControlFlow;

impl Dynamics<'_> {
    /// Inverse dynamics: runs the kinematics (mechanism crate: assembly at t0, position,
    /// velocity, acceleration) over the grid of `options`, then at each time solves the
    /// augmented system at the kinematic state. For a fully driven mechanism v̇ is fixed by the
    /// constraints, so this is Φ_vᵀλ = h − M v̇ solved for λ with the redundant rows dropped
    /// (rank-aware). Driver efforts ([`crate::DriverEfforts`]: the torque of a rotation driver
    /// about its joint axis, the force of a translation driver) and joint reactions follow from
    /// λ. The stored accelerations are the ones of the augmented system (equal to the kinematic
    /// ones up to round-off).
    ///
    /// # Errors
    /// [`DynamicsError::NotFullyDriven`] unless DOF = drivers; kinematic errors
    /// ([`DynamicsError::Mechanism`]). When the kinematics stops mid-run (a singular
    /// configuration, a limit of the motion), [`DynamicsError::MidRun`] with the efforts and
    /// reactions of the frames solved before it.
    pub fn inverse_dynamics(
        &mut self,
        options: &KinematicOptions,
    ) -> Result<DynamicResults, DynamicsError> {
        self.inverse_dynamics_with_progress(options, |_, _| ControlFlow::Continue(()))
    }

    /// [`inverse_dynamics`](Self::inverse_dynamics), calling `progress(k, t_k)` after each
    /// time k of the grid is solved (kinematics, then efforts and reactions). When it returns
    /// [`ControlFlow::Break`], the run stops with [`DynamicsError::Stopped`] in
    /// [`DynamicsError::MidRun`], with the times done so far.
    ///
    /// # Errors
    /// As [`inverse_dynamics`](Self::inverse_dynamics); [`DynamicsError::Stopped`].
    pub fn inverse_dynamics_with_progress(
        &mut self,
        options: &KinematicOptions,
        mut progress: impl FnMut(usize, f64) -> ControlFlow<()>,
    ) -> Result<DynamicResults, DynamicsError> {
        let mut all: Option<DynamicResults> = None;
        let mut keep = |k: usize, frame: &DynamicResults| {
            all.get_or_insert_with(|| frame.empty_like(options.steps + 1))
                .extend_from(frame);
            progress(k, frame.times()[0])
        };
        let run = self.inverse_dynamics_into(options, &mut keep);
        let with_times = |totals: &DynamicResults, all: Option<DynamicResults>| {
            let mut r = all.unwrap_or_default();
            r.stats = totals.stats;
            r.redundant.clone_from(&totals.redundant);
            r.kinematics.set_totals(totals.kinematics.totals());
            r
        };
        match run {
            Ok(totals) => Ok(with_times(&totals, all)),
            Err(DynamicsError::MidRun {
                source,
                last_time,
                partial,
            }) => Err(DynamicsError::MidRun {
                source,
                last_time,
                partial: Box::new(with_times(&partial, all)),
            }),
            Err(e) => Err(e),
        }
    }

    /// [`inverse_dynamics`](Self::inverse_dynamics), streamed: one pass over the grid, each
    /// time's kinematics (mechanism crate, [`cardan_mechanism::Model::kinematics_into`]), then
    /// its efforts and reactions, handed to `sink` ([`DynamicSink`]) in storage reused from one
    /// time to the next, none kept. Returns the run's counters and dropped rows in a
    /// [`DynamicResults`] without times. When the sink breaks, the run stops with
    /// [`DynamicsError::Stopped`] in [`DynamicsError::MidRun`].
    ///
    /// # Errors
    /// As [`inverse_dynamics`](Self::inverse_dynamics); the partial results of
    /// [`DynamicsError::MidRun`] hold no time (they went to the sink).
    pub fn inverse_dynamics_into(
        &mut self,
        options: &KinematicOptions,
        sink: &mut dyn DynamicSink,
    ) -> Result<DynamicResults, DynamicsError> {
        let start = std::time::Instant::now();
        self.reset_friction_history();
        // A rotational spring follows its joint's angle over turns from the kinematics' own
        // continuation (output times may be turns apart).
        let springs = self.forces.iter().any(Resolved::is_rotational);
        let kopts = options.outputs(Outputs {
            velocity: true,
            acceleration: true,
            points: false,
            joints: springs,
        });
        let model = self.model;
        let mut ws = model.workspace();
        let mut pass = EffortPass::new(self, sink);
        pass.midpoint = first_midpoint(model, &kopts);
        let kin = model.kinematics_into(&mut ws, &kopts, &mut |_: usize, frame: &Results| {
            pass.frame(self, options.outputs, frame)
        });
        let stopped = pass.stopped;
        let failure = pass.failure.take();
        let last_time = pass.last_time();
        let frames = pass.frames();
        let finish = |pass: EffortPass, d: &mut Self, totals: RunTotals| {
            let mut r = pass.finish(d, start);
            r.kinematics.set_totals(totals);
            r
        };
        let mid_run = |source: DynamicsError, partial: DynamicResults| DynamicsError::MidRun {
            last_time: last_time.unwrap_or(f64::NAN),
            source: Box::new(source),
            partial: Box::new(partial),
        };
        if let Some(e) = failure {
            // The efforts failed: the error alone (the times before it went to the sink).
            return Err(e);
        }
        match kin {
            Ok(totals) if stopped => {
                let time = last_time.unwrap_or(f64::NAN);
                let r = finish(pass, self, totals);
                Err(mid_run(DynamicsError::Stopped { time }, r))
            }
            Ok(totals) => Ok(finish(pass, self, totals)),
            Err(AnalysisError::DriverCount { dof, drivers }) => {
                Err(DynamicsError::NotFullyDriven { dof, drivers })
            }
            Err(e) if frames == 0 => Err(e.into()),
            Err(e) => {
                let totals = e.partial_results().map(Results::totals).unwrap_or_default();
                let r = finish(pass, self, totals);
                Err(mid_run(e.into(), r))
            }
        }
    }
}

/// The state at the midpoint t₀ + h/2 of the first interval of the grid `options`, solved by a
/// kinematic run of one step from a fresh workspace (assembly at t₀, as the run's own), for
/// Simpson's rule on the first interval of the work ([`crate::work::SampledWork`]): with two
/// samples the first interval's quadrature is only third order locally, and it held the energy
/// balance of the bundled slider-crank at 1.6e-6 of its energy scale where every later time
/// closes to 1e-8. `None` for a run of no steps or a kinematic failure there.
fn first_midpoint(model: &cardan_mechanism::Model, options: &KinematicOptions) -> Option<State> {
    if options.steps == 0 {
        return None;
    }
    let h = options.time(1) - options.time(0);
    let half = KinematicOptions {
        t_end: options.t0 + 0.5 * h,
        steps: 1,
        ..*options
    };
    let r = model.run_kinematics(&half).ok()?;
    let mut s = State::initial(model, half.t_end);
    for (k, b) in r.bodies.iter().enumerate() {
        s.set_pose(k, *b.r.get(1)?, *b.p.get(1)?);
        s.set_velocity(k, *b.r_dot.get(1)?, *b.omega_local.get(1)?);
    }
    Some(s)
}

/// The efforts and reactions of an inverse dynamics run, time by time along its kinematics.
struct EffortPass<'s> {
    /// Where the times go, until the recorder takes it at the first time.
    sink: Option<&'s mut dyn DynamicSink>,
    /// Built at the first time (the augmented system is prepared at its state).
    rec: Option<Recorder<'s>>,
    /// The row reselections counted before the run.
    reselections: usize,
    /// The sink asked to stop.
    stopped: bool,
    /// A failure of the efforts.
    failure: Option<DynamicsError>,
    /// The state of the time being solved (storage reused).
    state: State,
    /// The state at the midpoint of the first interval, for the work's quadrature
    /// ([`crate::work::SampledWork`]); used at the first time.
    midpoint: Option<State>,
}

impl<'s> EffortPass<'s> {
    fn new(d: &Dynamics, sink: &'s mut dyn DynamicSink) -> Self {
        Self {
            sink: Some(sink),
            rec: None,
            reselections: d.reselections,
            stopped: false,
            failure: None,
            state: State::initial(d.model, 0.0),
            midpoint: None,
        }
    }

    /// The efforts at the kinematic `frame` (one time), handed to the sink; a break stops the
    /// kinematics.
    fn frame(&mut self, d: &mut Dynamics, outputs: Outputs, frame: &Results) -> ControlFlow<()> {
        let s = &mut self.state;
        s.t = frame.times[0];
        for (k, b) in frame.bodies.iter().enumerate() {
            s.set_pose(k, b.r[0], b.p[0]);
            s.set_velocity(k, b.r_dot[0], b.omega_local[0]);
        }
        let rec = match (self.rec.as_mut(), self.sink.take()) {
            (Some(rec), _) => rec,
            (None, Some(sink)) => {
                if let Err(e) = d.prepare(&self.state) {
                    self.failure = Some(e);
                    return ControlFlow::Break(());
                }
                self.reselections = d.reselections;
                let rec = self.rec.insert(Recorder::streamed(d, outputs, sink));
                // A failed solve there leaves the first interval to the trapezoid.
                if let Some(mid) = self.midpoint.take() {
                    let _ = rec.first_midpoint(d, &mid);
                }
                rec
            }
            (None, None) => return ControlFlow::Break(()),
        };
        // The frames are the accepted poses of the kinematics: the couplers' turns follow.
        d.sync(&self.state);
        d.accept_turns();
        if !frame.joints.is_empty() {
            for f in &mut d.forces {
                f.follow_angle(|j| frame.joints[j].values[0][0]);
            }
        }
        let iterations = frame.iterations.first().copied().unwrap_or(0);
        match rec.record(d, &self.state, iterations, None, SchurRefinement::ONE_SHOT) {
            Ok(()) => ControlFlow::Continue(()),
            Err(DynamicsError::Stopped { .. }) => {
                self.stopped = true;
                ControlFlow::Break(())
            }
            Err(e) => {
                self.failure = Some(e);
                ControlFlow::Break(())
            }
        }
    }

    fn frames(&self) -> usize {
        self.rec.as_ref().map_or(0, Recorder::len)
    }

    fn last_time(&self) -> Option<f64> {
        self.rec.as_ref().and_then(Recorder::last_time)
    }

    /// The run's counters in results without times.
    fn finish(self, d: &Dynamics, start: std::time::Instant) -> DynamicResults {
        let done = self.frames();
        let stats = IntegrationStats {
            steps: done,
            evaluations: done,
            row_reselections: d.reselections - self.reselections,
            wall_time: start.elapsed().as_secs_f64(),
            ..IntegrationStats::default()
        };
        match self.rec {
            Some(rec) => rec.finish(d, stats),
            None => DynamicResults {
                stats,
                ..DynamicResults::default()
            },
        }
    }
}
