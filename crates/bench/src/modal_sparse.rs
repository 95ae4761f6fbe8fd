//! Modal analysis of large models on the sparse path (issue 26): a hanging chain of `n` rods
//! joined by revolute joints about z (`n` degrees of freedom), its lowest modes by
//! [`Dynamics::modal_sparse`] (static equilibrium, sparse tangents, shift-invert Lanczos), timed
//! at 100, 1,000 and 10,000 links (smoke: 100 and 1,000). At 100 links the frequencies are
//! checked against the dense path ([`Dynamics::modal`], all modes); every size is compared
//! with the continuous hanging chain, ω_i = (j₀,ᵢ / 2) √(g / L_total) (j₀,ᵢ the zeros of the
//! Bessel function J₀; Rayleigh's classic result), which the discrete chain approaches as the
//! number of links grows.

use cardan_dynamics::{Dynamics, Force, ModalOptions, StaticOptions};
use cardan_mechanism::{Body, JointKind, JointSpec, MechanismBuilder, Model, GROUND};
use nalgebra::Vector3;
use std::fmt::Write;
use std::time::Instant;

/// Gravity [m/s²].
const G: f64 = 9.81;

/// Modes asked of the sparse path.
const MODES: usize = 6;

/// The first zeros of J₀.
const J0_ZEROS: [f64; 6] = [
    2.404_825_557_695_773,
    5.520_078_110_286_311,
    8.653_727_912_911_013,
    11.791_534_439_014_281,
    14.930_917_708_487_787,
    18.071_063_967_910_924,
];

/// `n` rods of length 1 m (mass 1 kg, inertia diag(0.001, 1/12, 1/12) along the rod's x)
/// along +x from the origin, joined end to end (the first to the ground) by revolutes about z.
/// Under gravity along +x the chain hangs at its drawn pose.
pub fn hanging_chain(n: usize) -> Model {
    let mut b = MechanismBuilder::new();
    b.point(GROUND, "O", Vector3::zeros())
        .vector(GROUND, "x", Vector3::x())
        .vector(GROUND, "z", Vector3::z());
    for k in 0..n {
        let name = format!("b{k}");
        b.body(
            Body::new(&name)
                .mass(1.0)
                .inertia_diagonal(0.001, 1.0 / 12.0, 1.0 / 12.0)
                .position(Vector3::new(k as f64 + 0.5, 0.0, 0.0)),
        );
        b.point(&name, "a", Vector3::new(-0.5, 0.0, 0.0))
            .point(&name, "b", Vector3::new(0.5, 0.0, 0.0))
            .vector(&name, "x", Vector3::x())
            .vector(&name, "z", Vector3::z());
        let (pb, pp) = if k == 0 {
            (GROUND.to_string(), "O")
        } else {
            (format!("b{}", k - 1), "b")
        };
        b.joint(
            JointSpec::new(
                format!("j{k}"),
                JointKind::Revolute,
                (&pb, pp),
                (&name, "a"),
            )
            .axes("z", "z")
            .x_axes("x", "x"),
        );
    }
    b.build().expect("valid chain")
}

/// One size: (wall time s, frequencies Hz, Newton iterations, Lanczos steps).
fn sparse_run(model: &Model) -> (f64, Vec<f64>, usize, usize) {
    let start = Instant::now();
    let mut d = Dynamics::new(model).expect("dynamics");
    d.add_force(Force::gravity(Vector3::new(G, 0.0, 0.0)))
        .expect("gravity");
    let r = d
        .modal_sparse(&StaticOptions::default(), MODES)
        .expect("sparse modal analysis");
    let t = start.elapsed().as_secs_f64();
    assert!(r.converged, "Lanczos did not converge");
    let f = r.modes.iter().map(|m| m.frequency).collect();
    (
        t,
        f,
        r.equilibrium.equilibria[0].iterations,
        r.lanczos_steps,
    )
}

/// The markdown section.
pub fn section(smoke: bool) -> String {
    let mut md = String::new();
    let _ = writeln!(
        md,
        "### Modal analysis, sparse path\n\nA hanging chain of n rods on revolutes (n degrees \
         of freedom), its {MODES} lowest modes by `Dynamics::modal_sparse` (equilibrium, sparse \
         tangents, shift-invert Lanczos); time of the whole analysis including the model's \
         set-up. \"vs dense\": largest relative difference of the {MODES} frequencies from the \
         dense path (`Dynamics::modal`, all modes) on the same model; \"vs continuous\": the \
         lowest frequency against the continuous hanging chain (j₀,₁/2)√(g/L).\n"
    );
    let _ = writeln!(
        md,
        "| links | time (s) | Newton iterations | Lanczos steps | f₁ (Hz) | f₆ (Hz) | vs dense | vs continuous | dense time (s) |\n|---|---|---|---|---|---|---|---|---|"
    );
    let sizes: &[usize] = if smoke {
        &[100, 1000]
    } else {
        &[100, 1000, 10_000]
    };
    for &n in sizes {
        let model = hanging_chain(n);
        let (t, f, it, steps) = sparse_run(&model);
        let (vs_dense, dense_t) = if n <= 100 {
            let start = Instant::now();
            let mut d = Dynamics::new(&model).expect("dynamics");
            d.add_force(Force::gravity(Vector3::new(G, 0.0, 0.0)))
                .expect("gravity");
            let r = d.modal(&ModalOptions::default()).expect("dense modal");
            let dt = start.elapsed().as_secs_f64();
            let worst = f
                .iter()
                .zip(&r.modes)
                .map(|(a, m)| (a - m.frequency).abs() / m.frequency)
                .fold(0.0f64, f64::max);
            assert!(worst < 1e-8, "sparse vs dense: {worst:.2e}");
            (format!("{worst:.1e}"), format!("{dt:.3}"))
        } else {
            ("".into(), "".into())
        };
        let cont = J0_ZEROS[0] / 2.0 * (G / n as f64).sqrt() / (2.0 * std::f64::consts::PI);
        let _ = writeln!(
            md,
            "| {n} | {t:.3} | {it} | {steps} | {:.6} | {:.6} | {vs_dense} | {:.1e} | {dense_t} |",
            f[0],
            f[f.len() - 1],
            (f[0] - cont).abs() / cont
        );
        eprintln!("modal sparse: {n} links in {t:.3} s");
    }
    let _ = writeln!(md);
    md
}
