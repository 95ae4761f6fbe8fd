//! `Model::predict_poses`: the time grid's Taylor predictor for callers that step frames
//! themselves. Same converged poses, fewer Newton iterations.

mod common;

use cardan_mechanism::{AssemblyOptions, DriverSpec, TimeFunction};

#[test]
fn predicted_frames_converge_to_the_same_poses_in_fewer_iterations() {
    let model = common::slider_crank();
    let run = |predict: bool| {
        let mut ws = model.workspace();
        model
            .assemble(&mut ws, &AssemblyOptions::default())
            .unwrap();
        model.prepare_kinematics(&mut ws).unwrap();
        let mut iterations = 0;
        let dt = 0.01;
        for k in 1..=100 {
            let t = k as f64 * dt;
            if predict {
                let dt = t - ws.time();
                model.predict_poses(&mut ws, dt);
            }
            iterations += model.position(&mut ws, t).unwrap().iterations;
            model.velocity(&mut ws).unwrap();
            model.acceleration(&mut ws).unwrap();
        }
        (iterations, ws.state().to_vec())
    };
    let (plain, x_plain) = run(false);
    let (predicted, x_predicted) = run(true);
    assert!(predicted < plain, "{predicted} vs {plain} iterations");
    for (a, b) in x_plain.iter().zip(&x_predicted) {
        assert!((a - b).abs() < 1e-8, "{a} vs {b}");
    }
    // Without valid velocities the predictor does nothing.
    let mut ws = model.workspace();
    let before = ws.state().to_vec();
    model.predict_poses(&mut ws, 0.1);
    assert_eq!(ws.state(), &before[..]);
}

/// Velocities and accelerations of frames stepped with the predictor (chord iterations with the
/// previous frame's factors, iterative refinement when the frame ends near a refactorization)
/// equal those of a fresh factorization at the same poses, to 1e-12 relative, for the
/// slider-crank and Bricard's linkage at several frame rates.
#[test]
fn reused_factorizations_give_the_velocities_and_accelerations_of_fresh_ones() {
    let mut bricard = common::bricard_builder();
    bricard.driver(DriverSpec::rotation(
        "swing",
        "A",
        TimeFunction::Harmonic {
            amplitude: -0.3,
            frequency: 2.0 * std::f64::consts::PI,
            phase: std::f64::consts::PI / 2.0,
            offset: 0.3,
        },
    ));
    let models = [common::slider_crank(), bricard.build().unwrap()];
    for model in &models {
        for dt in [0.002, 0.01, 0.05] {
            let mut ws = model.workspace();
            model
                .assemble(&mut ws, &AssemblyOptions::default())
                .unwrap();
            model.prepare_kinematics(&mut ws).unwrap();
            let mut fresh = model.workspace();
            model
                .assemble(&mut fresh, &AssemblyOptions::default())
                .unwrap();
            model.prepare_kinematics(&mut fresh).unwrap();
            for k in 1..=60 {
                let t = k as f64 * dt;
                let step = t - ws.time();
                model.predict_poses(&mut ws, step);
                model.position(&mut ws, t).unwrap();
                model.velocity(&mut ws).unwrap();
                model.acceleration(&mut ws).unwrap();
                // Reference: the same poses, a fresh factorization (set_pose drops the old one).
                for b in 0..model.num_bodies() {
                    fresh.set_pose(b, ws.r(b), ws.p(b));
                }
                fresh.set_time(t);
                model.velocity(&mut fresh).unwrap();
                model.acceleration(&mut fresh).unwrap();
                let close = |a: &[f64], b: &[f64], what: &str| {
                    let scale = b.iter().fold(0.0f64, |m, v| m.max(v.abs())).max(1e-300);
                    for (x, y) in a.iter().zip(b) {
                        assert!(
                            (x - y).abs() <= 1e-12 * scale,
                            "{what} at t = {t} (dt = {dt}): {x} vs {y}"
                        );
                    }
                };
                close(ws.velocities(), fresh.velocities(), "velocity");
                close(ws.accelerations(), fresh.accelerations(), "acceleration");
            }
        }
    }
}

