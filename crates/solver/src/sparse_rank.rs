//! Sparse rank analysis: the redundant equations of a large Jacobian in about linear time.
//!
//! # Method
//! The dense analysis ([`crate::rank`]) factors `(D J)ᵀ` with a column-pivoted QR: `O(m n²)` time
//! and `m n` memory (52 s and 0.3 GB for a 1,000-body chain). Its answer, on the constraint
//! manifold, is the *lexicographic* basis of the rows: equation `i` is dependent exactly when it
//! lies (within the tolerance) in the span of the equations before it, since the pivoting takes
//! the lowest-numbered row whose orthogonal part is not small. The same basis is found here
//! without forming anything dense, in three steps.
//!
//! 1. **Scaling**, exactly as the dense analysis: columns by powers of two to largest entry about
//!    1 (over the whole matrix), rows to unit Euclidean norm, `tol = max(relative_tolerance,
//!    10 · max(m, n) · ε)`.
//! 2. **Row-by-row sparse elimination in equation order** (Gaussian elimination with threshold
//!    pivoting, Duff, Erisman & Reid, *Direct Methods for Sparse Matrices*, 2nd ed., §5.4 and
//!    §9.2). Each accepted row `u_k` has a pivot column; row `i` is reduced by the accepted rows
//!    that own a column of its pattern (in acceptance order, with fill followed),
//!
//!    ```text
//!      u_i = a_i − Σ_k l_ik u_k,     u_i(pivot column of k) = 0 for every k used,
//!    ```
//!
//!    and is dependent when `‖u_i‖ ≤ tol`: then `a_i` is (numerically) a combination of earlier
//!    rows. Otherwise it is accepted with the pivot column of lowest index among its entries of at
//!    least 0.1 of its largest (threshold pivoting: stability, and on a chain listed body after
//!    body the pivots stay on the older body, so fill stays local and the cost is linear).
//! 3. **Dense check of each dependent group.** For each dependent row (and each accepted row whose
//!    remainder was below 0.1, ten times the preference threshold, where the dense pivoting
//!    could order the rows differently), the
//!    combination `a_i ≈ Σ y_j a_j` is expanded back to original rows through `l` (a sparse
//!    triangular solve, coefficients below `1e-10` of the largest dropped); rows of overlapping
//!    combinations are merged into groups (a loop of a mechanism, typically a few dozen rows), and
//!    the dense analysis with the same tolerance and preference rule is run on each group's rows
//!    and columns, with the global column scaling. Its dependent rows are the answer (a group
//!    of more than 10⁶ entries, a single loop of hundreds of bodies, keeps the elimination's
//!    answer, which differs only in near-singular configurations). Rows in no
//!    group are independent of all others, so the dense analysis of the whole matrix would keep
//!    them too; inside a group the dense rule decides, so near-singular choices (the preference
//!    threshold) are the dense ones as well.
//!
//! Cost: proportional to the nonzeros of the reduced rows (linear for chains and trees listed body
//! after body, and for loops of bounded size), plus the dense analysis of the groups. The result
//! is a [`RankAnalysis`] like the dense one (its [`pivots`](RankAnalysis::pivots) are the
//! remainder norms `‖u_i‖` of the accepted rows in acceptance order, then the largest dependent
//! remainder).

use crate::error::SolverError;
use crate::pattern::SparsityPattern;
use crate::rank::{RankAnalysis, RankOptions, SPARSE_RANK_MIN_UNKNOWNS};
use std::cmp::Reverse;
use std::collections::{BTreeMap, BinaryHeap};

/// The sparse analysis and the switch between it and the dense one. They are defined here, beside
/// the elimination they call, so that the dense analysis (`rank.rs`) does not depend on the
/// sparse one.
impl RankAnalysis {
    /// The sparse analysis (this module): the same rows as [`compute`](Self::compute)
    /// (the dense analysis decides inside each group of dependent rows), in about linear time
    /// and memory for chains, trees and loops of bounded size.
    ///
    /// # Errors
    /// [`SolverError::DimensionMismatch`], [`SolverError::NonFinite`].
    pub fn compute_sparse(
        pattern: &SparsityPattern,
        slots: &[f64],
        options: RankOptions,
    ) -> Result<Self, SolverError> {
        analyze(pattern, slots, options)
    }

