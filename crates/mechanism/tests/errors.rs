//! Every bad input gives a clear error that names the element.

mod common;

use cardan_mechanism::{
    AnalysisError, AssemblyOptions, Axis, Body, DriverSpec, ForceInfo, ForceSpec, JointKind,
    JointSpec, KinematicOptions, MechanismBuilder, ModelError, Orientation, TimeFunction, GROUND,
};
use common::{bricard_builder, slider_crank_builder, slider_crank_undriven};
use nalgebra::{Matrix3, Vector3};

/// A crank on a revolute to ground, with points A, B and vectors x, z.
fn base() -> MechanismBuilder {
    let mut b = MechanismBuilder::new();
    b.body(Body::new("crank").mass(1.0).inertia_diagonal(1.0, 1.0, 1.0));
    b.point(GROUND, "A", Vector3::zeros())
        .vector(GROUND, "z", Vector3::z())
        .vector(GROUND, "x", Vector3::x());
    b.point("crank", "A", Vector3::zeros())
        .point("crank", "B", Vector3::x())
        .vector("crank", "z", Vector3::z())
        .vector("crank", "x", Vector3::x());
    b
}

fn build_err(b: &MechanismBuilder) -> ModelError {
    let e = b.build().unwrap_err();
    eprintln!("{e}");
    e
}

fn rev(name: &str) -> JointSpec {
    JointSpec::new(name, JointKind::Revolute, (GROUND, "A"), ("crank", "A"))
        .axes("z", "z")
        .x_axes("x", "x")
}

#[test]
fn unknown_names_suggest_the_closest() {
    let mut b = base();
    b.joint(JointSpec::new(
        "j1",
        JointKind::Spherical,
        (GROUND, "A"),
        ("crnak", "A"),
    ));
    let e = build_err(&b);
    assert_eq!(
        e,
        ModelError::UnknownBody {
            element: "joint \"j1\"".into(),
            name: "crnak".into(),
            suggestion: Some("crank".into()),
            known: vec!["ground".into(), "crank".into()],
        }
    );
    assert!(e.to_string().contains("did you mean \"crank\""));

    let mut b = base();
    b.joint(JointSpec::new(
        "j2",
        JointKind::Spherical,
        (GROUND, "A"),
        ("crank", "b"),
    ));
    assert_eq!(
        build_err(&b),
        ModelError::UnknownPoint {
            element: "joint \"j2\"".into(),
            body: "crank".into(),
            name: "b".into(),
            suggestion: Some("B".into()),
            known: vec!["A".into(), "B".into()],
        }
    );

    let mut b = base();
    b.joint(rev("j3").axes("z", "zz"));
    assert!(matches!(
        build_err(&b),
        ModelError::UnknownVector { ref name, ref suggestion, .. } if name == "zz" && suggestion.as_deref() == Some("z")
    ));

    let mut b = base();
    b.joint(rev("hinge"));
    b.driver(DriverSpec::rotation(
        "m",
        "hnige",
        TimeFunction::Constant(0.0),
    ));
    assert!(matches!(
        build_err(&b),
        ModelError::UnknownJoint { ref suggestion, .. } if suggestion.as_deref() == Some("hinge")
    ));

    // A driver is not a joint, even though the names share one namespace.
    let mut b = base();
    b.joint(rev("hinge"));
    b.driver(DriverSpec::rotation(
        "m",
        "hinge",
        TimeFunction::Constant(0.0),
    ));
    b.driver(DriverSpec::rotation("m2", "m", TimeFunction::Constant(0.0)));
    assert!(matches!(
        build_err(&b),
        ModelError::UnknownJoint { ref name, .. } if name == "m"
    ));

    // Nothing close: no suggestion.
    let mut b = base();
    b.point("wheel", "P", Vector3::zeros());
    assert!(matches!(
        build_err(&b),
        ModelError::UnknownBody {
            suggestion: None,
            ..
        }
    ));
}

