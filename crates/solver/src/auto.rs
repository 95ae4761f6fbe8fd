//! [`AutoSolver`]: the [`LinearSolver`] that picks [`DenseLu`], [`SparseLu`] or [`MinNormQr`] at
//! `analyze`, from a [`SolverChoice`] (by default the size and density rule of [`AutoPolicy`]),
//! and dispatches to it statically (a closed enum, no trait object in the hot path).

use crate::dense::DenseLu;
use crate::error::SolverError;
use crate::linear::LinearSolver;
use crate::pattern::SparsityPattern;
use crate::rank::MinNormQr;
use crate::singular::DEFAULT_PIVOT_TOLERANCE;
use crate::sparse::SparseLu;

/// Which solver [`AutoSolver`] uses.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum SolverChoice {
    /// Decide from size and density at `analyze` (see [`AutoPolicy`]).
    Auto(AutoPolicy),
    /// Always [`DenseLu`].
    Dense,
    /// Always [`SparseLu`].
    Sparse,
    /// Always [`MinNormQr`] (rank revealing; any shape).
    MinNorm,
}

impl Default for SolverChoice {
    fn default() -> Self {
        Self::Auto(AutoPolicy::default())
    }
}

/// The size/density rule of [`SolverChoice::Auto`] for square patterns (non-square patterns always
/// get [`MinNormQr`]).
///
/// Dense LU is chosen when `n ≤ dense_max_dim`, or when `n ≤ dense_density_max_dim` and the
/// density is at least `dense_min_density`; sparse LU otherwise.
///
/// The size threshold: [`SparseLu`] refactors with the pivots of the previous factorization
/// while they stay acceptable ([`crate::sparse_refactor`]), so in a sequence of factorizations
/// (Newton iterations, frames of a motion) it costs the floating-point work of the sparse
/// factors alone. Measured as instructions (callgrind) of whole kinematic runs of FreeCAD
/// assemblies (`cardan-bench --asmt --smoke --only FILE`), sparse against dense: 98 unknowns
/// −29 %, 70 unknowns −14 %, 28 unknowns −4.5 % and +8 % (two files), 21 unknowns +4 % to
/// +5 % (sparse's setup: ordering and presizing). Hence `dense_max_dim = 48`. Without the
/// pivot reuse the crossing was at about 100 unknowns (`benches/linear.rs`), and the dense LU
/// is 10–60× slower from 700 unknowns on. The density rule (dense up to 1000 unknowns at
/// ≥ 20 % density, where fill makes the sparse factors dense anyway) is a judgement, not a
/// measurement.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AutoPolicy {
    /// Dense at or below this many unknowns, whatever the density.
    pub dense_max_dim: usize,
    /// Density at or above which dense is chosen up to `dense_density_max_dim`.
    pub dense_min_density: f64,
    /// Size cap for the density rule.
    pub dense_density_max_dim: usize,
}

impl Default for AutoPolicy {
    fn default() -> Self {
        Self {
            dense_max_dim: 48,
            dense_min_density: 0.2,
            dense_density_max_dim: 1000,
        }
    }
}

impl AutoPolicy {
    /// The solver kind this policy picks for `pattern`.
    pub fn pick(&self, pattern: &SparsityPattern) -> SolverKind {
        let (m, n) = (pattern.nrows(), pattern.ncols());
        if m != n {
            SolverKind::MinNorm
        } else if n <= self.dense_max_dim
            || (n <= self.dense_density_max_dim && pattern.density() >= self.dense_min_density)
        {
            SolverKind::Dense
        } else {
            SolverKind::Sparse
        }
    }
}

/// The concrete solver kinds.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SolverKind {
    /// [`DenseLu`].
    Dense,
    /// [`SparseLu`].
    Sparse,
    /// [`MinNormQr`].
    MinNorm,
}

#[derive(Debug)]
enum Inner {
    None,
    Dense(Box<DenseLu>),
    Sparse(Box<SparseLu>),
    MinNorm(Box<MinNormQr>),
}

