//! The linear-solver abstraction: analyze once, factor many times, solve many times.
//!
//! A mechanism's Jacobian keeps its structure for the whole simulation, so the work splits in
//! three phases:
//!
//! | phase | when | may allocate |
//! |---|---|---|
//! | [`analyze`](LinearSolver::analyze) | once per [`SparsityPattern`] | yes |
//! | [`factor`](LinearSolver::factor) | when the values change | no |
//! | [`solve`](LinearSolver::solve) | per right-hand side | no |
//!
//! Members of the family: [`DenseLu`](crate::DenseLu) (partial pivoting, square),
//! [`SparseLu`](crate::SparseLu) (faer simplicial LU with a COLAMD fill-reducing ordering,
//! square), [`MinNormQr`](crate::MinNormQr) (rank revealing, any shape: minimum-norm least
//! squares, which satisfies every equation of a consistent redundant system) and
//! [`AutoSolver`](crate::AutoSolver) (`auto.rs`), which picks one of them from the pattern.
//!
//! This file holds the trait alone, so that every member builds on it without a circle; what
//! the LU members share is in `equilibration.rs` (row and column scaling), `singular.rs` (the
//! pivot tolerance and the error naming the dependent equations) and `scratch.rs` (faer's
//! scratch memory).

use crate::error::SolverError;
use crate::pattern::SparsityPattern;

/// A linear solver for `J x = b` with `J` given as slot values of a fixed [`SparsityPattern`].
///
/// Call order: `analyze` once, then any sequence of `factor` and `solve` (each `solve` uses the
/// last successful `factor`). After `analyze`, `factor` and `solve` must not allocate.
///
/// Implementing a new member means writing these methods; everything above (Newton-Raphson,
/// velocity and acceleration solves) works with any member.
pub trait LinearSolver {
    /// Symbolic analysis of the structure (orderings, buffer sizes). May allocate.
    ///
    /// # Errors
    /// Shape problems the solver cannot handle (for example [`SolverError::NotSquare`]).
    fn analyze(&mut self, pattern: &SparsityPattern) -> Result<(), SolverError>;

    /// Numeric factorization of the matrix whose slot values are `slots` (pattern of the last
    /// `analyze`). Must not allocate.
    ///
    /// # Errors
    /// [`SolverError::Singular`] (with the dependent equations when they can be identified),
    /// [`SolverError::NonFinite`], [`SolverError::DimensionMismatch`], [`SolverError::NotReady`].
    fn factor(&mut self, slots: &[f64]) -> Result<(), SolverError>;

    /// Solves `J x = b` with the last factorization: `b` has `nrows` entries, `x` has `ncols`.
    /// Must not allocate. Rank-revealing members return the minimum-norm solution of the
    /// independent equations.
    ///
    /// # Errors
    /// [`SolverError::NotReady`], [`SolverError::DimensionMismatch`], [`SolverError::NonFinite`].
    fn solve(&mut self, b: &[f64], x: &mut [f64]) -> Result<(), SolverError>;

    /// Rows of the analyzed pattern.
    fn nrows(&self) -> usize;

    /// Columns of the analyzed pattern.
    fn ncols(&self) -> usize;

    /// Numerical rank found by the last factorization, when the solver reveals it
    /// (`None` for the LU members, which fail with [`SolverError::Singular`] instead).
    fn rank(&self) -> Option<usize> {
        None
    }

    /// Equations found dependent by the last factorization (rank-revealing members only).
    fn dependent_equations(&self) -> &[usize] {
        &[]
    }

    /// Short name for reports and benchmarks (`"dense-lu"`, `"sparse-lu"`, `"min-norm-qr"`).
    fn name(&self) -> &'static str;
}
