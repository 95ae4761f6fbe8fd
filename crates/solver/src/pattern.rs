//! The fixed sparsity pattern of a Jacobian and its slot array.
//!
//! A mechanism's Jacobian has the same structure at every step: only the values change. A
//! [`SparsityPattern`] is built once from the list of `(row, col)` entries, in the order the caller
//! will write them. Each entry is a *slot*: the caller keeps a `Vec<f64>` of length
//! [`SparsityPattern::num_slots`] and, every step, writes slot `k` with the value of entry `k`. The
//! structure is never rebuilt; solvers gather the slots into their own storage (compressed
//! columns for the sparse path, a dense array for the dense one) through index maps computed here.
//!
//! Duplicate entries are allowed and are **summed** (convenient when two constraints touch the
//! same Jacobian entry). An explicitly listed entry whose value is zero stays in the structure.

use crate::error::SolverError;
use faer::sparse::{SymbolicSparseColMat, SymbolicSparseColMatRef};

/// Fixed `(row, col)` structure of an `m × n` matrix, with values held by the caller in slot order.
///
/// ```
/// use cardan_solver::SparsityPattern;
/// // [[2, 1], [0, 3]] written as three slots
/// let p = SparsityPattern::new(2, 2, &[(0, 0), (0, 1), (1, 1)]).unwrap();
/// let slots = [2.0, 1.0, 3.0];
/// let mut y = [0.0; 2];
/// p.mul_vec(&slots, &[1.0, 1.0], &mut y).unwrap();
/// assert_eq!(y, [3.0, 3.0]);
/// ```
#[derive(Debug, Clone)]
pub struct SparsityPattern {
    nrows: usize,
    ncols: usize,
    slot_row: Vec<usize>,
    slot_col: Vec<usize>,
    /// Position of each slot in the compressed-column value array.
    slot_to_csc: Vec<usize>,
    symbolic: SymbolicSparseColMat<usize>,
}

impl SparsityPattern {
    /// Builds the pattern of an `nrows × ncols` matrix from its entries, in slot order.
    ///
    /// # Errors
    /// [`SolverError::EntryOutOfBounds`] if an entry lies outside the matrix.
    pub fn new(
        nrows: usize,
        ncols: usize,
        entries: &[(usize, usize)],
    ) -> Result<Self, SolverError> {
        for (index, &(row, col)) in entries.iter().enumerate() {
            if row >= nrows || col >= ncols {
                return Err(SolverError::EntryOutOfBounds {
                    index,
                    row,
                    col,
                    nrows,
                    ncols,
                });
            }
        }
        let order = column_major_order(ncols, entries);
        let mut col_ptr = vec![0usize; ncols + 1];
        let mut row_idx = Vec::with_capacity(entries.len());
        let mut slot_to_csc = vec![0usize; entries.len()];
        let mut last: Option<(usize, usize)> = None;
        for &k in &order {
            let (r, c) = entries[k];
            if last != Some((r, c)) {
                row_idx.push(r);
                col_ptr[c + 1] += 1;
                last = Some((r, c));
            }
            slot_to_csc[k] = row_idx.len() - 1;
        }
        for c in 0..ncols {
            col_ptr[c + 1] += col_ptr[c];
        }
        let symbolic = SymbolicSparseColMat::new_checked(nrows, ncols, col_ptr, None, row_idx);
        Ok(Self {
            nrows,
            ncols,
            slot_row: entries.iter().map(|e| e.0).collect(),
            slot_col: entries.iter().map(|e| e.1).collect(),
            slot_to_csc,
            symbolic,
        })
    }

    /// Dense pattern (every entry present, column-major slot order): convenient for tests and
    /// small systems.
    pub fn dense(nrows: usize, ncols: usize) -> Self {
        let entries: Vec<(usize, usize)> = (0..ncols)
            .flat_map(|c| (0..nrows).map(move |r| (r, c)))
            .collect();
        Self::new(nrows, ncols, &entries).expect("entries are in bounds by construction")
    }

    /// Number of rows (equations).
    pub fn nrows(&self) -> usize {
        self.nrows
    }

    /// Number of columns (unknowns).
    pub fn ncols(&self) -> usize {
        self.ncols
    }

    /// Number of slots (entries as given, duplicates counted): the length of the value array.
    pub fn num_slots(&self) -> usize {
        self.slot_row.len()
    }

    /// Number of structurally distinct entries (duplicates merged).
    pub fn nnz(&self) -> usize {
        self.symbolic.row_idx().len()
    }

    /// Fraction of the `m × n` entries that are structurally present.
    pub fn density(&self) -> f64 {
        let total = self.nrows as f64 * self.ncols as f64;
        if total == 0.0 {
            0.0
        } else {
            self.nnz() as f64 / total
        }
    }

