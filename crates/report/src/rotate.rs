//! The point r + A(p) s' of a body at a pose, for the page's data (named points, joint axes,
//! mode shapes): A(p) = (2 e0² − 1) I + 2 (e eᵀ + e0 ẽ) (`shared/notation.md`), written out
//! because the crate knows nothing of mechanics and does not depend on `cardan-eulerparam`.

/// r + A(p) s', A(p) = (2e0² − 1) I + 2(e eᵀ + e0 ẽ) with p normalized. `#[inline]`: it was
/// inlined into the page writer's loops when it lived in `html.rs`, and still should be.
#[inline]
pub(crate) fn rotate(p: &[f64; 4], s: [f64; 3], r: &[f64; 3]) -> [f64; 3] {
    let n = p.iter().map(|x| x * x).sum::<f64>().sqrt();
    let [e0, e1, e2, e3] = p.map(|x| x / n);
    let e = [e1, e2, e3];
    let es = e[0] * s[0] + e[1] * s[1] + e[2] * s[2];
    let cross = [
        e[1] * s[2] - e[2] * s[1],
        e[2] * s[0] - e[0] * s[2],
        e[0] * s[1] - e[1] * s[0],
    ];
    [0, 1, 2].map(|c| r[c] + (2.0 * e0 * e0 - 1.0) * s[c] + 2.0 * (e[c] * es + e0 * cross[c]))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rotate_is_a_of_p() {
        // A quarter turn about z takes x to y.
        let h = std::f64::consts::FRAC_1_SQRT_2;
        let v = rotate(&[h, 0.0, 0.0, h], [1.0, 0.0, 0.0], &[0.0, 0.0, 1.0]);
        assert!((v[0]).abs() < 1e-15 && (v[1] - 1.0).abs() < 1e-15 && (v[2] - 1.0).abs() < 1e-15);
    }
}
