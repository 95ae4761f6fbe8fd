//! Assembly lands on the branch the drivers prescribe: a rotation driver's equation
//! sin(φ − θ(t)) = 0 also holds at φ = θ(t) ± π, and a run that starts where θ(t) is far from
//! the drawn angle must still assemble at θ(t) (mod 2π), or fail, never silently at θ ± π.

use cardan_mechanism::{
    AssemblyOptions, Body, DriverSpec, JointKind, JointSpec, KinematicOptions, MechanismBuilder,
    Model, TimeFunction, GROUND,
};
use nalgebra::Vector3;
use std::f64::consts::PI;

/// A crank on a revolute joint about z, drawn along +x (angle 0), driven by θ(t) = ω t.
fn crank(omega: f64) -> Model {
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
        JointSpec::new("pivot", JointKind::Revolute, (GROUND, "O"), ("crank", "O"))
            .axes("z", "z")
            .x_axes("x", "x"),
    );
    b.driver(DriverSpec::rotation(
        "motor",
        "pivot",
        TimeFunction::Polynomial(vec![0.0, omega]),
    ));
    b.build().unwrap()
}

/// |φ − θ| reduced to [0, π].
fn angle_error(phi: f64, theta: f64) -> f64 {
    let d = (phi - theta).rem_euclid(2.0 * PI);
    d.min(2.0 * PI - d)
}

/// The crank's angle from its tip direction.
fn crank_angle(model: &Model, ws: &cardan_mechanism::Workspace) -> f64 {
    let _ = model;
    let x = cardan_eulerparam::a(&ws.p(0)) * Vector3::x();
    x.y.atan2(x.x)
}

#[test]
fn assembly_far_from_the_drawn_angle_lands_on_the_driven_branch() {
    let model = crank(1.0);
    for t in [0.5, 1.2, 1.7, 2.5, 3.0, 3.1, 4.0, 5.5, -2.0, 20.0] {
        let mut ws = model.workspace();
        model.assemble(&mut ws, &AssemblyOptions::at(t)).unwrap();
        let phi = crank_angle(&model, &ws);
        let e = angle_error(phi, t);
        assert!(
            e < 1e-9,
            "t = {t}: assembled at {phi:.4} rad, driven θ = {t} (error {e:.3})"
        );
    }
}

#[test]
fn a_run_starting_late_follows_the_driven_angle() {
    let model = crank(1.0);
    let r = model
        .run_kinematics(&KinematicOptions::new(2.5, 3.5, 10))
        .unwrap();
    let j = r.joint("pivot").unwrap();
    for (k, &t) in r.times.iter().enumerate() {
        let e = angle_error(j.values[k][0], t);
        assert!(
            e < 1e-9,
            "t = {t}: joint angle {} (error {e:.3})",
            j.values[k][0]
        );
    }
}
