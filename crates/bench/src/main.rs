//! `cardan-bench`: runs the benchmarks and writes the performance report.
//!
//! ```text
//! cardan-bench [--smoke] [--report docs/performance.md] [--plots docs/performance] [--peers PYTHON]
//! cardan-bench --point <kin|dyn> <chain|ladder> N     (one scaling point; used internally)
//! cardan-bench --profile <frame EXAMPLE N | kin-chain N FRAMES | chain N STEPS | chain-dopri5 N RTOL | model FILE N | model-prepare FILE N | asmt FILE N>
//!     (one run for a profiler)
//! cardan-bench --peers-only PYTHON [--smoke] [kinematics|slider-crank|chain ...]  (peers to stdout)
//! cardan-bench --genalpha N T_END H [mass|tangent] [INTERVALS] [--no-reference]
//!     (generalized-α on the N-link chain: cost, iterations and error per slice of the run)
//! cardan-bench --genalpha-sc H T_END [RHO] [noproj] [mass]  (generalized-α on the slider-crank)
//! cardan-bench --drivers [--smoke]    (the driver-function section alone, to stdout)
//! cardan-bench --animation [--smoke]  (the animation and report section alone, to stdout)
//! cardan-bench --large [--smoke]      (check and run setup of 10³–10⁵-body chains, to stdout)
//! cardan-bench --contact [--smoke] [chain]  (contact at scale: a sphere pile and a chain on a plane, to stdout)
//! cardan-bench --contact-plots RESULTS OUT  (the billiard ball's plots from the peers' RESULT lines)
//! cardan-bench --modal [--smoke] [--peers PYTHON]  (the modal sections alone, to stdout; with
//!     --peers also the frequencies against Exudyn, exit status 1 above 1e-6 relative)
//! cardan-bench --asmt [--smoke] [--peers PYTHON] [--only FILE]  (ASMT files against OndselSolver, to stdout)
//! ```
//!
//! Usually run through `cargo xtask bench [--smoke] [--peers]`.

use cardan_bench::measure::{self, fmt_bytes, fmt_time, loglog_slope, ms, time_per_call};
use cardan_bench::models;
use cardan_bench::svg::{self, Series};
use cardan_dynamics::{
    Dopri5Options, Dynamics, Force, GeneralizedAlphaOptions, Integrator, IterationMatrix,
    SimulationOptions, State,
};
use cardan_mechanism::{AssemblyOptions, Model, Outputs};
use cardan_model::prepare::{prepare, Prepared};
use cardan_solver::{NewtonOptions, Tolerances};
use nalgebra::Vector3;
use stats_alloc::{Region, StatsAlloc, INSTRUMENTED_SYSTEM};
use std::alloc::System;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

#[global_allocator]
static GLOBAL: &StatsAlloc<System> = &INSTRUMENTED_SYSTEM;

const BEGIN: &str = "<!-- performance:begin -->";
const END: &str = "<!-- performance:end -->";

#[derive(Clone)]
struct Cfg {
    smoke: bool,
    batch: Duration,
    batches: usize,
}

impl Cfg {
    /// 7 batches of 200 ms per measurement, or one of 5 ms for a smoke run.
    fn new(smoke: bool) -> Self {
        Self {
            smoke,
            batch: if smoke { ms(5) } else { ms(200) },
            batches: if smoke { 1 } else { 7 },
        }
    }
}

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../..")
}

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    if single_mode(&args) {
        return;
    }
    let opts = ReportArgs::parse(&args);
    let cfg = Cfg::new(opts.smoke);
    let (md, svgs) = full_report(&cfg, &opts);
    if let Some(dir) = &opts.plots {
        std::fs::create_dir_all(dir).expect("plot directory");
        for (name, text) in &svgs {
            std::fs::write(dir.join(name), text).expect("write plot");
        }
    }
    match &opts.report {
        Some(path) => write_section(path, &md),
        None => println!("{md}"),
    }
}

/// The modes that run one section, one scaling point or one profile and print it (`--point`,
/// `--large`, `--modal`, ...; see the crate docs): `true` when `args` asked for one (it has
/// run), `false` for the full report.
fn single_mode(args: &[String]) -> bool {
    match args.first().map(String::as_str) {
        Some("--point") => {
            let kind = args.get(1).cloned().unwrap_or_default();
            let family = args.get(2).cloned().unwrap_or_default();
            let n: usize = args.get(3).and_then(|s| s.parse().ok()).unwrap_or(10);
            let smoke = args.iter().any(|a| a == "--smoke");
            scaling_point(&kind, &family, n, smoke);
        }
        Some("--large-point") => {
            cardan_bench::large::point(&args[1..]);
        }
        Some("--contact-plots") => {
            // RESULTS file (the peers' output) → two SVG files beside OUT (OUT_step.svg,
            // OUT_work.svg).
            let input = std::fs::read_to_string(&args[1]).expect("the results file");
            let (step, work) = cardan_bench::contact::billiard_plots(&input);
            std::fs::write(format!("{}_step.svg", args[2]), step).expect("write");
            std::fs::write(format!("{}_work.svg", args[2]), work).expect("write");
        }
        Some("--contact") => {
            let smoke = args.iter().any(|a| a == "--smoke");
            let chains = args.iter().any(|a| a == "chain");
            print!("{}", cardan_bench::contact::section(smoke, chains));
        }
        Some("--large") => {
            println!(
                "{}",
                cardan_bench::large::section(args.iter().any(|a| a == "--smoke"))
            );
        }
        Some("--peers-only") => {
            cardan_bench_peers::peers_only(&args[1..]);
        }
        Some("--drivers") => {
            let smoke = args.iter().any(|a| a == "--smoke");
            let cfg = Cfg::new(smoke);
            println!("{}", driver_functions_section(&cfg));
        }
        Some("--modal") => {
            let smoke = args.iter().any(|a| a == "--smoke");
            println!("{}", cardan_bench::modal_sparse::section(smoke));
            if let Some(k) = args.iter().position(|a| a == "--peers") {
                let py = args.get(k + 1).map_or("python3", String::as_str);
                let (md, ok) = cardan_bench::modal_peer::section(py, &root());
                println!("{md}");
                if !ok {
                    std::process::exit(1);
                }
            }
        }
        Some("--animation") => {
            let smoke = args.iter().any(|a| a == "--smoke");
            let (batch, batches) = if smoke { (ms(5), 1) } else { (ms(200), 7) };
            println!(
                "{}{}",
                cardan_bench::animation::section(smoke, batch, batches),
                cardan_bench::animation::examples_section(&root().join("examples"), smoke)
            );
        }
        Some("--genalpha") => {
            cardan_bench::genalpha::main(&args[1..]);
        }
        Some("--genalpha-sc") => {
            cardan_bench::genalpha::slider_crank(&args[1..], &root());
        }
        Some("--asmt") => {
            let smoke = args.iter().any(|a| a == "--smoke");
            let python = args
                .iter()
                .position(|a| a == "--peers")
                .and_then(|k| args.get(k + 1));
            let only = args
                .iter()
                .position(|a| a == "--only")
                .and_then(|k| args.get(k + 1));
            println!(
                "{}",
                cardan_bench::asmt::section_of(
                    smoke,
                    python.map(String::as_str),
                    only.map(String::as_str),
                    &root()
                )
            );
        }
        Some("--kinematic-accuracy") => {
            kinematic_accuracy(&args[1..]);
        }
        Some("--run-memory") => {
            run_memory(&args[1..]);
        }
        Some("--profile") => {
            profile(&args[1..]);
        }
        _ => return false,
    }
    true
}

