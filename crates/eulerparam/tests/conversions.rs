//! Conversions round-trip (issue 2): rotation matrix ↔ p (Shepperd, including exact 180° and
//! round-off), axis-angle ↔ p, 3-1-3 Euler and 1-2-3 Bryant angles ↔ p (including the singular
//! orientations, where rotation matrices are compared, not angles), and the frame builders with
//! their typed errors.
//!
//! References are built independently of the crate (Rodrigues' formula, products of elementary
//! rotations, 2 u uᵀ − I). Tolerance [`common::EXACT`] unless stated otherwise.

mod common;

use cardan_eulerparam::convert::{axis_angle_from_p, p_from_axis_angle, unit};
use cardan_eulerparam::{
    a, euler_123_from_p, euler_313_from_p, frame_from_axis, frame_from_two_axes, p_from_euler_123,
    p_from_euler_313, p_from_rotation_matrix, EulerParamError, EulerParams,
};
use common::*;
use nalgebra::{Matrix3, Vector3, Vector4};
use proptest::prelude::*;
use std::f64::consts::{FRAC_PI_2, PI};

// ---------------------------------------------------------------------------------------------
// Rotation matrix ↔ p.
// ---------------------------------------------------------------------------------------------

/// p_from_rotation_matrix(A(p)) is p or −p (the one with e0 ≥ 0), unit, and reproduces A(p).
fn check_matrix_round_trip(p: &Vector4<f64>, ctx: &str) -> Result<(), String> {
    let m = a(p);
    let q = p_from_rotation_matrix(&m).map_err(|e| format!("{ctx}: {e}"))?;
    let qv = *q.as_vector();
    if qv[0] < 0.0 {
        return Err(format!("{ctx}: e0 = {:e} < 0", qv[0]));
    }
    if !q.is_normalized(EXACT) {
        return Err(format!("{ctx}: |pᵀp − 1| = {:e}", q.norm_error()));
    }
    close(&a(&qv), &m, EXACT, &format!("{ctx}: A(p(A)) = A"))?;
    // Away from e0 = 0 the sign is determined: q = sign(e0) p.
    if p[0].abs() > 1e-8 {
        close(
            &qv,
            &(p * p[0].signum()),
            EXACT,
            &format!("{ctx}: p(A(p)) = ±p"),
        )?;
    } else {
        let d = (qv - p).norm().min((qv + p).norm());
        if d > 1e-8 {
            return Err(format!(
                "{ctx}: p(A(p)) = {:?} is neither p nor −p",
                qv.as_slice()
            ));
        }
    }
    Ok(())
}

#[test]
fn rotation_matrix_round_trip_on_curated_p() {
    for (name, p) in curated_unit_p() {
        if let Err(m) = check_matrix_round_trip(&p, &format!("p = {name} {:?}", p.as_slice())) {
            panic!("{m}");
        }
    }
}

#[test]
fn exact_half_turns_from_matrices() {
    // 2 u uᵀ − I is the half turn about u; built here without the crate.
    let mut axes = vec![
        Vector3::x(),
        Vector3::y(),
        Vector3::z(),
        Vector3::new(1.0, 1.0, 0.0),
        Vector3::new(0.0, 1.0, 1.0),
        Vector3::new(1.0, 0.0, -1.0),
        Vector3::new(1.0, 1.0, 1.0),
        Vector3::new(1.0, -2.0, 3.0),
        Vector3::new(-3.0, 0.5, 0.25),
        Vector3::new(1e-9, 1.0, 0.0),
    ];
    axes.extend(axes.clone().into_iter().map(|u| -u));
    for u in axes {
        let u = u.normalize();
        let m = u * u.transpose() * 2.0 - Matrix3::identity();
        let ctx = format!("half turn about {:?}", u.as_slice());
        let q = p_from_rotation_matrix(&m).unwrap_or_else(|e| panic!("{ctx}: {e}"));
        let qv = *q.as_vector();
        assert!(qv[0].abs() <= EXACT, "{ctx}: e0 = {:e}, want 0", qv[0]);
        assert!(qv[0] >= 0.0, "{ctx}: e0 = {:e} < 0", qv[0]);
        let e = q.e();
        let s = if e.dot(&u) >= 0.0 { 1.0 } else { -1.0 };
        assert_close(&e, &(u * s), EXACT, &format!("{ctx}: e = ±u"));
        assert_close(&a(&qv), &m, EXACT, &format!("{ctx}: A(p) = M"));
    }
    // Axis-aligned half turns are exact in floating point.
    for k in 0..3 {
        let mut d = Vector3::new(-1.0, -1.0, -1.0);
        d[k] = 1.0;
        let q = p_from_rotation_matrix(&Matrix3::from_diagonal(&d)).unwrap();
        let mut want = Vector4::zeros();
        want[k + 1] = 1.0;
        assert_eq!(*q.as_vector(), want, "half turn about axis {k}");
    }
}

