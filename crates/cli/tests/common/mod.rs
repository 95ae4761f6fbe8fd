//! Shared pieces of the CLI tests that run the real binary on generated model files.

#![allow(dead_code)]

use std::path::{Path, PathBuf};
use std::process::Command;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::OnceLock;

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

/// This test process's scratch root: `cli-scratch/<test binary>/<process id>` under cargo's
/// temporary directory for integration tests (inside `target/`, so `cargo clean` removes it).
/// The first call removes the roots that earlier runs of the same test binary left (their
/// processes have ended: nothing else removes a test's directories, about 150 per run).
fn scratch_root() -> &'static Path {
    static ROOT: OnceLock<PathBuf> = OnceLock::new();
    ROOT.get_or_init(|| {
        let exe = std::env::current_exe().expect("the test binary's path");
        let name = exe
            .file_stem()
            .map_or("tests".into(), |s| s.to_string_lossy().into_owned());
        let parent = Path::new(env!("CARGO_TARGET_TMPDIR"))
            .join("cli-scratch")
            .join(name);
        let me = std::process::id();
        for entry in std::fs::read_dir(&parent).into_iter().flatten().flatten() {
            let pid = entry.file_name().to_string_lossy().parse::<u32>().ok();
            if pid.is_some_and(|p| p != me && !process_alive(p)) {
                let _ = std::fs::remove_dir_all(entry.path());
            }
        }
        parent.join(me.to_string())
    })
}

/// Whether process `pid` is running (Linux's `/proc`; elsewhere assumed running, so nothing is
/// removed).
fn process_alive(pid: u32) -> bool {
    let proc = Path::new("/proc");
    !proc.is_dir() || proc.join(pid.to_string()).exists()
}

/// A fresh scratch directory of this test process, named after `prefix` ([`scratch_root`]).
pub fn scratch(prefix: &str) -> PathBuf {
    let k = COUNTER.fetch_add(1, Ordering::SeqCst);
    let d = scratch_root().join(format!("{prefix}-{k}"));
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

/// `cardan check` on `text` fails with its error at 1-based line `line` (the message starts
/// with `model.toml:LINE:`) and a message containing every needle.
pub fn check_fails_at(text: &str, line: usize, needles: &[&str]) {
    fails_with("check", text, &format!("model.toml:{line}:"), needles);
}

/// `cardan <cmd>` on `text` (as [`run_text`]) fails with an error starting with `want` and
/// containing every needle.
pub fn fails_with(cmd: &str, text: &str, want: &str, needles: &[&str]) -> Outcome {
    let o = run_text(cmd, text);
    assert_ne!(o.code, 0, "should fail: {}", o.stdout);
    assert!(o.stderr.starts_with(want), "want {want}, got: {}", o.stderr);
    for n in needles {
        assert!(o.stderr.contains(n), "missing {n:?} in: {}", o.stderr);
    }
    o
}

/// A written MatrixMarket coordinate file (`%%MatrixMarket matrix coordinate real general`):
/// rows, columns and the entries with 0-based indices; the header's entry count is checked.
pub fn matrix_market_triplets(path: &Path) -> (usize, usize, Vec<(usize, usize, f64)>) {
    let t = std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    assert!(
        t.starts_with("%%MatrixMarket matrix coordinate real general\n"),
        "{}: header",
        path.display()
    );
    let mut lines = t.lines().filter(|l| !l.starts_with('%'));
    let dims: Vec<usize> = lines
        .next()
        .unwrap()
        .split_whitespace()
        .map(|x| x.parse().unwrap())
        .collect();
    let e: Vec<(usize, usize, f64)> = lines
        .map(|l| {
            let f: Vec<&str> = l.split_whitespace().collect();
            let (r, c): (usize, usize) = (f[0].parse().unwrap(), f[1].parse().unwrap());
            (r - 1, c - 1, f[2].parse().unwrap())
        })
        .collect();
    assert_eq!(e.len(), dims[2], "{}: entry count", path.display());
    (dims[0], dims[1], e)
}

/// A written MatrixMarket coordinate file as a dense matrix (repeated entries summed).
pub fn matrix_market_dense(path: &Path) -> nalgebra::DMatrix<f64> {
    let (rows, cols, entries) = matrix_market_triplets(path);
    let mut m = nalgebra::DMatrix::zeros(rows, cols);
    for (r, c, v) in entries {
        m[(r, c)] += v;
    }
    m
}

/// The RSSR four-bar's rocker tip Q (`examples/rssr_fourbar.toml`) at crank angle θ on the drawn
/// branch (closed form of `examples.rs::rssr_matches_closed_form`).
pub fn rssr_q(th: f64) -> nalgebra::Vector3<f64> {
    use nalgebra::Vector3;
    let (a, b, l) = (0.1, 0.2, 0.35);
    let g = Vector3::new(0.3, 0.15, 0.1);
    let w = g - Vector3::new(a * th.cos(), a * th.sin(), 0.0);
    let cc = (l * l - w.norm_squared() - b * b) / (2.0 * b);
    let psi = w.z.atan2(w.x) + (cc / w.x.hypot(w.z)).acos();
    g + b * Vector3::new(psi.cos(), 0.0, psi.sin())
}

/// The tool `what` from `var`, or `None` after the skip message (a panic under CI).
pub fn tool(var: &str, what: &str, fallback: Option<PathBuf>) -> Option<PathBuf> {
    let found = std::env::var_os(var)
        .map(PathBuf::from)
        .or(fallback)
        .filter(|p| p.exists());
    if found.is_none() {
        let msg = format!(
            "{what} not found (set {var}, or run scripts/test, which installs it and sets it)"
        );
        if std::env::var_os("CI").is_some() {
            panic!("CI is set and {msg}");
        }
        eprintln!("\n!!!!!!!! SKIPPED: {msg} !!!!!!!!\n");
    }
    found
}

/// Headless Chromium (`CARDAN_CHROMIUM`, else the Debian paths), or `None` after the skip
/// message (a panic under CI).
pub fn chromium() -> Option<PathBuf> {
    let fallback = ["/usr/bin/chromium", "/usr/bin/chromium-browser"]
        .iter()
        .map(PathBuf::from)
        .find(|p| p.exists());
    tool("CARDAN_CHROMIUM", "headless Chromium", fallback)
}
