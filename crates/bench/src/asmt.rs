//! cardan against OndselSolver on ASMT files (issue 22): the ten assemblies of OndselSolver's
//! `testapp` folder (`crates/asmt/tests/data`), each solved over its whole time span, reading
//! included on both sides, back to back on the same machine.
//!
//! - **OndselSolver** (pyondsel, `bench/peers/asmt.py solve`): the file read from disk, parsed,
//!   assembled, solved over tstart..tend by hout and written back as text with its TimeSeries
//!   (the C++ extension in-process), best of N.
//! - **cardan**: the file read from disk, read and mapped (`cardan_asmt::load`), the mechanism
//!   built (redundancy analysis included), kinematics over the same grid
//!   (`Model::run_kinematics`: position, velocity, acceleration of every part at every output
//!   time: what the solved file holds), and the
//!   `.solved.asmt` text written ([`cardan_asmt::solved`]), best of N; also per stage.
//! - **cardan as a process**: `cardan run FILE --outputs asmt` (the command a user runs: process
//!   start, reading, solving and writing only the `.solved.asmt`), wall time, best of N.
//! - **Read-back**: every `.solved.asmt` cardan writes is read by OndselSolver's C++ reader (which
//!   solves it again: same number of frames) and by pyondsel's TimeSeries reader (every part,
//!   one pose per time) (`bench/peers/asmt.py readback`).
//!
//! - **Through Python**, as a Python user meets both (`bench/peers/asmt.py python`): cardan's
//!   package (`cardan.load(FILE).run()`, from the test environment `target/py-venv`) against
//!   pyondsel's public `solve_asmt` (OndselSolver in a worker process) and its in-process C++
//!   extension `solve_asmt_raw`, in one Python process; when `target/py-venv` holds the package.
//!
//! `cardan-bench --asmt [--smoke] [--peers PYTHON]` prints the section alone; without a Python
//! with pyondsel only cardan's times are given.

use crate::measure::fmt_time;
use std::fmt::Write as _;
use std::path::Path;
use std::process::Command;
use std::time::Instant;

/// A file's row: name, frames, OndselSolver's time, cardan's in-process and process times.
type Row<'a> = (&'a &'a str, usize, Option<f64>, f64, Option<f64>);

/// The table's rows (`readback`: OndselSolver's reading of each solved file); the smallest
/// ratio.
fn table_rows(md: &mut String, rows: &[Row], readback: &[String]) -> Option<f64> {
    let mut worst: Option<f64> = None;
    for ((f, frames, theirs, ours, process), back) in rows.iter().zip(readback) {
        let mut ratio = |t: f64, c: f64| {
            let r = t / c;
            worst = Some(worst.map_or(r, |w: f64| w.min(r)));
            (format!("{r:.0}×"), r >= TARGET)
        };
        let (t, (in_process, met_in), (by_process, met_by)) = match theirs {
            Some(t) => (
                fmt_time(*t),
                ratio(*t, *ours),
                process.map_or(("–".into(), true), |c| ratio(*t, c)),
            ),
            None => ("–".into(), ("–".into(), true), ("–".into(), true)),
        };
        let met = match theirs {
            None => "–",
            Some(_) if met_in && met_by => "met",
            Some(_) => "**missed**",
        };
        let shown = process.map_or("–".into(), fmt_time);
        let _ = writeln!(
            md,
            "| {f} | {frames} | {t} | {} | {in_process} | {shown} | {by_process} | {met} | {back} |",
            fmt_time(*ours)
        );
    }
    worst
}

/// `cardan run path --outputs asmt -o out --quiet` in its own process, best of `n` wall times;
/// `None` when the `cardan` binary is not built beside this one or the run fails.
fn process_best(path: &Path, out: &Path, n: usize) -> Option<f64> {
    let bin = crate::measure::cardan_binary();
    if !bin.exists() {
        return None;
    }
    let mut best = f64::INFINITY;
    for _ in 0..n {
        let t0 = Instant::now();
        let ok = Command::new(&bin)
            .arg("run")
            .arg(path)
            .args(["--outputs", "asmt", "--quiet", "-o"])
            .arg(out)
            .output()
            .is_ok_and(|o| o.status.success());
        if !ok {
            return None;
        }
        best = best.min(t0.elapsed().as_secs_f64());
    }
    Some(best)
}

/// The ten files, in the order of docs/asmt.md.
pub const FILES: [&str; 10] = [
    "crank_slider",
    "fourbar",
    "piston",
    "00backhoe",
    "parm",
    "dxfmotion",
    "circular",
    "wobpump",
    "rackscrew",
    "Gears",
];