#[test]
fn matrices_with_round_off_are_accepted_and_projected() {
    let deltas = [1e-15, 1e-12, 1e-9];
    for (name, p) in curated_unit_p() {
        for &eps in &deltas {
            // A deterministic, non-symmetric perturbation of every entry.
            let pert = Matrix3::from_fn(|r, c| eps * (((3 * r + c) % 5) as f64 - 2.0) / 2.0);
            let m = a(&p) + pert;
            let ctx = format!("p = {name}, perturbation {eps:e}");
            let q = p_from_rotation_matrix(&m).unwrap_or_else(|e| panic!("{ctx}: {e}"));
            assert!(
                q.is_normalized(EXACT),
                "{ctx}: |pᵀp − 1| = {:e}",
                q.norm_error()
            );
            // The recovered rotation is within O(perturbation) of the intended one.
            assert_close(&q.a(), &a(&p), 10.0 * eps + EXACT, &ctx);
        }
    }
}

#[test]
fn non_rotations_are_rejected_with_typed_errors() {
    let bad = [
        ("reflection −I", -Matrix3::identity()),
        (
            "reflection diag(1, 1, −1)",
            Matrix3::from_diagonal(&Vector3::new(1.0, 1.0, -1.0)),
        ),
        ("scaled 2 I", Matrix3::identity() * 2.0),
        ("zero", Matrix3::zeros()),
        (
            "shear",
            Matrix3::new(1.0, 0.1, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0),
        ),
        (
            "rotation + 1e-5",
            a(&Vector4::new(0.3, -0.5, 0.2, 0.7).normalize()).add_scalar(1e-5),
        ),
    ];
    for (name, m) in bad {
        assert!(
            matches!(
                p_from_rotation_matrix(&m),
                Err(EulerParamError::NotRotation { .. })
            ),
            "{name}: got {:?}",
            p_from_rotation_matrix(&m)
        );
    }
    for x in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
        let mut m = Matrix3::identity();
        m[(1, 2)] = x;
        assert!(
            matches!(
                p_from_rotation_matrix(&m),
                Err(EulerParamError::NotFinite { .. })
            ),
            "entry {x}: got {:?}",
            p_from_rotation_matrix(&m)
        );
    }
}

// ---------------------------------------------------------------------------------------------
// Axis-angle ↔ p.
// ---------------------------------------------------------------------------------------------

fn check_axis_angle(p: &Vector4<f64>, ctx: &str) -> Result<(), String> {
    let (u, chi) = axis_angle_from_p(&EulerParams::from_vector(*p));
    if !(0.0..=2.0 * PI).contains(&chi) {
        return Err(format!("{ctx}: χ = {chi} outside [0, 2π]"));
    }
    if (u.norm() - 1.0).abs() > EXACT {
        return Err(format!("{ctx}: |u| = {}", u.norm()));
    }
    let q = p_from_axis_angle(&u, chi).map_err(|e| format!("{ctx}: {e}"))?;
    close(
        q.as_vector(),
        p,
        EXACT,
        &format!("{ctx}: p → (u, χ) → p keeps p (and its sign)"),
    )?;
    close(
        &rodrigues(&u, chi),
        &a(p),
        EXACT,
        &format!("{ctx}: A(p) = Rodrigues(u, χ)"),
    )
}

