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
//! and their width.
//! * Index width: up to [`NARROW_MAX`] unknowns and nonzeros, faer's factors and this struct's
//!   maps use 32-bit indices (half the bytes of `usize`); larger patterns use `usize`. faer keeps
//!   signed 32-bit positions in COLAMD and in the factors' column pointers, so the bound leaves
//!   room for 2³¹ / 2²⁶ = 32 times the fill of the matrix itself (mechanism patterns fill 1.1 to
//!   3 times), and a presizing run with more than [`NARROW_MAX_FACTOR`] entries in `L + U`
//!   switches to `usize` at analysis.
//! * Passes: without duplicate slots, `factor` places each slot at its compressed-column
//!   position with the finiteness check and the row maxima of the equilibration in the same
//!   loop, then scales one column at a time while it is in L1. With duplicates (summed) the
//!   values are zeroed, summed, and their row maxima taken in a pass of their own.

use crate::equilibration::Equilibration;
use crate::error::{NonFiniteLocation, SolverError};
use crate::linear::LinearSolver;
use crate::pattern::{check_len, SparsityPattern};
use crate::scratch::Scratch;
use crate::singular::{singular_error, DEFAULT_PIVOT_TOLERANCE};
use crate::sparse_refactor::Refactor;
use faer::dyn_stack::StackReq;
use faer::perm::PermRef;
use faer::sparse::linalg::lu::{factorize_symbolic_lu, simplicial, LuSymbolicParams, SymbolicLu};
use faer::sparse::linalg::{LuError, SupernodalThreshold};
use faer::sparse::{SparseColMatRef, SymbolicSparseColMat};
use faer::{Conj, Index, MatMut, Par};

/// Largest number of unknowns and of nonzeros for which [`SparseLu`] uses 32-bit indices (2²⁶).
pub const NARROW_MAX: usize = 1 << 26;

/// Largest number of entries of `L + U` after the presizing factorizations for which
/// [`SparseLu`] keeps 32-bit indices (2³⁰, half of faer's signed 32-bit positions).
pub const NARROW_MAX_FACTOR: usize = 1 << 30;

/// What depends on the index type: the pattern in compressed columns, the slot maps, faer's
/// symbolic and numeric LU and the row permutation.
#[derive(Debug)]
struct Indexed<I: Index> {
    csc: SymbolicSparseColMat<I>,
    /// Per slot: its position in the compressed-column values, and its row.
    slot_pos: Vec<I>,
    slot_row: Vec<I>,
    symbolic: SymbolicLu<I>,
    lu: simplicial::SimplicialLu<I, f64>,
    row_perm: Vec<I>,
    row_perm_inv: Vec<I>,
    /// The factors of the last factorization, refactored with the same pivots when they still
    /// pass the threshold check ([`crate::sparse_refactor`]).
    refactor: Refactor<I>,
}

/// The index width chosen at analysis.
#[derive(Debug)]
enum Width {
    Narrow(Indexed<u32>),
    Wide(Indexed<usize>),
}

/// Calls `$body` with `$x` bound to the [`Indexed`] of either width.
macro_rules! with_width {
    ($w:expr, $x:ident => $body:expr) => {
        match $w {
            Width::Narrow($x) => $body,
            Width::Wide($x) => $body,
        }
    };
}

