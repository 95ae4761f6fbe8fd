//! Rank-revealing analysis for redundant constraints, and the minimum-norm solver built on it.
//!
//! # Method
//! Let `J` be `m × n`. Columns are first scaled by powers of two so that each has largest entry
//! about 1 (`J D_c`, optional, see [`RankOptions::equilibrate_columns`]). Each row is then divided
//! by its Euclidean norm (`D J`, `D` diagonal; `D_c` is left out of the formulas below): row
//! scaling does not change which rows are dependent, and it makes the tolerance independent of
//! units (a constraint in millimetres and one in radians weigh the same). Then the transpose is
//! factored with Householder QR and column pivoting (Businger–Golub; Golub & Van Loan,
//! *Matrix Computations*, 4th ed., §5.4.2):
//!
//! ```text
//!   (D J)ᵀ P = Q R,      R = [R11 R12; 0 R22],   R11 r × r
//! ```
//!
//! Column `k` of `(D J)ᵀ` is equation `k`. The pivoting picks, at each step, an equation whose
//! part orthogonal to the equations already chosen is large: among those within
//! [`RankOptions::preference_threshold`] of the largest, the lowest-numbered, so that the choice
//! is deterministic, independent of units, and drops the *last* equations of each dependent group
//! (the caller decides which equations go by their order). It stops when the largest orthogonal
//! part falls below the tolerance. The `r` chosen equations are
//! independent; the other `m − r` are reported as dependent (redundant). With unit rows the
//! tolerance is simply relative: `tol = max(relative_tolerance, 10 · max(m, n) · ε)`.
//!
//! # Minimum-norm least-squares solution
//! Dropping `R22` (below the tolerance), `Pᵀ (D J) ≈ S Q1ᵀ` with `S = [R11 R12]ᵀ` (`m × r`, full
//! column rank) and `Q1` the first `r` columns of `Q`. The solver returns
//!
//! ```text
//!   x = Q1 y,   y = argmin ‖S y − Pᵀ D b‖   (a second Householder QR, of S)
//! ```
//!
//! which is the minimum-norm least-squares solution `x = (D J)⁺ D b` (Golub & Van Loan §5.5, a
//! complete orthogonal decomposition). When the rows are independent (`r = m`) this reduces to a
//! forward substitution with `R11ᵀ`. Consequences:
//! * under-determined (`m < n`, assembly of an under-driven mechanism): the step that moves the
//!   unknowns least;
//! * redundant and consistent (on the constraint manifold): every equation is satisfied;
//! * redundant and inconsistent (a Newton iterate off the manifold of a redundant mechanism, where
//!   the Jacobian is usually of full rank): the Gauss-Newton step, which converges quadratically to
//!   a zero-residual solution.
//!
//! # When to run it
//! Redundant constraints are exactly dependent only on the constraint manifold. Run the analysis
//! at an assembled configuration (residual small compared with the tolerance), not at a rough
//! initial guess, where the Jacobian of a redundant mechanism usually has full row rank.

use crate::error::{NonFiniteLocation, SolverError};
use crate::linear::LinearSolver;
use crate::pattern::{check_len, SparsityPattern};

/// Options of the rank analysis.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RankOptions {
    /// An equation whose unit-normalised row has a component orthogonal to the independent rows
    /// smaller than this is dependent. Default `1e-9`: loose enough for a configuration assembled
    /// to a residual of about `1e-10`, tight enough not to flag a well-posed mechanism away from
    /// singular positions.
    pub relative_tolerance: f64,
    /// Scale each column (unknown) by a power of two so that its largest entry is about 1 before
    /// the rows are normalized. `RankOptions::default()` has it on: the rank decision then does
    /// not depend on the units of the unknowns. [`MinNormQr::new`] turns it off, because it also
    /// changes the norm that the minimum-norm solution minimizes (to `‖D_c⁻¹ x‖`, a metric that
    /// depends on the Jacobian's values); [`Newton`](crate::Newton) instead hands the solver
    /// unknowns already divided by the caller's unknown scales, so the step minimizes `‖U⁻¹ Δq‖`.
    pub equilibrate_columns: bool,
    /// Pivot preference: among the remaining rows whose part orthogonal to the rows already
    /// chosen is at least this fraction of the largest, the lowest-numbered is chosen. Default
    /// `0.01`: the dependent rows reported are then the last ones of each dependent group (the
    /// caller controls which equations are dropped by ordering them), independently of units.
    /// `1.0` is classical maximum-norm pivoting (best conditioned `R11`).
    pub preference_threshold: f64,
}

