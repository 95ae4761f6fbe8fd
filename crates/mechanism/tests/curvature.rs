//! The constraints' curvature of the least change's Newton step (`Model::eval_curvature`):
//! vᵀ C v against the second difference of −κᵀΦ along the Newton state's retraction
//! x ⊕ s v (r + s ṙ, p ⊗ exp(s ω'/2)), at poses off the constraint manifold, for random
//! multipliers and directions, on Haug's spatial slider-crank (revolute, spherical,
//! universal, prismatic and a driver with Φ_tt ≠ 0), Bricard's linkage and a four-bar.

mod common;
use cardan_mechanism::{apply_rotation_step, DriverSpec, Model, TimeFunction, Workspace};
use common::{bricard_builder, four_bar_links, slider_crank_undriven};
use nalgebra::{Vector3, Vector4};

/// A small deterministic generator of numbers in [−1, 1].
struct Lcg(u64);

impl Lcg {
    fn sym(&mut self) -> f64 {
        self.0 = self
            .0
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        ((self.0 >> 11) as f64 / (1u64 << 53) as f64) * 2.0 - 1.0
    }
}

fn state(ws: &Workspace, nb: usize) -> Vec<f64> {
    (0..nb)
        .flat_map(|b| {
            let (r, p) = (ws.r(b), ws.p(b));
            [r.x, r.y, r.z, p[0], p[1], p[2], p[3]]
        })
        .collect()
}

fn set_state(ws: &mut Workspace, x: &[f64]) {
    for (b, q) in x.chunks(7).enumerate() {
        ws.set_pose(
            b,
            Vector3::new(q[0], q[1], q[2]),
            Vector4::new(q[3], q[4], q[5], q[6]),
        );
    }
}

/// The largest |vᵀCv − (−κᵀΦ)''| over random κ and v, relative to the size of the terms.
fn worst_relative_error(model: &Model, seed: u64) -> f64 {
    let (m, nb) = (model.num_equations(), model.num_bodies());
    let n = 6 * nb;
    let mut rng = Lcg(seed);
    let mut ws = model.workspace();
    // Off the manifold: every body moved and turned a little from its drawn pose.
    let mut x = state(&ws, nb);
    let kick: Vec<f64> = (0..n).map(|_| 0.05 * rng.sym()).collect();
    apply_rotation_step(&mut x, &kick);
    let t = 0.37;
    let mut worst: f64 = 0.0;
    for _ in 0..5 {
        let kappa: Vec<f64> = (0..m).map(|_| rng.sym()).collect();
        let v: Vec<f64> = (0..n).map(|_| rng.sym()).collect();
        set_state(&mut ws, &x);
        let mut c = vec![0.0; n * n];
        model.eval_curvature(&ws, t, &kappa, &mut c);
        let vcv: f64 = (0..n)
            .map(|i| (0..n).map(|j| v[i] * c[i * n + j] * v[j]).sum::<f64>())
            .sum();
        // −κᵀΦ along x ⊕ s v.
        let mut f = |s: f64| {
            let mut y = x.clone();
            let step: Vec<f64> = v.iter().map(|vi| s * vi).collect();
            apply_rotation_step(&mut y, &step);
            set_state(&mut ws, &y);
            let mut phi = vec![0.0; m];
            model.eval_phi(&ws, t, &mut phi);
            -phi.iter().zip(&kappa).map(|(a, b)| a * b).sum::<f64>()
        };
        let h = 1e-4;
        let second = (f(h) - 2.0 * f(0.0) + f(-h)) / (h * h);
        worst = worst.max((vcv - second).abs() / (1.0 + vcv.abs()));
    }
    worst
}

#[test]
fn curvature_is_the_second_derivative_along_the_retraction() {
    let mut crank = slider_crank_undriven();
    crank.driver(DriverSpec::rotation(
        "motor",
        "A",
        TimeFunction::Polynomial(vec![0.0, 2.0, 3.0]),
    ));
    for (name, builder) in [
        ("slider-crank", crank),
        ("Bricard", bricard_builder()),
        ("four-bar", four_bar_links(0.3, 0.0)),
    ] {
        let model = builder.build().unwrap();
        for seed in 1..4 {
            let e = worst_relative_error(&model, seed);
            assert!(e < 1e-6, "{name}, seed {seed}: vᵀCv off by {e:.2e}");
        }
    }
}
