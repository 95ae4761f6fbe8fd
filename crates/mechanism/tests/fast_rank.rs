//! The large-model fast path of `prepare_kinematics` (a sparse LU of the square Φ_v instead of
//! the dense rank analysis) gives the same degrees-of-freedom report as the rank analysis, and
//! the same motion.

use cardan_mechanism::{
    Body, DriverSpec, JointKind, JointSpec, MechanismBuilder, Model, TimeFunction,
    FAST_RANK_MIN_UNKNOWNS, GROUND,
};
use nalgebra::Vector3;

/// A chain of `n` rods along x, revolute joints about z and y alternately, all driven.
fn driven_chain(n: usize) -> Model {
    let mut b = MechanismBuilder::new();
    b.point(GROUND, "O", Vector3::zeros());
    for (name, v) in [
        ("x", Vector3::x()),
        ("y", Vector3::y()),
        ("z", Vector3::z()),
    ] {
        b.vector(GROUND, name, v);
    }
    for k in 0..n {
        let body = format!("b{k}");
        b.body(
            Body::new(&body)
                .mass(1.0)
                .inertia_diagonal(0.001, 0.1, 0.1)
                .position(Vector3::new(k as f64 + 0.5, 0.0, 0.0)),
        );
        b.point(&body, "a", Vector3::new(-0.5, 0.0, 0.0)).point(
            &body,
            "b",
            Vector3::new(0.5, 0.0, 0.0),
        );
        for (name, v) in [
            ("x", Vector3::x()),
            ("y", Vector3::y()),
            ("z", Vector3::z()),
        ] {
            b.vector(&body, name, v);
        }
        let prev = if k == 0 {
            (GROUND.to_string(), "O")
        } else {
            (format!("b{}", k - 1), "b")
        };
        let axis = if k % 2 == 0 { "z" } else { "y" };
        b.joint(
            JointSpec::new(
                format!("j{k}"),
                JointKind::Revolute,
                (&prev.0, prev.1),
                (&body, "a"),
            )
            .axes(axis, axis)
            .x_axes("x", "x"),
        );
        b.driver(DriverSpec::rotation(
            format!("d{k}"),
            &format!("j{k}"),
            TimeFunction::Polynomial(vec![0.0, 0.1 + 0.01 * k as f64]),
        ));
    }
    b.build().unwrap()
}

#[test]
fn fast_path_report_equals_rank_analysis() {
    let n = FAST_RANK_MIN_UNKNOWNS / 6 + 5;
    let model = driven_chain(n);
    assert!(model.num_unknowns() >= FAST_RANK_MIN_UNKNOWNS);
    let mut ws = model.workspace();
    let dense = model.dof(&ws).unwrap();
    let fast = model.prepare_kinematics(&mut ws).unwrap();
    assert_eq!(fast, dense);
    assert_eq!(fast.dof, n);
    assert!(fast.redundant.is_empty());
    // The motion: every joint angle follows its driver.
    let r = model.position(&mut ws, 0.5).unwrap();
    assert!(r.residual < 1e-9);
    model.velocity(&mut ws).unwrap();
    model.acceleration(&mut ws).unwrap();
    // Tip of the chain moves; the model stays assembled.
    let mut phi = vec![0.0; model.num_equations()];
    model.eval_phi(&ws, 0.5, &mut phi);
    assert!(phi.iter().all(|v| v.abs() < 1e-9));
}

#[test]
fn wrong_driver_count_still_reported_on_large_models() {
    let n = FAST_RANK_MIN_UNKNOWNS / 6 + 5;
    // A chain like `driven_chain` without its last driver: one DOF left free.
    let short = {
        let mut b = MechanismBuilder::new();
        b.point(GROUND, "O", Vector3::zeros())
            .vector(GROUND, "z", Vector3::z())
            .vector(GROUND, "x", Vector3::x());
        for k in 0..n {
            let body = format!("b{k}");
            b.body(
                Body::new(&body)
                    .mass(1.0)
                    .inertia_diagonal(0.001, 0.1, 0.1)
                    .position(Vector3::new(k as f64 + 0.5, 0.0, 0.0)),
            );
            b.point(&body, "a", Vector3::new(-0.5, 0.0, 0.0))
                .point(&body, "b", Vector3::new(0.5, 0.0, 0.0))
                .vector(&body, "z", Vector3::z())
                .vector(&body, "x", Vector3::x());
            let prev = if k == 0 {
                (GROUND.to_string(), "O")
            } else {
                (format!("b{}", k - 1), "b")
            };
            b.joint(
                JointSpec::new(
                    format!("j{k}"),
                    JointKind::Revolute,
                    (&prev.0, prev.1),
                    (&body, "a"),
                )
                .axes("z", "z")
                .x_axes("x", "x"),
            );
            if k + 1 < n {
                b.driver(DriverSpec::rotation(
                    format!("d{k}"),
                    &format!("j{k}"),
                    TimeFunction::Polynomial(vec![0.0, 0.1]),
                ));
            }
        }
        b.build().unwrap()
    };
    let mut ws = short.workspace();
    let e = short.prepare_kinematics(&mut ws).unwrap_err();
    assert!(
        matches!(e, cardan_mechanism::AnalysisError::DriverCount { dof, drivers } if dof == n && drivers == n - 1),
        "{e:?}"
    );
}