impl Default for RankOptions {
    fn default() -> Self {
        Self {
            relative_tolerance: 1e-9,
            equilibrate_columns: true,
            preference_threshold: 0.01,
        }
    }
}

/// Matrices with at least this many columns (unknowns) are analyzed by the sparse method in
/// [`RankAnalysis::compute_auto`]; below it the dense QR is as fast.
pub const SPARSE_RANK_MIN_UNKNOWNS: usize = 300;

/// Result of a rank analysis of an `m × n` Jacobian.
#[derive(Debug, Clone, PartialEq)]
pub struct RankAnalysis {
    nrows: usize,
    ncols: usize,
    rank: usize,
    independent_rows: Vec<usize>,
    dependent_rows: Vec<usize>,
    tolerance: f64,
    pivots: Vec<f64>,
}

impl RankAnalysis {
    /// Analyzes the matrix with slot values `slots` of `pattern`. Allocates `m · n` doubles: meant
    /// for setup (once per mechanism), not for every step.
    ///
    /// # Errors
    /// [`SolverError::DimensionMismatch`], [`SolverError::NonFinite`].
    pub fn compute(
        pattern: &SparsityPattern,
        slots: &[f64],
        options: RankOptions,
    ) -> Result<Self, SolverError> {
        let mut qr = PivotedQr::new(pattern.nrows(), pattern.ncols());
        qr.factor(pattern, slots, options)?;
        Ok(qr.analysis())
    }

    /// Assembles a result (for the sparse analysis).
    pub(crate) fn from_parts(
        (nrows, ncols): (usize, usize),
        independent_rows: Vec<usize>,
        dependent_rows: Vec<usize>,
        tolerance: f64,
        pivots: Vec<f64>,
    ) -> Self {
        Self {
            nrows,
            ncols,
            rank: independent_rows.len(),
            independent_rows,
            dependent_rows,
            tolerance,
            pivots,
        }
    }

    /// Rows (equations) of the matrix.
    pub fn nrows(&self) -> usize {
        self.nrows
    }

    /// Columns (unknowns) of the matrix.
    pub fn ncols(&self) -> usize {
        self.ncols
    }

    /// Numerical rank.
    pub fn rank(&self) -> usize {
        self.rank
    }

    /// Number of redundant equations, `m − rank`.
    pub fn redundancy(&self) -> usize {
        self.nrows - self.rank
    }

    /// Degrees of freedom left by the equations, `n − rank`.
    pub fn degrees_of_freedom(&self) -> usize {
        self.ncols - self.rank
    }

    /// Independent equations, increasing. Pass them to
    /// [`SparsityPattern::select_rows`] to drop the others once.
    pub fn independent_rows(&self) -> &[usize] {
        &self.independent_rows
    }

    /// Dependent (redundant) equations, increasing.
    pub fn dependent_rows(&self) -> &[usize] {
        &self.dependent_rows
    }

    /// Tolerance that was applied (relative to unit rows).
    pub fn tolerance(&self) -> f64 {
        self.tolerance
    }

    /// `|R_kk|` in pivot order, one per step performed (rank-revealing gap: the first `rank` are
    /// above the tolerance; the next, if any, is below).
    pub fn pivots(&self) -> &[f64] {
        &self.pivots
    }
}

