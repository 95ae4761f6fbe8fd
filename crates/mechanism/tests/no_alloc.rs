//! "No allocation inside a step": a counting global allocator wraps the system one; after
//! setup (`prepare_kinematics`), kinematic frames (position Newton + velocity + acceleration)
//! must not allocate, the first one included.
//!
//! The counter is process-wide, so this test runs without the libtest harness (`harness = false`
//! in Cargo.toml): libtest's main thread, waiting for the test thread, allocated now and then
//! while a region was open (4 allocations in about one run in twenty, none on the test
//! thread), which made the test flaky. Here `main` runs the checks on the only thread.

mod common;

use cardan_mechanism::{AssemblyOptions, Model};
use stats_alloc::{Region, StatsAlloc, INSTRUMENTED_SYSTEM};
use std::alloc::System;
use std::f64::consts::PI;

#[global_allocator]
static GLOBAL: &StatsAlloc<System> = &INSTRUMENTED_SYSTEM;

fn allocations(mut f: impl FnMut()) -> usize {
    let region = Region::new(GLOBAL);
    f();
    let stats = region.change();
    stats.allocations + stats.reallocations
}

fn frames_do_not_allocate(model: &Model, label: &str) {
    let mut ws = model.workspace();
    model
        .assemble(&mut ws, &AssemblyOptions::default())
        .unwrap();
    model.prepare_kinematics(&mut ws).unwrap();
    let dt = 1e-3;
    let mut t = 0.0;
    let frame = |ws: &mut cardan_mechanism::Workspace, t: f64| {
        model.position(ws, t).unwrap();
        model.velocity(ws).unwrap();
        model.acceleration(ws).unwrap();
    };
    // The first frame after setup too: nothing is sized lazily at the first solve.
    t += dt;
    let first = allocations(|| frame(&mut ws, t));
    assert_eq!(first, 0, "{label}: {first} allocations in the first frame");
    for _ in 0..20 {
        t += dt;
        frame(&mut ws, t);
    }
    let mut phi = vec![0.0; model.num_equations()];
    let count = allocations(|| {
        for _ in 0..200 {
            t += dt;
            frame(&mut ws, t);
            model.eval_phi(&ws, t, &mut phi);
            // Outputs read from the workspace.
            let _ = ws.omega(0) + ws.omega_dot(0);
            let _ = ws.p_ddot(0);
        }
    });
    assert!(t > 0.2);
    assert_eq!(
        count, 0,
        "{label}: {count} allocations in 200 kinematic frames"
    );
    eprintln!("{label}: 0 allocations in 200 frames");
}

/// A streamed run (`Model::kinematics_into`) allocates the same for 50 and for 500 steps: its
/// setup, never per step (the frame handed to the sink is reused).
fn streamed_runs_do_not_allocate_per_step(model: &Model, label: &str) {
    let run = |steps: usize| {
        let opts = cardan_mechanism::KinematicOptions::new(0.0, 0.5, steps);
        let mut ws = model.workspace();
        let mut frames = 0usize;
        let mut sink = |_: usize, f: &cardan_mechanism::Results| {
            frames += f.len();
            std::ops::ControlFlow::Continue(())
        };
        let count = allocations(|| {
            model.kinematics_into(&mut ws, &opts, &mut sink).unwrap();
        });
        assert_eq!(frames, steps + 1);
        count
    };
    let (short, long) = (run(50), run(500));
    assert_eq!(
        short, long,
        "{label}: {short} allocations for 50 steps, {long} for 500"
    );
    eprintln!("{label}: {short} allocations for 50 streamed steps, {long} for 500");
}

fn main() {
    kinematic_frames_do_not_allocate();
    streamed_runs_do_not_allocate_per_step(&common::slider_crank(), "slider-crank");
    let slot = common::slotted_slider_crank(2.0 * PI).build().unwrap();
    streamed_runs_do_not_allocate_per_step(&slot, "slider-crank, pin in a slot");
    println!("no_alloc: 2 passed, 0 failed");
}

fn kinematic_frames_do_not_allocate() {
    frames_do_not_allocate(&common::slider_crank(), "slider-crank");
    // Redundant: the row selection path.
    let four_bar = common::four_bar_builder(0.3, 2.0 * PI).build().unwrap();
    frames_do_not_allocate(&four_bar, "four-bar");
    // A curve parameter as extra coordinate, with redundant rows.
    let rim = common::slider_crank_on_rim(2.0 * PI);
    frames_do_not_allocate(&rim, "slider-crank, pin on a circle");
}
