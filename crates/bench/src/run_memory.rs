//! Peak memory and wall time of a long `cardan run` (issue 25): the slider-crank kinematic run
//! of `examples/slider_crank.toml` with `steps` set to 10⁴, 10⁵, 10⁶, each in its own child
//! process of the `cardan` binary, everything written (CSV, SVG plots, run.json,
//! animation.glb, index.html) into a temporary directory that is removed afterwards.
//!
//! Peak memory is the child's peak resident set (`VmHWM`, polled every 2 ms until it exits);
//! wall time is from spawn to exit, processor time from `/proc/PID/stat`.
//!
//! `cardan-bench --run-memory [--smoke] [--asmt] [--cardan PATH] [STEPS ...]`: one table row
//! per step count (default 10⁴ 10⁵ 10⁶; `--smoke`: 10⁴ only). `--asmt` runs the FreeCAD
//! assembly `crates/asmt/tests/data/crank_slider.asmt` instead, with `hout` = 1 s / STEPS (its
//! `.solved.asmt` TimeSeries written too). `--cardan` measures another build of the binary
//! (e.g. the main branch's, for a before/after comparison); by default the `cardan` next to
//! `cardan-bench`.

use crate::measure::{fmt_bytes, fmt_time};
use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::Instant;

/// One measured run.
#[derive(Debug, Clone, Copy)]
pub struct RunMemory {
    /// Grid steps of the run.
    pub steps: usize,
    /// Peak resident set of the child \[bytes\].
    pub peak_rss: u64,
    /// Wall time from spawn to exit \[s\].
    pub wall: f64,
    /// Processor time of the child, user + system \[s\] (what a busy shared machine changes
    /// least).
    pub cpu: f64,
    /// Total size of the output directory \[bytes\].
    pub output_bytes: u64,
}

/// The `cardan` binary next to the running executable.
pub fn default_cardan() -> PathBuf {
    std::env::current_exe()
        .ok()
        .and_then(|e| e.parent().map(|d| d.join("cardan")))
        .unwrap_or_else(|| PathBuf::from("cardan"))
}

/// The model a run measures.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Subject {
    /// `examples/slider_crank.toml`, kinematic.
    SliderCrank,
    /// `crates/asmt/tests/data/crank_slider.asmt` (t = 0 … 1 s), kinematic.
    CrankSliderAsmt,
}

impl Subject {
    /// The model's file path relative to the repository and its file name.
    fn file(self) -> (&'static str, &'static str) {
        match self {
            Self::SliderCrank => ("examples/slider_crank.toml", "slider_crank.toml"),
            Self::CrankSliderAsmt => (
                "crates/asmt/tests/data/crank_slider.asmt",
                "crank_slider.asmt",
            ),
        }
    }

    /// The model text with `steps` grid steps.
    fn text(self, root: &Path, steps: usize) -> String {
        let (path, _) = self.file();
        let text = std::fs::read_to_string(root.join(path)).expect(path);
        let edited = match self {
            Self::SliderCrank => text.replace("steps = 200", &format!("steps = {steps}")),
            Self::CrankSliderAsmt => text.replacen(
                "\t\thout\n\t\t\t0.01 \n",
                &format!("\t\thout\n\t\t\t{:e}\n", 1.0 / steps as f64),
                1,
            ),
        };
        assert_ne!(edited, text, "{path} no longer has its step");
        edited
    }
}