impl<I: Index> Indexed<I> {
    /// The symbolic analysis of `pattern` (square, `n` unknowns) with indices of type `I`, and
    /// the scratch memory its factorizations and solves need.
    fn analyze(pattern: &SparsityPattern, n: usize) -> Result<(Self, Scratch), SolverError> {
        let sym = pattern.symbolic();
        let narrow = |v: &usize| I::truncate(*v);
        let csc = SymbolicSparseColMat::new_checked(
            n,
            n,
            sym.col_ptr().iter().map(narrow).collect(),
            None,
            sym.row_idx().iter().map(narrow).collect(),
        );
        let params = LuSymbolicParams {
            supernodal_flop_ratio_threshold: SupernodalThreshold::FORCE_SIMPLICIAL,
            ..Default::default()
        };
        let symbolic = factorize_symbolic_lu(csc.as_ref(), params)
            .map_err(|e| SolverError::Backend(format!("symbolic LU: {e:?}")))?;
        let req = StackReq::any_of(&[
            simplicial::factorize_simplicial_numeric_lu_scratch::<I, f64>(n, n),
            simplicial::solve_in_place_scratch::<I, f64>(n, 1, Par::Seq),
        ]);
        let mem = Scratch::try_new(req)?;
        let indexed = Self {
            csc,
            slot_pos: pattern.slot_to_csc().iter().map(narrow).collect(),
            slot_row: pattern.entries().map(|(r, _)| I::truncate(r)).collect(),
            symbolic,
            lu: simplicial::SimplicialLu::new(),
            row_perm: vec![I::truncate(0); n],
            row_perm_inv: vec![I::truncate(0); n],
            refactor: Refactor::new(),
        };
        Ok((indexed, mem))
    }

    /// faer's numeric LU of the equilibrated `values`.
    fn factor_values(&mut self, values: &[f64], mem: &mut Scratch) -> Result<(), LuError> {
        simplicial::factorize_simplicial_numeric_lu(
            &mut self.row_perm,
            &mut self.row_perm_inv,
            &mut self.lu,
            SparseColMatRef::new(self.csc.as_ref(), values),
            self.symbolic.col_perm(),
            mem.stack(),
        )
    }

    /// Sizes the factor storage at analysis: faer's simplicial LU grows its `L`/`U` vectors
    /// when a factorization produces more fill than every earlier one, which depends on the
    /// pivot sequence. One factorization of the pattern with random values leaves capacity
    /// (with the amortized doubling of `Vec`) for the fill of later ones in practice. One, not
    /// several: on a 10,000-body chain three random matrices gave fills within 0.02 % of each
    /// other (and 0.9 % below the real matrix's), and the two extra factorizations were a
    /// ninth of `cardan check`. Errors here are ignored (a structurally singular pattern fails
    /// later, with the real values). Returns the fill `L + U` (0 if the factorization failed).
    fn presize(&mut self, values: &mut [f64], mem: &mut Scratch) -> usize {
        let mut state = 0x9E37_79B9_7F4A_7C15u64;
        for v in values.iter_mut() {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            *v = (state >> 11) as f64 / (1u64 << 53) as f64 - 0.5;
        }
        let mut fill = 0;
        if self.factor_values(values, mem).is_ok() {
            fill = self.factor_nnz();
            self.capture();
        }
        self.refactor.invalidate();
        fill
    }

    /// Keeps faer's last factorization for refactoring with its pivots.
    fn capture(&mut self) {
        self.refactor
            .capture(&self.lu, &self.row_perm_inv, self.symbolic.col_perm());
    }

    /// Refactors the equilibrated `values` with the pivots of the last factorization; `false`
    /// if there is none or a pivot is no longer acceptable.
    fn try_refactor(&mut self, values: &[f64], tol: f64) -> bool {
        self.refactor
            .refactor(self.csc.col_ptr(), self.csc.row_idx(), values, tol)
    }

    fn factor_nnz(&self) -> usize {
        self.lu.l_factor_unsorted().compute_nnz() + self.lu.u_factor_unsorted().compute_nnz()
    }

    /// Places the slots at their compressed-column positions and equilibrates; `false` if a
    /// value is not finite (`values` and `equil` are then unusable).
    fn assemble(
        &self,
        slots: &[f64],
        duplicates: bool,
        values: &mut [f64],
        equil: &mut Equilibration,
    ) -> bool {
        let mut finite = true;
        if duplicates {
            values.fill(0.0);
            for (&v, &p) in slots.iter().zip(&self.slot_pos) {
                finite &= v.is_finite();
                values[p.zx()] += v;
            }
            if !finite {
                return false;
            }
            equil.row_max_csc(self.csc.row_idx(), values);
        } else {
            // One pass: place, check, row maxima.
            let row = &mut equil.row;
            row.fill(0.0);
            for ((&v, &p), &i) in slots.iter().zip(&self.slot_pos).zip(&self.slot_row) {
                finite &= v.is_finite();
                values[p.zx()] = v;
                let (a, r) = (v.abs(), &mut row[i.zx()]);
                if a > *r {
                    *r = a;
                }
            }
            if !finite {
                return false;
            }
        }
        equil.scale_csc(self.csc.col_ptr(), self.csc.row_idx(), values);
        true
    }