#[test]
fn duplicates() {
    let mut b = base();
    b.body(Body::new("crank"));
    assert!(matches!(build_err(&b), ModelError::DuplicateBody { ref name } if name == "crank"));
    let mut b = base();
    b.body(Body::new(GROUND));
    assert!(matches!(build_err(&b), ModelError::DuplicateBody { ref name } if name == "ground"));
    let mut b = base();
    b.point("crank", "B", Vector3::y());
    assert!(matches!(
        build_err(&b),
        ModelError::DuplicateFeature { what: "point", ref name, .. } if name == "B"
    ));
    let mut b = base();
    b.vector(GROUND, "z", Vector3::x());
    assert!(matches!(
        build_err(&b),
        ModelError::DuplicateFeature { what: "vector", .. }
    ));
    let mut b = base();
    b.joint(rev("j")).joint(rev("j"));
    assert!(matches!(build_err(&b), ModelError::DuplicateElement { ref name } if name == "j"));
    let mut b = base();
    b.joint(rev("j"));
    b.driver(DriverSpec::rotation("j", "j", TimeFunction::Constant(0.0)));
    assert!(matches!(build_err(&b), ModelError::DuplicateElement { .. }));
    let mut b = base();
    b.body(Body::new(""));
    assert!(matches!(build_err(&b), ModelError::EmptyName { .. }));
}

#[test]
fn non_finite_and_absurd_numbers() {
    let mut b = base();
    b.body(Body::new("b2").position(Vector3::new(f64::NAN, 0.0, 0.0)));
    assert!(
        matches!(build_err(&b), ModelError::NotFinite { ref element, .. } if element.contains("b2"))
    );
    let mut b = base();
    b.body(Body::new("b2").mass(f64::INFINITY));
    assert!(matches!(build_err(&b), ModelError::NotFinite { .. }));
    let mut b = base();
    b.point("crank", "far", Vector3::new(0.0, 1e13, 0.0));
    let e = build_err(&b);
    assert!(matches!(e, ModelError::Absurd { ref element, .. } if element.contains("far")));
    let mut b = base();
    b.body(Body::new("b2").orientation(Orientation::Euler313([0.0, f64::NAN, 0.0])));
    assert!(matches!(build_err(&b), ModelError::NotFinite { .. }));
    let mut b = base();
    b.joint(
        JointSpec::new(
            "ss",
            JointKind::SphericalSpherical,
            (GROUND, "A"),
            ("crank", "B"),
        )
        .length(f64::NAN),
    );
    assert!(matches!(build_err(&b), ModelError::NotFinite { .. }));
    let mut b = base();
    b.joint(rev("j"));
    b.driver(DriverSpec::rotation(
        "m",
        "j",
        TimeFunction::Polynomial(vec![0.0, f64::NAN]),
    ));
    assert!(
        matches!(build_err(&b), ModelError::BadTimeFunction { ref driver, .. } if driver == "m")
    );
}

#[test]
fn zero_axes_and_bad_orientations() {
    let mut b = base();
    b.vector("crank", "nil", Vector3::zeros());
    assert!(matches!(build_err(&b), ModelError::ZeroVector { ref name, .. } if name == "nil"));
    let mut b = base();
    b.body(Body::new("b2").orientation(Orientation::AxisAngle {
        axis: Vector3::zeros(),
        angle: 1.0,
    }));
    assert!(matches!(build_err(&b), ModelError::BadOrientation { ref body, .. } if body == "b2"));
    let mut b = base();
    b.body(Body::new("b2").orientation(Orientation::EulerParams([0.0; 4])));
    assert!(matches!(build_err(&b), ModelError::BadOrientation { .. }));
    let mut b = base();
    b.body(Body::new("b2").orientation(Orientation::Axes {
        z: Vector3::z(),
        x: Some(Vector3::z() * 2.0),
    }));
    assert!(matches!(build_err(&b), ModelError::BadOrientation { .. }));
    // A marker x axis parallel to the joint axis.
    let mut b = base();
    b.vector(GROUND, "z2", Vector3::z() * 3.0);
    b.joint(rev("j").x_axes("z2", "x"));
    assert!(matches!(build_err(&b), ModelError::BadMarker { ref joint, .. } if joint == "j"));
}

#[test]
fn mass_and_inertia() {
    for m in [-1.0, 0.0] {
        let mut b = base();
        b.body(Body::new("b2").mass(m));
        assert!(
            matches!(build_err(&b), ModelError::NonPositiveMass { ref body, .. } if body == "b2")
        );
    }
    let mut b = base();
    let mut i = Matrix3::identity();
    i[(0, 1)] = 0.1;
    b.body(Body::new("b2").inertia(i));
    assert!(matches!(
        build_err(&b),
        ModelError::InertiaNotSymmetric { .. }
    ));
    let mut b = base();
    b.body(Body::new("b2").inertia_diagonal(1.0, 1.0, -0.5));
    let e = build_err(&b);
    assert!(
        matches!(e, ModelError::InertiaNotPositiveDefinite { min_eigenvalue, .. } if (min_eigenvalue + 0.5).abs() < 1e-12)
    );
    let mut b = base();
    b.body(Body::new("b2").inertia(Matrix3::zeros()));
    assert!(matches!(
        build_err(&b),
        ModelError::InertiaNotPositiveDefinite { .. }
    ));
}