/// The target: cardan at least this many times faster than OndselSolver on every file.
pub const TARGET: f64 = 50.0;

/// Seconds of each stage of one cardan solve of a file.
#[derive(Debug, Clone, Copy)]
pub struct Stages {
    /// Reading the file and mapping it (`cardan_asmt::load`).
    pub read: f64,
    /// Building the mechanism (`MechanismBuilder::build`).
    pub build: f64,
    /// Kinematics over the file's time span (assembly, redundant rows, every frame).
    pub solve: f64,
    /// The `.solved.asmt` text (series and text).
    pub write: f64,
}

impl Stages {
    /// The whole solve.
    pub fn total(&self) -> f64 {
        self.read + self.build + self.solve + self.write
    }

    fn min(self, o: Stages) -> Stages {
        Stages {
            read: self.read.min(o.read),
            build: self.build.min(o.build),
            solve: self.solve.min(o.solve),
            write: self.write.min(o.write),
        }
    }
}

/// One cardan solve of the ASMT file `path`: its stages, the `.solved.asmt` text and the
/// number of output times.
///
/// # Panics
/// If the file does not read or solve (the ten files do).
pub fn cardan_solve(path: &Path) -> (Stages, String, usize) {
    let t0 = Instant::now();
    let text = std::fs::read_to_string(path).expect("the ASMT file");
    let (doc, import) = cardan_asmt::load(&text).expect("a readable ASMT file");
    let t1 = Instant::now();
    let model = import.builder().build().expect("a valid mechanism");
    let t2 = Instant::now();
    let s = import.settings.expect("simulation parameters");
    // What the `.solved.asmt` holds: part poses, velocities and accelerations (no joint
    // coordinates or point histories, which the CLI computes for its own tables).
    let outputs = cardan_mechanism::Outputs {
        points: false,
        joints: false,
        ..cardan_mechanism::Outputs::default()
    };
    let options =
        cardan_mechanism::KinematicOptions::new(s.t_start, s.t_end, s.steps()).outputs(outputs);
    let results = model.run_kinematics(&options).expect("kinematics");
    let t3 = Instant::now();
    let series = cardan_asmt::solved::time_series(&doc, &import, &results);
    let solved = cardan_asmt::solved::solved_text(&text, &series);
    let t4 = Instant::now();
    let stages = Stages {
        read: (t1 - t0).as_secs_f64(),
        build: (t2 - t1).as_secs_f64(),
        solve: (t3 - t2).as_secs_f64(),
        write: (t4 - t3).as_secs_f64(),
    };
    (stages, solved, results.times.len())
}

/// Best of `n` cardan solves (the whole, and each stage on its own).
pub fn cardan_best(path: &Path, n: usize) -> (f64, Stages, String, usize) {
    let (mut stages, text, frames) = cardan_solve(path);
    let mut best = stages.total();
    for _ in 1..n {
        let (s, _, _) = cardan_solve(path);
        best = best.min(s.total());
        stages = stages.min(s);
    }
    (best, stages, text, frames)
}

/// The `RESULT key=value ...` lines of `python bench/peers/asmt.py args...`, as string maps.
fn peer(
    python: &str,
    script: &Path,
    args: &[String],
) -> Result<Vec<Vec<(String, String)>>, String> {
    let o = Command::new(python)
        .arg(script)
        .args(args)
        .output()
        .map_err(|e| format!("cannot start {python}: {e}"))?;
    let out = String::from_utf8_lossy(&o.stdout);
    let lines: Vec<Vec<(String, String)>> = out
        .lines()
        .filter_map(|l| l.strip_prefix("RESULT "))
        .map(|l| {
            l.split_whitespace()
                .filter_map(|kv| kv.split_once('='))
                .map(|(k, v)| (k.to_string(), v.to_string()))
                .collect()
        })
        .collect();
    if lines.is_empty() || !o.status.success() {
        let err = String::from_utf8_lossy(&o.stderr);
        return Err(format!(
            "`bench/peers/asmt.py {}` failed: {}",
            args.first().map_or("", String::as_str),
            err.lines().last().unwrap_or("no output")
        ));
    }
    Ok(lines)
}

fn value<'a>(r: &'a [(String, String)], k: &str) -> &'a str {
    r.iter()
        .find(|(key, _)| key == k)
        .map_or("", |(_, v)| v.as_str())
}

