//! A stiff spring-damper (the flyball governor's K = 8e5 N/m, C = 4e4 N s/m) on a 1 kg slider:
//! explicit fixed steps of 1 ms blow up (h |λ_fast| = 40), generalized-α at 1 ms follows the
//! closed form of the overdamped oscillator.

mod common;
use cardan_constraints::JointKind;
use cardan_dynamics::{
    Dopri5Options, Dynamics, Force, GeneralizedAlphaOptions, Integrator, SimulationOptions,
};
use cardan_mechanism::{Body, JointSpec, MechanismBuilder, Model, GROUND};
use common::G;
use nalgebra::Vector3;

const K: f64 = 8e5;
const C: f64 = 4e4;

fn slider() -> Model {
    let mut b = MechanismBuilder::new();
    b.body(
        Body::new("slider")
            .mass(1.0)
            .inertia_diagonal(0.01, 0.01, 0.01)
            .position(Vector3::new(0.0, -0.5, 0.0)),
    );
    b.point(GROUND, "O", Vector3::zeros())
        .vector(GROUND, "y", Vector3::y())
        .vector(GROUND, "x", Vector3::x());
    b.point("slider", "c", Vector3::zeros())
        .vector("slider", "y", Vector3::y())
        .vector("slider", "x", Vector3::x());
    b.joint(
        JointSpec::new(
            "guide",
            JointKind::Prismatic,
            (GROUND, "O"),
            ("slider", "c"),
        )
        .axes("y", "y")
        .x_axes("x", "x"),
    );
    b.build().unwrap()
}

fn dynamics(model: &Model) -> Dynamics<'_> {
    let mut d = Dynamics::new(model).unwrap();
    d.add_force(Force::gravity(Vector3::new(0.0, -G, 0.0)))
        .unwrap();
    d.add_force(Force::spring_damper(
        "spring",
        (GROUND, "O"),
        ("slider", "c"),
        K,
        C,
        Some(0.5),
    ))
    .unwrap();
    d
}

/// u = y + 0.5 of the overdamped oscillator u'' + C u' + K u = −g, u(0) = u'(0) = 0.
fn exact(t: f64) -> f64 {
    let disc = (C * C - 4.0 * K).sqrt();
    let (s1, s2) = ((-C + disc) / 2.0, (-C - disc) / 2.0);
    let ueq = -G / K;
    let d0 = -ueq;
    let a = d0 * s2 / (s2 - s1);
    let b = d0 - a;
    ueq + a * (s1 * t).exp() + b * (s2 * t).exp()
}

#[test]
fn explicit_fixed_step_explodes() {
    let model = slider();
    let mut d = dynamics(&model);
    let opts =
        SimulationOptions::new(0.1, 10).integrator(Integrator::Dopri5(Dopri5Options::fixed(1e-3)));
    match d.simulate(&d.initial_guess(), &opts) {
        Err(e) => {
            eprintln!("DOPRI5 h = 1 ms: {e}");
            // The outputs before the blow-up are kept.
            let partial = e.partial_results().expect("t = 0 was stored");
            assert!(!partial.is_empty());
            // The spring's force passes the limit of any force (1e12 N) before the state
            // overflows.
            assert!(matches!(
                e.cause(),
                cardan_dynamics::DynamicsError::NonFinite { .. }
                    | cardan_dynamics::DynamicsError::ForceLimit { .. }
            ));
        }
        Ok(res) => {
            let y = res.body("slider").unwrap().r.last().unwrap().y;
            eprintln!("DOPRI5 h = 1 ms: y(0.1) = {y:e}");
            assert!(
                y.is_nan() || y.abs() >= 1.0,
                "explicit step should have blown up, y = {y}"
            );
        }
    }
}

#[test]
fn generalized_alpha_is_stable_and_accurate() {
    let model = slider();
    let mut d = dynamics(&model);
    let opts = SimulationOptions::new(0.2, 20).integrator(Integrator::GeneralizedAlpha(
        GeneralizedAlphaOptions::with_step(1e-3),
    ));
    let res = d.simulate(&d.initial_guess(), &opts).unwrap();
    let b = res.body("slider").unwrap();
    let mut err: f64 = 0.0;
    for (k, &t) in res.times().iter().enumerate().skip(1) {
        err = err.max((b.r[k].y + 0.5 - exact(t)).abs());
    }
    let rel = err / (G / K);
    eprintln!(
        "gen-α h = 1 ms: max error {err:.2e} m ({rel:.2e} of the static deflection), {} steps, {} Newton iterations, {:.2e} s/step",
        res.stats.steps,
        res.stats.newton_iterations,
        res.stats.wall_time / res.stats.steps as f64
    );
    assert!(rel < 2e-2, "{rel}");
    // The adaptive explicit method needs far more steps for the same span.
    let opts =
        SimulationOptions::new(0.2, 20).integrator(Integrator::Dopri5(Dopri5Options::default()));
    let res2 = d.simulate(&d.initial_guess(), &opts).unwrap();
    eprintln!(
        "adaptive DOPRI5: {} steps ({} rejected)",
        res2.stats.steps, res2.stats.rejected
    );
    assert!(res2.stats.steps > 10 * res.stats.steps);
}

/// The mass-only iteration matrix does not converge on the stiff spring at h = 1 ms
/// (β' K ≫ M): it gets through only by halving steps (or fails). The `MassOnlyThenTangent`
/// mode retries each failing step with the tangent instead, so it rejects no step and gives the
/// motion of the tangent matrix, to the Newton tolerance.
#[test]
fn mass_only_then_tangent_recovers_the_stiff_steps() {
    use cardan_dynamics::IterationMatrix;
    let model = slider();
    let mut d = dynamics(&model);
    let run = |d: &mut Dynamics, m: IterationMatrix| {
        let opts = SimulationOptions::new(0.2, 20).integrator(Integrator::GeneralizedAlpha(
            GeneralizedAlphaOptions {
                iteration_matrix: m,
                ..GeneralizedAlphaOptions::with_step(1e-3)
            },
        ));
        d.simulate(&d.initial_guess(), &opts)
    };
    if let Ok(r) = run(&mut d, IterationMatrix::MassOnly) {
        assert!(
            r.stats.rejected > 0,
            "mass-only Newton converged on K = 8e5"
        );
    }
    let tangent = run(&mut d, IterationMatrix::Tangent).unwrap();
    let hybrid = run(&mut d, IterationMatrix::MassOnlyThenTangent).unwrap();
    let (a, b) = (
        tangent.body("slider").unwrap(),
        hybrid.body("slider").unwrap(),
    );
    let diff =
        a.r.iter()
            .zip(&b.r)
            .map(|(x, y)| (x - y).norm())
            .fold(0.0, f64::max);
    assert!(diff < 1e-9, "hybrid differs from tangent by {diff:e} m");
    assert_eq!(hybrid.stats.steps, tangent.stats.steps);
    assert_eq!(hybrid.stats.rejected, 0);
}
