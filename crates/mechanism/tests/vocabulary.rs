//! The joint vocabulary against closed forms: a constant-velocity joint turns its output shaft
//! at exactly the input speed at every bend (a universal joint does not), a point_in_plane
//! joint drives the pistons of a wobble-plate pump along R tan α sin(φ − θ), and an angle joint
//! holds its angle at 0°, 90° and 180° without losing rank; a cone joint keeps z_iᵀz_j = cos α
//! while its body is driven around z_i, and refuses α near 0 or π.

use cardan_constraints::{JointKind, TimeFunction};
use cardan_mechanism::{
    Body, DriverSpec, JointSpec, KinematicOptions, MechanismBuilder, Model, Orientation, GROUND,
};
use nalgebra::Vector3;
use std::f64::consts::PI;

/// Euler parameters of a rotation by `angle` about x.
fn about_x(angle: f64) -> Orientation {
    let h = 0.5 * angle;
    Orientation::EulerParams([h.cos(), h.sin(), 0.0, 0.0])
}

fn shaft(name: &str) -> Body {
    Body::new(name)
        .mass(1.0)
        .inertia_diagonal(0.01, 0.01, 0.002)
}

/// An input shaft along z, turned at 2π rad/s, and an output shaft along u = (0, sin β, cos β),
/// each on a revolute joint to ground, coupled at the origin by `coupling` (constant_velocity,
/// or a universal joint with its cross arms along x of the input and y of the output).
fn driveline(beta: f64, coupling: JointKind) -> Model {
    let u = Vector3::new(0.0, beta.sin(), beta.cos());
    let mut b = MechanismBuilder::new();
    b.body(shaft("in").position(Vector3::new(0.0, 0.0, -0.5)));
    b.body(shaft("out").position(0.5 * u).orientation(about_x(-beta)));
    b.point(GROUND, "A", Vector3::new(0.0, 0.0, -0.5))
        .point(GROUND, "B", 0.5 * u)
        .vector(GROUND, "z", Vector3::z())
        .vector(GROUND, "u", u)
        .vector(GROUND, "x", Vector3::x());
    for s in ["in", "out"] {
        b.point(s, "C", Vector3::zeros())
            .vector(s, "z", Vector3::z())
            .vector(s, "x", Vector3::x())
            .vector(s, "y", Vector3::y());
    }
    b.point("in", "end", Vector3::new(0.0, 0.0, 0.5)).point(
        "out",
        "end",
        Vector3::new(0.0, 0.0, -0.5),
    );
    b.joint(
        JointSpec::new(
            "bearing_in",
            JointKind::Revolute,
            (GROUND, "A"),
            ("in", "C"),
        )
        .axes("z", "z")
        .x_axes("x", "x"),
    );
    b.joint(
        JointSpec::new(
            "bearing_out",
            JointKind::Revolute,
            (GROUND, "B"),
            ("out", "C"),
        )
        .axes("u", "z")
        .x_axes("x", "x"),
    );
    let c = JointSpec::new("coupling", coupling, ("in", "end"), ("out", "end"));
    b.joint(match coupling {
        JointKind::Universal => c.axes("x", "y"),
        _ => c.axes("z", "z").x_axes("x", "x"),
    });
    b.driver(DriverSpec::rotation(
        "motor",
        "bearing_in",
        TimeFunction::Polynomial(vec![0.0, 2.0 * PI]),
    ));
    b.build().unwrap()
}

/// The largest |ψ − θ| (rad) and |ψ̇ − θ̇| (rad/s) over one input turn.
fn speed_error(beta: f64, coupling: JointKind) -> (f64, f64) {
    let model = driveline(beta, coupling);
    let res = model
        .run_kinematics(&KinematicOptions::new(0.0, 1.0, 100))
        .unwrap();
    let theta = &res.joint("bearing_in").unwrap().values;
    let psi = &res.joint("bearing_out").unwrap().values;
    let out = res.body("out").unwrap();
    let u = Vector3::new(0.0, beta.sin(), beta.cos());
    let (mut angle, mut speed): (f64, f64) = (0.0, 0.0);
    for k in 0..res.len() {
        angle = angle.max((psi[k][0] - theta[k][0]).abs());
        speed = speed.max((out.omega[k].dot(&u) - 2.0 * PI).abs());
    }
    (angle, speed)
}

