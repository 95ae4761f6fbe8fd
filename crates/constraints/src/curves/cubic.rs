//! The interpolating cubic spline through points P_0 … P_n (body coordinates), parametrized by
//! cumulative chord length: u_0 = 0, u_k = u_{k−1} + |P_k − P_{k−1}| (close to arc length, so
//! the parameter's rate is near the point's speed and Newton's steps in u are well scaled).
//!
//! With h_k = u_{k+1} − u_k, A = (u_{k+1} − u)/h_k, B = (u − u_k)/h_k on segment k:
//!
//! ```text
//! c'(u)    = A P_k + B P_{k+1} + ((A³ − A) M_k + (B³ − B) M_{k+1}) h_k²/6
//! c'_u     = (P_{k+1} − P_k)/h_k − (3A² − 1) h_k M_k/6 + (3B² − 1) h_k M_{k+1}/6
//! c'_uu    = A M_k + B M_{k+1}
//! c'_uuu   = (M_{k+1} − M_k)/h_k
//! ```
//!
//! The knot second derivatives M_k (3-vectors) make c' C² (de Boor, *A Practical Guide to
//! Splines*, ch. IV): h_{k−1} M_{k−1} + 2 (h_{k−1} + h_k) M_k + h_k M_{k+1} = 6 (Δ_k − Δ_{k−1}),
//! Δ_k = (P_{k+1} − P_k)/h_k, with
//! - **open** curves: natural ends M_0 = M_n = 0 (a tridiagonal system), and beyond the ends the
//!   straight continuation along the end tangent (C² there too, since M = 0 at the ends), so the
//!   constraint is smooth everywhere and the analysis, not the evaluation, reports a parameter
//!   that left [u_0, u_n];
//! - **closed** curves (P_n = P_0 given): the same equation at every knot, taken cyclically
//!   (M_n = M_0, h_{−1} = h_{n−1}; a cyclic tridiagonal system, solved by Sherman–Morrison), so c'
//!   is C² across the seam too and periodic in u with period L = u_n.
//!
//! Both systems are solved once at construction; evaluation finds the segment by bisection and
//! does not allocate.

use super::CurveJet;
use crate::error::{finite, ConstraintError};
use nalgebra::Vector3;

/// The relative size (to the points' extent) below which two consecutive points are taken as
/// repeated, and the ends of a closed curve as meeting.
const COINCIDENT: f64 = 1e-9;

/// A C² cubic (or, made by [`CubicCurve::quintic`], C⁴ quintic) spline curve through points.
#[derive(Debug, Clone, PartialEq)]
pub struct CubicCurve {
    points: Vec<Vector3<f64>>,
    knots: Vec<f64>,
    m: Vec<Vector3<f64>>,
    /// The knot fourth derivatives of a quintic spline; empty for a cubic one.
    f: Vec<Vector3<f64>>,
    closed: bool,
}

fn bad(msg: String) -> ConstraintError {
    ConstraintError::Curve(msg)
}

fn fmt_point(p: &Vector3<f64>) -> String {
    format!("[{}, {}, {}]", p.x, p.y, p.z)
}

impl CubicCurve {
    /// The spline through `points` (in order); `closed` makes it periodic, and then the last
    /// point must repeat the first (within 1e-9 of the points' extent).
    ///
    /// Refused: fewer than 2 points (open) or 3 distinct points (closed), a non-finite
    /// coordinate, two consecutive points that coincide (the chord-length parameter would not
    /// advance), a closed curve whose ends do not meet.
    pub fn new(points: Vec<Vector3<f64>>, closed: bool) -> Result<Self, ConstraintError> {
        Self::of_degree(points, closed, 3)
    }

    /// The C⁴ quintic spline through `points` (`super::quintic`: natural ends c''' = c'''' = 0
    /// when open, periodic when `closed`), with the same knots, checks and errors as
    /// [`CubicCurve::new`]; beyond an open curve's ends it continues along its quadratic Taylor
    /// polynomial (C⁴ there, since c''' = c'''' = 0 at the ends).
    pub fn quintic(points: Vec<Vector3<f64>>, closed: bool) -> Result<Self, ConstraintError> {
        Self::of_degree(points, closed, 5)
    }

    /// The interpolating polynomial degree: 3 or 5.
    pub fn degree(&self) -> usize {
        if self.f.is_empty() {
            3
        } else {
            5
        }
    }

