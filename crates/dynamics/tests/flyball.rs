//! The stiff flyball governor (IFToMM A05: K = 8e5 N/m, C = 4e4 N s/m between the slider and
//! the rods, i.e. stiff elements between moving bodies): generalized-α at 1 ms runs stably and
//! follows the reference slider height s(t) of `shared/benchmarks/flyball_governor.csv` over the
//! first second. (The full benchmark lives with the benchmark suite.)

mod common;
use cardan_dynamics::{Dynamics, Force, GeneralizedAlphaOptions, Integrator, SimulationOptions};
use cardan_mechanism::{Body, JointKind, JointSpec, MechanismBuilder, Model, Orientation, GROUND};
use common::G;
use nalgebra::{Matrix3, Vector3};
use std::f64::consts::PI;

/// Reference s(t) [S: shared/benchmarks/README.md §2.5].
const S_REF: [(f64, f64); 3] = [(0.1, 0.523836476), (0.5, 0.743249425), (1.0, 0.501420922)];

fn flyball() -> Model {
    let mut b = MechanismBuilder::new();
    let prism = |m: f64, a: f64, bb: f64, c: f64| {
        Matrix3::from_diagonal(&Vector3::new(
            m * (bb * bb + c * c) / 12.0,
            m * (a * a + c * c) / 12.0,
            m * (a * a + bb * bb) / 12.0,
        ))
    };
    b.body(
        Body::new("shaft")
            .mass(0.3)
            .inertia(prism(0.3, 0.01, 0.01, 1.0))
            .position(Vector3::new(0.0, 0.0, 0.5)),
    );
    b.body(
        Body::new("slider")
            .mass(3.0)
            .inertia(prism(3.0, 0.1, 0.1, 0.1))
            .position(Vector3::new(0.0, 0.0, 0.5)),
    );
    b.point(GROUND, "O", Vector3::zeros())
        .vector(GROUND, "z", Vector3::z())
        .vector(GROUND, "x", Vector3::x());
    b.point("shaft", "O", Vector3::new(0.0, 0.0, -0.5))
        .point("shaft", "c", Vector3::zeros())
        .point("shaft", "A", Vector3::new(0.05, 0.0, 0.5))
        .point("shaft", "B", Vector3::new(-0.05, 0.0, 0.5))
        .vector("shaft", "z", Vector3::z())
        .vector("shaft", "x", Vector3::x())
        .vector("shaft", "y", Vector3::y());
    b.point("slider", "c", Vector3::zeros())
        .point("slider", "A", Vector3::new(0.05, 0.0, 0.0))
        .point("slider", "B", Vector3::new(-0.05, 0.0, 0.0))
        .vector("slider", "z", Vector3::z())
        .vector("slider", "x", Vector3::x());
    b.joint(
        JointSpec::new("spin", JointKind::Revolute, (GROUND, "O"), ("shaft", "O"))
            .axes("z", "z")
            .x_axes("x", "x"),
    );
    b.joint(
        JointSpec::new(
            "slide",
            JointKind::Prismatic,
            ("shaft", "c"),
            ("slider", "c"),
        )
        .axes("z", "z")
        .x_axes("x", "x"),
    );
    // Rod (0.3 kg, 1 m) plus a 5 kg point mass at its end: one body, reference at the CoM.
    let (mr, mp) = (0.3, 5.0);
    let m = mr + mp;
    let g = (mr * 0.5 + mp * 1.0) / m; // CoM distance from the hinge
    let mut j = prism(mr, 1.0, 0.01, 0.01);
    j[(1, 1)] += mr * (g - 0.5).powi(2) + mp * (1.0 - g).powi(2);
    j[(2, 2)] += mr * (g - 0.5).powi(2) + mp * (1.0 - g).powi(2);
    for (name, hinge, sign, angle) in [
        ("rodA", "A", 1.0, PI / 6.0),
        ("rodB", "B", -1.0, PI - PI / 6.0),
    ] {
        let dir = Vector3::new(sign * (PI / 6.0).cos(), 0.0, -(PI / 6.0).sin());
        let hinge_pos = Vector3::new(sign * 0.05, 0.0, 1.0);
        b.body(
            Body::new(name)
                .mass(m)
                .inertia(j)
                .position(hinge_pos + g * dir)
                .orientation(Orientation::AxisAngle {
                    axis: Vector3::y(),
                    angle,
                }),
        );
        b.point(name, "hinge", Vector3::new(-g, 0.0, 0.0))
            .point(name, "mid", Vector3::new(0.5 - g, 0.0, 0.0))
            .vector(name, "y", Vector3::y());
        b.joint(
            JointSpec::new(
                format!("hinge{hinge}"),
                JointKind::Revolute,
                ("shaft", hinge),
                (name, "hinge"),
            )
            .axes("y", "y"),
        );
    }
    b.build().unwrap()
}

