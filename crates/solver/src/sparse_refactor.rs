//! Numeric refactorization of a sparse LU with the pivot sequence of an earlier one.
//!
//! A mechanism's Jacobian keeps its sparsity pattern from frame to frame and its values change
//! smoothly, so the row pivots that partial pivoting chose at one frame are almost always good
//! pivots at the next. [`Refactor`] keeps the structure of the factors `P A Q = L U` of the
//! last full factorization (faer's simplicial LU, which chooses the pivots by partial pivoting
//! and finds the fill by a depth-first search per column) and recomputes only their values:
//! for each column `j` of `P A Q`, left-looking,
//!
//! ```text
//! x ← (P A Q)[:, j]                  (scatter)
//! for k in pattern(U[:, j]), k < j, ascending:
//!     U[k, j] = x[k];  x[k+1..] −= L[k+1.., k] · x[k]
//! U[j, j] = x[j];  L[j+1.., j] = x[j+1..] / x[j]
//! ```
//!
//! (Gilbert & Peierls' left-looking LU with the reach known in advance; the "refactor" of
//! Davis & Palamadai Natarajan's KLU, ACM TOMS 37(3), 2010). With the same pivot sequence the
//! pattern of the factors is the same, so no search and no allocation are needed: the cost is
//! the floating-point work alone.
//!
//! **Pivot check.** A kept pivot is accepted when `|U[j, j]| ≥ τ max_i |x_i|` over the
//! candidates of its column (the diagonal and the entries that go to `L`), with
//! `τ =` [`PIVOT_THRESHOLD`]: threshold partial pivoting, which bounds the growth of the
//! factors as partial pivoting does (by `1 + 1/τ` per step instead of 2). When a pivot fails
//! the check or is at most the singularity tolerance, the refactorization gives up and the
//! caller factors afresh with pivoting (which also decides whether the matrix is singular).
//!
//! The factors are kept in compressed columns with indices in pivot order: `L` strictly lower
//! (its unit diagonal implied), `U` strictly upper with rows ascending (the order in which the
//! left-looking update must visit them), and the diagonal of `U` on its own.

use faer::perm::PermRef;
use faer::sparse::linalg::lu::simplicial::SimplicialLu;
use faer::Index;

/// Relative size a kept pivot must have among the candidates of its column (see the
/// [module docs](self)).
pub const PIVOT_THRESHOLD: f64 = 0.1;

/// The factors of the last accepted factorization and what refactoring them needs.
#[derive(Debug)]
pub struct Refactor<I: Index> {
    l_ptr: Vec<I>,
    l_idx: Vec<I>,
    l_val: Vec<f64>,
    u_ptr: Vec<I>,
    u_idx: Vec<I>,
    u_val: Vec<f64>,
    diag: Vec<f64>,
    /// Original row → its position in pivot order.
    row_pos: Vec<I>,
    /// Position in pivot order → original column.
    col_of: Vec<I>,
    /// Dense work vector, all zero between calls.
    work: Vec<f64>,
    /// Scratch for sorting a column of `U` by row at capture.
    sort: Vec<(usize, f64)>,
    /// Whether the factors hold a factorization of the current matrix.
    valid: bool,
}

impl<I: Index> Default for Refactor<I> {
    fn default() -> Self {
        Self::new()
    }
}

impl<I: Index> Refactor<I> {
    /// An empty refactorization (nothing captured).
    pub fn new() -> Self {
        Self {
            l_ptr: Vec::new(),
            l_idx: Vec::new(),
            l_val: Vec::new(),
            u_ptr: Vec::new(),
            u_idx: Vec::new(),
            u_val: Vec::new(),
            diag: Vec::new(),
            row_pos: Vec::new(),
            col_of: Vec::new(),
            work: Vec::new(),
            sort: Vec::new(),
            valid: false,
        }
    }

    /// Whether a factorization is held (captured or refactored since the last failure).
    pub fn is_valid(&self) -> bool {
        self.valid
    }

    /// Forgets the held factorization (the next factorization must pivot afresh).
    pub fn invalidate(&mut self) {
        self.valid = false;
    }

