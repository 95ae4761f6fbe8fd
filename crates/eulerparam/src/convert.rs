//! Conversions between Euler parameters and other descriptions of orientation.
//!
//! - Rotation matrix → p by Shepperd's method (Shepperd 1978; Nikravesh 1988 §6.3.3): pick the
//!   largest of e0², e1², e2², e3² from the trace and diagonal, so the division is always by a
//!   number ≥ ½ — robust at every angle including 180°.
//! - Axis-angle ↔ p (Nikravesh 1988 eq. 6.14).
//! - Euler angles 3-1-3 (φ, θ, ψ): A = R_z(φ) R_x(θ) R_z(ψ) (Nikravesh 1988 §6.4.1).
//! - Bryant angles 1-2-3 (φ, θ, ψ): A = R_x(φ) R_y(θ) R_z(ψ) (Nikravesh 1988 §6.4.2).
//! - Frames from one or two axes: how joints build the marker frames of their bodies.

use crate::error::EulerParamError;
use crate::params::EulerParams;
use nalgebra::{Matrix3, Vector3};

fn check_finite(what: &'static str, v: &[f64]) -> Result<(), EulerParamError> {
    if v.iter().all(|x| x.is_finite()) {
        Ok(())
    } else {
        Err(EulerParamError::NotFinite {
            what,
            value: v.to_vec(),
        })
    }
}

/// Unit direction of `v`, or an error naming `what` when it is zero or not finite.
pub fn unit(what: &'static str, v: &Vector3<f64>) -> Result<Vector3<f64>, EulerParamError> {
    check_finite(what, v.as_slice())?;
    // Scale first so that tiny and huge vectors normalize without under/overflow.
    let m = v.amax();
    if m == 0.0 || !m.is_normal() {
        return Err(EulerParamError::ZeroAxis { what, norm: v.norm() });
    }
    let s = v / m;
    Ok(s / s.norm())
}

/// p for a rotation by `angle` about `axis` (normalized here): p = [cos(χ/2), u sin(χ/2)].
pub fn p_from_axis_angle(axis: &Vector3<f64>, angle: f64) -> Result<EulerParams, EulerParamError> {
    check_finite("rotation angle", &[angle])?;
    let u = unit("rotation axis", axis)?;
    let (s, c) = (0.5 * angle).sin_cos();
    Ok(EulerParams::new(c, u.x * s, u.y * s, u.z * s))
}

/// Axis and angle χ ∈ [0, 2π] of p (normalized first). The sign of p is kept: −p gives the
/// angle 2π − χ about the negated axis, which is the same rotation. For zero e the axis is x.
pub fn axis_angle_from_p(p: &EulerParams) -> (Vector3<f64>, f64) {
    let n = p.as_vector().norm();
    let (e0, e) = (p.e0() / n, p.e() / n);
    let s = e.norm();
    if s == 0.0 {
        let angle = if e0 >= 0.0 { 0.0 } else { 2.0 * std::f64::consts::PI };
        return (Vector3::x(), angle);
    }
    (e / s, 2.0 * s.atan2(e0))
}

/// p of a proper rotation matrix by Shepperd's method. The result has e0 ≥ 0 (the usual
/// choice; the caller that needs continuity with an earlier p flips the sign itself).
///
/// Fails when `m` is not finite or not a rotation (|mᵀm − I|_F > 1e-6 or det ≤ 0).
pub fn p_from_rotation_matrix(m: &Matrix3<f64>) -> Result<EulerParams, EulerParamError> {
    check_finite("rotation matrix", m.as_slice())?;
    let orth = (m.transpose() * m - Matrix3::identity()).norm();
    let det = m.determinant();
    if orth > 1e-6 || det <= 0.0 {
        return Err(EulerParamError::NotRotation {
            orthogonality_error: orth,
            det,
        });
    }
    let tr = m.trace();
    // 4 e_k² for k = 0..3 (Nikravesh 1988 eq. 6.25–6.28).
    let cand = [
        1.0 + tr,
        1.0 + 2.0 * m[(0, 0)] - tr,
        1.0 + 2.0 * m[(1, 1)] - tr,
        1.0 + 2.0 * m[(2, 2)] - tr,
    ];
    let k = (0..4).fold(0, |best, i| if cand[i] > cand[best] { i } else { best });
    let ek = 0.5 * cand[k].sqrt(); // ≥ 0.5
    let f = 0.25 / ek;
    let (a32, a23) = (m[(2, 1)], m[(1, 2)]);
    let (a13, a31) = (m[(0, 2)], m[(2, 0)]);
    let (a21, a12) = (m[(1, 0)], m[(0, 1)]);
    let mut p = match k {
        0 => [ek, (a32 - a23) * f, (a13 - a31) * f, (a21 - a12) * f],
        1 => [(a32 - a23) * f, ek, (a21 + a12) * f, (a13 + a31) * f],
        2 => [(a13 - a31) * f, (a21 + a12) * f, ek, (a32 + a23) * f],
        _ => [(a21 - a12) * f, (a13 + a31) * f, (a32 + a23) * f, ek],
    };
    if p[0] < 0.0 {
        p.iter_mut().for_each(|x| *x = -*x);
    }
    EulerParams::new(p[0], p[1], p[2], p[3]).normalized()
}

