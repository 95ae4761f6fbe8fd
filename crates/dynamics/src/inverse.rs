//! Inverse dynamics of a kinematically driven mechanism: [`Dynamics::inverse_dynamics`].

use crate::record::Recorder;
use crate::results::{DynamicResults, IntegrationStats};
use crate::state::State;
use crate::system::Dynamics;
use crate::DynamicsError;
use cardan_mechanism::{AnalysisError, KinematicOptions, Outputs, Results};
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

    /// [`inverse_dynamics`](Self::inverse_dynamics), calling `progress(done, t)` after each
    /// frame of its two passes: the kinematics (done = 0..=steps), then the efforts (done =
    /// steps + 1 ..= 2 steps + 1). When it returns [`ControlFlow::Break`], the run stops with
    /// [`DynamicsError::Stopped`] in [`DynamicsError::MidRun`], with the efforts of the frames
    /// done so far.
    ///
    /// # Errors
    /// As [`inverse_dynamics`](Self::inverse_dynamics); [`DynamicsError::Stopped`].
    pub fn inverse_dynamics_with_progress(
        &mut self,
        options: &KinematicOptions,
        mut progress: impl FnMut(usize, f64) -> ControlFlow<()>,
    ) -> Result<DynamicResults, DynamicsError> {
        let start = std::time::Instant::now();
        let kopts = options.outputs(Outputs {
            velocity: true,
            acceleration: true,
            points: false,
            joints: false,
        });
        let mut stopped = false;
        let mut ws = self.model.workspace();
        let kin = self.model.kinematics_with_control(&mut ws, &kopts, |k, t| {
            let flow = progress(k, t);
            stopped = flow.is_break();
            flow
        });
        let offset = options.steps + 1;
        match kin {
            Ok(kin) => {
                let r = self.efforts_along(&kin, options.outputs, start, &mut |i, t| {
                    let flow = progress(offset + i, t);
                    stopped |= flow.is_break();
                    flow
                })?;
                if stopped {
                    return Err(DynamicsError::MidRun {
                        last_time: r.times().last().copied().unwrap_or(f64::NAN),
                        source: Box::new(DynamicsError::Stopped {
                            time: r.times().last().copied().unwrap_or(f64::NAN),
                        }),
                        partial: Box::new(r),
                    });
                }
                Ok(r)
            }
            Err(AnalysisError::DriverCount { dof, drivers }) => {
                Err(DynamicsError::NotFullyDriven { dof, drivers })
            }
            Err(e) => {
                let partial = match e.partial_results() {
                    Some(kin) if !kin.times.is_empty() => {
                        self.efforts_along(kin, options.outputs, start, &mut |i, t| {
                            progress(offset + i, t)
                        })?
                    }
                    _ => return Err(e.into()),
                };
                Err(DynamicsError::MidRun {
                    last_time: partial.times().last().copied().unwrap_or(f64::NAN),
                    source: Box::new(e.into()),
                    partial: Box::new(partial),
                })
            }
        }
    }

    /// Driver efforts and reactions at every frame of the kinematic results `kin`.
    /// `progress(i, t_i)` after each frame; a break keeps the frames done.
    fn efforts_along(
        &mut self,
        kin: &Results,
        outputs: Outputs,
        start: std::time::Instant,
        progress: &mut dyn FnMut(usize, f64) -> ControlFlow<()>,
    ) -> Result<DynamicResults, DynamicsError> {
        let model = self.model;
        let nb = model.num_bodies();
        let state_at = |i: usize| {
            let mut s = State::initial(model, kin.times[i]);
            for k in 0..nb {
                let b = &kin.bodies[k];
                s.set_pose(k, b.r[i], b.p[i]);
                s.set_velocity(k, b.r_dot[i], b.omega_local[i]);
            }
            s
        };
        if kin.times.is_empty() {
            return Ok(DynamicResults::default());
        }
        let s0 = state_at(0);
        self.prepare(&s0)?;
        let reselections = self.reselections;
        let mut rec = Recorder::new(self, kin.times.len(), outputs);
        let mut done = 0;
        for i in 0..kin.times.len() {
            let s = state_at(i);
            // The frames are the accepted poses of the kinematics: the couplers' turns follow.
            self.sync(&s);
            self.accept_turns();
            rec.record(self, &s, kin.iterations.get(i).copied().unwrap_or(0), None)?;
            done += 1;
            if progress(i, kin.times[i]).is_break() {
                break;
            }
        }
        let stats = IntegrationStats {
            steps: done,
            evaluations: done,
            row_reselections: self.reselections - reselections,
            wall_time: start.elapsed().as_secs_f64(),
            ..IntegrationStats::default()
        };
        let mut r = rec.finish(self, stats);
        // What the kinematic pass counted and found.
        r.kinematics.subdivided_steps = kin.subdivided_steps;
        r.kinematics.row_reselections = kin.row_reselections;
        r.kinematics.dropped_rows = kin.dropped_rows.clone();
        Ok(r)
    }
}
