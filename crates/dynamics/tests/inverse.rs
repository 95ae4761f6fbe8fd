//! Inverse dynamics of a driven crank against the closed form: motor torque
//! T = (m L²/3) θ̈ + m g (L/2) cos θ and pin force F = m a_G − m g.

mod common;
use cardan_constraints::TimeFunction;
use cardan_dynamics::{Dynamics, DynamicsError, Force};
use cardan_mechanism::KinematicOptions;
use common::*;
use nalgebra::Vector3;

#[test]
fn driven_crank_motor_torque_and_pin_force() {
    let (m, l) = (2.0, 0.8);
    let model = crank(m, l, Some(TimeFunction::Polynomial(vec![0.0, 1.0, 0.5])));
    let mut d = Dynamics::new(&model).unwrap();
    d.add_force(Force::gravity(Vector3::new(0.0, -G, 0.0)))
        .unwrap();
    let res = d
        .inverse_dynamics(&KinematicOptions::new(0.0, 3.0, 60))
        .unwrap();
    let motor = res.driver("motor").unwrap();
    let pin = res.joint_reactions("pin").unwrap();
    let (mut terr, mut ferr, mut axial): (f64, f64, f64) = (0.0, 0.0, 0.0);
    for (k, &t) in res.times().iter().enumerate() {
        let (th, thd, thdd) = (t + 0.5 * t * t, 1.0 + t, 1.0);
        let torque = m * l * l / 3.0 * thdd + m * G * l / 2.0 * th.cos();
        terr = terr.max((motor.effort[k] - torque).abs());
        let a_g = l / 2.0
            * (thdd * Vector3::new(-th.sin(), th.cos(), 0.0)
                - thd * thd * Vector3::new(th.cos(), th.sin(), 0.0));
        let f = m * a_g - m * Vector3::new(0.0, -G, 0.0);
        ferr = ferr.max((pin.on_j[k].force - f).norm());
        // Newton's third law at the pin, and no axial torque through a revolute joint.
        ferr = ferr.max((pin.on_i[k].force + pin.on_j[k].force).norm());
        axial = axial.max(pin.on_j[k].torque.z.abs());
        // The driver's torque on the crank about the axis is the effort.
        terr = terr.max((motor.reactions.on_j[k].torque.z - motor.effort[k]).abs());
    }
    eprintln!("inverse dynamics: torque error {terr:.2e}, pin force error {ferr:.2e}, axial torque {axial:.2e}");
    assert!(terr < 1e-8, "{terr}");
    assert!(ferr < 1e-8, "{ferr}");
    assert!(axial < 1e-8, "{axial}");
}

#[test]
fn undriven_mechanism_is_rejected() {
    let model = crank(1.0, 1.0, None);
    let mut d = Dynamics::new(&model).unwrap();
    let err = d
        .inverse_dynamics(&KinematicOptions::new(0.0, 1.0, 10))
        .unwrap_err();
    assert!(
        matches!(err, DynamicsError::NotFullyDriven { dof: 1, drivers: 0 }),
        "{err}"
    );
}

#[test]
fn forward_dynamics_with_a_driver_reproduces_the_motion() {
    // The driver is a rheonomic constraint: forward dynamics follows it, and its effort equals
    // the inverse-dynamics torque.
    let (m, l) = (2.0, 0.8);
    let model = crank(m, l, Some(TimeFunction::Polynomial(vec![0.0, 1.0, 0.5])));
    let mut d = Dynamics::new(&model).unwrap();
    d.add_force(Force::gravity(Vector3::new(0.0, -G, 0.0)))
        .unwrap();
    let res = d
        .simulate(
            &d.initial_guess(),
            &cardan_dynamics::SimulationOptions::new(2.0, 20),
        )
        .unwrap();
    let motor = res.driver("motor").unwrap();
    let mut err: f64 = 0.0;
    for (k, &t) in res.times().iter().enumerate() {
        let th = t + 0.5 * t * t;
        let torque = m * l * l / 3.0 + m * G * l / 2.0 * th.cos();
        err = err.max((motor.effort[k] - torque).abs());
        err = err.max((res.kinematics.joint("pin").unwrap().values[k][0] - th).abs());
    }
    eprintln!("driven forward dynamics: error {err:.2e}");
    assert!(err < 1e-6, "{err}");
}
