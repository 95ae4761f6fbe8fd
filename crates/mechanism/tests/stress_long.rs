//! Stress: long kinematic run — 10⁶ frames of Haug's slider-crank driven at 2π rad/s (10⁴ crank
//! turns, 100 frames per turn), position + velocity + acceleration at every frame, each frame
//! starting from the previous one (no reassembly). Normalization, constraint residual and the
//! error against the closed form must stay bounded (no drift); the measured bounds are printed
//! as `STRESS <name> <value>` lines for `cargo xtask stress`.
//!
//! `#[ignore]`d: run by `cargo xtask stress` (release build) or
//! `cargo test --release -p cardan-mechanism --test stress_long -- --ignored --nocapture`.
//! `CARDAN_STRESS_FRAMES` overrides the frame count.

mod common;

use cardan_mechanism::AssemblyOptions;
use std::f64::consts::PI;
use std::time::Instant;

#[test]
#[ignore = "long run (10⁶ frames): cargo xtask stress"]
fn million_frames_of_a_driven_slider_crank() {
    let frames: usize = std::env::var("CARDAN_STRESS_FRAMES")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(1_000_000);
    let per_turn = 100usize;
    let model = common::slider_crank();
    let mut ws = model.workspace();
    model
        .assemble(&mut ws, &AssemblyOptions::default())
        .unwrap();
    model.prepare_kinematics(&mut ws).unwrap();
    let slider = 2; // body order: crank, conrod, slider
    let start = Instant::now();
    let (mut norm, mut residual, mut closed, mut vel, mut iterations) =
        (0.0f64, 0.0f64, 0.0f64, 0.0f64, 0usize);
    let mut first_turn_closed = 0.0f64;
    for k in 1..=frames {
        let t = k as f64 / per_turn as f64;
        let rep = model
            .position(&mut ws, t)
            .unwrap_or_else(|e| panic!("frame {k}: {e}"));
        model.velocity(&mut ws).unwrap();
        model.acceleration(&mut ws).unwrap();
        iterations += rep.iterations;
        residual = residual.max(rep.residual);
        for b in 0..3 {
            norm = norm.max((ws.p(b).norm() - 1.0).abs());
        }
        let theta = 2.0 * PI * t;
        let (x, dx, _) = common::slider_x(theta);
        let e = (ws.r(slider).x - x).abs();
        closed = closed.max(e);
        vel = vel.max((ws.r_dot(slider).x - 2.0 * PI * dx).abs());
        if k <= per_turn {
            first_turn_closed = first_turn_closed.max(e);
        }
        assert!(ws.state().iter().all(|v| v.is_finite()), "frame {k}");
    }
    let wall = start.elapsed().as_secs_f64();
    println!("STRESS kinematic_frames {frames}");
    println!("STRESS kinematic_turns {}", frames / per_turn);
    println!("STRESS kinematic_wall_s {wall:.2}");
    println!(
        "STRESS kinematic_newton_iterations_per_frame {:.3}",
        iterations as f64 / frames as f64
    );
    println!("STRESS kinematic_max_normalization_error {norm:.3e}");
    println!("STRESS kinematic_max_constraint_residual_m {residual:.3e}");
    println!("STRESS kinematic_max_position_error_vs_closed_form_m {closed:.3e}");
    println!("STRESS kinematic_first_turn_position_error_m {first_turn_closed:.3e}");
    println!("STRESS kinematic_max_velocity_error_vs_closed_form_m_per_s {vel:.3e}");
    assert!(norm < 1e-13, "normalization {norm:e}");
    assert!(residual < 1e-10, "residual {residual:e}");
    assert!(closed < 1e-9, "closed form {closed:e}");
    assert!(vel < 1e-8, "velocity {vel:e}");
}