#[test]
fn axis_angle_round_trip_on_curated_p() {
    for (name, p) in curated_unit_p() {
        if let Err(m) = check_axis_angle(&p, &format!("p = {name} {:?}", p.as_slice())) {
            panic!("{m}");
        }
    }
}

#[test]
fn axis_angle_special_cases() {
    let (u, chi) = EulerParams::identity().to_axis_angle();
    assert_eq!((u, chi), (Vector3::x(), 0.0), "identity");
    let (u, chi) = (-EulerParams::identity()).to_axis_angle();
    assert_eq!((u, chi), (Vector3::x(), 2.0 * PI), "−identity");
    let (u, chi) = EulerParams::new(0.0, 0.0, -1.0, 0.0).to_axis_angle();
    assert_eq!((u, chi), (-Vector3::y(), PI), "half turn about −y");
    // Unnormalized p: the axis and angle of p / |p|.
    let (u, chi) = EulerParams::new(0.0, 0.0, 0.0, 3.0).to_axis_angle();
    assert_eq!((u, chi), (Vector3::z(), PI), "3 × half turn about z");
    // Axis of any nonzero length, including extreme magnitudes.
    let p = p_from_axis_angle(&Vector3::new(1.0, 2.0, -2.0), 0.7).unwrap();
    for s in [1e-300, 1e-200, 1e-5, 7.0, 1e200, 1e300] {
        let q = p_from_axis_angle(&(Vector3::new(1.0, 2.0, -2.0) * s), 0.7).unwrap();
        assert_close(
            q.as_vector(),
            p.as_vector(),
            EXACT,
            &format!("axis scaled by {s:e}"),
        );
    }
    // Negative and > 2π angles are fine (p ↔ χ + 4π, −p ↔ χ + 2π).
    let p = p_from_axis_angle(&Vector3::z(), 0.7).unwrap();
    let q = p_from_axis_angle(&Vector3::z(), 0.7 + 2.0 * PI).unwrap();
    assert_close(q.as_vector(), &-p.as_vector(), EXACT, "χ + 2π gives −p");
    let q = p_from_axis_angle(&-Vector3::z(), -0.7).unwrap();
    assert_close(q.as_vector(), p.as_vector(), EXACT, "(−u, −χ) gives p");
}

#[test]
fn axis_angle_errors_are_typed() {
    assert!(matches!(
        p_from_axis_angle(&Vector3::zeros(), 1.0),
        Err(EulerParamError::ZeroAxis { .. })
    ));
    assert!(matches!(
        p_from_axis_angle(&Vector3::new(1e-320, 0.0, 0.0), 1.0),
        Err(EulerParamError::ZeroAxis { .. })
    ));
    assert!(matches!(
        p_from_axis_angle(&Vector3::new(f64::NAN, 0.0, 1.0), 1.0),
        Err(EulerParamError::NotFinite { .. })
    ));
    assert!(matches!(
        p_from_axis_angle(&Vector3::new(f64::INFINITY, 0.0, 1.0), 1.0),
        Err(EulerParamError::NotFinite { .. })
    ));
    assert!(matches!(
        p_from_axis_angle(&Vector3::z(), f64::NAN),
        Err(EulerParamError::NotFinite { .. })
    ));
    assert!(matches!(
        unit("v", &Vector3::zeros()),
        Err(EulerParamError::ZeroAxis { what: "v", .. })
    ));
}

// ---------------------------------------------------------------------------------------------
// Euler angles 3-1-3 and Bryant angles 1-2-3.
// ---------------------------------------------------------------------------------------------

fn r313(phi: f64, theta: f64, psi: f64) -> Matrix3<f64> {
    rot(2, phi) * rot(0, theta) * rot(2, psi)
}

fn r123(phi: f64, theta: f64, psi: f64) -> Matrix3<f64> {
    rot(0, phi) * rot(1, theta) * rot(2, psi)
}