/// The options of the full report.
struct ReportArgs {
    smoke: bool,
    /// The file whose marked section gets the report (default: standard output).
    report: Option<PathBuf>,
    /// The folder for the plots.
    plots: Option<PathBuf>,
    /// The Python that runs the peers.
    peers: Option<String>,
    /// Why the peers could not be installed.
    peers_error: Option<String>,
}

impl ReportArgs {
    /// Reads the options; exits with status 2 on an unknown one.
    fn parse(args: &[String]) -> Self {
        let mut smoke = false;
        let mut report: Option<PathBuf> = None;
        let mut plots: Option<PathBuf> = None;
        let mut peers: Option<String> = None;
        let mut peers_error: Option<String> = None;
        let mut it = args.iter();
        while let Some(a) = it.next() {
            match a.as_str() {
                "--smoke" => smoke = true,
                "--report" => report = it.next().map(PathBuf::from),
                "--plots" => plots = it.next().map(PathBuf::from),
                "--peers" => peers = it.next().cloned(),
                "--peers-error" => peers_error = it.next().cloned(),
                other => {
                    eprintln!("unknown argument {other}");
                    std::process::exit(2);
                }
            }
        }
        Self {
            smoke,
            report,
            plots,
            peers,
            peers_error,
        }
    }
}

/// The full report (every section; the peers when asked) and its plots.
fn full_report(cfg: &Cfg, opts: &ReportArgs) -> (String, Vec<(String, String)>) {
    let started = Instant::now();
    let mut md = String::new();
    let _ = writeln!(md, "{BEGIN}\n## Measurements\n");
    let _ = writeln!(
        md,
        "Written by `cargo xtask bench{}` ({}); do not edit by hand. Machine: {}. \
         Times are medians of repeated batches (wall clock; the machine is shared, treat them as \
         ±15 %). Sources: `crates/bench/`.\n",
        if cfg.smoke { " --smoke" } else { "" },
        if cfg.smoke {
            "smoke run: a few iterations each, numbers NOT representative"
        } else {
            "full run"
        },
        measure::machine()
    );
    let mut svgs: Vec<(String, String)> = Vec::new();
    eprintln!("== kinematic frames of the example mechanisms");
    md.push_str(&frames_section(cfg));
    eprintln!("== driver functions");
    md.push_str(&driver_functions_section(cfg));
    eprintln!("== Newton tolerance");
    md.push_str(&tolerance_section(cfg, &mut svgs));
    eprintln!("== scaling");
    md.push_str(&scaling_section(cfg, &mut svgs));
    eprintln!("== modal analysis, sparse path");
    md.push_str(&cardan_bench::modal_sparse::section(cfg.smoke));
    eprintln!("== animation and report");
    md.push_str(&cardan_bench::animation::section(
        cfg.smoke,
        cfg.batch,
        cfg.batches,
    ));
    md.push_str(&cardan_bench::animation::examples_section(
        &root().join("examples"),
        cfg.smoke,
    ));
    eprintln!("== work-precision");
    md.push_str(&work_precision_section(cfg, &mut svgs));
    eprintln!("== ASMT files against OndselSolver");
    md.push_str(&cardan_bench::asmt::section(
        cfg.smoke,
        opts.peers.as_deref(),
        &root(),
    ));
    if let Some(py) = &opts.peers {
        eprintln!("== peers");
        md.push_str(&peers_section(cfg, py));
        md.push_str(&cardan_bench::modal_peer::section(py, &root()).0);
    } else if let Some(e) = &opts.peers_error {
        let _ = writeln!(md, "### Peers\n\nPeers could not be installed: {e}\n");
    } else {
        md.push_str("### Peers\n\nNot run (`cargo xtask bench --peers` runs Exudyn and OndselSolver side by side).\n\n");
    }
    let _ = writeln!(
        md,
        "Total benchmark time: {:.0} s.\n\n{END}",
        started.elapsed().as_secs_f64()
    );
    (md, svgs)
}

/// Replaces (or appends) the marked section of `path`, keeping everything else.
fn write_section(path: &Path, section: &str) {
    let old = std::fs::read_to_string(path).unwrap_or_default();
    let new = match (old.find(BEGIN), old.find(END)) {
        (Some(a), Some(b)) if b > a => {
            format!(
                "{}{}{}",
                &old[..a],
                section.trim_end(),
                &old[b + END.len()..]
            )
        }
        _ if old.trim().is_empty() => format!("# Performance\n\n{}\n", section.trim_end()),
        _ => format!("{}\n\n{}\n", old.trim_end(), section.trim_end()),
    };
    if let Some(dir) = path.parent() {
        let _ = std::fs::create_dir_all(dir);
    }
    std::fs::write(path, new).expect("write report");
    eprintln!("wrote {}", path.display());
}

fn allocations(f: impl FnOnce()) -> usize {
    let region = Region::new(GLOBAL);
    f();
    let s = region.change();
    s.allocations + s.reallocations
}

