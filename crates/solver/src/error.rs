//! The one error type of the solver layer.
//!
//! Every failure is data: the variants carry the numbers a caller needs to explain the failure
//! (which equations, which unknowns, what residual). Nothing in this crate panics on bad input;
//! shapes are validated when a pattern or solver is built and again, cheaply, on every call.

use core::fmt::Write as _;

/// Where a non-finite value (NaN or ±∞) was found.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum NonFiniteLocation {
    /// The residual Φ of this equation.
    Residual {
        /// Equation (row) index.
        equation: usize,
    },
    /// This Jacobian entry (slot `slot` of the pattern, at `(row, col)`).
    Jacobian {
        /// Slot index in the pattern's value array.
        slot: usize,
        /// Row (equation) of the entry.
        row: usize,
        /// Column (unknown) of the entry.
        col: usize,
    },
    /// Component of a right-hand side handed to a linear solve.
    RightHandSide {
        /// Index in the right-hand side.
        index: usize,
    },
    /// Component of a linear-solve solution or of a Newton step.
    Solution {
        /// Unknown index.
        unknown: usize,
    },
    /// Component of the unknowns after a Newton step was applied.
    Unknown {
        /// Index in the state vector.
        index: usize,
    },
}

impl core::fmt::Display for NonFiniteLocation {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match *self {
            Self::Residual { equation } => write!(f, "residual of equation {equation}"),
            Self::Jacobian { slot, row, col } => {
                write!(f, "Jacobian entry ({row}, {col}) (slot {slot})")
            }
            Self::RightHandSide { index } => write!(f, "right-hand side component {index}"),
            Self::Solution { unknown } => write!(f, "solution component {unknown}"),
            Self::Unknown { index } => write!(f, "unknown {index} after the step"),
        }
    }
}

/// Errors of the solver layer.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum SolverError {
    /// Newton-Raphson reached its iteration cap (or could not reduce the residual).
    #[error(
        "Newton-Raphson did not converge after {iterations} iterations: scaled residual {} \
         (history {}); worst equations {}",
        last_or_nan(.residual_history),
        fmt_history(.residual_history),
        fmt_pairs(.worst_equations)
    )]
    NotConverged {
        /// Iterations performed.
        iterations: usize,
        /// Scaled residual norm (∞-norm) before each iteration and after the last one.
        residual_history: Vec<f64>,
        /// The equations with the largest scaled residuals at the end, `(equation, residual)`,
        /// largest first (at most [`NewtonOptions::report_worst`](crate::NewtonOptions)).
        worst_equations: Vec<(usize, f64)>,
    },
    /// The matrix is (numerically) singular: these equations depend linearly on the others.
    #[error(
        "singular Jacobian: equations {} are linearly dependent on the others \
         (remove them, or use a rank-revealing solver)",
        fmt_list(.dependent_equations)
    )]
    Singular {
        /// Equations (rows) found dependent on the others, in increasing order.
        dependent_equations: Vec<usize>,
    },
    /// A NaN or infinity appeared.
    #[error("non-finite value (NaN or infinity) in the {location}{}", fmt_iteration(.iteration))]
    NonFinite {
        /// Where it appeared.
        location: NonFiniteLocation,
        /// Newton iteration at which it appeared, when inside Newton-Raphson.
        iteration: Option<usize>,
    },
    /// A vector or slice has the wrong length.
    #[error("length mismatch for {what}: expected {expected}, found {found}")]
    DimensionMismatch {
        /// What was being checked (for example `"right-hand side"`).
        what: &'static str,
        /// Expected length.
        expected: usize,
        /// Actual length.
        found: usize,
    },
    /// The solver only handles square matrices.
    #[error("this solver needs a square matrix, got {nrows} × {ncols}")]
    NotSquare {
        /// Rows.
        nrows: usize,
        /// Columns.
        ncols: usize,
    },
    /// A pattern entry lies outside the matrix.
    #[error("pattern entry {index} at ({row}, {col}) lies outside the {nrows} × {ncols} matrix")]
    EntryOutOfBounds {
        /// Position of the entry in the list given to the pattern.
        index: usize,
        /// Row of the entry.
        row: usize,
        /// Column of the entry.
        col: usize,
        /// Rows of the matrix.
        nrows: usize,
        /// Columns of the matrix.
        ncols: usize,
    },
    /// A row index list (for row selection) is invalid.
    #[error("invalid row selection: {reason}")]
    InvalidRowSelection {
        /// What is wrong.
        reason: String,
    },
    /// `factor` or `solve` was called before `analyze` / `factor`.
    #[error("the solver is not ready: call {missing} first")]
    NotReady {
        /// The call that is missing (`"analyze"` or `"factor"`).
        missing: &'static str,
    },
    /// The solver was analyzed for a different pattern.
    #[error("the solver was analyzed for a {expected_rows} × {expected_cols} pattern with {expected_nnz} slots, got {found_rows} × {found_cols} with {found_nnz}")]
    PatternMismatch {
        /// Rows at analysis.
        expected_rows: usize,
        /// Columns at analysis.
        expected_cols: usize,
        /// Slots at analysis.
        expected_nnz: usize,
        /// Rows now.
        found_rows: usize,
        /// Columns now.
        found_cols: usize,
        /// Slots now.
        found_nnz: usize,
    },
    /// An error reported by faer (for example out of memory during symbolic analysis).
    #[error("linear algebra backend: {0}")]
    Backend(String),
}

