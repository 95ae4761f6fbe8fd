//! Timing and memory helpers.
//!
//! Times are medians of repeated batches: `f` is called in batches long enough to be timed
//! (≥ `batch_time`), several batches are run, the median batch mean is reported. Allocation
//! counts come from the binary's counting global allocator (`stats_alloc`), peak memory from
//! `VmHWM` of `/proc/self/status` (the process's peak resident set: measure each size in its own
//! process).

use std::time::{Duration, Instant};

/// Median seconds per call of `f`, over `batches` batches of at least `batch_time` each.
pub fn time_per_call(mut f: impl FnMut(), batch_time: Duration, batches: usize) -> f64 {
    // Calibrate the batch size.
    let mut reps = 1usize;
    loop {
        let t0 = Instant::now();
        for _ in 0..reps {
            f();
        }
        let e = t0.elapsed();
        if e >= batch_time || reps >= 1 << 24 {
            break;
        }
        let scale = if e.is_zero() {
            16.0
        } else {
            (batch_time.as_secs_f64() / e.as_secs_f64() * 1.2).clamp(1.5, 16.0)
        };
        reps = ((reps as f64) * scale).ceil() as usize;
    }
    let mut samples: Vec<f64> = (0..batches.max(1))
        .map(|_| {
            let t0 = Instant::now();
            for _ in 0..reps {
                f();
            }
            t0.elapsed().as_secs_f64() / reps as f64
        })
        .collect();
    median(&mut samples)
}

/// The median (sorts `v`).
pub fn median(v: &mut [f64]) -> f64 {
    v.sort_by(f64::total_cmp);
    let n = v.len();
    if n == 0 {
        f64::NAN
    } else if n % 2 == 1 {
        v[n / 2]
    } else {
        0.5 * (v[n / 2 - 1] + v[n / 2])
    }
}

/// Peak resident set size of this process in bytes (`VmHWM`), if available.
pub fn peak_rss_bytes() -> Option<u64> {
    let s = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = s.lines().find(|l| l.starts_with("VmHWM:"))?;
    let kb: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kb * 1024)
}

/// Least-squares slope of log y against log x (the scaling exponent).
pub fn loglog_slope(points: &[(f64, f64)]) -> f64 {
    let pts: Vec<(f64, f64)> = points
        .iter()
        .filter(|(x, y)| *x > 0.0 && *y > 0.0 && y.is_finite())
        .map(|(x, y)| (x.ln(), y.ln()))
        .collect();
    let n = pts.len() as f64;
    if pts.len() < 2 {
        return f64::NAN;
    }
    let mx = pts.iter().map(|p| p.0).sum::<f64>() / n;
    let my = pts.iter().map(|p| p.1).sum::<f64>() / n;
    let sxy: f64 = pts.iter().map(|p| (p.0 - mx) * (p.1 - my)).sum();
    let sxx: f64 = pts.iter().map(|p| (p.0 - mx) * (p.0 - mx)).sum();
    sxy / sxx
}

/// A human-readable time.
pub fn fmt_time(s: f64) -> String {
    if !s.is_finite() {
        "—".into()
    } else if s < 1e-6 {
        format!("{:.0} ns", s * 1e9)
    } else if s < 1e-3 {
        format!("{:.1} µs", s * 1e6)
    } else if s < 1.0 {
        format!("{:.2} ms", s * 1e3)
    } else {
        format!("{:.2} s", s)
    }
}

/// A human-readable byte count.
pub fn fmt_bytes(b: u64) -> String {
    let b = b as f64;
    if b < 1024.0 * 1024.0 {
        format!("{:.0} KiB", b / 1024.0)
    } else if b < 1024.0 * 1024.0 * 1024.0 {
        format!("{:.1} MiB", b / 1024.0 / 1024.0)
    } else {
        format!("{:.2} GiB", b / 1024.0 / 1024.0 / 1024.0)
    }
}

/// One line describing the machine: CPU model, cores, memory, rustc.
pub fn machine() -> String {
    let cpu = std::fs::read_to_string("/proc/cpuinfo")
        .ok()
        .and_then(|s| {
            s.lines()
                .find(|l| l.starts_with("model name"))
                .and_then(|l| l.split(':').nth(1))
                .map(|s| s.trim().to_string())
        })
        .unwrap_or_else(|| "unknown CPU".into());
    let cores = std::thread::available_parallelism().map_or(0, |n| n.get());
    let mem = std::fs::read_to_string("/proc/meminfo")
        .ok()
        .and_then(|s| {
            s.lines()
                .find(|l| l.starts_with("MemTotal"))
                .and_then(|l| l.split_whitespace().nth(1))
                .and_then(|v| v.parse::<u64>().ok())
        })
        .map_or("? GiB".into(), |kb| {
            format!("{:.0} GiB", kb as f64 / 1048576.0)
        });
    let rustc = std::process::Command::new("rustc")
        .arg("-V")
        .output()
        .ok()
        .map(|o| String::from_utf8_lossy(&o.stdout).trim().to_string())
        .unwrap_or_else(|| "rustc ?".into());
    format!("{cpu}, {cores} cores, {mem} RAM, Linux; {rustc}, `--release` (no target-cpu=native), sequential")
}

/// `Duration` from milliseconds.
pub fn ms(v: u64) -> Duration {
    Duration::from_millis(v)
}

/// The `cardan` binary beside this one (`cargo build --release -p cardan-cli`).
pub fn cardan_binary() -> std::path::PathBuf {
    std::env::current_exe()
        .map(|p| p.with_file_name("cardan"))
        .unwrap_or_else(|_| "cardan".into())
}
