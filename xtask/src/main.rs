//! Project tasks, run as `cargo xtask <task>`.
//!
//! - `cargo xtask oracle`: regenerate `oracle/data/` with the CasADi oracle (see `oracle/README.md`).
//! - `cargo xtask oracle --check`: fail when the committed `oracle/data/` are stale.
//! - `cargo xtask stress [--quick]`: the numerical stability stress suite (docs/stress.md).
//! - `cargo xtask bench [--smoke] [--peers]`: performance benchmarks → docs/performance.md.
//! - `cargo xtask bench --peers-only [kinematics|slider-crank|chain ...]`: the peer comparisons
//!   alone, tables to stdout.
//! - `cargo xtask docs`: regenerate the tables of docs/ that come from code (the joint table, the key tables).
//! - `cargo xtask compare-outputs <rev>`: every example's CSV output at `<rev>` and now, byte for
//!   byte.

mod bench;
mod oracle;
mod outputs;
mod stress;

use std::path::{Path, PathBuf};
use std::process::{Command, ExitCode};

const USAGE: &str =
    "usage: cargo xtask oracle [--check] | stress [--quick] | bench [--smoke] [--peers]
       cargo xtask bench --peers-only [kinematics|slider-crank|chain ...]
       cargo xtask docs | compare-outputs REV

tasks:
  oracle            create/update the Python venv under target/ and regenerate oracle/data/
  oracle --check    regenerate into target/ and fail if oracle/data/ differs (CI)
  stress            stress suites with many cases (release), 10^6-frame and 10^5-step runs
  stress --quick    the stress subset that cargo test --workspace runs (CI)
  bench             performance benchmarks; writes docs/performance.md (generated section) and plots
  bench --smoke     a few iterations of every benchmark (CI); writes target/bench/
  bench --peers     also Exudyn and OndselSolver side by side (PyPI, venv in target/)
  bench --peers-only [NAME ...]
                    only the peer comparisons (all, or those named), tables to stdout
  docs              regenerate docs/model-format.md's joint and key tables from the code's tables
  compare-outputs REV
                    every example's CSV files at commit REV and in the working tree, byte for byte";

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let args: Vec<&str> = args.iter().map(String::as_str).collect();
    let result = match args.as_slice() {
        ["oracle"] => oracle::run(oracle::Mode::Write),
        ["oracle", "--check"] => oracle::run(oracle::Mode::Check),
        ["stress"] => stress::run(false),
        ["stress", "--quick"] => stress::run(true),
        ["bench", "--peers-only", which @ ..] => bench::peers_only(which),
        ["bench", flags @ ..] if flags.iter().all(|f| matches!(*f, "--smoke" | "--peers")) => {
            bench::run(flags.contains(&"--smoke"), flags.contains(&"--peers"))
        }
        ["docs"] => docs(),
        ["compare-outputs", rev] => outputs::run(rev),
        ["help"] | ["--help"] | ["-h"] => {
            println!("{USAGE}");
            return ExitCode::SUCCESS;
        }
        _ => {
            eprintln!("{USAGE}");
            return ExitCode::from(2);
        }
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::FAILURE
        }
    }
}

/// The workspace root (the parent of the `xtask` package).
pub fn workspace_root() -> PathBuf {
    let manifest = Path::new(env!("CARGO_MANIFEST_DIR"));
    manifest.parent().unwrap_or(manifest).to_path_buf()
}

/// Writes the generated tables of docs/ (the tests that check them, in bless mode): the joint
/// table from the kind table, the key tables from the model file's vocabularies.
fn docs() -> Result<(), String> {
    for (package, test, what) in [
        ("cardan-constraints", "docs_table", "the joint table"),
        ("cardan-model", "docs_tables", "the key tables"),
    ] {
        let mut cmd = Command::new(std::env::var("CARGO").unwrap_or_else(|_| "cargo".into()));
        cmd.args(["test", "-q", "-p", package, "--test", test])
            .env("CARDAN_BLESS", "1")
            .current_dir(workspace_root());
        run_status(cmd, &format!("writing {what}"))?;
        println!("docs/model-format.md: {what} written");
    }
    Ok(())
}

/// Runs `cmd` to completion in the foreground; an error names `what` when it cannot start or
/// fails.
pub fn run_status(mut cmd: Command, what: &str) -> Result<(), String> {
    let status = cmd
        .status()
        .map_err(|e| format!("cannot run {what}: {e}"))?;
    if status.success() {
        Ok(())
    } else {
        Err(format!("{what} failed"))
    }
}
