//! Saddle-point systems with a block-diagonal symmetric positive definite top-left, solved by
//! the Schur complement and a sparse Cholesky factorization.
//!
//! # Theory
//! The system (for mechanisms: A = M, B = Φ_v, the augmented equations of motion)
//!
//! ```text
//!   ⎡ A  Bᵀ ⎤ ⎡ x ⎤   ⎡ f ⎤        A = diag(A_1, …, A_N)   (n = N b unknowns, A_k b × b SPD)
//!   ⎣ B  0  ⎦ ⎣ λ ⎦ = ⎣ g ⎦        B   m × n, full row rank
//! ```
//!
//! is eliminated onto the multipliers: the first row gives x = A⁻¹(f − Bᵀλ), and the second then
//! reads
//!
//! ```text
//!   S λ = B A⁻¹ f − g,        S = B A⁻¹ Bᵀ = Σ_k B_k A_k⁻¹ B_kᵀ
//! ```
//!
//! with B_k the b columns of block k. S is m × m, symmetric positive definite exactly when B has
//! full row rank, and factored by a sparse Cholesky S = L Lᵀ (AMD ordering and symbolic
//! analysis by faer at [`analyze`](SchurSolver::analyze); the numeric factorization up-looking on
//! that fixed pattern, each row's pattern precomputed). Each A_k is
//! factored densely, A_k = L_k L_kᵀ; with W_k = L_k⁻¹ B_kᵀ (one column w_r per row r of B that
//! touches block k) every contribution is a Gram matrix, S += W_kᵀ W_k, so the assembled S is
//! exactly symmetric. Rows r and s are coupled in S when they touch a common block; the pattern
//! of S is fixed at [`analyze`](SchurSolver::analyze), which also runs the symbolic Cholesky.
//!
//! The solve, with z_k = L_k⁻¹ f_k:
//!
//! ```text
//!   t_r = Σ_k w_rᵀ z_k − g_r,     λ = S⁻¹ t,     x_k = L_k⁻ᵀ (z_k − Σ_r w_r λ_r)
//! ```
//!
//! Work: O(N b³) for the blocks, O(Σ_k p_k² b) for S (p_k rows touching block k) and a sparse
//! Cholesky of order m, against a sparse LU of order n + m with pivoting for the full matrix.
//!
//! # Conditioning
//! S squares the conditioning of B (κ(S) ≈ κ(A) κ(B)² in the A⁻¹ metric), so a configuration
//! where B is close to rank deficient (a four-bar passing a singular position) loses twice as
//! many digits as an LU of the full matrix; and S inherits the conditioning of A, since A⁻¹
//! weights the columns of B (a point mass with a negligible inertia, J' = 10⁻¹³ m I, makes S
//! mix terms 10¹³ apart). [`factor`](SchurSolver::factor) therefore checks every pivot of S
//! relative to its diagonal entry, L_jj² > τ S_jj (the ratio is the squared sine of the angle
//! between a row and the span of the rows eliminated before it, in the A⁻¹ metric; it does not
//! depend on row scaling), and every pivot of a block relative to the block's largest diagonal
//! entry, (L_k)_jj² > τ max_i (A_k)_ii (a bound on the block's condition number; scale
//! dependent across a block's units, kg against kg m², but only pathological blocks come near
//! it), and fails with [`SolverError::Singular`] below τ so that the caller can fall back to an
//! LU of the full matrix, which pivots and equilibrates. It never returns NaN.
//!
//! The default τ = 1e-4 comes from the constraint rows: the solution satisfies B x = g only up
//! to the residual of the S solve, about u κ(S) ≈ u / (smallest pivot ratio) relative (u the
//! unit roundoff), where the LU of the full matrix, whose condition is about the square root,
//! keeps it near u / √ratio. τ = 1e-4 keeps it near 1e-12, below the integrators' 1e-10
//! tolerances. Measured: the IFToMM A02 four-bar (N = 2) passes its singular horizontal
//! positions with τ = 1e-4 but fails one with τ = 1e-5 (generalized-α, the file's settings).
//!
//! The ratio also measures global conditioning, not only near dependence: for a chain of N
//! equal links (spherical joints, the first to the ground) the smallest ratio is about 1/(2N),
//! the last pivot of a path Laplacian (measured at rest: 1.7e-2, 5.0e-3, 1.7e-3, 5.0e-4 for
//! N = 30, 100, 300, 1,000), and κ(S) grows like N². Chains beyond about 5,000 links are
//! therefore refused at τ = 1e-4 and solved by the caller's LU (10,000 links: no gain).
//!
//! # Allocation
//! [`analyze`](SchurSolver::analyze) allocates everything; [`factor`](SchurSolver::factor) and
//! [`solve`](SchurSolver::solve) do not (the numeric factorization works in a preallocated
//! dense vector of length m; only error values allocate).

use crate::error::{NonFiniteLocation, SolverError};
use crate::pattern::check_len;
use faer::sparse::linalg::cholesky::{
    factorize_symbolic_cholesky, CholeskySymbolicParams, SymbolicCholeskyRaw, SymmetricOrdering,
};
use faer::sparse::linalg::SupernodalThreshold;
use faer::sparse::SymbolicSparseColMat;
use faer::Side;

