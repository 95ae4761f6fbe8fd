//! Conversions between Euler parameters and other descriptions of orientation.
//!
//! - Rotation matrix → p by Shepperd's method (Shepperd 1978; Nikravesh 1988 ch. 6): pick the
//!   largest of e0², e1², e2², e3² from the trace and diagonal, so the division is always by a
//!   number ≥ ½ — robust at every angle including 180°.
//! - Axis-angle ↔ p (Nikravesh 1988 ch. 6).
//! - Euler angles 3-1-3 (φ, θ, ψ): A = R_z(φ) R_x(θ) R_z(ψ) (Nikravesh 1988 ch. 6).
//! - Bryant angles 1-2-3 (φ, θ, ψ): A = R_x(φ) R_y(θ) R_z(ψ) (Nikravesh 1988 ch. 6).
//!   Angles are extracted from p, not from A, and reproduce A to round-off at every orientation.
//! - Frames from one or two axes: how joints build the marker frames of their bodies.

use crate::error::EulerParamError;
use crate::params::EulerParams;
use nalgebra::{Matrix3, Vector3};

/// The conversions as constructors and accessors of [`EulerParams`]. They live here, beside
/// the functions they call, so that the coordinate type (`params.rs`) does not depend on the
/// conversions.
impl EulerParams {
    /// The parameters of a rotation by `angle` (rad) about `axis` (any nonzero length):
    /// e0 = cos(χ/2), e = u sin(χ/2) (Nikravesh 1988 ch. 6).
    pub fn from_axis_angle(axis: &Vector3<f64>, angle: f64) -> Result<Self, EulerParamError> {
        p_from_axis_angle(axis, angle)
    }

    /// The parameters of a proper rotation matrix (Shepperd's method; exact at 180°).
    pub fn from_rotation_matrix(m: &Matrix3<f64>) -> Result<Self, EulerParamError> {
        p_from_rotation_matrix(m)
    }

    /// Unit axis and angle χ ∈ [0, 2π] with p = [cos(χ/2), u sin(χ/2)] (keeps p's sign:
    /// e0 < 0 gives χ > π). The identity gives the axis x and χ = 0.
    pub fn to_axis_angle(&self) -> (Vector3<f64>, f64) {
        axis_angle_from_p(self)
    }
}

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
        return Err(EulerParamError::ZeroAxis {
            what,
            norm: v.norm(),
        });
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
        let angle = if e0 >= 0.0 {
            0.0
        } else {
            2.0 * std::f64::consts::PI
        };
        return (Vector3::x(), angle);
    }
    (e / s, 2.0 * s.atan2(e0))
}

/// p of a proper rotation matrix by Shepperd's method. The result has e0 ≥ 0 (the usual
/// choice; the caller that needs continuity with an earlier p flips the sign itself).
///
/// Fails when `m` is not finite or not a rotation (|mᵀm − I|_F > 1e-6 or det ≤ 0).
///
/// ```
/// use cardan_eulerparam::{p_from_rotation_matrix, EulerParamError};
/// use nalgebra::{Matrix3, Vector3};
/// // A half turn about u is 2 u uᵀ − I; its e0 is 0 and e = ±u.
/// let u = Vector3::new(0.0, 1.0, 1.0).normalize();
/// let p = p_from_rotation_matrix(&(2.0 * u * u.transpose() - Matrix3::identity())).unwrap();
/// assert!(p.e0().abs() < 1e-15 && (p.e() - u).norm().min((p.e() + u).norm()) < 1e-15);
/// // A reflection is not a rotation.
/// let r = Matrix3::from_diagonal(&Vector3::new(1.0, 1.0, -1.0));
/// assert!(matches!(p_from_rotation_matrix(&r), Err(EulerParamError::NotRotation { .. })));
/// ```
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
    // 4 e_k² for k = 0..3, from the trace and the diagonal of A.
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
/// (Nikravesh 1988 ch. 6): e0 = cos(θ/2) cos((φ+ψ)/2), e1 = sin(θ/2) cos((φ−ψ)/2),
/// e2 = sin(θ/2) sin((φ−ψ)/2), e3 = cos(θ/2) sin((φ+ψ)/2).
pub fn p_from_euler_313(phi: f64, theta: f64, psi: f64) -> Result<EulerParams, EulerParamError> {
    check_finite("3-1-3 Euler angles", &[phi, theta, psi])?;
    Ok(about(2, phi)
        .compose(&about(0, theta))
        .compose(&about(2, psi)))
}

