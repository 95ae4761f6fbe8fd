//! Shared by the `benchmark_*` tests: load an example model file through cardan-cli's library
//! (so the committed file is what is tested), run it with the file's settings or with other
//! integrator settings, read the reference tables in `tests/data/benchmarks/` (subsampled copies
//! of `shared/benchmarks/*.csv`), and print one row of the docs/validation.md tables.
//!
//! Run with `--nocapture` to see the rows:
//! `cargo test -p cardan-tests --release --test benchmark_a01_pendulum -- --nocapture`.

#![allow(dead_code)]

use cardan_dynamics::{DynamicResults, Integrator};
use cardan_model::prepare::{prepare, Prepared};
use std::path::PathBuf;
use std::time::Instant;

/// The example `examples/<name>.toml`, read, validated and built.
pub fn example(name: &str) -> Prepared {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../examples")
        .join(format!("{name}.toml"));
    match prepare(&path) {
        Ok(p) => p,
        Err(e) => panic!("{name}: {e}"),
    }
}

/// The rows of `tests/data/benchmarks/<file>` (comment lines skipped).
pub fn reference(file: &str) -> Vec<Vec<f64>> {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("data/benchmarks")
        .join(file);
    let text = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{path:?}: {e}"));
    text.lines()
        .filter(|l| !l.starts_with('#') && !l.trim().is_empty())
        .map(|l| l.split(',').map(|x| x.trim().parse().unwrap()).collect())
        .collect()
}

/// A finished run.
pub struct Run {
    /// The results at the requested times.
    pub results: DynamicResults,
    /// Wall time of `simulate` (s), initial conditions included.
    pub cpu: f64,
    /// The integrator used.
    pub integrator: Integrator,
}

/// Runs the example's dynamic analysis until `t_end` with results at `times`, with the file's
/// integrator settings (`None`) or others.
pub fn run(p: &Prepared, integrator: Option<Integrator>, t_end: f64, times: Vec<f64>) -> Run {
    let mut opts =
        cardan_model::analysis::dynamic::options(p, integrator).expect("dynamic analysis");
    opts.t_end = t_end;
    let opts = opts.output_times(times);
    let mut d = cardan_model::analysis::dynamic::dynamics(p).expect("dynamics");
    let s = cardan_model::analysis::dynamic::initial_state(p);
    let start = Instant::now();
    let results = match d.simulate(&s, &opts) {
        Ok(r) => r,
        Err(e) => panic!("{}: {e}", p.loaded.name),
    };
    Run {
        results,
        cpu: start.elapsed().as_secs_f64(),
        integrator: opts.integrator,
    }
}

/// The reference times up to `t_end`, as the uniform output grid the CLI uses
/// (t_k = t_last · k / n; the CSV's decimal times agree to an ulp). Exactly the same grid
/// matters: generalized-α subdivides each output interval into equal steps, and an ulp's
/// difference moves a step onto a singular configuration in A02 (see benchmark_a02_fourbar.rs).
pub fn times_until(reference: &[Vec<f64>], t_end: f64) -> Vec<f64> {
    let t: Vec<f64> = reference
        .iter()
        .map(|r| r[0])
        .filter(|&t| t <= t_end + 1e-9)
        .collect();
    let n = t.len() - 1;
    let (t0, t1) = (t[0], t[n]);
    (0..=n)
        .map(|k| t0 + (t1 - t0) * (k as f64 / n as f64))
        .collect()
}

/// The integrator and its settings, for the tables.
pub fn describe(i: &Integrator) -> (String, String) {
    match i {
        Integrator::Dopri5(o) => (
            "DOPRI5".into(),
            match o.step {
                cardan_dynamics::StepControl::Fixed(h) => format!("fixed h = {h:e} s"),
                _ => format!("rtol = {:e}, atol = {:e}", o.rtol, o.atol),
            },
        ),
        Integrator::GeneralizedAlpha(o) => (
            "generalized-α".into(),
            format!("dt = {:e} s, ρ∞ = {}", o.dt, o.rho_inf),
        ),
    }
}

/// Prints one table row: | run | integrator | settings | max error | CPU | steps (rejected) |
/// energy drift |.
pub fn print_row(problem: &str, label: &str, run: &Run, max_error: f64, energy_drift: Option<f64>) {
    let (name, settings) = describe(&run.integrator);
    let s = &run.results.stats;
    println!(
        "ROW {problem} | {label} | {name} | {settings} | {max_error:.2e} m | {:.3} s | {} ({} rejected) | {} |",
        run.cpu,
        s.steps,
        s.rejected,
        energy_drift.map_or("—".to_string(), |e| format!("{e:.1e} J")),
    );
}

/// DOPRI5 with tolerances.
pub fn dopri5(rtol: f64, atol: f64) -> Integrator {
    Integrator::Dopri5(cardan_dynamics::Dopri5Options::tolerances(rtol, atol))
}

/// Generalized-α with time step dt and ρ∞.
pub fn gen_alpha(dt: f64, rho_inf: f64) -> Integrator {
    Integrator::GeneralizedAlpha(cardan_dynamics::GeneralizedAlphaOptions {
        dt,
        rho_inf,
        ..Default::default()
    })
}