    /// Rows (of the equilibrated matrix's pivot order) whose pivot `|u_jj|` is `≤ tol` or NaN.
    fn small_pivots(&self, tol: f64, out: &mut Vec<usize>) {
        out.clear();
        let u = self.lu.u_factor_unsorted();
        let col_ptr = u.symbolic().col_ptr();
        let vals = u.val();
        for j in 0..self.row_perm.len() {
            // The diagonal of U is the last stored entry of each of its columns.
            let (start, end) = (col_ptr[j].zx(), col_ptr[j + 1].zx());
            let d = if end > start { vals[end - 1] } else { 0.0 };
            if d.abs() <= tol || d.is_nan() {
                out.push(self.row_perm[j].zx());
            }
        }
    }

    fn solve_in_place(&mut self, x: &mut [f64], mem: &mut Scratch) {
        if self.refactor.is_valid() {
            self.refactor.solve_in_place(x);
            return;
        }
        let n = self.row_perm.len();
        self.lu.solve_in_place_with_conj(
            PermRef::new_checked(&self.row_perm, &self.row_perm_inv, n),
            self.symbolic.col_perm(),
            Conj::No,
            MatMut::from_column_major_slice_mut(x, n, 1),
            Par::Seq,
            mem.stack(),
        );
    }
}

/// How many factorizations a [`SparseLu`] made, by kind ([`SparseLu::factorization_counts`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct FactorizationCounts {
    /// Those that chose their pivots afresh (faer's simplicial LU).
    pub pivoted: usize,
    /// Those that reused the previous pivot sequence ([`crate::sparse_refactor`]).
    pub refactored: usize,
}