/// Default relative pivot tolerance τ of S in [`SchurSolver`] (see the module docs).
pub const DEFAULT_SCHUR_PIVOT_TOLERANCE: f64 = 1e-4;

/// Default block tolerance τ_A of [`SchurSolver`]: blocks of condition up to about 1e8 (see the
/// module docs).
pub const DEFAULT_BLOCK_PIVOT_TOLERANCE: f64 = 1e-8;

/// Solver for `[A Bᵀ; B 0] [x; λ] = [f; g]` with `A` block diagonal (equal square SPD blocks)
/// by the Schur complement `S = B A⁻¹ Bᵀ` (see the module docs).
///
/// Call order: [`analyze`](Self::analyze) once with the block size and the entries of `B`, then
/// any sequence of [`factor`](Self::factor) (blocks of `A`, values of `B`) and
/// [`solve`](Self::solve) (each uses the last successful `factor`, including its `B`).
#[derive(Debug)]
pub struct SchurSolver {
    /// Block size b, number of blocks N, rows m of B, number of B values.
    shape: Shape,
    /// τ of S and τ_A of the blocks.
    tolerances: PivotTolerances,
    /// The blocks of A and their Cholesky factors L_k.
    a: BlockFactors,
    /// The block-row pairs of B and W = L⁻¹ Bᵀ.
    pairs: BlockRowPairs,
    /// S = B A⁻¹ Bᵀ: pattern, values and ordering.
    s: SchurMatrix,
    /// The Cholesky factor L of S.
    l: CholeskyFactor,
    /// Scratch of the factorization and the solve.
    work: Work,
    /// Smallest relative pivot of the last factorization attempt (NaN before).
    min_pivot_ratio: f64,
    /// Whether the last factorization succeeded.
    factored: bool,
}

/// The dimensions of the system.
#[derive(Debug)]
struct Shape {
    /// Block size b.
    block: usize,
    /// Number of blocks N.
    nblocks: usize,
    /// Rows of B (m).
    m: usize,
    /// Number of B values (entries as given to `analyze`).
    nb_values: usize,
}

/// The relative pivot tolerances (see the module docs).
#[derive(Debug)]
struct PivotTolerances {
    /// τ: a pivot of S fails when `L_jj² ≤ τ S_jj`.
    pivot: f64,
    /// τ_A: a block fails when `(L_k)_jj² ≤ τ_A max_i (A_k)_ii`.
    block: f64,
}

/// The blocks A_k and their factors.
#[derive(Debug)]
struct BlockFactors {
    /// Cholesky factors L_k of the blocks, column-major b × b each (lower triangle used).
    fac: Vec<f64>,
    /// The blocks `fac` was computed from, and whether that succeeded.
    prev: Vec<f64>,
    factored: bool,
}

/// B by block-row pairs (k, r): rows r of B touching block k, grouped by block (r in the
/// permuted numbering of S), with their entries, and the columns w_r of W = L⁻¹ Bᵀ.
#[derive(Debug)]
struct BlockRowPairs {
    /// Every block-row pair has its b entries in column order at consecutive value indices
    /// (the caller's layout groups them): gathered by one copy.
    contiguous: bool,
    /// Block k's pairs are `start[k]..start[k + 1]`; `row[p]` is pair p's row.
    start: Vec<usize>,
    row: Vec<usize>,
    /// Entries of each pair: (column within the block, index into the B values).
    entry_start: Vec<usize>,
    entry_col: Vec<usize>,
    entry_val: Vec<usize>,
    /// w = L_k⁻¹ b_r for every pair, b values each.
    w: Vec<f64>,
}

impl BlockRowPairs {
    /// The block-row pairs of B and their entries from B's entries `(row, col)` (value index =
    /// position in the list), pairs grouped by block and sorted by row, entries by column.
    fn lay_out(&mut self, block: usize, nblocks: usize, b_entries: &[(usize, usize)]) {
        // Entries sorted by (block, row, col): the block-row pairs and their entries. Bucketed
        // by block first (a counting sort), so that only each block's few entries are compared.
        let mut order = bucket_by(b_entries.len(), nblocks, |e| b_entries[e].1 / block);
        let mut start = 0;
        while start < order.len() {
            let k = b_entries[order[start]].1 / block;
            let len = order[start..]
                .iter()
                .take_while(|&&e| b_entries[e].1 / block == k)
                .count();
            order[start..start + len].sort_unstable_by_key(|&e| (b_entries[e].0, b_entries[e].1));
            start += len;
        }
        self.start = vec![0; nblocks + 1];
        self.row.clear();
        self.entry_start = vec![0];
        self.entry_col.clear();
        self.entry_val.clear();
        let mut last: Option<(usize, usize)> = None;
        for &e in &order {
            let (r, c) = b_entries[e];
            let k = c / block;
            if last != Some((k, r)) {
                if last.is_some() {
                    self.entry_start.push(self.entry_col.len());
                }
                self.row.push(r);
                self.start[k + 1] += 1;
                last = Some((k, r));
            }
            self.entry_col.push(c % block);
            self.entry_val.push(e);
        }
        if last.is_some() {
            self.entry_start.push(self.entry_col.len());
        }
        for k in 0..nblocks {
            self.start[k + 1] += self.start[k];
        }
    }
}

