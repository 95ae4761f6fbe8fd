//! IFToMM spatial rigid slider-crank (`examples/slider_crank_dynamic.toml`, crank CoM at the
//! midpoint) against the reference of shared/benchmarks/README.md §2.6
//! (`tests/data/benchmarks/spatial_slider_crank_crankCoM_mid.csv`, every 0.05 s over 5 s).
//! Position error: max over the samples of |x_slider − x_ref| and of |B − B_ref| (B = crank tip,
//! from the reference crank angle θ: B = A + 0.08 (0, −sin θ, cos θ)). Energy: E = 0.76643568 J.

mod benchmark_support;
use benchmark_support::*;

fn check(label: &str, integrator: Option<cardan_dynamics::Integrator>) -> (f64, f64) {
    let p = example("slider_crank_dynamic");
    let reference = reference("spatial_slider_crank_crankCoM_mid.csv");
    let run = run(&p, integrator, 5.0, times_until(&reference, 5.0));
    let r = &run.results;
    let c = r.point("slider", "C").expect("slider.C");
    let b = r.point("crank", "B").expect("crank.B");
    let mut err = 0.0f64;
    for (k, row) in reference.iter().enumerate() {
        assert!((r.times()[k] - row[0]).abs() < 1e-12);
        let (x, th) = (row[1], row[2]);
        let b_ref = nalgebra::Vector3::new(0.0, 0.1 - 0.08 * th.sin(), 0.12 + 0.08 * th.cos());
        err = err
            .max((c.position[k] - nalgebra::Vector3::new(x, 0.0, 0.0)).norm())
            .max((b.position[k] - b_ref).norm());
    }
    let e0 = 0.76643568;
    assert!(
        (r.energy.total[0] - e0).abs() < 1e-8,
        "E0 = {}",
        r.energy.total[0]
    );
    let drift = r
        .energy
        .total
        .iter()
        .fold(0.0f64, |a, e| a.max((e - e0).abs()));
    print_row("slider-crank", label, &run, err, Some(drift));
    (err, drift)
}

#[test]
fn slider_crank_file_settings() {
    let (e, _) = check("5 s, file settings", None);
    assert!(e <= 1e-3, "max position error {e:e} m");
}

#[test]
fn slider_crank_tight() {
    let (e, drift) = check("5 s, tight", Some(dopri5(1e-10, 1e-12)));
    assert!(e <= 1e-6, "max position error {e:e} m");
    assert!(drift < 1e-7, "energy drift {drift:e} J");
}

/// Generalized-α on the same model (second order): h = 1e-4 s is accurate to ~1e-6 m.
#[test]
#[ignore = "slow in the test profile: cargo test -p cardan-tests --release -- --ignored"]
fn slider_crank_generalized_alpha() {
    let (e, _) = check("5 s, generalized-α", Some(gen_alpha(1e-4, 0.9)));
    assert!(e <= 1e-3, "max position error {e:e} m");
}