/// Sparse LU with a fill-reducing ordering computed once. Square matrices only.
#[derive(Debug)]
pub struct SparseLu {
    pattern: Option<SparsityPattern>,
    indexed: Option<Width>,
    /// Whether two slots share an entry (they are summed: the values are zeroed first and the
    /// row maxima taken after assembly).
    duplicates: bool,
    values: Vec<f64>,
    mem: Scratch,
    pivot_tolerance: f64,
    factored: bool,
    pivot_rows: Vec<usize>,
    equil: Equilibration,
    /// Whether factorizations after the first reuse its pivots when they pass the check.
    reuse_pivots: bool,
    /// Factorizations that chose their pivots afresh, and those that reused the last ones.
    counts: [usize; 2],
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
            indexed: None,
            duplicates: false,
            values: Vec::new(),
            mem: Scratch::empty(),
            pivot_tolerance: DEFAULT_PIVOT_TOLERANCE,
            factored: false,
            pivot_rows: Vec::new(),
            equil: Equilibration::default(),
            reuse_pivots: true,
            counts: [0; 2],
        }
    }

    /// Successful factorizations so far: those that chose their pivots afresh and those that
    /// reused the previous pivot sequence.
    pub fn factorization_counts(&self) -> FactorizationCounts {
        FactorizationCounts {
            pivoted: self.counts[0],
            refactored: self.counts[1],
        }
    }

    /// Whether a factorization reuses the pivot sequence of the previous one while its pivots
    /// pass the threshold check ([`crate::sparse_refactor`]; on by default). Off: every
    /// factorization pivots afresh (faer's simplicial LU), as a reference.
    pub fn with_pivot_reuse(mut self, reuse: bool) -> Self {
        self.reuse_pivots = reuse;
        self
    }

    /// Sets the pivot tolerance (singular if a pivot of the equilibrated matrix is `≤ tol`).
    pub fn with_pivot_tolerance(mut self, tol: f64) -> Self {
        self.pivot_tolerance = tol;
        self
    }

    /// Number of stored entries in `L + U` after the last factorization (fill measure).
    pub fn factor_nnz(&self) -> usize {
        match (&self.indexed, self.factored) {
            (Some(w), true) => with_width!(w, x => x.factor_nnz()),
            _ => 0,
        }
    }

    /// Whether the analysis chose 32-bit indices (see the [module docs](self)).
    pub fn uses_32_bit_indices(&self) -> bool {
        matches!(self.indexed, Some(Width::Narrow(_)))
    }

    /// [`analyze`](LinearSolver::analyze) with a choice of index width: `narrow` if the pattern
    /// allows it, 64-bit otherwise or when the presizing run's fill exceeds
    /// [`NARROW_MAX_FACTOR`].
    fn analyze_with(&mut self, pattern: &SparsityPattern, narrow: bool) -> Result<(), SolverError> {
        // Nothing of an earlier analysis survives a failed one.
        self.pattern = None;
        self.indexed = None;
        self.factored = false;
        let (m, n) = (pattern.nrows(), pattern.ncols());
        if m != n {
            return Err(SolverError::NotSquare { nrows: m, ncols: n });
        }
        let mut values = vec![0.0; pattern.nnz()];
        let narrow = narrow && n <= NARROW_MAX && pattern.nnz() <= NARROW_MAX;
        let (mut indexed, mut mem) = if narrow {
            let (x, mem) = Indexed::<u32>::analyze(pattern, n)?;
            (Width::Narrow(x), mem)
        } else {
            let (x, mem) = Indexed::<usize>::analyze(pattern, n)?;
            (Width::Wide(x), mem)
        };
        let fill = with_width!(&mut indexed, x => x.presize(&mut values, &mut mem));
        if narrow && fill > NARROW_MAX_FACTOR {
            return self.analyze_with(pattern, false);
        }
        self.indexed = Some(indexed);
        self.mem = mem;
        self.values = values;
        self.pivot_rows = Vec::with_capacity(n);
        self.equil = Equilibration::new(n, n);
        self.duplicates = pattern.num_slots() != pattern.nnz();
        self.pattern = Some(pattern.clone());
        Ok(())
    }
}

impl LinearSolver for SparseLu {
    fn analyze(&mut self, pattern: &SparsityPattern) -> Result<(), SolverError> {
        self.analyze_with(pattern, true)
    }

    fn factor(&mut self, slots: &[f64]) -> Result<(), SolverError> {
        self.factored = false;
        let (Some(pattern), Some(indexed)) = (self.pattern.as_ref(), self.indexed.as_mut()) else {
            return Err(SolverError::NotReady { missing: "analyze" });
        };
        check_len("Jacobian slot values", pattern.num_slots(), slots.len())?;
        let (values, equil, mem) = (&mut self.values, &mut self.equil, &mut self.mem);
        let duplicates = self.duplicates;
        if !with_width!(&*indexed, x => x.assemble(slots, duplicates, values, equil)) {
            // Name the first offending slot.
            pattern.check_finite(slots)?;
        }
        let tol = self.pivot_tolerance;
        if self.reuse_pivots && with_width!(indexed, x => x.try_refactor(values, tol)) {
            self.counts[1] += 1;
            self.factored = true;
            return Ok(());
        }
        with_width!(indexed, x => x.refactor.invalidate());
        match with_width!(indexed, x => x.factor_values(values, mem)) {
            Ok(()) => {}
            Err(LuError::SymbolicSingular { .. }) => {
                // A column with no pivot candidate: structurally singular. The dense analysis
                // names the equations when the matrix is small enough.
                return Err(singular_error(pattern, slots, &[]));
            }
            Err(e) => return Err(SolverError::Backend(format!("numeric LU: {e:?}"))),
        }
        with_width!(&*indexed, x => x.small_pivots(tol, &mut self.pivot_rows));
        if !self.pivot_rows.is_empty() {
            return Err(singular_error(pattern, slots, &self.pivot_rows));
        }
        if self.reuse_pivots {
            with_width!(indexed, x => x.capture());
        }
        self.counts[0] += 1;
        self.factored = true;
        Ok(())
    }

