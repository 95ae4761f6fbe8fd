//! Kinematics at equal accuracy (issue 25): the work–precision curve of cardan's position
//! tolerance against OndselSolver's `errorTol` on the spatial slider-crank
//! (`examples/slider_crank.toml`, the model of `bench/peers/peers.py`).
//!
//! **Error** is the distance from the closed form, not a residual: the largest component error
//! \[m\] of the slider point C and of the crank's centre of mass over all frames, with
//!
//! ```text
//! B(θ) = (0, 0.1 − 0.08 sin θ, 0.12 + 0.08 cos θ),   x_C = √(0.09 − B_y² − B_z²),
//! crank centre = (A + B) / 2,   A = (0, 0.1, 0.12),   θ = 2πt
//! ```
//!
//! (the closed form of `crates/cli/tests/examples.rs`). Both solvers compute position,
//! velocity and acceleration at every frame of one crank turn.
//!
//! **Time per frame** = (run of N frames − run of 1 frame) / (N − 1) for both: assembly, setup
//! and (for OndselSolver) the model text are excluded. cardan: [`Model::run_kinematics`] with
//! `KinematicOptions::tolerance(τ)` (what `[analysis] position_tolerance = τ` sets), medians of
//! repeated runs; OndselSolver: `bench/peers/kinematics_accuracy.py` (best of 3, in Python
//! around the solver call).
//!
//! `cardan-bench --kinematic-accuracy PYTHON [--smoke] [--svg FILE]` prints the table
//! (markdown) and writes the plot; PYTHON is the peers venv (`target/peers-venv/bin/python`,
//! made by `cargo xtask bench --peers-only kinematics`). Without pyondsel the OndselSolver
//! columns say so and cardan's curve is still measured.

use crate::measure::{fmt_time, median};
use crate::svg::{loglog, Series};
use cardan_mechanism::{KinematicOptions, Model};
use nalgebra::Vector3;
use std::f64::consts::PI;
use std::fmt::Write as _;
use std::path::Path;
use std::process::Command;
use std::time::Instant;

/// The tolerances of both curves (cardan's `position_tolerance`, OndselSolver's `errorTol`).
pub const TOLERANCES: [f64; 5] = [1e-6, 1e-8, 1e-10, 1e-12, 1e-14];

/// One point of a work–precision curve.
#[derive(Debug, Clone, Copy)]
pub struct Point {
    /// The tolerance asked for.
    pub tolerance: f64,
    /// Largest position error against the closed form \[m\].
    pub error: f64,
    /// Seconds per frame.
    pub per_frame: f64,
}

/// The closed-form slider point C and crank centre of mass at time `t` (module docs).
pub fn closed_form(t: f64) -> (Vector3<f64>, Vector3<f64>) {
    let th = 2.0 * PI * t;
    let (by, bz) = (0.1 - 0.08 * th.sin(), 0.12 + 0.08 * th.cos());
    let x = (0.09 - by * by - bz * bz).sqrt();
    (
        Vector3::new(x, 0.0, 0.0),
        Vector3::new(0.0, 0.5 * (0.1 + by), 0.5 * (0.12 + bz)),
    )
}

/// cardan's point at tolerance `tolerance`: `frames` frames over t ∈ [0, 1].
///
/// # Panics
/// If the slider-crank does not run (the example is broken).
pub fn cardan_point(model: &Model, frames: usize, tolerance: f64, rounds: usize) -> Point {
    let run = |n: usize| {
        model
            .run_kinematics(&KinematicOptions::new(0.0, 1.0, n).tolerance(tolerance))
            .expect("the slider-crank runs")
    };
    let r = run(frames);
    let (c, crank) = (
        r.point("slider", "C").expect("slider.C"),
        r.body("crank").expect("crank"),
    );
    let error = r.times.iter().enumerate().fold(0.0f64, |e, (k, &t)| {
        let (c0, m0) = closed_form(t);
        e.max((c.position[k] - c0).amax())
            .max((crank.r[k] - m0).amax())
    });
    let time = |n: usize| {
        let mut v: Vec<f64> = (0..rounds.max(1))
            .map(|_| {
                let t0 = Instant::now();
                std::hint::black_box(run(n));
                t0.elapsed().as_secs_f64()
            })
            .collect();
        median(&mut v)
    };
    let per_frame = ((time(frames) - time(1)) / (frames - 1) as f64).max(0.0);
    Point {
        tolerance,
        error,
        per_frame,
    }
}

/// OndselSolver's point at `errorTol = tolerance` through `python` (module docs).
///
/// # Errors
/// The script's failure (no pyondsel, a solver error), as a sentence.
pub fn ondsel_point(
    python: &str,
    root: &Path,
    frames: usize,
    tolerance: f64,
) -> Result<Point, String> {
    let script = root.join("bench/peers/kinematics_accuracy.py");
    let o = Command::new(python)
        .arg(&script)
        .arg(frames.to_string())
        .arg(format!("{tolerance:e}"))
        .current_dir(root.join("bench/peers"))
        .output()
        .map_err(|e| format!("cannot start {python}: {e}"))?;
    let out = String::from_utf8_lossy(&o.stdout);
    let Some(line) = out.lines().find(|l| l.starts_with("RESULT ")) else {
        let err = String::from_utf8_lossy(&o.stderr);
        return Err(format!(
            "{} gave no result: {}",
            script.display(),
            err.lines().last().unwrap_or("")
        ));
    };
    let get = |key: &str| {
        line[7..]
            .split_whitespace()
            .find_map(|kv| kv.strip_prefix(key)?.strip_prefix('='))
            .and_then(|v| v.parse::<f64>().ok())
            .unwrap_or(f64::NAN)
    };
    Ok(Point {
        tolerance,
        error: get("error"),
        per_frame: get("per_frame"),
    })
}

