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
//!
//! This file holds the report, which the workspace keeps; the count itself is
//! [`Model::dof`](crate::Model::dof) (`analysis/dof.rs`).

use crate::equation::EquationName;

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
