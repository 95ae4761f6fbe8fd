//! The quintic spline's segments and knot derivatives (the degree-5 option of
//! [`super::CubicCurve`], made by [`super::CubicCurve::quintic`]): C⁴ through the points, with
//! the same chord-length knots.
//!
//! On a segment of length h (local t = u − u_k ∈ [0, h]) the fourth derivative is linear
//! between the knots' F_k and F_{k+1}, and the segment is fixed by the end points P, the second
//! derivatives M and the fourth derivatives F (integrating c'''' = F_k (h − t)/h + F_{k+1} t/h
//! four times):
//!
//! ```text
//! a = M_k − F_k h²/6,  b = M_{k+1} − F_{k+1} h²/6
//! p = P_k − F_k h⁴/120 − a h²/6,  q = P_{k+1} − F_{k+1} h⁴/120 − b h²/6
//! c'(t)    = F_k (h−t)⁵/(120h) + F_{k+1} t⁵/(120h) + a (h−t)³/(6h) + b t³/(6h) + p (h−t)/h + q t/h
//! c'_u     = −F_k (h−t)⁴/(24h) + F_{k+1} t⁴/(24h) − a (h−t)²/(2h) + b t²/(2h) + (q − p)/h
//! c'_uu    = F_k (h−t)³/(6h) + F_{k+1} t³/(6h) + a (h−t)/h + b t/h
//! c'_uuu   = −F_k (h−t)²/(2h) + F_{k+1} t²/(2h) + (b − a)/h
//! ```
//!
//! c', c'' and c'''' are continuous by construction; the knot values (M_k, F_k) make c'_u and
//! c'_uuu continuous too: two equations at each interior knot (every knot of a closed curve,
//! cyclically) and, at the ends of an open curve, the natural conditions of the quintic
//! (the spline minimizing ∫ |c'''|²; de Boor, *A Practical Guide to Splines*, ch. XIII):
//! c''' = c'''' = 0, i.e. F = 0 and c'_uuu = 0 there. The system (2 unknowns per knot, three
//! right-hand sides) is assembled from the segment formulas, which are linear in (M, F, P), by
//! evaluating them on unit vectors, and solved once by a dense LU.

use nalgebra::{DMatrix, Vector3};

/// One segment's (c', c'_u, c'_uu, c'_uuu) at local t of a segment of length h with end values
/// `p` = (P_k, P_{k+1}), `m` = (M_k, M_{k+1}), `f` = (F_k, F_{k+1}).
pub(super) fn segment<T>(h: f64, t: f64, p: [T; 2], m: [T; 2], f: [T; 2]) -> [T; 4]
where
    T: Copy
        + std::ops::Add<Output = T>
        + std::ops::Sub<Output = T>
        + std::ops::Mul<f64, Output = T>,
{
    let s = h - t;
    let a = m[0] - f[0] * (h * h / 6.0);
    let b = m[1] - f[1] * (h * h / 6.0);
    let p0 = p[0] - f[0] * (h.powi(4) / 120.0) - a * (h * h / 6.0);
    let q = p[1] - f[1] * (h.powi(4) / 120.0) - b * (h * h / 6.0);
    [
        f[0] * (s.powi(5) / (120.0 * h))
            + f[1] * (t.powi(5) / (120.0 * h))
            + a * (s.powi(3) / (6.0 * h))
            + b * (t.powi(3) / (6.0 * h))
            + p0 * (s / h)
            + q * (t / h),
        f[1] * (t.powi(4) / (24.0 * h)) - f[0] * (s.powi(4) / (24.0 * h)) + b * (t * t / (2.0 * h))
            - a * (s * s / (2.0 * h))
            + (q - p0) * (1.0 / h),
        f[0] * (s.powi(3) / (6.0 * h)) + f[1] * (t.powi(3) / (6.0 * h)) + a * (s / h) + b * (t / h),
        f[1] * (t * t / (2.0 * h)) - f[0] * (s * s / (2.0 * h)) + (b - a) * (1.0 / h),
    ]
}

