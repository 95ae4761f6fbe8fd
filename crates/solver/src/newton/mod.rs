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
//! and [`Newton::solve_linear`] then solves both with that one factorization; or
//! [`Newton::solve_linear_at`] refines with the factors of the last iteration (`refine.rs`).
//!
//! # Layout (one job per type)
//! * this file — [`NonlinearSystem`], [`Newton`]'s construction, state and linear solves;
//! * `iteration.rs` — the iteration loop of [`Newton::solve`];
//! * `options.rs` — [`NewtonOptions`], [`JacobianUpdate`], [`LineSearch`], [`NewtonReport`];
//! * `factorization.rs` — the factored Jacobian and how far the state has moved from it;
//! * `slot_map.rs` — row selection and scaling as index maps over slots;
//! * `weights.rs` — the weights of the scaled norms;
//! * `line_search.rs` — backtracking on the scaled residual;
//! * `policy.rs` — when to refactor (Jacobian reuse);
//! * `rate.rs` — the chord rate estimate and the error a chord step leaves;
//! * `refine.rs` — iterative refinement of the velocity and acceleration solves;
//! * the convergence test itself is in [`convergence`](crate::convergence).

mod factorization;
mod iteration;
mod line_search;
mod options;
mod policy;
mod rate;
mod refine;
mod slot_map;
mod weights;

pub use options::{JacobianUpdate, LineSearch, NewtonOptions, NewtonReport};
pub use refine::{REFINE_BACKWARD_ERROR, REFINE_MAX_CORRECTIONS, REFINE_MAX_DRIFT};

use crate::auto::AutoSolver;
use crate::error::{NonFiniteLocation, SolverError};
use crate::linear::LinearSolver;
use crate::pattern::{check_len, RowSelection, SparsityPattern};
use factorization::Factorization;
use line_search::Backtracking;
use policy::RefactorPolicy;
use rate::ChordRate;
use refine::Refinement;
use weights::Weights;

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

