//! A(p), G(p), L(p), the 4×4 ā, ∂(A a')/∂p and their time derivatives.
//!
//! All functions take the raw parameter vector p = [e0, e1, e2, e3]ᵀ and are defined for any p,
//! normalized or not. For every p: G p = L p = 0, G Gᵀ = L Lᵀ = (pᵀp) I and
//! G Lᵀ = A + (1 − pᵀp) I; so A = G Lᵀ, AᵀA = I and G Gᵀ = L Lᵀ = I need pᵀp = 1. Because G
//! and L are linear in p, their time derivatives are the same functions evaluated at ṗ:
//! Ġ = G(ṗ), L̇ = L(ṗ). [`da_dp`] and [`a_dot`] are the exact derivatives of [`a`] as written,
//! for every p and ṗ (tests/derivatives.rs checks both against central differences).

#![allow(non_snake_case)]

use crate::skew::skew;
use nalgebra::{Matrix3, Matrix3x4, Matrix4, Vector3, Vector4};

/// The rotation matrix, body → global:
/// A(p) = (2 e0² − 1) I + 2 (e eᵀ + e0 ẽ)   (Nikravesh 1988 ch. 6; Haug 1989 ch. 6).
///
/// Written out term by term so that it is exactly this quadratic form for unnormalized p too.
#[inline]
pub fn a(p: &Vector4<f64>) -> Matrix3<f64> {
    let (e0, e1, e2, e3) = (p[0], p[1], p[2], p[3]);
    let d = 2.0 * e0 * e0 - 1.0;
    Matrix3::new(
        d + 2.0 * e1 * e1,
        2.0 * (e1 * e2 - e0 * e3),
        2.0 * (e1 * e3 + e0 * e2),
        2.0 * (e1 * e2 + e0 * e3),
        d + 2.0 * e2 * e2,
        2.0 * (e2 * e3 - e0 * e1),
        2.0 * (e1 * e3 - e0 * e2),
        2.0 * (e2 * e3 + e0 * e1),
        d + 2.0 * e3 * e3,
    )
}

/// G(p) = [−e, ẽ + e0 I]  (Nikravesh's G; Haug's E). ω = 2 G ṗ.
#[inline]
pub fn g(p: &Vector4<f64>) -> Matrix3x4<f64> {
    let (e0, e1, e2, e3) = (p[0], p[1], p[2], p[3]);
    Matrix3x4::new(
        -e1, e0, -e3, e2, //
        -e2, e3, e0, -e1, //
        -e3, -e2, e1, e0,
    )
}

/// L(p) = [−e, −ẽ + e0 I]  (Nikravesh's L; Haug's G). ω' = 2 L ṗ.
#[inline]
pub fn l(p: &Vector4<f64>) -> Matrix3x4<f64> {
    let (e0, e1, e2, e3) = (p[0], p[1], p[2], p[3]);
    Matrix3x4::new(
        -e1, e0, e3, -e2, //
        -e2, -e3, e0, e1, //
        -e3, e2, -e1, e0,
    )
}

/// The 4×4 matrix of a 3-vector, ā = [[0, −aᵀ], [a, −ã]] (Nikravesh 1988 ch. 6), the building
/// block of [`da_dp`]. It is skew-symmetric, and ā q = q ⊗ [0, a] (Hamilton product).
#[inline]
pub fn bar(v: &Vector3<f64>) -> Matrix4<f64> {
    let t = skew(v);
    let mut m = Matrix4::zeros();
    for k in 0..3 {
        m[(0, k + 1)] = -v[k];
        m[(k + 1, 0)] = v[k];
        for c in 0..3 {
            m[(k + 1, c + 1)] = -t[(k, c)];
        }
    }
    m
}

/// ∂(A(p) a')/∂p = 2 (G ā' + a' pᵀ), a 3×4 matrix (Nikravesh 1988 ch. 6; Haug 1989 ch. 9).
///
/// Exact for every p, normalized or not (it is the derivative of [`a`] as written).
///
/// ```
/// use cardan_eulerparam::{a, da_dp};
/// use nalgebra::{Vector3, Vector4};
/// let p = Vector4::new(0.9, -0.3, 0.5, 0.2); // need not be normalized
/// let s = Vector3::new(0.4, -1.3, 2.2);
/// let (dp, h) = (Vector4::new(0.1, 0.7, -0.2, 0.4), 1e-4);
/// // A is quadratic in p: a central difference is exact up to round-off.
/// let fd = (a(&(p + dp * h)) * s - a(&(p - dp * h)) * s) / (2.0 * h);
/// assert!((da_dp(&p, &s) * dp - fd).norm() < 1e-10);
/// ```
///
/// The seed slides call it C_k when a' is a direction vector s'_k and B_k when a' is a point
/// vector s'^P_k. It is linear in p, so (∂(A a')/∂p)(ṗ) ṗ is the velocity-quadratic part of the
/// second time derivative of A a' (the 7-coordinate γ# terms are built from it).
#[inline]
pub fn da_dp(p: &Vector4<f64>, a_local: &Vector3<f64>) -> Matrix3x4<f64> {
    2.0 * (g(p) * bar(a_local) + a_local * p.transpose())
}

