//! [`EulerParams`]: the four Euler parameters used as *coordinates*.

use crate::error::EulerParamError;
use crate::matrices;
use nalgebra::{Matrix3, Matrix3x4, Vector3, Vector4};

/// Default tolerance of [`EulerParams::is_normalized`] on |pᵀp − 1|.
pub const NORM_TOLERANCE: f64 = 1e-10;

/// Euler parameters p = [e0, e1, e2, e3]ᵀ, scalar first, used as generalized coordinates.
///
/// Unlike a unit quaternion type, p and −p are *different values* here (they are different
/// coordinates of the same rotation), equality is component-wise, and the type does not force
/// normalization: a Newton iterate may be slightly off the unit sphere and the normalization
/// constraint pᵀp − 1 = 0 is part of the equations. [`EulerParams::normalized`] and
/// [`EulerParams::norm_error`] are there when a unit vector is wanted or must be checked.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct EulerParams(Vector4<f64>);

impl Default for EulerParams {
    fn default() -> Self {
        Self::identity()
    }
}

impl EulerParams {
    /// p = [e0, e1, e2, e3] as given (not normalized).
    pub const fn new(e0: f64, e1: f64, e2: f64, e3: f64) -> Self {
        Self(Vector4::new(e0, e1, e2, e3))
    }

    /// The identity rotation, p = [1, 0, 0, 0].
    pub const fn identity() -> Self {
        Self::new(1.0, 0.0, 0.0, 0.0)
    }

    /// Wraps a raw 4-vector (not normalized).
    pub const fn from_vector(p: Vector4<f64>) -> Self {
        Self(p)
    }

    /// Normalizes four given parameters; fails on non-finite or zero-length input.
    pub fn try_new_normalized(e0: f64, e1: f64, e2: f64, e3: f64) -> Result<Self, EulerParamError> {
        Self::new(e0, e1, e2, e3).normalized()
    }

    /// The raw vector [e0, e1, e2, e3].
    pub const fn as_vector(&self) -> &Vector4<f64> {
        &self.0
    }

    /// The scalar part e0.
    pub fn e0(&self) -> f64 {
        self.0[0]
    }

    /// The vector part e = [e1, e2, e3].
    pub fn e(&self) -> Vector3<f64> {
        Vector3::new(self.0[1], self.0[2], self.0[3])
    }

    /// pᵀp.
    pub fn norm_squared(&self) -> f64 {
        self.0.norm_squared()
    }

    /// |pᵀp − 1|, the violation of the normalization constraint.
    pub fn norm_error(&self) -> f64 {
        (self.0.norm_squared() - 1.0).abs()
    }

    /// Whether |pᵀp − 1| ≤ `tol`.
    pub fn is_normalized(&self, tol: f64) -> bool {
        self.norm_error() <= tol
    }

    /// p / |p|. Keeps the sign of p (never maps p to −p).
    pub fn normalized(&self) -> Result<Self, EulerParamError> {
        if !self.0.iter().all(|x| x.is_finite()) {
            return Err(EulerParamError::NotFinite {
                what: "Euler parameters",
                value: self.0.iter().copied().collect(),
            });
        }
        let n = self.0.norm();
        if n < 1e-150 {
            return Err(EulerParamError::ZeroNorm { norm: n });
        }
        Ok(Self(self.0 / n))
    }

    /// The rotation matrix A(p), body → global.
    pub fn a(&self) -> Matrix3<f64> {
        matrices::a(&self.0)
    }

    /// G(p).
    pub fn g(&self) -> Matrix3x4<f64> {
        matrices::g(&self.0)
    }

    /// L(p).
    pub fn l(&self) -> Matrix3x4<f64> {
        matrices::l(&self.0)
    }

    /// The composition p ⊗ q (Hamilton product, scalar first), with A(p ⊗ q) = A(p) A(q):
    /// first rotate by q in the frame of p. Used to apply a body-frame rotation to a body.
    pub fn compose(&self, q: &EulerParams) -> EulerParams {
        let (p0, pv) = (self.e0(), self.e());
        let (q0, qv) = (q.e0(), q.e());
        let s = p0 * q0 - pv.dot(&qv);
        let v = p0 * qv + q0 * pv + pv.cross(&qv);
        EulerParams::new(s, v.x, v.y, v.z)
    }

