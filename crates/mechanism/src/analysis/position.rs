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
//!
//! ### Redundant equations: re-selection
//! A mechanism with redundant equations (a planar loop of spatial revolutes, Bennett's or
//! Bricard's linkage) is solved on a square subset of its rows, picked by the rank analysis at the
//! assembled pose. The full set keeps its rank along the motion, but a subset can lose it at a
//! regular position (Bennett's linkage: the rows kept at the drawn pose are singular at two crank
//! angles). So the subset's LU runs with a tighter pivot tolerance,
//! [`SELECTION_PIVOT_TOLERANCE`] instead of 1e-12, and when the position solve on the subset fails
//! (singular or not converging), the rows are chosen again by a rank analysis of all rows at the
//! frame's start and the frame is solved again from there. The new subset is the best conditioned
//! one at that pose and is kept until it degrades in turn, so the choice does not chatter. Only
//! a failure of the full set is reported. The reactions of redundant joints are one admissible
//! split: at a re-selection the split changes (the multipliers of the dropped rows are 0).

use crate::analysis::dof::solver;
use crate::dof::DofReport;
use crate::equation::EquationName;
use crate::error::AnalysisError;
use crate::model::Model;
use crate::workspace::{PositionSystem, Workspace};
use cardan_constraints::BodyPair;
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

/// Pivot tolerance of the LU of a selection of rows (a mechanism with redundant equations):
/// an equilibrated pivot below it makes the solver re-select its rows (see the module docs)
/// before the subset's conditioning (about 1 / pivot) costs accuracy.
pub const SELECTION_PIVOT_TOLERANCE: f64 = 1e-8;

/// Outcome of one position solve.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PositionReport {
    /// Newton iterations.
    pub iterations: usize,
    /// Max |Φ_i| over all equations at the solution (unscaled).
    pub residual: f64,
    /// The solved row (not dropped as redundant) with the largest scaled residual |Φ_i| / e_i
    /// after the couplers' turns were accepted, when that exceeds the solve's tolerance: the
    /// solve converged on equations that no longer hold once the angles are continued (a
    /// coupler's angle taken a turn off because it changed by π or more since the last accepted
    /// pose). A caller must not accept such a pose ([`Model::kinematics`] subdivides the step).
    pub open: Option<OpenRow>,
}

