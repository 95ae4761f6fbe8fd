// Included into main.rs as the module `cardan_bench_peers` (uses the parent's helpers).
//
// Peers side by side: OndselSolver (pyondsel, kinematics) and Exudyn (dynamics) run through
// `bench/peers/peers.py` in the Python given on the command line, alternately with cardan on the
// same machine, the same models at matched accuracy.
//
// Parts: `kinematics` (slider-crank frames vs OndselSolver), `slider-crank` (IFToMM spatial
// slider-crank dynamics vs Exudyn at equal error: for each Exudyn step h, the cheapest cardan
// generalized-α (mass-only and tangent iteration matrix) and DOPRI5 runs reaching Exudyn's max
// position error), `chain` (N-link spherical chain vs Exudyn).
//
// To rerun the peers alone (no other benchmark, docs/performance.md untouched; the markdown goes
// to stdout, progress to stderr):
//
//   cargo build --release -p cardan-bench
//   target/release/cardan-bench --peers-only target/peers-venv/bin/python [--smoke] [PART ...]
//
// e.g. `... --peers-only target/peers-venv/bin/python slider-crank`. The venv is the one
// `cargo xtask bench --peers` creates. `--smoke`: one short run of each (numbers not
// representative).

use super::{get, FrameRun};
use cardan_bench::measure::{fmt_time, median};
use cardan_bench::models;
use cardan_model::prepare::Prepared;
use cardan_dynamics::{
    Dynamics, Force, GeneralizedAlphaOptions, Integrator, IterationMatrix, SimulationOptions, State,
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

/// `cardan-bench --peers-only PYTHON [--smoke] [PART ...]`: the peers section (only the given
/// parts, all without), printed to stdout.
pub fn peers_only(args: &[String]) {
    let Some(python) = args.first().filter(|a| !a.starts_with("--")) else {
        eprintln!(
            "usage: cardan-bench --peers-only PYTHON [--smoke] [kinematics|slider-crank|chain ...]"
        );
        std::process::exit(2);
    };
    let smoke = args.iter().any(|a| a == "--smoke");
    let parts: Vec<&str> = args[1..]
        .iter()
        .map(String::as_str)
        .filter(|a| *a != "--smoke")
        .collect();
    for p in &parts {
        if !PARTS.contains(p) {
            eprintln!("unknown peers part {p} (one of {})", PARTS.join(", "));
            std::process::exit(2);
        }
    }
    print!("{}", run_parts(smoke, python, &super::root(), &parts));
}

const PARTS: &[&str] = &[
    "kinematics",
    "slider-crank",
    "chain",
    "cli-genalpha",
    "cli-genalpha-slider-crank",
    "cli-genalpha-chain",
];

/// The peers section of the report.
pub fn run(smoke: bool, python: &str, root: &Path) -> String {
    run_parts(smoke, python, root, &[])
}

/// The peers section with only `parts` (all if empty).
fn run_parts(smoke: bool, python: &str, root: &Path, parts: &[&str]) -> String {
    let want = |p: &str| parts.is_empty() || parts.contains(&p);
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
                String::from_utf8_lossy(&o.stderr)
                    .lines()
                    .last()
                    .unwrap_or("")
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
    let _ =
        writeln!(
        md,
        "Versions: {versions} (PyPI, `bench/peers/requirements.txt`), Python {}. Same machine, \
         cardan and the peer run alternately (cardan, peer, cardan, peer, …), medians. Peer \
         times are measured inside Python around the solver call only (no interpreter start-up, \
         no model building). Models: `bench/peers/peers.py` (peer) and \
         `examples/slider_crank.toml`, `examples/slider_crank_dynamic.toml`, \
         `crates/bench/src/models.rs` (cardan).\n",
        Command::new(python)
            .arg("-V")
            .output()
            .map(|o| String::from_utf8_lossy(&o.stdout).trim().replace("Python ", ""))
            .unwrap_or_default()
    );
    if want("kinematics") {
        md.push_str(&slider_crank_kinematics(smoke, python, &script));
    }
    if want("slider-crank") {
        md.push_str(&slider_crank_dynamics(smoke, python, &script, root));
    }
    if want("chain") {
        md.push_str(&chain_dynamics(smoke, python, &script));
    }
    let (sc, chain) = (
        want("cli-genalpha") || want("cli-genalpha-slider-crank"),
        want("cli-genalpha") || want("cli-genalpha-chain"),
    );
    if sc || chain {
        md.push_str(&cli_genalpha(smoke, python, &script, root, sc, chain));
    }
    md
}

fn slider_crank_kinematics(smoke: bool, python: &str, script: &Path) -> String {
    let mut md = String::new();
    let path = super::root().join("examples/slider_crank.toml");
    let Ok(p) = cardan_model::prepare::prepare(&path) else {
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
        let mut run = FrameRun::new(model, times.clone(), Model::kinematic_newton_options())
            .expect("prepare");
        let t0 = Instant::now();
        for _ in 0..frames {
            run.frame(true);
        }
        cardan.push(t0.elapsed().as_secs_f64() / frames as f64);
        match call(
            python,
            script,
            &["ondsel-slider-crank", &frames.to_string()],
        ) {
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
    let mut ws_model =
        FrameRun::new(&p.model, vec![0.0], Model::kinematic_newton_options()).expect("prepare");
    let mut x_at = |t: f64| {
        for k in 1..=50 {
            p.model
                .position(&mut ws_model.ws, t * k as f64 / 50.0)
                .expect("position");
        }
        let slider = p.model.body_id("slider").expect("slider");
        ws_model.ws.point_position(slider, &Vector3::zeros()).x
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

/// Time at error `e` on a curve of (error, time) runs: log-log interpolation between the two
/// runs whose errors bracket `e` (NaN outside the curve).
fn time_at(runs: &[(f64, f64)], e: f64) -> f64 {
    let mut curve: Vec<(f64, f64)> = runs
        .iter()
        .filter(|r| r.0 > 0.0 && r.0.is_finite())
        .map(|r| (r.0.ln(), r.1.ln()))
        .collect();
    curve.sort_by(|a, b| a.0.total_cmp(&b.0));
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
}

/// A ratio in bold ("—" when not finite).
fn bold_ratio(r: f64) -> String {
    if r.is_finite() {
        format!("**{r:.1}×**")
    } else {
        "—".into()
    }
}

fn chain_dynamics(smoke: bool, python: &str, script: &Path) -> String {
    let mut md = String::new();
    let _ = writeln!(
        md,
        "**Dynamics: chain of N spherical-joint links, Exudyn.** Rods along +x at rest, gravity \
         −z. Exudyn: generalized-α (ρ∞ = 0.8), fixed step h, its defaults otherwise \
         (EigenSparse). cardan: generalized-α with the same ρ∞ and h (mass-only iteration \
         matrix), and DOPRI5 with rtol = 1e-3 … 1e-8 (atol = rtol/100). Error: max over the far \
         ends of the first and last links of the distance to a cardan DOPRI5 reference \
         (rtol 1e-10) at t_end. Time: the whole integration (initial accelerations included), \
         model building excluded, median of the rounds. *Ratio at equal error*: Exudyn's time \
         over cardan's time at Exudyn's error (log-log interpolation along cardan's runs of \
         that integrator; — outside their range).\n\n\
         | N | t_end | h | cardan gen-α time | cardan gen-α error [m] | Exudyn time | Exudyn error [m] | gen-α ratio same h | gen-α ratio at equal error | DOPRI5 ratio at equal error |\n\
         |---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|"
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
            Some(Integrator::Dopri5(
                cardan_dynamics::Dopri5Options::tolerances(1e-10, 1e-12),
            )),
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
                    &[
                        "exudyn-chain",
                        &n.to_string(),
                        &h.to_string(),
                        &t_end.to_string(),
                    ],
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
        // cardan's time at a given error: log-log interpolation of its (error, time) curves,
        // generalized-α (the runs above) and DOPRI5 (a tolerance ladder).
        let ga: Vec<(f64, f64)> = rows.iter().map(|r| (r.2, r.1)).collect();
        let dopri_tols: &[f64] = if smoke {
            &[1e-5]
        } else {
            &[1e-3, 1e-4, 1e-5, 1e-6, 1e-7, 1e-8]
        };
        let dopri: Vec<(f64, f64)> = dopri_tols
            .iter()
            .map(|&rtol| {
                let integ = Integrator::Dopri5(cardan_dynamics::Dopri5Options::tolerances(
                    rtol,
                    rtol * 1e-2,
                ));
                let mut t = Vec::new();
                let mut e = f64::NAN;
                for _ in 0..rounds {
                    let c = cardan_chain(&model, 0.0, t_end, Some(integ));
                    t.push(c.wall);
                    e = err(c.tip, c.b0);
                }
                (e, median(&mut t))
            })
            .collect();
        for &(h, c, ce, x, xe) in &rows {
            let eq = x / time_at(&ga, xe);
            let eq_dopri = x / time_at(&dopri, xe);
            summary.push((n, eq.max(eq_dopri)));
            let _ = writeln!(
                md,
                "| {n} | {t_end} | {h:.0e} | {} | {ce:.1e} | {} | {xe:.1e} | {:.1}× | {} | {} |",
                fmt_time(c),
                fmt_time(x),
                x / c,
                bold_ratio(eq),
                bold_ratio(eq_dopri),
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
                "- N = {n}: cardan (the faster of its two integrators at each accuracy) is {lo:.1}–{hi:.1}× faster than Exudyn at equal error (target ≥ 10×: {}).",
                if lo >= 10.0 { "met" } else if hi >= 10.0 { "met at some accuracies" } else { "**missed**" }
            );
        }
    }
    md.push('\n');
    md
}

// ---------------------------------------------------------------------------------------------
// Dynamics: IFToMM spatial slider-crank, cardan against Exudyn at equal error.

/// The reference table (t, x_slider, θ_crank, …) both codes are measured against.
const SLIDER_CRANK_CSV: &str = "tests/data/benchmarks/spatial_slider_crank_crankCoM_mid.csv";

/// One cardan run of the slider-crank: wall time of `simulate` (consistent initial conditions
/// included), accepted steps, max position error.
#[derive(Clone, Copy)]
struct ScRun {
    wall: f64,
    steps: usize,
    err: f64,
}

struct SliderCrank {
    p: Prepared,
    /// Rows (t, x_ref, θ_ref) up to t_end.
    reference: Vec<[f64; 3]>,
    /// The output grid: the reference times as a uniform grid (as the benchmark test does).
    times: Vec<f64>,
    t_end: f64,
}

impl SliderCrank {
    /// The max over the reference samples of |C − (x_ref, 0, 0)| and |B − B_ref(θ_ref)|, as
    /// tests/tests/benchmark_slider_crank.rs computes it.
    fn run(&self, integ: Integrator) -> Option<ScRun> {
        let mut opts = cardan_model::analysis::dynamic::options(&self.p, Some(integ)).ok()?;
        opts.t_end = self.t_end;
        opts.max_steps = 5_000_000;
        let opts = opts
            .output_times(self.times.clone())
            .outputs(Outputs::position_only());
        let mut d = cardan_model::analysis::dynamic::dynamics(&self.p).ok()?;
        let s = cardan_model::analysis::dynamic::initial_state(&self.p);
        let t0 = Instant::now();
        let r = d.simulate(&s, &opts).ok()?;
        let wall = t0.elapsed().as_secs_f64();
        let b = &r.point("crank", "B")?.position;
        let c = &r.point("slider", "C")?.position;
        let mut err = 0.0f64;
        for (k, &[_, x, th]) in self.reference.iter().enumerate() {
            let b_ref = Vector3::new(0.0, 0.1 - 0.08 * th.sin(), 0.12 + 0.08 * th.cos());
            err = err
                .max((b.get(k)? - b_ref).norm())
                .max((c.get(k)? - Vector3::new(x, 0.0, 0.0)).norm());
        }
        Some(ScRun {
            wall,
            steps: r.stats.steps,
            err,
        })
    }
}

/// A cardan integrator family and its settings from cheapest to most accurate.
struct Ladder {
    name: &'static str,
    settings: Vec<(String, Integrator)>,
    /// Runs made so far (None: not run yet; Some(None): failed).
    runs: Vec<Option<Option<ScRun>>>,
}

impl Ladder {
    /// The run of setting `k` (made on first use).
    fn get(&mut self, sc: &SliderCrank, k: usize) -> Option<ScRun> {
        *self.runs[k].get_or_insert_with(|| sc.run(self.settings[k].1))
    }

    /// The first (cheapest) setting whose error is at most `target` and so is the next finer
    /// setting's (a lucky cancellation at one setting does not count), running settings as
    /// needed.
    fn reach(&mut self, sc: &SliderCrank, target: f64) -> Option<usize> {
        let n = self.settings.len();
        let ok = |r: Option<ScRun>| r.is_some_and(|r| r.err <= target);
        (0..n).find(|&k| ok(self.get(sc, k)) && (k + 1 == n || ok(self.get(sc, k + 1))))
    }
}

/// Ladders of generalized-α (ρ∞ = 0.9 as Exudyn's default, mass-only and tangent iteration
/// matrix; h = output spacing / n so that the steps tile the output grid) and DOPRI5 (rtol
/// every half decade, atol = rtol / 100).
fn ladders(spacing: f64) -> Vec<Ladder> {
    let per_output = [
        1, 2, 4, 5, 8, 10, 16, 20, 25, 40, 50, 80, 100, 125, 160, 200, 250, 400, 500,
    ];
    let ga = |m: IterationMatrix| -> Vec<(String, Integrator)> {
        per_output
            .iter()
            .map(|&n| {
                let h = spacing / f64::from(n);
                (
                    format!("h {h:.3e}"),
                    Integrator::GeneralizedAlpha(GeneralizedAlphaOptions {
                        iteration_matrix: m,
                        rho_inf: 0.9,
                        ..GeneralizedAlphaOptions::with_step(h)
                    }),
                )
            })
            .collect()
    };
    let dopri: Vec<(String, Integrator)> = (6..=24)
        .map(|k| {
            let rtol = 10f64.powf(-f64::from(k) / 2.0);
            (
                format!("rtol {rtol:.1e}"),
                Integrator::Dopri5(cardan_dynamics::Dopri5Options::tolerances(
                    rtol,
                    rtol * 1e-2,
                )),
            )
        })
        .collect();
    [
        ("gen-α, mass-only matrix", ga(IterationMatrix::MassOnly)),
        ("gen-α, tangent matrix", ga(IterationMatrix::Tangent)),
        ("DOPRI5 (adaptive)", dopri),
    ]
    .into_iter()
    .map(|(name, settings)| Ladder {
        name,
        runs: vec![None; settings.len()],
        settings,
    })
    .collect()
}

/// "cardan is X× faster" (X < 1: slower).
fn faster(r: f64) -> String {
    if !r.is_finite() {
        "—".into()
    } else if r >= 10.0 {
        format!("**{r:.1}×**")
    } else {
        format!("{r:.2}×")
    }
}

fn slider_crank_dynamics(smoke: bool, python: &str, script: &Path, root: &Path) -> String {
    let mut md = String::new();
    let ScProblem { sc, spacing, csv } = match slider_crank_problem(smoke, root) {
        Ok(problem) => problem,
        Err(message) => return message,
    };
    let t_end = sc.t_end;
    let peer_steps: &[f64] = if smoke {
        &[2e-3]
    } else {
        &[2e-3, 1e-3, 5e-4, 2.5e-4]
    };
    let rounds = if smoke { 1 } else { 3 };
    let _ = writeln!(
        md,
        "**Dynamics at equal error: IFToMM spatial slider-crank, Exudyn.** \
         `examples/slider_crank_dynamic.toml` and its Exudyn twin (`peers.py \
         exudyn-slider-crank`: Euler-parameter rigid bodies, revolute, spherical, generic joint \
         with one locked rotation as the universal joint, prismatic), free motion under gravity \
         for {t_end} s. Error: max over the {} reference samples (every {spacing} s, \
         `{SLIDER_CRANK_CSV}`) of the slider and crank-tip position errors, the same formula \
         for both codes (`tests/tests/benchmark_slider_crank.rs`). Exudyn: generalized-α with \
         its default settings (ρ∞ 0.9, modified Newton, relative tolerance 1e-8, dense solver), \
         fixed step h. cardan: for each Exudyn run, the cheapest setting of each integrator \
         whose error is at most Exudyn's, and so is the next finer setting's (settings tried \
         from coarse to fine: gen-α ρ∞ 0.9 with h = {spacing} s / n, default Newton options; \
         DOPRI5 rtol every half decade, atol = rtol/100). Time: the whole \
         integration (initial accelerations included, model building excluded), median of \
         {rounds} alternating runs; per step: time / accepted steps (a DOPRI5 step is 6 \
         right-hand sides plus a projection, not the same work as an implicit step). Ratios: \
         Exudyn's time over cardan's, i.e. *cardan is X× faster* (below 1: slower).\n\n\
         | Exudyn h | Exudyn error [m] | Exudyn time | Exudyn / step | cardan integrator | setting | cardan error [m] | cardan time | cardan / step | whole run: cardan is … faster | per step: cardan is … faster |\n\
         |---:|---:|---:|---:|---|---:|---:|---:|---:|---:|---:|",
        sc.reference.len(),
    );
    let mut ladders = ladders(spacing);
    let csv_arg = csv.to_string_lossy().to_string();
    let peer = ScPeer {
        python,
        script,
        csv: &csv_arg,
        rounds,
    };
    let mut summary = Vec::new();
    for &h in peer_steps {
        match slider_crank_at(&sc, &peer, &mut ladders, h, &mut md) {
            Ok(best) => summary.extend(best),
            Err(message) => {
                let _ = writeln!(md, "{message}");
                return md;
            }
        }
        eprintln!("peers: slider-crank Exudyn h = {h} done");
    }
    md.push('\n');
    for b in &summary {
        let _ = writeln!(
            md,
            "- Exudyn h = {:.1e} (error {:.1e} m): fastest cardan run at equal or smaller \
             error is {}; cardan is {:.1}× faster over the whole run and {:.1}× \
             per step (target ≥ 10×: {}).",
            b.h,
            b.error,
            b.integrator,
            b.whole,
            b.per_step,
            if b.whole >= 10.0 { "met" } else { "**missed**" }
        );
    }
    settings_tried(&mut md, &ladders);
    md.push('\n');
    md
}

/// The slider-crank benchmark as the peers section runs it.
struct ScProblem {
    /// The model and its reference up to the run's end time.
    sc: SliderCrank,
    /// The spacing of the reference samples (s).
    spacing: f64,
    /// The reference file.
    csv: std::path::PathBuf,
}

/// The slider-crank problem; `Err` with the text the section shows when a file is missing.
fn slider_crank_problem(smoke: bool, root: &Path) -> Result<ScProblem, String> {
    let csv = root.join(SLIDER_CRANK_CSV);
    let Ok(p) = cardan_model::prepare::prepare(&root.join("examples/slider_crank_dynamic.toml"))
    else {
        return Err("slider_crank_dynamic.toml not found\n\n".into());
    };
    let Some(rows) = std::fs::read_to_string(&csv).ok().map(|t| {
        t.lines()
            .filter(|l| !l.starts_with('#') && !l.trim().is_empty())
            .filter_map(|l| {
                let v: Vec<f64> = l.split(',').filter_map(|x| x.trim().parse().ok()).collect();
                (v.len() >= 3).then(|| [v[0], v[1], v[2]])
            })
            .collect::<Vec<_>>()
    }) else {
        return Err(format!("{SLIDER_CRANK_CSV} not found\n\n"));
    };
    let t_end = if smoke { 0.5 } else { 5.0 };
    let reference: Vec<[f64; 3]> = rows.into_iter().filter(|r| r[0] <= t_end + 1e-9).collect();
    let n = reference.len() - 1;
    let (t0, t1) = (reference[0][0], reference[n][0]);
    let times: Vec<f64> = (0..=n)
        .map(|k| t0 + (t1 - t0) * (k as f64 / n as f64))
        .collect();
    let spacing = (t1 - t0) / n as f64;
    let sc = SliderCrank {
        p,
        reference,
        times,
        t_end,
    };
    Ok(ScProblem { sc, spacing, csv })
}

/// How the Exudyn twin is run: the Python, the peers script, the reference file, and the
/// timing rounds.
struct ScPeer<'a> {
    python: &'a str,
    script: &'a Path,
    csv: &'a str,
    rounds: usize,
}

/// The fastest cardan run at the error of one Exudyn run.
struct ScBest {
    /// Exudyn's step.
    h: f64,
    /// Exudyn's error (m).
    error: f64,
    /// The cardan integrator.
    integrator: &'static str,
    /// Exudyn's time over cardan's, whole run and per step.
    whole: f64,
    per_step: f64,
}

/// One Exudyn step `h`: its error, the cheapest setting of each cardan integrator that
/// reaches it, both timed alternately, and a row per integrator in `md`. `Err`: Exudyn failed
/// (the message).
fn slider_crank_at(
    sc: &SliderCrank,
    peer: &ScPeer,
    ladders: &mut [Ladder],
    h: f64,
    md: &mut String,
) -> Result<Option<ScBest>, String> {
    let (python, script, csv_arg, rounds, t_end) =
        (peer.python, peer.script, peer.csv, peer.rounds, sc.t_end);
    // Exudyn's error at this h (deterministic), then the matching cardan settings.
    let exudyn = || {
        call(
            python,
            script,
            &[
                "exudyn-slider-crank",
                &h.to_string(),
                &t_end.to_string(),
                csv_arg,
            ],
        )
    };
    let first = match exudyn() {
        Ok(r) => r,
        Err(e) => return Err(format!("\nExudyn slider-crank h = {h} failed: {e}\n")),
    };
    let target = get(&first, "err");
    let x_steps = get(&first, "steps");
    let matched: Vec<Option<usize>> =
        ladders.iter_mut().map(|l| l.reach(sc, target)).collect();
    // Timing: cardan's matched runs and Exudyn, alternately.
    let mut xt = vec![get(&first, "wall")];
    let mut ct: Vec<Vec<f64>> = vec![Vec::new(); ladders.len()];
    let mut cruns: Vec<Option<ScRun>> = vec![None; ladders.len()];
    for round in 0..rounds {
        for (i, l) in ladders.iter().enumerate() {
            if let Some(k) = matched[i] {
                if let Some(r) = sc.run(l.settings[k].1) {
                    ct[i].push(r.wall);
                    cruns[i] = Some(r);
                }
            }
        }
        if round + 1 < rounds {
            if let Ok(r) = exudyn() {
                xt.push(get(&r, "wall"));
            }
        }
    }
    let x = median(&mut xt);
    let x_step = x / x_steps;
    let mut best: Option<(usize, f64, f64)> = None;
    for (i, l) in ladders.iter().enumerate() {
        let (Some(k), Some(r)) = (matched[i], cruns[i]) else {
            let _ = writeln!(
                md,
                "| {h:.1e} | {target:.2e} | {} | {} | {} | not reached (finest: {}) | | | | | |",
                fmt_time(x),
                fmt_time(x_step),
                l.name,
                l.settings.last().map_or("", |s| s.0.as_str())
            );
            continue;
        };
        let c = median(&mut ct[i]);
        let c_step = c / r.steps as f64;
        if best.is_none_or(|b| x / c > b.1) {
            best = Some((i, x / c, x_step / c_step));
        }
        let _ = writeln!(
            md,
            "| {h:.1e} | {target:.2e} | {} | {} | {} | {} | {:.2e} | {} ({} steps) | {} | {} | {} |",
            fmt_time(x),
            fmt_time(x_step),
            l.name,
            l.settings[k].0,
            r.err,
            fmt_time(c),
            r.steps,
            fmt_time(c_step),
            faster(x / c),
            faster(x_step / c_step),
        );
    }
    Ok(best.map(|b| ScBest {
        h,
        error: target,
        integrator: ladders[b.0].name,
        whole: b.1,
        per_step: b.2,
    }))
}

/// The error curves cardan's search went through (single runs), for reruns and plots.
fn settings_tried(md: &mut String, ladders: &[Ladder]) {
    let _ = writeln!(
        md,
        "\ncardan settings tried (one run each; error [m] / time):\n"
    );
    for l in ladders {
        let tried: Vec<String> = l
            .runs
            .iter()
            .zip(&l.settings)
            .filter_map(|(r, (s, _))| match r {
                Some(Some(r)) => Some(format!("{s}: {:.1e} / {}", r.err, fmt_time(r.wall))),
                Some(None) => Some(format!("{s}: failed")),
                None => None,
            })
            .collect();
        let _ = writeln!(md, "- {}: {}", l.name, tried.join("; "));
    }
}

use cardan_bench::measure::cardan_binary;

/// A whole `cardan run MODEL -o OUT` in its own process: wall time (reading the model, assembly,
/// the integration and every output file), or why it failed.
fn cardan_run(model: &Path, out: &Path) -> Result<f64, String> {
    let _ = std::fs::remove_dir_all(out);
    let t0 = Instant::now();
    let o = Command::new(cardan_binary())
        .arg("run")
        .arg(model)
        .arg("-o")
        .arg(out)
        .output()
        .map_err(|e| format!("cannot start {}: {e}", cardan_binary().display()))?;
    let wall = t0.elapsed().as_secs_f64();
    if !o.status.success() {
        return Err(String::from_utf8_lossy(&o.stderr).into_owned());
    }
    Ok(wall)
}

/// The rows of a CSV file written by `cardan run` (header skipped).
fn csv_rows(path: &Path) -> Vec<Vec<f64>> {
    std::fs::read_to_string(path)
        .unwrap_or_default()
        .lines()
        .skip(1)
        .map(|l| l.split(',').filter_map(|x| x.parse().ok()).collect())
        .collect()
}

/// The N-link spherical chain of [`models::spherical_chain`] as a model file: gravity −z,
/// generalized-α with step `h` and ρ∞ 0.8 for `t_end`, ten output times, the far ends of the
/// first and last links as outputs.
fn spherical_chain_toml(n: usize, h: f64, t_end: f64) -> String {
    let mut s = String::from(
        "[model]\nname = \"spherical_chain\"\nunits = \"SI\"\ngravity = [0.0, 0.0, -9.81]\n\n\
         [ground]\npoints = { O = [0.0, 0.0, 0.0] }\n",
    );
    cardan_bench::large::push_rods(&mut s, n, [0.001, 1.0 / 12.0, 1.0 / 12.0], "");
    for k in 0..n {
        let (prev, point) = if k == 0 {
            ("ground".to_string(), "O")
        } else {
            (format!("b{}", k - 1), "b")
        };
        let _ = write!(
            s,
            "\n[[joint]]\nname = \"s{k}\"\ntype = \"spherical\"\nbody_i = \"{prev}\"\n\
             point_i = \"{point}\"\nbody_j = \"b{k}\"\npoint_j = \"a\"\n"
        );
    }
    let _ = write!(
        s,
        "\n[analysis]\nkind = \"dynamic\"\nintegrator = \"generalized_alpha\"\ndt = {h:e}\n\
         rho_inf = 0.8\nt_end = {t_end:e}\noutput_dt = {:e}\n\n[analysis.outputs]\n\
         points = [\"b0.b\", \"b{}.b\"]\n",
        t_end / 10.0,
        n - 1
    );
    s
}

/// `examples/slider_crank_dynamic.toml` with generalized-α (step `h`, ρ∞ 0.9, Exudyn's default)
/// for `t_end`, its outputs unchanged.
fn slider_crank_genalpha_toml(root: &Path, h: f64, t_end: f64) -> String {
    let text = std::fs::read_to_string(root.join("examples/slider_crank_dynamic.toml"))
        .expect("examples/slider_crank_dynamic.toml");
    text.lines()
        .filter(|l| !l.starts_with("rtol") && !l.starts_with("atol"))
        .map(|l| match l {
            l if l.starts_with("integrator") => {
                format!("integrator = \"generalized_alpha\"\ndt = {h:e}\nrho_inf = 0.9")
            }
            l if l.starts_with("t_end") => format!("t_end = {t_end:e}"),
            l => l.to_string(),
        })
        .collect::<Vec<_>>()
        .join("\n")
}

/// Max over the reference samples of |E − E(0)| and E − E(0) at the last one, from a run's
/// `energy.csv` (its `drift` column), as `exudyn-slider-crank` measures Exudyn's.
fn slider_crank_energy_error(energy: &Path, reference: &[[f64; 3]]) -> (f64, f64) {
    let text = std::fs::read_to_string(energy).unwrap_or_default();
    let Some(col) = text
        .lines()
        .next()
        .and_then(|h| h.split(',').position(|c| c.starts_with("drift")))
    else {
        return (f64::NAN, f64::NAN);
    };
    let rows = csv_rows(energy);
    let (mut err, mut last) = (0.0f64, f64::NAN);
    for &[t, ..] in reference {
        match rows.iter().find(|r| r.len() > col && (r[0] - t).abs() < 1e-9) {
            Some(r) => (err, last) = (err.max(r[col].abs()), r[col]),
            None => return (f64::NAN, f64::NAN),
        }
    }
    (err, last)
}

/// Max over the reference samples of |B − B_ref| and |C − C_ref| from a run's `points.csv`
/// (columns t, crank.B xyz, slider.C xyz), as `exudyn-slider-crank` measures Exudyn's.
fn slider_crank_csv_error(points: &Path, reference: &[[f64; 3]]) -> f64 {
    let rows = csv_rows(points);
    let mut err = 0.0f64;
    for &[t, x, th] in reference {
        let Some(r) = rows.iter().find(|r| r.len() >= 7 && (r[0] - t).abs() < 1e-9) else {
            return f64::NAN;
        };
        let b_ref = Vector3::new(0.0, 0.1 - 0.08 * th.sin(), 0.12 + 0.08 * th.cos());
        err = err
            .max((Vector3::new(r[1], r[2], r[3]) - b_ref).norm())
            .max((Vector3::new(r[4], r[5], r[6]) - Vector3::new(x, 0.0, 0.0)).norm());
    }
    err
}

/// One row of the whole-run comparison: a code's step, its error and its best wall time.
struct WholeRun {
    h: f64,
    err: f64,
    /// Max |E − E(0)| over the same samples and E − E(0) at the last (NaN: not measured).
    energy: (f64, f64),
    wall: f64,
}

/// Rows of the whole-run table and the ratio at equal error for each Exudyn run.
fn whole_run_table(md: &mut String, what: &str, cardan: &[WholeRun], exudyn: &[WholeRun]) {
    let curve: Vec<(f64, f64)> = cardan.iter().map(|r| (r.err, r.wall)).collect();
    let mut row = |code: &str, r: &WholeRun, ratio: String| {
        let (h, err, wall) = (r.h * 1e3, r.err, fmt_time(r.wall));
        let energy = if r.energy.0.is_nan() {
            "—".to_string()
        } else {
            format!("{:.1e} / {:+.1e}", r.energy.0, r.energy.1)
        };
        let _ = writeln!(
            md,
            "| {what} | {code} | {h:.2} | {err:.2e} | {energy} | {wall} | {ratio} |"
        );
    };
    for r in cardan {
        row("cardan", r, String::new());
    }
    for r in exudyn {
        row("Exudyn", r, bold_ratio(r.wall / time_at(&curve, r.err)));
    }
}

/// `cli-genalpha`: generalized-α whole runs through the command (reading, assembly, the
/// integration and every output file, each its own process) against Exudyn's solver call, at
/// equal error, on the slider-crank (5 s and 1 s) and the 1,000-link spherical chain.
fn cli_genalpha(
    smoke: bool,
    python: &str,
    script: &Path,
    root: &Path,
    slider_crank: bool,
    chain: bool,
) -> String {
    let mut md = String::new();
    let _ = writeln!(
        md,
        "**Generalized-α whole runs through the command, Exudyn.** cardan: `cardan run` in its \
         own process, wall time of the whole run (reading the model, assembly, consistent \
         initial accelerations, the integration, and every output file: CSV, SVG plots, \
         animation, report). Exudyn: its `SolveDynamic` call only (model building and Python \
         start-up excluded), its generalized-α defaults. Both ρ∞ as stated, fixed step h. \
         Slider-crank: `examples/slider_crank_dynamic.toml` with generalized-α (ρ∞ 0.9, \
         Exudyn's default), error = max over the IFToMM reference samples of the crank-pin and \
         slider position errors; *energy error* = max over the same samples of |E − E(0)| / \
         E − E(0) at t_end (the motion is conservative). Chain: N spherical-joint links (ρ∞ 0.8), error at t_end of the \
         far ends of the first and last links against a cardan DOPRI5 reference (rtol 1e-10). \
         Best of the rounds (slider-crank 9, chain 1), cardan and Exudyn alternating. *Ratio*: \
         Exudyn's time over cardan's at Exudyn's error (log-log interpolation between \
         cardan's runs; — outside them).\n\n\
         | problem | code | h [ms] | error [m] | energy error [J], max / end | time | ratio at equal error |\n\
         |---|---|---:|---:|---:|---:|---:|"
    );
    let tmp = std::env::temp_dir().join(format!("cardan-bench-cli-genalpha-{}", std::process::id()));
    let _ = std::fs::create_dir_all(&tmp);
    let out = tmp.join("out");
    let cx = CliRuns {
        python,
        script,
        root,
        tmp: &tmp,
        out: &out,
    };
    if slider_crank {
        cli_genalpha_slider_crank(&cx, smoke, &mut md);
    }
    if chain {
        cli_genalpha_chain(&cx, smoke, &mut md);
    }
    let _ = std::fs::remove_dir_all(&tmp);
    md.push('\n');
    md
}

/// Where the whole runs of [`cli_genalpha`] happen: the peers' Python and script, the
/// repository root, the scratch folder and the run's output folder in it.
struct CliRuns<'a> {
    python: &'a str,
    script: &'a Path,
    root: &'a Path,
    tmp: &'a Path,
    out: &'a Path,
}

/// The slider-crank rows: cardan's and Exudyn's generalized-α runs over each time span, best
/// of the rounds, against the IFToMM reference.
fn cli_genalpha_slider_crank(cx: &CliRuns, smoke: bool, md: &mut String) {
    let (python, script, root, tmp, out) = (cx.python, cx.script, cx.root, cx.tmp, cx.out);
    let reference_rows: Vec<[f64; 3]> = std::fs::read_to_string(
        root.join("tests/data/benchmarks/spatial_slider_crank_crankCoM_mid.csv"),
    )
    .unwrap_or_default()
    .lines()
    .filter(|l| !l.trim().is_empty() && !l.starts_with('#'))
    .filter_map(|l| {
        let v: Vec<f64> = l.split(',').filter_map(|x| x.trim().parse().ok()).collect();
        v.get(..3).map(|r| [r[0], r[1], r[2]])
    })
    .collect();
    let (spans, rounds): (&[f64], usize) = if smoke { (&[0.2], 1) } else { (&[5.0, 1.0], 9) };
    let (cardan_h, exudyn_h): (&[f64], &[f64]) = if smoke {
        (&[1e-3, 5e-4], &[1e-3])
    } else {
        (&[1e-3, 5e-4, 2.5e-4, 1.25e-4], &[1e-3, 5e-4])
    };
    for &t_end in spans {
        let reference: Vec<[f64; 3]> = reference_rows
            .iter()
            .copied()
            .filter(|r| r[0] <= t_end + 1e-9)
            .collect();
        let mut c: Vec<WholeRun> = cardan_h
            .iter()
            .map(|&h| WholeRun {
                h,
                err: f64::NAN,
                energy: (f64::NAN, f64::NAN),
                wall: f64::INFINITY,
            })
            .collect();
        let mut x: Vec<WholeRun> = exudyn_h
            .iter()
            .map(|&h| WholeRun {
                h,
                err: f64::NAN,
                energy: (f64::NAN, f64::NAN),
                wall: f64::INFINITY,
            })
            .collect();
        for _ in 0..rounds {
            for r in c.iter_mut() {
                let file = tmp.join("slider_crank.toml");
                let _ = std::fs::write(&file, slider_crank_genalpha_toml(root, r.h, t_end));
                match cardan_run(&file, out) {
                    Ok(w) => {
                        r.wall = r.wall.min(w);
                        r.err = slider_crank_csv_error(&out.join("points.csv"), &reference);
                        r.energy =
                            slider_crank_energy_error(&out.join("energy.csv"), &reference);
                    }
                    Err(e) => eprintln!("cardan slider-crank h {}: {e}", r.h),
                }
            }
            for r in x.iter_mut() {
                let args = ["exudyn-slider-crank", &r.h.to_string(), &t_end.to_string()];
                match call(python, script, &args) {
                    Ok(v) => {
                        r.wall = r.wall.min(get(&v, "wall"));
                        r.err = get(&v, "err");
                        r.energy = (get(&v, "energy_err"), get(&v, "energy_end"));
                    }
                    Err(e) => eprintln!("{e}"),
                }
            }
        }
        whole_run_table(md, &format!("slider-crank {t_end} s"), &c, &x);
    }
}

/// The chain rows: N spherical-joint links, cardan at three steps and Exudyn at 1 ms, against
/// a cardan DOPRI5 reference.
fn cli_genalpha_chain(cx: &CliRuns, smoke: bool, md: &mut String) {
    let (python, script, tmp, out) = (cx.python, cx.script, cx.tmp, cx.out);
    let n = if smoke { 20 } else { 1000 };
    let chain_spans: &[f64] = if smoke { &[0.05] } else { &[1.0, 5.0] };
    let model = models::spherical_chain(n);
    for &t_end in chain_spans {
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
        let mut c = Vec::new();
        for &h in &[2e-3, 1e-3, 5e-4] {
            let file = tmp.join("chain.toml");
            let _ = std::fs::write(&file, spherical_chain_toml(n, h, t_end));
            match cardan_run(&file, out) {
                Ok(wall) => {
                    let rows = csv_rows(&out.join("points.csv"));
                    let e = rows.last().filter(|r| r.len() >= 7).map_or(f64::NAN, |r| {
                        err(Vector3::new(r[4], r[5], r[6]), Vector3::new(r[1], r[2], r[3]))
                    });
                    c.push(WholeRun {
                        h,
                        err: e,
                        energy: (f64::NAN, f64::NAN),
                        wall,
                    });
                }
                Err(e) => eprintln!("cardan chain h {h}: {e}"),
            }
        }
        let mut x = Vec::new();
        let args = ["exudyn-chain", &n.to_string(), "0.001", &t_end.to_string()];
        match call(python, script, &args) {
            Ok(v) => {
                let tip = Vector3::new(get(&v, "tip_x"), get(&v, "tip_y"), get(&v, "tip_z"));
                let b0 = Vector3::new(get(&v, "b0_x"), get(&v, "b0_y"), get(&v, "b0_z"));
                x.push(WholeRun {
                    h: 1e-3,
                    err: err(tip, b0),
                    energy: (f64::NAN, f64::NAN),
                    wall: get(&v, "wall"),
                });
            }
            Err(e) => eprintln!("{e}"),
        }
        whole_run_table(md, &format!("chain N = {n}, {t_end} s"), &c, &x);
    }
}