#[test]
fn constant_velocity_joint_turns_the_output_at_the_input_speed_at_every_bend() {
    for deg in [0.0, 10.0, 20.0, 30.0, 40.0] {
        let (angle, speed) = speed_error(f64::to_radians(deg), JointKind::ConstantVelocity);
        eprintln!("CV at {deg}°: |ψ − θ| ≤ {angle:.1e} rad, |ψ̇ − θ̇| ≤ {speed:.1e} rad/s");
        assert!(angle < 1e-9 && speed < 1e-9, "{deg}°: {angle:e}, {speed:e}");
    }
}

#[test]
fn a_universal_joint_at_the_same_bend_does_not_keep_the_speed() {
    // The contrast that shows the CV test can fail: a Cardan joint's output speed fluctuates by
    // the factor cos β … 1/cos β.
    let beta = f64::to_radians(30.0);
    let (angle, speed) = speed_error(beta, JointKind::Universal);
    eprintln!("universal at 30°: |ψ − θ| up to {angle:.3} rad, |ψ̇ − θ̇| up to {speed:.3} rad/s");
    let want = 2.0 * PI * (1.0 / beta.cos() - 1.0);
    assert!(angle > 0.03, "{angle}");
    assert!((speed - want).abs() < 1e-3 * want, "{speed} vs {want}");
}

/// A swash plate tilted by α turning about z (2π rad/s), three pistons at radius R on
/// prismatic joints along z, each tip kept in the plate's plane by a point_in_plane joint.
fn wobble_plate(alpha: f64, r: f64) -> Model {
    let mut b = MechanismBuilder::new();
    b.body(
        Body::new("plate")
            .mass(2.0)
            .inertia_diagonal(0.02, 0.02, 0.04),
    );
    b.point(GROUND, "O", Vector3::zeros())
        .vector(GROUND, "z", Vector3::z())
        .vector(GROUND, "x", Vector3::x());
    b.point("plate", "O", Vector3::zeros())
        .vector("plate", "z", Vector3::z())
        .vector("plate", "x", Vector3::x())
        .vector("plate", "n", Vector3::new(0.0, -alpha.sin(), alpha.cos()));
    b.joint(
        JointSpec::new(
            "spindle",
            JointKind::Revolute,
            (GROUND, "O"),
            ("plate", "O"),
        )
        .axes("z", "z")
        .x_axes("x", "x"),
    );
    b.driver(DriverSpec::rotation(
        "motor",
        "spindle",
        TimeFunction::Polynomial(vec![0.0, 2.0 * PI]),
    ));
    for k in 0..3 {
        let phi = 2.0 * PI * k as f64 / 3.0;
        let (name, bore) = (format!("piston{k}"), format!("bore{k}"));
        let at = Vector3::new(r * phi.cos(), r * phi.sin(), 0.0);
        let z0 = r * alpha.tan() * phi.sin();
        b.body(
            Body::new(&name)
                .mass(0.1)
                .inertia_diagonal(1e-4, 1e-4, 1e-5)
                .position(at + Vector3::new(0.0, 0.0, z0)),
        );
        b.point(GROUND, &bore, at);
        b.point(&name, "tip", Vector3::zeros())
            .vector(&name, "z", Vector3::z())
            .vector(&name, "x", Vector3::x());
        b.joint(
            JointSpec::new(&bore, JointKind::Prismatic, (GROUND, &bore), (&name, "tip"))
                .axes("z", "z")
                .x_axes("x", "x"),
        );
        b.joint(
            JointSpec::new(
                format!("shoe{k}"),
                JointKind::PointInPlane,
                ("plate", "O"),
                (&name, "tip"),
            )
            .axis_i("n"),
        );
    }
    b.build().unwrap()
}

