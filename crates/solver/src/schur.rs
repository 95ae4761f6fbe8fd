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
//! full row rank, and factored by a sparse Cholesky S = L Lᵀ. Each A_k is factored densely,
//! A_k = L_k L_kᵀ; with W_k = L_k⁻¹ B_kᵀ (one column w_r per row r of B that touches block k)
//! every contribution is a Gram matrix, S += W_kᵀ W_k, so the assembled S is exactly symmetric.
//! Rows r and s are coupled in S when they touch a common block; the pattern of S is fixed at
//! [`analyze`](SchurSolver::analyze), which also orders it (AMD) and computes the pattern of L
//! (faer's symbolic analysis: elimination tree, column counts, row indices).
//!
//! The numeric factorization is our own, up-looking (by rows) on that fixed pattern. Row k of
//! L, ℓ_k = (L_k0, …, L_k,k−1), solves a triangular system with the rows already factored, and
//! the pivot follows:
//!
//! ```text
//!   L_{0:k,0:k} ℓ_kᵀ = S_{0:k,k},   i.e.   L_ki = (S_ki − Σ_{j<i} L_ij L_kj) / L_ii,
//!   d_k = L_kk² = S_kk − Σ_{i<k} L_ki²
//! ```
//!
//! Row k's pattern (the columns i < k with L_ki ≠ 0) is known from the analysis, and ascending
//! i is a valid order for the forward substitution. A dense vector u (zero between rows)
//! collects the sums: at each i of the pattern in turn, u_i = −Σ_{j<i} L_ij L_kj is complete,
//! L_ki = (S_ki + u_i) / L_ii, and column i pushes its entries on, u_r −= L_ri L_ki for the
//! rows i < r < k of column i (all in row k's pattern, by the fill rule); u_i is then cleared.
//! L is stored by columns, diagonal first and rows ascending, so the entries of column i above
//! row k are the slots between its diagonal and L_ki's slot; S is assembled in the layout of L
//! (S_ki at L_ki's slot, zero at the fill); and the analysis lists, for every row, its columns
//! and those slots. The factorization thus neither searches nor recomputes a pattern: it does
//! Σ_i c_i (c_i + 1) / 2 multiply-adds (c_i the entries of column i below the diagonal), for
//! the block-tridiagonal S of a chain (no fill after AMD) about 10 per row. Each pivot d_k is
//! checked before its square root is taken, so a non-positive one fails cleanly.
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
//! [`analyze`](SchurSolver::analyze) allocates everything (the layout of S, the structure of L
//! by columns and by rows, the dense vector u of the factorization);
//! [`factor`](SchurSolver::factor) and [`solve`](SchurSolver::solve) do not (only error values
//! allocate). u is zero between rows, also after a failed pivot: a row's entries of u are
//! cleared as they are consumed, and it writes no other.

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
    /// Block size b.
    block: usize,
    /// Number of blocks N.
    nblocks: usize,
    /// Rows of B (m).
    m: usize,
    /// Number of B values (entries as given to `analyze`).
    nb_values: usize,
    /// Cholesky factors L_k of the blocks, column-major b × b each (lower triangle used).
    a_fac: Vec<f64>,
    /// The blocks `a_fac` was computed from, and whether that succeeded.
    a_prev: Vec<f64>,
    a_factored: bool,
    /// Every block-row pair has its b entries in column order at consecutive value indices
    /// (the caller's layout groups them): gathered by one copy.
    contiguous: bool,
    /// Block-row pairs (k, r): rows r of B touching block k, grouped by block (r in the
    /// permuted numbering of S).
    pair_start: Vec<usize>,
    pair_row: Vec<usize>,
    /// Entries of each pair: (column within the block, index into the B values).
    entry_start: Vec<usize>,
    entry_col: Vec<usize>,
    entry_val: Vec<usize>,
    /// w = L_k⁻¹ b_r for every pair, b values each.
    w: Vec<f64>,
    /// For every block, its pairs (p, q) with q ≤ p in loop order: the slot of S they add to.
    s_target: Vec<usize>,
    /// Lower triangle of S in the permuted numbering, laid out like L: S_ij at the slot of
    /// L_ij in `l_values`, zero at the fill.
    s_values: Vec<f64>,
    /// Structurally distinct entries in the lower triangle of S.
    s_nnz: usize,
    /// Structure of L (compressed columns, diagonal first, then rows ascending) and its values.
    l_col_ptr: Vec<usize>,
    l_row_idx: Vec<usize>,
    l_values: Vec<f64>,
    /// The strictly lower part of L by rows, columns ascending: row k's entries are
    /// `l_rows[l_row_ptr[k]..l_row_ptr[k + 1]]`.
    l_row_ptr: Vec<usize>,
    l_rows: Vec<RowEntry>,
    /// 1 / L_jj.
    l_inv_diag: Vec<f64>,
    /// The dense vector u of the factorization (m entries, zero between rows).
    work: Vec<f64>,
    /// The AMD ordering: row `perm_fwd[j]` of B is row j of S as laid out; `perm_inv` inverse.
    perm_fwd: Vec<usize>,
    perm_inv: Vec<usize>,
    /// λ in the permuted numbering (solve scratch).
    lambda: Vec<f64>,
    pivot_tolerance: f64,
    block_tolerance: f64,
    min_pivot_ratio: f64,
    analyzed: bool,
    factored: bool,
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
            block: 0,
            nblocks: 0,
            m: 0,
            nb_values: 0,
            a_fac: Vec::new(),
            a_prev: Vec::new(),
            a_factored: false,
            contiguous: false,
            pair_start: vec![0],
            pair_row: Vec::new(),
            entry_start: vec![0],
            entry_col: Vec::new(),
            entry_val: Vec::new(),
            w: Vec::new(),
            s_target: Vec::new(),
            s_values: Vec::new(),
            s_nnz: 0,
            l_col_ptr: Vec::new(),
            l_row_idx: Vec::new(),
            l_values: Vec::new(),
            l_row_ptr: Vec::new(),
            l_rows: Vec::new(),
            l_inv_diag: Vec::new(),
            work: Vec::new(),
            perm_fwd: Vec::new(),
            perm_inv: Vec::new(),
            lambda: Vec::new(),
            pivot_tolerance: DEFAULT_SCHUR_PIVOT_TOLERANCE,
            block_tolerance: DEFAULT_BLOCK_PIVOT_TOLERANCE,
            min_pivot_ratio: f64::NAN,
            analyzed: false,
            factored: false,
        }
    }

    /// Sets the relative pivot tolerance τ (a pivot fails when `L_jj² ≤ τ S_jj`).
    pub fn with_pivot_tolerance(mut self, tol: f64) -> Self {
        self.pivot_tolerance = tol;
        self
    }

    /// Sets the block tolerance τ_A (a block fails when `(L_k)_jj² ≤ τ_A max_i (A_k)_ii`).
    pub fn with_block_tolerance(mut self, tol: f64) -> Self {
        self.block_tolerance = tol;
        self
    }

    /// Lays out the system: `nblocks` diagonal blocks of size `block` (n = `nblocks · block`
    /// unknowns), `m` rows of B whose entries `(row, col)` are listed in the order their values
    /// will be given to [`factor`](Self::factor) (duplicates are summed). Computes the pattern of
    /// S, its fill-reducing ordering and the structure of its Cholesky factor (by columns and by
    /// rows), and every buffer.
    ///
    /// # Errors
    /// [`SolverError::EntryOutOfBounds`] for an entry outside B; [`SolverError::Backend`] if
    /// faer's symbolic analysis fails or returns a structure of L not laid out as expected.
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
        self.analyzed = false;
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
        self.pair_start = vec![0; nblocks + 1];
        self.pair_row.clear();
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
                self.pair_row.push(r);
                self.pair_start[k + 1] += 1;
                last = Some((k, r));
            }
            self.entry_col.push(c % block);
            self.entry_val.push(e);
        }
        if last.is_some() {
            self.entry_start.push(self.entry_col.len());
        }
        for k in 0..nblocks {
            self.pair_start[k + 1] += self.pair_start[k];
        }
        // Pattern of the lower triangle of S: the diagonal, and (max, min) of every two rows
        // touching a common block.
        let mut lower: Vec<(usize, usize)> = (0..m).map(|r| (r, r)).collect();
        for k in 0..nblocks {
            let rows = &self.pair_row[self.pair_start[k]..self.pair_start[k + 1]];
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
        // The fill-reducing (AMD) ordering, computed once on the lower triangle; then the pattern
        // of S is built directly in the permuted numbering (upper triangle, the input of faer's
        // symbolic factorization) and its values are assembled in the layout of L, so that
        // neither the factorization nor the solve permutes anything.
        let (perm_fwd, perm_inv) = {
            let sym = csc(m, lower.clone());
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
        for r in &mut self.pair_row {
            *r = perm_inv[*r];
        }
        let inv = &perm_inv;
        let upper = |(r, c): (usize, usize)| {
            let (a, b) = (inv[r], inv[c]);
            (a.min(b), a.max(b))
        };
        let symbolic = csc(m, lower.iter().map(|&e| upper(e)).collect());
        self.s_nnz = symbolic.row_idx().len();
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
        self.l_col_ptr = simplicial.col_ptr().to_vec();
        self.l_row_idx = simplicial.row_idx().to_vec();
        (self.l_row_ptr, self.l_rows) = rows_of_factor(m, &self.l_col_ptr, &self.l_row_idx)?;
        // S is laid out like L (its entries at their slots in L, the fill zero).
        let (cp, ri) = (&self.l_col_ptr, &self.l_row_idx);
        self.s_target = lower[m..]
            .iter()
            .map(|&e| {
                let (c, r) = upper(e);
                ri[cp[c]..cp[c + 1]]
                    .binary_search(&r)
                    .map(|i| cp[c] + i)
                    .map_err(|_| {
                        SolverError::Backend(format!(
                            "symbolic Cholesky: entry ({r}, {c}) of S is not in the pattern of L"
                        ))
                    })
            })
            .collect::<Result<_, _>>()?;
        self.s_values = vec![0.0; ri.len()];
        self.l_values = vec![0.0; ri.len()];
        self.l_inv_diag = vec![0.0; m];
        self.work = vec![0.0; m];
        self.lambda = vec![0.0; m];
        self.perm_fwd = perm_fwd;
        self.perm_inv = perm_inv;
        self.block = block;
        self.nblocks = nblocks;
        self.m = m;
        self.nb_values = b_entries.len();
        self.a_fac = vec![0.0; nblocks * block * block];
        self.a_prev = vec![0.0; nblocks * block * block];
        self.a_factored = false;
        self.contiguous = (0..self.pair_row.len()).all(|p| {
            let (s, e) = (self.entry_start[p], self.entry_start[p + 1]);
            e - s == block
                && (s..e).all(|i| {
                    self.entry_col[i] == i - s && self.entry_val[i] == self.entry_val[s] + i - s
                })
        });
        self.w = vec![0.0; self.pair_row.len() * block];
        self.min_pivot_ratio = f64::NAN;
        self.analyzed = true;
        Ok(())
    }

    /// Number of unknowns n (the size of A).
    pub fn num_unknowns(&self) -> usize {
        self.block * self.nblocks
    }

    /// Number of rows m of B (the order of S).
    pub fn num_rows(&self) -> usize {
        self.m
    }

    /// Structurally distinct entries in the lower triangle of S.
    pub fn schur_nnz(&self) -> usize {
        self.s_nnz
    }

    /// Entries of the Cholesky factor L of S (fill measure).
    pub fn factor_nnz(&self) -> usize {
        self.l_values.len()
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
        if !self.analyzed {
            return Err(SolverError::NotReady { missing: "analyze" });
        }
        let bs = self.block;
        check_len("block-diagonal values", self.a_fac.len(), a.len())?;
        check_len("constraint values", self.nb_values, b.len())?;
        let tol_a = self.block_tolerance;
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
        if let Err(singular) = self.factor_schur() {
            return Err(self.non_finite_input(a, b).unwrap_or(singular));
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
        if !self.analyzed {
            return Err(SolverError::NotReady { missing: "analyze" });
        }
        let (bs, n, m) = (self.block, self.num_unknowns(), self.m);
        check_len("right-hand side", n + m, rhs.len())?;
        check_len("solution", n + m, sol.len())?;
        let (x, lambda_out) = sol.split_at_mut(n);
        // z_k = L_k⁻¹ f_k (in x); t = W z − g (in λ, permuted numbering).
        x.copy_from_slice(&rhs[..n]);
        let mut lambda = std::mem::take(&mut self.lambda);
        for (l, &r) in lambda.iter_mut().zip(&self.perm_fwd) {
            *l = -rhs[n + r];
        }
        if bs == 6 {
            self.solve_forward::<6>(x, &mut lambda);
        } else {
            self.solve_forward::<0>(x, &mut lambda);
        }
        // λ = S⁻¹ t = L⁻ᵀ L⁻¹ t.
        let (cp, ri, lv) = (&self.l_col_ptr, &self.l_row_idx, &self.l_values);
        for j in 0..m {
            let v = lambda[j] * self.l_inv_diag[j];
            lambda[j] = v;
            for p in cp[j] + 1..cp[j + 1] {
                lambda[ri[p]] -= lv[p] * v;
            }
        }
        for j in (0..m).rev() {
            let mut v = lambda[j];
            for p in cp[j] + 1..cp[j + 1] {
                v -= lv[p] * lambda[ri[p]];
            }
            lambda[j] = v * self.l_inv_diag[j];
        }
        // x_k = L_k⁻ᵀ (z_k − Σ_r w_r λ_r).
        if bs == 6 {
            self.solve_backward::<6>(x, &lambda);
        } else {
            self.solve_backward::<0>(x, &lambda);
        }
        for (o, &j) in lambda_out.iter_mut().zip(&self.perm_inv) {
            *o = lambda[j];
        }
        self.lambda = lambda;
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
        let bs = self.block;
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
        let e = self.entry_val.iter().position(|&v| v == slot).unwrap_or(0);
        let p = self
            .entry_start
            .partition_point(|&s| s <= e)
            .saturating_sub(1);
        let k = self
            .pair_start
            .partition_point(|&s| s <= p)
            .saturating_sub(1);
        let row = self
            .pair_row
            .get(p)
            .and_then(|&j| self.perm_fwd.get(j))
            .copied()
            .unwrap_or(0);
        Some(SolverError::NonFinite {
            location: NonFiniteLocation::Jacobian {
                slot,
                row,
                col: k * bs + self.entry_col.get(e).copied().unwrap_or(0),
            },
            iteration: None,
        })
    }

    /// The up-looking Cholesky factorization S = L Lᵀ on the structure from `analyze` (see the
    /// module docs): row k of L from L_ki = (S_ki + u_i) / L_ii in ascending i, where u_i holds
    /// −Σ_{j<i} L_ij L_kj (pushed on by u_r −= L_ri L_ki down each column i), and its pivot
    /// d_k = S_kk − Σ_i L_ki², checked before L_kk = √d_k. Sets L, 1 / L_kk (the division by
    /// L_ii is a multiplication by it) and the smallest ratio d_k / S_kk.
    ///
    /// # Errors
    /// [`SolverError::Singular`]: at the first pivot d_k that is not positive (or NaN) the
    /// factorization stops and names that row alone (the smallest ratio is then 0); otherwise
    /// every row whose pivot fails the relative test d_k > τ S_kk is named (rows of B, sorted).
    fn factor_schur(&mut self) -> Result<(), SolverError> {
        let tol = self.pivot_tolerance;
        // Slices, not vectors (the stores into L and u cannot be taken to move them), of two
        // lengths only, m and nnz(L), so that one bounds check covers several arrays.
        let (m, nnz) = (self.m, self.l_values.len());
        let (cp, ri, s) = (
            &self.l_col_ptr[..=m],
            &self.l_row_idx[..nnz],
            &self.s_values[..nnz],
        );
        let (row_ptr, rows) = (&self.l_row_ptr[..=m], &self.l_rows[..]);
        let (lv, inv) = (&mut self.l_values[..nnz], &mut self.l_inv_diag[..m]);
        let u = &mut self.work[..m];
        let mut min_ratio = f64::INFINITY;
        // Rows whose relative pivot fails (allocates only then).
        let mut small = Vec::new();
        for k in 0..m {
            let skk = s[cp[k]];
            let mut d = skk;
            for &RowEntry {
                col: i,
                below,
                slot,
            } in &rows[row_ptr[k]..row_ptr[k + 1]]
            {
                // u_i is final: every column before i has been applied.
                let lki = (s[slot] + u[i]) * inv[i];
                u[i] = 0.0;
                for q in below..slot {
                    u[ri[q]] -= lv[q] * lki;
                }
                lv[slot] = lki;
                d -= lki * lki;
            }
            // Here u is zero again: row k's pattern covers every entry written.
            if d.is_nan() || d <= 0.0 {
                self.min_pivot_ratio = 0.0;
                return Err(SolverError::Singular {
                    dependent_equations: vec![self.perm_fwd[k]],
                });
            }
            let lkk = d.sqrt();
            lv[cp[k]] = lkk;
            inv[k] = 1.0 / lkk;
            min_ratio = min_ratio.min(d / skk);
            if !pivot_ok(d, skk, tol) {
                small.push(self.perm_fwd[k]);
            }
        }
        self.min_pivot_ratio = min_ratio;
        if small.is_empty() {
            Ok(())
        } else {
            small.sort_unstable();
            Err(SolverError::Singular {
                dependent_equations: small,
            })
        }
    }

    /// Block size: `B` when it is not 0 (a compile-time size, loops unrolled), else the
    /// analyzed one.
    #[inline(always)]
    fn bs<const B: usize>(&self) -> usize {
        if B == 0 {
            self.block
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
        let reuse = self.a_factored && self.a_prev == a;
        if !reuse {
            self.a_factored = false;
            for k in 0..self.nblocks {
                let lk = &mut self.a_fac[k * bb..(k + 1) * bb];
                lk.copy_from_slice(&a[k * bb..(k + 1) * bb]);
                if !dense_cholesky(lk, bs, tol) {
                    return false;
                }
            }
            self.a_prev.copy_from_slice(a);
            self.a_factored = true;
        }
        self.s_values.fill(0.0);
        let mut target = 0;
        for k in 0..self.nblocks {
            let lk = &self.a_fac[k * bb..(k + 1) * bb];
            let pairs = self.pair_start[k]..self.pair_start[k + 1];
            for p in pairs.clone() {
                let wp = &mut self.w[p * bs..(p + 1) * bs];
                let entries = self.entry_start[p]..self.entry_start[p + 1];
                if self.contiguous {
                    let first = self.entry_val[entries.start];
                    wp.copy_from_slice(&b[first..first + bs]);
                } else {
                    wp.fill(0.0);
                    for e in entries {
                        wp[self.entry_col[e]] += b[self.entry_val[e]];
                    }
                }
                forward(lk, bs, wp);
            }
            for p in pairs.clone() {
                let wp = &self.w[p * bs..(p + 1) * bs];
                for q in pairs.start..=p {
                    self.s_values[self.s_target[target]] +=
                        dot(wp, &self.w[q * bs..(q + 1) * bs], bs);
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
        for k in 0..self.nblocks {
            let zk = &mut x[k * bs..(k + 1) * bs];
            forward(&self.a_fac[k * bb..(k + 1) * bb], bs, zk);
            for p in self.pair_start[k]..self.pair_start[k + 1] {
                lambda[self.pair_row[p]] += dot(&self.w[p * bs..(p + 1) * bs], zk, bs);
            }
        }
    }

    /// x_k ← L_k⁻ᵀ (x_k − Σ_r w_r λ_r).
    fn solve_backward<const B: usize>(&self, x: &mut [f64], lambda: &[f64]) {
        let bs = self.bs::<B>();
        let bb = bs * bs;
        for k in 0..self.nblocks {
            let zk = &mut x[k * bs..(k + 1) * bs];
            for p in self.pair_start[k]..self.pair_start[k + 1] {
                let wp = &self.w[p * bs..(p + 1) * bs];
                let l = lambda[self.pair_row[p]];
                for i in 0..bs {
                    zk[i] -= wp[i] * l;
                }
            }
            backward(&self.a_fac[k * bb..(k + 1) * bb], bs, zk);
        }
    }
}

/// The compressed-column structure of an m × m matrix from its entries (duplicates merged, rows
/// ascending).
fn csc(m: usize, entries: Vec<(usize, usize)>) -> SymbolicSparseColMat<usize> {
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
    SymbolicSparseColMat::new_checked(m, m, col_ptr, None, row_idx)
}

/// An entry L_ki of the strictly lower part of L, in the order the factorization visits them
/// (by rows k, columns i ascending).
#[derive(Clone, Copy, Debug)]
struct RowEntry {
    /// Its column i.
    col: usize,
    /// The slot of the first entry of column i below the diagonal: the entries of column i
    /// above row k are the slots `below..slot`.
    below: usize,
    /// Its slot in L's values.
    slot: usize,
}

/// The strictly lower part of the m × m factor L given by compressed columns (each diagonal
/// first, then rows ascending) as rows: `(row_ptr, entries)` with row k's entries, columns
/// ascending, at `row_ptr[k]..row_ptr[k + 1]`.
///
/// # Errors
/// [`SolverError::Backend`] when a column does not start with its diagonal or its rows are not
/// ascending (the factorization relies on both).
fn rows_of_factor(
    m: usize,
    col_ptr: &[usize],
    row_idx: &[usize],
) -> Result<(Vec<usize>, Vec<RowEntry>), SolverError> {
    let mut row_ptr = vec![0usize; m + 1];
    for j in 0..m {
        let col = &row_idx[col_ptr[j]..col_ptr[j + 1]];
        if col.first() != Some(&j)
            || col.windows(2).any(|w| w[0] >= w[1])
            || col[col.len() - 1] >= m
        {
            return Err(SolverError::Backend(format!(
                "symbolic Cholesky: column {j} of L is not laid out diagonal first, rows ascending"
            )));
        }
        for &r in &col[1..] {
            row_ptr[r + 1] += 1;
        }
    }
    for k in 0..m {
        row_ptr[k + 1] += row_ptr[k];
    }
    let mut next = row_ptr[..m].to_vec();
    let empty = RowEntry {
        col: 0,
        below: 0,
        slot: 0,
    };
    let mut entries = vec![empty; row_ptr[m]];
    for j in 0..m {
        for slot in col_ptr[j] + 1..col_ptr[j + 1] {
            let e = &mut next[row_idx[slot]];
            entries[*e] = RowEntry {
                col: j,
                below: col_ptr[j] + 1,
                slot,
            };
            *e += 1;
        }
    }
    Ok((row_ptr, entries))
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

#[cfg(test)]
mod tests {
    use super::*;

    /// Deterministic xorshift generator: uniform in [-1, 1).
    struct Rng(u64);

    impl Rng {
        fn sym(&mut self) -> f64 {
            self.0 ^= self.0 << 13;
            self.0 ^= self.0 >> 7;
            self.0 ^= self.0 << 17;
            2.0 * ((self.0 >> 11) as f64 / (1u64 << 53) as f64) - 1.0
        }
    }

    /// A saddle-point system whose S has fill: two rails of `n` blocks each (blocks i and n + i),
    /// joined along each rail, by a rung at every i, and by a diagonal closing the ladder into a
    /// loop; `rows` rows per joint, and one ground row on block 0. Blocks G Gᵀ + I, entries of B
    /// on every column of both blocks, random.
    struct Ladder {
        bs: usize,
        nb: usize,
        m: usize,
        a: Vec<f64>,
        entries: Vec<(usize, usize)>,
        b: Vec<f64>,
    }

    fn ladder(rng: &mut Rng, bs: usize, n: usize, rows: usize) -> Ladder {
        let nb = 2 * n;
        let mut a = Vec::new();
        for _ in 0..nb {
            let g: Vec<f64> = (0..bs * bs).map(|_| rng.sym()).collect();
            for c in 0..bs {
                for r in 0..bs {
                    let gg: f64 = (0..bs).map(|t| g[t * bs + r] * g[t * bs + c]).sum();
                    a.push(gg + if r == c { 1.0 } else { 0.0 });
                }
            }
        }
        let mut joints = vec![(0, None)];
        for i in 0..n - 1 {
            joints.push((i, Some(i + 1)));
            joints.push((n + i, Some(n + i + 1)));
        }
        for i in 0..n {
            joints.push((i, Some(n + i)));
        }
        joints.push((n - 1, Some(n)));
        let (mut m, mut entries, mut b) = (0, Vec::new(), Vec::new());
        for (k, other) in joints {
            for _ in 0..if other.is_some() { rows } else { 1 } {
                for blk in std::iter::once(k).chain(other) {
                    for c in 0..bs {
                        entries.push((m, bs * blk + c));
                        b.push(rng.sym());
                    }
                }
                m += 1;
            }
        }
        Ladder {
            bs,
            nb,
            m,
            a,
            entries,
            b,
        }
    }

    impl Ladder {
        fn n(&self) -> usize {
            self.bs * self.nb
        }

        /// The dense B (m × n, row-major).
        fn dense_b(&self) -> Vec<f64> {
            let n = self.n();
            let mut bd = vec![0.0; self.m * n];
            for (&(r, c), &v) in self.entries.iter().zip(&self.b) {
                bd[r * n + c] += v;
            }
            bd
        }

        /// The dense A (n × n, row-major).
        fn dense_a(&self) -> Vec<f64> {
            let (bs, n) = (self.bs, self.n());
            let mut ad = vec![0.0; n * n];
            for k in 0..self.nb {
                for c in 0..bs {
                    for r in 0..bs {
                        ad[(k * bs + r) * n + k * bs + c] = self.a[k * bs * bs + c * bs + r];
                    }
                }
            }
            ad
        }

        /// S = B A⁻¹ Bᵀ densely (m × m, row-major, B's numbering).
        fn dense_s(&self) -> Vec<f64> {
            let (n, m) = (self.n(), self.m);
            let (ad, bd) = (self.dense_a(), self.dense_b());
            let mut s = vec![0.0; m * m];
            for r in 0..m {
                // A⁻¹ b_r, then its products with every row.
                let z = gauss(ad.clone(), bd[r * n..(r + 1) * n].to_vec());
                for q in 0..m {
                    s[q * m + r] = (0..n).map(|c| bd[q * n + c] * z[c]).sum();
                }
            }
            s
        }

        /// The solution of the full system [A Bᵀ; B 0] [x; λ] = rhs, densely.
        fn dense_solve(&self, rhs: &[f64]) -> Vec<f64> {
            let (n, m) = (self.n(), self.m);
            let size = n + m;
            let (ad, bd) = (self.dense_a(), self.dense_b());
            let mut k = vec![0.0; size * size];
            for r in 0..n {
                k[r * size..r * size + n].copy_from_slice(&ad[r * n..(r + 1) * n]);
            }
            for r in 0..m {
                for c in 0..n {
                    k[(n + r) * size + c] = bd[r * n + c];
                    k[c * size + n + r] = bd[r * n + c];
                }
            }
            gauss(k, rhs.to_vec())
        }

        fn solver(&self) -> SchurSolver {
            let mut s = SchurSolver::new();
            s.analyze(self.bs, self.nb, self.m, &self.entries).unwrap();
            s
        }
    }

    /// Solves the dense row-major system `a x = b` by Gaussian elimination with partial pivoting.
    fn gauss(mut a: Vec<f64>, mut b: Vec<f64>) -> Vec<f64> {
        let n = b.len();
        for j in 0..n {
            let p = (j..n)
                .max_by(|&r, &s| a[r * n + j].abs().total_cmp(&a[s * n + j].abs()))
                .unwrap();
            for c in 0..n {
                a.swap(j * n + c, p * n + c);
            }
            b.swap(j, p);
            for r in j + 1..n {
                let f = a[r * n + j] / a[j * n + j];
                for c in j..n {
                    a[r * n + c] -= f * a[j * n + c];
                }
                b[r] -= f * b[j];
            }
        }
        for j in (0..n).rev() {
            let t: f64 = (j + 1..n).map(|c| a[j * n + c] * b[c]).sum();
            b[j] = (b[j] - t) / a[j * n + j];
        }
        b
    }

    /// The pivots d_j = L_jj² of the dense Cholesky factorization of the m × m row-major `s`.
    fn dense_pivots(s: &[f64], m: usize) -> Vec<f64> {
        let mut l = vec![0.0; m * m];
        let mut d = vec![0.0; m];
        for j in 0..m {
            d[j] = s[j * m + j] - (0..j).map(|t| l[j * m + t] * l[j * m + t]).sum::<f64>();
            let ljj = d[j].sqrt();
            l[j * m + j] = ljj;
            for i in j + 1..m {
                let v = s[i * m + j] - (0..j).map(|t| l[i * m + t] * l[j * m + t]).sum::<f64>();
                l[i * m + j] = v / ljj;
            }
        }
        d
    }

    /// S in the solver's (permuted) numbering, from B's.
    fn permuted(solver: &SchurSolver, s: &[f64]) -> Vec<f64> {
        let (m, p) = (solver.m, &solver.perm_fwd);
        let mut sp = vec![0.0; m * m];
        for i in 0..m {
            for j in 0..m {
                sp[i * m + j] = s[p[i] * m + p[j]];
            }
        }
        sp
    }

    fn max_abs(v: &[f64]) -> f64 {
        v.iter().fold(0.0f64, |a, x| a.max(x.abs()))
    }

    #[test]
    fn factor_and_solve_match_a_dense_reference_on_a_ladder_with_fill() {
        let mut rng = Rng(0x1ADDE5);
        for (bs, n, rows) in [(6, 7, 2), (6, 4, 3), (3, 6, 1), (4, 9, 2)] {
            let c = ladder(&mut rng, bs, n, rows);
            let m = c.m;
            let mut solver = c.solver();
            assert!(
                solver.factor_nnz() > solver.schur_nnz(),
                "no fill: {} entries in L, {} in S",
                solver.factor_nnz(),
                solver.schur_nnz()
            );
            solver.factor(&c.a, &c.b).unwrap();
            // S as assembled (laid out like L, zero at the fill) is B A⁻¹ Bᵀ, permuted.
            let s_ref = permuted(&solver, &c.dense_s());
            let scale = max_abs(&s_ref);
            let (cp, ri) = (&solver.l_col_ptr, &solver.l_row_idx);
            let mut s_got = vec![0.0; m * m];
            let mut l = vec![0.0; m * m];
            for j in 0..m {
                for p in cp[j]..cp[j + 1] {
                    let i = ri[p];
                    s_got[i * m + j] = solver.s_values[p];
                    s_got[j * m + i] = solver.s_values[p];
                    l[i * m + j] = solver.l_values[p];
                }
                assert_eq!(solver.l_inv_diag[j], 1.0 / l[j * m + j]);
            }
            let ds = s_got
                .iter()
                .zip(&s_ref)
                .fold(0.0f64, |a, (x, y)| a.max((x - y).abs()));
            assert!(ds < 1e-12 * scale, "bs {bs}: S differs by {ds:.2e}");
            // L Lᵀ = S at every entry, the fill included (a missing fill entry would show).
            let mut dl = 0.0f64;
            for i in 0..m {
                for j in 0..m {
                    let llt: f64 = (0..m).map(|t| l[i * m + t] * l[j * m + t]).sum();
                    dl = dl.max((llt - s_got[i * m + j]).abs());
                }
            }
            assert!(dl < 1e-12 * scale, "bs {bs}: L Lᵀ − S = {dl:.2e}");
            assert!(solver.work.iter().all(|&u| u == 0.0));
            // The pivots and their smallest ratio are the dense factorization's.
            let d = dense_pivots(&s_ref, m);
            let ratio = (0..m).fold(f64::INFINITY, |a, j| a.min(d[j] / s_ref[j * m + j]));
            assert!((solver.min_pivot_ratio() - ratio).abs() < 1e-9 * ratio);
            // The solve against Gaussian elimination on the full matrix.
            let size = c.n() + m;
            for _ in 0..2 {
                let rhs: Vec<f64> = (0..size).map(|_| rng.sym()).collect();
                let mut sol = vec![0.0; size];
                solver.solve(&rhs, &mut sol).unwrap();
                let sol_ref = c.dense_solve(&rhs);
                let diff = sol
                    .iter()
                    .zip(&sol_ref)
                    .fold(0.0f64, |a, (x, y)| a.max((x - y).abs()));
                assert!(
                    diff < 1e-9 * max_abs(&sol_ref),
                    "bs {bs}: solutions differ by {diff:.2e}"
                );
            }
        }
    }

    #[test]
    fn failed_relative_pivots_are_the_dense_factorizations_sorted_in_b_numbering() {
        let mut rng = Rng(77);
        let c = ladder(&mut rng, 6, 6, 2);
        let probe = c.solver();
        let s_ref = permuted(&probe, &c.dense_s());
        let m = c.m;
        let d = dense_pivots(&s_ref, m);
        let mut ratios: Vec<f64> = (0..m).map(|j| d[j] / s_ref[j * m + j]).collect();
        // A tolerance halfway between two ratios a third of the way up: some rows fail, none
        // at the edge.
        let mut sorted = ratios.clone();
        sorted.sort_by(f64::total_cmp);
        let tol = 0.5 * (sorted[m / 3] + sorted[m / 3 + 1]);
        let mut expected: Vec<usize> = (0..m)
            .filter(|&j| ratios[j] <= tol)
            .map(|j| probe.perm_fwd[j])
            .collect();
        expected.sort_unstable();
        assert!(expected.len() > 1 && expected.len() < m);
        let mut solver = c.solver().with_pivot_tolerance(tol);
        assert_eq!(
            solver.factor(&c.a, &c.b),
            Err(SolverError::Singular {
                dependent_equations: expected
            })
        );
        ratios.sort_by(f64::total_cmp);
        assert!((solver.min_pivot_ratio() - ratios[0]).abs() < 1e-9 * ratios[0]);
        let mut sol = vec![0.0; c.n() + m];
        assert!(matches!(
            solver.solve(&vec![1.0; c.n() + m], &mut sol),
            Err(SolverError::NotReady { .. })
        ));
        // The default tolerance accepts the same system.
        let mut solver = c.solver();
        solver.factor(&c.a, &c.b).unwrap();
    }

    #[test]
    fn a_non_positive_pivot_fails_cleanly_at_its_row() {
        let mut rng = Rng(2024);
        let c = ladder(&mut rng, 6, 5, 2);
        let mut solver = c.solver();
        solver.factor(&c.a, &c.b).unwrap();
        let (l_ok, s_ok) = (solver.l_values.clone(), solver.s_values.clone());
        let m = c.m;
        let k = m / 2;
        let kk = solver.l_col_ptr[k];
        // An off-diagonal entry of row k in S's pattern (rows of S are coupled along the ladder).
        let off = solver.l_rows[solver.l_row_ptr[k]..solver.l_row_ptr[k + 1]]
            .iter()
            .map(|e| e.slot)
            .find(|&p| s_ok[p] != 0.0)
            .unwrap();
        for (slot, v) in [(kk, -1.0), (kk, 0.0), (kk, f64::NAN), (off, f64::NAN)] {
            solver.s_values[slot] = v;
            assert_eq!(
                solver.factor_schur(),
                Err(SolverError::Singular {
                    dependent_equations: vec![solver.perm_fwd[k]]
                }),
                "S slot {slot} = {v}"
            );
            assert_eq!(solver.min_pivot_ratio(), 0.0);
            // The rows before k are factored as before, nothing after row k's off-diagonal
            // entries is written (L_kk neither: no square root of d_k), and u is zero.
            let row_k: Vec<usize> = solver.l_rows[solver.l_row_ptr[k]..solver.l_row_ptr[k + 1]]
                .iter()
                .map(|e| e.slot)
                .collect();
            for p in 0..l_ok.len() {
                if !row_k.contains(&p) {
                    assert_eq!(solver.l_values[p].to_bits(), l_ok[p].to_bits());
                }
            }
            assert!(solver.work.iter().all(|&u| u == 0.0));
            // Restored, S factors to the same L.
            solver.s_values.copy_from_slice(&s_ok);
            solver.factor_schur().unwrap();
            assert_eq!(solver.l_values, l_ok);
        }
        // Through the public path: a row of B repeated makes S singular.
        let mut dup = c;
        let (r1, r2) = (3, dup.m - 2);
        for e in 0..dup.entries.len() {
            if dup.entries[e].0 == r2 {
                dup.b[e] = 0.0;
            }
        }
        for e in 0..dup.entries.len() {
            if dup.entries[e].0 == r1 {
                dup.entries.push((r2, dup.entries[e].1));
                dup.b.push(dup.b[e]);
            }
        }
        let mut solver = dup.solver();
        match solver.factor(&dup.a, &dup.b) {
            Err(SolverError::Singular {
                dependent_equations,
            }) => assert!(
                dependent_equations.iter().any(|&r| r == r1 || r == r2),
                "{dependent_equations:?}"
            ),
            other => panic!("expected Singular, got {other:?}"),
        }
        assert!(solver.work.iter().all(|&u| u == 0.0));
    }
}
