//! # cardan-solver
//!
//! The numerical engine of cardan, independent of mechanisms: it is handed a constraint system
//! (residual `Φ`, Jacobian values on a fixed sparsity pattern, right-hand sides `ν`, `γ#`) and
//! solves it. Nothing here knows about bodies or joints.
//!
//! # Theory
//!
//! ## Position analysis: Newton-Raphson on Φ(q) = 0
//! The kinematic constraints `Φ(q, t) = 0` (`m` equations, `n` coordinates) are nonlinear in `q`.
//! Newton-Raphson linearizes them at the current iterate (Haug 1989, §4.4, eq. 4.4.5; Nikravesh
//! 1988, §4.5):
//!
//! ```text
//!   Φ_q(q_k) Δq_k = −Φ(q_k, t),      q_{k+1} = q_k + Δq_k
//! ```
//!
//! In the 7-coordinate form `q_i = [r_i; p_i]` and the normalization rows `p_iᵀ p_i − 1 = 0` are
//! part of `Φ`. In the 6-coordinate form the step is `[Δr_i; Δπ'_i]` (virtual rotation in the body
//! frame; `Φ_π' = ½ Φ_p Lᵀ`), there are no normalization rows, and the update of `p_i` is a
//! rotation, supplied by the caller through [`NonlinearSystem::apply_step`]. Convergence is tested
//! on scaled residual and step norms ([`convergence`]), so results do not depend on units.
//!
//! ## Velocity and acceleration: linear systems with the same matrix
//! Differentiating `Φ(q, t) = 0` once and twice in time (Haug §6.1, eqs. 6.1.4 and 6.1.5):
//!
//! ```text
//!   Φ_q q̇ = ν  = −Φ_t
//!   Φ_q q̈ = γ# = −(Φ_q q̇)_q q̇ − 2 Φ_qt q̇ − Φ_tt
//! ```
//!
//! (6-coordinate form: `Φ_v v = ν`, `Φ_v v̇ = γ#` with `v = [ṙ; ω']`.) Both have the matrix of the
//! converged position iteration, so one factorization serves position (last iterations), velocity
//! and acceleration ([`Newton::solve_linear`]).
//!
//! ## Redundant constraints
//! Mechanisms such as Bricard's linkage, the Bennett linkage, or a planar four-bar modelled with
//! four spatial revolute joints have more constraint equations than independent ones: on the
//! constraint manifold `rank Φ_q < m` and the LU factorization of `Φ_q` fails. [`RankAnalysis`]
//! finds the dependent rows with a column-pivoted QR of `Φ_qᵀ` (rows unit-normalized, tolerance
//! relative; see [`rank`]). Two consistent ways on:
//!
//! 1. drop the dependent rows once ([`SparsityPattern::select_rows`],
//!    [`Newton::with_row_selection`]) and keep using a fast square LU;
//! 2. use [`MinNormQr`], which returns the minimum-norm least-squares solution at every step: it
//!    satisfies all equations of a consistent redundant system, is the Gauss-Newton step at an
//!    iterate off the manifold (where the redundant Jacobian usually has full rank), and is the
//!    step to use for assembling an under-driven mechanism (`m < n`), since it moves the bodies
//!    as little as possible (in the norm of the unknowns divided by their scales).
//!
//! The dependent rows are decided once, at an assembled configuration; choose them by ordering
//! the equations (the last equations of each dependent group are the ones reported).
//!
//! # Layout (one concept per file)
//! * [`pattern`] — [`SparsityPattern`] (fixed structure, values in a caller-owned slot array) and
//!   [`RowSelection`].
//! * [`linear`] — the [`LinearSolver`] trait (analyze / factor / solve); [`auto`] —
//!   [`AutoSolver`], which picks a member from the pattern.
//! * What the LU members share: `equilibration` (row and column scaling by powers of two),
//!   `singular` ([`DEFAULT_PIVOT_TOLERANCE`] and the error naming the dependent equations),
//!   `scratch` (faer's scratch memory).
//! * [`dense`] — [`DenseLu`]; [`sparse`] — [`SparseLu`]; [`rank`] — [`RankAnalysis`], [`MinNormQr`];
//!   [`sparse_rank`] — the sparse rank analysis for large models (and
//!   [`RankAnalysis::compute_auto`], the switch between the two); [`sparse_min_norm`] —
//!   [`SparseMinNorm`], the minimum-norm step of large assemblies.
//! * [`schur`] — [`SchurSolver`]: saddle-point systems `[A Bᵀ; B 0]` with a block-diagonal SPD
//!   `A` (the equations of motion with a mass-only matrix) by the Schur complement and a sparse
//!   Cholesky.
//! * [`newton`] — [`NonlinearSystem`], [`Newton`], options and report; [`convergence`] — scaled
//!   tests.
//! * [`error`] — [`SolverError`].
//!
//! # Allocation
//! Every buffer is allocated when a solver is analyzed or a [`Newton`] is built. After that,
//! `factor`, `solve`, `Newton::solve` and `Newton::solve_linear` do not allocate on success
//! (checked by `tests/no_alloc.rs` with a counting allocator, including a 160-step time-stepping
//! loop over a full crank turn). Caveats: (1) faer's simplicial sparse LU keeps its factors in
//! vectors that grow if a factorization produces more fill than every earlier one (a different
//! pivot sequence); [`SparseLu`] presizes them at `analyze` by factoring random values on the
//! pattern, so this does not happen in practice (the test checks the first factorization after
//! `analyze` of a ladder and a chain, which allocates 125 times without presizing), but it is
//! not a hard guarantee. (2) The first
//! `Newton::solve` sizes one buffer to the state length. (3) Error values allocate (messages,
//! residual histories), and an LU failure runs a dense rank analysis to name the dependent
//! equations.
//!
//! # Example: velocity after position
//! ```
//! use cardan_solver::{AutoSolver, Newton, NewtonOptions, NonlinearSystem, SparsityPattern};
//!
//! /// A point on the unit circle whose x coordinate is driven: Φ = [x² + y² − 1, x − d].
//! struct Driven { d: f64 }
//! impl NonlinearSystem for Driven {
//!     fn num_equations(&self) -> usize { 2 }
//!     fn num_unknowns(&self) -> usize { 2 }
//!     fn residual(&mut self, q: &[f64], out: &mut [f64]) {
//!         out[0] = q[0] * q[0] + q[1] * q[1] - 1.0;
//!         out[1] = q[0] - self.d;
//!     }
//!     fn jacobian(&mut self, q: &[f64], slots: &mut [f64]) {
//!         slots.copy_from_slice(&[2.0 * q[0], 2.0 * q[1], 1.0]);
//!     }
//! }
//!
//! let pattern = SparsityPattern::new(2, 2, &[(0, 0), (0, 1), (1, 0)])?;
//! let mut newton = Newton::new(&pattern, AutoSolver::default(), NewtonOptions::default())?;
//! let mut sys = Driven { d: 0.6 };
//! let mut q = [0.5, 0.9];
//! let report = newton.solve(&mut sys, &mut q)?;
//! assert!((q[1] - 0.8).abs() < 1e-12, "{report:?}");
//!
//! // Velocity: Φ_q q̇ = ν with ν = [0, ḋ] (ḋ = 1), using the factorization at the solution.
//! let mut qdot = [0.0; 2];
//! newton.solve_linear(&[0.0, 1.0], &mut qdot)?;
//! assert!((qdot[0] - 1.0).abs() < 1e-12 && (qdot[1] + 0.75).abs() < 1e-12);
//! # Ok::<(), cardan_solver::SolverError>(())
//! ```
//!
//! # References
//! * E. J. Haug, *Computer Aided Kinematics and Dynamics of Mechanical Systems*, Allyn and Bacon,
//!   1989: §4.4 (Newton-Raphson), §6.1 (velocity and acceleration equations).
//! * P. E. Nikravesh, *Computer-Aided Analysis of Mechanical Systems*, Prentice Hall, 1988: §4.5.
//! * G. H. Golub, C. F. Van Loan, *Matrix Computations*, 4th ed., 2013: §3.4 (LU with partial
//!   pivoting), §5.4.2 (QR with column pivoting), §5.6 (minimum-norm solutions).
//! * J. E. Dennis, R. B. Schnabel, *Numerical Methods for Unconstrained Optimization and Nonlinear
//!   Equations*, SIAM, 1996: §6.3 (backtracking line search).

