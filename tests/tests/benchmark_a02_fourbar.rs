//! IFToMM A02 N four-bar mechanism (`examples/a02_fourbar_n2.toml`, `a02_fourbar_n40.toml`)
//! against the exact 1-DOF reduction of shared/benchmarks/README.md §2.2
//! (`tests/data/benchmarks/n_fourbar_N{2,40}.csv`, every 0.05 s). The mechanism passes through
//! the singular horizontal position every ~1.2 s. Position error: max over the samples and over
//! the tops of all rockers of |top_k − (k + x_B0, y_B0)| (so the run must stay on the
//! parallelogram branch). Energy is conserved.
//!
//! N = 40 (81 bodies) is slow: `cargo test -p cardan-tests --release --test
//! benchmark_a02_fourbar -- --ignored --nocapture`.

mod benchmark_support;
use benchmark_support::*;

fn check(
    n: usize,
    label: &str,
    integrator: Option<cardan_dynamics::Integrator>,
    t_end: f64,
) -> (f64, f64) {
    let p = example(&format!("a02_fourbar_n{n}"));
    let reference = reference(&format!("n_fourbar_N{n}.csv"));
    let run = run(&p, integrator, t_end, times_until(&reference, t_end));
    let r = &run.results;
    let tops: Vec<_> = (0..=n)
        .map(|k| r.point(&format!("r{k}"), "top").expect("rocker top"))
        .collect();
    let mut err = 0.0f64;
    for (k, row) in reference.iter().take(r.len()).enumerate() {
        assert!((r.times()[k] - row[0]).abs() < 1e-12);
        for (j, top) in tops.iter().enumerate() {
            let x = top.position[k];
            err = err.max((x.x - j as f64 - row[1]).hypot(x.y - row[2]).hypot(x.z));
        }
    }
    let drift = r.energy.max_drift();
    print_row(&format!("A02 N={n}"), label, &run, err, Some(drift));
    (err, drift)
}

#[test]
fn a02_n2_file_settings() {
    let (e, _) = check(2, "10 s, file settings", None, 10.0);
    assert!(e <= 1e-3, "max position error {e:e} m");
}

/// Tight: DOPRI5 cannot pass the singular horizontal position with tight tolerances (see
/// `a02_n2_dopri5_tight_stops_at_the_singular_position`), so the tight run is generalized-α
/// with a small step (second order: 5.2e-7 m at h = 5e-5 s, 2.1e-6 m at h = 1e-4 s).
/// Fragile near the singular positions: with output times an ulp away from the uniform grid
/// (the CSV's decimal times), 7 steps land where the Newton iteration fails, each is halved
/// once, and the error grows to 7.5e-5 m — a step-size change costs generalized-α its
/// second order. `times_until` therefore returns the CLI's uniform grid.
#[test]
#[ignore = "200 000 implicit steps: cargo test -p cardan-tests --release -- --ignored"]
fn a02_n2_tight() {
    let (e, _) = check(2, "10 s, tight", Some(gen_alpha(5e-5, 0.9)), 10.0);
    assert!(e <= 1e-6, "max position error {e:e} m");
}

/// Documents a limitation (not a criterion): with rtol ≤ 1e-9, DOPRI5 lands a stage close
/// enough to the first horizontal position (t ≈ 0.714 s) that the KKT matrix
/// [M Φ_vᵀ; Φ_v 0] is numerically singular (2 coupler rows dependent) and the run stops with
/// `Singular`; with rtol = 1e-8 it happens to step over it. The dynamics layer has no
/// rank-aware fallback for the KKT solve. If this test starts failing because the run passes,
/// move DOPRI5 back into `a02_n2_tight`.
#[test]
fn a02_n2_dopri5_tight_stops_at_the_singular_position() {
    let p = example("a02_fourbar_n2");
    let mut opts = cardan_cli::dynamic::options(&p, Some(dopri5(1e-9, 1e-11))).unwrap();
    opts.t_end = 1.0;
    let mut d = cardan_cli::dynamic::dynamics(&p).unwrap();
    let err = d
        .simulate(&cardan_cli::dynamic::initial_state(&p), &opts)
        .expect_err("DOPRI5 at rtol 1e-9 stops at the horizontal position");
    let m = err.to_string();
    assert!(m.contains("singular") && m.contains("t = 0.71"), "{m}");
}

/// The implicit integrator through the same singular positions.
#[test]
#[ignore = "10 000 implicit steps: cargo test -p cardan-tests --release -- --ignored"]
fn a02_n2_generalized_alpha() {
    let (e, _) = check(2, "10 s, generalized-α", Some(gen_alpha(1e-3, 0.9)), 10.0);
    assert!(e <= 1e-3, "max position error {e:e} m");
}

/// The original spec: N = 40, 20 s, generalized-α h = 1e-3 (the file's settings).
#[test]
#[ignore = "81 bodies, 20 000 implicit steps (minutes): cargo test -p cardan-tests --release -- --ignored"]
fn a02_n40_file_settings() {
    let (e, _) = check(40, "20 s, file settings", None, 20.0);
    assert!(e <= 1e-3, "max position error {e:e} m");
}
