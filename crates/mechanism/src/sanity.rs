//! Physical sanity of input data, in one place for the builder and for any reader of model
//! files (the `cardan` command places the same refusals at a line of the file).
//!
//! ## Inertia tensors
//! A tensor J about the centre of mass is a rigid body's when it is symmetric, positive
//! definite, and its principal moments I₁ ≤ I₂ ≤ I₃ satisfy the triangle inequality
//! I₁ + I₂ ≥ I₃. (With the second moments of mass Sₖ = ∫ xₖ² dm along the principal axes,
//! I₃ = S₁ + S₂ and I₁ + I₂ − I₃ = 2 S₃ ≥ 0.) A thin disk or plate has I₁ + I₂ = I₃ exactly;
//! values rounded to four digits may miss it by a few 1e-4 relative, so the test allows
//! [`INERTIA_TRIANGLE_TOLERANCE`] × I₃.

use crate::error::ModelError;
use nalgebra::Matrix3;

/// Relative slack of the triangle inequality: I₁ + I₂ ≥ (1 − 1e-3) I₃ is accepted.
pub const INERTIA_TRIANGLE_TOLERANCE: f64 = 1e-3;

/// Relative asymmetry max |J − Jᵀ| / max |J| accepted (roundoff of a rotated tensor).
pub const INERTIA_ASYMMETRY_TOLERANCE: f64 = 1e-9;

/// Checks that `inertia` (kg m², about the centre of mass) can be a rigid body's: finite,
/// symmetric, positive definite, principal moments satisfying the triangle inequality.
///
/// # Errors
/// [`ModelError::NotFinite`], [`ModelError::InertiaNotSymmetric`],
/// [`ModelError::InertiaNotPositiveDefinite`] or [`ModelError::InertiaTriangle`], naming `body`.
pub fn check_inertia(body: &str, inertia: &Matrix3<f64>) -> Result<(), ModelError> {
    if let Some(&v) = inertia.iter().find(|v| !v.is_finite()) {
        return Err(ModelError::NotFinite {
            element: format!("body \"{body}\""),
            what: "inertia".into(),
            value: v,
        });
    }
    let scale = inertia.amax();
    let asym = (inertia - inertia.transpose()).amax();
    if scale > 0.0 && asym > INERTIA_ASYMMETRY_TOLERANCE * scale {
        return Err(ModelError::InertiaNotSymmetric {
            body: body.into(),
            asymmetry: asym / scale,
        });
    }
    let moments = principal_moments(inertia);
    let sym = 0.5 * (inertia + inertia.transpose());
    if scale == 0.0 || sym.cholesky().is_none() {
        return Err(ModelError::InertiaNotPositiveDefinite {
            body: body.into(),
            min_eigenvalue: moments[0],
        });
    }
    let [i1, i2, i3] = moments;
    if i1 + i2 < (1.0 - INERTIA_TRIANGLE_TOLERANCE) * i3 {
        return Err(ModelError::InertiaTriangle {
            body: body.into(),
            moments,
        });
    }
    Ok(())
}

/// The eigenvalues of the symmetric part of `j`, ascending.
pub fn principal_moments(j: &Matrix3<f64>) -> [f64; 3] {
    let sym = 0.5 * (j + j.transpose());
    let e = sym.symmetric_eigenvalues();
    let mut m = [e[0], e[1], e[2]];
    m.sort_by(f64::total_cmp);
    m
}
