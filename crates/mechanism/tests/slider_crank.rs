//! Haug's spatial slider-crank (benchmark README §2.6) against its closed form.
//!
//! With the crank angle θ = 2π t (driven), B = A + 0.08 (0, −sin θ, cos θ), C = (x, 0, 0) and
//! |C − B| = 0.3:
//!
//! ```text
//! x(θ)² = 0.09 − (0.1 − 0.08 sin θ)² − (0.12 + 0.08 cos θ)²          (x > 0)
//! x x'  = 0.008 cos θ + 0.0096 sin θ
//! x'² + x x'' = −0.008 sin θ + 0.0096 cos θ
//! ẋ = x' θ̇,   ẍ = x'' θ̇²    (θ̇ = 2π, θ̈ = 0)
//! ```
//!
//! (the ±0.0064 sin θ cos θ terms cancel in x x'). At θ = 0: x = 0.2, x' = 0.04, so with the
//! benchmark's θ̇ = 6 the slider moves at 0.24 m/s, as published.

mod common;

use cardan_mechanism::{KinematicOptions, Outputs};
use common::{slider_crank, slider_crank_builder, slider_x};
use nalgebra::Vector3;
use std::f64::consts::PI;

#[test]
fn dof_is_one_without_redundancy() {
    let model = slider_crank();
    let ws = model.workspace();
    let dof = model.dof(&ws).unwrap();
    assert_eq!(dof.dof, 1, "{dof}");
    assert_eq!(dof.joint_equations, 17);
    assert_eq!(dof.rank, 17);
    assert!(dof.redundant.is_empty());
}

#[test]
fn positions_velocities_accelerations_match_closed_form() {
    let model = slider_crank();
    let omega = 2.0 * PI;
    let results = model
        .run_kinematics(&KinematicOptions::new(0.0, 2.0, 400))
        .unwrap();
    let slider = results.body("slider").unwrap();
    let (mut ex, mut ev, mut ea) = (0.0f64, 0.0f64, 0.0f64);
    for (k, &t) in results.times.iter().enumerate() {
        let (x, x1, x2) = slider_x(omega * t);
        ex = ex.max((slider.r[k] - Vector3::new(x, 0.0, 0.0)).norm());
        ev = ev.max((slider.r_dot[k] - Vector3::new(x1 * omega, 0.0, 0.0)).norm());
        ea = ea.max((slider.r_ddot[k] - Vector3::new(x2 * omega * omega, 0.0, 0.0)).norm());
    }
    let max_it = results.iterations.iter().max().unwrap();
    let max_res = results.residual.iter().cloned().fold(0.0, f64::max);
    eprintln!(
        "slider-crank, 401 steps over 2 s: max |x − x_exact| = {ex:.2e} m, |v − v_exact| = {ev:.2e} m/s, \
         |a − a_exact| = {ea:.2e} m/s², max Newton iterations {max_it}, max residual {max_res:.2e}"
    );
    assert!(ex < 1e-10, "position error {ex}");
    assert!(ev < 1e-9, "velocity error {ev}");
    assert!(ea < 1e-8, "acceleration error {ea}");
    assert!(*max_it <= 4);
    // The crank angle is unwrapped over the two turns.
    let angle = &results.joint("A").unwrap().values;
    assert!((angle[400][0] - 4.0 * PI).abs() < 1e-9, "{}", angle[400][0]);
    // Point B follows the crank circle.
    let b = results.point("crank", "B").unwrap();
    for (k, &t) in results.times.iter().enumerate() {
        let th = omega * t;
        let want = Vector3::new(0.0, 0.1 - 0.08 * th.sin(), 0.12 + 0.08 * th.cos());
        assert!((b.position[k] - want).norm() < 1e-10);
    }
}

