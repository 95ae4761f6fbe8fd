//! The tilde (skew-symmetric) operator: ã b = a × b (the tilde notation of Nikravesh 1988 and
//! Haug 1989).

use nalgebra::{Matrix3, Vector3};

/// ã, the skew-symmetric matrix with ã b = a × b:
///
/// ```text
///     ⎡  0   −a3   a2 ⎤
/// ã = ⎢  a3   0   −a1 ⎥
///     ⎣ −a2   a1   0  ⎦
/// ```
#[inline]
pub fn skew(a: &Vector3<f64>) -> Matrix3<f64> {
    Matrix3::new(0.0, -a.z, a.y, a.z, 0.0, -a.x, -a.y, a.x, 0.0)
}

/// The inverse of [`skew`]: the axial vector of the skew-symmetric part of `m`,
/// ½ [m32 − m23, m13 − m31, m21 − m12].
#[inline]
pub fn unskew(m: &Matrix3<f64>) -> Vector3<f64> {
    0.5 * Vector3::new(
        m[(2, 1)] - m[(1, 2)],
        m[(0, 2)] - m[(2, 0)],
        m[(1, 0)] - m[(0, 1)],
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn skew_is_cross_product_and_unskew_inverts_it() {
        let a = Vector3::new(0.3, -1.2, 2.5);
        let b = Vector3::new(-0.7, 0.1, 0.4);
        assert!((skew(&a) * b - a.cross(&b)).norm() < 1e-15);
        assert!((skew(&a) + skew(&a).transpose()).norm() == 0.0);
        assert_eq!(unskew(&skew(&a)), a);
    }
}
