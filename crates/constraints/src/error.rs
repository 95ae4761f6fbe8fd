//! Errors raised when a joint, driver or time function is *built* from bad data.
//! Evaluation itself never fails: everything is validated here, once.

use thiserror::Error;

/// A definition that cannot make a well-posed constraint.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum ConstraintError {
    /// A number is NaN or infinite.
    #[error("{what} is not finite ({value})")]
    NotFinite {
        /// Which input.
        what: String,
        /// The offending value.
        value: f64,
    },
    /// A direction has zero length.
    #[error("{what} has zero length; a direction is needed")]
    ZeroAxis {
        /// Which input.
        what: String,
    },
    /// Two axes that must be distinct are parallel.
    #[error("{what}: the axes are parallel and do not define a frame")]
    ParallelAxes {
        /// Which input.
        what: String,
    },
    /// A marker frame is not a right-handed orthonormal triad.
    #[error("{what} is not a right-handed orthonormal frame (|FᵀF − I| = {error:e}, det = {det})")]
    NotOrthonormal {
        /// Which marker.
        what: String,
        /// ‖FᵀF − I‖.
        error: f64,
        /// det F.
        det: f64,
    },
    /// A length that must be positive is not.
    #[error("{what} must be positive, got {value}")]
    NotPositive {
        /// Which input.
        what: String,
        /// The value.
        value: f64,
    },
    /// A time function is malformed.
    #[error("time function: {0}")]
    TimeFunction(String),
    /// Any other invalid definition, explained.
    #[error("{0}")]
    Invalid(String),
    /// A curve that cannot be built from its data (too few or repeated points, a closed curve
    /// whose ends do not meet), explained.
    #[error("curve: {0}")]
    Curve(String),
    /// A coordinate index out of 0..3.
    #[error("coordinate axis must be 0 (x), 1 (y) or 2 (z), got {0}")]
    BadAxis(usize),
}

pub(crate) fn finite(what: &str, v: &[f64]) -> Result<(), ConstraintError> {
    match v.iter().find(|x| !x.is_finite()) {
        None => Ok(()),
        Some(&value) => Err(ConstraintError::NotFinite {
            what: what.to_string(),
            value,
        }),
    }
}