    /// The dense analysis below [`SPARSE_RANK_MIN_UNKNOWNS`] unknowns, the sparse one from there
    /// on: the one switch point for callers that analyze models of any size.
    ///
    /// # Errors
    /// [`SolverError::DimensionMismatch`], [`SolverError::NonFinite`].
    pub fn compute_auto(
        pattern: &SparsityPattern,
        slots: &[f64],
        options: RankOptions,
    ) -> Result<Self, SolverError> {
        if pattern.ncols() >= SPARSE_RANK_MIN_UNKNOWNS {
            Self::compute_sparse(pattern, slots, options)
        } else {
            Self::compute(pattern, slots, options)
        }
    }
}

/// Threshold of the pivot choice: entries of at least this fraction of the row's largest may be
/// the pivot (the one of lowest column index is taken).
const PIVOT_THRESHOLD: f64 = 0.1;

/// Accepted rows whose remainder is below this multiple of the preference threshold (relative to
/// unit rows; 0.1 with the default threshold) are checked by the dense analysis of their group as
/// well: the dense pivoting postpones a row whose orthogonal part is below the preference
/// threshold, and may then drop it instead of a later row.
const GRAY_ZONE_FACTOR: f64 = 10.0;

/// Coefficients of an expanded combination smaller than this fraction of the largest are
/// rounding noise (the combination of a loop's rows has exact zeros on the rest of the chain).
const COMBINATION_DROP: f64 = 1e-10;

/// Largest group (rows × columns) checked by the dense analysis (about 0.1 s); a larger one (a
/// single loop of more than about 200 bodies) keeps the elimination's answer, the same except
/// in near-singular configurations.
const DENSE_GROUP_MAX_ENTRIES: usize = 1_000_000;

/// Layers of surrounding rows added to a group before its dense check (see [`surround`]).
const HALO_LAYERS: usize = 2;

/// Fill smaller than this fraction of the row's largest entry is dropped (rounding noise).
const FILL_DROP: f64 = 1e-15;

/// An accepted (reduced) row `u_k`.
struct Accepted {
    /// Original row.
    row: usize,
    pivot: usize,
    /// Entries (column, value), pivot included.
    entries: Vec<(usize, f64)>,
}

/// Sparse rank analysis with the answer of [`RankAnalysis::compute`] (see the module docs).
///
/// # Errors
/// [`SolverError::DimensionMismatch`], [`SolverError::NonFinite`].
pub fn analyze(
    pattern: &SparsityPattern,
    slots: &[f64],
    options: RankOptions,
) -> Result<RankAnalysis, SolverError> {
    pattern.check_finite(slots)?;
    let (m, n) = (pattern.nrows(), pattern.ncols());
    let rows = scaled_rows(pattern, slots, options)?;
    let tol = options
        .relative_tolerance
        .max(10.0 * (m.max(n) as f64) * f64::EPSILON);
    let gray = (GRAY_ZONE_FACTOR * options.preference_threshold.clamp(0.0, 1.0)).min(0.1);
    let mut elim = Elimination::new(m, n);
    let mut candidates = Vec::new();
    let mut pivots = Vec::new();
    let mut worst_dependent = 0.0f64;
    for (i, row) in rows.iter().enumerate() {
        let norm = elim.reduce(i, row);
        if norm <= tol {
            elim.clear();
            elim.dependent[i] = true;
            candidates.push(i);
            worst_dependent = worst_dependent.max(norm);
        } else {
            pivots.push(norm);
            if norm <= gray {
                candidates.push(i);
            }
            elim.accept(i);
        }
    }
    if !candidates.is_empty() {
        pivots.push(worst_dependent);
    }
    let groups = elim.groups(&candidates);
    let mut col_rows: Vec<Vec<usize>> = vec![Vec::new(); n];
    if !groups.is_empty() {
        for (i, row) in rows.iter().enumerate() {
            for &(c, _) in row {
                col_rows[c].push(i);
            }
        }
    }
    let regions = merge_overlapping(
        groups
            .iter()
            .map(|g| surround(&rows, &col_rows, g, HALO_LAYERS))
            .collect(),
    );
    let mut dependent = Vec::new();
    for region in regions {
        match dense_group(&rows, &region, tol, options)? {
            Some(d) => dependent.extend(d),
            // Too large for the dense check: the elimination's answer.
            None => dependent.extend(region.iter().filter(|&&r| elim.dependent[r])),
        }
    }
    dependent.sort_unstable();
    let mut independent = Vec::with_capacity(m - dependent.len());
    let mut d = dependent.iter().peekable();
    for i in 0..m {
        if d.peek() == Some(&&i) {
            d.next();
        } else {
            independent.push(i);
        }
    }
    Ok(RankAnalysis::from_parts(
        (m, n),
        independent,
        dependent,
        tol,
        pivots,
    ))
}