/// 3-1-3 Euler angles (φ, θ, ψ) of p, with θ ∈ [0, π] and φ, ψ ∈ (−π, π]. At the singular
/// orientations θ = 0 and θ = π only φ + ψ (resp. φ − ψ) is defined; there ψ = 0 is returned.
///
/// Computed from the half-angle form of p (Nikravesh 1988 ch. 6), not from A:
/// e0 = cos(θ/2) cos σ, e3 = cos(θ/2) sin σ, e1 = sin(θ/2) cos δ, e2 = sin(θ/2) sin δ with
/// σ = (φ + ψ)/2, δ = (φ − ψ)/2. Every angle is an `atan2` of two parameters, so the angles
/// reproduce A(p) to round-off at every orientation, including arbitrarily close to the
/// singular ones (an extraction from the entries of A loses accuracy there). p and −p give the
/// same angles. p need not be normalized; a p that cannot be normalized (zero or not finite)
/// gives (0, 0, 0).
pub fn euler_313_from_p(p: &EulerParams) -> (f64, f64, f64) {
    let Ok(q) = p.normalized() else {
        return (0.0, 0.0, 0.0);
    };
    let v = q.as_vector();
    // R_z R_x R_z: outer axis z (e3), middle axis x (e1), third axis y (e2).
    proper_euler_from_half_angles(v[0], v[3], v[1], v[2])
}

/// Proper Euler angles (φ, θ, ψ) of R_a(φ) R_b(θ) R_a(ψ) from the parameters of that rotation
/// listed as r0 (scalar), ra (outer axis a), rb (middle axis b), rc (the third axis c, with
/// (a, b, c) a cyclic permutation of (x, y, z)):
/// r0 = cos(θ/2) cos σ, ra = cos(θ/2) sin σ, rb = sin(θ/2) cos δ, rc = sin(θ/2) sin δ,
/// σ = (φ + ψ)/2, δ = (φ − ψ)/2. θ ∈ [0, π], φ, ψ ∈ (−π, π]; ψ = 0 at θ = 0 and θ = π (up
/// to round-off: when sin(θ/2) or cos(θ/2) is below 4 ε |r|, which moves A by less than 1e-15).
fn proper_euler_from_half_angles(r0: f64, ra: f64, rb: f64, rc: f64) -> (f64, f64, f64) {
    let c = r0.hypot(ra); // |cos(θ/2)|
    let s = rb.hypot(rc); // |sin(θ/2)|
    let tiny = 4.0 * f64::EPSILON * c.hypot(s);
    if s <= tiny {
        // θ = 0: A = R_a(φ + ψ).
        return (wrap_angle(2.0 * ra.atan2(r0)), 0.0, 0.0);
    }
    if c <= tiny {
        // θ = π: A = R_a(φ − ψ) R_b(π).
        return (wrap_angle(2.0 * rc.atan2(rb)), std::f64::consts::PI, 0.0);
    }
    let sigma = ra.atan2(r0);
    let delta = rc.atan2(rb);
    (
        wrap_angle(sigma + delta),
        2.0 * s.atan2(c),
        wrap_angle(sigma - delta),
    )
}

/// Maps an angle in [−2π, 2π] to (−π, π].
fn wrap_angle(x: f64) -> f64 {
    use std::f64::consts::PI;
    if x > PI {
        x - 2.0 * PI
    } else if x <= -PI {
        x + 2.0 * PI
    } else {
        x
    }
}

/// p for 1-2-3 Bryant angles (φ, θ, ψ): A = R_x(φ) R_y(θ) R_z(ψ) (Nikravesh 1988 ch. 6).
pub fn p_from_euler_123(phi: f64, theta: f64, psi: f64) -> Result<EulerParams, EulerParamError> {
    check_finite("1-2-3 Bryant angles", &[phi, theta, psi])?;
    Ok(about(0, phi)
        .compose(&about(1, theta))
        .compose(&about(2, psi)))
}

