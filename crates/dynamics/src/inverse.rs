//! Inverse dynamics of a kinematically driven mechanism: [`Dynamics::inverse_dynamics`].

use crate::record::Recorder;
use crate::results::{DynamicResults, IntegrationStats};
use crate::state::State;
use crate::system::Dynamics;
use crate::DynamicsError;
use cardan_mechanism::{AnalysisError, KinematicOptions, Outputs, Results};

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
        let start = std::time::Instant::now();
        let kopts = options.outputs(Outputs {
            velocity: true,
            acceleration: true,
            points: false,
            joints: false,
        });
        match self.model.run_kinematics(&kopts) {
            Ok(kin) => self.efforts_along(&kin, options.outputs, start),
            Err(AnalysisError::DriverCount { dof, drivers }) => {
                Err(DynamicsError::NotFullyDriven { dof, drivers })
            }
            Err(e) => {
                let partial = match e.partial_results() {
                    Some(kin) if !kin.times.is_empty() => {
                        self.efforts_along(kin, options.outputs, start)?
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
    fn efforts_along(
        &mut self,
        kin: &Results,
        outputs: Outputs,
        start: std::time::Instant,
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
        let mut rec = Recorder::new(self, kin.times.len(), outputs);
        for i in 0..kin.times.len() {
            let s = state_at(i);
            rec.record(self, &s, kin.iterations.get(i).copied().unwrap_or(0))?;
        }
        let stats = IntegrationStats {
            steps: kin.times.len(),
            evaluations: kin.times.len(),
            wall_time: start.elapsed().as_secs_f64(),
            ..IntegrationStats::default()
        };
        Ok(rec.finish(stats))
    }
}