pub mod auto;
pub mod convergence;
pub mod dense;
mod equilibration;
pub mod error;
pub mod linear;
pub mod newton;
pub mod pattern;
pub mod rank;
pub mod schur;
mod scratch;
mod singular;
pub mod sparse;
pub mod sparse_min_norm;
pub mod sparse_rank;
pub mod sparse_refactor;

pub use auto::{AutoPolicy, AutoSolver, SolverChoice, SolverKind};
pub use convergence::Tolerances;
pub use dense::DenseLu;
pub use error::{NonFiniteLocation, SolverError};
pub use linear::LinearSolver;
pub use newton::{
    JacobianUpdate, LineSearch, Newton, NewtonOptions, NewtonReport, NonlinearSystem,
    REFINE_BACKWARD_ERROR, REFINE_MAX_CORRECTIONS, REFINE_MAX_DRIFT,
};
pub use pattern::{RowSelection, SparsityPattern};
pub use rank::{MinNormQr, RankAnalysis, RankOptions, SPARSE_RANK_MIN_UNKNOWNS};
pub use schur::{SchurSolver, DEFAULT_BLOCK_PIVOT_TOLERANCE, DEFAULT_SCHUR_PIVOT_TOLERANCE};
pub use singular::DEFAULT_PIVOT_TOLERANCE;
pub use sparse::{FactorizationCounts, SparseLu};
pub use sparse_min_norm::SparseMinNorm;