#[test]
fn point_in_plane_drives_the_wobble_plate_pistons_along_the_closed_form() {
    let (alpha, r) = (f64::to_radians(15.0), 0.1);
    let model = wobble_plate(alpha, r);
    let dof = model.dof(&model.workspace()).unwrap();
    assert_eq!((dof.dof, dof.redundant.len()), (1, 0), "{dof}");
    let res = model
        .run_kinematics(&KinematicOptions::new(0.0, 1.0, 120))
        .unwrap();
    let w = 2.0 * PI;
    let (mut ez, mut ev, mut ea): (f64, f64, f64) = (0.0, 0.0, 0.0);
    for k in 0..3 {
        let phi = 2.0 * PI * k as f64 / 3.0;
        let p = res.body(&format!("piston{k}")).unwrap();
        let c = r * alpha.tan();
        for (n, &t) in res.times.iter().enumerate() {
            let a = phi - w * t;
            ez = ez.max((p.r[n].z - c * a.sin()).abs());
            ev = ev.max((p.r_dot[n].z + c * w * a.cos()).abs());
            ea = ea.max((p.r_ddot[n].z + c * w * w * a.sin()).abs());
        }
    }
    eprintln!("wobble plate: |z − z_exact| ≤ {ez:.1e} m, |ż − ż_exact| ≤ {ev:.1e}, |z̈ − z̈_exact| ≤ {ea:.1e}");
    assert!(
        ez < 1e-12 && ev < 1e-11 && ea < 1e-10,
        "{ez:e} {ev:e} {ea:e}"
    );
}

/// A body on a cylindrical joint along global x (its slide driven), its z axis held at `alpha`
/// from ground's z about x by an angle joint; drawn 0.2 rad away from it.
fn hinge_at_angle(alpha: f64) -> Model {
    let mut b = MechanismBuilder::new();
    b.body(
        Body::new("lid")
            .mass(1.0)
            .inertia_diagonal(0.01, 0.02, 0.03)
            .orientation(about_x(alpha + 0.2)),
    );
    b.point(GROUND, "O", Vector3::zeros())
        .vector(GROUND, "x", Vector3::x())
        .vector(GROUND, "y", Vector3::y())
        .vector(GROUND, "z", Vector3::z());
    b.point("lid", "O", Vector3::zeros())
        .vector("lid", "x", Vector3::x())
        .vector("lid", "y", Vector3::y())
        .vector("lid", "z", Vector3::z());
    b.joint(
        JointSpec::new("rail", JointKind::Cylindrical, (GROUND, "O"), ("lid", "O"))
            .axes("x", "x")
            .x_axes("y", "y"),
    );
    b.joint(
        JointSpec::new("stay", JointKind::Angle, (GROUND, "O"), ("lid", "O"))
            .axes("z", "z")
            .x_axes("x", "x")
            .angle(alpha),
    );
    b.driver(DriverSpec::translation(
        "push",
        "rail",
        TimeFunction::Harmonic {
            amplitude: 0.1,
            frequency: 2.0 * PI,
            phase: 0.0,
            offset: 0.0,
        },
    ));
    b.build().unwrap()
}

#[test]
fn angle_joint_holds_its_angle_at_0_90_and_180_degrees_with_full_rank() {
    for deg in [0.0, 90.0, 180.0] {
        let alpha = f64::to_radians(deg);
        let model = hinge_at_angle(alpha);
        let dof = model.dof(&model.workspace()).unwrap();
        assert_eq!((dof.dof, dof.redundant.len()), (1, 0), "{deg}°: {dof}");
        let res = model
            .run_kinematics(&KinematicOptions::new(0.0, 1.0, 50))
            .unwrap();
        let lid = res.body("lid").unwrap();
        let want = Vector3::new(0.0, -alpha.sin(), alpha.cos());
        let mut err: f64 = 0.0;
        for k in 0..res.len() {
            let zj = cardan_eulerparam::a(&lid.p[k]) * Vector3::z();
            err = err.max((zj - want).norm());
            err = err.max((zj.dot(&Vector3::z()).clamp(-1.0, 1.0).acos() - alpha).abs());
            err = err.max((res.joint("stay").unwrap().values[k][0] - alpha).abs());
        }
        eprintln!("angle joint at {deg}°: held to {err:.1e} rad");
        assert!(err < 1e-7, "{deg}°: {err:e}");
    }
}