    /// Takes the structure and values of faer's factorization `lu` with its row positions
    /// (`row_perm_inv`: original row → pivot position) and column order. Allocates only when
    /// the factors are larger than every earlier capture.
    pub fn capture(
        &mut self,
        lu: &SimplicialLu<I, f64>,
        row_perm_inv: &[I],
        col_perm: PermRef<'_, I>,
    ) {
        let n = row_perm_inv.len();
        self.row_pos.clear();
        self.row_pos.extend_from_slice(row_perm_inv);
        self.col_of.clear();
        self.col_of.extend_from_slice(col_perm.arrays().0);
        self.work.clear();
        self.work.resize(n, 0.0);
        self.diag.clear();
        self.diag.resize(n, 0.0);
        let l = lu.l_factor_unsorted();
        let (lp, li, lv) = (l.symbolic().col_ptr(), l.symbolic().row_idx(), l.val());
        self.l_ptr.clear();
        self.l_idx.clear();
        self.l_val.clear();
        self.l_ptr.push(I::truncate(0));
        for j in 0..n {
            for p in lp[j].zx()..lp[j + 1].zx() {
                if li[p].zx() != j {
                    self.l_idx.push(li[p]);
                    self.l_val.push(lv[p]);
                }
            }
            self.l_ptr.push(I::truncate(self.l_idx.len()));
        }
        let u = lu.u_factor_unsorted();
        let (up, ui, uv) = (u.symbolic().col_ptr(), u.symbolic().row_idx(), u.val());
        self.u_ptr.clear();
        self.u_idx.clear();
        self.u_val.clear();
        self.u_ptr.push(I::truncate(0));
        for j in 0..n {
            self.sort.clear();
            for p in up[j].zx()..up[j + 1].zx() {
                let i = ui[p].zx();
                if i == j {
                    self.diag[j] = uv[p];
                } else {
                    self.sort.push((i, uv[p]));
                }
            }
            self.sort.sort_unstable_by_key(|e| e.0);
            for &(i, v) in &self.sort {
                self.u_idx.push(I::truncate(i));
                self.u_val.push(v);
            }
            self.u_ptr.push(I::truncate(self.u_idx.len()));
        }
        self.valid = true;
    }

    /// Refactors the matrix in compressed columns (`col_ptr`, `row_idx`, `values`: the pattern
    /// of the captured factorization) with the captured pivots. `false` (and the held
    /// factorization forgotten) when a pivot fails the threshold check or is at most `tol`:
    /// the caller must factor with pivoting.
    pub fn refactor(&mut self, col_ptr: &[I], row_idx: &[I], values: &[f64], tol: f64) -> bool {
        if !self.valid {
            return false;
        }
        let n = self.diag.len();
        for j in 0..n {
            if !self.column(j, col_ptr, row_idx, values, tol) {
                self.work.fill(0.0);
                self.valid = false;
                return false;
            }
        }
        true
    }

    /// Column `j` of the refactorization (module docs); `false` if its pivot is not accepted.
    fn column(&mut self, j: usize, col_ptr: &[I], row_idx: &[I], values: &[f64], tol: f64) -> bool {
        let c = self.col_of[j].zx();
        let x = &mut self.work;
        for p in col_ptr[c].zx()..col_ptr[c + 1].zx() {
            x[self.row_pos[row_idx[p].zx()].zx()] = values[p];
        }
        for q in self.u_ptr[j].zx()..self.u_ptr[j + 1].zx() {
            let k = self.u_idx[q].zx();
            let xk = std::mem::take(&mut x[k]);
            self.u_val[q] = xk;
            if xk != 0.0 {
                let range = self.l_ptr[k].zx()..self.l_ptr[k + 1].zx();
                for (&i, &l) in self.l_idx[range.clone()].iter().zip(&self.l_val[range]) {
                    x[i.zx()] -= l * xk;
                }
            }
        }
        let d = std::mem::take(&mut x[j]);
        let range = self.l_ptr[j].zx()..self.l_ptr[j + 1].zx();
        let largest = self.l_idx[range.clone()]
            .iter()
            .fold(0.0f64, |m, &i| m.max(x[i.zx()].abs()));
        // Written so that a NaN pivot fails.
        if !(d.abs() > tol && d.abs() >= PIVOT_THRESHOLD * largest) {
            return false;
        }
        self.diag[j] = d;
        let inv = 1.0 / d;
        for (&i, l) in self.l_idx[range.clone()].iter().zip(&mut self.l_val[range]) {
            *l = std::mem::take(&mut x[i.zx()]) * inv;
        }
        true
    }

    /// Solves `A x = b` in place with the held factors (`x` holds `b` on entry).
    pub fn solve_in_place(&mut self, x: &mut [f64]) {
        let n = self.diag.len();
        let y = &mut self.work;
        for (r, &b) in x.iter().enumerate() {
            y[self.row_pos[r].zx()] = b;
        }
        for k in 0..n {
            let yk = y[k];
            if yk != 0.0 {
                let range = self.l_ptr[k].zx()..self.l_ptr[k + 1].zx();
                for (&i, &l) in self.l_idx[range.clone()].iter().zip(&self.l_val[range]) {
                    y[i.zx()] -= l * yk;
                }
            }
        }
        for k in (0..n).rev() {
            let yk = y[k] / self.diag[k];
            y[k] = yk;
            if yk != 0.0 {
                let range = self.u_ptr[k].zx()..self.u_ptr[k + 1].zx();
                for (&i, &u) in self.u_idx[range.clone()].iter().zip(&self.u_val[range]) {
                    y[i.zx()] -= u * yk;
                }
            }
        }
        for (j, &c) in self.col_of.iter().enumerate() {
            x[c.zx()] = std::mem::take(&mut y[j]);
        }
    }
}