/// S in the permuted numbering.
#[derive(Debug)]
struct SchurMatrix {
    /// For every block, its pairs (p, q) with q ≤ p in loop order: the slot of S they add to.
    target: Vec<usize>,
    /// Upper triangle of S in the permuted numbering (compressed columns) and its values.
    symbolic: Option<SymbolicSparseColMat<usize>>,
    values: Vec<f64>,
    /// Slot of S_jj in `values`, per (permuted) row.
    diag: Vec<usize>,
    /// The AMD ordering: row `perm_fwd[j]` of B is row j of S as laid out; `perm_inv` inverse.
    perm_fwd: Vec<usize>,
    perm_inv: Vec<usize>,
}

/// The Cholesky factor L of S on the pattern fixed at `analyze`.
#[derive(Debug)]
struct CholeskyFactor {
    /// Structure of L (compressed columns, diagonal first) and its values.
    col_ptr: Vec<usize>,
    row_idx: Vec<usize>,
    values: Vec<f64>,
    /// 1 / L_jj.
    inv_diag: Vec<f64>,
    /// Row pattern of L: for row k, the columns i < k with L_ki ≠ 0 in increasing order, each
    /// with the slot of L_ki in `values` (rows `row_start[k]..row_start[k + 1]`).
    row_start: Vec<usize>,
    row_col: Vec<usize>,
    row_slot: Vec<usize>,
}

/// Scratch vectors, sized at `analyze`.
#[derive(Debug)]
struct Work {
    /// λ in the permuted numbering (solve scratch).
    lambda: Vec<f64>,
    /// Dense scratch of the numeric factorization (m, zero between uses).
    x: Vec<f64>,
}

impl Default for SchurSolver {
    fn default() -> Self {
        Self::new()
    }
}

impl SchurSolver {
    /// A solver with the default pivot tolerance ([`DEFAULT_SCHUR_PIVOT_TOLERANCE`]).
    pub fn new() -> Self {
        Self {
            shape: Shape {
                block: 0,
                nblocks: 0,
                m: 0,
                nb_values: 0,
            },
            tolerances: PivotTolerances {
                pivot: DEFAULT_SCHUR_PIVOT_TOLERANCE,
                block: DEFAULT_BLOCK_PIVOT_TOLERANCE,
            },
            a: BlockFactors {
                fac: Vec::new(),
                prev: Vec::new(),
                factored: false,
            },
            pairs: BlockRowPairs {
                contiguous: false,
                start: vec![0],
                row: Vec::new(),
                entry_start: vec![0],
                entry_col: Vec::new(),
                entry_val: Vec::new(),
                w: Vec::new(),
            },
            s: SchurMatrix {
                target: Vec::new(),
                symbolic: None,
                values: Vec::new(),
                diag: Vec::new(),
                perm_fwd: Vec::new(),
                perm_inv: Vec::new(),
            },
            l: CholeskyFactor {
                col_ptr: Vec::new(),
                row_idx: Vec::new(),
                values: Vec::new(),
                inv_diag: Vec::new(),
                row_start: vec![0],
                row_col: Vec::new(),
                row_slot: Vec::new(),
            },
            work: Work {
                lambda: Vec::new(),
                x: Vec::new(),
            },
            min_pivot_ratio: f64::NAN,
            factored: false,
        }
    }

    /// Sets the relative pivot tolerance τ (a pivot fails when `L_jj² ≤ τ S_jj`).
    pub fn with_pivot_tolerance(mut self, tol: f64) -> Self {
        self.tolerances.pivot = tol;
        self
    }

    /// Sets the block tolerance τ_A (a block fails when `(L_k)_jj² ≤ τ_A max_i (A_k)_ii`).
    pub fn with_block_tolerance(mut self, tol: f64) -> Self {
        self.tolerances.block = tol;
        self
    }

