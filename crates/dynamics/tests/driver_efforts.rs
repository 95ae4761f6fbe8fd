//! Every driver type's effort is the physical force (N) or torque (N m) along its driven
//! coordinate, so that effort × rate = power:
//! - Newton–Euler: a slider of mass m, free of gravity, moved along x by a translation, a
//!   distance or a coordinate driver needs the force m s̈ along x; a crank of polar inertia J
//!   turned by a rotation driver needs the torque J θ̈.
//! - Work–energy: the work ∫ effort · ċ dt (trapezoid over a fine grid) equals the change of
//!   kinetic energy, and the power column equals effort × rate at every output.

mod common;
use cardan_constraints::{JointKind, TimeFunction};
use cardan_dynamics::{DriverEfforts, DynamicResults, Dynamics};
use cardan_mechanism::{
    Axis, Body, DriverSpec, JointSpec, KinematicOptions, MechanismBuilder, Model, GROUND,
};
use nalgebra::Vector3;

/// The slide s(t) = 0.3 t² + 0.1 t³ and its derivatives.
fn slide(t: f64) -> (f64, f64, f64) {
    (
        0.3 * t * t + 0.1 * t * t * t,
        0.6 * t + 0.3 * t * t,
        0.6 + 0.6 * t,
    )
}

/// The slide as a time function, offset by `c` (a distance ℓ = c + s).
fn slide_function(c: f64) -> TimeFunction {
    TimeFunction::Polynomial(vec![c, 0.0, 0.3, 0.1])
}

const M: f64 = 3.0;

/// A slider on a prismatic joint along global x, its centre of mass at (1, 0, 0) at s = 0,
/// driven by `driver`.
fn slider(driver: DriverSpec) -> Model {
    let mut b = MechanismBuilder::new();
    b.body(
        Body::new("slider")
            .mass(M)
            .inertia_diagonal(0.1, 0.2, 0.3)
            .position(Vector3::new(1.0, 0.0, 0.0)),
    );
    b.point(GROUND, "O", Vector3::zeros())
        .point(GROUND, "A", Vector3::new(1.0, 0.0, 0.0))
        .vector(GROUND, "x", Vector3::x())
        .vector(GROUND, "y", Vector3::y());
    b.point("slider", "G", Vector3::zeros())
        .vector("slider", "x", Vector3::x())
        .vector("slider", "y", Vector3::y());
    b.joint(
        JointSpec::new(
            "guide",
            JointKind::Prismatic,
            (GROUND, "A"),
            ("slider", "G"),
        )
        .axes("x", "x")
        .x_axes("y", "y"),
    );
    b.driver(driver);
    b.build().unwrap()
}

fn inverse(model: &Model, t_end: f64, steps: usize) -> DynamicResults {
    let mut d = Dynamics::new(model).unwrap();
    d.inverse_dynamics(&KinematicOptions::new(0.0, t_end, steps))
        .unwrap()
}

/// max |effort − expected(t)|, and the work–energy and power checks.
fn check(
    label: &str,
    res: &DynamicResults,
    driver: &DriverEfforts,
    expected: impl Fn(f64) -> (f64, f64),
    kinetic: impl Fn(f64) -> f64,
) {
    let times = res.times();
    let (mut err, mut scale, mut power_err) = (0.0f64, 0.0f64, 0.0f64);
    let mut work = 0.0;
    for (k, &t) in times.iter().enumerate() {
        let (effort, rate) = expected(t);
        err = err.max((driver.effort[k] - effort).abs());
        scale = scale.max(effort.abs());
        power_err = power_err.max((driver.power[k] - driver.effort[k] * rate).abs());
        if k > 0 {
            work += 0.5 * (driver.power[k] + driver.power[k - 1]) * (t - times[k - 1]);
        }
    }
    let (t0, t1) = (times[0], *times.last().unwrap());
    let de = kinetic(t1) - kinetic(t0);
    let energy_err = (work - de).abs() / de.abs().max(1e-12);
    eprintln!(
        "{label}: effort error {err:.2e} (scale {scale:.2e}), power error {power_err:.2e}, \
         work {work:.6e} vs ΔT {de:.6e} ({energy_err:.1e} relative)"
    );
    assert!(err < 1e-8 * scale.max(1.0), "{label}: effort error {err}");
    assert!(
        power_err < 1e-8 * scale.max(1.0),
        "{label}: power error {power_err}"
    );
    assert!(energy_err < 1e-4, "{label}: work–energy error {energy_err}");
}

fn slider_kinetic(t: f64) -> f64 {
    0.5 * M * slide(t).1.powi(2)
}

#[test]
fn translation_driver_effort_is_the_force_along_the_slide() {
    let model = slider(DriverSpec::translation(
        "push",
        "guide",
        slide_function(0.0),
    ));
    let res = inverse(&model, 2.0, 2000);
    let d = res.driver("push").unwrap();
    check(
        "translation",
        &res,
        d,
        |t| (M * slide(t).2, slide(t).1),
        slider_kinetic,
    );
}

#[test]
fn distance_driver_effort_is_the_force_along_the_line() {
    // ℓ = 1 + s from the ground origin to the slider's centre of mass: the force along the
    // line (positive when it pushes the points apart) is m ℓ̈.
    let model = slider(DriverSpec::distance(
        "rod",
        (GROUND, "O"),
        ("slider", "G"),
        slide_function(1.0),
    ));
    let res = inverse(&model, 2.0, 2000);
    let d = res.driver("rod").unwrap();
    check(
        "distance",
        &res,
        d,
        |t| (M * slide(t).2, slide(t).1),
        slider_kinetic,
    );
}

#[test]
fn coordinate_driver_effort_is_the_force_along_the_axis() {
    let model = slider(DriverSpec::coordinate(
        "x",
        ("slider", "G"),
        Axis::X,
        slide_function(1.0),
    ));
    let res = inverse(&model, 2.0, 2000);
    let d = res.driver("x").unwrap();
    check(
        "coordinate",
        &res,
        d,
        |t| (M * slide(t).2, slide(t).1),
        slider_kinetic,
    );
}

#[test]
fn rotation_driver_effort_is_the_torque_about_the_axis() {
    // θ = 0.3 t² + 0.1 t³ on the crank of the shared models (no gravity): T = J θ̈ with J
    // about the pin, m l²/3.
    let (m, l) = (2.0, 0.8);
    let model = common::crank(m, l, Some(slide_function(0.0)));
    let res = inverse(&model, 2.0, 2000);
    let d = res.driver("motor").unwrap();
    let j = m * l * l / 3.0;
    check(
        "rotation",
        &res,
        d,
        |t| (j * slide(t).2, slide(t).1),
        |t| 0.5 * j * slide(t).1.powi(2),
    );
}
