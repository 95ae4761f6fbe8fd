//! Convergence orders on the A01 pendulum at t = 2 s: DOPRI5 error against rtol (adaptive) and
//! against h (fixed step, order 5); generalized-α second order (halving h divides the error by
//! about 4).

mod common;
use cardan_dynamics::{
    Dopri5Options, Dynamics, Force, GeneralizedAlphaOptions, Integrator, SimulationOptions,
};
use common::*;
use nalgebra::Vector3;

fn error_at_2s(integrator: Integrator) -> (f64, usize) {
    let model = pendulum(1.0, 1e-13, 1.0);
    let mut d = Dynamics::new(&model).unwrap();
    d.add_force(Force::gravity(Vector3::new(0.0, -G, 0.0)))
        .unwrap();
    let res = d
        .simulate(
            &d.initial_guess(),
            &SimulationOptions::new(2.0, 1).integrator(integrator),
        )
        .unwrap();
    let r = res.body("mass").unwrap().r[1];
    let (_, x, y) = A01[2];
    (
        ((r.x - x).powi(2) + (r.y - y).powi(2)).sqrt(),
        res.stats.steps,
    )
}

#[test]
fn dopri5_error_follows_the_tolerance() {
    let mut errs = Vec::new();
    for tol in [1e-5, 1e-7, 1e-9] {
        let (e, steps) = error_at_2s(Integrator::Dopri5(Dopri5Options::tolerances(
            tol,
            tol * 1e-2,
        )));
        eprintln!("DOPRI5 rtol {tol:.0e}: error {e:.2e}, {steps} steps");
        errs.push(e);
    }
    for w in errs.windows(2) {
        // 100× tighter tolerance: at least 20× smaller error.
        assert!(w[1] < w[0] / 20.0, "{errs:?}");
    }
    assert!(errs[2] < 1e-6);
}

#[test]
fn dopri5_fixed_step_is_fifth_order() {
    let (e1, _) = error_at_2s(Integrator::Dopri5(Dopri5Options::fixed(0.02)));
    let (e2, _) = error_at_2s(Integrator::Dopri5(Dopri5Options::fixed(0.01)));
    let order = (e1 / e2).log2();
    eprintln!(
        "DOPRI5 fixed: h=0.02 error {e1:.2e}, h=0.01 error {e2:.2e}, observed order {order:.2}"
    );
    assert!(order > 4.0 && order < 6.5, "order {order}");
}

#[test]
fn generalized_alpha_is_second_order() {
    let mut errs = Vec::new();
    for h in [4e-3, 2e-3, 1e-3] {
        let (e, _) = error_at_2s(Integrator::GeneralizedAlpha(GeneralizedAlphaOptions {
            rho_inf: 0.8,
            ..GeneralizedAlphaOptions::with_step(h)
        }));
        errs.push(e);
    }
    let r1 = errs[0] / errs[1];
    let r2 = errs[1] / errs[2];
    eprintln!("generalized-α errors {errs:?}, ratios {r1:.2} {r2:.2}");
    assert!(r1 > 3.0 && r1 < 5.5 && r2 > 3.0 && r2 < 5.5, "{errs:?}");
}
