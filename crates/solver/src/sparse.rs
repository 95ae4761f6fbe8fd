//! Sparse LU (faer), for large square systems.
//!
//! [`analyze`](LinearSolver::analyze) computes faer's symbolic LU once per pattern: a COLAMD
//! fill-reducing column ordering and the elimination structure. [`factor`](LinearSolver::factor)
//! runs faer's **simplicial** left-looking numeric LU with threshold-free partial pivoting
//! (`faer::sparse::linalg::lu::simplicial::factorize_simplicial_numeric_lu`) into storage owned
//! by this struct, with scratch memory (a faer `MemBuffer`) sized at analysis.
//!
//! Why simplicial and not supernodal: faer's supernodal numeric LU allocates temporary vectors
//! during every factorization, the simplicial one only grows its factor storage when a
//! factorization produces more fill than every earlier one (a different pivot sequence). On
//! mechanism patterns (blocks of 7 columns per body, few bodies per loop) supernodes are small
//! and the simplicial variant is not slower (see `BENCHMARKS.md`).
//!
//! Equilibration and singularity: as for [`DenseLu`](crate::DenseLu), the matrix is equilibrated
//! (powers of two, rows then columns) and the diagonal of `U` is checked against the pivot
//! tolerance; an exactly structurally singular matrix is reported by faer and mapped to
//! [`SolverError::Singular`].

use crate::error::{NonFiniteLocation, SolverError};
use crate::linear::{
    singular_error, Equilibration, LinearSolver, Scratch, DEFAULT_PIVOT_TOLERANCE,
};
use crate::pattern::{check_len, SparsityPattern};
use faer::dyn_stack::StackReq;
use faer::perm::PermRef;
use faer::sparse::linalg::lu::{factorize_symbolic_lu, simplicial, LuSymbolicParams, SymbolicLu};
use faer::sparse::linalg::{LuError, SupernodalThreshold};
use faer::sparse::SparseColMatRef;
use faer::{Conj, MatMut, Par};

/// Sparse LU with a fill-reducing ordering computed once. Square matrices only.
#[derive(Debug)]
pub struct SparseLu {
    pattern: Option<SparsityPattern>,
    symbolic: Option<SymbolicLu<usize>>,
    lu: simplicial::SimplicialLu<usize, f64>,
    row_perm: Vec<usize>,
    row_perm_inv: Vec<usize>,
    values: Vec<f64>,
    mem: Scratch,
    pivot_tolerance: f64,
    factored: bool,
    pivot_rows: Vec<usize>,
    equil: Equilibration,
}

impl Default for SparseLu {
    fn default() -> Self {
        Self::new()
    }
}

impl SparseLu {
    /// A sparse LU with the default pivot tolerance.
    pub fn new() -> Self {
        Self {
            pattern: None,
            symbolic: None,
            lu: simplicial::SimplicialLu::new(),
            row_perm: Vec::new(),
            row_perm_inv: Vec::new(),
            values: Vec::new(),
            mem: Scratch::empty(),
            pivot_tolerance: DEFAULT_PIVOT_TOLERANCE,
            factored: false,
            pivot_rows: Vec::new(),
            equil: Equilibration::default(),
        }
    }

    /// Sets the pivot tolerance (singular if a pivot of the equilibrated matrix is `≤ tol`).
    pub fn with_pivot_tolerance(mut self, tol: f64) -> Self {
        self.pivot_tolerance = tol;
        self
    }

    /// Sizes the factor storage at analysis: faer's simplicial LU grows its `L`/`U` vectors when a
    /// factorization produces more fill than every earlier one, which depends on the pivot
    /// sequence. Factoring a few matrices with the pattern and random values (pivots all over the
    /// place, hence more fill than a mechanism's usual near-diagonal pivoting) leaves enough
    /// capacity, with the amortized doubling of `Vec`, that later factorizations do not allocate
    /// in practice. Errors here are ignored (a structurally singular pattern fails later, with
    /// the real values).
    fn presize_factor_storage(&mut self) {
        let (Some(pattern), Some(symbolic)) = (self.pattern.as_ref(), self.symbolic.as_ref())
        else {
            return;
        };
        let mut state = 0x9E37_79B9_7F4A_7C15u64;
        for _ in 0..3 {
            for v in self.values.iter_mut() {
                state ^= state << 13;
                state ^= state >> 7;
                state ^= state << 17;
                *v = (state >> 11) as f64 / (1u64 << 53) as f64 - 0.5;
            }
            let a = SparseColMatRef::new(pattern.symbolic(), &self.values);
            let _ = simplicial::factorize_simplicial_numeric_lu(
                &mut self.row_perm,
                &mut self.row_perm_inv,
                &mut self.lu,
                a,
                symbolic.col_perm(),
                self.mem.stack(),
            );
        }
    }