    /// Lays out the system: `nblocks` diagonal blocks of size `block` (n = `nblocks · block`
    /// unknowns), `m` rows of B whose entries `(row, col)` are listed in the order their values
    /// will be given to [`factor`](Self::factor) (duplicates are summed). Computes the pattern of
    /// S, its fill-reducing ordering and symbolic Cholesky factorization, and every buffer.
    ///
    /// # Errors
    /// [`SolverError::EntryOutOfBounds`] for an entry outside B; [`SolverError::Backend`] if
    /// faer's symbolic analysis fails.
    pub fn analyze(
        &mut self,
        block: usize,
        nblocks: usize,
        m: usize,
        b_entries: &[(usize, usize)],
    ) -> Result<(), SolverError> {
        self.factored = false;
        let n = block * nblocks;
        for (index, &(row, col)) in b_entries.iter().enumerate() {
            if row >= m || col >= n {
                return Err(SolverError::EntryOutOfBounds {
                    index,
                    row,
                    col,
                    nrows: m,
                    ncols: n,
                });
            }
        }
        self.pairs.lay_out(block, nblocks, b_entries);
        // Pattern of the lower triangle of S: the diagonal, and (max, min) of every two rows
        // touching a common block.
        let mut lower: Vec<(usize, usize)> = (0..m).map(|r| (r, r)).collect();
        for k in 0..nblocks {
            let rows = &self.pairs.row[self.pairs.start[k]..self.pairs.start[k + 1]];
            for (p, &rp) in rows.iter().enumerate() {
                for &rq in &rows[..=p] {
                    lower.push((rp.max(rq), rp.min(rq)));
                }
            }
        }
        let params = CholeskySymbolicParams {
            supernodal_flop_ratio_threshold: SupernodalThreshold::FORCE_SIMPLICIAL,
            ..Default::default()
        };
        // The fill-reducing (AMD) ordering, computed once on the lower triangle; then S is laid
        // out directly in the permuted numbering (upper triangle, faer's simplicial input), so
        // that neither the factorization nor the solve permutes anything.
        let (perm_fwd, perm_inv) = {
            let (sym, _) = csc(m, lower.clone());
            let amd = factorize_symbolic_cholesky(
                sym.as_ref(),
                Side::Lower,
                SymmetricOrdering::Amd,
                params,
            )
            .map_err(|e| SolverError::Backend(format!("AMD ordering: {e:?}")))?;
            match amd.perm() {
                Some(p) => (p.arrays().0.to_vec(), p.arrays().1.to_vec()),
                None => ((0..m).collect(), (0..m).collect()),
            }
        };
        for r in &mut self.pairs.row {
            *r = perm_inv[*r];
        }
        let inv = &perm_inv;
        let upper = |(r, c): (usize, usize)| {
            let (a, b) = (inv[r], inv[c]);
            (a.min(b), a.max(b))
        };
        let (symbolic, slot) = csc(m, lower.iter().map(|&e| upper(e)).collect());
        self.s.diag = (0..m).map(|j| slot(j, j)).collect();
        self.s.target = lower[m..]
            .iter()
            .map(|&e| {
                let (r, c) = upper(e);
                slot(r, c)
            })
            .collect();
        let cholesky = factorize_symbolic_cholesky(
            symbolic.as_ref(),
            Side::Upper,
            SymmetricOrdering::Identity,
            params,
        )
        .map_err(|e| SolverError::Backend(format!("symbolic Cholesky: {e:?}")))?;
        let SymbolicCholeskyRaw::Simplicial(simplicial) = cholesky.raw() else {
            return Err(SolverError::Backend(
                "Schur complement: expected a simplicial Cholesky".into(),
            ));
        };
        self.l.col_ptr = simplicial.col_ptr().to_vec();
        self.l.row_idx = simplicial.row_idx().to_vec();
        (self.l.row_start, self.l.row_col, self.l.row_slot) =
            row_pattern(m, &self.l.col_ptr, &self.l.row_idx);
        self.work.x = vec![0.0; m];
        self.l.values = vec![0.0; cholesky.len_val()];
        self.l.inv_diag = vec![0.0; m];
        self.s.values = vec![0.0; symbolic.row_idx().len()];
        self.work.lambda = vec![0.0; m];
        self.s.perm_fwd = perm_fwd;
        self.s.perm_inv = perm_inv;
        self.s.symbolic = Some(symbolic);
        self.shape.block = block;
        self.shape.nblocks = nblocks;
        self.shape.m = m;
        self.shape.nb_values = b_entries.len();
        self.a.fac = vec![0.0; nblocks * block * block];
        self.a.prev = vec![0.0; nblocks * block * block];
        self.a.factored = false;
        self.pairs.contiguous = (0..self.pairs.row.len()).all(|p| {
            let (s, e) = (self.pairs.entry_start[p], self.pairs.entry_start[p + 1]);
            e - s == block
                && (s..e).all(|i| {
                    self.pairs.entry_col[i] == i - s
                        && self.pairs.entry_val[i] == self.pairs.entry_val[s] + i - s
                })
        });
        self.pairs.w = vec![0.0; self.pairs.row.len() * block];
        self.min_pivot_ratio = f64::NAN;
        Ok(())
    }

    /// Number of unknowns n (the size of A).
    pub fn num_unknowns(&self) -> usize {
        self.shape.block * self.shape.nblocks
    }

    /// Number of rows m of B (the order of S).
    pub fn num_rows(&self) -> usize {
        self.shape.m
    }

    /// Structurally distinct entries in the lower triangle of S.
    pub fn schur_nnz(&self) -> usize {
        self.s.values.len()
    }

    /// Entries of the Cholesky factor L of S (fill measure).
    pub fn factor_nnz(&self) -> usize {
        self.l.values.len()
    }

    /// Smallest relative pivot `L_jj² / S_jj` of the last factorization attempt (NaN before):
    /// a cheap lower-bound indicator of how close B is to rank deficiency.
    pub fn min_pivot_ratio(&self) -> f64 {
        self.min_pivot_ratio
    }

