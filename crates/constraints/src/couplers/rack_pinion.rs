//! Rack-and-pinion coupler: the slide of the rack along its length and the turn of the pinion,
//! as one equation between the rack body i and the pinion body j (OndselSolver's
//! `RackPinConstraintIJ`, written from its definition).
//!
//! Marker i on the rack: x_i along the rack (the slide direction), z_i parallel to the pinion
//! axis; marker j on the pinion: a point of its axis, z_j the axis. With d = P_j − P_i:
//!
//! ```text
//! Φ = k_s x_iᵀ d + k_θ atan2(y_iᵀ x_j, x_iᵀ x_j) − c        1 row, a length
//! ```
//!
//! (the angle continued over turns; derivatives in [`super::slide_angle`]). When the rack slides
//! and the pinion turns relative to one carrier body (the shared body of the prismatic and the
//! revolute joint), x_iᵀ d is the rack's slide up to sign and a constant, and the angle the
//! pinion's joint angle up to sign and a constant: Φ = 0 is s = −r θ + c for k_θ = ±r (the
//! mechanism builder picks the signs). Reference: OndselSolver `RackPinConstraintIJ`
//! (d_I[0] + r θz(I→J) − c), ASMT notes §3 of the project.

use super::slide_angle::SlideAngle;
use crate::marker::Marker;

/// The rack-and-pinion equation: [`SlideAngle`] with the slide along x_i.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RackPinion {
    /// The equation.
    pub inner: SlideAngle,
}

impl RackPinion {
    /// k_s x_iᵀ d + k_θ θ(i → j) − c with the angle continued from `reference`.
    pub fn new(
        marker_i: Marker,
        marker_j: Marker,
        k_slide: f64,
        k_angle: f64,
        constant: f64,
        reference: f64,
    ) -> Self {
        let inner = SlideAngle {
            axis: marker_i.x(),
            marker_i,
            marker_j,
            k_slide,
            k_angle,
            constant,
            reference,
        };
        Self { inner }
    }
}

forward_constraint_to_field!(RackPinion, inner, "rack_pinion");
