//! Shared helpers of the integration tests: proptest strategies, curated inputs, central
//! differences and a comparison that names the entries that disagree.
//!
//! Each test binary uses a different subset, hence the `dead_code` allowance.

#![allow(dead_code)]

use nalgebra::{Dim, Matrix, Matrix3, RawStorage, SMatrix, Vector3, Vector4};
use proptest::prelude::*;
use std::f64::consts::{FRAC_PI_2, PI};

// ---------------------------------------------------------------------------------------------
// Tolerances.
//
// EXACT: an identity evaluated in f64 on O(1) data (a handful of products and sums per entry);
//   round-off is a few ulps, ~1e-16 each, so 1e-14 leaves a margin of ~50 ulps and still
//   catches any wrong sign or factor (those give O(1) errors).
// FD_QUADRATIC: A(p) is quadratic in p, so a central difference of A along a straight line is
//   exact in exact arithmetic (the third derivative vanishes); only cancellation round-off
//   remains, ≈ ε |A| / h. With h = 1e-4 that is ≈ 2e-12; 1e-10 is a 50× margin.
// FD_SMOOTH: central difference of a smooth non-polynomial trajectory with h = 1e-5: truncation
//   h²/6 |f'''| ≈ 2e-11 |f'''| plus round-off ε |f| / h ≈ 2e-11; 1e-8 covers |f'''| up to ~100.
// FD_SECOND: second central difference with h = 1e-4: truncation h²/12 |f''''| ≈ 1e-9 |f''''|
//   plus round-off 4 ε |f| / h² ≈ 1e-7 at worst (typically 1e-8); 1e-6.
// ---------------------------------------------------------------------------------------------

/// Tolerance of exact identities on O(1) data.
pub const EXACT: f64 = 1e-14;
/// Step and tolerance of central differences of the quadratic A(p) (exact up to round-off).
pub const H_QUADRATIC: f64 = 1e-4;
/// See [`H_QUADRATIC`].
pub const FD_QUADRATIC: f64 = 1e-10;
/// Step and tolerance of first central differences of smooth trajectories.
pub const H_SMOOTH: f64 = 1e-5;
/// See [`H_SMOOTH`].
pub const FD_SMOOTH: f64 = 1e-8;
/// Step and tolerance of second central differences of smooth trajectories.
pub const H_SECOND: f64 = 1e-4;
/// See [`H_SECOND`].
pub const FD_SECOND: f64 = 1e-6;

// ---------------------------------------------------------------------------------------------
// Comparison.
// ---------------------------------------------------------------------------------------------

/// The largest |got − want| over all entries, with its (row, col).
pub fn worst<R: Dim, C: Dim, S1: RawStorage<f64, R, C>, S2: RawStorage<f64, R, C>>(
    got: &Matrix<f64, R, C, S1>,
    want: &Matrix<f64, R, C, S2>,
) -> (f64, usize, usize) {
    assert_eq!(got.shape(), want.shape(), "shape mismatch");
    let (nr, nc) = got.shape();
    let mut w = (0.0, 0, 0);
    for r in 0..nr {
        for c in 0..nc {
            let d = (got[(r, c)] - want[(r, c)]).abs();
            if d > w.0 || d.is_nan() {
                w = (d, r, c);
            }
        }
    }
    w
}

/// Whether every |got − want| ≤ tol · max(1, max |want|), and a message naming the worst entry
/// (row, col, got, want) and the context (the failing input) when not.
pub fn close<R: Dim, C: Dim, S1: RawStorage<f64, R, C>, S2: RawStorage<f64, R, C>>(
    got: &Matrix<f64, R, C, S1>,
    want: &Matrix<f64, R, C, S2>,
    tol: f64,
    ctx: &str,
) -> Result<(), String> {
    let scale = want.iter().fold(1.0f64, |m, x| m.max(x.abs()));
    let (d, r, c) = worst(got, want);
    if d <= tol * scale {
        Ok(())
    } else {
        Err(format!(
            "{ctx}: entry ({r}, {c}) got {:e}, want {:e} (|diff| = {d:e} > {:e} = tol {tol:e} × scale {scale:e})\n\
             got  = {got}\nwant = {want}",
            got[(r, c)],
            want[(r, c)],
            tol * scale,
        ))
    }
}

/// Panics with [`close`]'s message (for curated loops).
#[track_caller]
pub fn assert_close<R: Dim, C: Dim, S1: RawStorage<f64, R, C>, S2: RawStorage<f64, R, C>>(
    got: &Matrix<f64, R, C, S1>,
    want: &Matrix<f64, R, C, S2>,
    tol: f64,
    ctx: &str,
) {
    if let Err(m) = close(got, want, tol, ctx) {
        panic!("{m}");
    }
}

/// [`close`] inside a proptest body: fails the case (proptest then prints the input).
#[macro_export]
macro_rules! prop_close {
    ($got:expr, $want:expr, $tol:expr, $($ctx:tt)+) => {
        if let Err(m) = $crate::common::close(&$got, &$want, $tol, &format!($($ctx)+)) {
            return Err(proptest::test_runner::TestCaseError::fail(m));
        }
    };
}

