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
    let err = error(n, &run.results, &reference);
    let drift = run.results.energy.max_drift();
    print_row(&format!("A02 N={n}"), label, &run, err, Some(drift));
    (err, drift)
}

/// Max over the stored samples and the tops of all rockers of |top_k − (k + x_B0, y_B0)|.
fn error(n: usize, r: &cardan_dynamics::DynamicResults, reference: &[Vec<f64>]) -> f64 {
    error_until(n, r, reference, f64::INFINITY)
}

/// [`error`] over the samples at times below `t_max`.
fn error_until(
    n: usize,
    r: &cardan_dynamics::DynamicResults,
    reference: &[Vec<f64>],
    t_max: f64,
) -> f64 {
    let tops: Vec<_> = (0..=n)
        .map(|k| r.point(&format!("r{k}"), "top").expect("rocker top"))
        .collect();
    let mut err = 0.0f64;
    for (k, row) in reference.iter().take(r.len()).enumerate() {
        assert!((r.times()[k] - row[0]).abs() < 1e-12);
        if row[0] >= t_max {
            break;
        }
        for (j, top) in tops.iter().enumerate() {
            let x = top.position[k];
            err = err.max((x.x - j as f64 - row[1]).hypot(x.y - row[2]).hypot(x.z));
        }
    }
    err
}

/// The file's settings: generalized-α, h = 1 ms. (DOPRI5 at rtol = 1e-8 used to be the file's
/// integrator; whether it passes the horizontal positions depends on where its stages land,
/// i.e. on roundoff: since the KKT solve became a Schur complement it stops at t = 6.54 s.)
#[test]
fn a02_n2_file_settings() {
    let (e, _) = check(2, "10 s, file settings", None, 10.0);
    assert!(e <= 1e-3, "max position error {e:e} m");
}

/// Tight: DOPRI5 cannot pass the singular horizontal position with tight tolerances (see
/// `a02_n2_dopri5_tight_stops_at_a_singular_position`), so the tight run is generalized-α
/// with a small step (second order: 5.2e-7 m at h = 5e-5 s, 2.0e-6 m at h = 1e-4 s).
#[test]
#[ignore = "200 000 implicit steps: cargo test -p cardan-tests --release -- --ignored"]
fn a02_n2_tight() {
    let (e, _) = check(2, "10 s, tight", Some(gen_alpha(5e-5, 0.9)), 10.0);
    assert!(e <= 1e-6, "max position error {e:e} m");
}

/// The same with the reference file's decimal output times, an ulp off the uniform grid, so
/// that steps land within roundoff of the horizontal positions: there the Newton matrix is
/// singular to working precision and the iteration stagnates at roundoff, which the
/// integrator accepts when the constraints hold (before, 7 steps were halved and the error grew
/// to 7.5e-5 m). Mass-only iteration matrix (gravity only), as for N = 40.
#[test]
#[ignore = "200 000 implicit steps: cargo test -p cardan-tests --release -- --ignored"]
fn a02_n2_tight_steps_on_the_singular_positions() {
    let p = example("a02_fourbar_n2");
    let reference = reference("n_fourbar_N2.csv");
    let times: Vec<f64> = reference.iter().map(|r| r[0]).collect();
    let integrator =
        cardan_dynamics::Integrator::GeneralizedAlpha(cardan_dynamics::GeneralizedAlphaOptions {
            dt: 5e-5,
            rho_inf: 0.9,
            iteration_matrix: cardan_dynamics::IterationMatrix::MassOnly,
            ..Default::default()
        });
    let run = run(&p, Some(integrator), 10.0, times);
    let e = error(2, &run.results, &reference);
    print_row("A02 N=2", "10 s, tight, CSV times", &run, e, None);
    assert_eq!(run.results.stats.rejected, 0);
    assert!(e <= 1e-6, "max position error {e:e} m");
}