/// 1-2-3 Bryant angles (φ, θ, ψ) of p, with θ ∈ [−π/2, π/2] and φ, ψ ∈ (−π, π]. At gimbal
/// lock (θ = ±π/2) only φ ± ψ is defined; there ψ = 0 is returned.
///
/// Computed from p, not from A, so that the angles reproduce A(p) to round-off at every
/// orientation including arbitrarily close to gimbal lock (an extraction from the entries of A
/// loses accuracy there: cos θ is a difference of O(1) entries). Because
/// R_y(θ) R_z(ψ) = R_y(θ + π/2) R_x(−ψ) R_y(−π/2), the rotation A(p) R_y(π/2) has the proper
/// x-y-x angles (φ, θ + π/2, −ψ), and its parameters are p ⊗ [1, 0, 1, 0]/√2 =
/// [e0 − e2, e1 − e3, e0 + e2, e1 + e3]/√2. p and −p give the same angles. p need not be
/// normalized; a p that cannot be normalized (zero or not finite) gives (0, 0, 0).
///
/// ```
/// use cardan_eulerparam::{euler_123_from_p, p_from_euler_123};
/// use std::f64::consts::FRAC_PI_2;
/// // Gimbal lock: only φ + ψ = 0.5 is defined; ψ = 0 is returned, the rotation is the same.
/// let p = p_from_euler_123(0.2, FRAC_PI_2, 0.3).unwrap();
/// let (phi, theta, psi) = euler_123_from_p(&p);
/// assert_eq!(psi, 0.0);
/// assert!((phi - 0.5).abs() < 1e-14 && (theta - FRAC_PI_2).abs() < 1e-14);
/// let q = p_from_euler_123(phi, theta, psi).unwrap();
/// assert!((q.a() - p.a()).norm() < 1e-14);
/// ```
pub fn euler_123_from_p(p: &EulerParams) -> (f64, f64, f64) {
    let Ok(q) = p.normalized() else {
        return (0.0, 0.0, 0.0);
    };
    let v = q.as_vector();
    let (phi, theta_xyx, psi_xyx) =
        proper_euler_from_half_angles(v[0] - v[2], v[1] - v[3], v[0] + v[2], v[1] + v[3]);
    (
        phi,
        theta_xyx - std::f64::consts::FRAC_PI_2,
        wrap_angle(-psi_xyx),
    )
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
/// perpendicular to z (Gram-Schmidt, two passes so that the frame is orthonormal to round-off
/// however close the hint is to z). Fails when either is zero or not finite, or when they are
/// parallel or antiparallel (angle below 1e-6 rad).
///
/// ```
/// use cardan_eulerparam::{frame_from_two_axes, EulerParamError};
/// use nalgebra::Vector3;
/// let f = frame_from_two_axes(&Vector3::new(0.0, 0.0, 2.0), &Vector3::new(1.0, 1.0, 0.0)).unwrap();
/// let r = std::f64::consts::FRAC_1_SQRT_2;
/// assert!((f.column(0) - Vector3::new(r, r, 0.0)).norm() < 1e-15);
/// assert!((f.column(1) - Vector3::new(-r, r, 0.0)).norm() < 1e-15);
/// assert!((f.determinant() - 1.0).abs() < 1e-15);
/// let z = Vector3::new(0.3, -0.2, 0.9);
/// assert!(matches!(frame_from_two_axes(&z, &(-2.0 * z)), Err(EulerParamError::ParallelAxes { .. })));
/// ```
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
    // A second Gram-Schmidt pass: when the hint is within a few degrees of z the first pass
    // leaves a component along z of relative size ε / sin, which would make the frame
    // non-orthonormal by that much (1e-10 at the 1e-6 rad threshold).
    let x = x / sin;
    let x = (x - z * z.dot(&x)).normalize();
    let y = z.cross(&x);
    Ok(Matrix3::from_columns(&[x, y, z]))
}
