//! Products with Φ_v held by groups of six values ([`Group`]): Φ_v x and Φ_vᵀ λ over the
//! active rows, one pass over the values each. No allocation.

use super::layout::Group;

/// y (active rows) = Φ_v x.
pub(crate) fn mul(groups: &[Group], jac: &[f64], x: &[f64], y: &mut [f64]) {
    y.fill(0.0);
    for (g, v) in groups.iter().zip(jac.chunks_exact(6)) {
        let x = &x[g.col..g.col + 6];
        let mut s = y[g.row];
        for c in 0..6 {
            s += v[c] * x[c];
        }
        y[g.row] = s;
    }
}

/// y (n) += Φ_vᵀ λ (λ over active rows).
pub(crate) fn t_mul_add(groups: &[Group], jac: &[f64], lambda: &[f64], y: &mut [f64]) {
    for (g, v) in groups.iter().zip(jac.chunks_exact(6)) {
        let l = lambda[g.row];
        let y = &mut y[g.col..g.col + 6];
        for c in 0..6 {
            y[c] += v[c] * l;
        }
    }
}

/// y (n) += Φ_vᵀ λ and size (n) += |Φ_vᵀ| |λ| (entrywise absolute values: the size of the
/// terms of Φ_vᵀλ), in one pass over Φ_v.
pub(crate) fn t_mul_add_with_size(
    groups: &[Group],
    jac: &[f64],
    lambda: &[f64],
    y: &mut [f64],
    size: &mut [f64],
) {
    for (g, v) in groups.iter().zip(jac.chunks_exact(6)) {
        let l = lambda[g.row];
        let y = &mut y[g.col..g.col + 6];
        let size = &mut size[g.col..g.col + 6];
        for c in 0..6 {
            let t = v[c] * l;
            y[c] += t;
            size[c] += t.abs();
        }
    }
}