fn last_or_nan(h: &[f64]) -> String {
    h.last()
        .map_or_else(|| "n/a".to_owned(), |r| format!("{r:.3e}"))
}

fn fmt_history(h: &[f64]) -> String {
    let mut s = String::new();
    let skip = h.len().saturating_sub(8);
    if skip > 0 {
        s.push_str("…, ");
    }
    for (k, r) in h.iter().enumerate().skip(skip) {
        if k > skip {
            s.push_str(", ");
        }
        let _ = write!(s, "{r:.2e}");
    }
    s
}

fn fmt_pairs(p: &[(usize, f64)]) -> String {
    if p.is_empty() {
        return "(none)".to_owned();
    }
    let mut s = String::new();
    for (k, (i, r)) in p.iter().enumerate() {
        if k > 0 {
            s.push_str(", ");
        }
        let _ = write!(s, "#{i} ({r:.3e})");
    }
    s
}

fn fmt_list(p: &[usize]) -> String {
    if p.is_empty() {
        return "(could not be identified)".to_owned();
    }
    let mut s = String::new();
    for (k, i) in p.iter().enumerate() {
        if k > 0 {
            s.push_str(", ");
        }
        let _ = write!(s, "#{i}");
    }
    s
}

fn fmt_iteration(it: &Option<usize>) -> String {
    it.map_or_else(String::new, |k| format!(" at Newton iteration {k}"))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn messages_name_equations_and_residuals() {
        let e = SolverError::NotConverged {
            iterations: 3,
            residual_history: vec![1.0, 0.5, 0.25, 0.125],
            worst_equations: vec![(4, 0.125), (1, 0.01)],
        };
        let s = e.to_string();
        assert!(s.contains("3 iterations"), "{s}");
        assert!(s.contains("#4 (1.250e-1)"), "{s}");
        assert!(s.contains("1.250e-1"), "{s}");
        let e = SolverError::Singular {
            dependent_equations: vec![2, 7],
        };
        assert!(e.to_string().contains("#2, #7"));
        let e = SolverError::NonFinite {
            location: NonFiniteLocation::Residual { equation: 5 },
            iteration: Some(2),
        };
        assert_eq!(
            e.to_string(),
            "non-finite value (NaN or infinity) in the residual of equation 5 at Newton iteration 2"
        );
    }
}