// ---------------------------------------------------------------------------------------------
// Central differences.
// ---------------------------------------------------------------------------------------------

/// (f(h) − f(−h)) / 2h for a matrix-valued f of one real variable.
pub fn central<const R: usize, const C: usize, F>(f: F, h: f64) -> SMatrix<f64, R, C>
where
    F: Fn(f64) -> SMatrix<f64, R, C>,
{
    (f(h) - f(-h)) / (2.0 * h)
}

/// (f(h) − 2 f(0) + f(−h)) / h² for a matrix-valued f of one real variable.
pub fn central_second<const R: usize, const C: usize, F>(f: F, h: f64) -> SMatrix<f64, R, C>
where
    F: Fn(f64) -> SMatrix<f64, R, C>,
{
    (f(h) - f(0.0) * 2.0 + f(-h)) / (h * h)
}

/// The 3×4 Jacobian of a 3-vector function of p, column k by a central difference along e_k.
pub fn jacobian_p<F: Fn(&Vector4<f64>) -> Vector3<f64>>(
    f: F,
    p: &Vector4<f64>,
    h: f64,
) -> nalgebra::Matrix3x4<f64> {
    let mut j = nalgebra::Matrix3x4::zeros();
    for k in 0..4 {
        let col = central(
            |t| {
                let mut q = *p;
                q[k] += t;
                f(&q)
            },
            h,
        );
        j.set_column(k, &col);
    }
    j
}

/// The 3×3 Jacobian of a 3-vector function of a 3-vector at 0, by central differences.
pub fn jacobian_3<F: Fn(&Vector3<f64>) -> Vector3<f64>>(f: F, h: f64) -> Matrix3<f64> {
    let mut j = Matrix3::zeros();
    for k in 0..3 {
        let col = central(
            |t| {
                let mut x = Vector3::zeros();
                x[k] = t;
                f(&x)
            },
            h,
        );
        j.set_column(k, &col);
    }
    j
}

// ---------------------------------------------------------------------------------------------
// Independent reference constructions (no crate code).
// ---------------------------------------------------------------------------------------------

/// Rodrigues' formula for a unit axis u: cos χ I + sin χ ũ + (1 − cos χ) u uᵀ.
pub fn rodrigues(u: &Vector3<f64>, chi: f64) -> Matrix3<f64> {
    let ut = Matrix3::new(0.0, -u.z, u.y, u.z, 0.0, -u.x, -u.y, u.x, 0.0);
    let (s, c) = chi.sin_cos();
    Matrix3::identity() * c + ut * s + u * u.transpose() * (1.0 - c)
}

/// Elementary rotation about coordinate axis 0, 1 or 2.
pub fn rot(axis: usize, angle: f64) -> Matrix3<f64> {
    let mut u = Vector3::zeros();
    u[axis] = 1.0;
    rodrigues(&u, angle)
}

/// Hamilton product, scalar first (written out here, independent of `EulerParams::compose`).
pub fn qmul(p: &Vector4<f64>, q: &Vector4<f64>) -> Vector4<f64> {
    Vector4::new(
        p[0] * q[0] - p[1] * q[1] - p[2] * q[2] - p[3] * q[3],
        p[0] * q[1] + p[1] * q[0] + p[2] * q[3] - p[3] * q[2],
        p[0] * q[2] - p[1] * q[3] + p[2] * q[0] + p[3] * q[1],
        p[0] * q[3] + p[1] * q[2] - p[2] * q[1] + p[3] * q[0],
    )
}

/// exp(χ u / 2) = [cos(χ/2), u sin(χ/2)] for a unit axis u.
pub fn qexp(u: &Vector3<f64>, chi: f64) -> Vector4<f64> {
    let (s, c) = (0.5 * chi).sin_cos();
    Vector4::new(c, u.x * s, u.y * s, u.z * s)
}

// ---------------------------------------------------------------------------------------------
// Curated inputs.
// ---------------------------------------------------------------------------------------------