/// Householder QR with column pivoting of `(D J)ᵀ`, all buffers preallocated.
#[derive(Debug, Clone)]
struct PivotedQr {
    m: usize,
    n: usize,
    /// `(D J)ᵀ`, n × m column-major; after factor: R in the upper triangle, reflectors below.
    a: Vec<f64>,
    tau: Vec<f64>,
    perm: Vec<usize>,
    row_scale: Vec<f64>,
    col_scale: Vec<f64>,
    norms: Vec<f64>,
    rank: usize,
    tol: f64,
    pivots_len: usize,
    pivots: Vec<f64>,
    /// `S = R[:r, :]ᵀ` (m × r, column-major) and its QR, for the least-squares solve when r < m.
    s: Vec<f64>,
    tau2: Vec<f64>,
    work: Vec<f64>,
    /// n entries: Qᵀ y of [`PivotedQr::solve_transpose`].
    work_n: Vec<f64>,
}

/// x ← (I − τ v vᵀ) x for the Householder vector v = [1; `tail`] (the unit first entry implied,
/// as the factors store it). No allocation.
#[inline]
fn reflect(tail: &[f64], tau: f64, x: &mut [f64]) {
    let (head, rest) = x.split_at_mut(1);
    let w = head[0]
        + tail
            .iter()
            .zip(rest.iter())
            .map(|(a, b)| a * b)
            .sum::<f64>();
    let tw = tau * w;
    head[0] -= tw;
    for (xi, vi) in rest.iter_mut().zip(tail) {
        *xi -= tw * vi;
    }
}

/// Householder QR (no pivoting) of a column-major `rows × cols` matrix in place, `rows ≥ cols`.
/// R in the upper triangle, reflectors (unit first entry implied) below, scalars in `tau`.
fn householder_in_place(a: &mut [f64], rows: usize, cols: usize, tau: &mut [f64]) {
    for k in 0..cols {
        let (head, tail) = a.split_at_mut((k + 1) * rows);
        let col = &mut head[k * rows + k..(k + 1) * rows];
        let norm = col.iter().map(|v| v * v).sum::<f64>().sqrt();
        if norm == 0.0 {
            tau[k] = 0.0;
            continue;
        }
        let alpha = col[0];
        let beta = if alpha >= 0.0 { -norm } else { norm };
        let v0 = alpha - beta;
        for v in col[1..].iter_mut() {
            *v /= v0;
        }
        let t = (beta - alpha) / beta;
        col[0] = beta;
        tau[k] = t;
        let v = &col[1..];
        for c in tail.chunks_exact_mut(rows) {
            let c = &mut c[k..];
            let w = c[0] + v.iter().zip(&c[1..]).map(|(a, b)| a * b).sum::<f64>();
            let tw = t * w;
            c[0] -= tw;
            for (ci, vi) in c[1..].iter_mut().zip(v) {
                *ci -= tw * vi;
            }
        }
    }
}

impl PivotedQr {
    fn new(m: usize, n: usize) -> Self {
        let k = m.min(n);
        Self {
            m,
            n,
            a: vec![0.0; m * n],
            tau: vec![0.0; k],
            perm: (0..m).collect(),
            row_scale: vec![0.0; m],
            col_scale: vec![1.0; n],
            norms: vec![0.0; m],
            rank: 0,
            tol: 0.0,
            pivots_len: 0,
            pivots: vec![0.0; (k + 1).min(m)],
            s: vec![0.0; m * k],
            tau2: vec![0.0; k],
            work: vec![0.0; m],
            work_n: vec![0.0; n],
        }
    }