    fn solve(&mut self, b: &[f64], x: &mut [f64]) -> Result<(), SolverError> {
        if !self.factored {
            return Err(SolverError::NotReady { missing: "factor" });
        }
        let Some(indexed) = self.indexed.as_mut() else {
            return Err(SolverError::NotReady { missing: "analyze" });
        };
        let n = self.equil.col.len();
        check_len("right-hand side", n, b.len())?;
        check_len("solution", n, x.len())?;
        if let Some(index) = b.iter().position(|v| !v.is_finite()) {
            return Err(SolverError::NonFinite {
                location: NonFiniteLocation::RightHandSide { index },
                iteration: None,
            });
        }
        self.equil.scale_rhs(b, x);
        let mem = &mut self.mem;
        with_width!(indexed, w => w.solve_in_place(x, mem));
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
        self.pattern.as_ref().map_or(0, SparsityPattern::nrows)
    }

    fn ncols(&self) -> usize {
        self.pattern.as_ref().map_or(0, SparsityPattern::ncols)
    }

    fn name(&self) -> &'static str {
        "sparse-lu"
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A 3-body-like banded pattern with random values and a dominant diagonal.
    fn system(n: usize) -> (SparsityPattern, Vec<f64>, Vec<f64>) {
        let mut entries = Vec::new();
        for i in 0..n {
            for j in i.saturating_sub(3)..(i + 4).min(n) {
                entries.push((i, j));
            }
        }
        let mut state = 12345u64;
        let slots: Vec<f64> = entries
            .iter()
            .map(|&(i, j)| {
                state = state
                    .wrapping_mul(6364136223846793005)
                    .wrapping_add(1442695040888963407);
                let r = (state >> 11) as f64 / (1u64 << 53) as f64 - 0.5;
                if i == j {
                    4.0 + r
                } else {
                    r * 1e3f64.powf(r)
                }
            })
            .collect();
        let b = (0..n).map(|i| (i as f64).sin()).collect();
        (SparsityPattern::new(n, n, &entries).unwrap(), slots, b)
    }

    #[test]
    fn both_index_widths_give_the_same_bits() {
        let (p, slots, b) = system(200);
        let mut narrow = SparseLu::new();
        narrow.analyze(&p).unwrap();
        assert!(narrow.uses_32_bit_indices());
        let mut wide = SparseLu::new();
        wide.analyze_with(&p, false).unwrap();
        assert!(!wide.uses_32_bit_indices());
        let (mut x_n, mut x_w) = (vec![0.0; 200], vec![0.0; 200]);
        for s in [narrow, wide].iter_mut().zip([&mut x_n, &mut x_w]) {
            s.0.factor(&slots).unwrap();
            s.0.solve(&b, s.1).unwrap();
        }
        assert!(x_n
            .iter()
            .zip(&x_w)
            .all(|(a, b)| a.to_bits() == b.to_bits()));
        assert!(x_n.iter().any(|v| *v != 0.0));
    }

    /// Solves with pivot reuse and with fresh pivoting; the largest difference relative to
    /// the solution's size.
    fn reuse_vs_fresh(
        reuse: &mut SparseLu,
        fresh: &mut SparseLu,
        slots: &[f64],
        b: &[f64],
    ) -> Result<f64, SolverError> {
        let n = b.len();
        let (mut x_r, mut x_f) = (vec![0.0; n], vec![0.0; n]);
        reuse.factor(slots)?;
        reuse.solve(b, &mut x_r)?;
        fresh.factor(slots)?;
        fresh.solve(b, &mut x_f)?;
        let scale = x_f.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        Ok(x_r
            .iter()
            .zip(&x_f)
            .fold(0.0f64, |m, (a, b)| m.max((a - b).abs()))
            / scale)
    }