/// A solved row that does not hold ([`PositionReport::open`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct OpenRow {
    /// The global row.
    pub row: usize,
    /// Its scaled residual |Φ_r| / e_r (at least 1 for a driver on a spurious root: its
    /// branch error).
    pub scaled_residual: f64,
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
        ws.reset_dropped_rows();
        if let Some(report) = self.prepare_square_fast(ws, options) {
            return Ok(report);
        }
        let report = self.dof(ws)?;
        self.select_rows(ws, report, options, None)
    }

    /// Checks the drivers against the DOF report, picks the independent rows at the workspace's
    /// poses and builds the square kinematic Newton on them. `kept_rows_only`: whether Newton
    /// judges the kept rows only ([`cardan_solver::Newton::judge_kept_rows_only`]); `None` at a
    /// solved pose decides it there (dropped rows already off: a slightly inconsistent model,
    /// `analysis::dropped`), and widens the rank tolerance by the pose's residual.
    fn select_rows(
        &self,
        ws: &mut Workspace,
        report: DofReport,
        options: NewtonOptions,
        kept_rows_only: Option<bool>,
    ) -> Result<DofReport, AnalysisError> {
        if report.dof != report.drivers {
            return Err(AnalysisError::DriverCount {
                dof: report.dof,
                drivers: report.drivers,
            });
        }
        let mut slots = vec![0.0; self.pattern.num_slots()];
        self.jacobian_into(&ws.pose.bodies, ws.pose.u(), ws.pose.t, &mut slots);
        self.phi_into(
            &ws.pose.bodies,
            ws.pose.u(),
            &ws.pose.turns,
            ws.pose.t,
            &mut ws.rows.phi,
        );
        let rank_options = match kept_rows_only {
            None => self.rank_options_for(&ws.rows.phi, self.num_equations()),
            Some(_) => RankOptions::default(),
        };
        let ra = RankAnalysis::compute_auto(&self.pattern, &slots, rank_options)
            .map_err(|e| solver(ws.pose.t, e))?;
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
            .map_err(|e| solver(ws.pose.t, e))?;
        let lu = if ra.independent_rows().len() < self.num_equations() {
            AutoSolver::default().with_pivot_tolerance(SELECTION_PIVOT_TOLERANCE)
        } else {
            AutoSolver::default()
        };
        let mut newton = Newton::with_row_selection(&self.pattern, selection, lu, options)
            .map_err(|e| solver(ws.pose.t, e))?;
        newton.fit_state(ws.pose.x.len());
        ws.set_kept_rows(ra.independent_rows());
        // Dropped rows already off at this (assembled or accepted) pose belong to a slightly
        // inconsistent model: they cannot vanish with the kept ones, so Newton judges the kept
        // rows and the dropped ones are recorded (`analysis::dropped`).
        newton.judge_kept_rows_only(kept_rows_only.unwrap_or_else(|| {
            self.dropped_residual(&ws.rows.phi, &ws.dropped.kept) > options.tolerances.residual
        }));
        ws.kin.newton = Some(newton);
        ws.kin.dof = Some(report.clone());
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
        if n < FAST_RANK_MIN_UNKNOWNS || m != n || n - mj != self.drivers.len() + self.paths.len() {
            return None;
        }
        let mut newton = Newton::new(&self.pattern, AutoSolver::default(), options).ok()?;
        let mut sys = PositionSystem {
            model: self,
            bodies: &mut ws.pose.bodies,
            turns: &ws.pose.turns,
            t: ws.pose.t,
        };
        newton.factor_at(&mut sys, &ws.pose.x).ok()?;
        let report = DofReport {
            dof: n - mj,
            moving_bodies: self.num_bodies(),
            joint_equations: mj,
            rank: mj,
            redundant: Vec::new(),
            drivers: self.drivers.len() + self.paths.len(),
        };
        ws.kin.newton = Some(newton);
        ws.kin.dof = Some(report.clone());
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
        if ws.kin.newton.is_none() {
            self.prepare_kinematics(ws)?;
        }
        ws.motion.velocity_valid = false;
        ws.motion.acceleration_valid = false;
        let selected = self.solves_a_selection(ws);
        if selected {
            ws.kin.x_start.copy_from_slice(&ws.pose.x);
        }
        let mut result = self.solve_positions(ws, t);
        if selected
            && matches!(
                result,
                Err(SolverError::Singular { .. } | SolverError::NotConverged { .. })
            )
        {
            // The kept rows may have lost rank where the full set has not: choose again at the
            // failed iterate (near the solution, where the kept rows are nearly dependent; the
            // frame's start if the iterate is not finite) and solve the frame again from its
            // start (allocates; rare).
            if !ws.pose.x.iter().all(|v| v.is_finite()) {
                ws.pose.x.copy_from_slice(&ws.kin.x_start);
            }
            ws.sync_poses();
            let newton = ws.kin.newton.as_ref().expect("prepared above");
            let (options, old) = (*newton.options(), newton.row_selection().cloned());
            let kept_rows_only = newton.judges_kept_rows_only();
            let report = ws.kin.dof.clone().expect("prepared with a DOF report");
            let t_prepared = ws.pose.t;
            ws.pose.t = t;
            self.select_rows(ws, report, options, Some(kept_rows_only))?;
            ws.pose.t = t_prepared;
            ws.pose.x.copy_from_slice(&ws.kin.x_start);
            ws.sync_poses();
            let new = ws.kin.newton.as_ref().and_then(|n| n.row_selection());
            if new.map(|s| s.rows()) != old.as_ref().map(|s| s.rows()) {
                ws.counters.reselections += 1;
                result = self.solve_positions(ws, t);
            }
        }
        ws.pose.t = t;
        ws.motion.v.fill(0.0);
        ws.motion.vdot.fill(0.0);
        ws.sync_poses();
        match result {
            Ok(rep) => {
                self.accept_turns(&ws.pose.bodies, &mut ws.pose.turns);
                self.phi_into(
                    &ws.pose.bodies,
                    ws.pose.u(),
                    &ws.pose.turns,
                    t,
                    &mut ws.rows.phi,
                );
                if selected {
                    self.record_dropped_rows(ws, t);
                }
                let residual = ws.rows.phi.iter().fold(0.0f64, |a, v| a.max(v.abs()));
                Ok(PositionReport {
                    iterations: rep.iterations,
                    residual,
                    open: self.open_row(ws, selected),
                })
            }
            Err(e) => Err(self.map_solver_error(t, e)),
        }
    }

    /// The solved row with the largest scaled residual |Φ_i| / e_i in `ws.rows.phi` (rows
    /// dropped as redundant skipped when `selected`), when it exceeds the kinematic solver's
    /// residual tolerance ([`PositionReport::open`]). No allocation.
    fn open_row(&self, ws: &Workspace, selected: bool) -> Option<OpenRow> {
        let tol = ws.kin.newton.as_ref()?.options().tolerances.residual;
        if let Some(open) = self.spurious_driver_row(ws) {
            return Some(open);
        }
        let mut worst: Option<OpenRow> = None;
        for (r, (phi, e)) in ws.rows.phi.iter().zip(&self.equation_scales).enumerate() {
            if selected && !ws.dropped.kept[r] {
                continue;
            }
            let d = (phi / e).abs();
            if (d > tol || d.is_nan()) && worst.is_none_or(|w| d > w.scaled_residual || d.is_nan())
            {
                worst = Some(OpenRow {
                    row: r,
                    scaled_residual: d,
                });
            }
        }
        worst
    }

    /// The first row of a driver whose equations hold on a spurious root at the workspace's
    /// poses and time ([`cardan_constraints::Driver::branch_error`]), with that error (≥ 1).
    /// No allocation.
    fn spurious_driver_row(&self, ws: &Workspace) -> Option<OpenRow> {
        self.drivers.iter().find_map(|d| {
            let (si, sj) = (ws.state_of(d.body_i), ws.state_of(d.body_j));
            let e = d.driver.branch_error(&BodyPair::new(&si, &sj), ws.pose.t);
            (e > 0.0).then_some(OpenRow {
                row: d.rows.start,
                scaled_residual: e,
            })
        })
    }

    /// Whether the prepared kinematic solver works on a selection of the rows (some dropped as
    /// redundant).
    fn solves_a_selection(&self, ws: &Workspace) -> bool {
        ws.kin
            .newton
            .as_ref()
            .and_then(|n| n.row_selection())
            .is_some_and(|s| s.rows().len() < self.num_equations())
    }

    /// One Newton solve of the prepared kinematic solver from the workspace's poses.
    fn solve_positions(
        &self,
        ws: &mut Workspace,
        t: f64,
    ) -> Result<cardan_solver::NewtonReport, SolverError> {
        let newton = ws.kin.newton.as_mut().expect("prepared above");
        let mut sys = PositionSystem {
            model: self,
            bodies: &mut ws.pose.bodies,
            turns: &ws.pose.turns,
            t,
        };
        newton.solve(&mut sys, &mut ws.pose.x)
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