/// Angles → p against the independent product of elementary rotations; p → angles → p
/// against A; angle ranges.
fn check_313(phi: f64, theta: f64, psi: f64, tol_back: f64, ctx: &str) -> Result<(), String> {
    let p = p_from_euler_313(phi, theta, psi).map_err(|e| format!("{ctx}: {e}"))?;
    if !p.is_normalized(EXACT) {
        return Err(format!("{ctx}: |pᵀp − 1| = {:e}", p.norm_error()));
    }
    close(
        &p.a(),
        &r313(phi, theta, psi),
        EXACT,
        &format!("{ctx}: A(p) = R_z(φ) R_x(θ) R_z(ψ)"),
    )?;
    let (f, t, s) = euler_313_from_p(&p);
    if !(0.0..=PI).contains(&t) || !(-PI..=PI).contains(&f) || !(-PI..=PI).contains(&s) {
        return Err(format!("{ctx}: angles ({f}, {t}, {s}) out of range"));
    }
    close(
        &r313(f, t, s),
        &p.a(),
        tol_back,
        &format!("{ctx}: p → ({f}, {t}, {s}) → A"),
    )?;
    let back = p_from_euler_313(f, t, s).unwrap();
    close(
        &back.a(),
        &p.a(),
        tol_back,
        &format!("{ctx}: p → angles → p"),
    )
}

fn check_123(phi: f64, theta: f64, psi: f64, tol_back: f64, ctx: &str) -> Result<(), String> {
    let p = p_from_euler_123(phi, theta, psi).map_err(|e| format!("{ctx}: {e}"))?;
    if !p.is_normalized(EXACT) {
        return Err(format!("{ctx}: |pᵀp − 1| = {:e}", p.norm_error()));
    }
    close(
        &p.a(),
        &r123(phi, theta, psi),
        EXACT,
        &format!("{ctx}: A(p) = R_x(φ) R_y(θ) R_z(ψ)"),
    )?;
    let (f, t, s) = euler_123_from_p(&p);
    if !(-FRAC_PI_2..=FRAC_PI_2).contains(&t)
        || !(-PI..=PI).contains(&f)
        || !(-PI..=PI).contains(&s)
    {
        return Err(format!("{ctx}: angles ({f}, {t}, {s}) out of range"));
    }
    close(
        &r123(f, t, s),
        &p.a(),
        tol_back,
        &format!("{ctx}: p → ({f}, {t}, {s}) → A"),
    )?;
    let back = p_from_euler_123(f, t, s).unwrap();
    close(
        &back.a(),
        &p.a(),
        tol_back,
        &format!("{ctx}: p → angles → p"),
    )
}

/// Angles away from the singularities and from the ±π wrap come back unchanged.
#[test]
fn regular_angles_round_trip() {
    for &(phi, theta, psi) in &[
        (0.3, 1.1, -0.7),
        (-2.5, 0.2, 3.0),
        (1.0, 3.0, -3.0),
        (0.0, 0.5, 0.0),
    ] {
        let (f, t, s) = euler_313_from_p(&p_from_euler_313(phi, theta, psi).unwrap());
        let ctx = format!("3-1-3 ({phi}, {theta}, {psi}) → ({f}, {t}, {s})");
        assert!(
            (f - phi).abs() < 1e-14 && (t - theta).abs() < 1e-14 && (s - psi).abs() < 1e-14,
            "{ctx}"
        );
    }
    for &(phi, theta, psi) in &[
        (0.3, 1.1, -0.7),
        (-2.5, -1.4, 3.0),
        (1.0, 0.0, -3.0),
        (0.0, 0.5, 0.0),
    ] {
        let (f, t, s) = euler_123_from_p(&p_from_euler_123(phi, theta, psi).unwrap());
        let ctx = format!("1-2-3 ({phi}, {theta}, {psi}) → ({f}, {t}, {s})");
        assert!(
            (f - phi).abs() < 1e-14 && (t - theta).abs() < 1e-14 && (s - psi).abs() < 1e-14,
            "{ctx}"
        );
    }
}