    /// Factors A (the `nblocks` blocks, each `block × block` column-major, concatenated; only
    /// the lower triangles are read, A_k is taken symmetric) and S = B A⁻¹ Bᵀ with `b` the values
    /// of B's entries in the order given to [`analyze`](Self::analyze). Keeps W = L⁻¹ Bᵀ (so
    /// [`solve`](Self::solve) uses this B). No allocation on success.
    ///
    /// # Errors
    /// [`SolverError::Singular`] when a block of A is not (numerically) positive definite or
    /// too ill-conditioned (with no equations listed) or S is not (B rank deficient, or close to
    /// it relative to the pivot tolerance; the rows whose pivot failed are listed);
    /// [`SolverError::NonFinite`] (a value of A or B, looked for when a pivot fails);
    /// [`SolverError::DimensionMismatch`]; [`SolverError::NotReady`].
    pub fn factor(&mut self, a: &[f64], b: &[f64]) -> Result<(), SolverError> {
        self.factored = false;
        if self.s.symbolic.is_none() {
            return Err(SolverError::NotReady { missing: "analyze" });
        }
        let bs = self.shape.block;
        check_len("block-diagonal values", self.a.fac.len(), a.len())?;
        check_len("constraint values", self.shape.nb_values, b.len())?;
        let (tol, tol_a) = (self.tolerances.pivot, self.tolerances.block);
        // Block kernels unrolled for the mechanisms' block size 6.
        let blocks_ok = if bs == 6 {
            self.assemble::<6>(a, b, tol_a)
        } else {
            self.assemble::<0>(a, b, tol_a)
        };
        // Non-finite inputs make a pivot fail (NaN, or an infinite ratio); they are looked for
        // only then, to name them.
        if !blocks_ok {
            return Err(self
                .non_finite_input(a, b)
                .unwrap_or(SolverError::Singular {
                    dependent_equations: Vec::new(),
                }));
        }
        if let Err(j) = self.numeric_cholesky() {
            self.min_pivot_ratio = 0.0;
            let row = self.s.perm_fwd[j];
            return Err(self
                .non_finite_input(a, b)
                .unwrap_or(SolverError::Singular {
                    dependent_equations: vec![row],
                }));
        }
        let perm_fwd = &self.s.perm_fwd;
        // Relative pivots: the diagonal of L is the first stored entry of each column.
        let mut min_ratio = f64::INFINITY;
        let mut failed = false;
        for j in 0..self.shape.m {
            let l = self.l.values[self.l.col_ptr[j]];
            let sjj = self.s.values[self.s.diag[j]];
            min_ratio = min_ratio.min(l * l / sjj);
            failed |= !pivot_ok(l * l, sjj, tol);
        }
        self.min_pivot_ratio = min_ratio;
        if failed {
            // Error path only (allocates).
            let mut rows: Vec<usize> = (0..self.shape.m)
                .filter(|&j| {
                    let l = self.l.values[self.l.col_ptr[j]];
                    !pivot_ok(l * l, self.s.values[self.s.diag[j]], tol)
                })
                .map(|j| perm_fwd[j])
                .collect();
            rows.sort_unstable();
            return Err(self
                .non_finite_input(a, b)
                .unwrap_or(SolverError::Singular {
                    dependent_equations: rows,
                }));
        }
        self.factored = true;
        Ok(())
    }

    /// Solves `[A Bᵀ; B 0] [x; λ] = [f; g]` with the last factorization: `rhs = [f; g]` and
    /// `sol = [x; λ]` have n + m entries. No allocation on success.
    ///
    /// # Errors
    /// [`SolverError::NotReady`], [`SolverError::DimensionMismatch`], [`SolverError::NonFinite`].
    pub fn solve(&mut self, rhs: &[f64], sol: &mut [f64]) -> Result<(), SolverError> {
        if !self.factored {
            return Err(SolverError::NotReady { missing: "factor" });
        }
        if self.s.symbolic.is_none() {
            return Err(SolverError::NotReady { missing: "analyze" });
        }
        let (bs, n, m) = (self.shape.block, self.num_unknowns(), self.shape.m);
        check_len("right-hand side", n + m, rhs.len())?;
        check_len("solution", n + m, sol.len())?;
        let (x, lambda_out) = sol.split_at_mut(n);
        // z_k = L_k⁻¹ f_k (in x); t = W z − g (in λ, permuted numbering).
        x.copy_from_slice(&rhs[..n]);
        let mut lambda = std::mem::take(&mut self.work.lambda);
        for (l, &r) in lambda.iter_mut().zip(&self.s.perm_fwd) {
            *l = -rhs[n + r];
        }
        if bs == 6 {
            self.solve_forward::<6>(x, &mut lambda);
        } else {
            self.solve_forward::<0>(x, &mut lambda);
        }
        // λ = S⁻¹ t = L⁻ᵀ L⁻¹ t. Column j's entries below the diagonal as zipped slices (one
        // bounds check per column instead of three per entry: most of a small model's solve).
        let (cp, ri, lv) = (&self.l.col_ptr, &self.l.row_idx, &self.l.values);
        let below = |j: usize| {
            let range = cp[j] + 1..cp[j + 1];
            ri[range.clone()].iter().zip(&lv[range])
        };
        for j in 0..m {
            let v = lambda[j] * self.l.inv_diag[j];
            lambda[j] = v;
            for (&r, &l) in below(j) {
                lambda[r] -= l * v;
            }
        }
        for j in (0..m).rev() {
            let mut v = lambda[j];
            for (&r, &l) in below(j) {
                v -= l * lambda[r];
            }
            lambda[j] = v * self.l.inv_diag[j];
        }
        // x_k = L_k⁻ᵀ (z_k − Σ_r w_r λ_r).
        if bs == 6 {
            self.solve_backward::<6>(x, &lambda);
        } else {
            self.solve_backward::<0>(x, &lambda);
        }
        for (o, &j) in lambda_out.iter_mut().zip(&self.s.perm_inv) {
            *o = lambda[j];
        }
        self.work.lambda = lambda;
        // A non-finite right-hand side makes the solution non-finite: looked for only then.
        if let Some(unknown) = sol.iter().position(|v| !v.is_finite()) {
            let location = match rhs.iter().position(|v| !v.is_finite()) {
                Some(index) => NonFiniteLocation::RightHandSide { index },
                None => NonFiniteLocation::Solution { unknown },
            };
            return Err(SolverError::NonFinite {
                location,
                iteration: None,
            });
        }
        Ok(())
    }
}

