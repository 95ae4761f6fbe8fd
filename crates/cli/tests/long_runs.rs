//! Long runs (issue 27, item 9): a dynamic run that needs more than 10⁷ integration steps is
//! refused before it starts (unless `--allow-long`), and Ctrl-C stops any run, keeping its
//! results so far: written, marked partial in run.json, exit code 130.

mod common;

use common::{cardan, edited, scratch, BASE};
use std::path::Path;
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

/// The A01 pendulum with the given `[analysis]` integrator and grid lines.
fn pendulum(analysis: &str) -> String {
    let text = std::fs::read_to_string(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/a01_pendulum.toml"),
    )
    .unwrap();
    let from =
        "integrator = \"dopri5\"\nrtol = 1e-10\natol = 1e-12\nt_end = 10.0\noutput_dt = 0.05";
    assert!(text.contains(from));
    text.replacen(from, analysis, 1)
}

fn run(text: &str, extra: &[&str]) -> common::Outcome {
    let dir = scratch("long");
    std::fs::write(dir.join("model.toml"), text).unwrap();
    let mut args = vec!["run", "model.toml", "-o", "out", "--quiet"];
    args.extend_from_slice(extra);
    cardan(&args, &dir)
}

#[test]
fn dynamic_runs_of_1e10_to_1e13_steps_are_refused_before_they_start() {
    for (analysis, estimate) in [
        (
            "integrator = \"dopri5\"\ndt = 1e-9\nt_end = 10.0\noutput_dt = 0.05",
            "1.00e10",
        ),
        (
            "integrator = \"generalized_alpha\"\ndt = 1e-12\nt_end = 10.0\noutput_dt = 0.05",
            "1.00e13",
        ),
        (
            "integrator = \"dopri5\"\nh_max = 1e-9\nt_end = 100.0\noutput_dt = 0.05",
            "1.00e11",
        ),
    ] {
        let start = Instant::now();
        let o = run(&pendulum(analysis), &[]);
        assert_eq!(o.code, 1, "{analysis}: {}", o.stderr);
        for needle in [estimate, "integration steps", "--allow-long", "10000000"] {
            assert!(
                o.stderr.contains(needle),
                "missing {needle:?}: {}",
                o.stderr
            );
        }
        assert!(start.elapsed() < Duration::from_secs(20));
        assert!(!o.dir.join("out").exists());
    }
}

/// Starts `cardan run model.toml -o out --quiet ARGS` on `text`, sends SIGINT after `delay`,
/// and returns the exit code and the directory.
fn interrupted(
    text: &str,
    extra: &[&str],
    delay: Duration,
) -> (Option<i32>, std::path::PathBuf, String) {
    let dir = scratch("sigint");
    std::fs::write(dir.join("model.toml"), text).unwrap();
    let mut child = Command::new(env!("CARGO_BIN_EXE_cardan"))
        .args(["run", "model.toml", "-o", "out", "--quiet"])
        .args(extra)
        .current_dir(&dir)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    std::thread::sleep(delay);
    let sent = Command::new("kill")
        .args(["-INT", &child.id().to_string()])
        .status()
        .unwrap();
    assert!(sent.success());
    let start = Instant::now();
    let status = loop {
        if let Some(s) = child.try_wait().unwrap() {
            break s;
        }
        if start.elapsed() > Duration::from_secs(60) {
            let _ = child.kill();
            panic!("the run did not stop within 60 s of SIGINT");
        }
        std::thread::sleep(Duration::from_millis(20));
    };
    let mut stderr = String::new();
    use std::io::Read as _;
    child
        .stderr
        .take()
        .unwrap()
        .read_to_string(&mut stderr)
        .unwrap();
    (status.code(), dir, stderr)
}

/// run.json of a run stopped by Ctrl-C, checked: partial, exit code 130, some results.
fn check_partial(dir: &Path, table: &str) {
    let text = std::fs::read_to_string(dir.join("out/run.json")).unwrap();
    let j: serde_json::Value = serde_json::from_str(&text).unwrap();
    assert_eq!(j["status"], "partial", "{j}");
    assert_eq!(j["exit_code"], 130);
    assert!(j["reason"].as_str().unwrap().contains("Ctrl-C"), "{j}");
    let steps = j["steps"].as_u64().unwrap();
    assert!(steps >= 1, "{j}");
    let csv = std::fs::read_to_string(dir.join("out").join(table)).unwrap();
    let (_, rows) = cardan_model::table::parse_csv(&csv).unwrap();
    assert_eq!(rows.len() as u64, steps);
    // (serde_json's default float parsing may be one ulp off: compare to 1e-15.)
    let last = rows.last().unwrap()[0];
    let reached = j["t_reached"].as_f64().unwrap();
    assert!(
        (reached - last).abs() <= 1e-15 * last.abs(),
        "{reached} vs {last}"
    );
}

#[test]
fn ctrl_c_stops_a_long_dynamic_run_and_keeps_its_results() {
    // 10¹⁰ fixed steps: hours of work, accepted with --allow-long.
    let text = pendulum("integrator = \"dopri5\"\ndt = 1e-9\nt_end = 10.0\noutput_dt = 1e-5");
    let (code, dir, stderr) = interrupted(&text, &["--allow-long"], Duration::from_millis(1500));
    assert_eq!(code, Some(130), "{stderr}");
    assert!(stderr.contains("stopped by Ctrl-C"), "{stderr}");
    check_partial(&dir, "points.csv");
}

#[test]
fn ctrl_c_stops_a_long_kinematic_run_and_keeps_its_results() {
    let text = edited("steps = 10", "steps = 3000000");
    let (code, dir, stderr) = interrupted(&text, &[], Duration::from_millis(1500));
    assert_eq!(code, Some(130), "{stderr}");
    check_partial(&dir, "points.csv");
}

#[test]
fn ctrl_c_stops_a_long_inverse_dynamics_run_and_keeps_its_results() {
    let text = BASE.replacen(
        "kind = \"kinematic\"\nt_end = 1.0\nsteps = 10",
        "kind = \"inverse_dynamics\"\nt_end = 1.0\nsteps = 3000000",
        1,
    );
    assert!(text.contains("inverse_dynamics"));
    let (code, dir, stderr) = interrupted(&text, &[], Duration::from_millis(1500));
    assert_eq!(code, Some(130), "{stderr}");
    check_partial(&dir, "driver_efforts.csv");
}