    /// p ⊗ q rescaled to unit length: the composition of two unit parameters, with the roundoff
    /// drift of its norm removed (both must be unit, or nearly).
    pub fn compose_unit(&self, q: &EulerParams) -> EulerParams {
        let v = self.compose(q).0;
        let n = v.norm();
        EulerParams::new(v[0] / n, v[1] / n, v[2] / n, v[3] / n)
    }

    /// exp(θ/2) = [cos(|θ|/2), sin(|θ|/2) θ/|θ|]: the parameters of a rotation by |θ| about the
    /// rotation vector θ (identity for θ = 0). Unit by construction. Applied in a body frame,
    /// p ⊗ exp(θ'/2) gives A(p) exp(θ̃').
    pub fn from_rotation_vector(theta: &Vector3<f64>) -> EulerParams {
        let a = theta.norm();
        if a > 0.0 {
            let (s, c) = (0.5 * a).sin_cos();
            let u = theta * (s / a);
            EulerParams::new(c, u.x, u.y, u.z)
        } else {
            EulerParams::identity()
        }
    }

    /// The conjugate [e0, −e], which for unit p is the inverse rotation: A(p*) = A(p)ᵀ.
    pub fn conjugate(&self) -> EulerParams {
        EulerParams::new(self.0[0], -self.0[1], -self.0[2], -self.0[3])
    }
}

impl From<EulerParams> for Vector4<f64> {
    fn from(p: EulerParams) -> Self {
        p.0
    }
}

impl std::ops::Neg for EulerParams {
    type Output = EulerParams;
    /// −p: the same rotation, the other coordinates.
    fn neg(self) -> EulerParams {
        EulerParams(-self.0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_rotation_vector_gives_the_axis_angle_parameters() {
        let th = Vector3::new(0.3, -1.2, 0.5);
        let p = EulerParams::from_rotation_vector(&th);
        let q = EulerParams::from_axis_angle(&th, th.norm()).unwrap();
        assert!((p.as_vector() - q.as_vector()).norm() < 1e-15);
        assert_eq!(
            EulerParams::from_rotation_vector(&Vector3::zeros()),
            EulerParams::identity()
        );
        // Composed with a slightly unnormalized p, the result is unit again.
        let r = EulerParams::new(0.6, 0.8, 0.0, 1e-9).compose_unit(&p);
        assert!(r.norm_error() < 1e-15);
        assert!((r.a() - EulerParams::new(0.6, 0.8, 0.0, 0.0).a() * p.a()).norm() < 1e-8);
    }

    #[test]
    fn p_and_minus_p_are_different_values_with_the_same_rotation() {
        let p = EulerParams::try_new_normalized(0.3, -0.5, 0.2, 0.7).unwrap();
        let m = -p;
        assert_ne!(p, m);
        assert!((p.a() - m.a()).norm() < 1e-15);
        assert_eq!(
            m.normalized().unwrap(),
            m,
            "normalization must keep the sign"
        );
    }

    #[test]
    fn normalization_errors_are_typed() {
        assert!(matches!(
            EulerParams::new(0.0, 0.0, 0.0, 0.0).normalized(),
            Err(EulerParamError::ZeroNorm { .. })
        ));
        assert!(matches!(
            EulerParams::new(f64::NAN, 0.0, 0.0, 1.0).normalized(),
            Err(EulerParamError::NotFinite { .. })
        ));
    }

    #[test]
    fn compose_multiplies_rotation_matrices() {
        let p = EulerParams::try_new_normalized(0.3, -0.5, 0.2, 0.7).unwrap();
        let q = EulerParams::try_new_normalized(-0.1, 0.4, 0.9, -0.2).unwrap();
        assert!((p.compose(&q).a() - p.a() * q.a()).norm() < 1e-14);
        assert!(
            (p.compose(&p.conjugate()).as_vector() - EulerParams::identity().as_vector()).norm()
                < 1e-15
        );
    }
}