impl SchurSolver {
    /// The first non-finite value of A or B, as an error naming its entry (error path only).
    fn non_finite_input(&self, a: &[f64], b: &[f64]) -> Option<SolverError> {
        let bs = self.shape.block;
        if let Some(slot) = a.iter().position(|v| !v.is_finite()) {
            let (k, i) = (slot / (bs * bs), slot % (bs * bs));
            return Some(SolverError::NonFinite {
                location: NonFiniteLocation::Jacobian {
                    slot,
                    row: k * bs + i % bs,
                    col: k * bs + i / bs,
                },
                iteration: None,
            });
        }
        let slot = b.iter().position(|v| !v.is_finite())?;
        // The entry's block-row pair: its row of B and column.
        let e = self
            .pairs
            .entry_val
            .iter()
            .position(|&v| v == slot)
            .unwrap_or(0);
        let p = self
            .pairs
            .entry_start
            .partition_point(|&s| s <= e)
            .saturating_sub(1);
        let k = self
            .pairs
            .start
            .partition_point(|&s| s <= p)
            .saturating_sub(1);
        let row = self
            .pairs
            .row
            .get(p)
            .and_then(|&j| self.s.perm_fwd.get(j))
            .copied()
            .unwrap_or(0);
        Some(SolverError::NonFinite {
            location: NonFiniteLocation::Jacobian {
                slot,
                row,
                col: k * bs + self.pairs.entry_col.get(e).copied().unwrap_or(0),
            },
            iteration: None,
        })
    }

    /// The numeric Cholesky factorization S = L Lᵀ on the pattern of L fixed at `analyze`,
    /// up-looking (row k of L from column k of S's upper triangle, Davis, *Direct Methods for
    /// Sparse Linear Systems* §4.2): row k's pattern and the slots its entries go to are
    /// precomputed (`row_pattern`), so nothing symbolic is redone per factorization (faer's
    /// numeric factorization recomputed each row's reach: a quarter of its cost on the
    /// slider-crank). Columns i of row k in increasing order are a topological order (every
    /// column that updates x_i is a smaller one). `Err(j)`: the pivot of row j (permuted
    /// numbering) is not positive (or not a number).
    fn numeric_cholesky(&mut self) -> Result<(), usize> {
        let Some(sym) = self.s.symbolic.as_ref() else {
            return Err(0);
        };
        let (scp, sri) = (sym.col_ptr(), sym.row_idx());
        let (cp, ri) = (&self.l.col_ptr, &self.l.row_idx);
        let lv = &mut self.l.values;
        let x = &mut self.work.x;
        for k in 0..self.shape.m {
            for p in scp[k]..scp[k + 1] {
                x[sri[p]] = self.s.values[p];
            }
            let mut d = x[k];
            x[k] = 0.0;
            for r in self.l.row_start[k]..self.l.row_start[k + 1] {
                let (i, slot) = (self.l.row_col[r], self.l.row_slot[r]);
                let lki = x[i] * self.l.inv_diag[i];
                x[i] = 0.0;
                // Column i's rows between i and k, computed before row k.
                for p in cp[i] + 1..slot {
                    x[ri[p]] -= lv[p] * lki;
                }
                d -= lki * lki;
                lv[slot] = lki;
            }
            if d.is_nan() || d <= 0.0 {
                x.fill(0.0);
                return Err(k);
            }
            let l = d.sqrt();
            lv[cp[k]] = l;
            self.l.inv_diag[k] = 1.0 / l;
        }
        Ok(())
    }

