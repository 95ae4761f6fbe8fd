//! Contact between bodies at scale: the cost of a generalized-α step against the number of
//! bodies and of contact points, with the fitted exponents, for
//!
//! - a pile of steel-like spheres (r = 1 cm, 32.7 g) settling in a box (a floor and four
//!   walls), drawn in layers 0.5 mm apart with a small random offset, μ = 0.3, e = 0.5,
//!   K = 1e7 N/m^1.5 for a pair (a soft contact: a resting ball sinks 2.4 µm);
//! - a free chain of capsule links on spherical joints falling flat on a plane.
//!
//! Each case: 0.03 s of the run (the bottom layer lands, the layers above start to), then
//! 0.01 s timed; time per step, contact points per step (contacts.csv's rows per output time),
//! Newton iterations per step.

use crate::measure::{fmt_time, loglog_slope};
use cardan_dynamics::{Dynamics, Force, GeneralizedAlphaOptions, Integrator, SimulationOptions};
use cardan_mechanism::{
    Body, Geometry, JointKind, JointSpec, MaterialSpec, MechanismBuilder, Model, ShapeSpec,
    Stiffness, GROUND,
};
use nalgebra::Vector3;
use std::fmt::Write as _;
use std::time::Instant;

const G: f64 = 9.81;

/// A deterministic pseudo-random number in [−1, 1) (a linear congruential sequence).
fn jitter(seed: &mut u64) -> f64 {
    *seed = seed
        .wrapping_mul(6_364_136_223_846_793_005)
        .wrapping_add(1_442_695_040_888_963_407);
    ((*seed >> 11) as f64 / (1u64 << 53) as f64) * 2.0 - 1.0
}

fn material(b: &mut MechanismBuilder) {
    b.material(
        MaterialSpec::new(
            "steel",
            Stiffness::Direct {
                k: 2e7,
                exponent: 1.5,
            },
            0.5,
        )
        .friction(0.3),
    );
}

/// `n` spheres in a box of side ⌈∛n⌉ × 2.5 r (module docs).
pub fn pile(n: usize) -> Model {
    let (r, m) = (0.01, 0.0327);
    let j = 0.4 * m * r * r;
    let side = (n as f64).cbrt().ceil() as usize;
    let pitch = 2.5 * r;
    let half = 0.5 * side as f64 * pitch;
    let mut b = MechanismBuilder::new();
    let mut seed = 1u64;
    for k in 0..n {
        let (i, jj, layer) = (k % side, (k / side) % side, k / (side * side));
        let name = format!("s{k}");
        let x = -half + (i as f64 + 0.5) * pitch + 0.2 * r * jitter(&mut seed);
        let y = -half + (jj as f64 + 0.5) * pitch + 0.2 * r * jitter(&mut seed);
        let z = r + 5e-4 + layer as f64 * (2.0 * r + 5e-4);
        b.body(
            Body::new(&name)
                .mass(m)
                .inertia_diagonal(j, j, j)
                .position(Vector3::new(x, y, z)),
        );
        b.shape(ShapeSpec::new(
            &name,
            &name,
            Geometry::Sphere { radius: r },
            "steel",
        ));
    }
    material(&mut b);
    b.shape(ShapeSpec::new("floor", GROUND, Geometry::Plane, "steel"));
    for (k, (x, y, nx, ny)) in [
        (-half, 0.0, 1.0, 0.0),
        (half, 0.0, -1.0, 0.0),
        (0.0, -half, 0.0, 1.0),
        (0.0, half, 0.0, -1.0),
    ]
    .into_iter()
    .enumerate()
    {
        b.shape(
            ShapeSpec::new(format!("wall{k}"), GROUND, Geometry::Plane, "steel")
                .center(Vector3::new(x, y, 0.0))
                .axes(Vector3::new(nx, ny, 0.0), Vector3::z()),
        );
    }
    b.build().expect("the pile builds")
}

