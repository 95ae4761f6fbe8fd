//! From the system's Jacobian to the linear solver's matrix: row selection and scaling as a map
//! over slots.
//!
//! The system writes `Φ_q` in the slot order of the full [`SparsityPattern`]. The linear solver
//! sees the kept rows only (with a [`RowSelection`]) and, with scaling, the matrix
//! `E⁻¹ Φ_q U` (equation scales `E`, unknown scales `U`): solver slot `k` at full row `i`,
//! column `j` holds `a_src(k) · w_i / v_j` with the weights `w = 1/e`, `v = 1/u`. Right-hand
//! sides are gathered the same way, `b_k = ±rhs_{row_k} · w_{row_k}`, and solutions scaled back,
//! `Δq_j = y_j / v_j`. Everything is an index map computed once; an update is a gather.

use super::weights::Weights;
use crate::pattern::{RowSelection, SparsityPattern};

/// Index maps from full slots and rows to the linear solver's slots and rows.
#[derive(Debug)]
pub(super) struct SlotMap {
    /// For each solver slot: full slot (empty without a row selection: the identity). 32-bit:
    /// on a large model these maps are streamed at every factorization and refinement, and half
    /// the width is half the memory traffic.
    src: Vec<u32>,
    /// For each solver slot: full row and column.
    pub(super) row: Vec<u32>,
    pub(super) col: Vec<u32>,
    /// For each solver slot: `w_row / v_col` (the scaling of the linear system).
    scale: Vec<f64>,
    /// For each solver row: full row.
    pub(super) solve_rows: Vec<usize>,
    /// The full rows the selection drops (empty without one).
    pub(super) dropped_rows: Vec<usize>,
}

impl SlotMap {
    /// The maps for `pattern` (whose slots, rows and columns fit in 32 bits) and an optional
    /// selection made from it.
    pub(super) fn new(pattern: &SparsityPattern, selection: Option<&RowSelection>) -> Self {
        let m = pattern.nrows();
        let (full, solve_rows): (Vec<usize>, Vec<usize>) = match selection {
            Some(sel) => (sel.slot_map().to_vec(), sel.rows().to_vec()),
            None => ((0..pattern.num_slots()).collect(), (0..m).collect()),
        };
        // In range: the caller checked the index width.
        let narrow = |v: usize| v as u32;
        let row = full.iter().map(|&k| narrow(pattern.entry(k).0)).collect();
        let col = full.iter().map(|&k| narrow(pattern.entry(k).1)).collect();
        let num_solve_slots = full.len();
        let src = if selection.is_some() {
            full.into_iter().map(narrow).collect()
        } else {
            Vec::new()
        };
        let mut kept = vec![false; m];
        for &r in &solve_rows {
            kept[r] = true;
        }
        let dropped_rows = (0..m).filter(|&r| !kept[r]).collect();
        Self {
            src,
            row,
            col,
            scale: vec![1.0; num_solve_slots],
            solve_rows,
            dropped_rows,
        }
    }

    /// Number of solver slots.
    pub(super) fn num_slots(&self) -> usize {
        self.scale.len()
    }

    /// Recomputes the slot scales `w_row / v_col` from new weights.
    pub(super) fn rescale(&mut self, weights: &Weights) {
        for k in 0..self.scale.len() {
            self.scale[k] =
                weights.eq[self.row[k] as usize] / weights.unknown[self.col[k] as usize];
        }
    }

    /// The solver's slot values from the full ones, scaled if `scaled`; returns whether every
    /// value is finite (the check folded into the copy).
    pub(super) fn gather(&self, full: &[f64], dst: &mut [f64], scaled: bool) -> bool {
        let scale = scaled.then_some(self.scale.as_slice());
        if self.src.is_empty() {
            gather_slots(dst, full.iter().copied(), scale)
        } else {
            let src = self.src.iter().map(|&k| full[k as usize]);
            gather_slots(dst, src, scale)
        }
    }

    /// `rhs_k = sign · full[row_k] · w_row_k` (`w = 1` unscaled). No allocation.
    pub(super) fn gather_rhs(
        &self,
        full: &[f64],
        sign: f64,
        weights: &Weights,
        scaled: bool,
        rhs: &mut [f64],
    ) {
        for (dst, &r) in rhs.iter_mut().zip(&self.solve_rows) {
            let w = if scaled { weights.eq[r] } else { 1.0 };
            *dst = sign * full[r] * w;
        }
    }

    /// `r_i −= a_k v_j` and `s_i += |a_k v_j|` for each solver slot `k = (i, j)` with its full
    /// value `a_k`: the residual of `Φ_q v = rhs` and the scale of its backward error.
    pub(super) fn residual_and_scale(&self, full: &[f64], v: &[f64], r: &mut [f64], s: &mut [f64]) {
        if self.src.is_empty() {
            residual_and_scale(r, s, full.iter().copied(), &self.row, &self.col, v);
        } else {
            let src = self.src.iter().map(|&k| full[k as usize]);
            residual_and_scale(r, s, src, &self.row, &self.col, v);
        }
    }
}

/// `dst[k] = v_k · w_k` (or `v_k` without scales) for the values `v` in slot order; returns
/// whether every value is finite.
#[inline]
fn gather_slots(dst: &mut [f64], values: impl Iterator<Item = f64>, scale: Option<&[f64]>) -> bool {
    let mut finite = true;
    match scale {
        Some(w) => {
            for ((d, v), &w) in dst.iter_mut().zip(values).zip(w) {
                finite &= v.is_finite();
                *d = v * w;
            }
        }
        None => {
            for (d, v) in dst.iter_mut().zip(values) {
                finite &= v.is_finite();
                *d = v;
            }
        }
    }
    finite
}

#[inline]
fn residual_and_scale(
    r: &mut [f64],
    s: &mut [f64],
    values: impl Iterator<Item = f64>,
    rows: &[u32],
    cols: &[u32],
    v: &[f64],
) {
    for ((a, &i), &j) in values.zip(rows).zip(cols) {
        let av = a * v[j as usize];
        r[i as usize] -= av;
        s[i as usize] += av.abs();
    }
}