    /// Block size: `B` when it is not 0 (a compile-time size, loops unrolled), else the
    /// analyzed one.
    #[inline(always)]
    fn bs<const B: usize>(&self) -> usize {
        if B == 0 {
            self.shape.block
        } else {
            B
        }
    }

    /// Factors the blocks (L_k, with the reciprocals of their diagonals stored), computes
    /// W = L⁻¹ Bᵀ and assembles S. `false` when a block is not positive definite.
    fn assemble<const B: usize>(&mut self, a: &[f64], b: &[f64], tol: f64) -> bool {
        let bs = self.bs::<B>();
        let bb = bs * bs;
        // The block factors are kept when A is unchanged (a mass matrix: every factorization).
        let reuse = self.a.factored && self.a.prev == a;
        if !reuse {
            self.a.factored = false;
            for k in 0..self.shape.nblocks {
                let lk = &mut self.a.fac[k * bb..(k + 1) * bb];
                lk.copy_from_slice(&a[k * bb..(k + 1) * bb]);
                if !dense_cholesky(lk, bs, tol) {
                    return false;
                }
            }
            self.a.prev.copy_from_slice(a);
            self.a.factored = true;
        }
        self.s.values.fill(0.0);
        let mut target = 0;
        for k in 0..self.shape.nblocks {
            let lk = &self.a.fac[k * bb..(k + 1) * bb];
            let pairs = self.pairs.start[k]..self.pairs.start[k + 1];
            for p in pairs.clone() {
                let wp = &mut self.pairs.w[p * bs..(p + 1) * bs];
                let entries = self.pairs.entry_start[p]..self.pairs.entry_start[p + 1];
                if self.pairs.contiguous {
                    let first = self.pairs.entry_val[entries.start];
                    wp.copy_from_slice(&b[first..first + bs]);
                } else {
                    wp.fill(0.0);
                    for e in entries {
                        wp[self.pairs.entry_col[e]] += b[self.pairs.entry_val[e]];
                    }
                }
                forward(lk, bs, wp);
            }
            for p in pairs.clone() {
                let wp = &self.pairs.w[p * bs..(p + 1) * bs];
                for q in pairs.start..=p {
                    self.s.values[self.s.target[target]] +=
                        dot(wp, &self.pairs.w[q * bs..(q + 1) * bs], bs);
                    target += 1;
                }
            }
        }
        true
    }

    /// x_k ← L_k⁻¹ x_k, λ_r += w_rᵀ x_k.
    fn solve_forward<const B: usize>(&self, x: &mut [f64], lambda: &mut [f64]) {
        let bs = self.bs::<B>();
        let bb = bs * bs;
        for k in 0..self.shape.nblocks {
            let zk = &mut x[k * bs..(k + 1) * bs];
            forward(&self.a.fac[k * bb..(k + 1) * bb], bs, zk);
            for (&r, wp) in self.pairs_of(k, bs) {
                lambda[r] += dot(wp, zk, bs);
            }
        }
    }

    /// x_k ← L_k⁻ᵀ (x_k − Σ_r w_r λ_r).
    fn solve_backward<const B: usize>(&self, x: &mut [f64], lambda: &[f64]) {
        let bs = self.bs::<B>();
        let bb = bs * bs;
        for k in 0..self.shape.nblocks {
            let zk = &mut x[k * bs..(k + 1) * bs];
            for (&r, wp) in self.pairs_of(k, bs) {
                let l = lambda[r];
                for (z, w) in zk.iter_mut().zip(wp) {
                    *z -= w * l;
                }
            }
            backward(&self.a.fac[k * bb..(k + 1) * bb], bs, zk);
        }
    }

    /// Block `k`'s pairs: the row of S each couples to and its column w_r of W = L⁻¹ Bᵀ.
    #[inline(always)]
    fn pairs_of(&self, k: usize, bs: usize) -> impl Iterator<Item = (&usize, &[f64])> {
        let range = self.pairs.start[k]..self.pairs.start[k + 1];
        let w = &self.pairs.w[range.start * bs..range.end * bs];
        self.pairs.row[range].iter().zip(w.chunks_exact(bs))
    }
}

/// The compressed-column structure of an m × m matrix from its entries (duplicates merged) and
/// a map from an entry to its position in the value array.
fn csc(
    m: usize,
    entries: Vec<(usize, usize)>,
) -> (SymbolicSparseColMat<usize>, impl Fn(usize, usize) -> usize) {
    // Bucketed by column (a counting sort), then each column's rows sorted and deduplicated.
    let order = bucket_by(entries.len(), m, |e| entries[e].1);
    let mut col_ptr = vec![0usize; m + 1];
    let mut row_idx = Vec::with_capacity(entries.len());
    let mut start = 0;
    for c in 0..m {
        let len = order[start..]
            .iter()
            .take_while(|&&e| entries[e].1 == c)
            .count();
        let first = row_idx.len();
        row_idx.extend(order[start..start + len].iter().map(|&e| entries[e].0));
        row_idx[first..].sort_unstable();
        let mut kept = first;
        for i in first..row_idx.len() {
            if i == first || row_idx[i] != row_idx[kept - 1] {
                row_idx[kept] = row_idx[i];
                kept += 1;
            }
        }
        row_idx.truncate(kept);
        col_ptr[c + 1] = kept;
        start += len;
    }
    let (cp, ri) = (col_ptr.clone(), row_idx.clone());
    let slot = move |r: usize, c: usize| -> usize {
        let col = &ri[cp[c]..cp[c + 1]];
        cp[c] + col.binary_search(&r).expect("entry is in the pattern")
    };
    (
        SymbolicSparseColMat::new_checked(m, m, col_ptr, None, row_idx),
        slot,
    )
}

