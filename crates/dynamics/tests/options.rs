//! Integrator options outside their sensible ranges are refused before a step is taken (issue
//! 27, item 6): `newton_tolerance = 1.0` used to run, with constraint drift 0.24 and an energy
//! of 1.9e11 J.

mod common;
use cardan_dynamics::{
    Dopri5Options, Dynamics, DynamicsError, Force, GeneralizedAlphaOptions, Integrator,
    SimulationOptions,
};
use common::*;
use nalgebra::Vector3;

/// The pendulum run with `integrator`; the error message if it is refused.
fn refused(integrator: Integrator) -> Option<String> {
    let model = pendulum(1.0, 1e-3, 1.0);
    let mut d = Dynamics::new(&model).unwrap();
    d.add_force(Force::gravity(Vector3::new(0.0, -G, 0.0)))
        .unwrap();
    let opts = SimulationOptions::new(0.1, 10).integrator(integrator);
    match d.simulate(&d.initial_guess(), &opts) {
        Ok(_) => None,
        Err(e @ DynamicsError::Options(_)) => Some(e.to_string()),
        Err(e) => panic!("refused for another reason: {e}"),
    }
}

#[test]
fn a_loose_newton_tolerance_is_refused() {
    let ga = |o: GeneralizedAlphaOptions| refused(Integrator::GeneralizedAlpha(o));
    let m = ga(GeneralizedAlphaOptions {
        newton_tolerance: 1.0,
        ..GeneralizedAlphaOptions::with_step(1e-3)
    })
    .expect("tolerance 1.0 must be refused");
    assert!(m.contains("tolerance = 1 is outside"), "{m}");
    assert!(m.contains("[1e-14, 1e-6]"), "{m}");
    for bad in [
        GeneralizedAlphaOptions {
            rho_inf: 1.5,
            ..Default::default()
        },
        GeneralizedAlphaOptions::with_step(0.0),
        GeneralizedAlphaOptions::with_step(f64::NAN),
        GeneralizedAlphaOptions {
            max_iterations: 0,
            ..Default::default()
        },
    ] {
        assert!(ga(bad).is_some(), "{bad:?} accepted");
    }
    assert_eq!(ga(GeneralizedAlphaOptions::with_step(1e-3)), None);
}

#[test]
fn meaningless_dopri5_tolerances_and_steps_are_refused() {
    let dp = |o: Dopri5Options| refused(Integrator::Dopri5(o));
    for (o, needle) in [
        (Dopri5Options::tolerances(0.5, 1e-8), "rtol = 0.5"),
        (Dopri5Options::tolerances(1e-20, 1e-8), "rtol = 1e-20"),
        (Dopri5Options::tolerances(1e-6, 0.0), "atol = 0"),
        (Dopri5Options::tolerances(1e-6, 1.0), "atol = 1"),
        (Dopri5Options::fixed(-1e-3), "dt = -0.001"),
        (
            Dopri5Options {
                h_max: 0.0,
                ..Default::default()
            },
            "h_max = 0",
        ),
        (
            Dopri5Options {
                projection_tolerance: 0.1,
                ..Default::default()
            },
            "projection_tolerance = 0.1",
        ),
    ] {
        let m = dp(o).unwrap_or_else(|| panic!("{o:?} accepted"));
        assert!(m.contains(needle), "{needle}: {m}");
        assert!(m.contains("sensible range"), "{m}");
    }
    assert_eq!(dp(Dopri5Options::tolerances(1e-8, 1e-10)), None);
    assert_eq!(dp(Dopri5Options::fixed(1e-3)), None);
}
