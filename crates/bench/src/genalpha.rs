//! Generalized-α over a developing motion (issue 25): the N-link spherical chain released from
//! rest under gravity, integrated for `t_end` with a fixed step, the cost and the Newton
//! iterations per step in each of `intervals` equal slices of the run, and the error of the
//! chain's first and last link ends against a DOPRI5 reference (rtol 1e-10) at the slices' ends.
//!
//! ```text
//! cardan-bench --genalpha N T_END H [mass|tangent] [INTERVALS] [--no-reference] [noproj]
//! ```
//!
//! The time of a slice is the wall time between the progress callbacks at its first and last
//! steps (so the recording of the outputs is left out); the whole run's time includes
//! everything (`simulate_consistent`, consistent initial accelerations included).

use crate::models;
use cardan_dynamics::{
    Dopri5Options, Dynamics, Force, GeneralizedAlphaOptions, Integrator, IterationMatrix,
    SimulationOptions, State,
};
use cardan_mechanism::{Model, Outputs};
use nalgebra::Vector3;
use std::fmt::Write as _;
use std::ops::ControlFlow;
use std::time::Instant;

/// One run: the output times, the first and last link ends at them, Newton iterations per
/// slice, wall time per slice, the whole time, steps and factorizations.
struct Run {
    times: Vec<f64>,
    tip: Vec<Vector3<f64>>,
    b0: Vec<Vector3<f64>>,
    iterations: Vec<usize>,
    slice_wall: Vec<f64>,
    wall: f64,
    steps: usize,
    factorizations: usize,
}

fn run(model: &Model, t_end: f64, intervals: usize, integ: Integrator) -> Run {
    let mut d = Dynamics::new(model).expect("dynamics");
    d.add_force(Force::gravity(Vector3::new(0.0, 0.0, -9.81)))
        .expect("gravity");
    let s = State::initial(model, 0.0);
    let times: Vec<f64> = (1..=intervals)
        .map(|k| t_end * k as f64 / intervals as f64)
        .collect();
    let opts = SimulationOptions::new(t_end, intervals)
        .integrator(integ)
        .output_times(times.clone())
        .outputs(Outputs::position_only());
    let t0 = Instant::now();
    d.prepare(&s).expect("prepare");
    // Wall clock at the first step of each slice.
    let mut starts = vec![f64::NAN; intervals + 1];
    let mut last = 0.0f64;
    let r = d
        .simulate_consistent_with_progress(s, &opts, |t| {
            let k = ((t / t_end * intervals as f64) + 1e-9).floor() as usize;
            let now = t0.elapsed().as_secs_f64();
            if k < starts.len() && starts[k].is_nan() {
                starts[k] = now;
            }
            last = now;
            ControlFlow::Continue(())
        })
        .expect("simulate");
    let wall = t0.elapsed().as_secs_f64();
    starts[intervals] = last;
    let n = model.num_bodies();
    let tip = r
        .kinematics
        .point(&format!("b{}", n - 1), "b")
        .expect("tip")
        .position
        .clone();
    let b0 = r.kinematics.point("b0", "b").expect("b0").position.clone();
    let k0 = r.kinematics.times.len() - intervals;
    Run {
        times: r.kinematics.times[k0..].to_vec(),
        tip: tip[k0..].to_vec(),
        b0: b0[k0..].to_vec(),
        iterations: r.kinematics.iterations[k0..].to_vec(),
        slice_wall: starts.windows(2).map(|w| w[1] - w[0]).collect(),
        wall,
        steps: r.stats.steps,
        factorizations: r.stats.factorizations,
    }
}

/// `--genalpha N T_END H [mass|tangent] [INTERVALS] [--no-reference] [noproj]`: the table to stdout.
pub fn main(args: &[String]) {
    let num = |k: usize, d: f64| args.get(k).and_then(|s| s.parse().ok()).unwrap_or(d);
    let n = num(0, 1000.0) as usize;
    let t_end = num(1, 1.0);
    let h = num(2, 1e-3);
    let matrix = match args.get(3).map(String::as_str) {
        Some("tangent") => IterationMatrix::Tangent,
        _ => IterationMatrix::MassOnly,
    };
    let intervals = num(4, 10.0) as usize;
    let reference = !args.iter().any(|a| a == "--no-reference");
    let model = models::spherical_chain(n);
    let ga = run(
        &model,
        t_end,
        intervals,
        Integrator::GeneralizedAlpha(GeneralizedAlphaOptions {
            iteration_matrix: matrix,
            rho_inf: 0.8,
            project_velocities: !args.iter().any(|a| a == "noproj"),
            ..GeneralizedAlphaOptions::with_step(h)
        }),
    );
    let refr = reference.then(|| {
        run(
            &model,
            t_end,
            intervals,
            Integrator::Dopri5(Dopri5Options::tolerances(1e-10, 1e-12)),
        )
    });
    let steps_per_slice = (t_end / h / intervals as f64).round();
    let mut md = String::new();
    let _ = writeln!(
        md,
        "chain N = {n}, gen-α {matrix:?} h = {h:e}, ρ∞ 0.8, {t_end} s: whole run {:.3} s, {} steps, \
         {} factorizations ({:.2} per step)\n\n\
         | slice end [s] | ms per step | iterations per step | error [m] |\n|---:|---:|---:|---:|",
        ga.wall,
        ga.steps,
        ga.factorizations,
        ga.factorizations as f64 / ga.steps as f64
    );
    let mut emax = 0.0f64;
    for k in 0..intervals {
        let err = refr.as_ref().map_or(f64::NAN, |r| {
            (ga.tip[k] - r.tip[k])
                .norm()
                .max((ga.b0[k] - r.b0[k]).norm())
        });
        emax = emax.max(err);
        let _ = writeln!(
            md,
            "| {:.3} | {:.3} | {:.2} | {:.2e} |",
            ga.times[k],
            1e3 * ga.slice_wall[k] / steps_per_slice,
            ga.iterations[k] as f64 / steps_per_slice,
            err
        );
    }
    let _ = writeln!(
        md,
        "\nmax error {emax:.2e} m; mean {:.3} ms per step",
        1e3 * ga.wall / ga.steps as f64
    );
    let at_end = |r: &Run| {
        let (b0, tip) = (r.b0[intervals - 1], r.tip[intervals - 1]);
        format!(
            "b0 end ({:.12}, {:.12}, {:.12}), tip ({:.12}, {:.12}, {:.12})",
            b0.x, b0.y, b0.z, tip.x, tip.y, tip.z
        )
    };
    let _ = writeln!(md, "gen-α at {t_end} s: {}", at_end(&ga));
    if let Some(r) = refr {
        let _ = writeln!(md, "(reference: DOPRI5 rtol 1e-10, {:.1} s)", r.wall);
        let _ = writeln!(md, "reference at {t_end} s: {}", at_end(&r));
    }
    println!("{md}");
}