fn about(axis: usize, angle: f64) -> EulerParams {
    let (s, c) = (0.5 * angle).sin_cos();
    let mut v = [c, 0.0, 0.0, 0.0];
    v[axis + 1] = s;
    EulerParams::new(v[0], v[1], v[2], v[3])
}

/// p for 3-1-3 Euler angles (φ, θ, ψ): A = R_z(φ) R_x(θ) R_z(ψ)
/// (Nikravesh 1988 eq. 6.53: e0 = cos(θ/2) cos((φ+ψ)/2), e1 = sin(θ/2) cos((φ−ψ)/2), …).
pub fn p_from_euler_313(phi: f64, theta: f64, psi: f64) -> Result<EulerParams, EulerParamError> {
    check_finite("3-1-3 Euler angles", &[phi, theta, psi])?;
    Ok(about(2, phi).compose(&about(0, theta)).compose(&about(2, psi)))
}

/// 3-1-3 Euler angles (φ, θ, ψ) of p, with θ ∈ [0, π] and φ, ψ ∈ (−π, π]. At the singular
/// orientations θ = 0 and θ = π only φ ± ψ is defined; ψ = 0 is returned.
pub fn euler_313_from_p(p: &EulerParams) -> (f64, f64, f64) {
    let m = p.normalized().map(|q| q.a()).unwrap_or_else(|_| Matrix3::identity());
    let c = m[(2, 2)].clamp(-1.0, 1.0);
    let s = m[(0, 2)].hypot(m[(1, 2)]);
    if s < 1e-12 {
        let theta = if c > 0.0 { 0.0 } else { std::f64::consts::PI };
        return (m[(1, 0)].atan2(m[(0, 0)]), theta, 0.0);
    }
    let theta = s.atan2(c);
    let phi = m[(0, 2)].atan2(-m[(1, 2)]);
    let psi = m[(2, 0)].atan2(m[(2, 1)]);
    (phi, theta, psi)
}

/// p for 1-2-3 Bryant angles (φ, θ, ψ): A = R_x(φ) R_y(θ) R_z(ψ) (Nikravesh 1988 §6.4.2).
pub fn p_from_euler_123(phi: f64, theta: f64, psi: f64) -> Result<EulerParams, EulerParamError> {
    check_finite("1-2-3 Bryant angles", &[phi, theta, psi])?;
    Ok(about(0, phi).compose(&about(1, theta)).compose(&about(2, psi)))
}

/// 1-2-3 Bryant angles (φ, θ, ψ) of p, with θ ∈ [−π/2, π/2]. At gimbal lock (θ = ±π/2) only
/// φ ± ψ is defined; ψ = 0 is returned.
pub fn euler_123_from_p(p: &EulerParams) -> (f64, f64, f64) {
    let m = p.normalized().map(|q| q.a()).unwrap_or_else(|_| Matrix3::identity());
    let s = m[(0, 2)].clamp(-1.0, 1.0);
    let c = m[(0, 0)].hypot(m[(0, 1)]);
    if c < 1e-12 {
        let theta = std::f64::consts::FRAC_PI_2.copysign(s);
        let phi = if s > 0.0 {
            m[(1, 0)].atan2(m[(1, 1)])
        } else {
            (-m[(1, 0)]).atan2(m[(1, 1)])
        };
        return (phi, theta, 0.0);
    }
    let theta = s.atan2(c);
    let phi = (-m[(1, 2)]).atan2(m[(2, 2)]);
    let psi = (-m[(0, 1)]).atan2(m[(0, 0)]);
    (phi, theta, psi)
}

/// A right-handed orthonormal frame [x y z] (columns) whose z column is along `z`.
///
/// x is chosen perpendicular to z by crossing with the coordinate axis along which z has its
/// smallest component, so the choice is well conditioned for every direction (and is a fixed,
/// reproducible function of z).
pub fn frame_from_axis(z: &Vector3<f64>) -> Result<Matrix3<f64>, EulerParamError> {
    let z = unit("frame z axis", z)?;
    let k = z.iamin();
    let mut e = Vector3::zeros();
    e[k] = 1.0;
    let x = e.cross(&z).normalize();
    let y = z.cross(&x);
    Ok(Matrix3::from_columns(&[x, y, z]))
}

/// A right-handed orthonormal frame [x y z] with z along `z` and x along the part of `x_hint`
/// perpendicular to z (Gram-Schmidt). Fails when either is zero or they are parallel
/// (angle below 1e-6 rad).
pub fn frame_from_two_axes(
    z: &Vector3<f64>,
    x_hint: &Vector3<f64>,
) -> Result<Matrix3<f64>, EulerParamError> {
    let z = unit("frame z axis", z)?;
    let xh = unit("frame x axis", x_hint)?;
    let x = xh - z * z.dot(&xh);
    let sin = x.norm();
    if sin < 1e-6 {
        return Err(EulerParamError::ParallelAxes {
            angle_deg: sin.asin().to_degrees(),
        });
    }
    let x = x / sin;
    let y = z.cross(&x);
    Ok(Matrix3::from_columns(&[x, y, z]))
}
