//! Andrews' squeezing mechanism (IFToMM A03; `examples/a03_andrews.toml`) against the Bari IVP
//! test-set reference at t = 0.03 s (PSIDE, rtol = atol = 1e-14; shared/benchmarks/README.md §3).
//! The test set's seven angles (β, Θ, γ, Φ, δ, Ω, ε) are joint angles of the model; the position
//! error is the largest distance at t = 0.03 between the model's joint points F, E, D, G, H and
//! the same points computed from the reference angles (the test set's constraint formulas).

mod benchmark_support;
use benchmark_support::*;
use nalgebra::Vector3;

/// y(1..7) of the test set at t = 0.03: β, Θ, γ, Φ, δ, Ω, ε.
const REFERENCE: [f64; 7] = [
    0.1581077119629904e+2,
    -0.1575637105984298e+2,
    0.4082224013073101e-1,
    -0.5347301163226948e+0,
    0.5244099658805304e+0,
    0.5347301163226948e+0,
    0.1048080741042263e+1,
];

fn rot(t: f64, x: f64, y: f64) -> Vector3<f64> {
    Vector3::new(x * t.cos() - y * t.sin(), x * t.sin() + y * t.cos(), 0.0)
}

/// Points F, E, D, G, H from the test set's angles (its constraint and spring formulas).
fn points(q: &[f64; 7]) -> [Vector3<f64>; 5] {
    let [be, th, ga, _ph, de, _om, ep] = *q;
    let (rr, d, sc, sd, zt, u) = (7e-3, 28e-3, 18e-3, 2e-2, 4e-2, 4e-2);
    let a = Vector3::new(-0.06934, -0.00227, 0.0);
    let b = Vector3::new(-0.03635, 0.03273, 0.0);
    let f = rot(be, rr, 0.0);
    [
        f,
        f + rot(be + th, -d, 0.0),
        b + rot(ga, sd, -sc),
        a + rot(de, zt, 0.0),
        a + rot(ep, 0.0, -u),
    ]
}

fn check(label: &str, integrator: Option<cardan_dynamics::Integrator>) -> (f64, f64) {
    let p = example("a03_andrews");
    // Fine outputs so that the joint angles unwrap over the crank's turns (β̇ ≈ 1400 rad/s).
    let times: Vec<f64> = (0..=300).map(|k| k as f64 * 1e-4).collect();
    let run = run(&p, integrator, 0.03, times);
    let r = &run.results;
    let k = r.len() - 1;
    assert!((r.times()[k] - 0.03).abs() < 1e-15);
    let angle = |j: &str| r.kinematics.joint(j).expect("joint").values[k][0];
    // β, Θ, γ, Φ, δ, Ω, ε
    let q = [
        angle("O"),
        angle("F"),
        angle("B"),
        angle("G"),
        angle("A_AG"),
        angle("H"),
        angle("A_AH"),
    ];
    let angle_err = q
        .iter()
        .zip(REFERENCE)
        .fold(0.0f64, |a, (x, y)| a.max((x - y).abs()));
    let reference = points(&REFERENCE);
    let model = [
        r.point("OF", "F").unwrap().position[k],
        r.point("FE", "E").unwrap().position[k],
        r.point("BDE", "D").unwrap().position[k],
        r.point("AG", "G").unwrap().position[k],
        r.point("AH", "H").unwrap().position[k],
    ];
    let err = model
        .iter()
        .zip(&reference)
        .fold(0.0f64, |a, (x, y)| a.max((x - y).norm()));
    print_row("A03", label, &run, err, None);
    println!("A03 {label}: max angle error {angle_err:.2e} rad; angles {q:?}");
    (err, angle_err)
}

#[test]
fn a03_file_settings() {
    let (e, a) = check("0.03 s, file settings", None);
    assert!(e <= 1e-3, "position error {e:e} m");
    assert!(a <= 1e-3, "angle error {a:e} rad");
}

#[test]
fn a03_tight() {
    let (e, a) = check("0.03 s, tight", Some(dopri5(1e-11, 1e-13)));
    assert!(e <= 1e-6, "position error {e:e} m");
    assert!(a <= 1e-6, "angle error {a:e} rad");
}
