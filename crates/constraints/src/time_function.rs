//! Time functions f(t) for drivers, each with exact f', f''.
//!
//! | kind | f(t) |
//! |---|---|
//! | constant | c |
//! | polynomial | Σ c_k t^k |
//! | harmonic | b + a sin(ω t + φ) |
//! | ramp | f0 + (f1 − f0)(10τ³ − 15τ⁴ + 6τ⁵), τ = clamp((t − t0)/(t1 − t0), 0, 1): a C² smooth step |
//! | spline | natural cubic spline through knots (t_k, f_k); linear extrapolation with the end slopes |
//! | expression | a formula of t as text ([`Expression`]: grammar, functions, exact derivatives by jets) |
//!
//! The spline's second derivatives M_k at the knots solve the tridiagonal system
//! h_{k−1} M_{k−1} + 2 (h_{k−1} + h_k) M_k + h_k M_{k+1} = 6 (Δ_k − Δ_{k−1}), M_0 = M_n = 0
//! (Δ_k the slope of segment k); it is solved once at construction, so evaluation does not
//! allocate (a binary search finds the segment).

use crate::error::{finite, ConstraintError};
use crate::expression::Expression;

/// A scalar function of time with its first two derivatives.
#[derive(Debug, Clone, PartialEq)]
pub enum TimeFunction {
    /// f = c.
    Constant(f64),
    /// f = Σ c_k t^k (coefficients from c_0).
    Polynomial(Vec<f64>),
    /// f = offset + amplitude · sin(frequency · t + phase), frequency in rad/s.
    Harmonic {
        /// a.
        amplitude: f64,
        /// ω in rad/s.
        frequency: f64,
        /// φ in rad.
        phase: f64,
        /// b.
        offset: f64,
    },
    /// C² quintic step from f0 at t0 to f1 at t1 (t1 > t0), constant outside.
    Ramp {
        /// Start time.
        t0: f64,
        /// End time.
        t1: f64,
        /// Value before t0.
        f0: f64,
        /// Value after t1.
        f1: f64,
    },
    /// Natural cubic spline (build with [`TimeFunction::spline`]).
    Spline(Spline),
    /// A formula of t (build with [`Expression::parse`]); not finite where it is undefined.
    Expression(Expression),
}

/// A natural cubic spline with precomputed knot second derivatives.
#[derive(Debug, Clone, PartialEq)]
pub struct Spline {
    t: Vec<f64>,
    f: Vec<f64>,
    m: Vec<f64>,
}

impl TimeFunction {
    /// Every kind's name, as in model files and oracle data; [`TimeFunction::kind`] (an
    /// exhaustive match) names each variant, and the oracle gate requires reference data for
    /// every name here.
    pub const KINDS: [&'static str; 6] = [
        "constant",
        "polynomial",
        "harmonic",
        "ramp",
        "spline",
        "expression",
    ];

    /// The kind's name (one of [`TimeFunction::KINDS`]).
    pub fn kind(&self) -> &'static str {
        match self {
            TimeFunction::Constant(_) => "constant",
            TimeFunction::Polynomial(_) => "polynomial",
            TimeFunction::Harmonic { .. } => "harmonic",
            TimeFunction::Ramp { .. } => "ramp",
            TimeFunction::Spline(_) => "spline",
            TimeFunction::Expression(_) => "expression",
        }
    }

    /// A natural cubic spline through (t_k, f_k); t strictly increasing, at least 2 knots.
    pub fn spline(t: Vec<f64>, f: Vec<f64>) -> Result<Self, ConstraintError> {
        Ok(TimeFunction::Spline(Spline::new(t, f)?))
    }

    /// An expression function parsed from `text` (see [`crate::expression`]).
    pub fn expression(text: &str) -> Result<Self, ConstraintError> {
        Expression::parse(text)
            .map(TimeFunction::Expression)
            .map_err(|e| {
                let text = crate::expression::quoted(text);
                ConstraintError::TimeFunction(format!("expression \"{text}\" {e}"))
            })
    }

    /// Checks that every parameter is finite and the shape is valid.
    pub fn validate(&self) -> Result<(), ConstraintError> {
        match self {
            TimeFunction::Constant(c) => finite("constant value", &[*c]),
            TimeFunction::Polynomial(c) => {
                if c.is_empty() {
                    return Err(ConstraintError::TimeFunction(
                        "polynomial needs at least one coefficient".into(),
                    ));
                }
                finite("polynomial coefficient", c)
            }
            TimeFunction::Harmonic {
                amplitude,
                frequency,
                phase,
                offset,
            } => finite(
                "harmonic parameter",
                &[*amplitude, *frequency, *phase, *offset],
            ),
            TimeFunction::Ramp { t0, t1, f0, f1 } => {
                finite("ramp parameter", &[*t0, *t1, *f0, *f1])?;
                if t1 <= t0 {
                    return Err(ConstraintError::TimeFunction(format!(
                        "ramp needs t1 > t0, got t0 = {t0}, t1 = {t1}"
                    )));
                }
                Ok(())
            }
            TimeFunction::Spline(_) | TimeFunction::Expression(_) => Ok(()),
        }
    }

    /// (f, f', f'') at t.
    pub fn eval(&self, t: f64) -> (f64, f64, f64) {
        match self {
            TimeFunction::Constant(c) => (*c, 0.0, 0.0),
            TimeFunction::Polynomial(c) => {
                // Horner for f, f', f'' together.
                let (mut f, mut d1, mut d2) = (0.0, 0.0, 0.0);
                for &ck in c.iter().rev() {
                    d2 = d2 * t + 2.0 * d1;
                    d1 = d1 * t + f;
                    f = f * t + ck;
                }
                (f, d1, d2)
            }
            TimeFunction::Harmonic {
                amplitude: a,
                frequency: w,
                phase,
                offset,
            } => {
                let (s, c) = (w * t + phase).sin_cos();
                (offset + a * s, a * w * c, -a * w * w * s)
            }
            TimeFunction::Ramp { t0, t1, f0, f1 } => {
                let h = t1 - t0;
                let tau = ((t - t0) / h).clamp(0.0, 1.0);
                let inside = t > *t0 && t < *t1;
                let df = f1 - f0;
                let s = tau * tau * tau * (10.0 - 15.0 * tau + 6.0 * tau * tau);
                if !inside {
                    return (f0 + df * s, 0.0, 0.0);
                }
                let ds = 30.0 * tau * tau * (1.0 - tau) * (1.0 - tau);
                let dds = 60.0 * tau * (1.0 - tau) * (1.0 - 2.0 * tau);
                (f0 + df * s, df * ds / h, df * dds / (h * h))
            }
            TimeFunction::Spline(s) => s.eval(t),
            TimeFunction::Expression(e) => e.eval(t),
        }
    }
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