/// Issue 27, item 8: principal moments that violate the triangle inequality (I1 + I2 ≥ I3)
/// belong to no rigid body (a negative second moment of mass); they were accepted.
#[test]
fn inertia_violating_the_triangle_inequality() {
    let refused = |i: Matrix3<f64>| {
        let mut b = base();
        b.body(Body::new("b2").inertia(i));
        b.build().err()
    };
    let e = refused(Matrix3::from_diagonal(&Vector3::new(1.0, 1.0, 2.5)));
    assert!(
        matches!(e, Some(ModelError::InertiaTriangle { ref body, .. }) if body == "b2"),
        "{e:?}"
    );
    let m = e.unwrap().to_string();
    assert!(m.contains("triangle inequality"), "{m}");
    assert!(m.contains("2.5"), "{m}");
    // The same tensor in rotated axes (the check is on the eigenvalues).
    let r = nalgebra::Rotation3::from_euler_angles(0.3, -0.7, 1.1).into_inner();
    let rotated = |d: Vector3<f64>| r * Matrix3::from_diagonal(&d) * r.transpose();
    let e = refused(rotated(Vector3::new(2.5, 1.0, 1.0)));
    assert!(
        matches!(e, Some(ModelError::InertiaTriangle { .. })),
        "{e:?}"
    );
    // A thin disk (I3 = I1 + I2 exactly) and a thin rod are bodies, also when rotated.
    for d in [
        Vector3::new(0.25, 0.25, 0.5),
        Vector3::new(0.5, 0.25, 0.25),
        Vector3::new(1e-9, 1.0, 1.0),
    ] {
        assert_eq!(refused(Matrix3::from_diagonal(&d)), None, "{d:?}");
        assert_eq!(refused(rotated(d)), None, "rotated {d:?}");
    }
}

/// Issue 27, item 12: the builder's magnitude limits are per quantity, in SI
/// (`cardan_mechanism::sanity::Quantity`), not one bound on every number.
#[test]
fn magnitude_limits_per_quantity() {
    let mut b = base();
    b.body(
        Body::new("ship")
            .mass(1e8)
            .inertia_diagonal(2e11, 3e11, 3e11),
    );
    assert!(b.build().is_ok(), "{:?}", b.build().err());
    let mut b = base();
    b.body(Body::new("b2").mass(1e11));
    let e = build_err(&b);
    assert!(
        matches!(e, ModelError::Absurd { limit, unit: "kg", .. } if limit == 1e10),
        "{e:?}"
    );
    let mut b = base();
    b.point("crank", "far", Vector3::new(0.0, 2e7, 0.0));
    let e = build_err(&b);
    assert!(matches!(e, ModelError::Absurd { unit: "m", .. }), "{e:?}");
    assert!(
        e.to_string().contains("2e7 m is beyond the limit of 1e7 m"),
        "{e}"
    );
}