/// A carrier on a revolute joint about ground z, driven at ω; a top hinged to it about the
/// carrier's x axis (free), held by a cone joint at `alpha` between ground z and the top's z.
/// Drawn 0.2 rad off the cone; `angle` is the cone's angle key (None: as drawn).
fn top_on_cone(drawn: f64, angle: Option<f64>) -> Result<Model, String> {
    let mut b = MechanismBuilder::new();
    b.body(shaft("carrier"));
    b.body(shaft("top").orientation(about_x(drawn)));
    b.point(GROUND, "O", Vector3::zeros())
        .vector(GROUND, "x", Vector3::x())
        .vector(GROUND, "z", Vector3::z());
    for body in ["carrier", "top"] {
        b.point(body, "O", Vector3::zeros())
            .vector(body, "x", Vector3::x())
            .vector(body, "y", Vector3::y())
            .vector(body, "z", Vector3::z());
    }
    b.joint(
        JointSpec::new("spin", JointKind::Revolute, (GROUND, "O"), ("carrier", "O"))
            .axes("z", "z")
            .x_axes("x", "x"),
    );
    b.joint(
        JointSpec::new("hinge", JointKind::Revolute, ("carrier", "O"), ("top", "O"))
            .axes("x", "x")
            .x_axes("y", "y"),
    );
    let mut cone =
        JointSpec::new("cone", JointKind::Cone, (GROUND, "O"), ("top", "O")).axes("z", "z");
    if let Some(a) = angle {
        cone = cone.angle(a);
    }
    b.joint(cone);
    b.driver(DriverSpec::rotation(
        "motor",
        "spin",
        TimeFunction::Polynomial(vec![0.0, 1.5]),
    ));
    b.build().map_err(|e| e.to_string())
}

#[test]
fn cone_joint_keeps_its_angle_while_driven_about_its_axis() {
    let w = 1.5;
    for deg in [20.0, 60.0, 120.0] {
        let alpha = f64::to_radians(deg);
        let model = top_on_cone(alpha + 0.2, Some(alpha)).unwrap();
        let dof = model.dof(&model.workspace()).unwrap();
        assert_eq!((dof.dof, dof.redundant.len()), (1, 0), "{deg}°: {dof}");
        let res = model
            .run_kinematics(&KinematicOptions::new(0.0, 2.0, 40))
            .unwrap();
        let top = res.body("top").unwrap();
        let cone = res.joint("cone").unwrap();
        let (mut ez, mut ew, mut eb): (f64, f64, f64) = (0.0, 0.0, 0.0);
        for (k, &t) in res.times.iter().enumerate() {
            // z_j = R_z(ωt) (0, −sin α, cos α); the hinge stays at α, so ω = ω e_z.
            let (s, c) = (w * t).sin_cos();
            let want = Vector3::new(alpha.sin() * s, -alpha.sin() * c, alpha.cos());
            let zj = cardan_eulerparam::a(&top.p[k]) * Vector3::z();
            ez = ez.max((zj - want).norm());
            ez = ez.max((zj.z - alpha.cos()).abs());
            ew = ew.max((top.omega[k] - Vector3::new(0.0, 0.0, w)).norm());
            eb = eb.max((cone.values[k][0] - alpha).abs());
            eb = eb.max(cone.rates[k][0].abs());
        }
        eprintln!("cone at {deg}°: |z_j − exact| ≤ {ez:.1e}, |ω − exact| ≤ {ew:.1e} rad/s, bend ≤ {eb:.1e}");
        assert!(
            ez < 1e-10 && ew < 1e-9 && eb < 1e-9,
            "{deg}°: {ez:e} {ew:e} {eb:e}"
        );
    }
}

#[test]
fn cone_joint_refuses_angles_near_0_and_pi() {
    for (drawn, angle) in [
        (0.5, Some(5e-4)),
        (0.5, Some(PI - 5e-4)),
        (0.5, Some(-0.5)),
        (0.5, Some(PI + 0.1)),
        // No angle given: the drawn one, here z_j ∥ z_i.
        (0.0, None),
    ] {
        let e = top_on_cone(drawn, angle).unwrap_err();
        assert!(
            e.contains("joint \"cone\" (cone)")
                && e.contains("loses rank")
                && e.contains("parallel_axes"),
            "{angle:?}: {e}"
        );
        assert_eq!(e.contains("as drawn"), angle.is_none(), "{e}");
    }
    // Just inside the margin: accepted.
    for a in [1.5e-3, PI - 1.5e-3] {
        top_on_cone(0.5, Some(a)).unwrap();
    }
}
