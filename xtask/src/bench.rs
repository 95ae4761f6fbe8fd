//! `cargo xtask bench [--smoke] [--peers]`: the performance benchmarks and their report.
//!
//! 1. Builds `cardan-bench` (crates/bench) in release mode.
//! 2. With `--peers`: creates `target/peers-venv` and installs the pinned peers
//!    (`bench/peers/requirements.txt`: Exudyn, pyondsel). If Python, the venv or pip fails, it
//!    says so and the benchmarks run without peers (the report says why).
//! 3. Runs `target/release/cardan-bench`, which measures kinematic frames, scaling to 10,000
//!    bodies, work-precision of the dynamics benchmark problems, Newton tolerance, and (with
//!    peers) Exudyn / OndselSolver side by side, then writes the marked section of
//!    `docs/performance.md` and the SVG plots under `docs/performance/`.
//!
//! `--smoke` runs a few iterations of everything (about half a minute after the build) and writes
//! to `target/bench/` instead of `docs/`, so CI can prove that the benchmarks build and run.
//!
//! `cargo xtask bench --peers-only [kinematics|slider-crank|chain ...]` runs only the peer
//! comparisons (all three, or the ones named) and prints their Markdown tables to stdout,
//! without touching `docs/` (minutes instead of the hour of a full report).

use std::path::{Path, PathBuf};
use std::process::Command;

fn root() -> PathBuf {
    crate::workspace_root()
}

/// Builds `cardan-bench` in release mode — selected together with `cardan-python` so cargo unifies
/// the dependencies' features as for the wheel and the `cardan` command (scripts/python-env): the
/// three share one release build of the dependencies instead of compiling them once each.
fn build(root: &Path) -> Result<(), String> {
    let cargo = std::env::var("CARGO").unwrap_or_else(|_| "cargo".into());
    let status = Command::new(&cargo)
        .current_dir(root)
        .args([
            "build",
            "--release",
            "-p",
            "cardan-bench",
            "-p",
            "cardan-python",
            "--bin",
            "cardan-bench",
        ])
        .status()
        .map_err(|e| format!("cannot run cargo: {e}"))?;
    if !status.success() {
        return Err("cargo build -p cardan-bench failed".into());
    }
    Ok(())
}

/// Runs only the peer comparisons named in `which` (all when empty), tables to stdout.
pub fn peers_only(which: &[&str]) -> Result<(), String> {
    const NAMES: [&str; 3] = ["kinematics", "slider-crank", "chain"];
    if let Some(bad) = which.iter().find(|w| !NAMES.contains(w)) {
        return Err(format!(
            "unknown peer comparison '{bad}' (expected any of {})",
            NAMES.join(", ")
        ));
    }
    let root = root();
    build(&root)?;
    let python = peers_python(&root)?;
    let status = Command::new(root.join("target/release/cardan-bench"))
        .current_dir(&root)
        .arg("--peers-only")
        .arg(python)
        .args(which)
        .status()
        .map_err(|e| format!("cannot run cardan-bench: {e}"))?;
    if !status.success() {
        return Err("cardan-bench --peers-only failed".into());
    }
    Ok(())
}

/// Runs the benchmarks.
pub fn run(smoke: bool, peers: bool) -> Result<(), String> {
    let root = root();
    build(&root)?;
    let (report, plots) = if smoke {
        let dir = root.join("target/bench");
        (dir.join("benchmarks-smoke.md"), dir.join("plots"))
    } else {
        (
            root.join("docs/performance.md"),
            root.join("docs/performance"),
        )
    };
    let mut cmd = Command::new(root.join("target/release/cardan-bench"));
    cmd.current_dir(&root);
    if smoke {
        cmd.arg("--smoke");
    }
    cmd.arg("--report").arg(&report).arg("--plots").arg(&plots);
    if peers {
        match peers_python(&root) {
            Ok(python) => {
                cmd.arg("--peers").arg(python);
            }
            Err(e) => {
                eprintln!("bench: peers unavailable, running without them: {e}");
                cmd.arg("--peers-error").arg(e);
            }
        }
    }
    let status = cmd
        .status()
        .map_err(|e| format!("cannot run cardan-bench: {e}"))?;
    if !status.success() {
        return Err("cardan-bench failed".into());
    }
    eprintln!(
        "bench: report in {}, plots in {}",
        report.display(),
        plots.display()
    );
    Ok(())
}

/// The venv's Python with the peers installed.
fn peers_python(root: &Path) -> Result<PathBuf, String> {
    let venv = root.join("target/peers-venv");
    let python = venv.join("bin/python");
    if !python.exists() {
        let py = ["python3", "python"]
            .into_iter()
            .find(|p| {
                Command::new(p)
                    .arg("-V")
                    .output()
                    .is_ok_and(|o| o.status.success())
            })
            .ok_or("no python3 on PATH (the peers are PyPI packages)")?;
        let ok = Command::new(py)
            .args(["-m", "venv"])
            .arg(&venv)
            .status()
            .map_err(|e| format!("{py} -m venv: {e}"))?
            .success();
        if !ok {
            return Err(format!(
                "`{py} -m venv {}` failed (install the venv module)",
                venv.display()
            ));
        }
    }
    let out = Command::new(&python)
        .args(["-m", "pip", "install", "-q", "-r"])
        .arg(root.join("bench/peers/requirements.txt"))
        .output()
        .map_err(|e| format!("pip: {e}"))?;
    if !out.status.success() {
        let err = String::from_utf8_lossy(&out.stderr);
        return Err(format!(
            "pip could not install exudyn / pyondsel ({}): {}",
            "bench/peers/requirements.txt",
            err.lines().last().unwrap_or("no message")
        ));
    }
    Ok(python)
}
