//! Velocity analysis: Φ_v v = ν with v = [ṙ; ω'] per body, ν = −Φ_t (nonzero only for drivers).
//!
//! The matrix is the kinematic solver's factorization: when the position iteration ended with a
//! tiny step after a refactorization, those factors with iterative refinement against the exact
//! Φ_v at the solution ([`cardan_solver::Newton::solve_linear_at`]); otherwise Φ_v is factored at
//! the solution first (and the acceleration reuses it).

use crate::error::AnalysisError;
use crate::model::Model;
use crate::workspace::{PositionSystem, Workspace};

impl Model {
    /// Solves for the velocities at the workspace's poses and time (after [`Model::position`]).
    /// Evaluates ν only. No allocation.
    ///
    /// # Errors
    /// [`AnalysisError::Singular`] if the Jacobian must be refactored and is singular.
    pub fn velocity(&self, ws: &mut Workspace) -> Result<(), AnalysisError> {
        if ws.kin.newton.is_none() {
            self.prepare_kinematics(ws)?;
        }
        let t = ws.pose.t;
        let newton = ws.kin.newton.as_mut().expect("prepared above");
        self.nu_into(&ws.pose.bodies, ws.pose.u(), t, &mut ws.rows.rhs);
        ws.counters.evaluations.nu += 1;
        let mut sys = PositionSystem {
            model: self,
            bodies: &mut ws.pose.bodies,
            turns: &ws.pose.turns,
            t,
        };
        newton
            .solve_linear_at(&mut sys, &ws.pose.x, &ws.rows.rhs, &mut ws.motion.v)
            .map_err(|e| self.map_solver_error(t, e))?;
        ws.sync_poses();
        ws.motion.velocity_valid = true;
        ws.motion.acceleration_valid = false;
        Ok(())
    }
}
