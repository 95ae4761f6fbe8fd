//! Dense LU with partial pivoting (faer), for small square systems.
//!
//! `P J = L U`, stored in one column-major `n × n` buffer; the row permutation and faer's scratch
//! memory are allocated at [`analyze`](LinearSolver::analyze), so `factor` and `solve` do not
//! allocate. The matrix is first equilibrated (rows, then columns, scaled by powers of two so
//! that their largest entries are about 1), which makes the factorization and the singularity
//! test independent of units. Singularity is declared when a pivot of the equilibrated matrix
//! satisfies `|u_jj| ≤ tol` ([`DEFAULT_PIVOT_TOLERANCE`] unless changed with
//! [`DenseLu::with_pivot_tolerance`]).
//!
//! Matrices up to [`SMALL_DIM`] unknowns (the mechanisms of a few bodies) are factored by a plain
//! unblocked right-looking LU with the same partial pivoting (largest |entry| of the column): for
//! them faer's blocked, SIMD-dispatched kernel costs more in set-up than in arithmetic (measured
//! on the slider-crank kinematic frame, 18 unknowns: see the commit message). A singular matrix
//! is refactored by faer, so errors (the dependent equations) are reported exactly as before.

use crate::equilibration::Equilibration;
use crate::error::{NonFiniteLocation, SolverError};
use crate::linear::LinearSolver;
use crate::pattern::{check_len, SparsityPattern};
use crate::scratch::Scratch;
use crate::singular::{singular_error, DEFAULT_PIVOT_TOLERANCE};
use faer::dyn_stack::StackReq;
use faer::linalg::lu::partial_pivoting::{factor as lu_factor, solve as lu_solve};
use faer::perm::PermRef;
use faer::{MatMut, MatRef, Par};

/// Largest dimension factored by the built-in unblocked LU instead of faer's.
pub const SMALL_DIM: usize = 32;

/// Dense LU with partial pivoting. Square matrices only.
#[derive(Debug)]
pub struct DenseLu {
    pattern: Option<SparsityPattern>,
    n: usize,
    lu: Vec<f64>,
    perm: Vec<usize>,
    perm_inv: Vec<usize>,
    mem: Scratch,
    pivot_tolerance: f64,
    factored: bool,
    pivot_rows: Vec<usize>,
    equil: Equilibration,
    /// The factorization in `lu` is the built-in one (`perm[k]` = original row of row k).
    small: bool,
    work: Vec<f64>,
    /// Row, column and column-major dense index of every slot, when the pattern has no
    /// duplicate entries (empty otherwise): equilibration and assembly then touch the slots only.
    slot_row: Vec<usize>,
    slot_col: Vec<usize>,
    slot_dense: Vec<usize>,
}

impl Default for DenseLu {
    fn default() -> Self {
        Self::new()
    }
}

impl DenseLu {
    /// A dense LU with the default pivot tolerance.
    pub fn new() -> Self {
        Self {
            pattern: None,
            n: 0,
            lu: Vec::new(),
            perm: Vec::new(),
            perm_inv: Vec::new(),
            mem: Scratch::empty(),
            pivot_tolerance: DEFAULT_PIVOT_TOLERANCE,
            factored: false,
            pivot_rows: Vec::new(),
            equil: Equilibration::default(),
            small: false,
            work: Vec::new(),
            slot_row: Vec::new(),
            slot_col: Vec::new(),
            slot_dense: Vec::new(),
        }
    }

    /// Sets the pivot tolerance (singular if a pivot of the equilibrated matrix is `≤ tol`).
    pub fn with_pivot_tolerance(mut self, tol: f64) -> Self {
        self.pivot_tolerance = tol;
        self
    }
}

impl LinearSolver for DenseLu {
    fn analyze(&mut self, pattern: &SparsityPattern) -> Result<(), SolverError> {
        let (m, n) = (pattern.nrows(), pattern.ncols());
        if m != n {
            return Err(SolverError::NotSquare { nrows: m, ncols: n });
        }
        let req = StackReq::any_of(&[
            lu_factor::lu_in_place_scratch::<usize, f64>(n, n, Par::Seq, Default::default()),
            lu_solve::solve_in_place_scratch::<usize, f64>(n, 1, Par::Seq),
        ]);
        self.mem = Scratch::try_new(req)?;
        self.n = n;
        self.lu = vec![0.0; n * n];
        self.perm = vec![0; n];
        self.perm_inv = vec![0; n];
        self.pivot_rows = Vec::with_capacity(n);
        self.equil = Equilibration::new(n, n);
        self.work = vec![0.0; n];
        self.small = false;
        self.slot_row.clear();
        self.slot_col.clear();
        self.slot_dense.clear();
        if pattern.nnz() == pattern.num_slots() {
            for (i, j) in pattern.entries() {
                self.slot_row.push(i);
                self.slot_col.push(j);
                self.slot_dense.push(i + n * j);
            }
        }
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
        pattern.check_finite(slots)?;
        let n = self.n;
        let by_slots = !self.slot_dense.is_empty() || pattern.num_slots() == 0;
        if by_slots {
            self.equil.apply_slots(
                slots,
                &self.slot_row,
                &self.slot_col,
                &self.slot_dense,
                &mut self.lu,
            );
        } else {
            pattern.to_dense_col_major(slots, &mut self.lu)?;
            self.equil.apply_dense(&mut self.lu);
        }
        self.small = false;
        if n <= SMALL_DIM {
            if small_lu(&mut self.lu, n, &mut self.perm, self.pivot_tolerance) {
                self.small = true;
                self.factored = true;
                return Ok(());
            }
            // Singular: refactor with faer below so the error names the same equations.
            pattern.to_dense_col_major(slots, &mut self.lu)?;
            self.equil.apply_dense(&mut self.lu);
        }
        let stack = self.mem.stack();
        lu_factor::lu_in_place(
            MatMut::from_column_major_slice_mut(&mut self.lu, n, n),
            &mut self.perm,
            &mut self.perm_inv,
            Par::Seq,
            stack,
            Default::default(),
        );
        // The equilibrated matrix has entries of size about 1: the tolerance is absolute.
        let tol = self.pivot_tolerance;
        self.pivot_rows.clear();
        for j in 0..n {
            let u = self.lu[j + n * j];
            if u.abs() <= tol || u.is_nan() {
                self.pivot_rows.push(self.perm[j]);
            }
        }
        if !self.pivot_rows.is_empty() {
            return Err(singular_error(pattern, slots, &self.pivot_rows));
        }
        self.factored = true;
        Ok(())
    }