/// Newton-Raphson solver with all buffers allocated at construction.
///
/// Generic over the [`LinearSolver`] (default [`AutoSolver`]). `solve`, `factor_at` and
/// `solve_linear` do not allocate on success (error values do).
#[derive(Debug)]
pub struct Newton<S: LinearSolver = AutoSolver> {
    options: NewtonOptions,
    m: usize,
    n: usize,
    /// The factored Jacobian, its slot maps and where it was made.
    fact: Factorization<S>,
    /// Weights of the scaled norms.
    weights: Weights,
    /// With a row selection: judge convergence (and the line search's merit) on the kept rows
    /// only, the dropped ones being the caller's to check ([`Newton::judge_kept_rows_only`]).
    kept_rows_only: bool,
    /// Jacobian reuse and the chord rate of the current factors.
    policy: RefactorPolicy,
    rate: ChordRate,
    /// The residual at the current iterate, and the Newton step.
    residual: Vec<f64>,
    dx: Vec<f64>,
    /// Trial state and residual of the line search.
    trial: Backtracking,
    /// Buffers of the refinement in `solve_linear_at`.
    refinement: Refinement,
    /// Scaled residual norms of the current solve (for the error report).
    history: Vec<f64>,
    /// The state last returned by `solve` or passed to `factor_at` / `solve_linear_at`.
    x_last: Vec<f64>,
}

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
        if !selection_matches(pattern, &selection) {
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
        Self {
            options,
            m,
            n,
            fact: Factorization::new(pattern, selection, solver),
            weights: Weights::new(m, n),
            kept_rows_only: false,
            policy: RefactorPolicy::default(),
            rate: ChordRate::new(),
            residual: vec![0.0; m],
            dx: vec![0.0; n],
            trial: Backtracking::new(m, n),
            refinement: Refinement::new(m, n),
            history: Vec::with_capacity(options.max_iterations + 2),
            x_last: Vec::new(),
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
            self.weights.forget_scales();
        }
    }

    /// Whether convergence is judged on the kept rows only (see
    /// [`judge_kept_rows_only`](Self::judge_kept_rows_only)).
    pub fn judges_kept_rows_only(&self) -> bool {
        self.kept_rows_only && self.fact.selection.is_some()
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
        &self.fact.solver
    }

    /// The full pattern.
    pub fn pattern(&self) -> &SparsityPattern {
        &self.fact.pattern
    }

    /// The row selection, if any.
    pub fn row_selection(&self) -> Option<&RowSelection> {
        self.fact.selection.as_ref()
    }

    /// The Jacobian slot values of the last evaluation (full pattern order).
    pub fn jacobian_slots(&self) -> &[f64] {
        &self.fact.full_slots
    }

    /// True when the current factorization was computed at the state last returned by
    /// [`solve`](Self::solve) or passed to [`factor_at`](Self::factor_at).
    pub fn factorization_is_current(&self) -> bool {
        self.fact.is_current()
    }

    /// Factorizations (each with its Jacobian evaluation) made since construction by
    /// [`solve`](Self::solve), [`factor_at`](Self::factor_at) and
    /// [`solve_linear_at`](Self::solve_linear_at), failed attempts included: the costliest
    /// operation of a solve, counted to tell the work an analysis does from the speed of each
    /// piece of it. (The Jacobian evaluations of iterative refinement are not counted.)
    pub fn factorization_count(&self) -> u64 {
        self.fact.count
    }

    /// The state was moved outside the solver (for example by a predictor): the factorization is
    /// kept, so a [`JacobianUpdate::Modified`] solve may start with it, but it is no longer
    /// [current](Self::factorization_is_current).
    pub fn state_moved(&mut self) {
        self.fact.state_moved();
    }

    /// Forgets the factorization (the next solve refactors first).
    pub fn invalidate(&mut self) {
        self.fact.invalidate();
    }

    /// Sizes the buffers that hold a state (the line search's trial state, the last solved
    /// state) for states of `len` values, which the pattern does not tell (a body's Euler
    /// parameters are four values for three unknowns). Call it at setup with the system's
    /// [`NonlinearSystem::state_len`]: otherwise the first solve sizes them (allocates).
    pub fn fit_state(&mut self, len: usize) {
        if self.trial.fit_state(len) {
            self.x_last = vec![f64::NAN; len];
        }
    }

    fn check_system<N: NonlinearSystem + ?Sized>(
        &mut self,
        system: &N,
        x: &[f64],
    ) -> Result<(), SolverError> {
        check_len("equations of the system", self.m, system.num_equations())?;
        check_len("unknowns of the system", self.n, system.num_unknowns())?;
        check_len("state vector", system.state_len(), x.len())?;
        // Allocates only if not sized at setup (or if the state length changes).
        self.fit_state(x.len());
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
        self.fact.slots_at_last = true;
        Ok(())
    }

    /// Reads the scales from the system; a factorization made with other scales is dropped.
    fn update_weights<N: NonlinearSystem + ?Sized>(&mut self, system: &N) {
        let zero_rows: &[usize] = if self.judges_kept_rows_only() {
            // Weight 0 takes the dropped rows out of the residual norm and the merit.
            &self.fact.map.dropped_rows
        } else {
            &[]
        };
        if self.weights.update(system, zero_rows) {
            self.fact.map.rescale(&self.weights);
            if self.options.scale_linear_system {
                self.invalidate();
            }
        }
    }

    /// Evaluates the Jacobian at `x` and factors it; new factors start a new age and rate.
    fn refactor<N: NonlinearSystem + ?Sized>(
        &mut self,
        system: &mut N,
        x: &[f64],
        iteration: Option<usize>,
    ) -> Result<(), SolverError> {
        let scaled = self.options.scale_linear_system;
        self.fact.refactor(system, x, iteration, scaled)?;
        self.policy.factored();
        self.rate.reset();
        Ok(())
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
        if !self.fact.factored {
            return Err(SolverError::NotReady {
                missing: "factor_at (or a successful solve)",
            });
        }
        check_len("right-hand side", self.m, rhs.len())?;
        check_len("solution", self.n, out.len())?;
        let scaled = self.options.scale_linear_system;
        self.fact.solve(rhs, 1.0, out, &self.weights, scaled)
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
        if self.fact.is_current() {
            return self.solve_linear(rhs, out);
        }
        if self.fact.factored && self.fact.drift <= REFINE_MAX_DRIFT {
            if !self.fact.slots_at_last {
                system.jacobian(x, &mut self.fact.full_slots);
                self.fact.pattern.check_finite(&self.fact.full_slots)?;
                self.fact.slots_at_last = true;
            }
            let scaled = self.options.scale_linear_system;
            if self
                .refinement
                .run(&mut self.fact, &self.weights, scaled, rhs, out)?
            {
                return Ok(());
            }
        }
        self.update_weights(system);
        self.refactor(system, x, None)?;
        self.fact.slots_at_last = true;
        self.solve_linear(rhs, out)
    }
}

/// `Φ(x)` into `out`, refusing a non-finite entry (naming the equation and the iteration).
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

/// Whether `selection` was made from `pattern`: same rows and slots, same entries.
fn selection_matches(pattern: &SparsityPattern, selection: &RowSelection) -> bool {
    selection.rows().iter().all(|&r| r < pattern.nrows())
        && selection.slot_map().len() == selection.pattern().num_slots()
        && selection.slot_map().iter().enumerate().all(|(k, &full)| {
            full < pattern.num_slots() && {
                let (r, c) = selection.pattern().entry(k);
                pattern.entry(full) == (selection.rows()[r], c)
            }
        })
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

/// Sets the iteration of a [`SolverError::NonFinite`] (other errors unchanged).
fn with_iteration(e: SolverError, iteration: Option<usize>) -> SolverError {
    match e {
        SolverError::NonFinite { location, .. } => SolverError::NonFinite {
            location,
            iteration,
        },
        e => e,
    }
}
