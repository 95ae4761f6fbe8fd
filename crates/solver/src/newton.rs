//! Newton-Raphson for `Φ(q) = 0`, and the velocity/acceleration solves that reuse its
//! factorization.
//!
//! ```text
//!   Φ_q(q_k) Δq_k = −Φ(q_k),     q_{k+1} = q_k ⊕ α_k Δq_k
//! ```
//!
//! (Haug, *Computer Aided Kinematics and Dynamics of Mechanical Systems*, §4.4; Nikravesh,
//! *Computer-Aided Analysis of Mechanical Systems*, §4.5.) `⊕` is
//! [`NonlinearSystem::apply_step`]: plain addition for the 7-coordinate form, a rotation update for
//! the 6-coordinate form. `α_k` is 1 unless the line search shortens the step.
//!
//! * **Full Newton** refactors `Φ_q` every iteration.
//! * **Modified Newton** (chord iteration) keeps the factorization while the scaled residual and
//!   the step both contract by at least `min_contraction` per iteration and it has served fewer
//!   than `max_age` iterations of this solve; a slow or failed step triggers a refactorization at
//!   the current point. The factorization also survives from one [`Newton::solve`] to the next
//!   (time stepping), subject to the same checks.
//! * **Convergence**: the scaled residual test, and the step test on the error the last step
//!   leaves. A Newton step (factorization made at the point the step starts from) converges
//!   quadratically, so a step `‖Δ‖ ≤ τ_step` leaves an error of about `τ_step²`. A chord step
//!   (older factorization) converges linearly with rate `θ`, estimated as the ratio of the last two
//!   steps made with the same factorization (`min_contraction` for the first one), and leaves
//!   about `θ/(1 − θ) ‖Δ‖`: it passes when that is `≤ τ_step²`. Both kinds thus promise the same
//!   accuracy (see [`convergence`](crate::convergence)).
//! * **Line search**: backtracking on `f = Σ (Φ_i / e_i)²` with the Armijo condition
//!   `f(α) ≤ (1 − 2 c α) f(0)`, halving `α`; plus an optional cap on the scaled step length.
//!   Together they let assembly start from a rough guess.
//!
//! Velocity `Φ_q q̇ = ν` and acceleration `Φ_q q̈ = γ#` share the matrix of the last position
//! iteration only if it was evaluated at the converged `q`: with
//! [`NewtonOptions::factor_at_solution`] (default) Newton refactors there once before returning,
//! and [`Newton::solve_linear`] then solves both with that one factorization.

use crate::convergence::{
    reciprocal_in_place, weighted_inf_norm, weighted_sum_squares, worst_entries, Tolerances,
};
use crate::error::{NonFiniteLocation, SolverError};
use crate::linear::{AutoSolver, LinearSolver};
use crate::pattern::{check_len, RowSelection, SparsityPattern};

/// The system a caller hands to [`Newton`]: `m` equations in `n` step unknowns, with the Jacobian
/// on a fixed [`SparsityPattern`].
///
/// The state `x` (length [`state_len`](Self::state_len)) may be longer than the step (length
/// `n`): in the 6-coordinate form the state stores `[r; p]` (7 per body) while the step is
/// `[Δr; Δπ']` (6 per body) and [`apply_step`](Self::apply_step) rotates `p`.
///
/// ```
/// use cardan_solver::{NonlinearSystem, Newton, NewtonOptions, SparsityPattern, AutoSolver};
/// /// x² = 2, x·y = 1
/// struct Sys;
/// impl NonlinearSystem for Sys {
///     fn num_equations(&self) -> usize { 2 }
///     fn num_unknowns(&self) -> usize { 2 }
///     fn residual(&mut self, x: &[f64], out: &mut [f64]) {
///         out[0] = x[0] * x[0] - 2.0;
///         out[1] = x[0] * x[1] - 1.0;
///     }
///     // slots: (0,0), (1,0), (1,1)
///     fn jacobian(&mut self, x: &[f64], slots: &mut [f64]) {
///         slots[0] = 2.0 * x[0];
///         slots[1] = x[1];
///         slots[2] = x[0];
///     }
/// }
/// let pattern = SparsityPattern::new(2, 2, &[(0, 0), (1, 0), (1, 1)]).unwrap();
/// let mut newton = Newton::new(&pattern, AutoSolver::default(), NewtonOptions::default()).unwrap();
/// let mut x = [1.0, 1.0];
/// let report = newton.solve(&mut Sys, &mut x).unwrap();
/// assert!((x[0] - 2f64.sqrt()).abs() < 1e-12 && (x[1] - 0.5f64.sqrt()).abs() < 1e-12);
/// assert!(report.iterations <= 6);
/// ```
pub trait NonlinearSystem {
    /// Number of equations `m` (rows of the pattern).
    fn num_equations(&self) -> usize;

    /// Number of step unknowns `n` (columns of the pattern).
    fn num_unknowns(&self) -> usize;

    /// Length of the state vector `x`; defaults to `n`.
    fn state_len(&self) -> usize {
        self.num_unknowns()
    }

    /// Writes `Φ(x)` into `out` (length `m`).
    fn residual(&mut self, x: &[f64], out: &mut [f64]);

    /// Writes the Jacobian values at `x` into `slots`, in the slot order of the pattern.
    fn jacobian(&mut self, x: &[f64], slots: &mut [f64]);

    /// Applies a step: `x ← x ⊕ dx`. Default: `x += dx` (requires `state_len == n`).
    fn apply_step(&mut self, x: &mut [f64], dx: &[f64]) {
        for (xi, di) in x.iter_mut().zip(dx) {
            *xi += di;
        }
    }

