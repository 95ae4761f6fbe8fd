//! Large models through the command line's library: `cardan check`, the setup of a kinematic
//! run (one step) and the whole `cardan run` with its outputs, of driven revolute chains of 10³,
//! 10⁴ and 10⁵ bodies, each in its own process
//! (time and peak resident memory, `VmHWM`), with the fitted cost exponent.
//!
//! The model files are generated into the system's temporary directory (never into the
//! repository): an open chain of unit rods along x, revolute joints with axes alternating z and
//! y, every joint driven (θ = 0.1 t), a kinematic analysis of one step.

use crate::measure::{fmt_bytes, fmt_time, loglog_slope, peak_rss_bytes};
use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::time::Instant;

/// Appends the `[[body]]` tables of `n` unit rods b0 … b(n−1) along x (mass 1 kg, principal
/// moments `inertia`, centres at x = k + ½, points `a` and `b` at their ends), each followed by
/// the TOML lines `extra`.
pub fn push_rods(s: &mut String, n: usize, inertia: [f64; 3], extra: &str) {
    for k in 0..n {
        let _ = write!(
            s,
            "\n[[body]]\nname = \"b{k}\"\nmass = 1.0\ninertia = {{ diag = {inertia:?} }}\n\
             position = [{}, 0.0, 0.0]\n\
             points = {{ a = [-0.5, 0.0, 0.0], b = [0.5, 0.0, 0.0] }}\n{extra}",
            k as f64 + 0.5
        );
    }
}

/// The model file of the driven revolute chain of `n` bodies.
pub fn chain_toml(n: usize) -> String {
    let mut s = String::with_capacity(700 * n + 400);
    s.push_str(
        "[model]\nname = \"large_chain\"\nunits = \"SI\"\n\n[ground]\n\
         points = { O = [0.0, 0.0, 0.0] }\n\
         vectors = { x = [1.0, 0.0, 0.0], y = [0.0, 1.0, 0.0], z = [0.0, 0.0, 1.0] }\n",
    );
    push_rods(
        &mut s,
        n,
        [0.01, 0.1, 0.1],
        "vectors = { x = [1.0, 0.0, 0.0], y = [0.0, 1.0, 0.0], z = [0.0, 0.0, 1.0] }\n",
    );
    push_chain_joints(&mut s, n);
    push_chain_drivers(&mut s, n);
    s.push_str("\n[analysis]\nkind = \"kinematic\"\nt_end = 0.01\nsteps = 1\n");
    s
}

/// The revolute joints j0 … j(n−1): j0 from the ground's point O to b0's end a, then each
/// rod's end b to the next one's a, with axes alternating z and y and x axes for the angle.
fn push_chain_joints(s: &mut String, n: usize) {
    for k in 0..n {
        let (prev, point) = if k == 0 {
            ("ground".to_string(), "O")
        } else {
            (format!("b{}", k - 1), "b")
        };
        let axis = if k % 2 == 0 { "z" } else { "y" };
        let _ = write!(
            s,
            "\n[[joint]]\nname = \"j{k}\"\ntype = \"revolute\"\nbody_i = \"{prev}\"\n\
             point_i = \"{point}\"\naxis_i = \"{axis}\"\nbody_j = \"b{k}\"\npoint_j = \"a\"\n\
             axis_j = \"{axis}\"\nx_axis_i = \"x\"\nx_axis_j = \"x\"\n"
        );
    }
}

/// θ_k = 0.1 t for every joint.
const CHAIN_DRIVER_FUNCTION: &str = "{ kind = \"polynomial\", coefficients = [0.0, 0.1] }";

/// One rotation driver per joint, d0 … d(n−1), each [`CHAIN_DRIVER_FUNCTION`].
fn push_chain_drivers(s: &mut String, n: usize) {
    for k in 0..n {
        let _ = write!(
            s,
            "\n[[driver]]\nname = \"d{k}\"\ntype = \"rotation\"\njoint = \"j{k}\"\n\
             function = {CHAIN_DRIVER_FUNCTION}\n"
        );
    }
}

fn model_path(n: usize) -> PathBuf {
    std::env::temp_dir().join(format!(
        "cardan-bench-large-chain-{n}-{}.toml",
        std::process::id()
    ))
}

/// Child mode (`cardan-bench --large-point check|run|whole FILE`): runs the command's library entry
/// once and prints `RESULT seconds=… peak=…`.
pub fn point(args: &[String]) {
    let what = args.first().map(String::as_str).unwrap_or("check");
    let path = Path::new(args.get(1).map(String::as_str).unwrap_or(""));
    let out = path.with_extension("out");
    let t0 = Instant::now();
    let ok = match what {
        "whole" => {
            let flags = cardan_model::analysis::RunFlags::default();
            let r = cardan_cli::commands::run::run(path, Some(&out), &flags, &mut std::io::sink());
            r.map(|_| ())
        }
        "run" => cardan_model::prepare::prepare(path).and_then(|p| {
            let analysis = p.loaded.analysis.clone().expect("the file has [analysis]");
            let flags = cardan_model::analysis::RunFlags::default();
            cardan_model::analysis::analyse(&p, &analysis, &flags).map(|_| ())
        }),
        _ => cardan_model::check::check(path, &mut std::io::sink()),
    };
    // The outputs are removed after the clock stops: the bench's housekeeping, not the run's.
    let seconds = t0.elapsed().as_secs_f64();
    let _ = std::fs::remove_dir_all(&out);
    if let Err(e) = ok {
        eprintln!("{what} {}: {e}", path.display());
        std::process::exit(1);
    }
    println!(
        "RESULT seconds={seconds:e} peak={}",
        peak_rss_bytes().unwrap_or(0)
    );
}