/// The rows of `J`, duplicates summed, columns scaled by powers of two (when asked) and rows
/// normalized to unit length, each sorted by column.
fn scaled_rows(
    pattern: &SparsityPattern,
    slots: &[f64],
    options: RankOptions,
) -> Result<Vec<Vec<(usize, f64)>>, SolverError> {
    let (m, n) = (pattern.nrows(), pattern.ncols());
    let mut csc = vec![0.0; pattern.nnz()];
    pattern.scatter_csc(slots, &mut csc)?;
    let sym = pattern.symbolic();
    let (col_ptr, row_idx) = (sym.col_ptr(), sym.row_idx());
    let mut col_scale = vec![1.0; n];
    if options.equilibrate_columns {
        for (c, s) in col_scale.iter_mut().enumerate() {
            let big = csc[col_ptr[c]..col_ptr[c + 1]]
                .iter()
                .fold(0.0f64, |a, v| a.max(v.abs()));
            if big > 0.0 && big.is_finite() {
                *s = 2f64.powi(-(big.log2().round() as i32));
            }
        }
    }
    let mut rows: Vec<Vec<(usize, f64)>> = vec![Vec::new(); m];
    for c in 0..n {
        for k in col_ptr[c]..col_ptr[c + 1] {
            rows[row_idx[k]].push((c, csc[k] * col_scale[c]));
        }
    }
    for row in &mut rows {
        let norm = row.iter().map(|e| e.1 * e.1).sum::<f64>().sqrt();
        let s = if norm > 0.0 { 1.0 / norm } else { 0.0 };
        row.iter_mut().for_each(|e| e.1 *= s);
    }
    Ok(rows)
}

/// State of the row-by-row elimination.
struct Elimination {
    accepted: Vec<Accepted>,
    /// Accepted index owning each column as pivot.
    owner: Vec<Option<usize>>,
    /// Multipliers `l_ik` (accepted index, value) of every row.
    l: Vec<Vec<(usize, f64)>>,
    /// Rows the elimination found dependent.
    dependent: Vec<bool>,
    /// Dense work row, the columns touched, and which accepted rows are queued.
    w: Vec<f64>,
    touched: Vec<usize>,
    mark: Vec<bool>,
    queued: Vec<bool>,
    heap: BinaryHeap<Reverse<usize>>,
}

impl Elimination {
    fn new(m: usize, n: usize) -> Self {
        Self {
            accepted: Vec::new(),
            owner: vec![None; n],
            l: vec![Vec::new(); m],
            dependent: vec![false; m],
            w: vec![0.0; n],
            touched: Vec::new(),
            mark: vec![false; n],
            queued: vec![false; m],
            heap: BinaryHeap::new(),
        }
    }