    fn solve(&mut self, b: &[f64], x: &mut [f64]) -> Result<(), SolverError> {
        if !self.factored {
            return Err(SolverError::NotReady { missing: "factor" });
        }
        let n = self.n;
        check_len("right-hand side", n, b.len())?;
        check_len("solution", n, x.len())?;
        if let Some(index) = b.iter().position(|v| !v.is_finite()) {
            return Err(SolverError::NonFinite {
                location: NonFiniteLocation::RightHandSide { index },
                iteration: None,
            });
        }
        self.equil.scale_rhs(b, x);
        if self.small {
            small_solve(&self.lu, n, &self.perm, x, &mut self.work);
            self.equil.unscale_solution(x);
            return check_solution(x);
        }
        let lu = MatRef::from_column_major_slice(&self.lu, n, n);
        lu_solve::solve_in_place(
            lu,
            lu,
            PermRef::new_checked(&self.perm, &self.perm_inv, n),
            MatMut::from_column_major_slice_mut(x, n, 1),
            Par::Seq,
            self.mem.stack(),
        );
        self.equil.unscale_solution(x);
        check_solution(x)
    }

    fn nrows(&self) -> usize {
        self.n
    }

    fn ncols(&self) -> usize {
        self.n
    }

    fn name(&self) -> &'static str {
        "dense-lu"
    }
}

fn check_solution(x: &[f64]) -> Result<(), SolverError> {
    if let Some(unknown) = x.iter().position(|v| !v.is_finite()) {
        return Err(SolverError::NonFinite {
            location: NonFiniteLocation::Solution { unknown },
            iteration: None,
        });
    }
    Ok(())
}

/// In-place `P A = L U` of the column-major `n × n` matrix `a` (unit lower L below the diagonal,
/// U on and above), partial pivoting on the largest |entry|; `perm[k]` = original row of row k.
/// `false` as soon as a pivot is `≤ tol` in magnitude or not finite (the matrix is then garbage).
fn small_lu(a: &mut [f64], n: usize, perm: &mut [usize], tol: f64) -> bool {
    for (i, p) in perm.iter_mut().enumerate().take(n) {
        *p = i;
    }
    for k in 0..n {
        let col = &a[n * k..n * k + n];
        let mut p = k;
        let mut best = col[k].abs();
        for (i, v) in col.iter().enumerate().skip(k + 1) {
            if v.abs() > best {
                best = v.abs();
                p = i;
            }
        }
        if best.is_nan() || best <= tol || best.is_infinite() {
            return false;
        }
        if p != k {
            for j in 0..n {
                a.swap(p + n * j, k + n * j);
            }
            perm.swap(p, k);
        }
        let inv = 1.0 / a[k + n * k];
        for v in &mut a[n * k + k + 1..n * k + n] {
            *v *= inv;
        }
        let (left, right) = a.split_at_mut(n * (k + 1));
        let lk = &left[n * k + k + 1..n * k + n];
        for col in right.chunks_exact_mut(n) {
            let akj = col[k];
            if akj != 0.0 {
                for (v, l) in col[k + 1..].iter_mut().zip(lk) {
                    *v -= l * akj;
                }
            }
        }
    }
    true
}

/// Solves with the factors of [`small_lu`]: `x ← U⁻¹ L⁻¹ P x`.
fn small_solve(lu: &[f64], n: usize, perm: &[usize], x: &mut [f64], work: &mut [f64]) {
    let work = &mut work[..n];
    for (w, &p) in work.iter_mut().zip(perm) {
        *w = x[p];
    }
    // Forward: unit lower, column-oriented.
    for (k, col) in lu.chunks_exact(n).enumerate() {
        let (head, tail) = work.split_at_mut(k + 1);
        let wk = head[k];
        if wk != 0.0 {
            for (w, l) in tail.iter_mut().zip(&col[k + 1..]) {
                *w -= l * wk;
            }
        }
    }
    // Backward: upper, column-oriented.
    for (k, col) in lu.chunks_exact(n).enumerate().rev() {
        let (head, tail) = work.split_at_mut(k);
        let wk = tail[0] / col[k];
        tail[0] = wk;
        if wk != 0.0 {
            for (w, u) in head.iter_mut().zip(&col[..k]) {
                *w -= u * wk;
            }
        }
    }
    x.copy_from_slice(work);
}
