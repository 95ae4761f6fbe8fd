//! Limits on joint coordinates in the builder and in kinematic runs (issue 48): hostile specs
//! are builder errors naming the limit and the key; a prescribed motion that drives a joint
//! past its limit stops at the crossing, located inside the grid step.

use cardan_constraints::JointKind;
use cardan_mechanism::{
    AnalysisError, Body, Compliance, DriverSpec, ElementKind, JointSpec, KinematicOptions,
    LimitSpec, MechanismBuilder, ModelError, TimeFunction, GROUND,
};
use nalgebra::Vector3;

/// A crank turning about global z through a revolute joint "pin", driven at ω = 1 rad/s from
/// angle 0, plus a slider on a prismatic joint "rail" along x driven at 0.5 m/s.
fn model(limits: &[LimitSpec]) -> MechanismBuilder {
    let mut b = MechanismBuilder::new();
    b.body(Body::new("crank").position(Vector3::new(0.5, 0.0, 0.0)));
    b.body(Body::new("slider").position(Vector3::new(0.0, 2.0, 0.0)));
    b.point(GROUND, "O", Vector3::zeros())
        .vector(GROUND, "z", Vector3::z())
        .vector(GROUND, "x", Vector3::x())
        .point(GROUND, "R", Vector3::new(0.0, 2.0, 0.0));
    b.point("crank", "O", Vector3::new(-0.5, 0.0, 0.0))
        .vector("crank", "z", Vector3::z())
        .vector("crank", "x", Vector3::x());
    b.point("slider", "R", Vector3::zeros())
        .vector("slider", "x", Vector3::x())
        .vector("slider", "z", Vector3::z());
    b.joint(
        JointSpec::new("pin", JointKind::Revolute, (GROUND, "O"), ("crank", "O"))
            .axes("z", "z")
            .x_axes("x", "x"),
    );
    b.joint(
        JointSpec::new("rail", JointKind::Prismatic, (GROUND, "R"), ("slider", "R"))
            .axes("x", "x")
            .x_axes("z", "z"),
    );
    b.driver(DriverSpec::rotation(
        "turn",
        "pin",
        TimeFunction::Polynomial(vec![0.0, 1.0]),
    ));
    b.driver(DriverSpec::translation(
        "push",
        "rail",
        TimeFunction::Polynomial(vec![0.0, 0.5]),
    ));
    for l in limits {
        b.limit(l.clone());
    }
    b
}

fn build_error(l: LimitSpec) -> ModelError {
    model(&[l]).build().expect_err("refused")
}

#[test]
fn hostile_limits_are_builder_errors_naming_the_limit_and_the_key() {
    let cases: Vec<(LimitSpec, &str, &str)> = vec![
        (
            LimitSpec::new("s", "pin").range(1.0, -1.0),
            "upper",
            "range is empty",
        ),
        (
            LimitSpec::new("s", "pin").upper(1.0).restitution(1.5),
            "restitution",
            "[0, 1]",
        ),
        (
            LimitSpec::new("s", "pin").upper(1.0).restitution(-0.1),
            "restitution",
            "[0, 1]",
        ),
        (
            LimitSpec::new("s", "pin").coordinate("slide").upper(1.0),
            "coordinate",
            "no coordinate \"slide\"",
        ),
        (LimitSpec::new("s", "pin"), "lower", "give a lower bound"),
        (
            LimitSpec::new("s", "pin").upper(1.0).compliant(Compliance {
                stiffness: -1.0,
                damping: 0.0,
                exponent: 1.0,
            }),
            "stiffness",
            "positive",
        ),
        (
            LimitSpec::new("s", "pin").upper(1.0).compliant(Compliance {
                stiffness: 1e5,
                damping: -2.0,
                exponent: 1.0,
            }),
            "damping",
            "≥ 0",
        ),
        (
            LimitSpec::new("s", "pin").upper(f64::NAN),
            "upper",
            "not finite",
        ),
        // The drawn angle is 0: a lower bound of 0.1 rad is violated by the drawing.
        (
            LimitSpec::new("s", "pin").lower(0.1),
            "lower",
            "drawn pose violates",
        ),
    ];
    for (spec, key, words) in cases {
        let e = build_error(spec.clone());
        let msg = e.to_string();
        assert!(msg.contains(words), "{spec:?}: {msg}");
        assert_eq!(e.limit_site(), Some(("s", key)), "{msg}");
        let site = e.site().expect("a limit error has a site");
        assert_eq!(site.kind, ElementKind::Joint, "{msg}");
        assert_eq!(site.name, "pin", "{msg}");
        assert_eq!(site.field.as_deref(), Some(key), "{msg}");
    }
    let e = build_error(LimitSpec::new("s", "pn").upper(1.0));
    assert!(matches!(e, ModelError::UnknownJoint { .. }), "{e}");
    assert!(e.to_string().contains("\"pin\""), "{e}");
    assert_eq!(e.limit_site(), Some(("s", "joint")));
    // An angle limit on a joint without x axes (the zero of its angle).
    let mut b = MechanismBuilder::new();
    b.body(Body::new("crank").position(Vector3::new(0.5, 0.0, 0.0)));
    b.point(GROUND, "O", Vector3::zeros())
        .vector(GROUND, "z", Vector3::z());
    b.point("crank", "O", Vector3::new(-0.5, 0.0, 0.0))
        .vector("crank", "z", Vector3::z());
    b.joint(
        JointSpec::new("pin", JointKind::Revolute, (GROUND, "O"), ("crank", "O")).axes("z", "z"),
    );
    b.limit(LimitSpec::new("s", "pin").upper(1.0));
    let e = b.build().expect_err("no x axes");
    assert_eq!(e.limit_site(), Some(("s", "coordinate")), "{e}");
    assert!(e.to_string().contains("x axes"), "{e}");
    // A name already taken by a joint.
    let e = build_error(LimitSpec::new("pin", "pin").upper(1.0));
    assert!(matches!(e, ModelError::DuplicateElement { .. }), "{e}");
}

