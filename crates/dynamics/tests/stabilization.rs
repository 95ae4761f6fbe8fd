//! Constraint drift of DOPRI5 on the A01 pendulum with loose tolerances: unstabilized it grows,
//! Baumgarte bounds it, projection keeps it at round-off.

mod common;
use cardan_dynamics::{
    Dopri5Options, Dynamics, Force, Integrator, SimulationOptions, Stabilization,
};
use common::*;
use nalgebra::Vector3;

fn drift(stabilization: Stabilization) -> (f64, f64) {
    let model = pendulum(1.0, 1e-6, 1.0);
    let mut d = Dynamics::new(&model).unwrap();
    d.add_force(Force::gravity(Vector3::new(0.0, -G, 0.0)))
        .unwrap();
    let o = Dopri5Options {
        stabilization,
        ..Dopri5Options::tolerances(1e-5, 1e-7)
    };
    let res = d
        .simulate(
            &d.initial_guess(),
            &SimulationOptions::new(20.0, 200).integrator(Integrator::Dopri5(o)),
        )
        .unwrap();
    let p = res.position_drift.iter().fold(0.0f64, |a, v| a.max(*v));
    let v = res.velocity_drift.iter().fold(0.0f64, |a, v| a.max(*v));
    (p, v)
}

#[test]
fn projection_and_baumgarte_control_the_drift() {
    let none = drift(Stabilization::None);
    let baum = drift(Stabilization::Baumgarte {
        alpha: 10.0,
        beta: 10.0,
    });
    let proj = drift(Stabilization::Projection);
    eprintln!("max |Φ|, max |Φ_v v − ν| over 20 s: none {none:?}, Baumgarte {baum:?}, projection {proj:?}");
    assert!(none.0 > 1e-5, "{none:?}");
    assert!(baum.0 < none.0 / 10.0, "{baum:?} vs {none:?}");
    assert!(proj.0 < 1e-10 && proj.1 < 1e-10, "{proj:?}");
}
