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
//! The spline is a type of its own ([`Spline`], `spline.rs`), shared with the expressions'
//! `spline(...)` function.

use crate::error::{finite, ConstraintError};
use crate::expression::Expression;
pub use crate::spline::Spline;

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