/// θ at and near the singular orientations: compare matrices, not angles.
#[test]
fn euler_313_singular_and_near_singular_orientations() {
    let thetas = [
        0.0,
        1e-15,
        1e-13,
        1e-12,
        1e-11,
        1e-9,
        1e-6,
        PI,
        PI - 1e-15,
        PI - 1e-12,
        PI - 1e-9,
        PI - 1e-6,
    ];
    for &theta in &thetas {
        for &(phi, psi) in &[(0.0, 0.0), (0.4, -1.3), (2.9, 2.8), (-3.0, 1.0), (PI, -PI)] {
            for sign in [1.0, -1.0] {
                let ctx = format!("3-1-3 (φ, θ, ψ) = ({phi}, {}, {psi})", sign * theta);
                if let Err(m) = check_313(phi, sign * theta, psi, EXACT, &ctx) {
                    panic!("{m}");
                }
            }
        }
    }
}

#[test]
fn euler_123_singular_and_near_singular_orientations() {
    let offsets = [0.0, 1e-15, 1e-13, 1e-12, 1e-11, 1e-9, 1e-6];
    for &off in &offsets {
        for theta in [
            FRAC_PI_2 - off,
            -FRAC_PI_2 + off,
            FRAC_PI_2 + off,
            -FRAC_PI_2 - off,
        ] {
            for &(phi, psi) in &[(0.0, 0.0), (0.4, -1.3), (2.9, 2.8), (-3.0, 1.0), (PI, -PI)] {
                let ctx = format!("1-2-3 (φ, θ, ψ) = ({phi}, {theta}, {psi})");
                if let Err(m) = check_123(phi, theta, psi, EXACT, &ctx) {
                    panic!("{m}");
                }
            }
        }
    }
}

#[test]
fn euler_angles_of_curated_p() {
    for (name, p) in curated_unit_p() {
        let ep = EulerParams::from_vector(p);
        let (f, t, s) = euler_313_from_p(&ep);
        assert_close(
            &r313(f, t, s),
            &a(&p),
            EXACT,
            &format!("3-1-3 of p = {name}"),
        );
        let (f, t, s) = euler_123_from_p(&ep);
        assert_close(
            &r123(f, t, s),
            &a(&p),
            EXACT,
            &format!("1-2-3 of p = {name}"),
        );
    }
}

#[test]
fn euler_angle_errors_are_typed() {
    for bad in [f64::NAN, f64::INFINITY] {
        assert!(matches!(
            p_from_euler_313(bad, 0.0, 0.0),
            Err(EulerParamError::NotFinite { .. })
        ));
        assert!(matches!(
            p_from_euler_313(0.0, bad, 0.0),
            Err(EulerParamError::NotFinite { .. })
        ));
        assert!(matches!(
            p_from_euler_123(0.0, 0.0, bad),
            Err(EulerParamError::NotFinite { .. })
        ));
    }
}

// ---------------------------------------------------------------------------------------------
// Frames.
// ---------------------------------------------------------------------------------------------

/// v / |v| without under/overflow for extreme magnitudes (scaled by the largest entry first).
fn unit_of(v: &Vector3<f64>) -> Vector3<f64> {
    (v / v.amax()).normalize()
}

fn check_frame(f: &Matrix3<f64>, z: &Vector3<f64>, ctx: &str) -> Result<(), String> {
    close(
        &(f.transpose() * f),
        &Matrix3::identity(),
        EXACT,
        &format!("{ctx}: FᵀF = I"),
    )?;
    let det = f.determinant();
    if (det - 1.0).abs() > EXACT {
        return Err(format!("{ctx}: det = {det}, want 1 (right-handed)"));
    }
    close(
        &f.column(2).into_owned(),
        &unit_of(z),
        EXACT,
        &format!("{ctx}: z column along z"),
    )?;
    close(
        &f.column(0).cross(&f.column(1)),
        &f.column(2).into_owned(),
        EXACT,
        &format!("{ctx}: x × y = z"),
    )?;
    // The frame is a rotation matrix, so it has Euler parameters.
    p_from_rotation_matrix(f)
        .map(|_| ())
        .map_err(|e| format!("{ctx}: {e}"))
}