    fn factor(
        &mut self,
        pattern: &SparsityPattern,
        slots: &[f64],
        options: RankOptions,
    ) -> Result<(), SolverError> {
        check_len("pattern rows", self.m, pattern.nrows())?;
        check_len("pattern columns", self.n, pattern.ncols())?;
        pattern.check_finite(slots)?;
        pattern.to_dense_transpose(slots, &mut self.a)?;
        let (m, n) = (self.m, self.n);
        self.tol = options
            .relative_tolerance
            .max(10.0 * (m.max(n) as f64) * f64::EPSILON);
        self.col_scale.fill(1.0);
        if options.equilibrate_columns {
            self.col_scale.fill(0.0);
            for col in self.a.chunks_exact(n.max(1)) {
                for (c, v) in self.col_scale.iter_mut().zip(col) {
                    *c = c.max(v.abs());
                }
            }
            for c in self.col_scale.iter_mut() {
                *c = if *c > 0.0 && c.is_finite() {
                    2f64.powi(-(c.log2().round() as i32))
                } else {
                    1.0
                };
            }
            for col in self.a.chunks_exact_mut(n.max(1)) {
                for (v, c) in col.iter_mut().zip(&self.col_scale) {
                    *v *= c;
                }
            }
        }
        for i in 0..m {
            let col = &mut self.a[i * n..(i + 1) * n];
            let norm = col.iter().map(|v| v * v).sum::<f64>().sqrt();
            let s = if norm > 0.0 { 1.0 / norm } else { 0.0 };
            col.iter_mut().for_each(|v| *v *= s);
            self.row_scale[i] = s;
            self.perm[i] = i;
        }
        self.rank = 0;
        self.pivots_len = 0;
        let kmax = m.min(n);
        for k in 0..=kmax {
            if k == m {
                break;
            }
            // Remaining column norms (rows k..n of columns k..m).
            let mut best = 0.0f64;
            for j in k..m {
                let col = &self.a[j * n + k..(j + 1) * n];
                let s = col.iter().map(|v| v * v).sum::<f64>().sqrt();
                self.norms[j] = s;
                best = best.max(s);
            }
            if self.pivots_len < self.pivots.len() {
                self.pivots[self.pivots_len] = best;
                self.pivots_len += 1;
            }
            if k == kmax || best <= self.tol {
                break;
            }
            // Lowest original row index among near-maximal candidates.
            let threshold = (options.preference_threshold.clamp(0.0, 1.0) * best).max(self.tol);
            let mut p = usize::MAX;
            for j in k..m {
                if self.norms[j] >= threshold && (p == usize::MAX || self.perm[j] < self.perm[p]) {
                    p = j;
                }
            }
            if p != k {
                for i in 0..n {
                    self.a.swap(k * n + i, p * n + i);
                }
                self.perm.swap(k, p);
                self.norms.swap(k, p);
            }
            // Householder reflector for a[k..n, k].
            let (head, tail) = self.a.split_at_mut((k + 1) * n);
            let col = &mut head[k * n + k..(k + 1) * n];
            let alpha = col[0];
            let norm = self.norms[k];
            let beta = if alpha >= 0.0 { -norm } else { norm };
            let v0 = alpha - beta;
            for v in col[1..].iter_mut() {
                *v /= v0;
            }
            let tau = (beta - alpha) / beta;
            col[0] = beta;
            self.tau[k] = tau;
            let v = &col[1..];
            for j in 0..(m - k - 1) {
                let c = &mut tail[j * n + k..(j + 1) * n];
                let w = c[0] + v.iter().zip(&c[1..]).map(|(a, b)| a * b).sum::<f64>();
                let tw = tau * w;
                c[0] -= tw;
                for (ci, vi) in c[1..].iter_mut().zip(v) {
                    *ci -= tw * vi;
                }
            }
            self.rank = k + 1;
        }
        let r = self.rank;
        if r < m && r > 0 {
            // S = R[:r, :]ᵀ: row i of S is column i of R (pivot order), entries k ≤ min(i, r−1).
            let s = &mut self.s[..m * r];
            for k in 0..r {
                for i in 0..m {
                    s[k * m + i] = if k <= i { self.a[i * n + k] } else { 0.0 };
                }
            }
            householder_in_place(s, m, r, &mut self.tau2[..r]);
        }
        Ok(())
    }