    /// `(row, col)` of slot `k`.
    pub fn entry(&self, k: usize) -> (usize, usize) {
        (self.slot_row[k], self.slot_col[k])
    }

    /// Iterator over the `(row, col)` of every slot, in slot order.
    pub fn entries(&self) -> impl ExactSizeIterator<Item = (usize, usize)> + '_ {
        self.slot_row
            .iter()
            .copied()
            .zip(self.slot_col.iter().copied())
    }

    /// The compressed-column structure, as faer sees it.
    pub fn symbolic(&self) -> SymbolicSparseColMatRef<'_, usize> {
        self.symbolic.as_ref()
    }

    /// Position of each slot in the compressed-column value array (duplicates share a position).
    pub fn slot_to_csc(&self) -> &[usize] {
        &self.slot_to_csc
    }

    pub(crate) fn check_slots(&self, slots: &[f64]) -> Result<(), SolverError> {
        if slots.len() != self.num_slots() {
            return Err(SolverError::DimensionMismatch {
                what: "Jacobian slot values",
                expected: self.num_slots(),
                found: slots.len(),
            });
        }
        Ok(())
    }

    /// Returns an error naming the first non-finite slot, if any.
    ///
    /// # Errors
    /// [`SolverError::NonFinite`] with [`NonFiniteLocation::Jacobian`](crate::NonFiniteLocation).
    pub fn check_finite(&self, slots: &[f64]) -> Result<(), SolverError> {
        self.check_slots(slots)?;
        match slots.iter().position(|v| !v.is_finite()) {
            None => Ok(()),
            Some(slot) => Err(SolverError::NonFinite {
                location: crate::NonFiniteLocation::Jacobian {
                    slot,
                    row: self.slot_row[slot],
                    col: self.slot_col[slot],
                },
                iteration: None,
            }),
        }
    }

    /// Sums the slots into compressed-column values (length [`nnz`](Self::nnz)). No allocation.
    ///
    /// # Errors
    /// [`SolverError::DimensionMismatch`] on wrong lengths.
    pub fn scatter_csc(&self, slots: &[f64], csc_values: &mut [f64]) -> Result<(), SolverError> {
        self.check_slots(slots)?;
        check_len("compressed-column values", self.nnz(), csc_values.len())?;
        csc_values.fill(0.0);
        for (k, &v) in slots.iter().enumerate() {
            csc_values[self.slot_to_csc[k]] += v;
        }
        Ok(())
    }

    /// Writes the matrix as a dense column-major `m × n` array (zeros elsewhere). No allocation.
    ///
    /// # Errors
    /// [`SolverError::DimensionMismatch`] on wrong lengths.
    pub fn to_dense_col_major(&self, slots: &[f64], out: &mut [f64]) -> Result<(), SolverError> {
        self.check_slots(slots)?;
        check_len("dense matrix", self.nrows * self.ncols, out.len())?;
        out.fill(0.0);
        for (k, &v) in slots.iter().enumerate() {
            out[self.slot_row[k] + self.nrows * self.slot_col[k]] += v;
        }
        Ok(())
    }

    /// Writes the **transpose** as a dense column-major `n × m` array (column `i` holds row `i`
    /// of the matrix). No allocation.
    ///
    /// # Errors
    /// [`SolverError::DimensionMismatch`] on wrong lengths.
    pub fn to_dense_transpose(&self, slots: &[f64], out: &mut [f64]) -> Result<(), SolverError> {
        self.check_slots(slots)?;
        check_len("dense transpose", self.nrows * self.ncols, out.len())?;
        out.fill(0.0);
        for (k, &v) in slots.iter().enumerate() {
            out[self.slot_col[k] + self.ncols * self.slot_row[k]] += v;
        }
        Ok(())
    }

    /// `y = J x`. No allocation.
    ///
    /// # Errors
    /// [`SolverError::DimensionMismatch`] on wrong lengths.
    pub fn mul_vec(&self, slots: &[f64], x: &[f64], y: &mut [f64]) -> Result<(), SolverError> {
        self.check_slots(slots)?;
        check_len("x in y = J x", self.ncols, x.len())?;
        check_len("y in y = J x", self.nrows, y.len())?;
        y.fill(0.0);
        for (k, &v) in slots.iter().enumerate() {
            y[self.slot_row[k]] += v * x[self.slot_col[k]];
        }
        Ok(())
    }

    /// `y = Jᵀ x`. No allocation.
    ///
    /// # Errors
    /// [`SolverError::DimensionMismatch`] on wrong lengths.
    pub fn mul_transpose_vec(
        &self,
        slots: &[f64],
        x: &[f64],
        y: &mut [f64],
    ) -> Result<(), SolverError> {
        self.check_slots(slots)?;
        check_len("x in y = Jᵀ x", self.nrows, x.len())?;
        check_len("y in y = Jᵀ x", self.ncols, y.len())?;
        y.fill(0.0);
        for (k, &v) in slots.iter().enumerate() {
            y[self.slot_col[k]] += v * x[self.slot_row[k]];
        }
        Ok(())
    }

    /// Sub-pattern made of the listed rows (in the order given), with the map from its slots to
    /// the slots of `self`. Use it to drop redundant equations once
    /// (see [`RankAnalysis::independent_rows`](crate::RankAnalysis)).
    ///
    /// # Errors
    /// [`SolverError::InvalidRowSelection`] if a row is out of range or repeated.
    pub fn select_rows(&self, rows: &[usize]) -> Result<RowSelection, SolverError> {
        let mut new_index = vec![usize::MAX; self.nrows];
        for (i, &r) in rows.iter().enumerate() {
            if r >= self.nrows {
                return Err(SolverError::InvalidRowSelection {
                    reason: format!(
                        "row {r} is out of range (the matrix has {} rows)",
                        self.nrows
                    ),
                });
            }
            if new_index[r] != usize::MAX {
                return Err(SolverError::InvalidRowSelection {
                    reason: format!("row {r} is listed twice"),
                });
            }
            new_index[r] = i;
        }
        let mut entries = Vec::new();
        let mut slot_map = Vec::new();
        for (k, (r, c)) in self.entries().enumerate() {
            if new_index[r] != usize::MAX {
                entries.push((new_index[r], c));
                slot_map.push(k);
            }
        }
        let pattern = SparsityPattern::new(rows.len(), self.ncols, &entries)?;
        Ok(RowSelection {
            rows: rows.to_vec(),
            full_rows: self.nrows,
            full_slots: self.num_slots(),
            pattern,
            slot_map,
        })
    }
}

