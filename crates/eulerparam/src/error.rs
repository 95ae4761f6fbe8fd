//! Errors of the Euler-parameter layer. Each variant says what was wrong with which input.

use thiserror::Error;

/// An input that cannot be turned into Euler parameters or a frame.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum EulerParamError {
    /// A value was NaN or infinite.
    #[error("{what} is not finite: {value:?}")]
    NotFinite {
        /// Which input.
        what: &'static str,
        /// The offending components.
        value: Vec<f64>,
    },
    /// The four parameters have (nearly) zero length and cannot be normalized.
    #[error("Euler parameters have zero length (|p| = {norm:e}); they cannot be normalized")]
    ZeroNorm {
        /// |p|.
        norm: f64,
    },
    /// A direction had (nearly) zero length.
    #[error("{what} has zero length (|v| = {norm:e}); a direction is needed")]
    ZeroAxis {
        /// Which axis.
        what: &'static str,
        /// Its length.
        norm: f64,
    },
    /// Two axes that must span a plane are (nearly) parallel.
    #[error("the two axes are parallel (angle {angle_deg:.3e} deg); they do not define a frame")]
    ParallelAxes {
        /// The angle between them in degrees (or from 180°).
        angle_deg: f64,
    },
    /// A 3×3 matrix is not a proper rotation (orthonormal with determinant +1).
    #[error("matrix is not a rotation: |AᵀA − I| = {orthogonality_error:e}, det = {det}")]
    NotRotation {
        /// Frobenius norm of AᵀA − I.
        orthogonality_error: f64,
        /// The determinant.
        det: f64,
    },
}