/// An open chain of `n` rods of length 1 along x, joint k a revolute about z (k even) or y
/// (k odd), turned by `drive(k)`; with `slide`, cylindrical joints instead, whose slides along
/// the axes follow `slide(k)` (then the joint points part, and the predictor's translation
/// terms are exercised).
fn driven_chain(
    n: usize,
    drive: impl Fn(usize) -> TimeFunction,
    slide: Option<&dyn Fn(usize) -> TimeFunction>,
) -> cardan_mechanism::Model {
    use cardan_mechanism::{Body, JointKind, JointSpec, MechanismBuilder, GROUND};
    use nalgebra::Vector3;
    let mut b = MechanismBuilder::new();
    b.point(GROUND, "O", Vector3::zeros());
    for body in std::iter::once(GROUND.to_string()).chain((0..n).map(|k| format!("b{k}"))) {
        b.vector(&body, "x", Vector3::x())
            .vector(&body, "y", Vector3::y())
            .vector(&body, "z", Vector3::z());
    }
    for k in 0..n {
        let name = format!("b{k}");
        b.body(
            Body::new(&name)
                .mass(1.0)
                .inertia_diagonal(0.001, 1.0 / 12.0, 1.0 / 12.0)
                .position(Vector3::new(k as f64 + 0.5, 0.0, 0.0)),
        );
        b.point(&name, "a", Vector3::new(-0.5, 0.0, 0.0)).point(
            &name,
            "b",
            Vector3::new(0.5, 0.0, 0.0),
        );
        let (pb, pp) = if k == 0 {
            (GROUND.to_string(), "O")
        } else {
            (format!("b{}", k - 1), "b")
        };
        let axis = if k % 2 == 0 { "z" } else { "y" };
        let j = format!("j{k}");
        let kind = if slide.is_some() {
            JointKind::Cylindrical
        } else {
            JointKind::Revolute
        };
        b.joint(
            JointSpec::new(&j, kind, (&pb, pp), (&name, "a"))
                .axes(axis, axis)
                .x_axes("x", "x"),
        );
        b.driver(DriverSpec::rotation(format!("d{k}"), &j, drive(k)));
        if let Some(f) = slide {
            b.driver(DriverSpec::translation(format!("s{k}"), &j, f(k)));
        }
    }
    b.build().unwrap()
}

/// Frames every `dt` from the assembled poses at 0 up to t = `frames` · dt (positions,
/// velocities, accelerations), then the prediction at t + dt; returns it with the converged
/// poses at t + dt, solved in a second workspace from the poses at t (not from the prediction,
/// which Newton may accept as it is), and the iterations of the solve from the prediction.
fn predicted_and_solved(
    model: &cardan_mechanism::Model,
    frames: usize,
    dt: f64,
) -> (Vec<f64>, Vec<f64>, usize) {
    let run = |ws: &mut cardan_mechanism::Workspace| {
        model.assemble(ws, &AssemblyOptions::at(0.0)).unwrap();
        model.prepare_kinematics(ws).unwrap();
        for k in 1..=frames {
            model.position(ws, k as f64 * dt).unwrap();
            model.velocity(ws).unwrap();
            model.acceleration(ws).unwrap();
        }
    };
    let (mut ws, mut reference) = (model.workspace(), model.workspace());
    run(&mut ws);
    run(&mut reference);
    let t = (frames + 1) as f64 * dt;
    model.predict_poses(&mut ws, dt);
    let predicted = ws.state().to_vec();
    let iterations = model.position(&mut ws, t).unwrap().iterations;
    model.position(&mut reference, t).unwrap();
    (predicted, reference.state().to_vec(), iterations)
}

fn max_difference(a: &[f64], b: &[f64]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(x, y)| (x - y).abs())
        .fold(0.0, f64::max)
}

/// Every joint of a 100-link chain turns at 0.1 rad/s, so the last links turn at up to about
/// 0.07 · 100 = 7 rad/s absolutely, but each relative to its neighbour at a constant rate: the
/// predictor, which predicts each link relative to its parent, is exact for any frame step and
/// the position solve does not iterate. (The absolute Taylor step of each link missed by
/// 6.5e-4 here and took 4 iterations.)
#[test]
fn uniformly_turning_joints_of_a_long_chain_are_predicted_exactly() {
    let model = driven_chain(100, |_| TimeFunction::Polynomial(vec![0.0, 0.1]), None);
    for (frames, dt) in [(10, 0.02), (5, 0.1)] {
        let (predicted, solved, iterations) = predicted_and_solved(&model, frames, dt);
        let e = max_difference(&predicted, &solved);
        assert!(e < 1e-9, "dt = {dt}: prediction off by {e:e}");
        assert_eq!(iterations, 0, "dt = {dt}");
    }
}

/// With joints that turn (and slide) non-uniformly, by harmonic drivers of different
/// frequencies, the relative prediction is fourth order: halving the frame step divides its
/// error by about 16.
#[test]
fn the_prediction_of_a_chain_with_harmonic_joints_is_fourth_order() {
    let turn = |k: usize| TimeFunction::Harmonic {
        amplitude: 0.4,
        frequency: 2.0 + 0.1 * k as f64,
        phase: 0.3 * k as f64,
        offset: 0.0,
    };
    let slide = |k: usize| TimeFunction::Harmonic {
        amplitude: 0.2,
        frequency: 1.5 + 0.1 * k as f64,
        phase: 0.7 * k as f64,
        offset: 0.1,
    };
    for model in [
        driven_chain(30, turn, None),
        driven_chain(30, turn, Some(&slide)),
    ] {
        fourth_order(&model);
    }
}

fn fourth_order(model: &cardan_mechanism::Model) {
    let errors: Vec<f64> = [(15, 0.04), (30, 0.02), (60, 0.01)]
        .iter()
        .map(|&(frames, dt)| {
            let (predicted, solved, _) = predicted_and_solved(model, frames, dt);
            max_difference(&predicted, &solved)
        })
        .collect();
    for w in errors.windows(2) {
        let ratio = w[0] / w[1];
        assert!(
            (12.0..20.0).contains(&ratio),
            "errors {errors:?}: ratio {ratio}"
        );
    }
}