/// Unit p worth checking by name: identity, half turns (e0 = 0) about coordinate and oblique
/// axes, rotations a hair from 180° on either side, tiny angles, quarter turns, a generic p, and
/// the negation of each (p and −p are different coordinates of the same rotation).
pub fn curated_unit_p() -> Vec<(String, Vector4<f64>)> {
    let oblique = Vector3::new(1.0, -2.0, 3.0).normalize();
    let diag = Vector3::new(1.0, 1.0, 1.0).normalize();
    let mut v: Vec<(String, Vector4<f64>)> = vec![
        ("identity".into(), Vector4::new(1.0, 0.0, 0.0, 0.0)),
        (
            "180° about x (e0 = 0)".into(),
            Vector4::new(0.0, 1.0, 0.0, 0.0),
        ),
        (
            "180° about y (e0 = 0)".into(),
            Vector4::new(0.0, 0.0, 1.0, 0.0),
        ),
        (
            "180° about z (e0 = 0)".into(),
            Vector4::new(0.0, 0.0, 0.0, 1.0),
        ),
        ("180° about [1,-2,3] (e0 = 0)".into(), qexp(&oblique, PI)),
        ("180° about [1,1,1] (e0 = 0)".into(), qexp(&diag, PI)),
        (
            "180° − 1e-9 about [1,-2,3]".into(),
            qexp(&oblique, PI - 1e-9),
        ),
        (
            "180° + 1e-9 about [1,-2,3]".into(),
            qexp(&oblique, PI + 1e-9),
        ),
        ("180° − 1e-6 about x".into(), qexp(&Vector3::x(), PI - 1e-6)),
        ("1e-9 rad about [1,-2,3]".into(), qexp(&oblique, 1e-9)),
        ("90° about x".into(), qexp(&Vector3::x(), FRAC_PI_2)),
        ("90° about y".into(), qexp(&Vector3::y(), FRAC_PI_2)),
        ("90° about z".into(), qexp(&Vector3::z(), FRAC_PI_2)),
        ("120° about [1,1,1]".into(), qexp(&diag, 2.0 * PI / 3.0)),
        (
            "generic".into(),
            Vector4::new(0.3, -0.5, 0.2, 0.7).normalize(),
        ),
    ];
    let neg: Vec<_> = v.iter().map(|(n, p)| (format!("−({n})"), -p)).collect();
    v.extend(neg);
    v
}

/// Unnormalized p: the curated unit ones scaled by 0.5 and 1.7, plus e0-only and e-only cases.
pub fn curated_unnormalized_p() -> Vec<(String, Vector4<f64>)> {
    let mut v = Vec::new();
    for (n, p) in curated_unit_p() {
        v.push((format!("0.5 × ({n})"), p * 0.5));
        v.push((format!("1.7 × ({n})"), p * 1.7));
    }
    v.push(("[2, 0, 0, 0]".into(), Vector4::new(2.0, 0.0, 0.0, 0.0)));
    v.push((
        "[0, 0.3, -0.1, 0.2]".into(),
        Vector4::new(0.0, 0.3, -0.1, 0.2),
    ));
    v
}

/// Body-frame vectors a' used in the curated loops.
pub fn curated_vectors() -> Vec<Vector3<f64>> {
    vec![
        Vector3::x(),
        Vector3::y(),
        Vector3::z(),
        Vector3::new(0.4, -1.3, 2.2),
        Vector3::zeros(),
    ]
}

// ---------------------------------------------------------------------------------------------
// Proptest strategies.
// ---------------------------------------------------------------------------------------------

/// A random 4-vector uniform in [−1, 1]⁴ with |p| ≥ 0.1 (so normalizing is well conditioned).
fn raw_p() -> impl Strategy<Value = Vector4<f64>> {
    prop::array::uniform4(-1.0f64..1.0)
        .prop_map(|a| Vector4::new(a[0], a[1], a[2], a[3]))
        .prop_filter("|p| ≥ 0.1", |p| p.norm() >= 0.1)
}

/// A random unit p (direction uniform on the 3-sphere up to the rejection), any sign of e0,
/// mixed with the curated cases.
pub fn unit_p() -> impl Strategy<Value = Vector4<f64>> {
    let curated: Vec<Vector4<f64>> = curated_unit_p().into_iter().map(|(_, p)| p).collect();
    prop_oneof![
        4 => raw_p().prop_map(|p| p.normalize()),
        1 => prop::sample::select(curated),
    ]
}

/// A random p that is not normalized: a unit p scaled by a factor in [0.3, 3].
pub fn unnormalized_p() -> impl Strategy<Value = Vector4<f64>> {
    (unit_p(), 0.3f64..3.0).prop_map(|(p, s)| p * s)
}

/// A random 4-vector in [−2, 2]⁴ (a parameter rate, not tangent in general).
pub fn vec4() -> impl Strategy<Value = Vector4<f64>> {
    prop::array::uniform4(-2.0f64..2.0).prop_map(|a| Vector4::new(a[0], a[1], a[2], a[3]))
}

/// A random 3-vector in [−2, 2]³.
pub fn vec3() -> impl Strategy<Value = Vector3<f64>> {
    prop::array::uniform3(-2.0f64..2.0).prop_map(|a| Vector3::new(a[0], a[1], a[2]))
}

/// A random 3-vector with |v| ≥ 0.1, mixed with coordinate axes and their negatives.
pub fn nonzero_vec3() -> impl Strategy<Value = Vector3<f64>> {
    prop_oneof![
        4 => vec3().prop_filter("|v| ≥ 0.1", |v| v.norm() >= 0.1),
        1 => prop::sample::select(vec![
            Vector3::x(), Vector3::y(), Vector3::z(), -Vector3::x(), -Vector3::y(), -Vector3::z(),
        ]),
    ]
}

/// A random unit axis.
pub fn unit_axis() -> impl Strategy<Value = Vector3<f64>> {
    nonzero_vec3().prop_map(|v| v.normalize())
}
