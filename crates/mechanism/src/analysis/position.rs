//! Position analysis at one time: Φ(q, t) = 0 for a kinematically driven mechanism.
//!
//! [`Model::prepare_kinematics`] runs once, at an assembled configuration: it counts the degrees
//! of freedom, checks that the drivers use them up exactly, finds the redundant equations with a
//! rank analysis of the full Jacobian (joints then drivers) and builds a square Newton solver on
//! the independent rows ([`cardan_solver::Newton::with_row_selection`], [`cardan_solver::AutoSolver`]:
//! dense LU for small models, sparse LU for large). Convergence is still judged on all equations.
//! [`Model::position`] then solves
//!
//! ```text
//! Φ_v(x_k) [Δr; Δπ'] = −Φ(x_k, t),   r ← r + Δr,   p ← normalize(p ⊗ exp(Δπ'/2))
//! ```
//!
//! starting from the poses in the workspace.

use crate::dof::{solver, DofReport};
use crate::error::{AnalysisError, EquationName};
use crate::model::Model;
use crate::workspace::{PositionSystem, Workspace};
use cardan_solver::{
    AutoSolver, JacobianUpdate, Newton, NewtonOptions, RankAnalysis, RankOptions, SolverError,
};

/// Steps one factorization serves in the default kinematic Newton
/// ([`Model::kinematic_newton_options`]): with the Taylor predictor a frame usually converges in
/// three chord steps with the factors made at the previous frame's solution; when the steps left
/// are not expected to pass the step test, Newton refactors and finishes with a Newton step.
pub const KINEMATIC_MAX_CHORD_STEPS: usize = 4;

/// Models with at least this many unknowns try a sparse LU of the square Φ_v before the dense
/// rank analysis in [`Model::prepare_kinematics`] (below it the dense QR costs little and gives
/// the same answer).
pub const FAST_RANK_MIN_UNKNOWNS: usize = 300;

/// Outcome of one position solve.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PositionReport {
    /// Newton iterations.
    pub iterations: usize,
    /// Max |Φ_i| over all equations at the solution (unscaled).
    pub residual: f64,
}

impl Model {
    /// Checks the drivers against the degrees of freedom at the workspace's (assembled) poses
    /// and prepares the square kinematic solver (redundant rows dropped once). Allocates.
    ///
    /// # Errors
    /// [`AnalysisError::DriverCount`] when the number of drivers differs from the degrees of
    /// freedom; [`AnalysisError::DependentDrivers`] when drivers do not control the free motion.
    pub fn prepare_kinematics(&self, ws: &mut Workspace) -> Result<DofReport, AnalysisError> {
        self.prepare_kinematics_with(ws, Self::kinematic_newton_options())
    }

    /// The default Newton options of the kinematic solver: modified Newton (chord steps with
    /// the last factorization, kept from frame to frame, while the residual and the steps
    /// contract by 0.3 or better, at most [`KINEMATIC_MAX_CHORD_STEPS`] steps per
    /// factorization; see [`cardan_solver::JacobianUpdate::Modified`]), the solver's backtracking
    /// line search and default scaled tolerances (residual 1e-10, step 1e-6, the step test
    /// applied to the error a chord step leaves). No refactorization at the solution: velocity
    /// and acceleration refactor there only when the factors are not close enough for
    /// iterative refinement ([`cardan_solver::Newton::solve_linear_at`]).
    pub fn kinematic_newton_options() -> NewtonOptions {
        NewtonOptions {
            jacobian_update: JacobianUpdate::Modified {
                max_age: KINEMATIC_MAX_CHORD_STEPS,
                min_contraction: 0.3,
            },
            factor_at_solution: false,
            ..NewtonOptions::default()
        }
    }

    /// [`prepare_kinematics`](Self::prepare_kinematics) with Newton options of your choice.
    ///
    /// # Errors
    /// As [`prepare_kinematics`](Self::prepare_kinematics).
    pub fn prepare_kinematics_with(
        &self,
        ws: &mut Workspace,
        options: NewtonOptions,
    ) -> Result<DofReport, AnalysisError> {
        if let Some(report) = self.prepare_square_fast(ws, options) {
            return Ok(report);
        }
        let report = self.dof(ws)?;
        if report.dof != report.drivers {
            return Err(AnalysisError::DriverCount {
                dof: report.dof,
                drivers: report.drivers,
            });
        }
        let mut slots = vec![0.0; self.pattern.num_slots()];
        self.jacobian_into(&ws.bodies, ws.t, &mut slots);
        let ra = RankAnalysis::compute(&self.pattern, &slots, RankOptions::default())
            .map_err(|e| solver(ws.t, e))?;
        if ra.rank() < self.num_unknowns() {
            let dependent = ra
                .dependent_rows()
                .iter()
                .filter(|&&r| r >= self.joint_rows)
                .filter_map(|&r| self.equation(r))
                .collect();
            return Err(AnalysisError::DependentDrivers { dependent });
        }
        let selection = self
            .pattern
            .select_rows(ra.independent_rows())
            .map_err(|e| solver(ws.t, e))?;
        let newton =
            Newton::with_row_selection(&self.pattern, selection, AutoSolver::default(), options)
                .map_err(|e| solver(ws.t, e))?;
        ws.kin = Some(newton);
        ws.dof = Some(report.clone());
        ws.invalidate();
        Ok(report)
    }

