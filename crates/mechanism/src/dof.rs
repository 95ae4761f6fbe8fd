//! Degrees of freedom and redundant equations.
//!
//! At a configuration on (or near) the constraint manifold, the rank of the joint Jacobian Φ_v
//! (drivers excluded) is found with a rank-revealing QR ([`cardan_solver::RankAnalysis`], rows
//! unit-normalized, columns scaled, tolerance relative). Then
//!
//! ```text
//! DOF = 6 · nb − rank Φ_v
//! ```
//!
//! and the `m − rank` dependent rows are the redundant equations (the last of each dependent
//! group, since the analysis prefers the lowest-numbered row among comparable pivots), named by
//! joint and primitive. A planar four-bar made of four spatial revolutes has 20 equations of
//! rank 17 for 3 bodies (18 unknowns): DOF 1 with 3 redundant equations. The count is only
//! meaningful at an assembled configuration (a singular position reports a lower rank).

use crate::error::{AnalysisError, EquationName};
use crate::model::Model;
use crate::workspace::Workspace;
use cardan_solver::{RankAnalysis, SparsityPattern};

/// The result of a degrees-of-freedom analysis.
#[derive(Debug, Clone, PartialEq)]
pub struct DofReport {
    /// Degrees of freedom left by the joints: 6 nb − rank.
    pub dof: usize,
    /// Moving bodies nb.
    pub moving_bodies: usize,
    /// Joint equations m_J.
    pub joint_equations: usize,
    /// Rank of the joint Jacobian.
    pub rank: usize,
    /// Redundant joint equations (m_J − rank of them), named.
    pub redundant: Vec<EquationName>,
    /// Number of drivers in the model.
    pub drivers: usize,
}

impl std::fmt::Display for DofReport {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "{} moving bodies, {} joint equations of rank {}: {} degrees of freedom, {} drivers",
            self.moving_bodies, self.joint_equations, self.rank, self.dof, self.drivers
        )?;
        if !self.redundant.is_empty() {
            write!(f, "; redundant equations: ")?;
            for (k, e) in self.redundant.iter().enumerate() {
                if k > 0 {
                    write!(f, ", ")?;
                }
                write!(f, "{e}")?;
            }
        }
        Ok(())
    }
}

impl Model {
    /// Counts the degrees of freedom at the workspace's current poses (allocates; for setup).
    ///
    /// # Errors
    /// [`AnalysisError::Solver`] if the Jacobian is not finite.
    pub fn dof(&self, ws: &Workspace) -> Result<DofReport, AnalysisError> {
        let mut slots = vec![0.0; self.pattern.num_slots()];
        self.jacobian_into(&ws.bodies, ws.t, &mut slots);
        let mj = self.joint_rows;
        let n = self.num_unknowns();
        let (rank, redundant) = if mj == 0 {
            (0, Vec::new())
        } else {
            // Joint rows come first and their entries are the first slots.
            let k = self.joints.last().map_or(0, |_| {
                self.pattern.entries().take_while(|&(r, _)| r < mj).count()
            });
            let entries: Vec<(usize, usize)> = self.pattern.entries().take(k).collect();
            let sub = SparsityPattern::new(mj, n, &entries).map_err(|e| solver(ws.t, e))?;
            // A slightly inconsistent model assembled to its least-squares pose: the tolerance
            // widens with its residual (`analysis::dropped`).
            let mut phi = vec![0.0; self.num_equations()];
            self.phi_into(&ws.bodies, &ws.turns, ws.t, &mut phi);
            let options = self.rank_options_for(&phi, mj);
            let ra = RankAnalysis::compute_auto(&sub, &slots[..k], options)
                .map_err(|e| solver(ws.t, e))?;
            let red = ra
                .dependent_rows()
                .iter()
                .filter_map(|&r| self.equation(r))
                .collect();
            (ra.rank(), red)
        };
        Ok(DofReport {
            dof: n - rank,
            moving_bodies: self.num_bodies(),
            joint_equations: mj,
            rank,
            redundant,
            drivers: self.drivers.len(),
        })
    }
}

pub(crate) fn solver(time: f64, source: cardan_solver::SolverError) -> AnalysisError {
    AnalysisError::Solver {
        time,
        source,
        partial: None,
    }
}