/// `--genalpha-sc H T_END [RHO] [noproj] [mass]`: the IFToMM spatial slider-crank
/// (`examples/slider_crank_dynamic.toml`) with generalized-α at step H for T_END: wall time,
/// steps, Newton iterations, factorizations and the error against the reference table (the
/// max over its samples of |C − (x_ref, 0, 0)| and |B − B_ref(θ_ref)|, as the peer comparison
/// and `tests/tests/benchmark_slider_crank.rs`). One line to stdout.
pub fn slider_crank(args: &[String], root: &std::path::Path) {
    let num = |k: usize, d: f64| args.get(k).and_then(|s| s.parse().ok()).unwrap_or(d);
    let h = num(0, 1e-3);
    let t_end = num(1, 5.0);
    let rho = num(2, 0.9);
    let proj = !args.iter().any(|a| a == "noproj");
    let matrix = if args.iter().any(|a| a == "mass") {
        IterationMatrix::MassOnly
    } else {
        IterationMatrix::Tangent
    };
    let csv = std::fs::read_to_string(
        root.join("tests/data/benchmarks/spatial_slider_crank_crankCoM_mid.csv"),
    )
    .expect("reference table");
    let reference: Vec<[f64; 3]> = csv
        .lines()
        .filter(|l| !l.trim().is_empty() && !l.starts_with('#'))
        .filter_map(|l| {
            let v: Vec<f64> = l.split(',').filter_map(|x| x.trim().parse().ok()).collect();
            v.get(..3).map(|r| [r[0], r[1], r[2]])
        })
        .filter(|r| r[0] <= t_end + 1e-9)
        .collect();
    let p = cardan_model::prepare::prepare(&root.join("examples/slider_crank_dynamic.toml"))
        .expect("slider_crank_dynamic.toml");
    let integ = Integrator::GeneralizedAlpha(GeneralizedAlphaOptions {
        iteration_matrix: matrix,
        rho_inf: rho,
        project_velocities: proj,
        ..GeneralizedAlphaOptions::with_step(h)
    });
    let mut opts = cardan_model::analysis::dynamic::options(&p, Some(integ)).expect("options");
    opts.t_end = t_end;
    opts.max_steps = 5_000_000;
    let opts = opts
        .output_times(reference.iter().map(|r| r[0]).collect())
        .outputs(Outputs::position_only());
    let mut best = f64::INFINITY;
    let mut out = None;
    for _ in 0..3 {
        let mut d = cardan_model::analysis::dynamic::dynamics(&p).expect("dynamics");
        let s = cardan_model::analysis::dynamic::initial_state(&p);
        let t0 = Instant::now();
        let r = d.simulate(&s, &opts).expect("simulate");
        best = best.min(t0.elapsed().as_secs_f64());
        out = Some(r);
    }
    let r = out.expect("ran");
    let b = &r.kinematics.point("crank", "B").expect("B").position;
    let c = &r.kinematics.point("slider", "C").expect("C").position;
    let mut err = 0.0f64;
    for (k, &[_, x, th]) in reference.iter().enumerate() {
        let b_ref = Vector3::new(0.0, 0.1 - 0.08 * th.sin(), 0.12 + 0.08 * th.cos());
        err = err
            .max((b[k] - b_ref).norm())
            .max((c[k] - Vector3::new(x, 0.0, 0.0)).norm());
    }
    println!(
        "slider-crank gen-α {matrix:?} h {h:e} ρ∞ {rho} proj {proj} {t_end} s: {:.4} s, {} steps, \
         {:.2} iterations and {:.2} factorizations per step, error {err:.3e} m",
        best,
        r.stats.steps,
        r.stats.newton_iterations as f64 / r.stats.steps as f64,
        r.stats.factorizations as f64 / r.stats.steps as f64,
    );
}
