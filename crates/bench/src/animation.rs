//! Writing `animation.glb` and `index.html` (cardan-report) at several sizes: the time must grow
//! linearly in frames × bodies (issue 23). Synthetic scenes: each body has a sphere, a rod and
//! two named points, and moves along a helix while turning, so every keyframe differs.

use crate::measure::{fmt_bytes, fmt_time, loglog_slope, time_per_call};
use cardan_report::{write_glb, write_html, Body, Geometry, NamedPoint, Page, Scene, Shape};
use std::fmt::Write as _;
use std::time::Duration;

/// A scene of `bodies` bodies over `frames` output times.
pub fn scene(bodies: usize, frames: usize) -> Scene {
    let times: Vec<f64> = (0..frames).map(|k| k as f64 * 1e-3).collect();
    let bodies = (0..bodies)
        .map(|b| {
            let phase = b as f64 * 0.1;
            let (positions, rotations) = times
                .iter()
                .map(|&t| {
                    let a = 10.0 * t + phase;
                    let (s, c) = (a / 2.0).sin_cos();
                    ([a.cos(), a.sin(), 0.01 * b as f64], [c, 0.0, 0.0, s])
                })
                .unzip();
            Body {
                name: format!("body{b}"),
                colour: cardan_report::palette_colour(b),
                geometry: vec![
                    Geometry::at(Shape::Sphere { radius: 0.02 }, [0.0; 3]),
                    Geometry::at(
                        Shape::Cylinder {
                            radius: 0.01,
                            length: 0.2,
                        },
                        [0.0, 0.0, 0.1],
                    ),
                ],
                points: vec![
                    NamedPoint {
                        name: "A".into(),
                        local: [0.1, 0.0, 0.0],
                    },
                    NamedPoint {
                        name: "B".into(),
                        local: [0.0, 0.0, 0.2],
                    },
                ],
                positions,
                rotations,
            }
        })
        .collect();
    Scene {
        name: "bench".into(),
        times,
        bodies,
        axes: Vec::new(),
        extent: 2.0,
    }
}

/// The report section: time to write the glb and the page per size, and the log-log slope
/// of the time against frames × bodies (1 = linear).
pub fn section(smoke: bool, batch: Duration, batches: usize) -> String {
    let sizes: &[(usize, usize)] = if smoke {
        &[(2, 10), (4, 40)]
    } else {
        &[(5, 200), (5, 2000), (20, 2000), (20, 20000), (100, 20000)]
    };
    let mut md = String::new();
    let _ = writeln!(
        md,
        "### Animation and report (animation.glb, index.html)\n\n\
         Synthetic scenes (each body: a sphere, a rod, two named points; a new pose every frame). \
         *glb*: `cardan_report::write_glb`; *page*: `write_html` (three.js, 0.67 MB, is a constant \
         part of it).\n\n\
         | bodies | frames | frames × bodies | glb | page | glb + page per frame·body | glb size | page size |\n\
         |---:|---:|---:|---:|---:|---:|---:|---:|"
    );
    let mut points = Vec::new();
    for &(b, f) in sizes {
        let s = scene(b, f);
        let glb = write_glb(&s).expect("a valid scene");
        let page = Page::default();
        let html = write_html(&s, &glb, &page).expect("the page");
        let t_glb = time_per_call(
            || {
                std::hint::black_box(write_glb(&s).ok());
            },
            batch,
            batches,
        );
        let t_html = time_per_call(
            || {
                std::hint::black_box(write_html(&s, &glb, &page).ok());
            },
            batch,
            batches,
        );
        let n = (b * f) as f64;
        points.push((n, t_glb + t_html));
        eprintln!(
            "animation {b} bodies × {f} frames: glb {}, page {}",
            fmt_time(t_glb),
            fmt_time(t_html)
        );
        let _ = writeln!(
            md,
            "| {b} | {f} | {} | {} | {} | {} | {} | {} |",
            b * f,
            fmt_time(t_glb),
            fmt_time(t_html),
            fmt_time((t_glb + t_html) / n),
            fmt_bytes(glb.len() as u64),
            fmt_bytes(html.len() as u64)
        );
    }
    let big: Vec<(f64, f64)> = points
        .iter()
        .copied()
        .filter(|(n, _)| *n >= 10_000.0)
        .collect();
    let slope = loglog_slope(if big.len() >= 2 { &big } else { &points });
    let _ = writeln!(
        md,
        "\nLog-log slope of (glb + page) time against frames × bodies (from 10⁴ on, where the \
         constant part no longer dominates): {slope:.2} (1 = linear).\n"
    );
    md
}