/// The row pattern of L from its columns (`col_ptr`, `row_idx`: diagonal first, then the rows
/// below in increasing order): for each row k, the columns i < k holding an entry of row k, in
/// increasing order, and that entry's slot.
fn row_pattern(
    m: usize,
    col_ptr: &[usize],
    row_idx: &[usize],
) -> (Vec<usize>, Vec<usize>, Vec<usize>) {
    let mut start = vec![0usize; m + 1];
    for i in 0..m {
        let below = &row_idx[col_ptr[i] + 1..col_ptr[i + 1]];
        debug_assert!(
            below.windows(2).all(|w| w[0] < w[1]) && below.first().is_none_or(|&r| r > i),
            "column {i} of L: rows below the diagonal, increasing"
        );
        for &r in below {
            start[r + 1] += 1;
        }
    }
    for k in 0..m {
        start[k + 1] += start[k];
    }
    let mut next = start.clone();
    let mut cols = vec![0usize; start[m]];
    let mut slots = vec![0usize; start[m]];
    // Columns visited in increasing order, so each row's list comes out increasing.
    for i in 0..m {
        for p in col_ptr[i] + 1..col_ptr[i + 1] {
            let r = row_idx[p];
            cols[next[r]] = i;
            slots[next[r]] = p;
            next[r] += 1;
        }
    }
    (start, cols, slots)
}

/// The indices 0..len ordered by `key` (< `buckets`), stably: a counting sort.
fn bucket_by(len: usize, buckets: usize, key: impl Fn(usize) -> usize) -> Vec<usize> {
    let mut start = vec![0usize; buckets + 1];
    for e in 0..len {
        start[key(e) + 1] += 1;
    }
    for k in 0..buckets {
        start[k + 1] += start[k];
    }
    let mut order = vec![0; len];
    for e in 0..len {
        let k = key(e);
        order[start[k]] = e;
        start[k] += 1;
    }
    order
}

/// x · y over the first n entries.
#[inline(always)]
fn dot(x: &[f64], y: &[f64], n: usize) -> f64 {
    let (x, y) = (&x[..n], &y[..n]);
    let mut d = 0.0;
    for i in 0..n {
        d += x[i] * y[i];
    }
    d
}

/// A pivot `d` of a row whose diagonal entry was `diag` is acceptable: `d > τ diag` (false for
/// NaN).
fn pivot_ok(d: f64, diag: f64, tol: f64) -> bool {
    d > tol * diag
}

/// In-place dense Cholesky of the `n × n` column-major `a` (lower triangle read and written),
/// with the **reciprocals** 1/L_jj stored on the diagonal: `false` when a pivot `d_j` is not
/// above `tol · max_i a_ii` (not positive definite, or too ill-conditioned).
#[inline(always)]
fn dense_cholesky(a: &mut [f64], n: usize, tol: f64) -> bool {
    let a = &mut a[..n * n];
    let amax = (0..n).fold(0.0f64, |m, j| m.max(a[j * n + j]));
    for j in 0..n {
        let mut d = a[j * n + j];
        for k in 0..j {
            d -= a[k * n + j] * a[k * n + j];
        }
        if !pivot_ok(d, amax, tol) {
            return false;
        }
        let r = 1.0 / d.sqrt();
        a[j * n + j] = r;
        for i in j + 1..n {
            let mut s = a[j * n + i];
            for k in 0..j {
                s -= a[k * n + i] * a[k * n + j];
            }
            a[j * n + i] = s * r;
        }
    }
    true
}

/// y ← L⁻¹ y (L lower triangular, column-major `n × n`, reciprocal diagonal).
#[inline(always)]
fn forward(l: &[f64], n: usize, y: &mut [f64]) {
    let (l, y) = (&l[..n * n], &mut y[..n]);
    for j in 0..n {
        let v = y[j] * l[j * n + j];
        y[j] = v;
        for i in j + 1..n {
            y[i] -= l[j * n + i] * v;
        }
    }
}

/// y ← L⁻ᵀ y.
#[inline(always)]
fn backward(l: &[f64], n: usize, y: &mut [f64]) {
    let (l, y) = (&l[..n * n], &mut y[..n]);
    for j in (0..n).rev() {
        let mut v = y[j];
        for i in j + 1..n {
            v -= l[j * n + i] * y[i];
        }
        y[j] = v * l[j * n + j];
    }
}