    fn of_degree(
        points: Vec<Vector3<f64>>,
        closed: bool,
        degree: usize,
    ) -> Result<Self, ConstraintError> {
        for p in &points {
            finite("curve point", p.as_slice())?;
        }
        let need = if closed { 4 } else { 2 };
        if points.len() < need {
            return Err(bad(format!(
                "a{} spline needs at least {need} points{}, got {}",
                if closed { " closed" } else { "n open" },
                if closed {
                    " (3 distinct ones and the first repeated at the end)"
                } else {
                    ""
                },
                points.len()
            )));
        }
        let extent = extent(&points);
        let mut points = points;
        if closed {
            let n = points.len() - 1;
            let gap = (points[n] - points[0]).norm();
            if gap > COINCIDENT * extent {
                return Err(bad(format!(
                    "a closed curve must end where it starts: its last point {} is {gap:.3e} from its first {}; repeat the first point at the end (or set closed = false)",
                    fmt_point(&points[n]),
                    fmt_point(&points[0])
                )));
            }
            points[n] = points[0];
        }
        let mut knots = Vec::with_capacity(points.len());
        knots.push(0.0);
        for k in 1..points.len() {
            let chord = (points[k] - points[k - 1]).norm();
            if chord <= COINCIDENT * extent {
                return Err(bad(format!(
                    "points[{}] and points[{}] coincide ({}): remove the repeated point",
                    k - 1,
                    k,
                    fmt_point(&points[k])
                )));
            }
            knots.push(knots[k - 1] + chord);
        }
        let (m, f) = match (degree, closed) {
            (5, _) => super::quintic::moments(&points, &knots, closed),
            (_, true) => (periodic_moments(&points, &knots), Vec::new()),
            (_, false) => (natural_moments(&points, &knots), Vec::new()),
        };
        Ok(Self {
            points,
            knots,
            m,
            f,
            closed,
        })
    }

    /// Whether the curve is closed (periodic).
    pub fn is_closed(&self) -> bool {
        self.closed
    }

    /// [u_0, u_n] = [0, total chord length].
    pub fn knot_range(&self) -> (f64, f64) {
        (0.0, self.knots[self.knots.len() - 1])
    }

    /// The knots u_k.
    pub fn knots(&self) -> &[f64] {
        &self.knots
    }

    /// The points P_k.
    pub fn points(&self) -> &[Vector3<f64>] {
        &self.points
    }

    /// c'(u) and its derivatives: on a closed curve at u wrapped into [0, L), on an open one
    /// along the end tangents beyond its ends.
    pub fn jet(&self, u: f64) -> CurveJet {
        let n = self.knots.len() - 1;
        let end = self.knots[n];
        let u = if self.closed {
            u - end * (u / end).floor()
        } else {
            u
        };
        if !self.closed && (u < 0.0 || u > end) {
            let (k, at) = if u < 0.0 { (0, 0.0) } else { (n - 1, end) };
            let j = self.segment(k, at);
            // The end's Taylor polynomial: straight for a cubic (c'' = 0 there), quadratic for
            // a quintic (c''' = 0 there).
            let d = u - at;
            return CurveJet {
                c: j.c + j.c_u * d + j.c_uu * (0.5 * d * d),
                c_u: j.c_u + j.c_uu * d,
                c_uu: j.c_uu,
                c_uuu: Vector3::zeros(),
            };
        }
        // The segment k with u_k ≤ u (the last one for u = u_n, or a wrap rounded up to L).
        let k = self.knots.partition_point(|&x| x <= u).clamp(1, n) - 1;
        self.segment(k, u)
    }

    fn segment(&self, k: usize, u: f64) -> CurveJet {
        let (u0, u1) = (self.knots[k], self.knots[k + 1]);
        let h = u1 - u0;
        if !self.f.is_empty() {
            let [c, c_u, c_uu, c_uuu] = super::quintic::segment(
                h,
                u - u0,
                [self.points[k], self.points[k + 1]],
                [self.m[k], self.m[k + 1]],
                [self.f[k], self.f[k + 1]],
            );
            return CurveJet {
                c,
                c_u,
                c_uu,
                c_uuu,
            };
        }
        let (a, b) = ((u1 - u) / h, (u - u0) / h);
        let (p0, p1) = (self.points[k], self.points[k + 1]);
        let (m0, m1) = (self.m[k], self.m[k + 1]);
        CurveJet {
            c: p0 * a + p1 * b + (m0 * (a * a * a - a) + m1 * (b * b * b - b)) * (h * h / 6.0),
            c_u: (p1 - p0) / h - m0 * ((3.0 * a * a - 1.0) * h / 6.0)
                + m1 * ((3.0 * b * b - 1.0) * h / 6.0),
            c_uu: m0 * a + m1 * b,
            c_uuu: (m1 - m0) / h,
        }
    }
}

/// The largest distance of a point from the first (1 when all coincide).
fn extent(points: &[Vector3<f64>]) -> f64 {
    let e = points
        .iter()
        .map(|p| (p - points[0]).norm())
        .fold(0.0, f64::max);
    if e > 0.0 {
        e
    } else {
        1.0
    }
}