#[test]
fn joints_and_drivers_between_wrong_bodies() {
    let mut b = base();
    b.joint(JointSpec::new(
        "self",
        JointKind::Spherical,
        ("crank", "A"),
        ("crank", "B"),
    ));
    assert!(
        matches!(build_err(&b), ModelError::SelfConnection { ref body, .. } if body == "crank")
    );
    let mut b = base();
    b.point(GROUND, "B", Vector3::x());
    b.joint(JointSpec::new(
        "gg",
        JointKind::Spherical,
        (GROUND, "A"),
        (GROUND, "B"),
    ));
    assert!(matches!(build_err(&b), ModelError::GroundToGround { .. }));
    let mut b = base();
    b.driver(DriverSpec::coordinate(
        "c",
        (GROUND, "A"),
        Axis::X,
        TimeFunction::Constant(0.0),
    ));
    assert!(matches!(build_err(&b), ModelError::OnGround { .. }));
    let mut b = base();
    b.driver(DriverSpec::distance(
        "d",
        ("crank", "A"),
        ("crank", "B"),
        TimeFunction::Constant(1.0),
    ));
    assert!(matches!(build_err(&b), ModelError::SelfConnection { .. }));
    // Missing axes.
    let mut b = base();
    b.joint(JointSpec::new(
        "j",
        JointKind::Revolute,
        (GROUND, "A"),
        ("crank", "A"),
    ));
    assert!(matches!(
        build_err(&b),
        ModelError::MissingAxis {
            which: "axis_i",
            ..
        }
    ));
    // Wrong joint kinds for drivers.
    let mut b = base();
    b.joint(JointSpec::new(
        "ball",
        JointKind::Spherical,
        (GROUND, "A"),
        ("crank", "A"),
    ));
    b.driver(DriverSpec::rotation(
        "m",
        "ball",
        TimeFunction::Constant(0.0),
    ));
    assert!(matches!(
        build_err(&b),
        ModelError::WrongJointKind {
            driver_kind: "rotation",
            ..
        }
    ));
    let mut b = base();
    b.joint(rev("hinge"));
    b.driver(DriverSpec::translation(
        "m",
        "hinge",
        TimeFunction::Constant(0.0),
    ));
    let e = build_err(&b);
    assert!(
        e.to_string().contains("needs a cylindrical, prismatic"),
        "{e}"
    );
    // Non-positive spherical-spherical length; a malformed ramp; no bodies.
    let mut b = base();
    b.joint(
        JointSpec::new(
            "ss",
            JointKind::SphericalSpherical,
            (GROUND, "A"),
            ("crank", "B"),
        )
        .length(-1.0),
    );
    assert!(matches!(build_err(&b), ModelError::NonPositive { .. }));
    let mut b = base();
    b.joint(rev("j"));
    b.driver(DriverSpec::rotation(
        "m",
        "j",
        TimeFunction::Ramp {
            t0: 1.0,
            t1: 0.5,
            f0: 0.0,
            f1: 1.0,
        },
    ));
    assert!(matches!(build_err(&b), ModelError::BadTimeFunction { .. }));
    assert_eq!(
        MechanismBuilder::new().build().unwrap_err(),
        ModelError::NoBodies
    );
}

#[test]
fn too_few_or_too_many_drivers() {
    let b = slider_crank_undriven();
    let model = b.build().unwrap();
    let e = model
        .run_kinematics(&KinematicOptions::new(0.0, 1.0, 10))
        .unwrap_err();
    eprintln!("{e}");
    assert!(matches!(
        e,
        AnalysisError::DriverCount { dof: 1, drivers: 0 }
    ));
    assert!(e
        .to_string()
        .contains("1 degrees of freedom but 0 drivers: 1 missing"));

    let mut b = slider_crank_builder(1.0);
    b.driver(DriverSpec::coordinate(
        "x",
        ("slider", "C"),
        Axis::X,
        TimeFunction::Constant(0.2),
    ));
    let e = b
        .build()
        .unwrap()
        .run_kinematics(&KinematicOptions::new(0.0, 1.0, 10))
        .unwrap_err();
    eprintln!("{e}");
    assert!(e
        .to_string()
        .contains("1 degrees of freedom but 2 drivers: 1 superfluous"));

    // An inconsistent extra driver is still reported as superfluous (not as an open assembly).
    let mut b = slider_crank_builder(1.0);
    b.driver(DriverSpec::coordinate(
        "x",
        ("slider", "C"),
        Axis::X,
        TimeFunction::Constant(5.0),
    ));
    let e = b
        .build()
        .unwrap()
        .run_kinematics(&KinematicOptions::new(0.0, 1.0, 10))
        .unwrap_err();
    assert!(
        matches!(e, AnalysisError::DriverCount { dof: 1, drivers: 2 }),
        "{e}"
    );

    // Right count, but the driver prescribes a coordinate the joints already fix.
    let mut b = slider_crank_undriven();
    b.driver(DriverSpec::coordinate(
        "y",
        ("slider", "C"),
        Axis::Y,
        TimeFunction::Constant(0.0),
    ));
    let e = b
        .build()
        .unwrap()
        .run_kinematics(&KinematicOptions::new(0.0, 1.0, 10))
        .unwrap_err();
    eprintln!("{e}");
    assert!(
        matches!(e, AnalysisError::DependentDrivers { ref dependent } if dependent[0].element == "y")
    );
}