fn check_frame_two(z: &Vector3<f64>, xh: &Vector3<f64>, ctx: &str) -> Result<(), String> {
    let f = frame_from_two_axes(z, xh).map_err(|e| format!("{ctx}: {e}"))?;
    check_frame(&f, z, ctx)?;
    // x is the normalized part of the hint perpendicular to z (same side as the hint).
    let (zu, xu) = (unit_of(z), unit_of(xh));
    let want = (xu - zu * zu.dot(&xu)).normalize();
    // The direction of that part is itself conditioned by 1 / sin(angle between z and hint):
    // both the crate and this reference carry ≈ ε / sin of round-off in it.
    let sin = zu.cross(&xu).norm();
    let tol = (1e-15 / sin).max(EXACT);
    close(
        &f.column(0).into_owned(),
        &want,
        tol,
        &format!("{ctx}: x column (tol {tol:e})"),
    )
}

#[test]
fn frames_on_curated_axes() {
    let axes = [
        Vector3::x(),
        Vector3::y(),
        Vector3::z(),
        -Vector3::x(),
        -Vector3::y(),
        -Vector3::z(),
        Vector3::new(1.0, 1.0, 1.0),
        Vector3::new(1.0, 1.0, 0.0),
        Vector3::new(0.0, 0.0, 2.0),
        Vector3::new(1e-200, -3e-200, 2e-200),
        Vector3::new(1e200, 3e200, -2e200),
        Vector3::new(1e-9, 1.0, -1e-9),
    ];
    for z in axes {
        let ctx = format!("z = {:?}", z.as_slice());
        let f = frame_from_axis(&z).unwrap_or_else(|e| panic!("{ctx}: {e}"));
        if let Err(m) = check_frame(&f, &z, &ctx) {
            panic!("{m}");
        }
        for xh in [
            Vector3::x(),
            Vector3::new(0.3, -0.2, 0.9),
            Vector3::new(-1e-7, 1.0, 0.0),
        ] {
            if unit_of(&xh).cross(&unit_of(&z)).norm() < 1e-3 {
                continue;
            }
            if let Err(m) =
                check_frame_two(&z, &xh, &format!("{ctx}, x hint = {:?}", xh.as_slice()))
            {
                panic!("{m}");
            }
        }
    }
    // The documented example: z = [0,0,2], x ~ [1,1,0].
    let f =
        frame_from_two_axes(&Vector3::new(0.0, 0.0, 2.0), &Vector3::new(1.0, 1.0, 0.0)).unwrap();
    let r = std::f64::consts::FRAC_1_SQRT_2;
    assert_close(
        &f,
        &Matrix3::new(r, -r, 0.0, r, r, 0.0, 0.0, 0.0, 1.0),
        EXACT,
        "documented example",
    );
}

#[test]
fn frame_errors_are_typed() {
    let z = Vector3::new(0.3, -0.2, 0.9);
    assert!(matches!(
        frame_from_axis(&Vector3::zeros()),
        Err(EulerParamError::ZeroAxis { .. })
    ));
    assert!(matches!(
        frame_from_axis(&Vector3::new(0.0, f64::NAN, 1.0)),
        Err(EulerParamError::NotFinite { .. })
    ));
    assert!(matches!(
        frame_from_axis(&Vector3::new(0.0, f64::INFINITY, 1.0)),
        Err(EulerParamError::NotFinite { .. })
    ));
    assert!(matches!(
        frame_from_two_axes(&Vector3::zeros(), &z),
        Err(EulerParamError::ZeroAxis { .. })
    ));
    assert!(matches!(
        frame_from_two_axes(&z, &Vector3::zeros()),
        Err(EulerParamError::ZeroAxis { .. })
    ));
    assert!(matches!(
        frame_from_two_axes(&z, &Vector3::new(f64::NAN, 0.0, 0.0)),
        Err(EulerParamError::NotFinite { .. })
    ));
    for xh in [z, -z, z * 1e5, z + Vector3::new(1e-9, 0.0, 0.0)] {
        assert!(
            matches!(
                frame_from_two_axes(&z, &xh),
                Err(EulerParamError::ParallelAxes { .. })
            ),
            "x hint {:?}: got {:?}",
            xh.as_slice(),
            frame_from_two_axes(&z, &xh)
        );
    }
    // Just above the documented 1e-6 rad threshold is accepted, and the frame is orthonormal to
    // round-off (a single Gram-Schmidt pass leaves an error of ε / angle here).
    let perp = z.cross(&Vector3::x()).normalize();
    for angle in [1e-5, 2e-6] {
        let xh = z.normalize() + perp * angle;
        if let Err(m) = check_frame_two(&z, &xh, &format!("x hint {angle:e} rad from z")) {
            panic!("{m}");
        }
    }
}