#[test]
fn a_valid_limit_is_in_the_model_with_its_stops() {
    let m = model(&[
        LimitSpec::new("stop", "pin")
            .range(-4.0, 4.0)
            .restitution(0.5),
        LimitSpec::new("stroke", "rail").upper(0.3),
    ])
    .build()
    .unwrap();
    assert_eq!(m.limits().len(), 2);
    assert_eq!(m.limits()[0].coordinate, "angle");
    assert_eq!(m.limits()[1].coordinate, "slide");
    let names: Vec<&str> = m.stops().iter().map(|s| s.name.as_str()).collect();
    assert_eq!(names, ["stop.lower", "stop.upper", "stroke.upper"]);
}

fn run_until_limit(limit: LimitSpec, steps: usize, t_end: f64) -> AnalysisError {
    let m = model(&[limit]).build().unwrap();
    m.run_kinematics(&KinematicOptions::new(0.0, t_end, steps))
        .expect_err("stops at the limit")
}

#[test]
fn a_motion_driven_past_a_limit_stops_at_the_crossing_inside_the_step() {
    // θ = t reaches 1.2345 rad at t = 1.2345 s, between grid times 1.2 and 1.4.
    let e = run_until_limit(LimitSpec::new("stop", "pin").upper(1.2345), 10, 2.0);
    let AnalysisError::LimitReached {
        ref limit,
        ref joint,
        time,
        value,
        bound_name,
        ref partial,
        ..
    } = e
    else {
        panic!("{e}")
    };
    assert_eq!(
        (limit.as_str(), joint.as_str(), bound_name),
        ("stop", "pin", "upper")
    );
    assert!((time - 1.2345).abs() < 1e-9, "{time}");
    assert!((value - 1.2345).abs() < 1e-9, "{value}");
    assert_eq!(
        partial.as_ref().unwrap().times.len(),
        7,
        "frames 0..1.2 kept"
    );
    let msg = e.to_string();
    for w in ["\"stop\"", "\"pin\"", "1.2345", "angle"] {
        assert!(msg.contains(w), "{msg}");
    }
}

#[test]
fn a_revolute_limit_of_270_degrees_holds_over_the_turn() {
    // The angle passes π (its principal value wraps) before it reaches 3π/2.
    let hi = 1.5 * std::f64::consts::PI;
    let e = run_until_limit(LimitSpec::new("stop", "pin").range(-hi, hi), 40, 6.0);
    let AnalysisError::LimitReached { time, value, .. } = e else {
        panic!("{e}")
    };
    assert!((time - hi).abs() < 1e-9, "{time}");
    assert!((value - hi).abs() < 1e-9, "{value}");
}

#[test]
fn a_slider_driven_past_its_stroke_stops_there() {
    // s = 0.5 t reaches 0.3 m at t = 0.6 s.
    let e = run_until_limit(LimitSpec::new("stroke", "rail").upper(0.3), 7, 1.0);
    let AnalysisError::LimitReached { time, value, .. } = e else {
        panic!("{e}")
    };
    assert!((time - 0.6).abs() < 1e-9, "{time}");
    assert!((value - 0.3).abs() < 1e-9, "{value}");
}

#[test]
fn a_run_inside_its_limits_is_unchanged() {
    let free = model(&[]).build().unwrap();
    let limited = model(&[LimitSpec::new("stop", "pin").range(-3.0, 3.0)])
        .build()
        .unwrap();
    let o = KinematicOptions::new(0.0, 2.0, 20);
    let (a, b) = (
        free.run_kinematics(&o).unwrap(),
        limited.run_kinematics(&o).unwrap(),
    );
    assert_eq!(a.bodies[0].r, b.bodies[0].r);
    assert_eq!(a.bodies[0].p, b.bodies[0].p);
}