/// The cheapest point of `curve` whose error is at most `error`.
fn cheapest_within(curve: &[Point], error: f64) -> Option<Point> {
    curve
        .iter()
        .filter(|p| p.error <= error)
        .min_by(|a, b| a.per_frame.total_cmp(&b.per_frame))
        .copied()
}

/// The markdown table and the SVG plot of both curves.
///
/// # Panics
/// If `examples/slider_crank.toml` is missing or does not run.
pub fn work_precision(root: &Path, python: Option<&str>, smoke: bool) -> (String, String) {
    let p = cardan_model::prepare::prepare(&root.join("examples/slider_crank.toml"))
        .expect("examples/slider_crank.toml");
    let (frames, rounds) = if smoke { (50, 1) } else { (200, 9) };
    let cardan: Vec<Point> = TOLERANCES
        .iter()
        .map(|&tol| cardan_point(&p.model, frames, tol, rounds))
        .collect();
    let mut peer_error = None;
    let mut ondsel = Vec::new();
    if let Some(py) = python {
        for &tol in &TOLERANCES {
            match ondsel_point(py, root, frames, tol) {
                Ok(pt) => ondsel.push(pt),
                Err(e) => {
                    peer_error = Some(e);
                    break;
                }
            }
        }
    } else {
        peer_error = Some("no Python given".into());
    }
    let mut md = format!(
        "**Kinematics at equal accuracy: spatial slider-crank, cardan against OndselSolver.** \
         {frames} frames over one crank turn, position + velocity + acceleration per frame. \
         Error: largest distance [m] of the slider point and the crank's centre of mass from \
         the closed form over all frames. Time per frame = (N frames − 1 frame) / (N − 1). \
         cardan: `position_tolerance` τ; OndselSolver: `errorTol` τ.\n\n\
         | τ | cardan error [m] | cardan / frame | OndselSolver error [m] | OndselSolver / frame | ratio (OndselSolver / cardan) |\n\
         |---:|---:|---:|---:|---:|---:|\n"
    );
    for (k, c) in cardan.iter().enumerate() {
        let (oe, ot, ratio) =
            ondsel
                .get(k)
                .map_or(("–".into(), "–".into(), "–".into()), |o| {
                    (
                        format!("{:.1e}", o.error),
                        fmt_time(o.per_frame),
                        format!("{:.0}×", o.per_frame / c.per_frame),
                    )
                });
        let _ = writeln!(
            md,
            "| {:.0e} | {:.1e} | {} | {oe} | {ot} | {ratio} |",
            c.tolerance,
            c.error,
            fmt_time(c.per_frame)
        );
    }
    md.push('\n');
    if let Some(e) = &peer_error {
        let _ = writeln!(md, "OndselSolver not measured: {e}\n");
    }
    // Equal accuracy: for each OndselSolver point, cardan's cheapest point at least as accurate.
    for o in &ondsel {
        if let Some(c) = cheapest_within(&cardan, o.error) {
            let _ = writeln!(
                md,
                "- OndselSolver errorTol {:.0e} (error {:.1e} m, {} / frame): cardan reaches \
                 {:.1e} m at τ = {:.0e} in {} / frame, **{:.0}×** faster.",
                o.tolerance,
                o.error,
                fmt_time(o.per_frame),
                c.error,
                c.tolerance,
                fmt_time(c.per_frame),
                o.per_frame / c.per_frame
            );
        }
    }
    if let (Some(c), Some(o)) = (cardan.last(), ondsel.last()) {
        let _ = writeln!(
            md,
            "- At ≤ 1e-14 m (target): cardan τ = {:.0e} reaches {:.1e} m ({}); OndselSolver's \
             tightest errorTol {:.0e} reaches {:.1e} m in {} / frame; ratio {:.0}× (target ≥ 50×).",
            c.tolerance,
            c.error,
            if c.error <= 1e-14 {
                "met"
            } else {
                "**missed**"
            },
            o.tolerance,
            o.error,
            fmt_time(o.per_frame),
            o.per_frame / c.per_frame
        );
    }
    let series = |label: &str, pts: &[Point]| Series {
        label: label.into(),
        points: pts
            .iter()
            .map(|p| (p.error.max(1e-17), p.per_frame))
            .collect(),
    };
    let svg = loglog(
        "Kinematics work–precision: spatial slider-crank",
        "position error against the closed form [m]",
        "time per frame [s]",
        &[series("cardan", &cardan), series("OndselSolver", &ondsel)],
    );
    (md, svg)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn closed_form_starts_at_the_drawn_pose() {
        let (c, m) = closed_form(0.0);
        assert!((c - Vector3::new(0.2, 0.0, 0.0)).amax() < 1e-15);
        assert!((m - Vector3::new(0.0, 0.1, 0.16)).amax() < 1e-15);
    }

    #[test]
    fn cheapest_within_picks_the_fastest_accurate_enough_point() {
        let pt = |error, per_frame| Point {
            tolerance: 0.0,
            error,
            per_frame,
        };
        let c = [pt(1e-8, 1.0), pt(1e-12, 2.0), pt(1e-15, 3.0)];
        assert_eq!(cheapest_within(&c, 1e-11).unwrap().per_frame, 2.0);
        assert!(cheapest_within(&c, 1e-16).is_none());
    }
}
