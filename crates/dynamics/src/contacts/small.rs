//! The dense solve of the few stop rows' systems (W x = b).

/// Solves the dense k × k system `w` x = `b` in place (x into `b`) by Gaussian elimination
/// with partial pivoting; `false` when singular. No allocation.
pub(crate) fn solve_small(w: &mut [f64], b: &mut [f64], k: usize) -> bool {
    for c in 0..k {
        let p = (c..k)
            .max_by(|&x, &y| w[x * k + c].abs().total_cmp(&w[y * k + c].abs()))
            .expect("k > 0");
        if w[p * k + c].abs() < 1e-300 || !w[p * k + c].is_finite() {
            return false;
        }
        if p != c {
            for j in 0..k {
                w.swap(p * k + j, c * k + j);
            }
            b.swap(p, c);
        }
        for r in c + 1..k {
            let f = w[r * k + c] / w[c * k + c];
            for j in c..k {
                w[r * k + j] -= f * w[c * k + j];
            }
            b[r] -= f * b[c];
        }
    }
    for c in (0..k).rev() {
        let mut s = b[c];
        for j in c + 1..k {
            s -= w[c * k + j] * b[j];
        }
        b[c] = s / w[c * k + c];
    }
    true
}