    fn analysis(&self) -> RankAnalysis {
        let mut independent_rows = self.perm[..self.rank].to_vec();
        independent_rows.sort_unstable();
        let mut dependent_rows = self.perm[self.rank..].to_vec();
        dependent_rows.sort_unstable();
        RankAnalysis {
            nrows: self.m,
            ncols: self.n,
            rank: self.rank,
            independent_rows,
            dependent_rows,
            tolerance: self.tol,
            pivots: self.pivots[..self.pivots_len].to_vec(),
        }
    }

    /// Minimum-norm least-squares solution (see the module docs). No allocation.
    fn solve(&mut self, b: &[f64], x: &mut [f64]) {
        let (m, n, r) = (self.m, self.n, self.rank);
        if r < m {
            // y = argmin ‖S y − c‖ with c = P (D b): apply Q2ᵀ, back-substitute R2.
            let s = &self.s[..m * r];
            let c = &mut self.work;
            for (i, ci) in c.iter_mut().enumerate() {
                let row = self.perm[i];
                *ci = self.row_scale[row] * b[row];
            }
            for k in 0..r {
                reflect(&s[k * m + k + 1..(k + 1) * m], self.tau2[k], &mut c[k..]);
            }
            for k in (0..r).rev() {
                let mut acc = c[k];
                for j in k + 1..r {
                    acc -= s[j * m + k] * x[j];
                }
                x[k] = acc / s[k * m + k];
            }
        }
        // Full row rank: forward substitution R11ᵀ y = (D b)_sel, y stored in x[..r].
        for k in 0..if r < m { 0 } else { r } {
            let row = self.perm[k];
            let mut s = self.row_scale[row] * b[row];
            let col = &self.a[k * n..k * n + k];
            for i in 0..k {
                s -= col[i] * x[i];
            }
            x[k] = s / self.a[k * n + k];
        }
        x[r..].fill(0.0);
        // x = H_0 H_1 … H_{r−1} [y; 0]
        for k in (0..r).rev() {
            reflect(
                &self.a[k * n + k + 1..(k + 1) * n],
                self.tau[k],
                &mut x[k..],
            );
        }
        for (xi, c) in x.iter_mut().zip(&self.col_scale) {
            *xi *= c;
        }
    }
}

impl PivotedQr {
    /// The multipliers μ of `Jᵀ μ = y` for a `y` in the row space of J (a minimum-norm
    /// solution's), with the dependent equations' multipliers zero: with μ = D P w,
    /// `(D J)ᵀ P w = Q R w = y`, so `R11 w₁ = (Qᵀ y)[..r]` and w₂ = 0. No allocation.
    fn solve_transpose(&mut self, y: &[f64], mu: &mut [f64]) {
        let (n, r) = (self.n, self.rank);
        let qty = &mut self.work_n;
        for ((q, yi), c) in qty.iter_mut().zip(y).zip(&self.col_scale) {
            *q = yi * c;
        }
        // Qᵀ y = H_{r−1} … H_0 y.
        for k in 0..r {
            reflect(
                &self.a[k * n + k + 1..(k + 1) * n],
                self.tau[k],
                &mut qty[k..],
            );
        }
        // R11 w₁ = (Qᵀ y)[..r]: R[i, k] = a[k n + i] for i ≤ k.
        for k in (0..r).rev() {
            let mut acc = qty[k];
            for j in k + 1..r {
                acc -= self.a[j * n + k] * qty[j];
            }
            qty[k] = acc / self.a[k * n + k];
        }
        mu.fill(0.0);
        for k in 0..r {
            let row = self.perm[k];
            mu[row] = self.row_scale[row] * qty[k];
        }
    }
}

impl MinNormQr {
    /// The multipliers μ of `Jᵀ μ = y` with the last factorization, for `y` in the row space
    /// of J (for instance a [`solve`](LinearSolver::solve)'s minimum-norm solution, which is
    /// `Jᵀ μ` for the μ of the least-norm problem's optimality conditions); the equations found
    /// dependent get μ = 0. `y` has `ncols` entries, `mu` `nrows`. No allocation.
    ///
    /// # Errors
    /// [`SolverError::NotReady`], [`SolverError::DimensionMismatch`].
    pub fn solve_transpose(&mut self, y: &[f64], mu: &mut [f64]) -> Result<(), SolverError> {
        if !self.factored {
            return Err(SolverError::NotReady { missing: "factor" });
        }
        check_len("right-hand side", self.qr.n, y.len())?;
        check_len("multipliers", self.qr.m, mu.len())?;
        self.qr.solve_transpose(y, mu);
        Ok(())
    }
}

