//! Acceleration analysis: Φ_v v̇ = γ#_v with v̇ = [r̈; ω̇'] per body.
//!
//! γ#_v (the 6-coordinate form, from ω') collects every term of Φ̈ that is not Φ_v v̇; it needs
//! the velocities, so it runs after [`Model::velocity`] and reuses the same factorization.

use crate::error::AnalysisError;
use crate::model::Model;
use crate::workspace::Workspace;

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
        newton
            .solve_linear(&ws.rhs, &mut ws.vdot)
            .map_err(|e| self.map_solver_error(t, e))?;
        ws.acceleration_valid = true;
        Ok(())
    }
}