/// Documents a limitation (not a criterion): with tight tolerances DOPRI5 sooner or later
/// lands a stage close enough to a horizontal position that the KKT matrix
/// [M Φ_vᵀ; Φ_v 0] is numerically singular (2 coupler rows dependent) and the run stops with
/// `Singular`. Where depends on roundoff and step-size control: at rtol = 1e-10 at the first
/// one (t ≈ 0.714 s); at rtol = 1e-9 at t ≈ 1.23 s, at rtol = 1e-8 at t ≈ 5.1 s (2026-11-22,
/// PI step control); rtol = 1e-7 happens to pass all of them. The dynamics layer has no
/// rank-aware fallback for the KKT solve. If this test starts failing because the run passes,
/// consider moving DOPRI5 back into `a02_n2_tight`.
#[test]
fn a02_n2_dopri5_tight_stops_at_a_singular_position() {
    let p = example("a02_fourbar_n2");
    let mut opts =
        cardan_model::analysis::dynamic::options(&p, Some(dopri5(1e-10, 1e-12))).unwrap();
    opts.t_end = 2.0;
    let mut d = cardan_model::analysis::dynamic::dynamics(&p).unwrap();
    let err = d
        .simulate(&cardan_model::analysis::dynamic::initial_state(&p), &opts)
        .expect_err("DOPRI5 at rtol 1e-10 stops at a horizontal position");
    let m = err.to_string();
    assert!(m.contains("singular") && m.contains("T1L"), "{m}");
}

/// The original spec: N = 40, 20 s, generalized-α h = 1e-3 (the file's settings).
#[test]
#[ignore = "81 bodies, 20 000 implicit steps (minutes): cargo test -p cardan-tests --release -- --ignored"]
fn a02_n40_file_settings() {
    let (e, _) = check(40, "20 s, file settings", None, 20.0);
    assert!(e <= 1e-3, "max position error {e:e} m");
}

/// Tight: N = 40 over the file's 20 s with generalized-α at h = 31.25 µs and the mass-only
/// iteration matrix (gravity only: no force tangent to add), modified Newton. It passes 16
/// horizontal positions; the grid point t = 11.07203125 s lies within roundoff of one, where
/// the iteration used to stagnate above its acceptance bounds and every halved retry aimed at
/// the same point again (the run stopped there; now a failed step shifts the grid, and a
/// stagnating Schur-complement solve is redone by LU). About 3 min.
///
/// Two criteria, because past the first few passages the error is decided by roundoff. Each
/// passage is a bifurcation (N + 1 degrees of freedom for an instant) that amplifies any
/// perturbation off the parallelogram branch, so changing gravity by one or two ulps
/// (−9.81 → −9.810000000000002, −9.810000000000004, −9.809999999999999) moves the 20 s error
/// between 4.5e-7 m and 1.6e-5 m (eight runs, with and without the refinement of the Schur
/// solves; 8.4e-7 m and 1.02e-6 m for the file's −9.81), while over the first 4 s (three
/// passages) all eight agree: 6.6e-8 to 6.7e-8 m, the discretization error. So: 2e-7 m up to
/// 4 s (the accuracy of the step), and 1e-4 m over the 20 s (the branch is kept and the
/// roundoff amplification stays bounded; the IFToMM high-precision bound is 1e-3 m).
#[test]
#[ignore = "81 bodies, 640 000 implicit steps (minutes): cargo test -p cardan-tests --release -- --ignored"]
fn a02_n40_tight() {
    let integrator =
        cardan_dynamics::Integrator::GeneralizedAlpha(cardan_dynamics::GeneralizedAlphaOptions {
            dt: 3.125e-5,
            rho_inf: 0.9,
            iteration_matrix: cardan_dynamics::IterationMatrix::MassOnly,
            ..Default::default()
        });
    let p = example("a02_fourbar_n40");
    let reference = reference("n_fourbar_N40.csv");
    let run = run(&p, Some(integrator), 20.0, times_until(&reference, 20.0));
    let early = error_until(40, &run.results, &reference, 4.0);
    let e = error(40, &run.results, &reference);
    let drift = run.results.energy.max_drift();
    print_row("A02 N=40", "20 s, tight", &run, e, Some(drift));
    println!("A02 N=40 tight: max position error over the first 4 s {early:.2e} m");
    assert!(
        early <= 2e-7,
        "max position error over the first 4 s {early:e} m"
    );
    assert!(e <= 1e-4, "max position error {e:e} m");
}