    /// Number of stored entries in `L + U` after the last factorization (fill measure).
    pub fn factor_nnz(&self) -> usize {
        if self.factored {
            self.lu.l_factor_unsorted().compute_nnz() + self.lu.u_factor_unsorted().compute_nnz()
        } else {
            0
        }
    }
}

impl LinearSolver for SparseLu {
    fn analyze(&mut self, pattern: &SparsityPattern) -> Result<(), SolverError> {
        let (m, n) = (pattern.nrows(), pattern.ncols());
        if m != n {
            return Err(SolverError::NotSquare { nrows: m, ncols: n });
        }
        let params = LuSymbolicParams {
            supernodal_flop_ratio_threshold: SupernodalThreshold::FORCE_SIMPLICIAL,
            ..Default::default()
        };
        let symbolic = factorize_symbolic_lu(pattern.symbolic(), params)
            .map_err(|e| SolverError::Backend(format!("symbolic LU: {e:?}")))?;
        let req = StackReq::any_of(&[
            simplicial::factorize_simplicial_numeric_lu_scratch::<usize, f64>(n, n),
            simplicial::solve_in_place_scratch::<usize, f64>(n, 1, Par::Seq),
        ]);
        self.mem = Scratch::try_new(req)?;
        self.symbolic = Some(symbolic);
        self.row_perm = vec![0; n];
        self.row_perm_inv = vec![0; n];
        self.values = vec![0.0; pattern.nnz()];
        self.pivot_rows = Vec::with_capacity(n);
        self.equil = Equilibration::new(n, n);
        self.lu = simplicial::SimplicialLu::new();
        self.pattern = Some(pattern.clone());
        self.factored = false;
        self.presize_factor_storage();
        Ok(())
    }

    fn factor(&mut self, slots: &[f64]) -> Result<(), SolverError> {
        self.factored = false;
        let (Some(pattern), Some(symbolic)) = (self.pattern.as_ref(), self.symbolic.as_ref())
        else {
            return Err(SolverError::NotReady { missing: "analyze" });
        };
        pattern.check_finite(slots)?;
        pattern.scatter_csc(slots, &mut self.values)?;
        {
            let sym = pattern.symbolic();
            self.equil
                .apply_csc(sym.col_ptr(), sym.row_idx(), &mut self.values);
        }
        let a = SparseColMatRef::new(pattern.symbolic(), &self.values);
        let result = simplicial::factorize_simplicial_numeric_lu(
            &mut self.row_perm,
            &mut self.row_perm_inv,
            &mut self.lu,
            a,
            symbolic.col_perm(),
            self.mem.stack(),
        );
        match result {
            Ok(()) => {}
            Err(LuError::SymbolicSingular { .. }) => {
                // A column with no pivot candidate: structurally singular. The dense analysis
                // names the equations when the matrix is small enough.
                return Err(singular_error(pattern, slots, &[]));
            }
            Err(e) => return Err(SolverError::Backend(format!("numeric LU: {e:?}"))),
        }
        // The diagonal of U is the last stored entry of each of its columns.
        let tol = self.pivot_tolerance;
        self.pivot_rows.clear();
        {
            let u = self.lu.u_factor_unsorted();
            let col_ptr = u.symbolic().col_ptr();
            let vals = u.val();
            for j in 0..pattern.ncols() {
                let end = col_ptr[j + 1];
                let d = if end > col_ptr[j] { vals[end - 1] } else { 0.0 };
                if d.abs() <= tol || d.is_nan() {
                    self.pivot_rows.push(self.row_perm[j]);
                }
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
        let Some(symbolic) = self.symbolic.as_ref() else {
            return Err(SolverError::NotReady { missing: "analyze" });
        };
        let n = self.row_perm.len();
        check_len("right-hand side", n, b.len())?;
        check_len("solution", n, x.len())?;
        if let Some(index) = b.iter().position(|v| !v.is_finite()) {
            return Err(SolverError::NonFinite {
                location: NonFiniteLocation::RightHandSide { index },
                iteration: None,
            });
        }
        self.equil.scale_rhs(b, x);
        self.lu.solve_in_place_with_conj(
            PermRef::new_checked(&self.row_perm, &self.row_perm_inv, n),
            symbolic.col_perm(),
            Conj::No,
            MatMut::from_column_major_slice_mut(x, n, 1),
            Par::Seq,
            self.mem.stack(),
        );
        self.equil.unscale_solution(x);
        if let Some(unknown) = x.iter().position(|v| !v.is_finite()) {
            return Err(SolverError::NonFinite {
                location: NonFiniteLocation::Solution { unknown },
                iteration: None,
            });
        }
        Ok(())
    }

    fn nrows(&self) -> usize {
        self.row_perm.len()
    }

    fn ncols(&self) -> usize {
        self.row_perm.len()
    }

    fn name(&self) -> &'static str {
        "sparse-lu"
    }
}
