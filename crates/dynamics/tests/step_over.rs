//! Generalized-α steps over a time at which no step can end: after a failed step the rest of
//! the output interval is re-divided, so the retried steps do not aim at the same end point
//! again. The obstacle here is a user force that is not finite at one step end (t = 0.33 on a
//! grid of h = 0.01); at A02's horizontal positions it is a configuration singular to working
//! precision.

mod common;
use cardan_dynamics::{
    Dynamics, Force, GeneralizedAlphaOptions, Integrator, IterationMatrix, SimulationOptions,
};
use cardan_mechanism::BodyId;
use common::*;
use nalgebra::Vector3;

fn run(poison: Option<f64>) -> cardan_dynamics::DynamicResults {
    let model = crank(1.5, 0.7, None);
    let mut d = Dynamics::new(&model).unwrap();
    d.add_force(Force::gravity(Vector3::new(0.0, -G, 0.0)))
        .unwrap();
    d.set_user_forces(move |t, f| {
        if poison.is_some_and(|tp| (t - tp).abs() < 1e-9) {
            f.add_force(BodyId::Moving(0), &Vector3::new(f64::NAN, 0.0, 0.0));
        }
    });
    let o = GeneralizedAlphaOptions {
        rho_inf: 0.9,
        iteration_matrix: IterationMatrix::MassOnly,
        ..GeneralizedAlphaOptions::with_step(0.01)
    };
    d.simulate(
        &d.initial_guess(),
        &SimulationOptions::new(1.0, 10).integrator(Integrator::GeneralizedAlpha(o)),
    )
    .unwrap()
}

#[test]
fn a_failed_step_end_is_stepped_over() {
    let clean = run(None);
    let poisoned = run(Some(0.33));
    assert_eq!(clean.stats.rejected, 0);
    // One rejected attempt at t = 0.33 (the halved step to 0.325 succeeds), then the rest of
    // the interval in 8 equal steps of 9.375 ms instead of aiming at 0.33 again.
    assert_eq!(poisoned.stats.rejected, 1, "{:?}", poisoned.stats);
    assert_eq!(poisoned.stats.steps, clean.stats.steps + 1);
    let (a, b) = (
        &clean.body("crank").unwrap().r,
        &poisoned.body("crank").unwrap().r,
    );
    let diff = a
        .iter()
        .zip(b)
        .map(|(x, y)| (x - y).norm())
        .fold(0.0, f64::max);
    eprintln!("largest difference from the uniform grid: {diff:.2e} m");
    assert!(diff > 0.0 && diff < 1e-4, "{diff:e}");
}
