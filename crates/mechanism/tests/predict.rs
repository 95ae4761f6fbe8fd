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