/// Rank-revealing linear solver for any shape: returns the minimum-norm least-squares solution,
/// which satisfies every equation of a consistent redundant system (see the module docs).
///
/// Dense (`O(m n min(m, n))` per factorization): meant for small and medium systems, for
/// assembly of under-driven mechanisms, and as the fallback when the LU members report
/// [`SolverError::Singular`]. For large redundant systems, run a [`RankAnalysis`] once, drop the
/// dependent rows with [`SparsityPattern::select_rows`], and use the sparse LU on the rest.
#[derive(Debug, Clone)]
pub struct MinNormQr {
    pattern: Option<SparsityPattern>,
    qr: PivotedQr,
    options: RankOptions,
    factored: bool,
}

impl Default for MinNormQr {
    fn default() -> Self {
        Self::new()
    }
}

impl MinNormQr {
    /// A solver with default [`RankOptions`] except `equilibrate_columns = false`: the minimum
    /// norm is the Euclidean norm of the unknowns as given.
    pub fn new() -> Self {
        Self::with_options(RankOptions {
            equilibrate_columns: false,
            ..RankOptions::default()
        })
    }

    /// A solver with the given rank tolerance.
    pub fn with_options(options: RankOptions) -> Self {
        Self {
            pattern: None,
            qr: PivotedQr::new(0, 0),
            options,
            factored: false,
        }
    }

    /// The rank analysis of the last factorization (allocates: for reports, not hot loops).
    pub fn analysis(&self) -> Option<RankAnalysis> {
        self.factored.then(|| self.qr.analysis())
    }
}

impl LinearSolver for MinNormQr {
    fn analyze(&mut self, pattern: &SparsityPattern) -> Result<(), SolverError> {
        self.qr = PivotedQr::new(pattern.nrows(), pattern.ncols());
        self.pattern = Some(pattern.clone());
        self.factored = false;
        Ok(())
    }

    fn factor(&mut self, slots: &[f64]) -> Result<(), SolverError> {
        self.factored = false;
        let pattern = self
            .pattern
            .as_ref()
            .ok_or(SolverError::NotReady { missing: "analyze" })?;
        self.qr.factor(pattern, slots, self.options)?;
        self.factored = true;
        Ok(())
    }

    fn solve(&mut self, b: &[f64], x: &mut [f64]) -> Result<(), SolverError> {
        if !self.factored {
            return Err(SolverError::NotReady { missing: "factor" });
        }
        check_len("right-hand side", self.qr.m, b.len())?;
        check_len("solution", self.qr.n, x.len())?;
        if let Some(index) = b.iter().position(|v| !v.is_finite()) {
            return Err(SolverError::NonFinite {
                location: NonFiniteLocation::RightHandSide { index },
                iteration: None,
            });
        }
        self.qr.solve(b, x);
        if let Some(unknown) = x.iter().position(|v| !v.is_finite()) {
            return Err(SolverError::NonFinite {
                location: NonFiniteLocation::Solution { unknown },
                iteration: None,
            });
        }
        Ok(())
    }

    fn nrows(&self) -> usize {
        self.qr.m
    }

    fn ncols(&self) -> usize {
        self.qr.n
    }

    fn rank(&self) -> Option<usize> {
        self.factored.then_some(self.qr.rank)
    }

    fn dependent_equations(&self) -> &[usize] {
        // perm[rank..] is the dependent set (pivot order, not sorted: sorting would need a buffer).
        if self.factored {
            &self.qr.perm[self.qr.rank..]
        } else {
            &[]
        }
    }

    fn name(&self) -> &'static str {
        "min-norm-qr"
    }
}
