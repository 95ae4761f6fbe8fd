//! IFToMM A04 Bricard mechanism (`examples/a04_bricard.toml`, prism inertia) against the
//! reference of shared/benchmarks/README.md §2.4 (`tests/data/benchmarks/bricard_P3_box.csv`,
//! every 0.05 s over 10 s): P3 = joint C (rod2.C). The model is overconstrained (one redundant
//! equation, dropped at the start); energy is conserved.

mod benchmark_support;
use benchmark_support::*;
use nalgebra::Vector3;

fn check(label: &str, integrator: Option<cardan_dynamics::Integrator>) -> (f64, f64) {
    let p = example("a04_bricard");
    let reference = reference("bricard_P3_box.csv");
    let run = run(&p, integrator, 10.0, times_until(&reference, 10.0));
    let r = &run.results;
    assert_eq!(
        r.redundant.len(),
        1,
        "one redundant equation: {:?}",
        r.redundant
    );
    let c = r.point("rod2", "C").expect("rod2.C");
    let mut err = 0.0f64;
    for (k, row) in reference.iter().enumerate() {
        assert!((r.times()[k] - row[0]).abs() < 1e-12);
        err = err.max((c.position[k] - Vector3::new(row[1], row[2], row[3])).norm());
    }
    let drift = r.energy.max_drift();
    print_row("A04", label, &run, err, Some(drift));
    (err, drift)
}

#[test]
fn a04_file_settings() {
    let (e, _) = check("10 s, file settings", None);
    assert!(e <= 1e-3, "max position error {e:e} m");
}

#[test]
fn a04_tight() {
    let (e, drift) = check("10 s, tight", Some(dopri5(1e-11, 1e-13)));
    assert!(e <= 1e-6, "max position error {e:e} m");
    assert!(drift < 1e-8, "energy drift {drift:e} J");
}
