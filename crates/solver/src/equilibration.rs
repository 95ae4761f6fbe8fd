//! Row and column equilibration of the LU members, `J̃ = D_r J D_c` with powers of two (so the
//! scaling is exact): `D_r` makes every row's largest entry about 1, then `D_c` every column's.
//! The LU members factor `J̃`, so their pivot tolerance is relative to 1 whatever the units.

/// Row and column equilibration `J̃ = D_r J D_c` (scales are powers of two, so scaling is exact):
/// `D_r` makes every row's largest entry about 1, then `D_c` every column's. The LU members factor
/// `J̃`, so their pivot tolerance is relative to 1 whatever the units, and solve
/// `x = D_c J̃⁻¹ D_r b`.
#[derive(Debug, Clone, Default)]
pub(crate) struct Equilibration {
    pub(crate) row: Vec<f64>,
    pub(crate) col: Vec<f64>,
}

/// 2^−round(log2 max) (1 for zero, non-finite or negative input), from the exponent and
/// mantissa bits: round(log2(m 2^e)) = e + [m ≥ √2] for m ∈ [1, 2). Called per row and column
/// at every factorization, where log2/round/powi cost more than the scaling itself.
#[inline]
fn pow2_recip(max: f64) -> f64 {
    if max.is_nan() || max <= 0.0 || max.is_infinite() {
        return 1.0;
    }
    let bits = max.to_bits();
    let biased = ((bits >> 52) & 0x7ff) as i32;
    if biased == 0 {
        // Subnormal.
        return 2f64.powi(-(max.log2().round() as i32));
    }
    let mantissa = f64::from_bits((bits & 0x000f_ffff_ffff_ffff) | 0x3ff0_0000_0000_0000);
    let k = biased - 1023 + i32::from(mantissa >= std::f64::consts::SQRT_2);
    let e = 1023 - k;
    if (1..=2046).contains(&e) {
        f64::from_bits((e as u64) << 52)
    } else {
        2f64.powi(-k)
    }
}

impl Equilibration {
    pub(crate) fn new(m: usize, n: usize) -> Self {
        Self {
            row: vec![1.0; m],
            col: vec![1.0; n],
        }
    }

    /// Row maxima of a compressed-column matrix into `self.row` (the first half of
    /// [`scale_csc`](Self::scale_csc), for callers that cannot fold it into their assembly).
    /// The values must be finite.
    pub(crate) fn row_max_csc<I: faer::Index>(&mut self, row_idx: &[I], values: &[f64]) {
        self.row.fill(0.0);
        for (&i, v) in row_idx.iter().zip(values) {
            let (a, r) = (v.abs(), &mut self.row[i.zx()]);
            if a > *r {
                *r = a;
            }
        }
    }

    /// Scales a compressed-column matrix in place, with `self.row` holding the largest magnitude
    /// of each row on entry (replaced by the row scales): rows first, then each column by its
    /// own scale, one pass over the values (a column is short, its second loop runs in L1).
    /// The values must be finite.
    pub(crate) fn scale_csc<I: faer::Index>(
        &mut self,
        col_ptr: &[I],
        row_idx: &[I],
        values: &mut [f64],
    ) {
        for r in self.row.iter_mut() {
            *r = pow2_recip(*r);
        }
        for (j, c_out) in self.col.iter_mut().enumerate() {
            let range = col_ptr[j].zx()..col_ptr[j + 1].zx();
            let mut max = 0.0f64;
            for (v, &i) in values[range.clone()]
                .iter_mut()
                .zip(&row_idx[range.clone()])
            {
                *v *= self.row[i.zx()];
                let a = v.abs();
                if a > max {
                    max = a;
                }
            }
            let c = pow2_recip(max);
            *c_out = c;
            for v in &mut values[range] {
                *v *= c;
            }
        }
    }

    /// Computes the scales from the slots of a pattern without duplicate entries (`rows[k]`,
    /// `cols[k]` of slot `k`) and writes the scaled matrix into the zeroed dense column-major
    /// `out` at `dense[k]`: the same scales and values as [`apply_dense`](Self::apply_dense) on
    /// the assembled matrix (the zeros do not change a maximum), touching the slots only. The
    /// values must be finite.
    pub(crate) fn apply_slots(
        &mut self,
        slots: &[f64],
        rows: &[usize],
        cols: &[usize],
        dense: &[usize],
        out: &mut [f64],
    ) {
        // Plain comparisons: the values are finite (no NaN semantics needed).
        self.row.fill(0.0);
        for (v, &i) in slots.iter().zip(rows) {
            let a = v.abs();
            let r = &mut self.row[i];
            if a > *r {
                *r = a;
            }
        }
        for r in self.row.iter_mut() {
            *r = pow2_recip(*r);
        }
        self.col.fill(0.0);
        for ((v, &i), &j) in slots.iter().zip(rows).zip(cols) {
            let a = (v * self.row[i]).abs();
            let c = &mut self.col[j];
            if a > *c {
                *c = a;
            }
        }
        for c in self.col.iter_mut() {
            *c = pow2_recip(*c);
        }
        out.fill(0.0);
        for (((v, &i), &j), &d) in slots.iter().zip(rows).zip(cols).zip(dense) {
            out[d] = v * self.row[i] * self.col[j];
        }
    }

    /// Same for a dense column-major `m × n` matrix.
    pub(crate) fn apply_dense(&mut self, a: &mut [f64]) {
        let m = self.row.len();
        self.row.fill(0.0);
        for col in a.chunks_exact(m.max(1)) {
            for (r, v) in self.row.iter_mut().zip(col) {
                *r = r.max(v.abs());
            }
        }
        for r in self.row.iter_mut() {
            *r = pow2_recip(*r);
        }
        for (j, col) in a.chunks_exact_mut(m.max(1)).enumerate() {
            let mut max = 0.0f64;
            for (v, r) in col.iter_mut().zip(&self.row) {
                *v *= r;
                max = max.max(v.abs());
            }
            let c = pow2_recip(max);
            self.col[j] = c;
            col.iter_mut().for_each(|v| *v *= c);
        }
    }

    /// `x ← D_r b` (the right-hand side of the scaled system).
    pub(crate) fn scale_rhs(&self, b: &[f64], x: &mut [f64]) {
        for ((x, b), r) in x.iter_mut().zip(b).zip(&self.row) {
            *x = b * r;
        }
    }

    /// `x ← D_c y` (back to the unknowns of the original system).
    pub(crate) fn unscale_solution(&self, x: &mut [f64]) {
        for (x, c) in x.iter_mut().zip(&self.col) {
            *x *= c;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::pow2_recip;

    #[test]
    fn pow2_recip_matches_the_log2_formula() {
        let reference = |x: f64| 2f64.powi(-(x.log2().round() as i32));
        let mut x = 1e-300;
        while x < 1e300 {
            for f in [1.0, 1.2, 1.41, 1.415, 1.5, 1.9, 1.99] {
                let v = x * f;
                assert_eq!(pow2_recip(v), reference(v), "{v}");
            }
            x *= 7.3;
        }
        assert_eq!(pow2_recip(0.0), 1.0);
        assert_eq!(pow2_recip(f64::NAN), 1.0);
        assert_eq!(pow2_recip(f64::INFINITY), 1.0);
        assert_eq!(pow2_recip(-3.0), 1.0);
        assert_eq!(pow2_recip(1e-310), reference(1e-310));
    }
}
