//! The options of [`Newton`](super::Newton) and the report of a converged solve.

use crate::convergence::Tolerances;

/// When the Jacobian is re-evaluated and refactored.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum JacobianUpdate {
    /// Full Newton: every iteration.
    EveryIteration,
    /// Modified Newton: keep the factorization while `‖Φ_{k+1}‖ ≤ min_contraction · ‖Φ_k‖`, the
    /// steps made with it shrink by at least `min_contraction` (`‖Δ_{k+1}‖ ≤ min_contraction ·
    /// ‖Δ_k‖`) and it has been used for fewer than `max_age` iterations.
    Modified {
        /// Iterations a factorization may serve in one [`Newton::solve`](super::Newton::solve)
        /// (it may serve the next solve again, subject to the contraction checks).
        max_age: usize,
        /// Required contraction of the scaled residual per iteration (for example 0.25).
        min_contraction: f64,
    },
}

/// Step-length control.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum LineSearch {
    /// Always the full step.
    None,
    /// Backtracking (halving) with the Armijo condition `f(α) ≤ (1 − 2 c α) f(0)`.
    Backtracking {
        /// Maximum halvings per iteration.
        max_halvings: usize,
        /// Armijo constant `c` (for example `1e-4`).
        sufficient_decrease: f64,
    },
}

/// Options of [`Newton`](super::Newton).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct NewtonOptions {
    /// Scaled convergence tolerances.
    pub tolerances: Tolerances,
    /// Iteration cap. Default 25.
    pub max_iterations: usize,
    /// Full or modified Newton. Default full.
    pub jacobian_update: JacobianUpdate,
    /// Line search. Default backtracking, 10 halvings, `c = 1e-4`.
    pub line_search: LineSearch,
    /// Optional cap on the scaled step `max_j |Δq_j| / u_j` (damping for rough starts): longer
    /// steps are shortened to this length before the line search. Default none.
    pub max_step: Option<f64>,
    /// Refactor at the converged point so [`Newton::solve_linear`](super::Newton::solve_linear)
    /// (velocity, acceleration) uses `Φ_q(q)` exactly. Default true.
    pub factor_at_solution: bool,
    /// Number of worst equations listed in
    /// [`SolverError::NotConverged`](crate::SolverError::NotConverged). Default 5.
    pub report_worst: usize,
    /// Hand the linear solver the scaled system `(E⁻¹ Φ_q U) (U⁻¹ Δq) = −E⁻¹ Φ` (equation scales
    /// `E`, unknown scales `U` from the [`NonlinearSystem`](super::NonlinearSystem)) instead of
    /// the raw one. Default true: pivoting, rank decisions and least-squares weights then see
    /// unit-free numbers, so a model in millimetres and the same model in kilometres take the
    /// same steps. (For a square nonsingular system the step is the same either way, up to
    /// rounding.)
    pub scale_linear_system: bool,
}

impl Default for NewtonOptions {
    fn default() -> Self {
        Self {
            tolerances: Tolerances::default(),
            max_iterations: 25,
            jacobian_update: JacobianUpdate::EveryIteration,
            line_search: LineSearch::Backtracking {
                max_halvings: 10,
                sufficient_decrease: 1e-4,
            },
            max_step: None,
            factor_at_solution: true,
            report_worst: 5,
            scale_linear_system: true,
        }
    }
}

/// Outcome of a converged [`Newton::solve`](super::Newton::solve).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct NewtonReport {
    /// Newton iterations (steps taken or attempted).
    pub iterations: usize,
    /// Final scaled residual `max_i |Φ_i| / e_i`.
    pub residual_norm: f64,
    /// Scaled length of the last step (0 if none was taken).
    pub step_norm: f64,
    /// Jacobian evaluations + factorizations performed (including the one at the solution).
    pub refactorizations: usize,
    /// Residual evaluations (including line-search trials).
    pub residual_evaluations: usize,
    /// Steps shortened by the line search or the step cap.
    pub damped_steps: usize,
    /// Rank of the last factorization, when the solver reveals it.
    pub rank: Option<usize>,
    /// Redundant equations: rows dropped by the row selection plus rows the rank-revealing solver
    /// found dependent in the last factorization.
    pub redundant_equations: usize,
}

impl NewtonReport {
    /// The report before the first iteration.
    pub(super) fn empty() -> Self {
        Self {
            iterations: 0,
            residual_norm: f64::NAN,
            step_norm: 0.0,
            refactorizations: 0,
            residual_evaluations: 0,
            damped_steps: 0,
            rank: None,
            redundant_equations: 0,
        }
    }
}
