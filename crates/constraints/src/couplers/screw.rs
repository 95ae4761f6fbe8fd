//! Screw coupler: the advance along a common axis and the turn about it, as one equation
//! between the nut body i and the screw body j (OndselSolver's `ScrewConstraintIJ`, written
//! from its definition).
//!
//! Marker i: z_i the screw axis; marker j: z_j the same axis on the other body. With
//! d = P_j − P_i:
//!
//! ```text
//! Φ = k_s z_iᵀ d + k_θ atan2(y_iᵀ x_j, x_iᵀ x_j) − c        1 row, a length
//! ```
//!
//! (the angle continued over turns; derivatives in [`super::slide_angle`]). On a cylindrical
//! joint with its own markers, z_iᵀ d and the angle are exactly the joint's slide s and angle θ,
//! and k_s = 1, k_θ = −pitch/2π give s = (pitch/2π) θ + c: the advance is the pitch per turn.
//! Between a revolute and a prismatic joint on a common axis the mechanism builder picks the
//! signs of k_s and k_θ. Reference: OndselSolver `ScrewConstraintIJ`
//! (2π d_I[2] − pitch θz(I→J) − c), ASMT notes §3 of the project.

use super::slide_angle::SlideAngle;
use crate::marker::Marker;

/// The screw equation: [`SlideAngle`] with the slide along z_i.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Screw {
    /// The equation.
    pub inner: SlideAngle,
}

impl Screw {
    /// k_s z_iᵀ d + k_θ θ(i → j) − c with the angle continued from `reference`.
    pub fn new(
        marker_i: Marker,
        marker_j: Marker,
        k_slide: f64,
        k_angle: f64,
        constant: f64,
        reference: f64,
    ) -> Self {
        let inner = SlideAngle {
            axis: marker_i.z(),
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

forward_constraint_to_field!(Screw, inner, "screw");
