//! Shared pieces of the CLI tests that run the real binary on generated model files.

#![allow(dead_code)]

use std::path::{Path, PathBuf};
use std::process::Command;
use std::sync::atomic::{AtomicUsize, Ordering};

/// A valid one-body model: a crank on a revolute joint, driven at 1 rad/s.
pub const BASE: &str = r#"[model]
name = "crank"

[ground]
points = { O = [0.0, 0.0, 0.0] }
vectors = { z = [0.0, 0.0, 1.0], x = [1.0, 0.0, 0.0] }

[[body]]
name = "crank"
mass = 1.0
inertia = { diag = [0.01, 0.1, 0.1] }
position = [0.5, 0.0, 0.0]
points = { O = [-0.5, 0.0, 0.0], tip = [0.5, 0.0, 0.0] }
vectors = { z = [0.0, 0.0, 1.0], x = [1.0, 0.0, 0.0] }

[[joint]]
name = "pivot"
type = "revolute"
body_i = "ground"
point_i = "O"
axis_i = "z"
body_j = "crank"
point_j = "O"
axis_j = "z"
x_axis_i = "x"
x_axis_j = "x"

[[driver]]
name = "motor"
type = "rotation"
joint = "pivot"
function = { kind = "polynomial", coefficients = [0.0, 1.0] }

[analysis]
kind = "kinematic"
t_end = 1.0
steps = 10
"#;

static COUNTER: AtomicUsize = AtomicUsize::new(0);

/// A fresh scratch directory under the system temp dir, named after `prefix`.
pub fn scratch(prefix: &str) -> PathBuf {
    let k = COUNTER.fetch_add(1, Ordering::SeqCst);
    let d = std::env::temp_dir().join(format!("cardan-{prefix}-{}-{k}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// [`BASE`] with the first `from` replaced by `to` (`from` must occur).
pub fn edited(from: &str, to: &str) -> String {
    assert!(BASE.contains(from), "{from}");
    BASE.replacen(from, to, 1)
}

/// What a run of the binary printed and returned, and the directory it ran in.
pub struct Outcome {
    pub code: i32,
    pub stdout: String,
    pub stderr: String,
    pub dir: PathBuf,
}

/// Runs `cardan ARGS` in `dir` (with backtraces on, so that a panic cannot pass unnoticed) and
/// asserts that it did not panic.
pub fn cardan(args: &[&str], dir: &Path) -> Outcome {
    let out = Command::new(env!("CARGO_BIN_EXE_cardan"))
        .args(args)
        .current_dir(dir)
        .env("RUST_BACKTRACE", "1")
        .output()
        .expect("the binary runs");
    let o = Outcome {
        code: out.status.code().unwrap_or(-1),
        stdout: String::from_utf8_lossy(&out.stdout).into_owned(),
        stderr: String::from_utf8_lossy(&out.stderr).into_owned(),
        dir: dir.to_path_buf(),
    };
    assert!(
        !o.stderr.contains("panicked") && !o.stderr.contains("stack backtrace"),
        "panic: {}",
        o.stderr
    );
    o
}

/// Writes `text` as model.toml in a fresh directory and runs `cardan run model.toml -o out
/// --quiet` (`cmd` = "run") or `cardan <cmd> model.toml`.
pub fn run_text(cmd: &str, text: &str) -> Outcome {
    let dir = scratch(cmd);
    std::fs::write(dir.join("model.toml"), text).unwrap();
    match cmd {
        "run" => cardan(&["run", "model.toml", "-o", "out", "--quiet"], &dir),
        other => cardan(&[other, "model.toml"], &dir),
    }
}
