//! A parallelogram four-bar of spatial revolute joints (20 equations of rank 17: three
//! redundant rows dropped once): forward dynamics against the exact one-degree-of-freedom
//! model J φ̈ = −2 m g L cos φ (J = 5/3 m L²), energy conservation, and inverse dynamics of
//! the driven linkage (motor torque J φ̈ + 2 m g L cos φ, rank-aware).

mod common;
use cardan_constraints::TimeFunction;
use cardan_dynamics::{
    Dopri5Options, Dynamics, Force, GeneralizedAlphaOptions, Integrator, SimulationOptions,
};
use cardan_mechanism::{
    Body, DriverSpec, JointKind, JointSpec, KinematicOptions, MechanismBuilder, Model, Orientation,
    GROUND,
};
use common::G;
use nalgebra::Vector3;
use std::f64::consts::FRAC_PI_2;

fn four_bar(drive: Option<TimeFunction>) -> Model {
    let (m, l) = (1.0, 1.0);
    let i = m * l * l / 12.0;
    let mut b = MechanismBuilder::new();
    for (k, name) in ["rocker0", "rocker1"].iter().enumerate() {
        b.body(
            Body::new(*name)
                .mass(m)
                .inertia_diagonal(1e-4, i, i)
                .position(Vector3::new(k as f64 * l, -l / 2.0, 0.0))
                .orientation(Orientation::AxisAngle {
                    axis: Vector3::z(),
                    angle: -FRAC_PI_2,
                }),
        );
        b.point(name, "pivot", Vector3::new(-l / 2.0, 0.0, 0.0))
            .point(name, "end", Vector3::new(l / 2.0, 0.0, 0.0))
            .vector(name, "z", Vector3::z());
    }
    b.body(
        Body::new("coupler")
            .mass(m)
            .inertia_diagonal(1e-4, i, i)
            .position(Vector3::new(l / 2.0, -l, 0.0)),
    );
    b.point("coupler", "left", Vector3::new(-l / 2.0, 0.0, 0.0))
        .point("coupler", "right", Vector3::new(l / 2.0, 0.0, 0.0))
        .vector("coupler", "z", Vector3::z());
    b.point(GROUND, "A", Vector3::zeros())
        .point(GROUND, "B", Vector3::new(l, 0.0, 0.0))
        .vector(GROUND, "z", Vector3::z())
        .vector(GROUND, "x", Vector3::x());
    b.vector("rocker0", "x", Vector3::x());
    let rev = |n: &str, a: (&str, &str), c: (&str, &str)| {
        JointSpec::new(n, JointKind::Revolute, a, c).axes("z", "z")
    };
    b.joint(rev("A", (GROUND, "A"), ("rocker0", "pivot")).x_axes("x", "x"));
    b.joint(rev("B", (GROUND, "B"), ("rocker1", "pivot")));
    b.joint(rev("C", ("rocker0", "end"), ("coupler", "left")));
    b.joint(rev("D", ("rocker1", "end"), ("coupler", "right")));
    if let Some(f) = drive {
        b.driver(DriverSpec::rotation("motor", "A", f));
    }
    b.build().unwrap()
}

/// φ(t) of J φ̈ = −2 g cos φ (m = L = 1), φ(0) = −π/2, φ̇(0) = 1, by RK4 with a tiny step.
fn phi_exact(t_end: f64) -> f64 {
    let f = |y: [f64; 2]| [y[1], -2.0 * G * y[0].cos() / (5.0 / 3.0)];
    let n = (t_end / 1e-4).round() as usize;
    let h = t_end / n as f64;
    let mut y = [-FRAC_PI_2, 1.0];
    for _ in 0..n {
        let k1 = f(y);
        let k2 = f([y[0] + 0.5 * h * k1[0], y[1] + 0.5 * h * k1[1]]);
        let k3 = f([y[0] + 0.5 * h * k2[0], y[1] + 0.5 * h * k2[1]]);
        let k4 = f([y[0] + h * k3[0], y[1] + h * k3[1]]);
        for c in 0..2 {
            y[c] += h / 6.0 * (k1[c] + 2.0 * k2[c] + 2.0 * k3[c] + k4[c]);
        }
    }
    y[0]
}