// ---------------------------------------------------------------------------------------------
// Property tests.
// ---------------------------------------------------------------------------------------------

proptest! {
    #[test]
    fn prop_rotation_matrix_round_trip(p in unit_p()) {
        if let Err(m) = check_matrix_round_trip(&p, "random p") { return Err(TestCaseError::fail(m)); }
    }

    #[test]
    fn prop_half_turn_about_random_axis(u in unit_axis()) {
        let m = u * u.transpose() * 2.0 - Matrix3::identity();
        let q = p_from_rotation_matrix(&m).map_err(|e| TestCaseError::fail(e.to_string()))?;
        prop_assert!(q.e0().abs() <= EXACT, "e0 = {:e}", q.e0());
        prop_close!(q.a(), m, EXACT, "A(p(2uuᵀ − I))");
    }

    #[test]
    fn prop_axis_angle_round_trip(p in unit_p()) {
        if let Err(m) = check_axis_angle(&p, "random p") { return Err(TestCaseError::fail(m)); }
    }

    #[test]
    fn prop_angle_axis_round_trip(u in unit_axis(), chi in 1e-3f64..(2.0 * PI - 1e-3)) {
        let p = p_from_axis_angle(&u, chi).map_err(|e| TestCaseError::fail(e.to_string()))?;
        prop_close!(p.a(), rodrigues(&u, chi), EXACT, "A(p(u, χ)) = Rodrigues");
        let (u2, chi2) = p.to_axis_angle();
        prop_close!(u2, u, 1e-12, "axis back");
        prop_assert!((chi2 - chi).abs() <= 1e-12, "angle back: {chi2} vs {chi}");
    }

    #[test]
    fn prop_euler_313_round_trip(p in unit_p()) {
        let (f, t, s) = euler_313_from_p(&EulerParams::from_vector(p));
        prop_close!(r313(f, t, s), a(&p), EXACT, "p → 3-1-3 ({f}, {t}, {s}) → A");
        if let Err(m) = check_313(f, t, s, EXACT, "p → 3-1-3 → p") { return Err(TestCaseError::fail(m)); }
    }

    #[test]
    fn prop_euler_123_round_trip(p in unit_p()) {
        let (f, t, s) = euler_123_from_p(&EulerParams::from_vector(p));
        prop_close!(r123(f, t, s), a(&p), EXACT, "p → 1-2-3 ({f}, {t}, {s}) → A");
        if let Err(m) = check_123(f, t, s, EXACT, "p → 1-2-3 → p") { return Err(TestCaseError::fail(m)); }
    }

    #[test]
    fn prop_euler_angles_to_p(phi in -4.0f64..4.0, theta in -4.0f64..4.0, psi in -4.0f64..4.0) {
        if let Err(m) = check_313(phi, theta, psi, EXACT, "3-1-3") { return Err(TestCaseError::fail(m)); }
        if let Err(m) = check_123(phi, theta, psi, EXACT, "1-2-3") { return Err(TestCaseError::fail(m)); }
    }

    #[test]
    fn prop_frames(z in nonzero_vec3(), xh in nonzero_vec3()) {
        let f = frame_from_axis(&z).map_err(|e| TestCaseError::fail(e.to_string()))?;
        if let Err(m) = check_frame(&f, &z, "frame_from_axis") { return Err(TestCaseError::fail(m)); }
        if xh.normalize().cross(&z.normalize()).norm() > 1e-3 {
            if let Err(m) = check_frame_two(&z, &xh, "frame_from_two_axes") { return Err(TestCaseError::fail(m)); }
        }
    }
}
