//! Angular velocity maps between ṗ, ω (global) and ω' (body frame), and p̈ from ω̇'.
//!
//! ```text
//! ω  = 2 G ṗ          ω' = 2 L ṗ                       (Nikravesh 1988 ch. 6)
//! ṗ  = ½ Gᵀ ω = ½ Lᵀ ω'                                 (valid for pᵀp = 1, pᵀṗ = 0)
//! ω̇' = 2 L p̈          p̈ = ½ Lᵀ ω̇' − ¼ (ω'ᵀ ω') p       (since L̇ ṗ = 0 and pᵀp̈ = −ṗᵀṗ)
//! ```

use crate::matrices::{g, l};
use nalgebra::{Vector3, Vector4};

/// ω = 2 G(p) ṗ, the angular velocity in the global frame.
#[inline]
pub fn omega_global(p: &Vector4<f64>, p_dot: &Vector4<f64>) -> Vector3<f64> {
    2.0 * g(p) * p_dot
}

/// ω' = 2 L(p) ṗ, the angular velocity in the body frame.
#[inline]
pub fn omega_local(p: &Vector4<f64>, p_dot: &Vector4<f64>) -> Vector3<f64> {
    2.0 * l(p) * p_dot
}

/// ṗ = ½ Lᵀ ω' (assumes pᵀp = 1; the result satisfies pᵀṗ = 0 for any p).
#[inline]
pub fn p_dot_from_local(p: &Vector4<f64>, omega_local: &Vector3<f64>) -> Vector4<f64> {
    0.5 * l(p).transpose() * omega_local
}

/// ṗ = ½ Gᵀ ω (assumes pᵀp = 1; the result satisfies pᵀṗ = 0 for any p).
#[inline]
pub fn p_dot_from_global(p: &Vector4<f64>, omega: &Vector3<f64>) -> Vector4<f64> {
    0.5 * g(p).transpose() * omega
}

/// p̈ = ½ Lᵀ ω̇' − ¼ (ω'ᵀω') p, the parameter acceleration of a unit p with body angular
/// velocity ω' (so ṗ = ½ Lᵀ ω' and ṗᵀṗ = ¼ ω'ᵀω') and acceleration ω̇'. It satisfies
/// 2 L p̈ = ω̇' and pᵀp̈ + ṗᵀṗ = 0, the two conditions that fix p̈ because [Lᵀ p] is orthogonal.
///
/// ```
/// use cardan_eulerparam::{l, p_ddot_from_local, p_dot_from_local};
/// use nalgebra::{Vector3, Vector4};
/// let p = Vector4::new(0.3, -0.5, 0.2, 0.7).normalize();
/// let (w, w_dot) = (Vector3::new(0.0, 0.0, 6.0), Vector3::new(1.0, -2.0, 0.5));
/// let p_dot = p_dot_from_local(&p, &w);
/// let p_ddot = p_ddot_from_local(&p, &w, &w_dot);
/// assert!((2.0 * l(&p) * p_ddot - w_dot).norm() < 1e-14);
/// assert!((p.dot(&p_ddot) + p_dot.dot(&p_dot)).abs() < 1e-14);
/// ```
#[inline]
pub fn p_ddot_from_local(
    p: &Vector4<f64>,
    omega_local: &Vector3<f64>,
    omega_local_dot: &Vector3<f64>,
) -> Vector4<f64> {
    0.5 * l(p).transpose() * omega_local_dot - 0.25 * omega_local.norm_squared() * p
}