/// `--profile frame EXAMPLE N`, `--profile kin-chain N FRAMES`, `--profile chain N STEPS` or
/// `--profile chain-dopri5 N RTOL`: a fixed amount of work for `valgrind --tool=callgrind` (instruction counts are steadier
/// than wall time).
fn profile(args: &[String]) {
    let arg = |k: usize| args.get(k).map(String::as_str);
    // The chain size is the first argument after the kind; a frame run's count the second.
    let chain = matches!(arg(0), Some("chain" | "chain-dopri5" | "kin-chain"));
    let n: usize = arg(if chain { 1 } else { 2 })
        .and_then(|s| s.parse().ok())
        .unwrap_or(1000);
    match arg(0) {
        Some("kin-chain") => {
            // Kinematic frames of the driven revolute chain (the scaling section's `kin chain`).
            let frames: usize = arg(2).and_then(|s| s.parse().ok()).unwrap_or(20);
            let model = models::revolute_chain(n);
            let mut ws = model.workspace();
            model.prepare_kinematics(&mut ws).expect("prepare");
            let mut run = FrameRun::prepared(&model, ws, scaling_times());
            let t0 = Instant::now();
            for _ in 0..frames {
                run.frame(true);
            }
            eprintln!(
                "{} iterations in {} frames, {:.3} ms per frame",
                run.iterations,
                run.frames,
                t0.elapsed().as_secs_f64() * 1e3 / frames.max(1) as f64
            );
        }
        Some("chain") => {
            let steps: usize = arg(2).and_then(|s| s.parse().ok()).unwrap_or(100);
            let model = models::spherical_chain(n);
            let mut d = gravity_dynamics(&model, Vector3::new(0.0, 0.0, -9.81));
            let s = State::initial(&model, 0.0);
            d.prepare(&s).expect("prepare");
            let opts = SimulationOptions::new(steps as f64 * 1e-3, 1)
                .integrator(Integrator::GeneralizedAlpha(GeneralizedAlphaOptions {
                    iteration_matrix: IterationMatrix::MassOnly,
                    ..GeneralizedAlphaOptions::with_step(1e-3)
                }))
                .outputs(Outputs::position_only());
            let r = d.simulate_consistent(s, &opts).expect("simulate");
            eprintln!("{:?}", r.stats);
        }
        Some("chain-dopri5") => {
            // 0.1 s of the chain with DOPRI5.
            let rtol: f64 = arg(2).and_then(|s| s.parse().ok()).unwrap_or(1e-4);
            let model = models::spherical_chain(n);
            let mut d = gravity_dynamics(&model, Vector3::new(0.0, 0.0, -9.81));
            let s = State::initial(&model, 0.0);
            d.prepare(&s).expect("prepare");
            let opts = SimulationOptions::new(0.1, 1)
                .integrator(Integrator::Dopri5(Dopri5Options::tolerances(
                    rtol,
                    rtol * 1e-2,
                )))
                .outputs(Outputs::position_only());
            let r = d.simulate_consistent(s, &opts).expect("simulate");
            eprintln!("{:?}", r.stats);
        }
        Some("asmt") => {
            // An ASMT file solved in process as the `--asmt` section times it, n times.
            let path = Path::new(arg(1).expect("profile asmt FILE [N]"));
            let t0 = Instant::now();
            for _ in 0..n {
                cardan_bench::asmt::cardan_solve(path);
            }
            eprintln!(
                "{:.3} ms per solve",
                t0.elapsed().as_secs_f64() * 1e3 / n.max(1) as f64
            );
        }
        Some(kind @ ("model" | "model-prepare")) => {
            // A model file's analysis, in memory (tables kept, nothing written), n times;
            // `model-prepare` also reads and prepares the file each time (an ASMT or URDF file
            // imported: as Python's `cardan.load(f).run()` does).
            let path = Path::new(arg(1).expect("profile model FILE [N]"));
            let prepare = || cardan_model::prepare::prepare(path).expect("prepare");
            let mut p = prepare();
            let a = p.loaded.analysis.clone().expect("an [analysis] table");
            let flags = cardan_model::analysis::RunFlags::default();
            let t0 = Instant::now();
            for _ in 0..n {
                if kind == "model-prepare" {
                    p = prepare();
                }
                cardan_model::analysis::analyse(&p, &a, &flags).expect("analyse");
            }
            eprintln!(
                "{:.3} ms per run",
                t0.elapsed().as_secs_f64() * 1e3 / n.max(1) as f64
            );
        }
        _ => {
            let name = args.get(1).map_or("slider_crank", String::as_str);
            let (_, p) = examples()
                .into_iter()
                .find(|(e, _)| e == name)
                .expect("example");
            let mut run =
                FrameRun::new(&p.model, grid(&p), Model::kinematic_newton_options()).expect("run");
            run.predict = args.get(3).is_none_or(|a| a != "--no-predict");
            for _ in 0..n {
                run.frame(true);
            }
            eprintln!("{} iterations in {} frames", run.iterations, run.frames);
        }
    }
}

// ---------------------------------------------------------------------------------------------
// 1. Kinematic frames of the example mechanisms.

struct FrameRun<'a> {
    model: &'a Model,
    ws: cardan_mechanism::Workspace,
    times: Vec<f64>,
    k: usize,
    dir: isize,
    iterations: usize,
    frames: usize,
    residual: f64,
    /// Start each full frame from the Taylor prediction (as the time grid does).
    predict: bool,
}

impl<'a> FrameRun<'a> {
    fn new(model: &'a Model, times: Vec<f64>, newton: NewtonOptions) -> Option<Self> {
        let mut ws = model.workspace();
        model
            .assemble(&mut ws, &AssemblyOptions::at(times[0]))
            .ok()?;
        model.prepare_kinematics_with(&mut ws, newton).ok()?;
        Some(Self::prepared(model, ws, times))
    }

    fn prepared(model: &'a Model, ws: cardan_mechanism::Workspace, times: Vec<f64>) -> Self {
        Self {
            model,
            ws,
            times,
            k: 0,
            dir: 1,
            iterations: 0,
            frames: 0,
            residual: 0.0,
            predict: true,
        }
    }

    /// Next time of the grid, back and forth (every frame starts from its neighbour).
    fn next_t(&mut self) -> f64 {
        if self.times.len() > 1 {
            let nk = self.k as isize + self.dir;
            if nk < 0 || nk >= self.times.len() as isize {
                self.dir = -self.dir;
            }
            self.k = (self.k as isize + self.dir) as usize;
        }
        self.times[self.k]
    }

    fn frame(&mut self, full: bool) {
        let t = self.next_t();
        if full && self.predict {
            // The time grid's Taylor predictor (what `Model::kinematics` does between frames).
            let dt = t - self.ws.time();
            self.model.predict_poses(&mut self.ws, dt);
        }
        let r = self.model.position(&mut self.ws, t).expect("position");
        self.iterations += r.iterations;
        self.residual = self.residual.max(r.residual);
        self.frames += 1;
        if full {
            self.model.velocity(&mut self.ws).expect("velocity");
            self.model.acceleration(&mut self.ws).expect("acceleration");
        }
    }

    fn reset_counts(&mut self) {
        self.iterations = 0;
        self.frames = 0;
        self.residual = 0.0;
    }
}

/// The time grid of the generated scaling models' kinematic frames: 0 … 4 s every 0.02 s.
fn scaling_times() -> Vec<f64> {
    (0..=200).map(|k| f64::from(k) * 0.02).collect()
}

fn examples() -> Vec<(String, Prepared)> {
    let dir = root().join("examples");
    let mut files: Vec<PathBuf> = std::fs::read_dir(&dir)
        .map(|d| d.filter_map(|e| e.ok().map(|e| e.path())).collect())
        .unwrap_or_default();
    files.sort();
    files
        .into_iter()
        .filter(|p| p.extension().is_some_and(|e| e == "toml"))
        .filter_map(|p| {
            let name = p.file_stem()?.to_string_lossy().to_string();
            prepare(&p).ok().map(|prep| (name, prep))
        })
        .collect()
}