#[test]
fn assembly_that_cannot_close_names_the_open_joints() {
    // A point held at 0.1 from two ground points 1 apart.
    let mut b = MechanismBuilder::new();
    b.body(Body::new("ball").position(Vector3::new(0.5, 0.1, 0.0)));
    b.point(GROUND, "P", Vector3::zeros())
        .point(GROUND, "Q", Vector3::x())
        .point("ball", "c", Vector3::zeros());
    b.joint(
        JointSpec::new(
            "rodP",
            JointKind::SphericalSpherical,
            (GROUND, "P"),
            ("ball", "c"),
        )
        .length(0.1),
    );
    b.joint(
        JointSpec::new(
            "rodQ",
            JointKind::SphericalSpherical,
            (GROUND, "Q"),
            ("ball", "c"),
        )
        .length(0.1),
    );
    let model = b.build().unwrap();
    let mut ws = model.workspace();
    let e = model
        .assemble(&mut ws, &AssemblyOptions::default())
        .unwrap_err();
    eprintln!("{e}");
    let AnalysisError::AssemblyFailed { open, .. } = &e else {
        panic!("{e}")
    };
    let names: Vec<&str> = open.iter().map(|o| o.element.as_str()).collect();
    assert!(
        names.contains(&"rodP") && names.contains(&"rodQ"),
        "{names:?}"
    );
    assert!(open.iter().all(|o| o.residual > 0.1));
    assert!(e.to_string().contains("rodP"));
}

#[test]
fn singular_configuration_mid_run_keeps_the_results() {
    // Bricard driven at joint A towards negative angles reaches a limit position at −π/6.
    let mut b = bricard_builder();
    b.driver(DriverSpec::rotation(
        "swing",
        "A",
        TimeFunction::Polynomial(vec![0.0, -1.0]),
    ));
    let model = b.build().unwrap();
    let e = model
        .run_kinematics(&KinematicOptions::new(0.0, 1.0, 200))
        .unwrap_err();
    eprintln!("{e}");
    let (time, names) = match &e {
        AnalysisError::Singular {
            time, dependent, ..
        } => (*time, dependent.len()),
        AnalysisError::NotConverged { time, worst, .. } => (*time, worst.len()),
        other => panic!("{other}"),
    };
    assert!((time - std::f64::consts::FRAC_PI_6).abs() < 0.01, "{time}");
    assert!(names > 0);
    let partial = e.partial_results().unwrap();
    assert_eq!(partial.len(), (time / 0.005).round() as usize);
    assert!(*partial.times.last().unwrap() < time);
    assert_eq!(partial.bodies[0].r.len(), partial.len());
    assert_eq!(partial.bodies[0].r_ddot.len(), partial.len());
}

/// Issue 27, item 6: position tolerances outside their sensible range (a residual tolerance
/// of 1.0 "assembles" a mechanism whose loops are open by a metre) were accepted.
#[test]
fn meaningless_assembly_tolerances_are_refused() {
    let model = slider_crank_builder(1.0).build().unwrap();
    let refused = |o: AssemblyOptions| {
        let mut ws = model.workspace();
        match model.assemble(&mut ws, &o) {
            Err(AnalysisError::Options(m)) => Some(m),
            Err(e) => panic!("refused for another reason: {e}"),
            Ok(_) => None,
        }
    };
    let loose = |residual, step| AssemblyOptions {
        tolerances: cardan_solver::Tolerances { residual, step },
        ..AssemblyOptions::at(0.0)
    };
    let m = refused(loose(1.0, 1e-6)).expect("residual tolerance 1.0 accepted");
    assert!(m.contains("residual tolerance = 1 is outside"), "{m}");
    assert!(m.contains("[1e-14, 1e-6]"), "{m}");
    assert!(refused(loose(0.0, 1e-6)).is_some());
    assert!(refused(loose(1e-10, f64::NAN)).is_some());
    assert!(refused(AssemblyOptions {
        max_iterations: 0,
        ..AssemblyOptions::at(0.0)
    })
    .is_some());
    assert_eq!(refused(AssemblyOptions::at(0.0)), None);
}

#[test]
fn bad_time_grid() {
    let model = slider_crank_builder(1.0).build().unwrap();
    let e = model
        .run_kinematics(&KinematicOptions::new(1.0, 0.0, 10))
        .unwrap_err();
    assert!(matches!(e, AnalysisError::Options(_)));
    let e = model
        .run_kinematics(&KinematicOptions::new(0.0, f64::NAN, 10))
        .unwrap_err();
    assert!(matches!(e, AnalysisError::Options(_)));
}

