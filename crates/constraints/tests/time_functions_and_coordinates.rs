//! Time functions (derivatives, spline properties, validation), joint coordinates and the
//! construction-time errors of markers and joints.

use cardan_constraints::*;
use cardan_eulerparam::EulerParams;
use nalgebra::{Matrix3, Vector3};
use std::f64::consts::PI;

fn functions() -> Vec<(&'static str, TimeFunction)> {
    vec![
        ("constant", TimeFunction::Constant(2.5)),
        (
            "polynomial",
            TimeFunction::Polynomial(vec![0.3, -1.0, 0.5, 0.25, -0.05]),
        ),
        (
            "harmonic",
            TimeFunction::Harmonic {
                amplitude: 0.7,
                frequency: 3.0,
                phase: 0.4,
                offset: -0.2,
            },
        ),
        (
            "ramp",
            TimeFunction::Ramp {
                t0: 0.5,
                t1: 1.7,
                f0: -1.0,
                f1: 2.0,
            },
        ),
        (
            "spline",
            TimeFunction::spline(
                vec![0.0, 0.4, 1.0, 1.3, 2.2],
                vec![0.0, 1.0, -0.5, 0.2, 0.9],
            )
            .unwrap(),
        ),
    ]
}

/// f' and f'' against 4th-order central differences of f, away from breakpoints.
#[test]
fn derivatives_match_finite_differences() {
    let h = 1e-3;
    for (name, f) in functions() {
        for k in 0..60 {
            let t = -0.5 + 0.05 * k as f64 + 0.0123;
            let v = |x: f64| f.eval(x).0;
            let d1 =
                (v(t - 2.0 * h) - 8.0 * v(t - h) + 8.0 * v(t + h) - v(t + 2.0 * h)) / (12.0 * h);
            let d2 = (-v(t - 2.0 * h) + 16.0 * v(t - h) - 30.0 * v(t) + 16.0 * v(t + h)
                - v(t + 2.0 * h))
                / (12.0 * h * h);
            let (_, g1, g2) = f.eval(t);
            assert!(
                (g1 - d1).abs() < 1e-7,
                "{name} f'({t}): got {g1}, want {d1}"
            );
            assert!(
                (g2 - d2).abs() < 1e-5,
                "{name} f''({t}): got {g2}, want {d2}"
            );
        }
    }
}

#[test]
fn spline_interpolates_is_natural_and_c2_at_knots() {
    let t = vec![0.0, 0.4, 1.0, 1.3, 2.2];
    let y = vec![0.0, 1.0, -0.5, 0.2, 0.9];
    let f = TimeFunction::spline(t.clone(), y.clone()).unwrap();
    for (tk, yk) in t.iter().zip(&y) {
        assert!(
            (f.eval(*tk).0 - yk).abs() < 1e-15,
            "spline misses knot ({tk}, {yk})"
        );
    }
    assert!(
        f.eval(0.0).2.abs() < 1e-14 && f.eval(2.2).2.abs() < 1e-14,
        "not natural"
    );
    for &tk in &t[1..4] {
        let (a, b) = (f.eval(tk - 1e-12), f.eval(tk + 1e-12));
        assert!(
            (a.1 - b.1).abs() < 1e-9 && (a.2 - b.2).abs() < 1e-9,
            "not C² at {tk}"
        );
    }
    // Linear extrapolation with the end slope.
    let (f_end, d_end, _) = f.eval(2.2);
    let (f_out, d_out, dd_out) = f.eval(3.0);
    assert!((f_out - (f_end + 0.8 * d_end)).abs() < 1e-14 && d_out == d_end && dd_out == 0.0);
}

#[test]
fn ramp_is_constant_outside_and_c2_at_its_ends() {
    let f = TimeFunction::Ramp {
        t0: 1.0,
        t1: 2.0,
        f0: 3.0,
        f1: 5.0,
    };
    assert_eq!(f.eval(0.0), (3.0, 0.0, 0.0));
    assert_eq!(f.eval(9.0), (5.0, 0.0, 0.0));
    let (v, d1, d2) = f.eval(1.5);
    assert!((v - 4.0).abs() < 1e-15 && (d1 - 3.75).abs() < 1e-12 && d2.abs() < 1e-12);
    for te in [1.0, 2.0] {
        let (a, b) = (f.eval(te - 1e-9), f.eval(te + 1e-9));
        assert!(
            (a.1 - b.1).abs() < 1e-6 && (a.2 - b.2).abs() < 1e-6,
            "ramp not C² at {te}"
        );
    }
}

#[test]
fn invalid_time_functions_are_rejected_with_reasons() {
    let bad = [
        (
            TimeFunction::spline(vec![0.0, 1.0, 1.0], vec![0.0, 1.0, 2.0]),
            "increase strictly",
        ),
        (
            TimeFunction::spline(vec![0.0], vec![0.0]),
            "at least 2 knots",
        ),
        (
            TimeFunction::spline(vec![0.0, 1.0], vec![0.0]),
            "2 times but 1 values",
        ),
        (
            TimeFunction::spline(vec![0.0, f64::NAN], vec![0.0, 1.0]),
            "not finite",
        ),
    ];
    for (r, want) in bad {
        let msg = r.expect_err("must fail").to_string();
        assert!(
            msg.contains(want),
            "message `{msg}` should contain `{want}`"
        );
    }
    let ramp = TimeFunction::Ramp {
        t0: 1.0,
        t1: 1.0,
        f0: 0.0,
        f1: 1.0,
    };
    assert!(ramp.validate().unwrap_err().to_string().contains("t1 > t0"));
    assert!(TimeFunction::Polynomial(vec![]).validate().is_err());
    assert!(TimeFunction::Constant(f64::INFINITY).validate().is_err());
}