/// Δ_k − Δ_{k−1} times 6: the right-hand side at knot k, with neighbours `prev`, `next`.
fn rhs(points: &[Vector3<f64>], h: &[f64], prev: usize, k: usize, next: usize) -> Vector3<f64> {
    let hp = h[prev];
    let hk = h[k];
    ((points[next] - points[k]) / hk - (points[k] - points[prev]) / hp) * 6.0
}

/// Natural end conditions: M_0 = M_n = 0, the interior tridiagonal system by the Thomas
/// algorithm (diagonally dominant, so no pivoting).
fn natural_moments(points: &[Vector3<f64>], knots: &[f64]) -> Vec<Vector3<f64>> {
    let n = points.len() - 1;
    let h: Vec<f64> = (0..n).map(|k| knots[k + 1] - knots[k]).collect();
    let mut m = vec![Vector3::zeros(); n + 1];
    if n < 2 {
        return m;
    }
    // Interior unknowns 1..n−1: sub h_{k−1}, diag 2(h_{k−1} + h_k), super h_k.
    let mut diag = vec![0.0; n + 1];
    let mut d = vec![Vector3::zeros(); n + 1];
    for k in 1..n {
        diag[k] = 2.0 * (h[k - 1] + h[k]);
        d[k] = rhs(points, &h, k - 1, k, k + 1);
    }
    for k in 2..n {
        let w = h[k - 1] / diag[k - 1];
        diag[k] -= w * h[k - 1];
        d[k] = d[k] - d[k - 1] * w;
    }
    m[n - 1] = d[n - 1] / diag[n - 1];
    for k in (1..n - 1).rev() {
        m[k] = (d[k] - m[k + 1] * h[k]) / diag[k];
    }
    m
}

/// Periodic conditions: the cyclic system over knots 0..n−1 (M_n = M_0), by Sherman–Morrison on
/// the tridiagonal part (Press et al., *Numerical Recipes*, §2.7 "cyclic tridiagonal").
fn periodic_moments(points: &[Vector3<f64>], knots: &[f64]) -> Vec<Vector3<f64>> {
    let n = points.len() - 1;
    let h: Vec<f64> = (0..n).map(|k| knots[k + 1] - knots[k]).collect();
    let prev = |k: usize| (k + n - 1) % n;
    // Row k: sub[k] M_{k−1} + diag[k] M_k + sup[k] M_{k+1}, indices cyclic.
    let sub: Vec<f64> = (0..n).map(|k| h[prev(k)]).collect();
    let diag: Vec<f64> = (0..n).map(|k| 2.0 * (h[prev(k)] + h[k])).collect();
    let sup: Vec<f64> = h.clone();
    let d: Vec<Vector3<f64>> = (0..n)
        .map(|k| rhs(points, &h, prev(k), k, (k + 1) % n))
        .collect();
    // A = T + u vᵀ with u = [γ, 0, …, β], v = [1, 0, …, α/γ]: α = A[0][n−1], β = A[n−1][0].
    let (alpha, beta) = (sub[0], sup[n - 1]);
    let gamma = -diag[0];
    let mut t_diag = diag.clone();
    t_diag[0] -= gamma;
    t_diag[n - 1] -= alpha * beta / gamma;
    let y = thomas(&sub, &t_diag, &sup, &d);
    let mut uvec = vec![Vector3::zeros(); n];
    uvec[0] = Vector3::repeat(gamma);
    uvec[n - 1] = Vector3::repeat(beta);
    let z = thomas(&sub, &t_diag, &sup, &uvec);
    let mut m = vec![Vector3::zeros(); n + 1];
    for c in 0..3 {
        let vy = y[0][c] + alpha / gamma * y[n - 1][c];
        let vz = z[0][c] + alpha / gamma * z[n - 1][c];
        let f = vy / (1.0 + vz);
        for k in 0..n {
            m[k][c] = y[k][c] - f * z[k][c];
        }
    }
    m[n] = m[0];
    m
}

/// Solves the tridiagonal system (sub[k] x_{k−1} + diag[k] x_k + sup[k] x_{k+1} = d_k, the
/// corner entries sub[0], sup[n−1] ignored) for three right-hand sides at once.
fn thomas(sub: &[f64], diag: &[f64], sup: &[f64], d: &[Vector3<f64>]) -> Vec<Vector3<f64>> {
    let n = diag.len();
    let mut c = vec![0.0; n];
    let mut x = d.to_vec();
    let mut b = diag[0];
    c[0] = sup[0] / b;
    x[0] /= b;
    for k in 1..n {
        b = diag[k] - sub[k] * c[k - 1];
        c[k] = if k + 1 < n { sup[k] / b } else { 0.0 };
        x[k] = (x[k] - x[k - 1] * sub[k]) / b;
    }
    for k in (0..n - 1).rev() {
        x[k] = x[k] - x[k + 1] * c[k];
    }
    x
}