/// Runs `cardan run` on `subject` with `steps` steps and measures it.
///
/// # Errors
/// The child could not start or failed (its stderr's last line).
pub fn measure(
    cardan: &Path,
    root: &Path,
    subject: Subject,
    steps: usize,
) -> Result<RunMemory, String> {
    let dir =
        std::env::temp_dir().join(format!("cardan-run-memory-{}-{steps}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).map_err(|e| e.to_string())?;
    let model = dir.join(subject.file().1);
    std::fs::write(&model, subject.text(root, steps)).map_err(|e| e.to_string())?;
    let out = dir.join("out");
    let log = dir.join("stderr.txt");
    let stderr_file = std::fs::File::create(&log).map_err(|e| e.to_string())?;
    let t0 = Instant::now();
    let child = Command::new(cardan)
        .arg("run")
        .arg(&model)
        .arg("-o")
        .arg(&out)
        .arg("--quiet")
        .stdout(Stdio::null())
        .stderr(stderr_file)
        .spawn()
        .map_err(|e| format!("cannot start {}: {e}", cardan.display()))?;
    let (status, peak_rss, cpu) = wait_with_usage(child)?;
    let wall = t0.elapsed().as_secs_f64();
    let output_bytes = std::fs::read_dir(&out)
        .map(|d| {
            d.filter_map(|e| e.ok()?.metadata().ok())
                .map(|m| m.len())
                .sum()
        })
        .unwrap_or(0);
    let stderr = std::fs::read_to_string(&log).unwrap_or_default();
    let _ = std::fs::remove_dir_all(&dir);
    if status != 0 {
        return Err(format!(
            "cardan run ({steps} steps) exited with {status}: {}",
            stderr.lines().last().unwrap_or("")
        ));
    }
    Ok(RunMemory {
        steps,
        peak_rss,
        wall,
        cpu,
        output_bytes,
    })
}

/// Waits for `child`, polling its peak resident set (`VmHWM` of `/proc/PID/status`) and
/// processor time (user + system ticks of `/proc/PID/stat`, 100 per second) every 2 ms; returns
/// the exit code, the last peak read [bytes] and the last processor time read [s] (both
/// monotonic, so the last reads before exit are within 2 ms of the final values).
fn wait_with_usage(mut child: std::process::Child) -> Result<(i32, u64, f64), String> {
    let status_file = format!("/proc/{}/status", child.id());
    let stat_file = format!("/proc/{}/stat", child.id());
    let (mut peak, mut cpu) = (0u64, 0.0f64);
    loop {
        if let Some(kb) = std::fs::read_to_string(&status_file).ok().and_then(|s| {
            s.lines()
                .find(|l| l.starts_with("VmHWM:"))
                .and_then(|l| l.split_whitespace().nth(1)?.parse::<u64>().ok())
        }) {
            peak = peak.max(kb * 1024);
        }
        if let Some(ticks) = std::fs::read_to_string(&stat_file).ok().and_then(|s| {
            // Fields after the command name (which may hold spaces): utime, stime are 14, 15.
            let rest = &s[s.rfind(')')? + 2..];
            let f: Vec<&str> = rest.split_whitespace().collect();
            Some(f.get(11)?.parse::<f64>().ok()? + f.get(12)?.parse::<f64>().ok()?)
        }) {
            cpu = cpu.max(ticks / 100.0);
        }
        match child.try_wait() {
            Ok(Some(st)) => return Ok((st.code().unwrap_or(-1), peak, cpu)),
            Ok(None) => std::thread::sleep(std::time::Duration::from_millis(2)),
            Err(e) => return Err(format!("waiting for cardan: {e}")),
        }
    }
}

/// The markdown table of the runs of `steps` (one process each).
pub fn section(cardan: &Path, root: &Path, subject: Subject, steps: &[usize]) -> String {
    let what = match subject {
        Subject::SliderCrank => "`examples/slider_crank.toml` with `steps` set",
        Subject::CrankSliderAsmt => {
            "`crates/asmt/tests/data/crank_slider.asmt` with `hout` = 1 s / steps (its \
             `.solved.asmt` too)"
        }
    };
    let mut md = format!(
        "**Peak memory of a long kinematic run** (`{}`): `cardan run` of {what}, all outputs \
         written (CSV, SVG plots, run.json, animation.glb, index.html); peak resident set of \
         the child process (`VmHWM`, polled), wall time from spawn to exit, processor time \
         (user + system) of the child.\n\n\
         | steps | peak memory | wall time | processor time | per step (processor) | output files |\n\
         |---:|---:|---:|---:|---:|---:|\n",
        cardan.display()
    );
    for &n in steps {
        eprintln!("run-memory: {n} steps");
        match measure(cardan, root, subject, n) {
            Ok(m) => {
                let _ = writeln!(
                    md,
                    "| {n} | {} | {} | {} | {} | {} |",
                    fmt_bytes(m.peak_rss),
                    fmt_time(m.wall),
                    fmt_time(m.cpu),
                    fmt_time(m.cpu / n as f64),
                    fmt_bytes(m.output_bytes)
                );
            }
            Err(e) => {
                let _ = writeln!(md, "| {n} | failed: {e} | | | | |");
            }
        }
    }
    md
}
