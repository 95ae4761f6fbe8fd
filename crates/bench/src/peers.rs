// Included into main.rs as the module `cardan_bench_peers` (uses the parent's helpers).
//
// Peers side by side: OndselSolver (pyondsel, kinematics) and Exudyn (dynamics) run through
// `bench/peers/peers.py` in the Python given on the command line, alternately with cardan on the
// same machine, the same models at matched accuracy.

use super::{get, FrameRun};
use cardan_bench::measure::{fmt_time, median};
use cardan_bench::models;
use cardan_dynamics::{
    Dynamics, Force, GeneralizedAlphaOptions, Integrator, IterationMatrix, SimulationOptions,
    State,
};
use cardan_mechanism::{Model, Outputs};
use nalgebra::Vector3;
use std::fmt::Write as _;
use std::path::Path;
use std::process::Command;
use std::time::Instant;

fn call(python: &str, script: &Path, args: &[&str]) -> Result<Vec<(String, f64)>, String> {
    let o = Command::new(python)
        .arg(script)
        .args(args)
        .output()
        .map_err(|e| format!("cannot start {python}: {e}"))?;
    let out = String::from_utf8_lossy(&o.stdout);
    let Some(line) = out.lines().find(|l| l.starts_with("RESULT ")) else {
        let err = String::from_utf8_lossy(&o.stderr);
        let last: Vec<&str> = err.lines().rev().take(3).collect();
        return Err(format!(
            "{} {}: no result ({})",
            script.display(),
            args.join(" "),
            last.into_iter().rev().collect::<Vec<_>>().join(" / ")
        ));
    };
    Ok(line[7..]
        .split_whitespace()
        .filter_map(|kv| {
            let (k, v) = kv.split_once('=')?;
            Some((k.to_string(), v.parse().unwrap_or(f64::NAN)))
        })
        .collect())
}

/// The peers section of the report.
pub fn run(smoke: bool, python: &str, root: &Path) -> String {
    let script = root.join("bench/peers/peers.py");
    let mut md = String::from("### Peers side by side\n\n");
    let versions = match Command::new(python).arg(&script).arg("check").output() {
        Ok(o) if o.status.success() => String::from_utf8_lossy(&o.stdout)
            .lines()
            .find(|l| l.starts_with("RESULT "))
            .map(|l| l[7..].replace(' ', ", "))
            .unwrap_or_default(),
        Ok(o) => {
            let msg = format!(
                "Peers not available: `{python} bench/peers/peers.py check` failed: {}",
                String::from_utf8_lossy(&o.stderr).lines().last().unwrap_or("")
            );
            eprintln!("{msg}");
            let _ = writeln!(md, "{msg}\n");
            return md;
        }
        Err(e) => {
            let msg = format!("Peers not available: cannot run {python}: {e}");
            eprintln!("{msg}");
            let _ = writeln!(md, "{msg}\n");
            return md;
        }
    };
    let _ = writeln!(
        md,
        "Versions: {versions} (PyPI, `bench/peers/requirements.txt`), Python {}. Same machine, \
         cardan and the peer run alternately (cardan, peer, cardan, peer, …), medians. Peer \
         times are measured inside Python around the solver call only (no interpreter start-up, \
         no model building). Models: `bench/peers/peers.py` (peer) and \
         `examples/slider_crank.toml`, `crates/bench/src/models.rs` (cardan).\n",
        Command::new(python)
            .arg("-V")
            .output()
            .map(|o| String::from_utf8_lossy(&o.stdout).trim().replace("Python ", ""))
            .unwrap_or_default()
    );
    md.push_str(&slider_crank_kinematics(smoke, python, &script));
    md.push_str(&chain_dynamics(smoke, python, &script));
    md
}