#[test]
fn conrod_angular_velocity_matches_the_benchmark() {
    // The benchmark gives ω_conrod = (1.92, −0.96, 0.48) for θ̇ = 6; the velocity problem is
    // linear in θ̇.
    let model = slider_crank_builder(6.0).build().unwrap();
    let results = model
        .run_kinematics(&KinematicOptions::new(0.0, 0.0, 0))
        .unwrap();
    let w = results.body("conrod").unwrap().omega[0];
    eprintln!("conrod ω at t = 0: {w:?}");
    assert!(
        (w - Vector3::new(1.92, -0.96, 0.48)).norm() < 1e-12,
        "{w:?}"
    );
    let v = results.body("slider").unwrap().r_dot[0];
    assert!((v - Vector3::new(0.24, 0.0, 0.0)).norm() < 1e-12);
    let vc = results.body("conrod").unwrap().r_dot[0];
    assert!(
        (vc - Vector3::new(0.12, -0.24, 0.0)).norm() < 1e-12,
        "{vc:?}"
    );
}

/// Central differences of the position history approximate the computed velocities (and of the
/// velocity history the accelerations) with error O(h²): halving h divides it by 4.
#[test]
fn finite_differences_of_the_history_converge_at_second_order() {
    let model = slider_crank();
    let fd_errors = |steps: usize| {
        let r = model
            .run_kinematics(&KinematicOptions::new(0.0, 0.5, steps))
            .unwrap();
        let h = 0.5 / steps as f64;
        let (mut ev, mut ea) = (0.0f64, 0.0f64);
        for b in &r.bodies {
            for k in 1..steps {
                let v_fd = (b.r[k + 1] - b.r[k - 1]) / (2.0 * h);
                ev = ev.max((v_fd - b.r_dot[k]).norm());
                let a_fd = (b.r_dot[k + 1] - b.r_dot[k - 1]) / (2.0 * h);
                ea = ea.max((a_fd - b.r_ddot[k]).norm());
                // ω from the Euler parameters: ω' = 2 L ṗ with ṗ by central differences.
                let p_fd = (b.p[k + 1] - b.p[k - 1]) / (2.0 * h);
                let w_fd = 2.0 * cardan_eulerparam::l(&b.p[k]) * p_fd;
                ev = ev.max((w_fd - b.omega_local[k]).norm() * 0.1);
                let wd_fd = (b.omega_local[k + 1] - b.omega_local[k - 1]) / (2.0 * h);
                ea = ea.max((wd_fd - b.omega_dot_local[k]).norm() * 0.1);
            }
        }
        (ev, ea)
    };
    let (v1, a1) = fd_errors(100);
    let (v2, a2) = fd_errors(200);
    let (rv, ra) = (v1 / v2, a1 / a2);
    eprintln!(
        "FD check: h = 5e-3: velocity {v1:.3e}, acceleration {a1:.3e}; h = 2.5e-3: {v2:.3e}, {a2:.3e}; \
         ratios {rv:.3}, {ra:.3} (expected 4)"
    );
    assert!((3.6..4.4).contains(&rv), "velocity FD ratio {rv}");
    assert!((3.6..4.4).contains(&ra), "acceleration FD ratio {ra}");
}

#[test]
fn position_only_run_stores_no_velocities() {
    let model = slider_crank();
    let r = model
        .run_kinematics(&KinematicOptions::new(0.0, 1.0, 100).outputs(Outputs::position_only()))
        .unwrap();
    let s = r.body("slider").unwrap();
    assert_eq!(s.r.len(), 101);
    assert!(s.r_dot.is_empty() && s.r_ddot.is_empty());
    let mut e = 0.0f64;
    for (k, &t) in r.times.iter().enumerate() {
        e = e.max((s.r[k].x - slider_x(2.0 * PI * t).0).abs());
    }
    // Linear extrapolation as predictor: still a handful of iterations.
    let max_it = *r.iterations.iter().max().unwrap();
    eprintln!("position-only: max error {e:.2e}, max iterations {max_it}");
    assert!(e < 1e-10);
    assert!(max_it <= 5);
}

