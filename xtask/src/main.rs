//! Project tasks, run as `cargo xtask <task>`.
//!
//! - `cargo xtask oracle`: regenerate `oracle/data/` with the CasADi oracle (see `oracle/README.md`).
//! - `cargo xtask oracle --check`: fail when the committed `oracle/data/` are stale.
//! - `cargo xtask stress [--quick]`: the numerical stability stress suite (docs/stress.md).

mod oracle;
mod stress;

use std::process::ExitCode;

const USAGE: &str = "usage: cargo xtask oracle [--check] | stress [--quick]

tasks:
  oracle            create/update the Python venv under target/ and regenerate oracle/data/
  oracle --check    regenerate into target/ and fail if oracle/data/ differs (CI)
  stress            stress suites with many cases (release), 10^6-frame and 10^5-step runs
  stress --quick    the stress subset that cargo test --workspace runs (CI)";

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let args: Vec<&str> = args.iter().map(String::as_str).collect();
    let result = match args.as_slice() {
        ["oracle"] => oracle::run(oracle::Mode::Write),
        ["oracle", "--check"] => oracle::run(oracle::Mode::Check),
        ["stress"] => stress::run(false),
        ["stress", "--quick"] => stress::run(true),
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
