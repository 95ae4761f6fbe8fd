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
//!
//! Memory traffic: on a large model (a 10,000-body chain has 660,000 nonzeros) a factorization
//! streams arrays far larger than the caches, so its cost is the number of passes over them
//! and their width. The indices are 32-bit (faer's factors and this struct's maps: half the
//! bytes of `usize`), and `factor` makes two passes before faer's: the slots go straight to
//! their compressed-column positions, with the finiteness check and the row maxima of the
//! equilibration in the same loop, then one pass per column scales it. Patterns beyond
//! 2³² − 1 nonzeros or unknowns are refused at [`analyze`](LinearSolver::analyze).

use crate::error::{NonFiniteLocation, SolverError};
use crate::linear::{
    singular_error, Equilibration, LinearSolver, Scratch, DEFAULT_PIVOT_TOLERANCE,
};
use crate::pattern::{check_len, SparsityPattern};
use faer::dyn_stack::StackReq;
use faer::perm::PermRef;
use faer::sparse::linalg::lu::{factorize_symbolic_lu, simplicial, LuSymbolicParams, SymbolicLu};
use faer::sparse::linalg::{LuError, SupernodalThreshold};
use faer::sparse::{SparseColMatRef, SymbolicSparseColMat};
use faer::{Conj, MatMut, Par};

/// Sparse LU with a fill-reducing ordering computed once. Square matrices only.
#[derive(Debug)]
pub struct SparseLu {
    pattern: Option<SparsityPattern>,
    /// The pattern's compressed columns with 32-bit indices.
    csc: Option<SymbolicSparseColMat<u32>>,
    /// Per slot: its position in the compressed-column values, and its row.
    slot_pos: Vec<u32>,
    slot_row: Vec<u32>,
    /// Whether two slots share an entry (they are summed: the values are zeroed first and the
    /// row maxima taken after assembly).
    duplicates: bool,
    symbolic: Option<SymbolicLu<u32>>,
    lu: simplicial::SimplicialLu<u32, f64>,
    row_perm: Vec<u32>,
    row_perm_inv: Vec<u32>,
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
            csc: None,
            slot_pos: Vec::new(),
            slot_row: Vec::new(),
            duplicates: false,
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
        let (Some(csc), Some(symbolic)) = (self.csc.as_ref(), self.symbolic.as_ref()) else {
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
            let a = SparseColMatRef::new(csc.as_ref(), &self.values);
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
        let too_large = |what: &str| {
            SolverError::Backend(format!(
                "sparse LU: {what} exceeds 2^32 - 1 (32-bit indices); split the model"
            ))
        };
        let narrow = |v: usize| u32::try_from(v);
        if narrow(n).is_err() || narrow(pattern.nnz()).is_err() {
            return Err(too_large("the number of unknowns or nonzeros"));
        }
        let sym = pattern.symbolic();
        let col_ptr: Vec<u32> = sym.col_ptr().iter().map(|&v| v as u32).collect();
        let row_idx: Vec<u32> = sym.row_idx().iter().map(|&v| v as u32).collect();
        let csc = SymbolicSparseColMat::new_checked(n, n, col_ptr, None, row_idx);
        self.slot_pos = pattern.slot_to_csc().iter().map(|&p| p as u32).collect();
        self.slot_row = pattern.entries().map(|(r, _)| r as u32).collect();
        self.duplicates = pattern.num_slots() != pattern.nnz();
        let params = LuSymbolicParams {
            supernodal_flop_ratio_threshold: SupernodalThreshold::FORCE_SIMPLICIAL,
            ..Default::default()
        };
        let symbolic = factorize_symbolic_lu(csc.as_ref(), params)
            .map_err(|e| SolverError::Backend(format!("symbolic LU: {e:?}")))?;
        let req = StackReq::any_of(&[
            simplicial::factorize_simplicial_numeric_lu_scratch::<u32, f64>(n, n),
            simplicial::solve_in_place_scratch::<u32, f64>(n, 1, Par::Seq),
        ]);
        self.mem = Scratch::try_new(req)?;
        self.symbolic = Some(symbolic);
        self.csc = Some(csc);
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
        let (Some(pattern), Some(csc), Some(symbolic)) = (
            self.pattern.as_ref(),
            self.csc.as_ref(),
            self.symbolic.as_ref(),
        ) else {
            return Err(SolverError::NotReady { missing: "analyze" });
        };
        check_len("Jacobian slot values", self.slot_pos.len(), slots.len())?;
        // One pass over the slots: place each value, check that it is finite and, without
        // duplicates, take the row maxima of the equilibration.
        let mut finite = true;
        let values = &mut self.values;
        if self.duplicates {
            values.fill(0.0);
            for (&v, &p) in slots.iter().zip(&self.slot_pos) {
                finite &= v.is_finite();
                values[p as usize] += v;
            }
        } else {
            let row = &mut self.equil.row;
            row.fill(0.0);
            for ((&v, &p), &i) in slots.iter().zip(&self.slot_pos).zip(&self.slot_row) {
                finite &= v.is_finite();
                values[p as usize] = v;
                let (a, r) = (v.abs(), &mut row[i as usize]);
                if a > *r {
                    *r = a;
                }
            }
        }
        if !finite {
            // Name the first offending slot.
            pattern.check_finite(slots)?;
        }
        if self.duplicates {
            self.equil.row_max_csc(csc.row_idx(), values);
        }
        self.equil.scale_csc(csc.col_ptr(), csc.row_idx(), values);
        let a = SparseColMatRef::new(csc.as_ref(), &self.values);
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
                let (start, end) = (col_ptr[j] as usize, col_ptr[j + 1] as usize);
                let d = if end > start { vals[end - 1] } else { 0.0 };
                if d.abs() <= tol || d.is_nan() {
                    self.pivot_rows.push(self.row_perm[j] as usize);
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