/// The four-bar under gravity, rockers turning at 1 rad/s (the coupler translating at 1 m/s).
fn loaded(model: &Model) -> (Dynamics<'_>, cardan_dynamics::State) {
    let mut d = Dynamics::new(model).unwrap();
    d.add_force(Force::gravity(Vector3::new(0.0, -G, 0.0)))
        .unwrap();
    let mut s = d.initial_guess();
    for k in 0..2 {
        s.set_velocity(k, Vector3::new(0.5, 0.0, 0.0), Vector3::new(0.0, 0.0, 1.0));
    }
    s.set_velocity(2, Vector3::new(1.0, 0.0, 0.0), Vector3::zeros());
    (d, s)
}

fn run(integrator: Integrator) -> (f64, f64, usize) {
    let model = four_bar(None);
    let (mut d, s) = loaded(&model);
    let res = d
        .simulate(&s, &SimulationOptions::new(3.0, 3).integrator(integrator))
        .unwrap();
    let end = res.point("rocker0", "end").unwrap();
    let mut err: f64 = 0.0;
    for (k, &t) in res.times().iter().enumerate() {
        let phi = phi_exact(t);
        err = err.max((end.position[k] - Vector3::new(phi.cos(), phi.sin(), 0.0)).norm());
    }
    (err, res.energy.max_drift(), res.redundant.len())
}

#[test]
fn redundant_four_bar_follows_the_one_dof_model() {
    let (err, drift, redundant) = run(Integrator::Dopri5(Dopri5Options::tolerances(1e-10, 1e-12)));
    eprintln!(
        "four-bar DOPRI5: error {err:.2e}, energy drift {drift:.2e}, {redundant} redundant rows"
    );
    assert_eq!(redundant, 3);
    assert!(err < 1e-7, "{err}");
    assert!(drift < 1e-7, "{drift}");
    let (err, drift, _) = run(Integrator::GeneralizedAlpha(
        GeneralizedAlphaOptions::with_step(1e-3),
    ));
    eprintln!("four-bar generalized-α h = 1 ms: error {err:.2e}, energy drift {drift:.2e}");
    assert!(err < 1e-3, "{err}");
}

#[test]
fn redundant_four_bar_inverse_dynamics() {
    let model = four_bar(Some(TimeFunction::Polynomial(vec![-FRAC_PI_2, 1.0, 0.3])));
    let mut d = Dynamics::new(&model).unwrap();
    d.add_force(Force::gravity(Vector3::new(0.0, -G, 0.0)))
        .unwrap();
    let res = d
        .inverse_dynamics(&KinematicOptions::new(0.0, 2.0, 40))
        .unwrap();
    let motor = res.driver("motor").unwrap();
    let mut err: f64 = 0.0;
    for (k, &t) in res.times().iter().enumerate() {
        let phi = -FRAC_PI_2 + t + 0.3 * t * t;
        let torque = 5.0 / 3.0 * 0.6 + 2.0 * G * phi.cos();
        err = err.max((motor.effort[k] - torque).abs());
    }
    eprintln!(
        "driven four-bar inverse dynamics: torque error {err:.2e}, {} redundant rows",
        res.redundant.len()
    );
    assert_eq!(res.redundant.len(), 3);
    assert!(err < 1e-8, "{err}");
}

/// Modified Newton with the mass-only matrix on the redundant four-bar (3 rows dropped): the
/// same motion as full Newton to the Newton tolerance, with at most a third of the
/// factorizations (the velocity projection reuses the Newton matrix by iterative refinement).
#[test]
fn modified_newton_matches_full_newton() {
    use cardan_dynamics::IterationMatrix;
    let model = four_bar(None);
    let (mut d, s) = loaded(&model);
    let mut run = |reuse: bool| {
        let opts = SimulationOptions::new(1.0, 10).integrator(Integrator::GeneralizedAlpha(
            GeneralizedAlphaOptions {
                iteration_matrix: IterationMatrix::MassOnly,
                reuse_factorization: reuse,
                ..GeneralizedAlphaOptions::with_step(1e-4)
            },
        ));
        d.simulate(&s, &opts).unwrap()
    };
    let full = run(false);
    let modified = run(true);
    let (a, b) = (
        full.point("rocker0", "end").unwrap(),
        modified.point("rocker0", "end").unwrap(),
    );
    let diff = a
        .position
        .iter()
        .zip(&b.position)
        .map(|(x, y)| (x - y).norm())
        .fold(0.0, f64::max);
    eprintln!(
        "four-bar mass-only h = 0.1 ms: factorizations {} (full) vs {} (modified), difference {diff:.2e} m",
        full.stats.factorizations, modified.stats.factorizations
    );
    assert!(diff < 1e-9, "modified Newton differs by {diff:e} m");
    assert!(3 * modified.stats.factorizations < full.stats.factorizations);
}