fn slider_crank_kinematics(smoke: bool, python: &str, script: &Path) -> String {
    let mut md = String::new();
    let path = super::root().join("examples/slider_crank.toml");
    let Ok(p) = cardan_cli::commands::prepare(&path) else {
        return "slider_crank.toml not found\n\n".into();
    };
    let frames = 200;
    let rounds = if smoke { 1 } else { 5 };
    let mut cardan = Vec::new();
    let mut peer = Vec::new();
    let mut last = Vec::new();
    let times: Vec<f64> = (0..=frames).map(|k| k as f64 / frames as f64).collect();
    for _ in 0..rounds {
        // cardan: the same 200 frames from t = 0 to 1 (position, velocity, acceleration).
        let model: &Model = &p.model;
        let mut run =
            FrameRun::new(model, times.clone(), Model::kinematic_newton_options()).expect("prepare");
        let t0 = Instant::now();
        for _ in 0..frames {
            run.frame(true);
        }
        cardan.push(t0.elapsed().as_secs_f64() / frames as f64);
        match call(python, script, &["ondsel-slider-crank", &frames.to_string()]) {
            Ok(r) => {
                peer.push(get(&r, "per_frame"));
                last = r;
            }
            Err(e) => {
                let _ = writeln!(md, "OndselSolver slider-crank failed: {e}\n");
                return md;
            }
        }
    }
    // Agreement at t = 0.25 and 0.5 (slider x).
    let mut ws_model = FrameRun::new(&p.model, vec![0.0], Model::kinematic_newton_options())
        .expect("prepare");
    let mut x_at = |t: f64| {
        for k in 1..=50 {
            p.model
                .position(&mut ws_model.ws, t * k as f64 / 50.0)
                .expect("position");
        }
        let slider = p.model.body_id("slider").expect("slider");
        ws_model
            .ws
            .point_position(slider, &Vector3::zeros())
            .x
    };
    let dx = (x_at(0.25) - get(&last, "x_quarter"))
        .abs()
        .max((x_at(0.5) - get(&last, "x_half")).abs());
    let c = median(&mut cardan);
    let o = median(&mut peer);
    let _ = writeln!(
        md,
        "**Kinematics: spatial slider-crank, OndselSolver (pyondsel).** {frames} frames over one \
         crank turn, position + velocity + acceleration per frame. OndselSolver: errorTol 1e-10, \
         time per frame = (solve of {frames} frames − solve of 1 frame) / {} (assembly and setup \
         excluded); cardan: default tolerance (scaled residual 1e-10), frames of the same grid. \
         Slider positions agree to {dx:.1e} m.\n\n\
         | | time per frame | ratio (OndselSolver / cardan) | target |\n|---|---:|---:|---|\n\
         | cardan | {} | | |\n| OndselSolver | {} | **{:.0}×** | ≥ 100× {} |\n",
        frames - 1,
        fmt_time(c),
        fmt_time(o),
        o / c,
        if o / c >= 100.0 { "met" } else { "**missed**" }
    );
    md
}

struct ChainRun {
    wall: f64,
    tip: Vector3<f64>,
    b0: Vector3<f64>,
}

fn cardan_chain(model: &Model, h: f64, t_end: f64, integ: Option<Integrator>) -> ChainRun {
    let mut d = Dynamics::new(model).expect("dynamics");
    d.add_force(Force::gravity(Vector3::new(0.0, 0.0, -9.81)))
        .expect("gravity");
    let s = State::initial(model, 0.0);
    let integ = integ.unwrap_or(Integrator::GeneralizedAlpha(GeneralizedAlphaOptions {
        iteration_matrix: IterationMatrix::MassOnly,
        rho_inf: 0.8,
        ..GeneralizedAlphaOptions::with_step(h)
    }));
    let opts = SimulationOptions::new(t_end, 1)
        .integrator(integ)
        .output_times(vec![t_end])
        .outputs(Outputs::position_only());
    let t0 = Instant::now();
    d.prepare(&s).expect("prepare");
    let r = d.simulate_consistent(s, &opts).expect("simulate");
    let wall = t0.elapsed().as_secs_f64();
    let n = model.num_bodies();
    let tip = *r
        .point(&format!("b{}", n - 1), "b")
        .expect("tip")
        .position
        .last()
        .expect("tip");
    let b0 = *r.point("b0", "b").expect("b0").position.last().expect("b0");
    ChainRun { wall, tip, b0 }
}