/// Only what a run asks for is computed: a position-only run evaluates ν once (the velocities
/// before its first step, for the substeps that keep each joint's turn per step small; later
/// steps use the last step's rotation) and never γ#, a velocity run never γ#, and a full run
/// each once per step.
#[test]
fn analyses_evaluate_only_what_was_requested() {
    let model = slider_crank();
    let steps = 50;
    let cases = [
        (Outputs::position_only(), 1, 0),
        (Outputs::with_velocity(), steps + 1, 0),
        (Outputs::default(), steps + 1, steps + 1),
    ];
    for (outputs, nu, gamma) in cases {
        let mut ws = model.workspace();
        model
            .kinematics(
                &mut ws,
                &KinematicOptions::new(0.0, 1.0, steps as usize).outputs(outputs),
            )
            .unwrap();
        let c = ws.evaluation_counts();
        assert_eq!((c.nu, c.gamma), (nu, gamma), "{outputs:?}");
    }
}

#[test]
fn assembly_from_a_rough_guess() {
    // Move every body away from the consistent pose; assembly brings them back.
    let model = slider_crank();
    let mut ws = model.workspace();
    ws.set_pose(
        1,
        Vector3::new(0.12, 0.03, 0.12),
        nalgebra::Vector4::new(0.9, 0.1, -0.2, 0.3),
    );
    ws.set_pose(
        2,
        Vector3::new(0.25, 0.01, -0.01),
        nalgebra::Vector4::new(1.0, 0.0, 0.05, 0.0),
    );
    let rep = model
        .assemble(&mut ws, &cardan_mechanism::AssemblyOptions::default())
        .unwrap();
    let mut phi = vec![0.0; model.num_equations()];
    model.eval_phi(&ws, 0.0, &mut phi);
    let res = phi.iter().fold(0.0f64, |a, v| a.max(v.abs()));
    eprintln!("assembly: {rep:?}, residual {res:.2e}");
    assert!(res < 1e-11);
    assert!((ws.r(2).x - 0.2).abs() < 1e-10);
}

#[test]
fn velocity_only_run_and_dt_grid() {
    let model = slider_crank();
    let opts = KinematicOptions::with_dt(0.0, 0.5, 0.01).outputs(Outputs::with_velocity());
    assert_eq!(opts.steps, 50);
    let r = model.run_kinematics(&opts).unwrap();
    assert_eq!(r.len(), 51);
    assert!((r.times[50] - 0.5).abs() < 1e-15);
    let s = r.body("slider").unwrap();
    assert_eq!(s.r_dot.len(), 51);
    assert!(s.r_ddot.is_empty());
    for (k, &t) in r.times.iter().enumerate() {
        let (_, x1, _) = slider_x(2.0 * PI * t);
        assert!((s.r_dot[k].x - 2.0 * PI * x1).abs() < 1e-10);
    }
    assert_eq!(KinematicOptions::with_dt(0.0, 0.0, 0.01).steps, 0);
    let mut seen = Vec::new();
    let mut ws = model.workspace();
    model
        .kinematics_with_progress(&mut ws, &KinematicOptions::new(0.0, 0.1, 4), |k, t| {
            seen.push((k, t))
        })
        .unwrap();
    assert_eq!(seen.len(), 5);
    assert_eq!(seen[4], (4, 0.1));
    assert!(model
        .run_kinematics(&KinematicOptions::with_dt(0.0, 1.0, -0.1))
        .is_err());
}

/// A crank turning 0.6 of a turn (3.8 rad, more than π) between two outputs: the joint angle
/// written is continued with the rates (trapezoidal prediction), not by the nearest-value rule
/// that needs less than half a turn per output (which would count the turn backwards).
#[test]
fn joint_angles_are_continued_over_more_than_half_a_turn_per_output() {
    let model = slider_crank_builder(2.0 * PI * 30.0).build().unwrap();
    let res = model
        .run_kinematics(&KinematicOptions::new(0.0, 2.0, 100))
        .unwrap();
    let crank = &res.joint("A").unwrap().values;
    for (k, &t) in res.times.iter().enumerate() {
        let want = 2.0 * PI * 30.0 * t;
        assert!(
            (crank[k][0] - want).abs() < 1e-9,
            "t = {t}: {} vs {want}",
            crank[k][0]
        );
    }
}