    #[test]
    fn refactoring_with_kept_pivots_solves_as_fresh_pivoting_does() {
        let (p, slots, b) = system(120);
        let mut reuse = SparseLu::new();
        reuse.analyze(&p).unwrap();
        let mut fresh = SparseLu::new().with_pivot_reuse(false);
        fresh.analyze(&p).unwrap();
        // A smooth drift of the values, as from frame to frame of a motion.
        for step in 0..20 {
            let t = f64::from(step) * 0.05;
            let moved: Vec<f64> = slots
                .iter()
                .enumerate()
                .map(|(k, v)| v * (1.0 + 0.2 * (t + k as f64).sin()))
                .collect();
            let diff = reuse_vs_fresh(&mut reuse, &mut fresh, &moved, &b).unwrap();
            assert!(diff < 1e-12, "step {step}: {diff:e}");
        }
        let FactorizationCounts {
            pivoted,
            refactored,
        } = reuse.factorization_counts();
        assert_eq!(pivoted + refactored, 20);
        assert!(
            refactored >= 15,
            "{pivoted} pivoted, {refactored} refactored"
        );
        assert_eq!(
            fresh.factorization_counts(),
            FactorizationCounts {
                pivoted: 20,
                refactored: 0
            }
        );
    }

    #[test]
    fn a_kept_pivot_that_became_small_is_chosen_again() {
        // [[a, 1], [1, 1]] with a from 2 to 1e-6: partial pivoting first takes row 0, and row
        // 1 once a < 0.1 (the threshold); a kept pivot of 1e-6 would lose six digits.
        let p = SparsityPattern::new(2, 2, &[(0, 0), (0, 1), (1, 0), (1, 1)]).unwrap();
        let mut reuse = SparseLu::new();
        reuse.analyze(&p).unwrap();
        let mut fresh = SparseLu::new().with_pivot_reuse(false);
        fresh.analyze(&p).unwrap();
        let b = [1.0, 2.0];
        for a in [2.0, 1.0, 0.5, 0.2, 1e-3, 1e-6] {
            let diff = reuse_vs_fresh(&mut reuse, &mut fresh, &[a, 1.0, 1.0, 3.0], &b).unwrap();
            assert!(diff < 1e-15, "a = {a}: {diff:e}");
        }
        let FactorizationCounts {
            pivoted,
            refactored,
        } = reuse.factorization_counts();
        assert!(pivoted >= 2 && refactored >= 2, "{pivoted}, {refactored}");
    }

    #[test]
    fn a_singular_matrix_after_a_regular_one_is_reported_as_singular() {
        let p = SparsityPattern::new(2, 2, &[(0, 0), (0, 1), (1, 0), (1, 1)]).unwrap();
        let mut s = SparseLu::new();
        s.analyze(&p).unwrap();
        s.factor(&[2.0, 1.0, 1.0, 3.0]).unwrap();
        assert!(matches!(
            s.factor(&[1.0, 2.0, 2.0, 4.0]),
            Err(SolverError::Singular { .. })
        ));
        let mut x = [0.0; 2];
        assert!(matches!(
            s.solve(&[1.0, 1.0], &mut x),
            Err(SolverError::NotReady { .. })
        ));
        s.factor(&[2.0, 1.0, 1.0, 3.0]).unwrap();
        s.solve(&[3.0, 4.0], &mut x).unwrap();
        assert!(
            (x[0] - 1.0).abs() < 1e-15 && (x[1] - 1.0).abs() < 1e-15,
            "{x:?}"
        );
    }

    #[test]
    fn a_failed_analysis_leaves_nothing_of_the_previous_one() {
        let (p, slots, _) = system(10);
        let mut s = SparseLu::new();
        s.analyze(&p).unwrap();
        s.factor(&slots).unwrap();
        let rect = SparsityPattern::new(2, 3, &[(0, 0), (1, 1), (1, 2)]).unwrap();
        assert!(matches!(
            s.analyze(&rect),
            Err(SolverError::NotSquare { .. })
        ));
        assert_eq!((s.nrows(), s.ncols(), s.factor_nnz()), (0, 0, 0));
        assert!(matches!(
            s.factor(&slots),
            Err(SolverError::NotReady { missing: "analyze" })
        ));
        let mut x = vec![0.0; 10];
        assert!(matches!(
            s.solve(&x.clone(), &mut x),
            Err(SolverError::NotReady { .. })
        ));
    }
}