    /// Scale `e_i > 0` of each equation (see [`convergence`](crate::convergence)). Default 1.
    fn equation_scales(&self, out: &mut [f64]) {
        out.fill(1.0);
    }

    /// Scale `u_j > 0` of each step unknown (see [`convergence`](crate::convergence)). Default 1.
    fn unknown_scales(&self, out: &mut [f64]) {
        out.fill(1.0);
    }
}

/// When the Jacobian is re-evaluated and refactored.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum JacobianUpdate {
    /// Full Newton: every iteration.
    EveryIteration,
    /// Modified Newton: keep the factorization while `‖Φ_{k+1}‖ ≤ min_contraction · ‖Φ_k‖`, the
    /// steps made with it shrink by at least `min_contraction` (`‖Δ_{k+1}‖ ≤ min_contraction ·
    /// ‖Δ_k‖`) and it has been used for fewer than `max_age` iterations.
    Modified {
        /// Iterations a factorization may serve in one [`Newton::solve`] (it may serve the
        /// next solve again, subject to the contraction checks).
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

/// Options of [`Newton`].
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
    /// Refactor at the converged point so [`Newton::solve_linear`] (velocity, acceleration) uses
    /// `Φ_q(q)` exactly. Default true.
    pub factor_at_solution: bool,
    /// Number of worst equations listed in [`SolverError::NotConverged`]. Default 5.
    pub report_worst: usize,
    /// Hand the linear solver the scaled system `(E⁻¹ Φ_q U) (U⁻¹ Δq) = −E⁻¹ Φ` (equation scales
    /// `E`, unknown scales `U` from the [`NonlinearSystem`]) instead of the raw one. Default true:
    /// pivoting, rank decisions and least-squares weights then see unit-free numbers, so a model
    /// in millimetres and the same model in kilometres take the same steps. (For a square
    /// nonsingular system the step is the same either way, up to rounding.)
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

/// Outcome of a converged [`Newton::solve`].
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

/// Newton-Raphson solver with all buffers allocated at construction.
///
/// Generic over the [`LinearSolver`] (default [`AutoSolver`]). `solve`, `factor_at` and
/// `solve_linear` do not allocate on success (error values do).
#[derive(Debug)]
pub struct Newton<S: LinearSolver = AutoSolver> {
    pattern: SparsityPattern,
    selection: Option<RowSelection>,
    /// With a row selection: judge convergence (and the line search's merit) on the kept rows
    /// only, the dropped ones being the caller's to check ([`Newton::judge_kept_rows_only`]).
    kept_rows_only: bool,
    /// The rows the selection drops (empty without one).
    dropped_rows: Vec<usize>,
    solver: S,
    options: NewtonOptions,
    m: usize,
    n: usize,
    full_slots: Vec<f64>,
    /// Values handed to the linear solver (reduced and scaled).
    solve_slots: Vec<f64>,
    /// For each solver slot: full slot (unused and empty without a row selection: the
    /// identity), full row, column. 32-bit: on a large model these maps are streamed at every
    /// factorization and refinement, and half the width is half the memory traffic.
    slot_src: Vec<u32>,
    slot_row: Vec<u32>,
    slot_col: Vec<u32>,
    /// For each solver slot: `w_row / w_col` (the scaling of the linear system; 1 unscaled).
    slot_scale: Vec<f64>,
    /// For each solver row: full row.
    solve_rows: Vec<usize>,
    residual: Vec<f64>,
    trial_residual: Vec<f64>,
    rhs: Vec<f64>,
    dx: Vec<f64>,
    scaled_dx: Vec<f64>,
    x_trial: Vec<f64>,
    eq_weights: Vec<f64>,
    unknown_weights: Vec<f64>,
    new_eq_weights: Vec<f64>,
    new_unknown_weights: Vec<f64>,
    /// The scales the weights were computed from (NaN before the first read).
    eq_scales: Vec<f64>,
    unknown_scales: Vec<f64>,
    history: Vec<f64>,
    factored: bool,
    factored_at_current: bool,
    age: usize,
    /// Scaled length of the last step made with the current factorization (NaN: none yet).
    matrix_step: f64,
    /// Largest ratio of consecutive steps made with the current factorization (0: none yet).
    matrix_theta: f64,
    /// Scaled distance (sum of step lengths) from the point of the factorization to the last
    /// iterate, `x_last` (infinite: unknown).
    drift: f64,
    /// The state last returned by `solve` or passed to `factor_at` / `solve_linear_at`.
    x_last: Vec<f64>,
    /// `full_slots` hold the Jacobian at `x_last`.
    slots_at_last: bool,
    /// Factorizations attempted since construction (successful or not).
    factorizations: u64,
    /// Refinement buffers: residual and its scale (length m), correction (length n).
    refine_r: Vec<f64>,
    refine_s: Vec<f64>,
    refine_dy: Vec<f64>,
}

/// Largest scaled distance between the point of the factorization and the current state at
/// which [`Newton::solve_linear_at`] refines instead of refactoring: the refinement contracts by
/// about the relative change of the Jacobian, so a few corrections then reach rounding level.
pub const REFINE_MAX_DRIFT: f64 = 1e-5;

/// Corrections [`Newton::solve_linear_at`] makes before it gives up and refactors.
pub const REFINE_MAX_CORRECTIONS: usize = 4;

/// Backward error at which [`Newton::solve_linear_at`] accepts a refined solution:
/// `‖rhs − Φ_q v‖ ≤ 8ε ‖|Φ_q| |v| + |rhs|‖` in the max norm over rows weighted by their equation
/// scales, about what the residual of a few-entry constraint row resolves in floating point.
pub const REFINE_BACKWARD_ERROR: f64 = 8.0 * f64::EPSILON;

impl<S: LinearSolver> Newton<S> {
    /// Sets up Newton-Raphson for `pattern`: analyzes `solver` and allocates every buffer.
    ///
    /// # Errors
    /// Whatever `solver.analyze` reports (for example [`SolverError::NotSquare`] for an LU solver
    /// on a rectangular pattern); [`SolverError::Backend`] for a pattern with 2³² or more slots,
    /// rows or columns (the slot maps are 32-bit).
    pub fn new(
        pattern: &SparsityPattern,
        mut solver: S,
        options: NewtonOptions,
    ) -> Result<Self, SolverError> {
        check_index_width(pattern)?;
        solver.analyze(pattern)?;
        Ok(Self::with_parts(pattern, None, solver, options))
    }

    /// Like [`new`](Self::new), but solves only the rows kept by `selection` (decided once, for
    /// example from a [`RankAnalysis`](crate::RankAnalysis)). Convergence is still judged on all
    /// equations, so the dropped ones must be consistent.
    ///
    /// # Errors
    /// [`SolverError::DimensionMismatch`] or [`SolverError::InvalidRowSelection`] if the selection
    /// was not made from `pattern`, or what `solver.analyze` reports on the reduced pattern;
    /// [`SolverError::Backend`] for a pattern with 2³² or more slots, rows or columns.
    pub fn with_row_selection(
        pattern: &SparsityPattern,
        selection: RowSelection,
        mut solver: S,
        options: NewtonOptions,
    ) -> Result<Self, SolverError> {
        check_index_width(pattern)?;
        check_len(
            "row-selection columns",
            pattern.ncols(),
            selection.pattern().ncols(),
        )?;
        // The selection must come from this pattern: same rows and slots, same entries.
        let consistent = selection.rows().iter().all(|&r| r < pattern.nrows())
            && selection.slot_map().len() == selection.pattern().num_slots()
            && selection.slot_map().iter().enumerate().all(|(k, &full)| {
                full < pattern.num_slots() && {
                    let (r, c) = selection.pattern().entry(k);
                    pattern.entry(full) == (selection.rows()[r], c)
                }
            });
        if !consistent {
            return Err(SolverError::InvalidRowSelection {
                reason: "the row selection was not made from this pattern".to_owned(),
            });
        }
        solver.analyze(selection.pattern())?;
        Ok(Self::with_parts(pattern, Some(selection), solver, options))
    }

    fn with_parts(
        pattern: &SparsityPattern,
        selection: Option<RowSelection>,
        solver: S,
        options: NewtonOptions,
    ) -> Self {
        let (m, n) = (pattern.nrows(), pattern.ncols());
        let (full, solve_rows): (Vec<usize>, Vec<usize>) = match &selection {
            Some(sel) => (sel.slot_map().to_vec(), sel.rows().to_vec()),
            None => ((0..pattern.num_slots()).collect(), (0..m).collect()),
        };
        // In range: `check_index_width` accepted the pattern.
        let narrow = |v: usize| v as u32;
        let slot_row = full.iter().map(|&k| narrow(pattern.entry(k).0)).collect();
        let slot_col = full.iter().map(|&k| narrow(pattern.entry(k).1)).collect();
        let num_solve_slots = full.len();
        let slot_src = if selection.is_some() {
            full.into_iter().map(narrow).collect()
        } else {
            Vec::new()
        };
        let rm = solve_rows.len();
        let mut kept = vec![false; m];
        for &r in &solve_rows {
            kept[r] = true;
        }
        let dropped_rows = (0..m).filter(|&r| !kept[r]).collect();
        Self {
            pattern: pattern.clone(),
            selection,
            kept_rows_only: false,
            dropped_rows,
            solver,
            options,
            m,
            n,
            full_slots: vec![0.0; pattern.num_slots()],
            solve_slots: vec![0.0; num_solve_slots],
            slot_scale: vec![1.0; num_solve_slots],
            slot_src,
            slot_row,
            slot_col,
            solve_rows,
            residual: vec![0.0; m],
            trial_residual: vec![0.0; m],
            rhs: vec![0.0; rm],
            dx: vec![0.0; n],
            scaled_dx: vec![0.0; n],
            x_trial: Vec::new(),
            eq_weights: vec![1.0; m],
            unknown_weights: vec![1.0; n],
            new_eq_weights: vec![1.0; m],
            new_unknown_weights: vec![1.0; n],
            eq_scales: vec![f64::NAN; m],
            unknown_scales: vec![f64::NAN; n],
            history: Vec::with_capacity(options.max_iterations + 2),
            factored: false,
            factored_at_current: false,
            age: 0,
            matrix_step: f64::NAN,
            matrix_theta: 0.0,
            drift: f64::INFINITY,
            x_last: Vec::new(),
            slots_at_last: false,
            factorizations: 0,
            refine_r: vec![0.0; m],
            refine_s: vec![0.0; m],
            refine_dy: vec![0.0; n],
        }
    }

    /// With a row selection, whether the convergence test and the line search's merit see the
    /// kept rows only (`true`) or all equations (`false`, the default: the dropped rows of a
    /// consistent redundant system are then satisfied too). `true` is for a redundant system
    /// that is slightly inconsistent, where the dropped rows cannot vanish with the kept ones:
    /// Newton then solves the kept rows exactly and the caller checks the dropped rows'
    /// residuals. No effect without a row selection.
    pub fn judge_kept_rows_only(&mut self, yes: bool) {
        if self.kept_rows_only != yes {
            self.kept_rows_only = yes;
            // Recompute the weights at the next solve.
            self.eq_scales.fill(f64::NAN);
        }
    }

    /// Whether convergence is judged on the kept rows only (see
    /// [`judge_kept_rows_only`](Self::judge_kept_rows_only)).
    pub fn judges_kept_rows_only(&self) -> bool {
        self.kept_rows_only && self.selection.is_some()
    }

    /// The options.
    pub fn options(&self) -> &NewtonOptions {
        &self.options
    }

    /// Mutable options (tolerances, policy); buffers are unaffected except the residual history,
    /// which grows if `max_iterations` grows.
    pub fn options_mut(&mut self) -> &mut NewtonOptions {
        &mut self.options
    }

    /// The linear solver (for its name, rank, dependent equations).
    pub fn linear_solver(&self) -> &S {
        &self.solver
    }

    /// The full pattern.
    pub fn pattern(&self) -> &SparsityPattern {
        &self.pattern
    }

    /// The row selection, if any.
    pub fn row_selection(&self) -> Option<&RowSelection> {
        self.selection.as_ref()
    }

    /// The Jacobian slot values of the last evaluation (full pattern order).
    pub fn jacobian_slots(&self) -> &[f64] {
        &self.full_slots
    }

    /// True when the current factorization was computed at the state last returned by
    /// [`solve`](Self::solve) or passed to [`factor_at`](Self::factor_at).
    pub fn factorization_is_current(&self) -> bool {
        self.factored && self.factored_at_current
    }

    /// Factorizations (each with its Jacobian evaluation) made since construction by
    /// [`solve`](Self::solve), [`factor_at`](Self::factor_at) and
    /// [`solve_linear_at`](Self::solve_linear_at), failed attempts included: the costliest
    /// operation of a solve, counted to tell the work an analysis does from the speed of each
    /// piece of it. (The Jacobian evaluations of iterative refinement are not counted.)
    pub fn factorization_count(&self) -> u64 {
        self.factorizations
    }

    /// The state was moved outside the solver (for example by a predictor): the factorization is
    /// kept, so a [`JacobianUpdate::Modified`] solve may start with it, but it is no longer
    /// [current](Self::factorization_is_current).
    pub fn state_moved(&mut self) {
        self.factored_at_current = false;
        self.slots_at_last = false;
        self.drift = f64::INFINITY;
    }

    /// Forgets the factorization (the next solve refactors first).
    pub fn invalidate(&mut self) {
        self.factored = false;
        self.factored_at_current = false;
        self.slots_at_last = false;
        self.drift = f64::INFINITY;
    }

    fn check_system<N: NonlinearSystem + ?Sized>(
        &mut self,
        system: &N,
        x: &[f64],
    ) -> Result<(), SolverError> {
        check_len("equations of the system", self.m, system.num_equations())?;
        check_len("unknowns of the system", self.n, system.num_unknowns())?;
        check_len("state vector", system.state_len(), x.len())?;
        if self.x_trial.len() != x.len() {
            // Allocates only the first time (or if the state length changes).
            self.x_trial = vec![0.0; x.len()];
            self.x_last = vec![f64::NAN; x.len()];
        }
        Ok(())
    }

    /// Evaluates the Jacobian at `x` and factors it (for velocity/acceleration at a `q` that did not
    /// come from [`solve`](Self::solve)). Does not allocate after the first call.
    ///
    /// # Errors
    /// Size mismatches, non-finite Jacobian entries, [`SolverError::Singular`].
    pub fn factor_at<N: NonlinearSystem + ?Sized>(
        &mut self,
        system: &mut N,
        x: &[f64],
    ) -> Result<(), SolverError> {
        self.check_system(system, x)?;
        self.update_weights(system);
        self.refactor(system, x, None)?;
        self.x_last.copy_from_slice(x);
        self.slots_at_last = true;
        Ok(())
    }

    /// Reads the scales from the system; a factorization made with other scales is dropped.
    fn update_weights<N: NonlinearSystem + ?Sized>(&mut self, system: &N) {
        system.equation_scales(&mut self.new_eq_weights);
        system.unknown_scales(&mut self.new_unknown_weights);
        if self.new_eq_weights == self.eq_scales && self.new_unknown_weights == self.unknown_scales
        {
            // Same scales as last time (the usual case): same weights.
            return;
        }
        self.eq_scales.copy_from_slice(&self.new_eq_weights);
        self.unknown_scales
            .copy_from_slice(&self.new_unknown_weights);
        reciprocal_in_place(&mut self.new_eq_weights);
        reciprocal_in_place(&mut self.new_unknown_weights);
        if self.judges_kept_rows_only() {
            // Weight 0 takes the dropped rows out of the residual norm and the merit.
            for &r in &self.dropped_rows {
                self.new_eq_weights[r] = 0.0;
            }
        }
        if self.new_eq_weights != self.eq_weights
            || self.new_unknown_weights != self.unknown_weights
        {
            self.eq_weights.copy_from_slice(&self.new_eq_weights);
            self.unknown_weights
                .copy_from_slice(&self.new_unknown_weights);
            for k in 0..self.slot_scale.len() {
                self.slot_scale[k] = self.eq_weights[self.slot_row[k] as usize]
                    / self.unknown_weights[self.slot_col[k] as usize];
            }
            if self.options.scale_linear_system {
                self.invalidate();
            }
        }
    }

    /// `rhs_solver[i] = sign · rhs_full[row_i] / e_row_i` (scaled if enabled). No allocation.
    fn load_rhs(&mut self, full: &[f64], sign: f64) {
        let scaled = self.options.scale_linear_system;
        for (dst, &r) in self.rhs.iter_mut().zip(&self.solve_rows) {
            let w = if scaled { self.eq_weights[r] } else { 1.0 };
            *dst = sign * full[r] * w;
        }
    }

    /// `out_j ← u_j · out_j` (back from the scaled unknowns).
    fn unscale_solution(&self, out: &mut [f64]) {
        if self.options.scale_linear_system {
            for (o, w) in out.iter_mut().zip(&self.unknown_weights) {
                *o /= w;
            }
        }
    }

    fn refactor<N: NonlinearSystem + ?Sized>(
        &mut self,
        system: &mut N,
        x: &[f64],
        iteration: Option<usize>,
    ) -> Result<(), SolverError> {
        self.factored = false;
        self.factored_at_current = false;
        self.factorizations += 1;
        system.jacobian(x, &mut self.full_slots);
        // The solver's (reduced, scaled) values, with the finiteness check in the same pass.
        let scale = self
            .options
            .scale_linear_system
            .then_some(self.slot_scale.as_slice());
        let full = &self.full_slots;
        let finite = if self.selection.is_none() {
            gather_slots(&mut self.solve_slots, full.iter().copied(), scale)
        } else {
            let src = self.slot_src.iter().map(|&k| full[k as usize]);
            gather_slots(&mut self.solve_slots, src, scale)
        };
        if !finite || self.selection.is_some() {
            // Name the slot (with a row selection, the dropped rows are checked too).
            self.pattern
                .check_finite(&self.full_slots)
                .map_err(|e| with_iteration(e, iteration))?;
        }
        self.solver
            .factor(&self.solve_slots)
            .map_err(|e| self.map_rows(with_iteration(e, iteration)))?;
        self.factored = true;
        self.factored_at_current = true;
        self.age = 0;
        self.matrix_step = f64::NAN;
        self.matrix_theta = 0.0;
        self.drift = 0.0;
        Ok(())
    }

    /// Maps equation indices of the reduced system back to the full system in errors.
    fn map_rows(&self, e: SolverError) -> SolverError {
        match (e, &self.selection) {
            (
                SolverError::Singular {
                    dependent_equations,
                },
                Some(sel),
            ) => {
                let mut rows: Vec<usize> = dependent_equations
                    .iter()
                    .filter_map(|&i| sel.rows().get(i).copied())
                    .collect();
                rows.sort_unstable();
                SolverError::Singular {
                    dependent_equations: rows,
                }
            }
            (e, _) => e,
        }
    }

    /// Solves `Φ_q v = rhs` with the current factorization: velocity (`rhs = ν`) or acceleration
    /// (`rhs = γ#`). `rhs` has `m` entries (all equations; dropped rows are ignored), `out` has
    /// `n`. No allocation.
    ///
    /// Valid for the `q` of the last factorization: check
    /// [`factorization_is_current`](Self::factorization_is_current) or call
    /// [`factor_at`](Self::factor_at) first.
    ///
    /// # Errors
    /// [`SolverError::NotReady`] without a factorization; size mismatches; non-finite values.
    pub fn solve_linear(&mut self, rhs: &[f64], out: &mut [f64]) -> Result<(), SolverError> {
        if !self.factored {
            return Err(SolverError::NotReady {
                missing: "factor_at (or a successful solve)",
            });
        }
        check_len("right-hand side", self.m, rhs.len())?;
        check_len("solution", self.n, out.len())?;
        self.load_rhs(rhs, 1.0);
        self.solver.solve(&self.rhs, out)?;
        self.unscale_solution(out);
        Ok(())
    }

    /// Solves `Φ_q(x) v = rhs` (velocity, acceleration) at the state `x`, reusing the current
    /// factorization when it was made close to `x`. No allocation after the first call.
    ///
    /// * Factorization made at `x`: one solve, as [`solve_linear`](Self::solve_linear).
    /// * Made at a point at most [`REFINE_MAX_DRIFT`] (scaled) from `x`, which `x` was reached
    ///   from by the steps of the last [`solve`](Self::solve) (typically the last, tiny Newton
    ///   step): iterative refinement against the exact Jacobian at `x` (evaluated once and kept
    ///   for further right-hand sides), `v ← v + M⁻¹ (rhs − Φ_q(x) v)` with the old factors `M`,
    ///   until the backward error of `v` is at most [`REFINE_BACKWARD_ERROR`] (as good as a
    ///   fresh factorization). It contracts by about the relative change of the Jacobian; if a
    ///   correction does not halve the backward error, or [`REFINE_MAX_CORRECTIONS`] do not
    ///   suffice, the Jacobian is refactored at `x`.
    /// * Otherwise (no factorization, another point, a moved state): refactors at `x` first.
    ///
    /// # Errors
    /// Size mismatches, non-finite values, [`SolverError::Singular`] from a refactorization.
    pub fn solve_linear_at<N: NonlinearSystem + ?Sized>(
        &mut self,
        system: &mut N,
        x: &[f64],
        rhs: &[f64],
        out: &mut [f64],
    ) -> Result<(), SolverError> {
        self.check_system(system, x)?;
        check_len("right-hand side", self.m, rhs.len())?;
        check_len("solution", self.n, out.len())?;
        if self.x_last.as_slice() != x {
            self.state_moved();
            self.x_last.copy_from_slice(x);
        }
        if self.factored && self.factored_at_current {
            return self.solve_linear(rhs, out);
        }
        if self.factored && self.drift <= REFINE_MAX_DRIFT {
            if !self.slots_at_last {
                system.jacobian(x, &mut self.full_slots);
                self.pattern.check_finite(&self.full_slots)?;
                self.slots_at_last = true;
            }
            if self.refine(rhs, out)? {
                return Ok(());
            }
        }
        self.update_weights(system);
        self.refactor(system, x, None)?;
        self.slots_at_last = true;
        self.solve_linear(rhs, out)
    }

    /// Iterative refinement of `Φ_q v = rhs` with the exact Jacobian in `full_slots` and the
    /// (slightly older) factorization: `Ok(true)` once the backward error of `v` is at most
    /// [`REFINE_BACKWARD_ERROR`], `Ok(false)` when it does not get there (a correction that does
    /// not halve it, or [`REFINE_MAX_CORRECTIONS`] spent).
    ///
    /// The backward error is `max_i w_i |r_i| / max_i w_i (|Φ_q| |v| + |rhs|)_i` over the solved
    /// rows, `r = rhs − Φ_q v`, rows in the units of their equation scales `w_i` (as the
    /// convergence test sees them): the relative change of `Φ_q` and `rhs` that makes `v`
    /// exact. A fresh factorization delivers a few ε. Unlike the size of the last correction it
    /// does not depend on the conditioning: a long chain's corrections stall at about `κ ε ‖v‖`
    /// while its backward error is already ε.
    fn refine(&mut self, rhs: &[f64], out: &mut [f64]) -> Result<bool, SolverError> {
        self.solve_linear(rhs, out)?;
        let mut last = f64::INFINITY;
        for correction in 0..=REFINE_MAX_CORRECTIONS {
            // r = rhs − Φ_q v and s = |rhs| + |Φ_q| |v| on the solved rows.
            let (mut r, mut s) = (
                std::mem::take(&mut self.refine_r),
                std::mem::take(&mut self.refine_s),
            );
            r.copy_from_slice(rhs);
            for (si, ri) in s.iter_mut().zip(rhs) {
                *si = ri.abs();
            }
            let full = &self.full_slots;
            let (rows, cols) = (&self.slot_row, &self.slot_col);
            if self.selection.is_none() {
                residual_and_scale(&mut r, &mut s, full.iter().copied(), rows, cols, out);
            } else {
                let src = self.slot_src.iter().map(|&k| full[k as usize]);
                residual_and_scale(&mut r, &mut s, src, rows, cols, out);
            }
            let (mut r_max, mut s_max) = (0.0f64, 0.0f64);
            for &i in &self.solve_rows {
                let w = self.eq_weights[i];
                r_max = r_max.max(r[i].abs() * w);
                s_max = s_max.max(s[i] * w);
            }
            self.refine_s = s;
            let berr = if r_max == 0.0 { 0.0 } else { r_max / s_max };
            if berr <= REFINE_BACKWARD_ERROR {
                self.refine_r = r;
                return Ok(true);
            }
            // (A NaN backward error, after an overflow, also ends here: refactor.)
            if correction == REFINE_MAX_CORRECTIONS || berr.is_nan() || berr > 0.5 * last {
                self.refine_r = r;
                return Ok(false);
            }
            last = berr;
            let mut dy = std::mem::take(&mut self.refine_dy);
            let solved = self.solve_linear(&r, &mut dy);
            self.refine_r = r;
            if let Err(e) = solved {
                self.refine_dy = dy;
                return Err(e);
            }
            for (o, d) in out.iter_mut().zip(&dy) {
                *o += d;
            }
            self.refine_dy = dy;
        }
        Ok(false)
    }

    fn eval_residual<N: NonlinearSystem + ?Sized>(
        system: &mut N,
        x: &[f64],
        out: &mut [f64],
        iteration: usize,
    ) -> Result<(), SolverError> {
        system.residual(x, out);
        match out.iter().position(|v| !v.is_finite()) {
            None => Ok(()),
            Some(equation) => Err(SolverError::NonFinite {
                location: NonFiniteLocation::Residual { equation },
                iteration: Some(iteration),
            }),
        }
    }

    fn redundancy(&self) -> usize {
        let dropped = self
            .selection
            .as_ref()
            .map_or(0, |s| self.m - s.rows().len());
        dropped + self.solver.rank().map_or(0, |r| self.solver.nrows() - r)
    }

    /// Solves `Φ(x) = 0` starting from `x` (overwritten with the solution, or with the last
    /// iterate on failure). Does not allocate after the first call (on success).
    ///
    /// # Errors
    /// [`SolverError::NotConverged`] (residual history and worst equations),
    /// [`SolverError::Singular`] (dependent equations), [`SolverError::NonFinite`], size
    /// mismatches.
    pub fn solve<N: NonlinearSystem + ?Sized>(
        &mut self,
        system: &mut N,
        x: &mut [f64],
    ) -> Result<NewtonReport, SolverError> {
        self.check_system(system, x)?;
        if self.x_last.as_slice() != x {
            // Moved since the last solve without `state_moved`: distance unknown.
            self.drift = f64::INFINITY;
        }
        // The state changes from here on: an old factorization is no longer "current".
        self.factored_at_current = false;
        self.slots_at_last = false;
        // Age and step ratios count within one solve.
        self.age = 0;
        self.matrix_step = f64::NAN;
        self.matrix_theta = 0.0;
        let opts = self.options;
        self.update_weights(system);
        if let JacobianUpdate::EveryIteration = opts.jacobian_update {
            self.factored = false;
        }
        self.history.clear();
        let mut report = NewtonReport {
            iterations: 0,
            residual_norm: f64::NAN,
            step_norm: 0.0,
            refactorizations: 0,
            residual_evaluations: 0,
            damped_steps: 0,
            rank: None,
            redundant_equations: 0,
        };
        let mut residual = std::mem::take(&mut self.residual);
        let result = self.iterate(system, x, &mut residual, &mut report, &opts);
        self.residual = residual;
        self.x_last.copy_from_slice(x);
        // A factorization at the solution holds its Jacobian.
        self.slots_at_last = self.factored && self.factored_at_current;
        result.map(|()| {
            report.rank = self.solver.rank();
            report.redundant_equations = self.redundancy();
            report
        })
    }

    fn iterate<N: NonlinearSystem + ?Sized>(
        &mut self,
        system: &mut N,
        x: &mut [f64],
        residual: &mut [f64],
        report: &mut NewtonReport,
        opts: &NewtonOptions,
    ) -> Result<(), SolverError> {
        Self::eval_residual(system, x, residual, 0)?;
        report.residual_evaluations += 1;
        let mut rn = weighted_inf_norm(residual, &self.eq_weights).0;
        let mut merit = weighted_sum_squares(residual, &self.eq_weights);
        self.history.push(rn);
        let mut last_step = f64::INFINITY;
        // Estimated error left by the last step (scaled), compared with τ_step².
        let mut last_error = f64::INFINITY;
        let mut force_refactor = false;
        let mut k = 0;
        let step_tol = opts.tolerances.step;
        loop {
            report.residual_norm = rn;
            if rn <= opts.tolerances.residual && (k == 0 || last_error <= step_tol * step_tol) {
                report.iterations = k;
                report.step_norm = if k == 0 { 0.0 } else { last_step };
                if opts.factor_at_solution && !(self.factored && self.factored_at_current) {
                    self.refactor(system, x, Some(k))?;
                    report.refactorizations += 1;
                }
                return Ok(());
            }
            if k >= opts.max_iterations {
                return Err(self.not_converged(k, residual, opts));
            }
            k += 1;
            let stale_allowed = matches!(opts.jacobian_update, JacobianUpdate::Modified { .. });
            let need = !self.factored
                || force_refactor
                || !stale_allowed
                || match opts.jacobian_update {
                    JacobianUpdate::Modified { max_age, .. } => self.age >= max_age.max(1),
                    JacobianUpdate::EveryIteration => true,
                };
            if need && !(self.factored && self.factored_at_current) {
                self.refactor(system, x, Some(k))?;
                report.refactorizations += 1;
            }
            force_refactor = false;
            let fresh = self.factored_at_current;
            // Newton step: Φ_q dx = −Φ.
            self.load_rhs(residual, -1.0);
            self.solver
                .solve(&self.rhs, &mut self.dx)
                .map_err(|e| with_iteration(e, Some(k)))?;
            let mut dx = std::mem::take(&mut self.dx);
            self.unscale_solution(&mut dx);
            self.dx = dx;
            self.age += 1;
            let (mut step, _) = weighted_inf_norm(&self.dx, &self.unknown_weights);
            let mut alpha = 1.0;
            if let Some(cap) = opts.max_step {
                if step > cap {
                    alpha = cap / step;
                }
            }
            // Line search.
            let (max_halvings, c) = match opts.line_search {
                LineSearch::None => (0, 0.0),
                LineSearch::Backtracking {
                    max_halvings,
                    sufficient_decrease,
                } => (max_halvings, sufficient_decrease),
            };
            let mut accepted = false;
            let mut halvings = 0;
            let (mut best_alpha, mut best_merit) = (0.0, merit);
            loop {
                self.x_trial.copy_from_slice(x);
                for (s, d) in self.scaled_dx.iter_mut().zip(&self.dx) {
                    *s = alpha * d;
                }
                system.apply_step(&mut self.x_trial, &self.scaled_dx);
                if let Some(index) = self.x_trial.iter().position(|v| !v.is_finite()) {
                    return Err(SolverError::NonFinite {
                        location: NonFiniteLocation::Unknown { index },
                        iteration: Some(k),
                    });
                }
                Self::eval_residual(system, &self.x_trial, &mut self.trial_residual, k)?;
                report.residual_evaluations += 1;
                let trial_merit = weighted_sum_squares(&self.trial_residual, &self.eq_weights);
                let ok = matches!(opts.line_search, LineSearch::None)
                    || trial_merit <= (1.0 - 2.0 * c * alpha) * merit
                    || trial_merit <= f64::MIN_POSITIVE;
                if ok {
                    accepted = true;
                    break;
                }
                if trial_merit < best_merit {
                    (best_alpha, best_merit) = (alpha, trial_merit);
                }
                if !fresh || halvings >= max_halvings {
                    break;
                }
                halvings += 1;
                alpha *= 0.5;
            }
            if !accepted && !fresh {
                // A stale factorization gave a poor direction: refactor here and retry.
                force_refactor = true;
                self.history.push(rn);
                continue;
            }
            if !accepted && best_alpha > 0.0 {
                // No sufficient decrease, but some decrease: take the best trial.
                alpha = best_alpha;
                self.x_trial.copy_from_slice(x);
                for (s, d) in self.scaled_dx.iter_mut().zip(&self.dx) {
                    *s = alpha * d;
                }
                system.apply_step(&mut self.x_trial, &self.scaled_dx);
                Self::eval_residual(system, &self.x_trial, &mut self.trial_residual, k)?;
                report.residual_evaluations += 1;
                accepted = true;
            }
            if !accepted {
                if rn <= opts.tolerances.residual {
                    // The residual test holds and no step reduces the residual further (rounding
                    // level): accept the point, reporting the step that could not be taken.
                    report.iterations = k;
                    report.residual_norm = rn;
                    report.step_norm = step;
                    if opts.factor_at_solution && !(self.factored && self.factored_at_current) {
                        self.refactor(system, x, Some(k))?;
                        report.refactorizations += 1;
                    }
                    return Ok(());
                }
                return Err(self.not_converged(k, residual, opts));
            }
            if alpha < 1.0 {
                report.damped_steps += 1;
            }
            step *= alpha;
            x.copy_from_slice(&self.x_trial);
            self.factored_at_current = false;
            residual.copy_from_slice(&self.trial_residual);
            let new_rn = weighted_inf_norm(residual, &self.eq_weights).0;
            merit = weighted_sum_squares(residual, &self.eq_weights);
            last_error = if fresh {
                // Newton step: quadratic convergence, the error left is about ‖Δ‖².
                if step <= step_tol {
                    0.0
                } else {
                    f64::INFINITY
                }
            } else {
                f64::INFINITY
            };
            if let JacobianUpdate::Modified {
                min_contraction,
                max_age,
            } = opts.jacobian_update
            {
                if new_rn > min_contraction * rn {
                    force_refactor = true;
                }
                if !fresh {
                    // Chord step: linear convergence with rate θ, estimated by the largest ratio
                    // of consecutive steps made with this factorization (the rate need not be
                    // steady: several modes give oscillating ratios), or for the first step by
                    // the residual ratio.
                    let residual_ratio = if rn > 0.0 { new_rn / rn } else { 0.0 };
                    let theta = if self.matrix_step.is_nan() {
                        residual_ratio
                    } else {
                        let ratio = if step == 0.0 {
                            0.0
                        } else {
                            step / self.matrix_step
                        };
                        self.matrix_theta = self.matrix_theta.max(ratio);
                        self.matrix_theta
                    };
                    if theta > min_contraction {
                        force_refactor = true;
                    } else {
                        last_error = step * theta / (1.0 - theta);
                        // Chord steps left with this factorization in this solve: if they are
                        // not expected to reach the step test, refactor now rather than spend
                        // them (Newton converges from here in fewer steps).
                        let left = max_age.max(1).saturating_sub(self.age);
                        let tol2 = step_tol * step_tol;
                        if last_error > tol2
                            && (left == 0 || last_error * theta.powi(left.min(64) as i32) > tol2)
                        {
                            force_refactor = true;
                        }
                    }
                }
            }
            self.matrix_step = step;
            self.drift += step;
            rn = new_rn;
            last_step = step;
            self.history.push(rn);
        }
    }

    fn not_converged(
        &self,
        iterations: usize,
        residual: &[f64],
        opts: &NewtonOptions,
    ) -> SolverError {
        SolverError::NotConverged {
            iterations,
            residual_history: self.history.clone(),
            worst_equations: worst_entries(residual, &self.eq_weights, opts.report_worst),
        }
    }
}

/// The slot maps are 32-bit: refuses a pattern whose slots, rows or columns do not fit.
fn check_index_width(pattern: &SparsityPattern) -> Result<(), SolverError> {
    let largest = pattern
        .num_slots()
        .max(pattern.nrows())
        .max(pattern.ncols());
    if u32::try_from(largest).is_err() {
        return Err(SolverError::Backend(format!(
            "Newton: {largest} slots, rows or columns exceed 2^32 - 1 (32-bit slot maps)"
        )));
    }
    Ok(())
}

/// `dst[k] = v_k · w_k` (or `v_k` without scales) for the values `v` in slot order; returns
/// whether every value is finite (the check folded into the copy).
#[inline]
fn gather_slots(dst: &mut [f64], values: impl Iterator<Item = f64>, scale: Option<&[f64]>) -> bool {
    let mut finite = true;
    match scale {
        Some(w) => {
            for ((d, v), &w) in dst.iter_mut().zip(values).zip(w) {
                finite &= v.is_finite();
                *d = v * w;
            }
        }
        None => {
            for (d, v) in dst.iter_mut().zip(values) {
                finite &= v.is_finite();
                *d = v;
            }
        }
    }
    finite
}

/// `r_i −= a_k v_j` and `s_i += |a_k v_j|` for each slot `k = (i, j)` with value `a_k`: the
/// residual and the scale of the refinement's backward error.
#[inline]
fn residual_and_scale(
    r: &mut [f64],
    s: &mut [f64],
    values: impl Iterator<Item = f64>,
    rows: &[u32],
    cols: &[u32],
    v: &[f64],
) {
    for ((a, &i), &j) in values.zip(rows).zip(cols) {
        let av = a * v[j as usize];
        r[i as usize] -= av;
        s[i as usize] += av.abs();
    }
}

fn with_iteration(e: SolverError, iteration: Option<usize>) -> SolverError {
    match e {
        SolverError::NonFinite { location, .. } => SolverError::NonFinite {
            location,
            iteration,
        },
        e => e,
    }
}
