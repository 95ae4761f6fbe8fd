//! A01 simple pendulum: positions against the exact solution, energy, pin reaction (tension
//! m (g cos θ + L θ̇²)), both integrators.

mod common;
use cardan_dynamics::{
    Dopri5Options, Dynamics, Force, GeneralizedAlphaOptions, Integrator, SimulationOptions,
};
use common::*;
use nalgebra::Vector3;

fn run(integrator: Integrator) -> (f64, f64, f64, f64) {
    let model = pendulum(1.0, 1e-13, 1.0);
    let mut d = Dynamics::new(&model).unwrap();
    d.add_force(Force::gravity(Vector3::new(0.0, -G, 0.0)))
        .unwrap();
    let times: Vec<f64> = A01.iter().map(|r| r.0).collect();
    let opts = SimulationOptions::new(20.0, 1)
        .output_times(std::iter::once(0.0).chain(times.iter().copied()).collect())
        .integrator(integrator);
    let res = d.simulate(&d.initial_guess(), &opts).unwrap();
    let body = res.body("mass").unwrap();
    let mut err: f64 = 0.0;
    for (k, (_, x, y)) in A01.iter().enumerate() {
        let r = body.r[k + 1];
        err = err.max((r.x - x).abs()).max((r.y - y).abs());
    }
    // Tension: on the mass at the pin, the force points from the mass to the pivot.
    let pin = res.joint_reactions("pin").unwrap();
    let mut terr: f64 = 0.0;
    for k in 0..res.len() {
        let r = body.r[k];
        let v = body.r_dot[k];
        let cos_theta = -r.y / r.norm();
        let tension = 1.0 * (G * cos_theta + v.norm_squared() / 1.0);
        let f = pin.on_j[k].force;
        let along = f.dot(&(-r / r.norm()));
        terr = terr
            .max((along - tension).abs())
            .max((f - along * (-r / r.norm())).norm());
    }
    (
        err,
        res.energy.max_drift(),
        terr,
        res.stats.wall_time / res.stats.steps.max(1) as f64,
    )
}

#[test]
fn a01_dopri5_matches_the_exact_solution() {
    let (err, drift, terr, per_step) =
        run(Integrator::Dopri5(Dopri5Options::tolerances(1e-10, 1e-12)));
    eprintln!("DOPRI5: max position error {err:.2e}, energy drift {drift:.2e}, tension error {terr:.2e}, {per_step:.2e} s/step");
    assert!(err < 1e-7, "position error {err}");
    assert!(drift < 1e-7, "energy drift {drift}");
    assert!(terr < 1e-6, "tension error {terr}");
}

#[test]
fn a01_generalized_alpha_matches_the_exact_solution() {
    let (err, drift, terr, per_step) = run(Integrator::GeneralizedAlpha(GeneralizedAlphaOptions {
        rho_inf: 1.0,
        ..GeneralizedAlphaOptions::with_step(1e-3)
    }));
    eprintln!("gen-α h=1e-3: max position error {err:.2e}, energy drift {drift:.2e}, tension error {terr:.2e}, {per_step:.2e} s/step");
    assert!(err < 1e-3, "position error {err}");
    assert!(drift < 1e-3, "energy drift {drift}");
    assert!(terr < 1e-6, "tension error {terr}");
}

/// The pin's angle rate and acceleration written by a dynamic run are the pendulum's ω_z and
/// ω̇_z (the joint axis is global z), and its angle is that of the mass about the pivot.
#[test]
fn a01_joint_rates_are_the_body_angular_velocity_and_acceleration() {
    let model = pendulum(1.0, 1e-13, 1.0);
    let mut d = Dynamics::new(&model).unwrap();
    d.add_force(Force::gravity(Vector3::new(0.0, -G, 0.0)))
        .unwrap();
    let res = d
        .simulate(&d.initial_guess(), &SimulationOptions::new(2.0, 50))
        .unwrap();
    let (pin, body) = (
        &res.kinematics.joint("pin").unwrap(),
        res.body("mass").unwrap(),
    );
    let mut err: f64 = 0.0;
    for k in 0..res.len() {
        let r = body.r[k];
        let angle = r.y.atan2(r.x);
        err = err
            .max((pin.values[k][0] - angle).abs())
            .max((pin.rates[k][0] - body.omega[k].z).abs())
            .max((pin.accelerations[k][0] - body.omega_dot[k].z).abs());
    }
    assert!(err < 1e-10, "{err}");
}

/// A crank spinning freely at 30 turns/s, written every 0.02 s (0.6 of a turn, more than π,
/// between outputs): its joint angle is continued with the rates, so it grows as ω t.
#[test]
fn a_fast_crank_s_angle_is_continued_over_more_than_half_a_turn_per_output() {
    let model = crank(1.0, 0.4, None);
    let mut d = Dynamics::new(&model).unwrap();
    let w = 2.0 * std::f64::consts::PI * 30.0;
    let mut s = d.initial_guess();
    s.set_velocity(
        0,
        Vector3::new(0.0, 0.2 * w, 0.0),
        Vector3::new(0.0, 0.0, w),
    );
    let opts = SimulationOptions::new(2.0, 100)
        .integrator(Integrator::Dopri5(Dopri5Options::tolerances(1e-10, 1e-12)));
    let res = d.simulate(&s, &opts).unwrap();
    let pin = res.kinematics.joint("pin").unwrap();
    for (k, &t) in res.times().iter().enumerate() {
        assert!(
            (pin.values[k][0] - w * t).abs() < 1e-6,
            "t = {t}: {}",
            pin.values[k][0]
        );
    }
}