    fn touch(&mut self, c: usize, heap: &mut BinaryHeap<Reverse<usize>>) {
        if !self.mark[c] {
            self.mark[c] = true;
            self.touched.push(c);
            if let Some(k) = self.owner[c] {
                if !self.queued[k] {
                    self.queued[k] = true;
                    heap.push(Reverse(k));
                }
            }
        }
    }

    /// Reduces row `i` by the accepted rows (multipliers into `l[i]`); the remainder stays in the
    /// work row. Returns its Euclidean norm.
    fn reduce(&mut self, i: usize, row: &[(usize, f64)]) -> f64 {
        let mut heap = std::mem::take(&mut self.heap);
        for &(c, v) in row {
            self.touch(c, &mut heap);
            self.w[c] += v;
        }
        while let Some(Reverse(k)) = heap.pop() {
            self.queued[k] = false;
            let piv = self.accepted[k].pivot;
            let pv = self.accepted[k]
                .entries
                .iter()
                .find(|e| e.0 == piv)
                .map_or(1.0, |e| e.1);
            let mult = self.w[piv] / pv;
            if mult == 0.0 {
                continue;
            }
            self.l[i].push((k, mult));
            let entries = std::mem::take(&mut self.accepted[k].entries);
            for &(c, v) in &entries {
                self.touch(c, &mut heap);
                self.w[c] -= mult * v;
            }
            self.accepted[k].entries = entries;
            self.w[piv] = 0.0;
        }
        self.heap = heap;
        self.touched
            .iter()
            .filter(|&&c| self.owner[c].is_none())
            .map(|&c| self.w[c] * self.w[c])
            .sum::<f64>()
            .sqrt()
    }

    /// Accepts the remainder in the work row as `u` of row `i` (a dependent row's remainder is
    /// dropped with [`clear`](Self::clear) instead).
    fn accept(&mut self, i: usize) {
        let big = self
            .touched
            .iter()
            .filter(|&&c| self.owner[c].is_none())
            .fold(0.0f64, |a, &c| a.max(self.w[c].abs()));
        let mut pivot = usize::MAX;
        let mut entries = Vec::new();
        for &c in &self.touched {
            let v = self.w[c];
            if self.owner[c].is_some() || v.abs() <= FILL_DROP * big {
                continue;
            }
            entries.push((c, v));
            if v.abs() >= PIVOT_THRESHOLD * big && c < pivot {
                pivot = c;
            }
        }
        entries.sort_unstable_by_key(|e| e.0);
        self.owner[pivot] = Some(self.accepted.len());
        self.accepted.push(Accepted {
            row: i,
            pivot,
            entries,
        });
        self.clear();
    }

    fn clear(&mut self) {
        for &c in &self.touched {
            self.w[c] = 0.0;
            self.mark[c] = false;
        }
        self.touched.clear();
    }

    /// Original rows of the combination `a_i ≈ Σ_k l_ik u_k` expanded through `u_k = a_{row(k)} −
    /// Σ_j l_{row(k), j} u_j`, small coefficients dropped; `i` included.
    fn combination(&self, i: usize) -> Vec<usize> {
        let mut coef: BTreeMap<usize, f64> = BTreeMap::new();
        for &(k, v) in &self.l[i] {
            *coef.entry(k).or_insert(0.0) += v;
        }
        let big = coef.values().fold(0.0f64, |a, v| a.max(v.abs()));
        let mut rows = vec![i];
        while let Some((k, c)) = coef.pop_last() {
            if c.abs() <= COMBINATION_DROP * big {
                continue;
            }
            let a = &self.accepted[k];
            rows.push(a.row);
            for &(j, v) in &self.l[a.row] {
                *coef.entry(j).or_insert(0.0) -= c * v;
            }
        }
        rows
    }