fn body(angle_about_z: f64, r: Vector3<f64>) -> BodyState {
    let p = EulerParams::from_axis_angle(&Vector3::z(), angle_about_z).unwrap();
    BodyState::at(r, *p.as_vector())
}

#[test]
fn revolute_angle_follows_many_turns_when_unwrapped() {
    let m = Marker::from_axes(Vector3::zeros(), Vector3::z(), Vector3::x()).unwrap();
    let joint = Joint::new(JointKind::Revolute, m, m).unwrap();
    let ground = BodyState::ground();
    let mut angle = 0.0;
    for k in 1..=2000 {
        let theta = 0.01 * k as f64 * 2.0 * PI / 3.0; // ~7 turns, through ±π many times
        let b = body(theta, Vector3::zeros());
        let c = joint.coordinates(&BodyPair::new(&ground, &b));
        angle = unwrap_angle(angle, c.as_slice()[0]);
        assert!(
            (angle - theta).abs() < 1e-9,
            "step {k}: unwrapped {angle}, true {theta}"
        );
    }
}

#[test]
fn prismatic_slide_cylindrical_and_universal_coordinates() {
    let m = Marker::from_axes(Vector3::zeros(), Vector3::z(), Vector3::x()).unwrap();
    let ground = BodyState::ground();
    let b = body(0.4, Vector3::new(0.0, 0.0, 1.25));
    let x = BodyPair::new(&ground, &b);
    let pr = Joint::new(JointKind::Prismatic, m, m)
        .unwrap()
        .coordinates(&x);
    assert_eq!(
        pr.coordinates.iter().map(|c| c.name).collect::<Vec<_>>(),
        ["slide"]
    );
    assert!((pr.values[0] - 1.25).abs() < 1e-15);
    let cy = Joint::new(JointKind::Cylindrical, m, m)
        .unwrap()
        .coordinates(&x);
    assert!((cy.values[0] - 0.4).abs() < 1e-14 && (cy.values[1] - 1.25).abs() < 1e-15);
    // Universal: arm i = x of ground; arm j = y of the body; the body turned by 0.3 about x.
    let arm_i = Marker::from_axes(Vector3::zeros(), Vector3::x(), Vector3::y()).unwrap();
    let arm_j = Marker::from_axes(Vector3::zeros(), Vector3::y(), Vector3::z()).unwrap();
    let u = Joint::new(JointKind::Universal, arm_i, arm_j).unwrap();
    let p = EulerParams::from_axis_angle(&Vector3::x(), 0.3).unwrap();
    let bj = BodyState::at(Vector3::zeros(), *p.as_vector());
    let c = u.coordinates(&BodyPair::new(&ground, &bj));
    assert_eq!(
        c.coordinates.iter().map(|c| c.name).collect::<Vec<_>>(),
        ["angle_i", "angle_j"]
    );
    // z_j = A y = (0, cos .3, sin .3); in marker i (x_i = y, y_i = z): atan2(sin .3, cos .3).
    assert!((c.values[0] - 0.3).abs() < 1e-14, "{c:?}");
}

#[test]
fn markers_and_joints_reject_bad_definitions() {
    let z = Vector3::z();
    assert!(matches!(
        Marker::from_axis(Vector3::zeros(), Vector3::zeros()),
        Err(ConstraintError::ZeroAxis { .. })
    ));
    assert!(matches!(
        Marker::from_axes(Vector3::zeros(), z, 2.0 * z),
        Err(ConstraintError::ParallelAxes { .. })
    ));
    assert!(matches!(
        Marker::from_axis(Vector3::new(f64::NAN, 0.0, 0.0), z),
        Err(ConstraintError::NotFinite { .. })
    ));
    let skewed = Matrix3::new(1.0, 0.1, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0);
    assert!(matches!(
        Marker::new(Vector3::zeros(), skewed),
        Err(ConstraintError::NotOrthonormal { .. })
    ));
    let mirror = Matrix3::from_diagonal(&Vector3::new(1.0, 1.0, -1.0));
    assert!(matches!(
        Marker::new(Vector3::zeros(), mirror),
        Err(ConstraintError::NotOrthonormal { .. })
    ));
    let m = Marker::from_axis(Vector3::zeros(), z).unwrap();
    assert!(matches!(
        Joint::new(JointKind::SphericalSpherical, m, m),
        Err(ConstraintError::Invalid(_))
    ));
    assert!(matches!(
        Joint::spherical_spherical(Vector3::zeros(), Vector3::x(), 0.0),
        Err(ConstraintError::NotPositive { .. })
    ));
    assert!(matches!(
        CoordinateDriver::new(Vector3::zeros(), 3, TimeFunction::Constant(0.0)),
        Err(ConstraintError::BadAxis(3))
    ));
}

#[test]
fn joint_row_counts_and_origins() {
    let m = Marker::from_axis(Vector3::zeros(), Vector3::z()).unwrap();
    for kind in JointKind::all() {
        let info = kind.info();
        let params = JointParams {
            length: if info.length { 1.0 } else { 0.0 },
            ..JointParams::default()
        };
        let j = Joint::with_params(kind, m, m, params).unwrap();
        assert_eq!(j.rows(), kind.rows(), "{kind:?}");
        assert_eq!(j.name(), kind.name());
        assert!(j.row_origin(kind.rows() - 1).is_some() && j.row_origin(kind.rows()).is_none());
    }
    let rev = Joint::new(JointKind::Revolute, m, m).unwrap();
    assert_eq!(rev.row_origin(2), Some((0, "s")));
    assert_eq!(rev.row_origin(3), Some((1, "p1_perp")));
}