#[test]
fn force_elements() {
    let spring = |k: f64, l0: Option<f64>, point_j: &str| ForceSpec::SpringDamper {
        name: "spring".into(),
        body_i: GROUND.into(),
        point_i: "A".into(),
        body_j: "crank".into(),
        point_j: point_j.into(),
        stiffness: k,
        damping: 1.0,
        free_length: l0,
    };
    let mut b = base();
    b.force(ForceSpec::Gravity {
        g: Vector3::new(0.0, 0.0, -9.81),
    });
    b.force(spring(100.0, None, "B"));
    b.force(ForceSpec::Torque {
        name: "motor".into(),
        body: "crank".into(),
        torque: Vector3::z(),
    });
    let model = b.build().unwrap();
    assert_eq!(model.forces().len(), 3);
    // The free length defaults to the initial distance |B − A| = 1.
    assert!(
        matches!(model.forces()[1], ForceInfo::SpringDamper { free_length, .. } if (free_length - 1.0).abs() < 1e-15)
    );

    let mut b = base();
    b.force(spring(-1.0, None, "B"));
    assert!(
        matches!(build_err(&b), ModelError::NonPositive { ref element, .. } if element.contains("spring"))
    );
    let mut b = base();
    b.force(spring(1.0, Some(f64::INFINITY), "B"));
    assert!(matches!(build_err(&b), ModelError::NotFinite { .. }));
    let mut b = base();
    b.force(spring(1.0, None, "BB"));
    assert!(
        matches!(build_err(&b), ModelError::UnknownPoint { ref suggestion, .. } if suggestion.as_deref() == Some("B"))
    );
    let mut b = base();
    b.force(ForceSpec::PointForce {
        name: "push".into(),
        body: GROUND.into(),
        point: "A".into(),
        force: Vector3::x(),
    });
    assert!(matches!(build_err(&b), ModelError::OnGround { .. }));
    let mut b = base();
    b.joint(rev("spring"));
    b.force(spring(1.0, None, "B"));
    assert!(matches!(build_err(&b), ModelError::DuplicateElement { .. }));
}

/// A rotation driver measures the joint angle from x_axis_i to x_axis_j: without x axes the
/// zero would be a perpendicular the program picks (a crank drawn at 50° was turned to 0° by
/// assembly), so the builder refuses it, naming the driver and the joint.
#[test]
fn driven_angle_needs_x_axes() {
    let mut b = base();
    b.joint(
        JointSpec::new("hinge", JointKind::Revolute, (GROUND, "A"), ("crank", "A")).axes("z", "z"),
    );
    b.driver(DriverSpec::rotation(
        "motor",
        "hinge",
        TimeFunction::Polynomial(vec![0.0, 1.0]),
    ));
    let e = build_err(&b);
    assert!(
        matches!(&e, ModelError::AngleWithoutXAxes { element, joint }
            if element == "driver \"motor\"" && joint == "hinge"),
        "{e}"
    );
    let text = e.to_string();
    assert!(
        text.contains("x_axis_i") && text.contains("x_axis_j"),
        "{text}"
    );
    // With x axes the same model builds.
    let mut b = base();
    b.joint(rev("hinge"));
    b.driver(DriverSpec::rotation(
        "motor",
        "hinge",
        TimeFunction::Polynomial(vec![0.0, 1.0]),
    ));
    b.build().unwrap();
}

/// Builder errors say where they are (element, key, offending name), so a front end can point
/// at the source without re-checking (issue 20).
#[test]
fn errors_name_their_site() {
    use cardan_mechanism::{ElementKind, Site};
    let check =
        |b: &MechanismBuilder, kind, name: &str, field: Option<&str>, value: Option<&str>| {
            let want = Site {
                kind,
                name: name.into(),
                field: field.map(Into::into),
                value: value.map(Into::into),
            };
            assert_eq!(build_err(b).site(), Some(want));
        };
    let mut b = base();
    b.body(Body::new("heavy").mass(-1.0));
    check(&b, ElementKind::Body, "heavy", Some("mass"), None);
    for (body, point, value) in [("crnk", "A", "crnk"), ("crank", "Q", "Q")] {
        let mut b = base();
        b.joint(JointSpec::new(
            "j",
            JointKind::Spherical,
            (GROUND, "A"),
            (body, point),
        ));
        check(&b, ElementKind::Joint, "j", None, Some(value));
    }
    let mut b = base();
    b.joint(rev("hinge"));
    b.driver(DriverSpec::translation(
        "m",
        "hinge",
        TimeFunction::Constant(0.0),
    ));
    check(&b, ElementKind::Driver, "m", Some("joint"), None);
    let mut b = base();
    let rod = JointSpec::new(
        "rod",
        JointKind::SphericalSpherical,
        (GROUND, "A"),
        ("crank", "B"),
    );
    b.joint(rod.length(-1.0));
    check(&b, ElementKind::Joint, "rod", Some("length"), None);
}