    /// Groups of rows: the combinations of the candidate rows, merged where they share a row.
    fn groups(&self, candidates: &[usize]) -> Vec<Vec<usize>> {
        let mut parent: BTreeMap<usize, usize> = BTreeMap::new();
        fn find(parent: &mut BTreeMap<usize, usize>, x: usize) -> usize {
            let p = *parent.entry(x).or_insert(x);
            if p == x {
                return x;
            }
            let r = find(parent, p);
            parent.insert(x, r);
            r
        }
        for &i in candidates {
            let rows = self.combination(i);
            let root = find(&mut parent, i);
            for r in rows {
                let other = find(&mut parent, r);
                if other != root {
                    parent.insert(other, root);
                }
            }
        }
        let keys: Vec<usize> = parent.keys().copied().collect();
        let mut groups: BTreeMap<usize, Vec<usize>> = BTreeMap::new();
        for r in keys {
            let root = find(&mut parent, r);
            groups.entry(root).or_default().push(r);
        }
        groups.into_values().collect()
    }
}

/// The rows `group` and `layers` layers of rows around them (rows sharing a column with the rows
/// so far), sorted.
fn surround(
    rows: &[Vec<(usize, f64)>],
    col_rows: &[Vec<usize>],
    group: &[usize],
    layers: usize,
) -> Vec<usize> {
    let mut all = group.to_vec();
    for _ in 0..layers {
        let mut next = all.clone();
        for &r in &all {
            for &(c, _) in &rows[r] {
                next.extend(&col_rows[c]);
            }
        }
        next.sort_unstable();
        next.dedup();
        all = next;
    }
    all
}

/// Unions of the sets that share an element (transitively), each sorted.
fn merge_overlapping(sets: Vec<Vec<usize>>) -> Vec<Vec<usize>> {
    let mut owner: BTreeMap<usize, usize> = BTreeMap::new();
    let mut parent: Vec<usize> = (0..sets.len()).collect();
    fn find(parent: &mut [usize], x: usize) -> usize {
        let mut r = x;
        while parent[r] != r {
            r = parent[r];
        }
        parent[x] = r;
        r
    }
    for (k, set) in sets.iter().enumerate() {
        for &r in set {
            if let Some(&j) = owner.get(&r) {
                let (a, b) = (find(&mut parent, j), find(&mut parent, k));
                parent[a.max(b)] = a.min(b);
            } else {
                owner.insert(r, k);
            }
        }
    }
    let mut merged: BTreeMap<usize, Vec<usize>> = BTreeMap::new();
    for (k, set) in sets.into_iter().enumerate() {
        let root = find(&mut parent, k);
        merged.entry(root).or_default().extend(set);
    }
    merged
        .into_values()
        .map(|mut v| {
            v.sort_unstable();
            v.dedup();
            v
        })
        .collect()
}

/// The dense analysis of the rows `group` (sorted) on the columns they touch: its dependent rows
/// (`None` when the group has more than [`DENSE_GROUP_MAX_ENTRIES`] entries: a single loop of
/// thousands of bodies).
fn dense_group(
    rows: &[Vec<(usize, f64)>],
    group: &[usize],
    tol: f64,
    options: RankOptions,
) -> Result<Option<Vec<usize>>, SolverError> {
    let mut cols: Vec<usize> = group
        .iter()
        .flat_map(|&r| rows[r].iter().map(|e| e.0))
        .collect();
    cols.sort_unstable();
    cols.dedup();
    let local = |c: usize| cols.binary_search(&c).expect("collected above");
    let (mg, ng) = (group.len(), cols.len());
    if mg.saturating_mul(ng) > DENSE_GROUP_MAX_ENTRIES {
        return Ok(None);
    }
    let mut entries = Vec::new();
    let mut values = Vec::new();
    for (lr, &r) in group.iter().enumerate() {
        for &(c, v) in &rows[r] {
            entries.push((lr, local(c)));
            values.push(v);
        }
    }
    let pattern = SparsityPattern::new(mg, ng, &entries)?;
    let dense = RankAnalysis::compute(
        &pattern,
        &values,
        RankOptions {
            relative_tolerance: tol,
            equilibrate_columns: false,
            ..options
        },
    )?;
    Ok(Some(
        dense.dependent_rows().iter().map(|&k| group[k]).collect(),
    ))
}
