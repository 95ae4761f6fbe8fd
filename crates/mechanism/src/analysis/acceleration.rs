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
        if !ws.velocity_valid {
            self.velocity(ws)?;
        }
        let t = ws.t;
        self.gamma_into(&ws.bodies, t, &mut ws.rhs);
        ws.counts.gamma += 1;
        let newton = ws.kin.as_mut().expect("prepared by velocity");
        let mut sys = PositionSystem {
            model: self,
            bodies: &mut ws.bodies,
            turns: &ws.turns,
            t,
        };
        let solved = newton.solve_linear_at(&mut sys, &ws.x, &ws.rhs, &mut ws.vdot);
        // An evaluation of Φ_v resets the bodies' velocities: restore them.
        ws.sync_poses();
        solved.map_err(|e| self.map_solver_error(t, e))?;
        ws.acceleration_valid = true;
        std::mem::swap(&mut ws.vdot_last, &mut ws.vdot_prev);
        ws.vdot_last.copy_from_slice(&ws.vdot);
        std::mem::swap(&mut ws.edge_acc_last, &mut ws.edge_acc_prev);
        crate::analysis::predictor::relative_accelerations(
            self,
            &ws.bodies,
            &ws.v,
            &ws.vdot,
            &mut ws.edge_acc_last,
        );
        ws.vdot_prev_time = ws.vdot_last_time;
        ws.vdot_last_time = t;
        Ok(())
    }
}