/// A free chain of `n` capsule links (0.1 m, r = 1 cm, 0.1 kg) on spherical joints, dropped
/// flat from 0.2 mm above a plane (every link lands at 6 ms; e = 0.5, settled by 20 ms).
pub fn chain_on_plane(n: usize) -> Model {
    let (len, r, m) = (0.1, 0.01, 0.1);
    let mut b = MechanismBuilder::new();
    let z = r + 2e-4;
    for k in 0..n {
        let name = format!("l{k}");
        let jt = m * len * len / 12.0;
        b.body(
            Body::new(&name)
                .mass(m)
                .inertia_diagonal(1e-5, jt, jt)
                .position(Vector3::new((k as f64 + 0.5) * len, 0.0, z)),
        );
        b.point(&name, "a", Vector3::new(-0.5 * len, 0.0, 0.0));
        b.point(&name, "b", Vector3::new(0.5 * len, 0.0, 0.0));
        b.shape(
            ShapeSpec::new(
                &name,
                &name,
                Geometry::Capsule {
                    radius: r,
                    length: len - 2.0 * r,
                },
                "steel",
            )
            .axes(Vector3::x(), Vector3::y()),
        );
        if k > 0 {
            let prev = format!("l{}", k - 1);
            b.joint(JointSpec::new(
                format!("j{k}"),
                JointKind::Spherical,
                (prev.as_str(), "b"),
                (name.as_str(), "a"),
            ));
        }
    }
    material(&mut b);
    b.shape(ShapeSpec::new("floor", GROUND, Geometry::Plane, "steel"));
    b.build().expect("the chain builds")
}

/// One case: (bodies, time per step, contact points per step, Newton iterations per step) of
/// the steps between `warm` and `warm + timed` (two runs from the start, the same steps: the
/// difference of their times and counters).
fn measure(model: &Model, h: f64, warm: f64, timed: f64) -> (usize, f64, f64, f64) {
    let run = |t_end: f64| {
        let mut d = Dynamics::new(model).expect("dynamics");
        d.add_force(Force::gravity(Vector3::new(0.0, 0.0, -G)))
            .expect("gravity");
        let ga = Integrator::GeneralizedAlpha(GeneralizedAlphaOptions::with_step(h));
        let opts = SimulationOptions::new(t_end, 10).integrator(ga);
        let s = d.initial_guess();
        let start = Instant::now();
        let r = d.simulate(&s, &opts).expect("the run");
        (start.elapsed().as_secs_f64(), r)
    };
    let (t1, r1) = run(warm);
    let (t2, r2) = run(warm + timed);
    let steps = (r2.stats.steps - r1.stats.steps).max(1) as f64;
    let iterations = (r2.stats.newton_iterations - r1.stats.newton_iterations) as f64;
    let late: Vec<f64> = r2.times().iter().copied().filter(|&t| t >= warm).collect();
    let points = r2
        .contacts
        .points
        .iter()
        .filter(|(t, _)| *t >= warm)
        .count() as f64
        / late.len().max(1) as f64;
    (
        model.num_bodies(),
        (t2 - t1).max(0.0) / steps,
        points,
        iterations / steps,
    )
}

/// The section (module docs), as Markdown.
pub fn section(smoke: bool, chains_only: bool) -> String {
    let (piles, chains): (&[usize], &[usize]) = if smoke {
        (&[8, 27], &[5, 10])
    } else {
        (&[27, 125, 343, 1000], &[25, 50, 100, 200])
    };
    let piles = if chains_only { &[][..] } else { piles };
    let (warm, timed) = if smoke { (0.005, 0.002) } else { (0.03, 0.01) };
    let mut out = String::new();
    let _ = writeln!(
        out,
        "| scene | bodies | time per step | contact points | Newton iterations per step |\n|---|---|---|---|---|"
    );
    let mut fits = Vec::new();
    for (label, sizes, make) in [
        ("sphere pile", piles, pile as fn(usize) -> Model),
        (
            "chain on a plane",
            chains,
            chain_on_plane as fn(usize) -> Model,
        ),
    ] {
        let mut by_bodies = Vec::new();
        let mut by_points = Vec::new();
        for &n in sizes {
            let (nb, t, p, it) = measure(&make(n), 1e-4, warm, timed);
            let row = format!("| {label} | {nb} | {} | {p:.0} | {it:.2} |", fmt_time(t));
            // As it is measured (a large case takes minutes).
            eprintln!("{row}");
            let _ = writeln!(out, "{row}");
            by_bodies.push((nb as f64, t));
            by_points.push((p.max(1.0), t));
        }
        fits.push(format!(
            "{label}: cost ∝ bodies^{:.2}, ∝ contact points^{:.2}",
            loglog_slope(&by_bodies),
            loglog_slope(&by_points)
        ));
    }
    let _ = writeln!(out, "\nFitted exponents: {}.", fits.join("; "));
    out
}