fn grid(p: &Prepared) -> Vec<f64> {
    p.loaded
        .analysis
        .as_ref()
        .map_or_else(|| vec![0.0], |a| a.times())
}

fn frames_section(cfg: &Cfg) -> String {
    let mut md = String::new();
    let _ = writeln!(
        md,
        "### Kinematic frame of each example mechanism\n\n\
         One frame = position Newton to the default tolerance (scaled residual 1e-10, step 1e-6) \
         from the previous frame's pose + velocity + acceleration, walking the file's time grid \
         back and forth. *Allocations*: counted by a global counting allocator over 200 frames \
         after 20 warm-up frames (setup excluded). Kinematic example files only (the dynamic ones \
         have no drivers).\n\n\
         | mechanism | bodies | unknowns | frame | position only | Newton iterations / frame | max ‖Φ‖ | allocations / 200 frames |\n\
         |---|---:|---:|---:|---:|---:|---:|---:|"
    );
    for (name, p) in examples() {
        let a = match &p.loaded.analysis {
            Some(a) if a.integrator().is_none() => a,
            _ => continue,
        };
        let _ = a;
        let model = &p.model;
        let Some(mut run) = FrameRun::new(model, grid(&p), Model::kinematic_newton_options())
        else {
            eprintln!("{name}: could not assemble/prepare; skipped");
            continue;
        };
        for _ in 0..20 {
            run.frame(true);
        }
        let allocs = allocations(|| {
            for _ in 0..200 {
                run.frame(true);
            }
        });
        run.reset_counts();
        let t_frame = time_per_call(|| run.frame(true), cfg.batch, cfg.batches);
        let iters = run.iterations as f64 / run.frames.max(1) as f64;
        let res = run.residual;
        let t_pos = time_per_call(|| run.frame(false), cfg.batch, cfg.batches);
        eprintln!(
            "{name}: {} / frame, {iters:.2} it, {allocs} allocs",
            fmt_time(t_frame)
        );
        let _ = writeln!(
            md,
            "| {name} | {} | {} | {} | {} | {iters:.2} | {res:.1e} | {allocs} |",
            model.num_bodies(),
            model.num_unknowns(),
            fmt_time(t_frame),
            fmt_time(t_pos)
        );
    }
    md.push('\n');
    md
}