/// The governor's dynamics (gravity, the two stiff spring-dampers) and its start: every body
/// spinning with the shaft at 2π rad/s.
fn loaded(model: &Model) -> (Dynamics<'_>, cardan_dynamics::State) {
    let mut d = Dynamics::new(model).unwrap();
    d.add_force(Force::gravity(Vector3::new(0.0, 0.0, -G)))
        .unwrap();
    for (side, rod) in [("A", "rodA"), ("B", "rodB")] {
        d.add_force(Force::spring_damper(
            &format!("spring{side}"),
            ("slider", side),
            (rod, "mid"),
            8e5,
            4e4,
            Some(0.5),
        ))
        .unwrap();
    }
    let mut s = d.initial_guess();
    let w = Vector3::new(0.0, 0.0, 2.0 * PI);
    for k in 0..model.num_bodies() {
        let r = s.r(k);
        s.set_velocity_global(k, w.cross(&r), w);
    }
    (d, s)
}

#[test]
fn flyball_governor_is_stable_with_generalized_alpha() {
    let model = flyball();
    let (mut d, s) = loaded(&model);
    let times = std::iter::once(0.0)
        .chain(S_REF.iter().map(|r| r.0))
        .collect();
    let opts = SimulationOptions::new(1.0, 1)
        .output_times(times)
        .integrator(Integrator::GeneralizedAlpha(
            GeneralizedAlphaOptions::with_step(1e-3),
        ));
    let res = d.simulate(&s, &opts).unwrap();
    let slider = res.body("slider").unwrap();
    let mut err: f64 = 0.0;
    for (k, (_, s_ref)) in S_REF.iter().enumerate() {
        err = err.max((slider.r[k + 1].z - s_ref).abs());
    }
    eprintln!(
        "flyball gen-α h = 1 ms: max |s − s_ref| = {err:.2e} m, {} steps, {} Newton iterations, {:.2e} s/step, energy {:.6} → {:.6} J",
        res.stats.steps,
        res.stats.newton_iterations,
        res.stats.wall_time / res.stats.steps as f64,
        res.energy.total[0],
        res.energy.total.last().unwrap()
    );
    assert!(err < 1e-3, "{err}");
}

/// Modified Newton (the default: factorizations kept across iterations, steps and velocity
/// projections while the iteration contracts) reaches the same motion as full Newton (a
/// factorization at every iteration) with far fewer factorizations, on a stiff model with the
/// tangent iteration matrix and with the mass-only-then-tangent one. "The same" means: the two
/// differ by less than 2 % of the step's own discretization error (estimated against a run at
/// h/2), so the Newton stopping test never decides the accuracy of a run.
#[test]
fn modified_newton_matches_full_newton_with_fewer_factorizations() {
    use cardan_dynamics::IterationMatrix;
    let model = flyball();
    let (mut d, s) = loaded(&model);
    let bodies = ["slider", "rodA", "rodB"];
    let max_diff = |a: &cardan_dynamics::DynamicResults, b: &cardan_dynamics::DynamicResults| {
        let mut diff: f64 = 0.0;
        for name in bodies {
            let (a, b) = (a.body(name).unwrap(), b.body(name).unwrap());
            for (x, y) in a.r.iter().zip(&b.r) {
                diff = diff.max((x - y).norm());
            }
        }
        diff
    };
    for matrix in [
        IterationMatrix::Tangent,
        IterationMatrix::MassOnlyThenTangent,
    ] {
        let mut run = |reuse: bool, h: f64| {
            let opts = SimulationOptions::new(0.3, 30).integrator(Integrator::GeneralizedAlpha(
                GeneralizedAlphaOptions {
                    iteration_matrix: matrix,
                    reuse_factorization: reuse,
                    ..GeneralizedAlphaOptions::with_step(h)
                },
            ));
            d.simulate(&s, &opts).unwrap()
        };
        let full = run(false, 1e-3);
        let modified = run(true, 1e-3);
        let half = run(false, 5e-4);
        let diff = max_diff(&full, &modified);
        let step_error = max_diff(&full, &half);
        eprintln!(
            "flyball {matrix:?}: full Newton {} factorizations, modified {} ({} iterations vs {}), max position difference {diff:.2e} m, discretization error {step_error:.2e} m",
            full.stats.factorizations,
            modified.stats.factorizations,
            full.stats.newton_iterations,
            modified.stats.newton_iterations
        );
        assert!(
            diff < 0.02 * step_error,
            "{matrix:?}: modified Newton differs by {diff:e} m, discretization error {step_error:e} m"
        );
        assert_eq!(modified.stats.rejected, 0);
        assert!(modified.stats.factorizations < full.stats.factorizations);
    }
}
