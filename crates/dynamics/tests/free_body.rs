//! A free body: ballistic flight in gravity (closed form) and torque-free precession of an
//! axisymmetric body (closed form ω'(t), conserved energy and angular momentum).

mod common;
use cardan_dynamics::{
    Dopri5Options, Dynamics, Force, GeneralizedAlphaOptions, Integrator, SimulationOptions,
};
use common::*;
use nalgebra::Vector3;

fn ballistic(integrator: Integrator) -> f64 {
    let model = free_body(2.0, [0.1, 0.2, 0.3]);
    let mut d = Dynamics::new(&model).unwrap();
    let g = Vector3::new(0.0, 0.0, -G);
    d.add_force(Force::gravity(g)).unwrap();
    let mut s = d.initial_guess();
    let v0 = Vector3::new(1.0, 2.0, 5.0);
    let w0 = Vector3::new(0.0, 0.0, 3.0); // spin about a principal axis: ω' stays constant
    s.set_velocity(0, v0, w0);
    let res = d
        .simulate(&s, &SimulationOptions::new(2.0, 20).integrator(integrator))
        .unwrap();
    let b = res.body("body").unwrap();
    let mut err: f64 = 0.0;
    for (k, &t) in res.times().iter().enumerate() {
        let r = Vector3::new(0.0, 0.0, 1.0) + v0 * t + 0.5 * g * t * t;
        err = err
            .max((b.r[k] - r).norm())
            .max((b.r_dot[k] - (v0 + g * t)).norm())
            .max((b.omega_local[k] - w0).norm())
            .max((b.r_ddot[k] - g).norm());
        // Rotation angle 3t about z: e0 = cos(1.5 t), e3 = sin(1.5 t).
        err = err.max((b.p[k][0] - (1.5 * t).cos()).abs() + (b.p[k][3] - (1.5 * t).sin()).abs());
    }
    err
}

#[test]
fn ballistic_flight_dopri5() {
    let err = ballistic(Integrator::Dopri5(Dopri5Options::tolerances(1e-10, 1e-12)));
    eprintln!("ballistic DOPRI5 error {err:.2e}");
    assert!(err < 1e-8, "{err}");
}

#[test]
fn ballistic_flight_generalized_alpha() {
    // Constant acceleration and constant spin are integrated exactly.
    let err = ballistic(Integrator::GeneralizedAlpha(
        GeneralizedAlphaOptions::with_step(0.01),
    ));
    eprintln!("ballistic gen-α error {err:.2e}");
    assert!(err < 1e-8, "{err}");
}

#[test]
fn torque_free_precession_of_an_axisymmetric_body() {
    let (i1, i3) = (0.3, 0.5);
    let model = free_body(1.0, [i1, i1, i3]);
    let mut d = Dynamics::new(&model).unwrap();
    let mut s = d.initial_guess();
    let (w1, w3) = (1.0, 4.0);
    s.set_velocity(0, Vector3::zeros(), Vector3::new(w1, 0.0, w3));
    let opts = SimulationOptions::new(10.0, 100)
        .integrator(Integrator::Dopri5(Dopri5Options::tolerances(1e-11, 1e-13)));
    let res = d.simulate(&s, &opts).unwrap();
    let b = res.body("body").unwrap();
    // Euler's equations: ω'3 constant, (ω'1, ω'2) turns at Ω = (I3 − I1) ω3 / I1.
    let om = (i3 - i1) * w3 / i1;
    let j = nalgebra::Matrix3::from_diagonal(&Vector3::new(i1, i1, i3));
    let h0 = j * Vector3::new(w1, 0.0, w3); // A = I at t = 0
    let (mut werr, mut herr): (f64, f64) = (0.0, 0.0);
    for (k, &t) in res.times().iter().enumerate() {
        let w = Vector3::new(w1 * (om * t).cos(), w1 * (om * t).sin(), w3);
        werr = werr.max((b.omega_local[k] - w).norm());
        let a = cardan_eulerparam::a(&b.p[k]);
        herr = herr.max((a * j * b.omega_local[k] - h0).norm());
    }
    let drift = res.energy.max_drift();
    eprintln!("precession: ω' error {werr:.2e}, angular momentum drift {herr:.2e}, energy drift {drift:.2e}, {} steps", res.stats.steps);
    assert!(werr < 1e-7, "{werr}");
    assert!(herr < 1e-7, "{herr}");
    assert!(drift < 1e-9, "{drift}");
}
