//! A natural cubic spline through knots (t_k, f_k), with exact f' and f''; linear
//! extrapolation with the end slopes. Used by the `spline` time function and by the
//! expressions' `spline(...)` function.
//!
//! The spline's second derivatives M_k at the knots solve the tridiagonal system
//! h_{k−1} M_{k−1} + 2 (h_{k−1} + h_k) M_k + h_k M_{k+1} = 6 (Δ_k − Δ_{k−1}), M_0 = M_n = 0
//! (Δ_k the slope of segment k); it is solved once at construction, so evaluation does not
//! allocate (a binary search finds the segment).

use crate::error::{finite, ConstraintError};

/// A natural cubic spline with precomputed knot second derivatives.
#[derive(Debug, Clone, PartialEq)]
pub struct Spline {
    t: Vec<f64>,
    f: Vec<f64>,
    m: Vec<f64>,
}

impl Spline {
    /// Builds the natural spline; fails on fewer than 2 knots, mismatched lengths, non-finite
    /// values or non-increasing t.
    pub fn new(t: Vec<f64>, f: Vec<f64>) -> Result<Self, ConstraintError> {
        let bad = |m: String| Err(ConstraintError::TimeFunction(m));
        if t.len() != f.len() {
            return bad(format!(
                "spline has {} times but {} values",
                t.len(),
                f.len()
            ));
        }
        if t.len() < 2 {
            return bad("spline needs at least 2 knots".into());
        }
        finite("spline knot time", &t)?;
        finite("spline knot value", &f)?;
        if let Some(k) = (1..t.len()).find(|&k| t[k] <= t[k - 1]) {
            return bad(format!(
                "spline knot times must increase strictly: t[{}] = {} follows t[{}] = {}",
                k,
                t[k],
                k - 1,
                t[k - 1]
            ));
        }
        let n = t.len();
        let mut m = vec![0.0; n];
        if n > 2 {
            // Thomas algorithm on the interior unknowns M_1 .. M_{n-2}.
            let h: Vec<f64> = (0..n - 1).map(|k| t[k + 1] - t[k]).collect();
            let slope: Vec<f64> = (0..n - 1).map(|k| (f[k + 1] - f[k]) / h[k]).collect();
            let mut diag = vec![0.0; n];
            let mut rhs = vec![0.0; n];
            for k in 1..n - 1 {
                diag[k] = 2.0 * (h[k - 1] + h[k]);
                rhs[k] = 6.0 * (slope[k] - slope[k - 1]);
            }
            for k in 2..n - 1 {
                let w = h[k - 1] / diag[k - 1];
                diag[k] -= w * h[k - 1];
                rhs[k] -= w * rhs[k - 1];
            }
            m[n - 2] = rhs[n - 2] / diag[n - 2];
            for k in (1..n - 2).rev() {
                m[k] = (rhs[k] - h[k] * m[k + 1]) / diag[k];
            }
        }
        Ok(Self { t, f, m })
    }

    fn segment(&self, k: usize, t: f64) -> (f64, f64, f64) {
        let h = self.t[k + 1] - self.t[k];
        let a = (self.t[k + 1] - t) / h;
        let b = (t - self.t[k]) / h;
        let (mk, mk1) = (self.m[k], self.m[k + 1]);
        let f = a * self.f[k]
            + b * self.f[k + 1]
            + ((a * a * a - a) * mk + (b * b * b - b) * mk1) * h * h / 6.0;
        let d1 = (self.f[k + 1] - self.f[k]) / h - (3.0 * a * a - 1.0) / 6.0 * h * mk
            + (3.0 * b * b - 1.0) / 6.0 * h * mk1;
        let d2 = a * mk + b * mk1;
        (f, d1, d2)
    }

    /// (f, f', f'') at t.
    pub fn eval(&self, t: f64) -> (f64, f64, f64) {
        let n = self.t.len();
        if t < self.t[0] {
            let (f, d1, _) = self.segment(0, self.t[0]);
            return (f + d1 * (t - self.t[0]), d1, 0.0);
        }
        if t > self.t[n - 1] {
            let (f, d1, _) = self.segment(n - 2, self.t[n - 1]);
            return (f + d1 * (t - self.t[n - 1]), d1, 0.0);
        }
        let k = self.t.partition_point(|&x| x <= t).clamp(1, n - 1) - 1;
        self.segment(k, t)
    }

    /// The knot times.
    pub fn times(&self) -> &[f64] {
        &self.t
    }

    /// The knot values.
    pub fn values(&self) -> &[f64] {
        &self.f
    }
}