/// Runs one point in a child process: (seconds, peak bytes).
fn run_child(what: &str, path: &Path) -> Option<(f64, f64)> {
    let exe = std::env::current_exe().ok()?;
    let o = std::process::Command::new(exe)
        .arg("--large-point")
        .arg(what)
        .arg(path)
        .output()
        .ok()?;
    if !o.status.success() {
        eprintln!(
            "large model point {what} failed: {}",
            String::from_utf8_lossy(&o.stderr)
        );
        return None;
    }
    let s = String::from_utf8_lossy(&o.stdout);
    let line = s.lines().find(|l| l.starts_with("RESULT "))?;
    let get = |k: &str| {
        line.split_whitespace()
            .find_map(|kv| kv.strip_prefix(k)?.strip_prefix('=')?.parse::<f64>().ok())
    };
    Some((get("seconds")?, get("peak")?))
}

/// The markdown section: a table of sizes and the fitted exponents.
pub fn section(smoke: bool) -> String {
    let sizes: &[usize] = if smoke {
        &[1_000]
    } else {
        &[1_000, 10_000, 100_000]
    };
    let mut md = String::from(
        "### Large models: `cardan check` and run setup\n\n\
         Driven revolute chains (`crates/bench/src/large.rs`: unit rods along x, axes alternating \
         z and y, every joint driven), model file generated in the temporary directory. *check* \
         is `cardan check` (parse, model checks, assembly, degrees of freedom and redundant \
         equations by the sparse rank analysis, kinematic preparation); *run setup* is \
         `cardan run`'s analysis of one kinematic step without writing outputs; *whole run* is \
         `cardan run` with every output written (tables, plots, animation, report, run.json; \
         into the temporary directory, removed after the clock stops; the model file is synced \
         to disk before). Each point runs in its own process; *peak* is its peak resident memory (VmHWM).\n\n\
         | bodies | file | check | peak (check) | peak / body | run setup + 1 step | peak (run) | whole run | peak (whole) |\n\
         |---:|---:|---:|---:|---:|---:|---:|---:|---:|\n",
    );
    let mut check_pts = Vec::new();
    let mut run_pts = Vec::new();
    let mut whole_pts = Vec::new();
    for &n in sizes {
        let path = model_path(n);
        let text = chain_toml(n);
        // Written through to the disk before the clock starts, so that the kernel's writing of
        // the 50 MB file does not fall into the measured check.
        let written = std::fs::File::create(&path).and_then(|mut f| {
            std::io::Write::write_all(&mut f, text.as_bytes())?;
            f.sync_all()
        });
        if written.is_err() {
            let _ = writeln!(md, "| {n} | (could not write {}) |", path.display());
            continue;
        }
        let c = run_child("check", &path);
        let r = run_child("run", &path);
        let w = run_child("whole", &path);
        let _ = std::fs::remove_file(&path);
        let cell = |v: Option<(f64, f64)>, f: &dyn Fn((f64, f64)) -> String| {
            v.map_or("failed".to_string(), f)
        };
        let _ = writeln!(
            md,
            "| {n} | {} | {} | {} | {} | {} | {} | {} | {} |",
            fmt_bytes(text.len() as u64),
            cell(c, &|(t, _)| fmt_time(t)),
            cell(c, &|(_, p)| fmt_bytes(p as u64)),
            cell(c, &|(_, p)| fmt_bytes((p / n as f64) as u64)),
            cell(r, &|(t, _)| fmt_time(t)),
            cell(r, &|(_, p)| fmt_bytes(p as u64)),
            cell(w, &|(t, _)| fmt_time(t)),
            cell(w, &|(_, p)| fmt_bytes(p as u64)),
        );
        if let Some((t, _)) = c {
            check_pts.push((n as f64, t));
        }
        if let Some((t, _)) = r {
            run_pts.push((n as f64, t));
        }
        if let Some((t, _)) = w {
            whole_pts.push((n as f64, t));
        }
    }
    let _ = writeln!(
        md,
        "\nFitted exponents p of t ∝ n^p: check {:.2}, run setup {:.2}, whole run {:.2}.\n",
        loglog_slope(&check_pts),
        loglog_slope(&run_pts),
        loglog_slope(&whole_pts)
    );
    md
}