/// The markdown section: a table per file (pyondsel, cardan, ratio, read-back), cardan's
/// stages. `python`: a Python with pyondsel (none: cardan only). `smoke`: one run of each.
pub fn section(smoke: bool, python: Option<&str>, root: &Path) -> String {
    section_of(smoke, python, None, root)
}

/// [`section`] for one file only (`only`: its name without `.asmt`, e.g. `wobpump`; for
/// profiling one file), or all ten with `None`.
pub fn section_of(smoke: bool, python: Option<&str>, only: Option<&str>, root: &Path) -> String {
    let data = root.join("crates/asmt/tests/data");
    let script = root.join("bench/peers/asmt.py");
    let (n_cardan, n_peer, rounds) = if smoke { (1, 1, 1) } else { (20, 3, 3) };
    let out_dir = std::env::temp_dir().join(format!("cardan-bench-asmt-{}", std::process::id()));
    let _ = std::fs::create_dir_all(&out_dir);
    let mut md = String::from("### ASMT files: cardan against OndselSolver\n\n");
    let _ = writeln!(
        md,
        "The ten assemblies of OndselSolver's testapp (`crates/asmt/tests/data`), each solved over \
         its whole time span with reading included on both sides, back to back per file in \
         {rounds} rounds (OndselSolver, then cardan, in each), the best of each over all rounds. \
         OndselSolver: pyondsel 0.0.3 in-process (`solve_asmt_raw`: read, assemble, solve, write \
         the solved text), best of {n_peer} per round. cardan: read and map \
         (`cardan_asmt::load`), build, kinematics over the same grid, write the `.solved.asmt` \
         text, best of {n_cardan} per round. `cardan run` process: the command a user runs, \
         `cardan run FILE --outputs asmt` (process start, reading, solving, writing only the \
         `.solved.asmt`), wall time, best of {n_cardan} per round. Read-back: cardan's `.solved.asmt` read by OndselSolver's C++ \
         reader (it solves the file again: same frames) and by pyondsel's TimeSeries reader \
         (every part, one pose per time). Sources: `crates/bench/src/asmt.rs`, \
         `bench/peers/asmt.py`.\n"
    );
    let _ = writeln!(
        md,
        "| file | frames | OndselSolver | cardan | ratio | `cardan run` process | ratio | target ≥ {TARGET:.0}× | OndselSolver reads cardan's file |\n\
         |---|---:|---:|---:|---:|---:|---:|---|---|"
    );
    let mut stages_md = String::from(
        "\ncardan by stage (best of each): read and map, build (with the redundancy analysis), \
         kinematics, `.solved.asmt` text.\n\n| file | read | build | kinematics | write | total |\n\
         |---|---:|---:|---:|---:|---:|\n",
    );
    let mut written = Vec::new();
    let mut rows = Vec::new();
    let mut peer_error = None;
    for f in FILES.iter().filter(|f| only.is_none_or(|o| o == **f)) {
        let path = data.join(format!("{f}.asmt"));
        eprintln!("asmt: {f}");
        // Back to back, in rounds (OndselSolver, then cardan, `rounds` times), the best of each
        // over all rounds: a noisy moment of the machine then hits both, not one.
        let mut theirs: Option<f64> = None;
        let mut ours: Option<(f64, Stages, String, usize)> = None;
        let mut process: Option<f64> = None;
        let process_dir = out_dir.join(format!("{f}-process"));
        for _ in 0..rounds {
            if let (Some(py), None) = (python, &peer_error) {
                let args = [
                    "solve".into(),
                    n_peer.to_string(),
                    path.display().to_string(),
                ];
                match peer(py, &script, &args) {
                    Ok(r) => {
                        if let Ok(t) = value(&r[0], "best").parse::<f64>() {
                            theirs = Some(theirs.map_or(t, |b| b.min(t)));
                        }
                    }
                    Err(e) => peer_error = Some(e),
                }
            }
            if let Some(t) = process_best(&path, &process_dir, n_cardan) {
                process = Some(process.map_or(t, |b| b.min(t)));
            }
            let run = cardan_best(&path, n_cardan);
            ours = Some(match ours {
                Some(o) if o.0 <= run.0 => (o.0, o.1.min(run.1), o.2, o.3),
                Some(o) => (run.0, run.1.min(o.1), run.2, run.3),
                None => run,
            });
        }
        let (best, st, text, frames) = ours.expect("at least one round");
        let file = out_dir.join(format!("{f}.solved.asmt"));
        if std::fs::write(&file, text).is_ok() {
            written.push(file);
        }
        let _ = writeln!(
            stages_md,
            "| {f} | {} | {} | {} | {} | {} |",
            fmt_time(st.read),
            fmt_time(st.build),
            fmt_time(st.solve),
            fmt_time(st.write),
            fmt_time(best)
        );
        rows.push((f, frames, theirs, best, process));
    }
    // OndselSolver reads the files cardan wrote.
    let mut readback: Vec<String> = vec!["not run".into(); rows.len()];
    if let (Some(py), None) = (python, &peer_error) {
        let mut args = vec!["readback".to_string()];
        args.extend(written.iter().map(|p| p.display().to_string()));
        match peer(py, &script, &args) {
            Ok(r) => {
                for (k, line) in r.iter().enumerate().take(readback.len()) {
                    let (cpp, py) = (value(line, "cpp"), value(line, "python"));
                    readback[k] = if cpp == "ok" && py == "ok" {
                        "yes (C++ reader and pyondsel)".into()
                    } else {
                        format!("**no**: C++ {cpp}, pyondsel {py}")
                    };
                }
            }
            Err(e) => peer_error = Some(e),
        }
    }
    let worst = table_rows(&mut md, &rows, &readback);
    if let Some(w) = worst {
        let _ = writeln!(
            md,
            "\nSmallest ratio: {w:.0}× (target ≥ {TARGET:.0}× on every file, in-process and as a process)."
        );
    }
    match (python, peer_error) {
        (None, _) => md.push_str(
            "\nOndselSolver not run (`cargo xtask bench --peers` installs pyondsel; \
             `cardan-bench --asmt --peers target/peers-venv/bin/python`).\n",
        ),
        (Some(_), Some(e)) => {
            let _ = writeln!(md, "\nOndselSolver failed: {e}");
        }
        _ => {}
    }
    md.push_str(&stages_md);
    md.push('\n');
    if let Some(py) = python {
        md.push_str(&through_python(py, &script, root, &data, only, smoke));
    }
    let _ = std::fs::remove_dir_all(&out_dir);
    md
}