/// A [`LinearSolver`] that picks [`DenseLu`], [`SparseLu`] or [`MinNormQr`] at `analyze`
/// according to a [`SolverChoice`] (static dispatch through a closed enum).
#[derive(Debug)]
pub struct AutoSolver {
    choice: SolverChoice,
    pivot_tolerance: Option<f64>,
    inner: Inner,
}

impl Default for AutoSolver {
    fn default() -> Self {
        Self::new(SolverChoice::default())
    }
}

impl AutoSolver {
    /// A solver that will decide according to `choice` at `analyze`.
    pub fn new(choice: SolverChoice) -> Self {
        Self {
            choice,
            pivot_tolerance: None,
            inner: Inner::None,
        }
    }

    /// The LU members declare the matrix singular when a pivot of the equilibrated matrix is
    /// below `tol` (instead of [`DEFAULT_PIVOT_TOLERANCE`]): a caller that can do better than
    /// solve with a nearly singular matrix (the kinematic solver re-selects its independent
    /// rows) asks to hear of it early.
    pub fn with_pivot_tolerance(mut self, tol: f64) -> Self {
        self.pivot_tolerance = Some(tol);
        self
    }

    /// The kind picked at the last `analyze` (`None` before).
    pub fn kind(&self) -> Option<SolverKind> {
        match self.inner {
            Inner::None => None,
            Inner::Dense(_) => Some(SolverKind::Dense),
            Inner::Sparse(_) => Some(SolverKind::Sparse),
            Inner::MinNorm(_) => Some(SolverKind::MinNorm),
        }
    }
}

/// Static dispatch over the members (a `match`, no trait object in the hot path).
macro_rules! dispatch {
    ($inner:expr, $s:ident => $call:expr, $none:expr) => {
        match $inner {
            Inner::None => $none,
            Inner::Dense($s) => $call,
            Inner::Sparse($s) => $call,
            Inner::MinNorm($s) => $call,
        }
    };
}

impl LinearSolver for AutoSolver {
    fn analyze(&mut self, pattern: &SparsityPattern) -> Result<(), SolverError> {
        let kind = match self.choice {
            SolverChoice::Auto(policy) => policy.pick(pattern),
            SolverChoice::Dense => SolverKind::Dense,
            SolverChoice::Sparse => SolverKind::Sparse,
            SolverChoice::MinNorm => SolverKind::MinNorm,
        };
        self.inner = Inner::None;
        let tol = self.pivot_tolerance.unwrap_or(DEFAULT_PIVOT_TOLERANCE);
        let mut inner = match kind {
            SolverKind::Dense => Inner::Dense(Box::new(DenseLu::new().with_pivot_tolerance(tol))),
            SolverKind::Sparse => {
                Inner::Sparse(Box::new(SparseLu::new().with_pivot_tolerance(tol)))
            }
            SolverKind::MinNorm => Inner::MinNorm(Box::default()),
        };
        match &mut inner {
            Inner::Dense(s) => s.analyze(pattern)?,
            Inner::Sparse(s) => s.analyze(pattern)?,
            Inner::MinNorm(s) => s.analyze(pattern)?,
            Inner::None => {}
        }
        self.inner = inner;
        Ok(())
    }

    fn factor(&mut self, slots: &[f64]) -> Result<(), SolverError> {
        let not_ready = Err(SolverError::NotReady { missing: "analyze" });
        dispatch!(&mut self.inner, s => s.factor(slots), not_ready)
    }

    fn solve(&mut self, b: &[f64], x: &mut [f64]) -> Result<(), SolverError> {
        let not_ready = Err(SolverError::NotReady { missing: "analyze" });
        dispatch!(&mut self.inner, s => s.solve(b, x), not_ready)
    }

    fn nrows(&self) -> usize {
        dispatch!(&self.inner, s => s.nrows(), 0)
    }

    fn ncols(&self) -> usize {
        dispatch!(&self.inner, s => s.ncols(), 0)
    }

    fn rank(&self) -> Option<usize> {
        dispatch!(&self.inner, s => s.rank(), None)
    }

    fn dependent_equations(&self) -> &[usize] {
        dispatch!(&self.inner, s => s.dependent_equations(), &[])
    }

    fn name(&self) -> &'static str {
        dispatch!(&self.inner, s => s.name(), "auto (not analyzed)")
    }
}