    /// The fast path of [`prepare_kinematics_with`](Self::prepare_kinematics_with) for large
    /// models (at least [`FAST_RANK_MIN_UNKNOWNS`] unknowns): when Φ_v is square and the solver's
    /// LU factors it at the current poses with acceptable pivots, it has full rank, so no
    /// equation is redundant, the joint rows are independent (DOF = n − m_J) and every driver
    /// row is needed. That replaces the two dense rank-revealing QRs (O(n³) time, O(n²) memory:
    /// 9 minutes and 0.3 GB at 6,000 unknowns, impossible at 60,000) by one sparse LU. `None`
    /// (nothing changed) when the model is small, not square, or the LU fails: the caller then
    /// runs the full rank analysis, which names what is wrong.
    fn prepare_square_fast(&self, ws: &mut Workspace, options: NewtonOptions) -> Option<DofReport> {
        let (m, n, mj) = (self.num_equations(), self.num_unknowns(), self.joint_rows);
        if n < FAST_RANK_MIN_UNKNOWNS || m != n || n - mj != self.drivers.len() {
            return None;
        }
        let mut newton = Newton::new(&self.pattern, AutoSolver::default(), options).ok()?;
        let mut sys = PositionSystem {
            model: self,
            bodies: &mut ws.bodies,
            t: ws.t,
        };
        newton.factor_at(&mut sys, &ws.x).ok()?;
        let report = DofReport {
            dof: n - mj,
            moving_bodies: self.num_bodies(),
            joint_equations: mj,
            rank: mj,
            redundant: Vec::new(),
            drivers: self.drivers.len(),
        };
        ws.kin = Some(newton);
        ws.dof = Some(report.clone());
        ws.invalidate();
        Some(report)
    }

    /// Solves the position equations at time `t`, starting from the workspace's poses (prepares
    /// the kinematic solver first if needed). No allocation after preparation (on success).
    ///
    /// # Errors
    /// [`AnalysisError::Singular`] (dependent equations named), [`AnalysisError::NotConverged`]
    /// (worst equations named), and the errors of [`prepare_kinematics`](Self::prepare_kinematics).
    pub fn position(&self, ws: &mut Workspace, t: f64) -> Result<PositionReport, AnalysisError> {
        if ws.kin.is_none() {
            self.prepare_kinematics(ws)?;
        }
        ws.velocity_valid = false;
        ws.acceleration_valid = false;
        let newton = ws.kin.as_mut().expect("prepared above");
        let mut sys = PositionSystem {
            model: self,
            bodies: &mut ws.bodies,
            t,
        };
        let result = newton.solve(&mut sys, &mut ws.x);
        ws.t = t;
        ws.v.fill(0.0);
        ws.vdot.fill(0.0);
        ws.sync_poses();
        match result {
            Ok(rep) => {
                self.phi_into(&ws.bodies, t, &mut ws.phi);
                let residual = ws.phi.iter().fold(0.0f64, |a, v| a.max(v.abs()));
                Ok(PositionReport {
                    iterations: rep.iterations,
                    residual,
                })
            }
            Err(e) => Err(self.map_solver_error(t, e)),
        }
    }

    /// Turns a solver error into an analysis error naming the equations.
    pub(crate) fn map_solver_error(&self, time: f64, e: SolverError) -> AnalysisError {
        match e {
            SolverError::Singular {
                dependent_equations,
            } => AnalysisError::Singular {
                time,
                dependent: self.names(&dependent_equations),
                partial: None,
            },
            SolverError::NotConverged {
                iterations,
                worst_equations,
                ..
            } => AnalysisError::NotConverged {
                time,
                iterations,
                worst: worst_equations
                    .iter()
                    .filter_map(|&(r, v)| self.equation(r).map(|n| (n, v)))
                    .collect(),
                partial: None,
            },
            source => AnalysisError::Solver {
                time,
                source,
                partial: None,
            },
        }
    }

    fn names(&self, rows: &[usize]) -> Vec<EquationName> {
        rows.iter().filter_map(|&r| self.equation(r)).collect()
    }
}
