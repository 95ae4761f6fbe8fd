//! Acceleration analysis: Φ_v v̇ = γ#_v with v̇ = [r̈; ω̇'] per body.
//!
//! γ#_v (the 6-coordinate form, from ω') collects every term of Φ̈ that is not Φ_v v̇; it needs
//! the velocities, so it runs after [`Model::velocity`] and reuses the same factorization (and,
//! when the velocity was refined, the same exact Φ_v for the refinement).

use crate::error::AnalysisError;
use crate::model::Model;
use crate::workspace::{PositionSystem, Workspace};

impl Model {
    /// Solves for the accelerations at the workspace's poses, velocities and time (computes the
    /// velocities first if they are not current). No allocation.
    ///
    /// # Errors
    /// As [`Model::velocity`].
    pub fn acceleration(&self, ws: &mut Workspace) -> Result<(), AnalysisError> {
        if !ws.motion.velocity_valid {
            self.velocity(ws)?;
        }
        let t = ws.pose.t;
        self.gamma_into(
            &ws.pose.bodies,
            (ws.pose.u(), self.extra_rates_of(&ws.motion.v)),
            t,
            &mut ws.rows.rhs,
        );
        ws.counters.evaluations.gamma += 1;
        let newton = ws.kin.newton.as_mut().expect("prepared by velocity");
        let mut sys = PositionSystem {
            model: self,
            bodies: &mut ws.pose.bodies,
            turns: &ws.pose.turns,
            t,
        };
        let solved =
            newton.solve_linear_at(&mut sys, &ws.pose.x, &ws.rows.rhs, &mut ws.motion.vdot);
        // An evaluation of Φ_v resets the bodies' velocities: restore them.
        ws.sync_poses();
        solved.map_err(|e| self.map_solver_error(t, e))?;
        ws.motion.acceleration_valid = true;
        std::mem::swap(&mut ws.jerk.vdot_last, &mut ws.jerk.vdot_prev);
        ws.jerk.vdot_last.copy_from_slice(&ws.motion.vdot);
        std::mem::swap(&mut ws.jerk.edge_acc_last, &mut ws.jerk.edge_acc_prev);
        crate::analysis::predictor::relative_accelerations(
            self,
            &ws.pose.bodies,
            &ws.motion.v,
            &ws.motion.vdot,
            &mut ws.jerk.edge_acc_last,
        );
        ws.jerk.vdot_prev_time = ws.jerk.vdot_last_time;
        ws.jerk.vdot_last_time = t;
        Ok(())
    }
}