/// A subset of the rows of a [`SparsityPattern`], decided once (for example after a
/// [`RankAnalysis`](crate::RankAnalysis) found redundant equations) and reused at every step.
#[derive(Debug, Clone)]
pub struct RowSelection {
    rows: Vec<usize>,
    full_rows: usize,
    full_slots: usize,
    pattern: SparsityPattern,
    slot_map: Vec<usize>,
}

impl RowSelection {
    /// The kept rows, as indices into the full system, in the order of the reduced system.
    pub fn rows(&self) -> &[usize] {
        &self.rows
    }

    /// The pattern of the reduced matrix.
    pub fn pattern(&self) -> &SparsityPattern {
        &self.pattern
    }

    /// For each slot of the reduced pattern, the slot of the full pattern it comes from.
    pub fn slot_map(&self) -> &[usize] {
        &self.slot_map
    }

    /// Copies the kept slots of a full slot array into a reduced one. No allocation.
    ///
    /// # Errors
    /// [`SolverError::DimensionMismatch`] on wrong lengths.
    pub fn gather_slots(&self, full: &[f64], reduced: &mut [f64]) -> Result<(), SolverError> {
        check_len("full Jacobian slots", self.full_slots, full.len())?;
        check_len("reduced Jacobian slots", self.slot_map.len(), reduced.len())?;
        for (dst, &k) in reduced.iter_mut().zip(&self.slot_map) {
            *dst = full[k];
        }
        Ok(())
    }

    /// Copies the kept components of a full-length vector (residual, ν, γ#) into a reduced one.
    /// No allocation.
    ///
    /// # Errors
    /// [`SolverError::DimensionMismatch`] on wrong lengths.
    pub fn gather_rows(&self, full: &[f64], reduced: &mut [f64]) -> Result<(), SolverError> {
        check_len("full equation vector", self.full_rows, full.len())?;
        check_len("reduced equation vector", self.rows.len(), reduced.len())?;
        for (dst, &r) in reduced.iter_mut().zip(&self.rows) {
            *dst = full[r];
        }
        Ok(())
    }
}

pub(crate) fn check_len(
    what: &'static str,
    expected: usize,
    found: usize,
) -> Result<(), SolverError> {
    if expected == found {
        Ok(())
    } else {
        Err(SolverError::DimensionMismatch {
            what,
            expected,
            found,
        })
    }
}

