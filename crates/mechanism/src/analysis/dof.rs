//! The degrees-of-freedom count at a pose, [`Model::dof`]: the rank of the joint rows of Φ_v by
//! a rank-revealing QR (the sparse elimination for large models,
//! [`cardan_solver::RankAnalysis::compute_auto`]), DOF = 6 nb − rank, and the dependent rows
//! named as the redundant equations (theory: [`crate::dof`]).

use crate::dof::DofReport;
use crate::error::AnalysisError;
use crate::model::Model;
use crate::workspace::Workspace;
use cardan_solver::{RankAnalysis, SparsityPattern};

impl Model {
    /// Counts the degrees of freedom at the workspace's current poses (allocates; for setup).
    ///
    /// # Errors
    /// [`AnalysisError::Solver`] if the Jacobian is not finite.
    pub fn dof(&self, ws: &Workspace) -> Result<DofReport, AnalysisError> {
        let n = self.num_unknowns();
        let (rank, dependent) = self.joint_rank(ws)?;
        let redundant = dependent.iter().filter_map(|&r| self.equation(r)).collect();
        Ok(DofReport {
            dof: n - rank,
            moving_bodies: self.num_bodies(),
            joint_equations: self.joint_rows,
            rank,
            redundant,
            drivers: self.drivers.len() + self.paths.len(),
        })
    }

    /// The rank of the joint rows' Jacobian at the workspace's poses and the joint rows the rank
    /// analysis finds dependent (indices), the tolerance widened by the residual of a slightly
    /// inconsistent model at its least-squares pose (`analysis::dropped`). Allocates.
    ///
    /// # Errors
    /// A solver error of the rank analysis.
    pub(crate) fn joint_rank(&self, ws: &Workspace) -> Result<(usize, Vec<usize>), AnalysisError> {
        let mj = self.joint_rows;
        if mj == 0 {
            return Ok((0, Vec::new()));
        }
        let mut slots = vec![0.0; self.pattern.num_slots()];
        self.jacobian_into(&ws.pose.bodies, ws.pose.u(), ws.pose.t, &mut slots);
        let n = self.num_unknowns();
        // Joint rows come first and their entries are the first slots.
        let k = self.joints.last().map_or(0, |_| {
            self.pattern.entries().take_while(|&(r, _)| r < mj).count()
        });
        let entries: Vec<(usize, usize)> = self.pattern.entries().take(k).collect();
        let sub = SparsityPattern::new(mj, n, &entries).map_err(|e| solver(ws.pose.t, e))?;
        let mut phi = vec![0.0; self.num_equations()];
        self.phi_into(
            &ws.pose.bodies,
            ws.pose.u(),
            &ws.pose.turns,
            ws.pose.t,
            &mut phi,
        );
        let options = self.rank_options_for(&phi, mj);
        let ra = RankAnalysis::compute_auto(&sub, &slots[..k], options)
            .map_err(|e| solver(ws.pose.t, e))?;
        Ok((ra.rank(), ra.dependent_rows().to_vec()))
    }
}

pub(crate) fn solver(time: f64, source: cardan_solver::SolverError) -> AnalysisError {
    AnalysisError::Solver {
        time,
        source,
        partial: None,
    }
}
