//! Consistent initial conditions from a rough guess, and typed errors naming the elements when
//! they cannot be made consistent.

mod common;
use cardan_constraints::{JointKind, TimeFunction};
use cardan_dynamics::{Dynamics, DynamicsError};
use cardan_mechanism::{Body, DriverSpec, JointSpec, MechanismBuilder, GROUND};
use common::*;
use nalgebra::Vector3;

#[test]
fn rough_guess_becomes_consistent_with_the_m_closest_velocity() {
    let (m, l) = (2.0, 0.8);
    let model = crank(m, l, None);
    let mut d = Dynamics::new(&model).unwrap();
    let mut guess = d.initial_guess();
    guess.set_pose(
        0,
        Vector3::new(0.47, 0.0, 0.03),
        nalgebra::Vector4::new(1.0, 0.0, 0.02, 0.0),
    );
    let v0 = Vector3::new(0.3, 1.0, 0.2);
    let w0 = Vector3::new(0.1, -0.2, 1.5);
    guess.set_velocity(0, v0, w0);
    let s = d.consistent_state(&guess).unwrap();
    // On the manifold: the pin point is at the origin and does not move.
    let pin = Vector3::new(-l / 2.0, 0.0, 0.0);
    let b = s.body_state(0);
    assert!(b.point(&pin).norm() < 1e-10, "{}", b.point(&pin));
    assert!(
        s.point_velocity(cardan_mechanism::BodyId::Moving(0), &pin)
            .norm()
            < 1e-10
    );
    // Only rotation about z is left, at the rate of the M-closest consistent velocity:
    // θ̇ = Nᵀ M v0 / Nᵀ M N with N = [ẑ × (r − 0); A ẑ-components in the body frame].
    let z_body = b.a.transpose() * Vector3::z();
    let n_r = Vector3::z().cross(&b.r);
    let j = d.inertia(0);
    let num = m * n_r.dot(&v0) + z_body.dot(&(j * w0));
    let den = m * n_r.norm_squared() + z_body.dot(&(j * z_body));
    let rate = num / den;
    assert!(
        (s.omega_local(0) - z_body * rate).norm() < 1e-9,
        "{} vs {}",
        s.omega_local(0),
        rate
    );
    assert!((s.r_dot(0) - n_r * rate).norm() < 1e-9);
}

#[test]
fn impossible_positions_name_the_open_joints() {
    let mut b = MechanismBuilder::new();
    b.body(Body::new("link").mass(1.0).inertia_diagonal(0.1, 0.1, 0.1));
    b.point(GROUND, "A", Vector3::new(-1.5, 0.0, 0.0))
        .point(GROUND, "B", Vector3::new(1.5, 0.0, 0.0))
        .point("link", "P", Vector3::zeros());
    b.joint(
        JointSpec::new(
            "left",
            JointKind::SphericalSpherical,
            (GROUND, "A"),
            ("link", "P"),
        )
        .length(1.0),
    );
    b.joint(
        JointSpec::new(
            "right",
            JointKind::SphericalSpherical,
            (GROUND, "B"),
            ("link", "P"),
        )
        .length(1.0),
    );
    let model = b.build().unwrap();
    let mut d = Dynamics::new(&model).unwrap();
    let err = d.consistent_state(&d.initial_guess()).unwrap_err();
    eprintln!("{err}");
    match err {
        DynamicsError::InconsistentPositions { open } => {
            let names: Vec<_> = open.iter().map(|e| e.element.as_str()).collect();
            assert!(
                names.contains(&"left") || names.contains(&"right"),
                "{names:?}"
            );
        }
        e => panic!("unexpected {e}"),
    }
}

#[test]
fn incompatible_velocities_name_the_equation() {
    // Two rotation drivers of one joint agree at t = 0 (angle 0) but not in rate: positions are
    // consistent (redundant), velocities are not.
    let mut b = MechanismBuilder::new();
    b.body(
        Body::new("crank")
            .mass(1.0)
            .inertia_diagonal(0.01, 0.1, 0.1)
            .position(Vector3::new(0.5, 0.0, 0.0)),
    );
    b.point(GROUND, "O", Vector3::zeros())
        .vector(GROUND, "z", Vector3::z())
        .vector(GROUND, "x", Vector3::x());
    b.point("crank", "O", Vector3::new(-0.5, 0.0, 0.0))
        .vector("crank", "z", Vector3::z())
        .vector("crank", "x", Vector3::x());
    b.joint(
        JointSpec::new("pin", JointKind::Revolute, (GROUND, "O"), ("crank", "O"))
            .axes("z", "z")
            .x_axes("x", "x"),
    );
    b.driver(DriverSpec::rotation(
        "slow",
        "pin",
        TimeFunction::Polynomial(vec![0.0, 1.0]),
    ));
    b.driver(DriverSpec::rotation(
        "fast",
        "pin",
        TimeFunction::Polynomial(vec![0.0, 2.0]),
    ));
    let model = b.build().unwrap();
    let mut d = Dynamics::new(&model).unwrap();
    let err = d.consistent_state(&d.initial_guess()).unwrap_err();
    eprintln!("{err}");
    match err {
        DynamicsError::InconsistentVelocities {
            equations,
            residual,
        } => {
            assert!((residual - 1.0).abs() < 1e-9, "{residual}");
            assert!(
                equations.iter().any(|e| e.element == "fast"),
                "{equations:?}"
            );
        }
        e => panic!("unexpected {e}"),
    }
}

#[test]
fn missing_inertia_is_reported() {
    let mut b = MechanismBuilder::new();
    b.body(Body::new("ghost").mass(1.0));
    let model = b.build().unwrap();
    let err = Dynamics::new(&model).unwrap_err();
    assert!(
        matches!(err, DynamicsError::MissingInertia { ref body } if body == "ghost"),
        "{err}"
    );
}