fn chain_dynamics(smoke: bool, python: &str, script: &Path) -> String {
    let mut md = String::new();
    let _ = writeln!(
        md,
        "**Dynamics: chain of N spherical-joint links, Exudyn.** Rods along +x at rest, gravity \
         −z, both codes with generalized-α (ρ∞ = 0.8), fixed step h, sparse linear solver \
         (cardan: mass-only iteration matrix; Exudyn: its defaults, EigenSparse). Error: max \
         over the far ends of the first and last links of the distance to a cardan DOPRI5 \
         reference (rtol 1e-10) at t_end. Time: the whole integration (initial accelerations \
         included), model building excluded. *Ratio at equal error*: Exudyn's time over cardan's \
         time at the same error (log-log interpolation between cardan's runs; — outside their \
         range).\n\n\
         | N | t_end | h | cardan time | cardan error [m] | Exudyn time | Exudyn error [m] | ratio same h | ratio at equal error |\n\
         |---:|---:|---:|---:|---:|---:|---:|---:|---:|"
    );
    let sizes: &[usize] = if smoke { &[10] } else { &[10, 100, 1000] };
    let steps: &[f64] = if smoke {
        &[2e-3]
    } else {
        &[4e-3, 2e-3, 1e-3, 5e-4]
    };
    let rounds = if smoke { 1 } else { 3 };
    let mut summary = Vec::new();
    for &n in sizes {
        let t_end = if n >= 1000 { 0.1 } else { 0.2 };
        let model = models::spherical_chain(n);
        let reference = cardan_chain(
            &model,
            0.0,
            t_end,
            Some(Integrator::Dopri5(cardan_dynamics::Dopri5Options::tolerances(
                1e-10, 1e-12,
            ))),
        );
        let err = |tip: Vector3<f64>, b0: Vector3<f64>| {
            (tip - reference.tip).norm().max((b0 - reference.b0).norm())
        };
        let mut rows = Vec::new();
        for &h in steps {
            let mut ct = Vec::new();
            let mut xt = Vec::new();
            let mut ce = f64::NAN;
            let mut xe = f64::NAN;
            for _ in 0..rounds {
                let c = cardan_chain(&model, h, t_end, None);
                ct.push(c.wall);
                ce = err(c.tip, c.b0);
                match call(
                    python,
                    script,
                    &["exudyn-chain", &n.to_string(), &h.to_string(), &t_end.to_string()],
                ) {
                    Ok(r) => {
                        xt.push(get(&r, "wall"));
                        xe = err(
                            Vector3::new(get(&r, "tip_x"), get(&r, "tip_y"), get(&r, "tip_z")),
                            Vector3::new(get(&r, "b0_x"), get(&r, "b0_y"), get(&r, "b0_z")),
                        );
                    }
                    Err(e) => {
                        let _ = writeln!(md, "\nExudyn chain N = {n} failed: {e}\n");
                        return md;
                    }
                }
            }
            rows.push((h, median(&mut ct), ce, median(&mut xt), xe));
        }
        // cardan's time at a given error: log-log interpolation of its (error, time) curve.
        let mut curve: Vec<(f64, f64)> = rows.iter().map(|r| (r.2.ln(), r.1.ln())).collect();
        curve.sort_by(|a, b| a.0.total_cmp(&b.0));
        let time_at = |e: f64| -> f64 {
            let le = e.ln();
            curve
                .windows(2)
                .find(|w| w[0].0 <= le && le <= w[1].0)
                .map_or(f64::NAN, |w| {
                    let f = if w[1].0 > w[0].0 {
                        (le - w[0].0) / (w[1].0 - w[0].0)
                    } else {
                        0.0
                    };
                    (w[0].1 + f * (w[1].1 - w[0].1)).exp()
                })
        };
        for &(h, c, ce, x, xe) in &rows {
            let eq = x / time_at(xe);
            summary.push((n, eq));
            let _ = writeln!(
                md,
                "| {n} | {t_end} | {h:.0e} | {} | {ce:.1e} | {} | {xe:.1e} | {:.1}× | {} |",
                fmt_time(c),
                fmt_time(x),
                x / c,
                if eq.is_finite() {
                    format!("**{eq:.1}×**")
                } else {
                    "—".into()
                }
            );
        }
        eprintln!("peers: chain {n} done");
    }
    md.push('\n');
    for n in sizes {
        let v: Vec<f64> = summary
            .iter()
            .filter(|s| s.0 == *n && s.1.is_finite())
            .map(|s| s.1)
            .collect();
        if let (Some(lo), Some(hi)) = (
            v.iter().copied().reduce(f64::min),
            v.iter().copied().reduce(f64::max),
        ) {
            let _ = writeln!(
                md,
                "- N = {n}: cardan is {lo:.1}–{hi:.1}× faster than Exudyn at equal error (target ≥ 10×: {}).",
                if lo >= 10.0 { "met" } else if hi >= 10.0 { "met at some accuracies" } else { "**missed**" }
            );
        }
    }
    md.push('\n');
    md
}