/// ∂(A a')/∂π' = −A ã', the derivative of a rotated body-fixed vector with respect to a virtual
/// rotation π' in the body frame, p → p ⊗ [1, π'/2] (6-coordinate form; Nikravesh 1988 ch. 6,
/// Haug 1989 ch. 9). For pᵀp = 1 it equals ½ [`da_dp`]`(p, a') Lᵀ`, i.e. Φ_π' = ½ Φ_p Lᵀ.
#[inline]
pub fn da_dpi_local(p: &Vector4<f64>, a_local: &Vector3<f64>) -> Matrix3<f64> {
    -a(p) * skew(a_local)
}

/// Ȧ, the time derivative of [`a`] along ṗ: Ȧ = Ġ Lᵀ + G L̇ᵀ + 2 (pᵀṗ) I with Ġ = G(ṗ),
/// L̇ = L(ṗ), so that Ȧ a' = (∂(A a')/∂p) ṗ = [`da_dp`]`(p, a') ṗ` for every p and ṗ.
///
/// On the constraint manifold (pᵀp = 1, pᵀṗ = 0) the last term vanishes and this is the book's
/// Ȧ = Ġ Lᵀ + G L̇ᵀ = 2 G L̇ᵀ = ω̃ A = A ω̃' (Nikravesh 1988 ch. 6). Off it (a Newton iterate, or
/// the 7-coordinate γ# = −d²/dτ² Φ(q + q̇τ) with an arbitrary q̇) the term 2 (pᵀṗ) I is the
/// derivative of the (2 e0² − 1) I part that G Lᵀ = A + (1 − pᵀp) I does not carry.
///
/// ```
/// use cardan_eulerparam::{a, a_dot, da_dp, omega_global, skew};
/// use nalgebra::{Vector3, Vector4};
/// let p = Vector4::new(0.3, -0.5, 0.2, 0.7).normalize();
/// let v = Vector4::new(0.4, 1.0, -0.6, 0.1);
/// let p_dot = v - p * p.dot(&v); // tangent: pᵀṗ = 0
/// let s = Vector3::new(1.0, 2.0, 3.0);
/// assert!((a_dot(&p, &p_dot) * s - da_dp(&p, &s) * p_dot).norm() < 1e-14);
/// let w = omega_global(&p, &p_dot);
/// assert!((a_dot(&p, &p_dot) - skew(&w) * a(&p)).norm() < 1e-14);
/// ```
#[inline]
pub fn a_dot(p: &Vector4<f64>, p_dot: &Vector4<f64>) -> Matrix3<f64> {
    g(p_dot) * l(p).transpose()
        + g(p) * l(p_dot).transpose()
        + Matrix3::identity() * (2.0 * p.dot(p_dot))
}

/// Ġ = G(ṗ) (G is linear in p). Ġ ṗ = 0.
#[inline]
pub fn g_dot(p_dot: &Vector4<f64>) -> Matrix3x4<f64> {
    g(p_dot)
}

/// L̇ = L(ṗ) (L is linear in p). L̇ ṗ = 0.
#[inline]
pub fn l_dot(p_dot: &Vector4<f64>) -> Matrix3x4<f64> {
    l(p_dot)
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    #[test]
    fn identity_parameters_give_identity_matrices() {
        let p = Vector4::new(1.0, 0.0, 0.0, 0.0);
        assert_eq!(a(&p), Matrix3::identity());
        assert_relative_eq!(g(&p) * l(&p).transpose(), Matrix3::identity());
    }

    #[test]
    fn a_of_half_turn_about_z() {
        // χ = π about z: e0 = 0, e3 = 1.
        let p = Vector4::new(0.0, 0.0, 0.0, 1.0);
        assert_relative_eq!(
            a(&p),
            Matrix3::from_diagonal(&Vector3::new(-1.0, -1.0, 1.0))
        );
    }
}