/// The slots ordered by column, then row: a counting sort by column (slot order kept within a
/// column), then each column's few slots sorted by row. Linear in the entries where a
/// comparison sort of them all is not: building the patterns was a sixth of `cardan check` on a
/// 10,000-body chain (three patterns of 740,000 entries).
fn column_major_order(ncols: usize, entries: &[(usize, usize)]) -> Vec<usize> {
    let mut start = vec![0usize; ncols + 1];
    for &(_, c) in entries {
        start[c + 1] += 1;
    }
    for c in 0..ncols {
        start[c + 1] += start[c];
    }
    let mut next = start.clone();
    let mut order = vec![0usize; entries.len()];
    for (k, &(_, c)) in entries.iter().enumerate() {
        order[next[c]] = k;
        next[c] += 1;
    }
    for c in 0..ncols {
        order[start[c]..start[c + 1]].sort_unstable_by_key(|&k| entries[k].0);
    }
    order
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn duplicates_are_summed_and_order_is_kept() {
        let p = SparsityPattern::new(2, 3, &[(1, 2), (0, 0), (1, 2), (0, 2)]).unwrap();
        assert_eq!(p.num_slots(), 4);
        assert_eq!(p.nnz(), 3);
        let mut dense = [0.0; 6];
        p.to_dense_col_major(&[1.0, 2.0, 10.0, 3.0], &mut dense)
            .unwrap();
        assert_eq!(dense, [2.0, 0.0, 0.0, 0.0, 3.0, 11.0]);
        let mut t = [0.0; 6];
        p.to_dense_transpose(&[1.0, 2.0, 10.0, 3.0], &mut t)
            .unwrap();
        assert_eq!(t, [2.0, 0.0, 3.0, 0.0, 0.0, 11.0]);
        let mut csc = [0.0; 3];
        p.scatter_csc(&[1.0, 2.0, 10.0, 3.0], &mut csc).unwrap();
        assert_eq!(csc, [2.0, 3.0, 11.0]);
    }

    proptest::proptest! {
        /// The compressed columns and slot map agree with a plain sort of the entries by
        /// (column, row), duplicates included.
        #[test]
        fn pattern_matches_a_sort_by_column_then_row(
            nrows in 1usize..12,
            ncols in 1usize..12,
            raw in proptest::collection::vec((0usize..12, 0usize..12), 0..80),
        ) {
            let entries: Vec<(usize, usize)> =
                raw.iter().map(|&(r, c)| (r % nrows, c % ncols)).collect();
            let p = SparsityPattern::new(nrows, ncols, &entries).unwrap();
            let mut distinct: Vec<(usize, usize)> =
                entries.iter().map(|&(r, c)| (c, r)).collect();
            distinct.sort_unstable();
            distinct.dedup();
            let sym = p.symbolic();
            let mut csc: Vec<(usize, usize)> = Vec::new();
            for c in 0..ncols {
                let (a, b) = (sym.col_ptr()[c], sym.col_ptr()[c + 1]);
                csc.extend(sym.row_idx()[a..b].iter().map(|&r| (c, r)));
            }
            proptest::prop_assert_eq!(&csc, &distinct);
            for (k, &(r, c)) in entries.iter().enumerate() {
                proptest::prop_assert_eq!(csc[p.slot_to_csc[k]], (c, r));
            }
        }
    }

    #[test]
    fn out_of_bounds_is_an_error_not_a_panic() {
        let e = SparsityPattern::new(2, 2, &[(0, 0), (2, 1)]).unwrap_err();
        assert!(matches!(
            e,
            SolverError::EntryOutOfBounds {
                index: 1,
                row: 2,
                ..
            }
        ));
        let p = SparsityPattern::new(2, 2, &[(0, 0)]).unwrap();
        assert!(p.mul_vec(&[1.0, 2.0], &[0.0; 2], &mut [0.0; 2]).is_err());
        assert!(p.select_rows(&[0, 0]).is_err());
        assert!(p.select_rows(&[3]).is_err());
    }

    #[test]
    fn row_selection_gathers() {
        let p = SparsityPattern::new(3, 2, &[(0, 0), (1, 1), (2, 0), (2, 1)]).unwrap();
        let s = p.select_rows(&[2, 0]).unwrap();
        assert_eq!(s.pattern().nrows(), 2);
        let mut red = [0.0; 3];
        s.gather_slots(&[1.0, 2.0, 3.0, 4.0], &mut red).unwrap();
        assert_eq!(red, [1.0, 3.0, 4.0]);
        let mut d = [0.0; 4];
        s.pattern().to_dense_col_major(&red, &mut d).unwrap();
        assert_eq!(d, [3.0, 1.0, 4.0, 0.0]);
        let mut r = [0.0; 2];
        s.gather_rows(&[7.0, 8.0, 9.0], &mut r).unwrap();
        assert_eq!(r, [9.0, 7.0]);
    }
}