/// The test environment's site-packages folder when it holds cardan's package.
fn cardan_site(root: &Path) -> Option<std::path::PathBuf> {
    let lib = root.join("target/py-venv/lib");
    std::fs::read_dir(lib)
        .ok()?
        .filter_map(Result::ok)
        .map(|e| e.path().join("site-packages"))
        .find(|site| site.join("cardan").is_dir())
}

/// The subsection timing both Python packages in one process (module docs).
fn through_python(
    python: &str,
    script: &Path,
    root: &Path,
    data: &Path,
    only: Option<&str>,
    smoke: bool,
) -> String {
    let mut md = String::from("#### Through Python, in one process\n\n");
    let Some(site) = cardan_site(root) else {
        md.push_str("Not run: `target/py-venv` has no cardan package (`scripts/python-env`).\n\n");
        return md;
    };
    let n = if smoke { 1 } else { 20 };
    let mut args = vec![
        "python".to_string(),
        n.to_string(),
        site.display().to_string(),
    ];
    args.extend(
        FILES
            .iter()
            .filter(|f| only.is_none_or(|o| o == **f))
            .map(|f| data.join(format!("{f}.asmt")).display().to_string()),
    );
    let _ = writeln!(
        md,
        "`cardan.load(FILE).run()` (reading, import, kinematics, every table as numpy arrays) \
         against pyondsel's `solve_asmt` (its public solve: OndselSolver in a worker process) \
         and `solve_asmt_raw` (the C++ extension in this process), each given the file's text \
         read in the timing; in 3 rounds, best of {n} (cardan) and of {} (pyondsel) per round. \
         Source: `bench/peers/asmt.py python`.\n\n\
         | file | cardan | `solve_asmt` | ratio | `solve_asmt_raw` | ratio |\n\
         |---|---:|---:|---:|---:|---:|",
        (n / 4).max(1)
    );
    let rows = match peer(python, script, &args) {
        Ok(r) => r,
        Err(e) => {
            let _ = writeln!(md, "\nFailed: {e}\n");
            return md;
        }
    };
    for r in &rows {
        let num = |k: &str| value(r, k).parse::<f64>().unwrap_or(f64::NAN);
        let (ours, public, raw) = (num("cardan"), num("public"), num("raw"));
        let name = Path::new(value(r, "file"))
            .file_stem()
            .map_or(String::new(), |s| s.to_string_lossy().into_owned());
        let _ = writeln!(
            md,
            "| {name} | {} | {} | {:.0}× | {} | {:.0}× |",
            fmt_time(ours),
            fmt_time(public),
            public / ours,
            fmt_time(raw),
            raw / ours
        );
    }
    md.push('\n');
    md
}
