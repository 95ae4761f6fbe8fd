//! Project tasks, run as `cargo xtask <task>`.
//!
//! - `cargo xtask oracle`: regenerate `oracle/data/` with the CasADi oracle (see `oracle/README.md`).
//! - `cargo xtask oracle --check`: fail when the committed `oracle/data/` are stale.
//! - `cargo xtask stress [--quick]`: the numerical stability stress suite (docs/stress.md).
//! - `cargo xtask bench [--smoke] [--peers]`: performance benchmarks → docs/benchmarks.md.
//! - `cargo xtask bench --peers-only [kinematics|slider-crank|chain ...]`: the peer comparisons
//!   alone, tables to stdout.

mod bench;
mod oracle;
mod stress;

use std::process::ExitCode;

const USAGE: &str = "usage: cargo xtask oracle [--check] | stress [--quick] | bench [--smoke] [--peers]
       cargo xtask bench --peers-only [kinematics|slider-crank|chain ...]

tasks:
  oracle            create/update the Python venv under target/ and regenerate oracle/data/
  oracle --check    regenerate into target/ and fail if oracle/data/ differs (CI)
  stress            stress suites with many cases (release), 10^6-frame and 10^5-step runs
  stress --quick    the stress subset that cargo test --workspace runs (CI)
  bench             performance benchmarks; writes docs/benchmarks.md (performance section) and plots
  bench --smoke     a few iterations of every benchmark (CI); writes target/bench/
  bench --peers     also Exudyn and OndselSolver side by side (PyPI, venv in target/)
  bench --peers-only [NAME ...]
                    only the peer comparisons (all, or those named), tables to stdout";

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