/// The billiard ball's plots from the peers' `RESULT code=... setting=... error=... time=...`
/// lines (`bench/peers/contact_mujoco.py`, `contact_exudyn.py`): the error against the step
/// of every fixed-step series, and the error against the time of every series (the
/// work–precision plot). Returns (error against step, work–precision) as SVG.
pub fn billiard_plots(results: &str) -> (String, String) {
    use crate::svg::{loglog, Series};
    use std::collections::BTreeMap;
    // Series name → (step or NaN, error, time).
    let mut series: BTreeMap<String, Vec<(f64, f64, f64)>> = BTreeMap::new();
    for line in results.lines().filter(|l| l.starts_with("RESULT ")) {
        let field = |k: &str| {
            line.split_whitespace()
                .find_map(|w| w.strip_prefix(&format!("{k}=")))
                .unwrap_or("")
                .to_string()
        };
        let (code, setting) = (field("code"), field("setting"));
        let (Ok(error), Ok(time)) = (field("error").parse::<f64>(), field("time").parse::<f64>())
        else {
            continue;
        };
        // "K_2.4e+10_genalpha_h_0.004" → series "cardan stiff gen-α", step 0.004; "h_0.004"
        // (MuJoCo's one series) → "mujoco", step 0.004.
        let padded = format!("_{setting}");
        let (name, step) = match padded.rsplit_once("_h_") {
            Some((head, h)) => (head.to_string(), h.parse().unwrap_or(f64::NAN)),
            None => match padded.rsplit_once("_rtol_") {
                Some((head, _)) => (head.to_string(), f64::NAN),
                None => (padded.clone(), f64::NAN),
            },
        };
        let name = name
            .replace("_K_2.4e+10", " stiff")
            .replace("_K_1e+08", " K1e8")
            .replace("_genalpha", " gen-α")
            .replace("_dopri5", " DOPRI5");
        let code = match code.as_str() {
            "mujoco" => "MuJoCo",
            "exudyn" => "Exudyn",
            other => other,
        };
        let label = format!("{code}{name}").trim().to_string();
        series.entry(label).or_default().push((step, error, time));
    }
    let by_step: Vec<Series> = (series.iter())
        .filter(|(_, p)| p.iter().all(|(h, _, _)| h.is_finite()))
        .map(|(label, p)| Series {
            label: label.clone(),
            points: p.iter().map(|&(h, e, _)| (h, e)).collect(),
        })
        .collect();
    let work: Vec<Series> = (series.iter())
        .map(|(label, p)| Series {
            label: label.clone(),
            points: p.iter().map(|&(_, e, t)| (t, e)).collect(),
        })
        .collect();
    (
        loglog(
            "billiard ball: error against the step",
            "step h [s]",
            "error [m/s]",
            &by_step,
        ),
        loglog(
            "billiard ball: error against the time",
            "time [s]",
            "error [m/s]",
            &work,
        ),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Friction makes a landing pile's Newton iterations: while its contacts settle the
    /// largest relative residual stays near 1 although each update halves, and such an
    /// attempt must not be given up as stalled (it was, and the step was halved).
    #[test]
    fn a_landing_pile_takes_every_step_at_its_size() {
        let model = pile(64);
        let mut d = Dynamics::new(&model).expect("dynamics");
        d.add_force(Force::gravity(Vector3::new(0.0, 0.0, -G)))
            .expect("gravity");
        let ga = Integrator::GeneralizedAlpha(GeneralizedAlphaOptions::with_step(1e-4));
        let opts = SimulationOptions::new(0.035, 5).integrator(ga);
        let r = d.simulate(&d.initial_guess(), &opts).expect("the run");
        eprintln!("{:?}", r.stats);
        assert_eq!(r.stats.rejected, 0, "{:?}", r.stats);
        assert_eq!(r.stats.steps, 350, "{:?}", r.stats);
    }
}