/// The slider-crank example with its driver function (θ = 2πt) written as `function`.
fn slider_crank_with(function: &str) -> Prepared {
    let path = root().join("examples/slider_crank.toml");
    let text = std::fs::read_to_string(&path).expect("examples/slider_crank.toml");
    let poly = r#"function = { kind = "polynomial", coefficients = [0.0, 6.283185307179586] }"#;
    assert!(
        text.contains(poly),
        "the slider-crank's driver line changed"
    );
    let dir = std::env::temp_dir().join(format!("cardan-bench-drivers-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    let file = dir.join(format!("{}.toml", function.len()));
    std::fs::write(&file, text.replace(poly, function)).expect("write model");
    let p = prepare(&file).expect("the variant prepares");
    let _ = std::fs::remove_dir_all(&dir);
    p
}

/// A kinematic frame of the slider-crank with the same θ(t) as a polynomial and as expressions,
/// and one evaluation of (f, ḟ, f̈) alone.
fn driver_functions_section(cfg: &Cfg) -> String {
    let mut md = String::new();
    let _ = writeln!(
        md,
        "### Driver functions: polynomial against expression\n\n\
         The slider-crank example (`examples/slider_crank.toml`) with θ(t) = 2πt written as a \
         polynomial and as expressions; a frame as above (position, velocity, acceleration), \
         and one evaluation of (f, ḟ, f̈) alone. Target: an expression frame costs at most 2× a \
         polynomial frame.\n\n\
         | driver function | frame | ratio to polynomial | f, ḟ, f̈ alone |\n|---|---:|---:|---:|"
    );
    let variants = [
        (
            "polynomial [0, 2π]",
            r#"function = { kind = "polynomial", coefficients = [0.0, 6.283185307179586] }"#,
        ),
        (
            "expression `2*pi*t`",
            r#"function = { kind = "expression", text = "2*pi*t" }"#,
        ),
        (
            "expression `2*pi*t + 0*sin(3*t)^2 + step(t, 5, 0, 6, 1)`",
            r#"function = { kind = "expression", text = "2*pi*t + 0*sin(3*t)^2 + step(t, 5, 0, 6, 1)" }"#,
        ),
    ];
    let mut base = None;
    for (label, function) in variants {
        let p = slider_crank_with(function);
        let Some(mut run) = FrameRun::new(&p.model, grid(&p), Model::kinematic_newton_options())
        else {
            eprintln!("{label}: could not assemble; skipped");
            continue;
        };
        for _ in 0..20 {
            run.frame(true);
        }
        let t_frame = time_per_call(|| run.frame(true), cfg.batch, cfg.batches);
        let f = &p.loaded.driver_functions[0].0;
        let mut t = 0.0;
        let t_eval = time_per_call(
            || {
                t += 1e-3;
                std::hint::black_box(f.eval(std::hint::black_box(t)));
            },
            cfg.batch,
            cfg.batches,
        );
        let b = *base.get_or_insert(t_frame);
        let ratio = t_frame / b;
        eprintln!(
            "{label}: {} / frame ({ratio:.2}×), {} / eval",
            fmt_time(t_frame),
            fmt_time(t_eval)
        );
        let _ = writeln!(
            md,
            "| {label} | {} | {ratio:.2} | {} |",
            fmt_time(t_frame),
            fmt_time(t_eval)
        );
    }
    md.push('\n');
    md
}

// ---------------------------------------------------------------------------------------------
// 4. Newton tolerance against achieved constraint error and time.

fn tolerance_section(cfg: &Cfg, svgs: &mut Vec<(String, String)>) -> String {
    let mut md = String::new();
    let _ = writeln!(
        md,
        "### Newton tolerance against achieved error and time\n\n\
         Position-only frames (the same walk of the time grid), residual tolerance τ on the \
         scaled residual and step tolerance √τ (quadratic convergence: a last step of √τ \
         leaves about τ). Achieved error: max |Φ_i| over all equations and frames (unscaled, m \
         or dimensionless).\n\n\
         | mechanism | τ | achieved max ‖Φ‖ | Newton iterations / frame | time / frame |\n\
         |---|---:|---:|---:|---:|"
    );
    let tols: &[f64] = if cfg.smoke {
        &[1e-4, 1e-10]
    } else {
        &[1e-2, 1e-4, 1e-6, 1e-8, 1e-10, 1e-12, 1e-14]
    };
    let mut series = Vec::new();
    let chain = models::revolute_chain(100);
    let mut cases: Vec<(String, Prepared)> = examples()
        .into_iter()
        .filter(|(n, _)| n == "slider_crank" || n == "bricard")
        .collect();
    cases.sort_by(|a, b| b.0.cmp(&a.0));
    let mut entries: Vec<(String, &Model, Vec<f64>)> = cases
        .iter()
        .map(|(n, p)| (n.clone(), &p.model, grid(p)))
        .collect();
    entries.push((
        "revolute chain, 100 bodies".into(),
        &chain,
        (0..=100).map(|k| k as f64 * 0.05).collect(),
    ));
    for (name, model, times) in entries {
        let mut pts = Vec::new();
        for &tol in tols {
            let newton = NewtonOptions {
                tolerances: Tolerances {
                    residual: tol,
                    step: tol.sqrt(),
                },
                ..Model::kinematic_newton_options()
            };
            let Some(mut run) = FrameRun::new(model, times.clone(), newton) else {
                continue;
            };
            for _ in 0..5 {
                run.frame(false);
            }
            run.reset_counts();
            let t = time_per_call(|| run.frame(false), cfg.batch, cfg.batches);
            let iters = run.iterations as f64 / run.frames.max(1) as f64;
            let _ = writeln!(
                md,
                "| {name} | {tol:.0e} | {:.1e} | {iters:.2} | {} |",
                run.residual,
                fmt_time(t)
            );
            pts.push((run.residual.max(1e-17), t));
        }
        series.push(Series {
            label: name,
            points: pts,
        });
    }
    svgs.push((
        "newton_tolerance.svg".into(),
        svg::loglog(
            "Position frame: time against achieved constraint error",
            "max |Φ| achieved",
            "time per frame [s]",
            &series,
        ),
    ));
    md.push_str("\n![Newton tolerance](performance/newton_tolerance.svg)\n\n");
    md
}

// ---------------------------------------------------------------------------------------------
// 2. Scaling: one process per point (peak memory per size).

fn gravity_dynamics(model: &Model, g: Vector3<f64>) -> Dynamics<'_> {
    let mut d = Dynamics::new(model).expect("dynamics");
    d.add_force(Force::gravity(g)).expect("gravity");
    d
}

/// Runs one scaling point and prints `RESULT key=value ...`.
fn scaling_point(kind: &str, family: &str, n: usize, smoke: bool) {
    let mut out: Vec<(String, String)> = Vec::new();
    let t0 = Instant::now();
    let (model, dyn_model) = match family {
        "chain" if kind == "kin" => (Some(models::revolute_chain(n)), None),
        "chain" => (None, Some(models::spherical_chain(n))),
        _ if kind == "kin" => (Some(models::ladder(models::ladder_loops(n), true)), None),
        _ => (None, Some(models::ladder(models::ladder_loops(n), false))),
    };
    out.push(("build".into(), format!("{:e}", t0.elapsed().as_secs_f64())));
    let batch = if smoke { ms(2) } else { ms(300) };
    let batches = if smoke { 1 } else { 5 };
    if let Some(model) = &model {
        out.push(("bodies".into(), model.num_bodies().to_string()));
        let t1 = Instant::now();
        let mut ws = model.workspace();
        model.prepare_kinematics(&mut ws).expect("prepare");
        out.push(("setup".into(), format!("{:e}", t1.elapsed().as_secs_f64())));
        let mut run = FrameRun::prepared(model, ws, scaling_times());
        for _ in 0..3 {
            run.frame(true);
        }
        let allocs = allocations(|| {
            for _ in 0..5 {
                run.frame(true);
            }
        });
        run.reset_counts();
        let facts0 = run.ws.kinematic_factorizations();
        let t = time_per_call(|| run.frame(true), batch, batches);
        out.push(("frame".into(), format!("{t:e}")));
        let frames = run.frames.max(1) as f64;
        out.push((
            "iters".into(),
            format!("{:.2}", run.iterations as f64 / frames),
        ));
        out.push((
            "facts".into(),
            format!(
                "{:.2}",
                (run.ws.kinematic_factorizations() - facts0) as f64 / frames
            ),
        ));
        out.push(("allocs".into(), allocs.to_string()));
    }
    if let Some(model) = &dyn_model {
        out.push(("bodies".into(), model.num_bodies().to_string()));
        let g = if family == "chain" {
            Vector3::new(0.0, 0.0, -9.81)
        } else {
            Vector3::new(-9.81, -9.81, 0.0)
        };
        let mut d = gravity_dynamics(model, g);
        let state = State::initial(model, 0.0);
        let t1 = Instant::now();
        d.prepare(&state).expect("prepare dynamics");
        out.push(("setup".into(), format!("{:e}", t1.elapsed().as_secs_f64())));
        let h = 1e-3;
        let steps = if smoke {
            2
        } else if n >= 10_000 {
            10
        } else {
            40
        };
        // Best time per step, and Newton iterations per step.
        let per_step = |d: &mut Dynamics, integ: Integrator| -> (f64, f64) {
            let opts = SimulationOptions::new(steps as f64 * h, 1)
                .integrator(integ)
                .outputs(Outputs::position_only());
            let (mut best, mut iters) = (f64::INFINITY, 0.0);
            for _ in 0..if smoke { 1 } else { 3 } {
                let r = d
                    .simulate_consistent(state.clone(), &opts)
                    .expect("simulate");
                let steps = r.stats.steps.max(1) as f64;
                best = best.min(r.stats.wall_time / steps);
                iters = r.stats.newton_iterations as f64 / steps;
            }
            (best, iters)
        };
        let (ga, ga_iters) = per_step(
            &mut d,
            Integrator::GeneralizedAlpha(GeneralizedAlphaOptions {
                iteration_matrix: IterationMatrix::MassOnly,
                ..GeneralizedAlphaOptions::with_step(h)
            }),
        );
        out.push(("ga_step".into(), format!("{ga:e}")));
        out.push(("ga_iters".into(), format!("{ga_iters:.2}")));
        let (dp, _) = per_step(&mut d, Integrator::Dopri5(Dopri5Options::fixed(h)));
        out.push(("dopri_step".into(), format!("{dp:e}")));
        if n <= 1000 {
            // O(n²): a few steps only at 1,000 bodies.
            let steps = if n >= 1000 { 2 } else { steps };
            let opts = SimulationOptions::new(steps as f64 * h, 1)
                .integrator(Integrator::GeneralizedAlpha(
                    GeneralizedAlphaOptions::with_step(h),
                ))
                .outputs(Outputs::position_only());
            let r = d
                .simulate_consistent(state.clone(), &opts)
                .expect("simulate");
            let gt = r.stats.wall_time / r.stats.steps.max(1) as f64;
            out.push(("ga_tangent_step".into(), format!("{gt:e}")));
        }
    }
    out.push((
        "peak".into(),
        measure::peak_rss_bytes().unwrap_or(0).to_string(),
    ));
    let line: Vec<String> = out.iter().map(|(k, v)| format!("{k}={v}")).collect();
    println!("RESULT {}", line.join(" "));
}

fn run_point(kind: &str, family: &str, n: usize, smoke: bool) -> Option<Vec<(String, f64)>> {
    let exe = std::env::current_exe().ok()?;
    let mut cmd = std::process::Command::new(exe);
    cmd.args(["--point", kind, family, &n.to_string()]);
    if smoke {
        cmd.arg("--smoke");
    }
    let o = cmd.output().ok()?;
    if !o.status.success() {
        eprintln!(
            "scaling point {kind} {family} {n} failed: {}",
            String::from_utf8_lossy(&o.stderr)
        );
        return None;
    }
    let s = String::from_utf8_lossy(&o.stdout);
    let line = s.lines().find(|l| l.starts_with("RESULT "))?;
    Some(
        line[7..]
            .split_whitespace()
            .filter_map(|kv| {
                let (k, v) = kv.split_once('=')?;
                Some((k.to_string(), v.parse().ok()?))
            })
            .collect(),
    )
}

fn get(r: &[(String, f64)], k: &str) -> f64 {
    r.iter().find(|(a, _)| a == k).map_or(f64::NAN, |(_, v)| *v)
}

fn scaling_section(cfg: &Cfg, svgs: &mut Vec<(String, String)>) -> String {
    let sizes: &[usize] = if cfg.smoke {
        &[10, 100]
    } else {
        &[10, 100, 1000, 10_000]
    };
    let mut md = String::new();
    let _ = writeln!(
        md,
        "### Scaling to 10,000 bodies\n\n\
         Generated models (`crates/bench/src/models.rs`): **chain** = an open chain of rods; for \
         kinematics every revolute joint is driven (axes alternating z, y), for dynamics the \
         joints are spherical (gravity −z); **ladder** = a row of closed R-S-U-R loops sharing \
         rockers (2k + 1 bodies, 1 DOF; the first revolute driven for kinematics; gravity in the \
         plane for dynamics). Each point runs in its own process; *peak* is that process's peak \
         resident memory (VmHWM), model and setup included. Dynamic steps: h = 1 ms, \
         generalized-α with the mass-only iteration matrix (*gen-α M*), with the default \
         finite-difference tangent matrix (*gen-α T*, block-sparse coloured differences; n ≤ 1,000 \
         only, to keep the run short), and DOPRI5 \
         at fixed step (6 stages, projection).\n"
    );
    let _ = writeln!(
        md,
        "| model | bodies | setup (kin) | kinematic frame | iterations | factorizations | allocs / 5 frames | peak (kin) | setup (dyn) | gen-α M step | iterations | gen-α T step | DOPRI5 step | peak (dyn) |\n\
         |---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|"
    );
    let mut fits = String::new();
    let mut series = Vec::new();
    for family in ["chain", "ladder"] {
        let mut kin_pts = Vec::new();
        let mut ga_pts = Vec::new();
        let mut dp_pts = Vec::new();
        let mut mem_pts = Vec::new();
        let mut dmem_pts = Vec::new();
        // Time per factorization of a kinematic frame, per Newton iteration of a gen-α step.
        let mut kin_fact_pts = Vec::new();
        let mut ga_iter_pts = Vec::new();
        for &n in sizes {
            eprintln!("scaling {family} {n}");
            let k = run_point("kin", family, n, cfg.smoke).unwrap_or_default();
            let d = run_point("dyn", family, n, cfg.smoke).unwrap_or_default();
            let nb = get(&k, "bodies").max(get(&d, "bodies"));
            kin_pts.push((nb, get(&k, "frame")));
            ga_pts.push((nb, get(&d, "ga_step")));
            dp_pts.push((nb, get(&d, "dopri_step")));
            mem_pts.push((nb, get(&k, "peak")));
            dmem_pts.push((nb, get(&d, "peak")));
            kin_fact_pts.push((nb, get(&k, "frame") / get(&k, "facts")));
            ga_iter_pts.push((nb, get(&d, "ga_step") / get(&d, "ga_iters")));
            let _ = writeln!(
                md,
                "| {family} | {nb} | {} | {} | {:.2} | {:.2} | {} | {} | {} | {} | {:.2} | {} | {} | {} |",
                fmt_time(get(&k, "setup")),
                fmt_time(get(&k, "frame")),
                get(&k, "iters"),
                get(&k, "facts"),
                get(&k, "allocs"),
                fmt_bytes(get(&k, "peak") as u64),
                fmt_time(get(&d, "setup")),
                fmt_time(get(&d, "ga_step")),
                get(&d, "ga_iters"),
                fmt_time(get(&d, "ga_tangent_step")),
                fmt_time(get(&d, "dopri_step")),
                fmt_bytes(get(&d, "peak") as u64),
            );
        }
        let _ = writeln!(
            fits,
            "| {family} | {:.2} | {:.2} | {:.2} | {:.2} | {:.2} | {:.2} | {:.2} |",
            loglog_slope(&kin_pts),
            loglog_slope(&kin_fact_pts),
            loglog_slope(&ga_pts),
            loglog_slope(&ga_iter_pts),
            loglog_slope(&dp_pts),
            loglog_slope(&mem_pts[mem_pts.len().saturating_sub(2)..]),
            loglog_slope(&dmem_pts[dmem_pts.len().saturating_sub(2)..]),
        );
        series.push(Series {
            label: format!("{family}: kin. frame"),
            points: kin_pts,
        });
        series.push(Series {
            label: format!("{family}: gen-α M step"),
            points: ga_pts,
        });
        series.push(Series {
            label: format!("{family}: DOPRI5 step"),
            points: dp_pts,
        });
    }
    let _ = writeln!(
        md,
        "\n*Iterations* and *factorizations* are per kinematic frame (Newton iterations of the \
         position analysis; factorizations of Φ_v in the position, velocity and acceleration \
         analyses), *iterations* after the gen-α step its Newton iterations per step: how much work \
         a frame or step of the model does (the chain's kinematic frames did more of it the \
         longer the chain until the predictor took each link relative to its parent, \
         optimization 18).\n\n\
         Fitted exponents p of t ∝ n^p (least squares over all sizes; peak memory over the two \
         largest; the dynamic peak at 1,000 bodies includes the tangent run, which is not \
         made at 10,000). *Per factorization* divides the frame time by the factorizations per \
         frame, *per iteration* the step time by the Newton iterations per step: the cost of one \
         unit of the solver's work.\n\n\
         | model | kinematic frame | … per factorization | gen-α M step | … per iteration | DOPRI5 step | peak memory (kin) | peak memory (dyn) |\n\
         |---|---:|---:|---:|---:|---:|---:|---:|\n{fits}\n![Scaling](performance/scaling.svg)\n"
    );
    svgs.push((
        "scaling.svg".into(),
        svg::loglog(
            "Time per kinematic frame / dynamic step",
            "bodies",
            "time [s]",
            &series,
        ),
    ));
    md
}

// ---------------------------------------------------------------------------------------------
// 3. Work-precision.

struct Problem {
    file: &'static str,
    title: &'static str,
    body: &'static str,
    point: &'static str,
    /// Reference table in tests/data/benchmarks and (csv column, xyz component) pairs.
    csv: Option<&'static str>,
    cols: &'static [(usize, usize)],
}

const PROBLEMS: &[Problem] = &[
    Problem {
        file: "a01_pendulum",
        title: "A01 pendulum, 10 s",
        body: "bob",
        point: "P1",
        csv: Some("simple_pendulum_exact.csv"),
        cols: &[(1, 0), (2, 1)],
    },
    Problem {
        file: "a02_fourbar_n2",
        title: "A02 double four-bar, 10 s",
        body: "r0",
        point: "top",
        csv: Some("n_fourbar_N2.csv"),
        cols: &[(1, 0), (2, 1)],
    },
    Problem {
        file: "a03_andrews",
        title: "A03 Andrews' squeezer, 0.03 s",
        body: "OF",
        point: "F",
        csv: None,
        cols: &[],
    },
    Problem {
        file: "a04_bricard",
        title: "A04 Bricard, 10 s",
        body: "rod2",
        point: "C",
        csv: Some("bricard_P3_box.csv"),
        cols: &[(1, 0), (2, 1), (3, 2)],
    },
    Problem {
        file: "a05_flyball",
        title: "A05 flyball governor, 10 s",
        body: "slider",
        point: "centre",
        csv: Some("flyball_governor.csv"),
        cols: &[(1, 2)],
    },
    Problem {
        file: "slider_crank_dynamic",
        title: "IFToMM spatial slider-crank, 5 s",
        body: "slider",
        point: "C",
        csv: Some("spatial_slider_crank_crankCoM_mid.csv"),
        cols: &[(1, 0)],
    },
];

fn read_csv(file: &str) -> Option<Vec<Vec<f64>>> {
    let text = std::fs::read_to_string(root().join("tests/data/benchmarks").join(file)).ok()?;
    Some(
        text.lines()
            .filter(|l| !l.starts_with('#') && !l.trim().is_empty())
            .filter_map(|l| l.split(',').map(|x| x.trim().parse().ok()).collect())
            .collect(),
    )
}

/// Runs a problem with `integ` to `t_end`, outputs at `times`; (CPU s, positions) or None.
fn wp_run(
    p: &Prepared,
    pr: &Problem,
    integ: Integrator,
    t_end: f64,
    times: &[f64],
) -> Option<(f64, Vec<Vector3<f64>>)> {
    let mut opts = cardan_model::analysis::dynamic::options(p, Some(integ)).ok()?;
    opts.t_end = t_end;
    opts.max_steps = 5_000_000;
    let opts = opts
        .output_times(times.to_vec())
        .outputs(Outputs::position_only());
    let mut cpu = f64::INFINITY;
    let mut last = None;
    let mut total = 0.0;
    for _ in 0..5 {
        let mut d = cardan_model::analysis::dynamic::dynamics(p).ok()?;
        let s = cardan_model::analysis::dynamic::initial_state(p);
        let t0 = Instant::now();
        let r = d.simulate(&s, &opts).ok()?;
        let e = t0.elapsed().as_secs_f64();
        cpu = cpu.min(e);
        total += e;
        last = Some(r.point(pr.body, pr.point)?.position.clone());
        if total > 0.3 {
            break;
        }
    }
    Some((cpu, last?))
}

fn work_precision_section(cfg: &Cfg, svgs: &mut Vec<(String, String)>) -> String {
    let mut md = String::new();
    let _ = writeln!(
        md,
        "### Work-precision (dynamics)\n\n\
         Each benchmark problem's model file (`examples/`), every integrator over a range of \
         tolerances (DOPRI5: rtol, atol = rtol/100) or steps (generalized-α, tangent iteration \
         matrix, the file's ρ∞ or 0.8). CPU time: the whole `simulate` call (consistent initial \
         conditions included), best of up to 5 runs. Error: max over the reference times of the \
         output point's position error [m] against the reference table \
         (`tests/data/benchmarks/`, from `shared/benchmarks/`); A03 has no point reference, so \
         its reference is a DOPRI5 run at rtol 1e-12 (*self*). Missing points: the run failed \
         (step too small / Newton) at that setting.\n"
    );
    let ex = examples();
    let mut summary = String::new();
    for pr in PROBLEMS {
        let Some((_, p)) = ex.iter().find(|(n, _)| n == pr.file) else {
            continue;
        };
        let Some(a) = p.loaded.analysis.as_ref() else {
            continue;
        };
        let mut t_end = a.t_end;
        if cfg.smoke {
            t_end *= 0.05;
        }
        let rho = match a.integrator() {
            Some(Integrator::GeneralizedAlpha(o)) => o.rho_inf,
            _ => 0.8,
        };
        let Some(reference) = wp_reference(p, pr, t_end) else {
            continue;
        };
        let span = WpSpan {
            file_t_end: a.t_end,
            t_end,
            rho,
        };
        let curves = wp_curves(cfg, p, pr, &reference, &span, &mut md);
        let best = |v: &[(f64, f64)], tol: f64| {
            v.iter()
                .filter(|(e, _)| *e <= tol)
                .map(|(_, c)| *c)
                .fold(f64::INFINITY, f64::min)
        };
        let _ = writeln!(
            summary,
            "| {} | {} | {} | {} | {} |",
            pr.title,
            fmt_time(best(&curves.dopri5, 1e-3)),
            fmt_time(best(&curves.genalpha, 1e-3)),
            fmt_time(best(&curves.dopri5, 1e-6)),
            fmt_time(best(&curves.genalpha, 1e-6)),
        );
        let stem = pr.file.to_string();
        svgs.push((
            format!("wp_{stem}.svg"),
            svg::loglog(
                pr.title,
                "max position error [m]",
                "CPU time [s]",
                &[
                    Series {
                        label: "DOPRI5".into(),
                        points: curves.dopri5,
                    },
                    Series {
                        label: format!("gen-α ρ∞={rho}"),
                        points: curves.genalpha,
                    },
                ],
            ),
        ));
        let _ = writeln!(md, "\n![{}](performance/wp_{stem}.svg)\n", pr.title);
        eprintln!("work-precision {} done", pr.file);
    }
    let _ = writeln!(
        md,
        "Cheapest run reaching a given accuracy:\n\n| problem | DOPRI5 ≤ 1e-3 m | gen-α ≤ 1e-3 m | DOPRI5 ≤ 1e-6 m | gen-α ≤ 1e-6 m |\n|---|---:|---:|---:|---:|\n{summary}"
    );
    md
}

/// The positions a work-precision run is measured against: at `times`, from the problem's
/// reference table or (without one) from a DOPRI5 run at rtol 1e-12.
struct WpReference {
    times: Vec<f64>,
    positions: Vec<Vector3<f64>>,
    label: &'static str,
}

/// The reference of problem `pr` up to `t_end`; `None` when the self-reference run fails.
fn wp_reference(p: &Prepared, pr: &Problem, t_end: f64) -> Option<WpReference> {
    let table = pr.csv.and_then(read_csv);
    Some(match &table {
        Some(rows) => {
            let rows: Vec<&Vec<f64>> = rows.iter().filter(|r| r[0] <= t_end + 1e-9).collect();
            let times = rows.iter().map(|r| r[0]).collect();
            let refs = rows
                .iter()
                .map(|r| {
                    let mut v = Vector3::zeros();
                    for &(c, k) in pr.cols {
                        v[k] = r[c];
                    }
                    v
                })
                .collect();
            WpReference {
                times,
                positions: refs,
                label: "reference table",
            }
        }
        None => {
            let n = 30;
            let times: Vec<f64> = (0..=n).map(|k| t_end * k as f64 / n as f64).collect();
            let integ = Integrator::Dopri5(Dopri5Options::tolerances(1e-12, 1e-14));
            let (_, refs) = wp_run(p, pr, integ, t_end, &times)?;
            WpReference {
                times,
                positions: refs,
                label: "self (DOPRI5 1e-12)",
            }
        }
    })
}

/// What the runs of one problem share: the file's end time (the generalized-α steps divide
/// it), the end time of the runs (shorter in a smoke run) and the file's ρ∞.
struct WpSpan {
    file_t_end: f64,
    t_end: f64,
    rho: f64,
}

/// The (error, CPU time) points of one problem per integrator.
struct WpCurves {
    dopri5: Vec<(f64, f64)>,
    genalpha: Vec<(f64, f64)>,
}

/// Runs every DOPRI5 tolerance and generalized-α step of problem `pr`, writing its table
/// into `md`.
fn wp_curves(
    cfg: &Cfg,
    p: &Prepared,
    pr: &Problem,
    reference: &WpReference,
    span: &WpSpan,
    md: &mut String,
) -> WpCurves {
    let (times, label) = (&reference.times, reference.label);
    let (file_t_end, t_end, rho) = (span.file_t_end, span.t_end, span.rho);
    let comps: Vec<usize> = if pr.cols.is_empty() {
        vec![0, 1, 2]
    } else {
        pr.cols.iter().map(|c| c.1).collect()
    };
    let err = |pos: &[Vector3<f64>]| -> f64 {
        pos.iter()
            .zip(&reference.positions)
            .map(|(a, b)| {
                comps
                    .iter()
                    .map(|&k| (a[k] - b[k]).abs())
                    .fold(0.0, f64::max)
            })
            .fold(0.0, f64::max)
    };
    let rtols: &[f64] = if cfg.smoke {
        &[1e-5]
    } else {
        &[1e-3, 1e-4, 1e-5, 1e-6, 1e-7, 1e-8, 1e-9, 1e-10, 1e-11]
    };
    let nsteps: &[f64] = if cfg.smoke {
        &[200.0]
    } else {
        &[250.0, 500.0, 1000.0, 2000.0, 4000.0, 8000.0, 16000.0]
    };
    let mut dp = Vec::new();
    let mut ga = Vec::new();
    let _ = writeln!(
        md,
        "**{}** (error against the {label}):\n\n| integrator | setting | CPU | max error [m] |\n|---|---:|---:|---:|",
        pr.title
    );
    for &rtol in rtols {
        let integ = Integrator::Dopri5(Dopri5Options::tolerances(rtol, rtol * 1e-2));
        if let Some((cpu, pos)) = wp_run(p, pr, integ, t_end, times) {
            let e = err(&pos);
            dp.push((e, cpu));
            let _ = writeln!(
                md,
                "| DOPRI5 | rtol {rtol:.0e} | {} | {e:.2e} |",
                fmt_time(cpu)
            );
        } else {
            let _ = writeln!(md, "| DOPRI5 | rtol {rtol:.0e} | failed | — |");
        }
    }
    for &ns in nsteps {
        let h = file_t_end / ns;
        let integ = Integrator::GeneralizedAlpha(GeneralizedAlphaOptions {
            rho_inf: rho,
            ..GeneralizedAlphaOptions::with_step(h)
        });
        if let Some((cpu, pos)) = wp_run(p, pr, integ, t_end, times) {
            let e = err(&pos);
            ga.push((e, cpu));
            let _ = writeln!(
                md,
                "| gen-α ρ∞ {rho} | h {h:.2e} | {} | {e:.2e} |",
                fmt_time(cpu)
            );
        } else {
            let _ = writeln!(md, "| gen-α ρ∞ {rho} | h {h:.2e} | failed | — |");
        }
    }
    WpCurves {
        dopri5: dp,
        genalpha: ga,
    }
}

// ---------------------------------------------------------------------------------------------
// Peers.

fn peers_section(cfg: &Cfg, python: &str) -> String {
    cardan_bench_peers::run(cfg.smoke, python, &root())
}

mod cardan_bench_peers {
    include!("peers.rs");
}

/// `--kinematic-accuracy PYTHON [--smoke] [--svg FILE]`: the work–precision table against
/// OndselSolver to stdout, the plot to FILE (module `kinematic_accuracy`).
fn kinematic_accuracy(args: &[String]) {
    let python = args
        .first()
        .filter(|a| !a.starts_with("--"))
        .map(String::as_str);
    let smoke = args.iter().any(|a| a == "--smoke");
    let (md, svg) = cardan_bench::kinematic_accuracy::work_precision(&root(), python, smoke);
    print!("{md}");
    if let Some(file) = args
        .iter()
        .position(|a| a == "--svg")
        .and_then(|i| args.get(i + 1))
    {
        if let Err(e) = std::fs::write(file, svg) {
            eprintln!("cannot write {file}: {e}");
            std::process::exit(1);
        }
    }
}

/// `--run-memory [--smoke] [--asmt] [--cardan PATH] [STEPS ...]`: peak memory and time of
/// long `cardan run`s (module `run_memory`).
fn run_memory(args: &[String]) {
    let smoke = args.iter().any(|a| a == "--smoke");
    let subject = match args.iter().any(|a| a == "--asmt") {
        true => cardan_bench::run_memory::Subject::CrankSliderAsmt,
        false => cardan_bench::run_memory::Subject::SliderCrank,
    };
    let cardan = args
        .iter()
        .position(|a| a == "--cardan")
        .and_then(|i| args.get(i + 1))
        .map_or_else(cardan_bench::run_memory::default_cardan, PathBuf::from);
    let mut steps: Vec<usize> = args.iter().filter_map(|a| a.parse().ok()).collect();
    if steps.is_empty() {
        steps = if smoke {
            vec![10_000]
        } else {
            vec![10_000, 100_000, 1_000_000]
        };
    }
    print!(
        "{}",
        cardan_bench::run_memory::section(&cardan, &root(), subject, &steps)
    );
}
