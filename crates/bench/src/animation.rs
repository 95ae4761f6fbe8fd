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

/// Per bundled example: the wall time of a whole `cardan run` (analysis and every file, into a
/// temporary directory) and of writing its animation and page alone (scene, glb, html: what
/// the run adds for them), median of `repeats` runs, with the file sizes.
pub fn examples_section(examples: &std::path::Path, smoke: bool) -> String {
    let mut files: Vec<std::path::PathBuf> = std::fs::read_dir(examples)
        .map(|d| d.filter_map(|e| e.ok().map(|e| e.path())).collect())
        .unwrap_or_default();
    files.retain(|p| p.extension().is_some_and(|e| e == "toml"));
    files.sort();
    if smoke {
        files.retain(|p| p.ends_with("slider_crank.toml"));
    }
    let repeats = if smoke { 1 } else { 3 };
    let mut md = String::from(
        "Bundled examples (`cardan run`, release build): the whole run (analysis, CSV, SVG, \
         animation, page, run.json) against writing the animation and the page alone (building \
         the scene, `write_glb`, `write_html`), medians of 3 runs (1 for a run over 2 s).\n\n\
         | example | bodies | frames | whole run | animation + page | share | glb size | page size |\n\
         |---|---:|---:|---:|---:|---:|---:|---:|\n",
    );
    let tmp = std::env::temp_dir().join(format!("cardan-bench-anim-{}", std::process::id()));
    for path in files {
        let name = path
            .file_stem()
            .unwrap_or_default()
            .to_string_lossy()
            .to_string();
        let mut whole = Vec::new();
        let mut write = Vec::new();
        let mut sizes = (0, 0, 0, 0);
        for _ in 0..repeats {
            let _ = std::fs::remove_dir_all(&tmp);
            let t0 = std::time::Instant::now();
            let Ok(o) = cardan_cli::commands::run::run_model(&path, Some(&tmp), false) else {
                break;
            };
            let elapsed = t0.elapsed().as_secs_f64();
            whole.push(elapsed);
            let t1 = std::time::Instant::now();
            let Ok(declared) = o.prepared.geometry.declared() else {
                break;
            };
            let scene = cardan_model::scene::scene(
                &o.prepared.loaded.name,
                &o.prepared.model,
                &o.results,
                &declared,
            );
            let glb = write_glb(&scene).unwrap_or_default();
            let html = write_html(&scene, &glb, &Page::default()).unwrap_or_default();
            write.push(t1.elapsed().as_secs_f64());
            sizes = (
                scene.bodies.len() - 1,
                scene.times.len(),
                glb.len(),
                html.len(),
            );
            if elapsed > 2.0 {
                // A long run once is enough (its share is tiny anyway).
                break;
            }
        }
        let _ = std::fs::remove_dir_all(&tmp);
        if whole.is_empty() || write.is_empty() {
            eprintln!("{name}: did not run; skipped");
            continue;
        }
        let (w, a) = (
            crate::measure::median(&mut whole),
            crate::measure::median(&mut write),
        );
        eprintln!(
            "{name}: run {}, animation + page {} ({:.1} %)",
            fmt_time(w),
            fmt_time(a),
            100.0 * a / w
        );
        let _ = writeln!(
            md,
            "| {name} | {} | {} | {} | {} | {:.1} % | {} | {} |",
            sizes.0,
            sizes.1,
            fmt_time(w),
            fmt_time(a),
            100.0 * a / w,
            fmt_bytes(sizes.2 as u64),
            fmt_bytes(sizes.3 as u64)
        );
    }
    md.push('\n');
    md
}