/// The knot values (M_k, F_k), k = 0..=n, of the quintic spline through `points` with `knots`
/// (module docs); a closed curve's last point repeats its first.
pub(super) fn moments(
    points: &[Vector3<f64>],
    knots: &[f64],
    closed: bool,
) -> (Vec<Vector3<f64>>, Vec<Vector3<f64>>) {
    let n = points.len() - 1;
    // Unknowns: (M_k, F_k) for k = 0..n (open) or 0..n−1 (closed; knot n is knot 0).
    let nk = if closed { n } else { n + 1 };
    let idx = |k: usize| if closed { k % n } else { k };
    let dim = 2 * nk;
    let mut a = DMatrix::<f64>::zeros(dim, dim);
    let mut rhs = DMatrix::<f64>::zeros(dim, 3);
    // sign × (c'_u, c'_uuu) at the start or `end` of segment k, added to rows r (c'_u) and
    // r + 1 (c'_uuu): its coefficient on each of the segment's four unknowns (the formulas on
    // unit inputs) and its P part (zero M and F) moved to the right-hand side.
    let add = |a: &mut DMatrix<f64>,
               rhs: &mut DMatrix<f64>,
               r: usize,
               (k, end): (usize, bool),
               sign: f64| {
        let h = knots[k + 1] - knots[k];
        let t = if end { h } else { 0.0 };
        for (r, d) in [(r, 1usize), (r + 1, 3)] {
            let units = [
                (2 * idx(k), [1.0, 0.0], [0.0, 0.0]),
                (2 * idx(k) + 1, [0.0, 0.0], [1.0, 0.0]),
                (2 * idx(k + 1), [0.0, 1.0], [0.0, 0.0]),
                (2 * idx(k + 1) + 1, [0.0, 0.0], [0.0, 1.0]),
            ];
            for (col, m, f) in units {
                a[(r, col)] += sign * segment(h, t, [0.0; 2], m, f)[d];
            }
            for c in 0..3 {
                let p = [points[k][c], points[k + 1][c]];
                rhs[(r, c)] -= sign * segment(h, t, p, [0.0; 2], [0.0; 2])[d];
            }
        }
    };
    let mut row = 0;
    // Continuity of c'_u and c'_uuu at knot k: the end of segment k − 1 minus the start of k.
    let interior: Vec<usize> = if closed {
        (0..n).collect()
    } else {
        (1..n).collect()
    };
    for k in interior {
        let left = if k == 0 { n - 1 } else { k - 1 };
        add(&mut a, &mut rhs, row, (left, true), 1.0);
        add(&mut a, &mut rhs, row, (k, false), -1.0);
        row += 2;
    }
    if !closed {
        // Natural ends: F = 0 and c'_uuu = 0 at both ends. `add` writes c'_u into the row
        // that F = 0 then overwrites.
        for (k, end, knot) in [(0, false, 0), (n - 1, true, n)] {
            add(&mut a, &mut rhs, row, (k, end), 1.0);
            for c in 0..dim {
                a[(row, c)] = 0.0;
            }
            for c in 0..3 {
                rhs[(row, c)] = 0.0;
            }
            a[(row, 2 * knot + 1)] = 1.0;
            row += 2;
        }
    }
    debug_assert_eq!(row, dim);
    let x = a
        .lu()
        .solve(&rhs)
        .expect("the quintic spline's system is nonsingular for distinct knots");
    let at = |k: usize, off: usize| {
        Vector3::new(
            x[(2 * idx(k) + off, 0)],
            x[(2 * idx(k) + off, 1)],
            x[(2 * idx(k) + off, 2)],
        )
    };
    let m = (0..=n).map(|k| at(k, 0)).collect();
    let f = (0..=n).map(|k| at(k, 1)).collect();
    (m, f)
}
