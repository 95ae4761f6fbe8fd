//! `cardan sweep MODEL --set NAME=A:B:N ... --output NAME=EXPR ...`: the model run for every
//! case of a grid (or of a cases file) on all cores ([`cardan_model::sweep`]), one row per case
//! in `sweep.csv`, a plot of each output against each parameter and `run.json`, written by the
//! directory rule of [`crate::output`].

use crate::output::OutputDir;
use cardan_model::diag::{Error, Source};
use cardan_model::sweep::{self, grid, outputs::Output, Row, Sweep};
use std::io::Write;
use std::path::{Path, PathBuf};
use std::time::Instant;

/// What `cardan sweep` was given.
#[derive(Debug, Clone)]
pub struct SweepArgs {
    /// The model file.
    pub model: PathBuf,
    /// `--set NAME=SPEC` axes.
    pub set: Vec<(String, String)>,
    /// `--cases FILE`.
    pub cases: Option<PathBuf>,
    /// `--output NAME=EXPR`.
    pub outputs: Vec<String>,
    /// `-o DIR`.
    pub dir: Option<PathBuf>,
    /// `--jobs N` (default: every core).
    pub jobs: Option<usize>,
    /// `--allow-long`.
    pub allow_long: bool,
}

/// Most failed cases listed in the printed summary (run.json and sweep.csv have them all).
const LISTED_FAILURES: usize = 5;

/// Runs the sweep, writes its files and prints its summary.
///
/// # Errors
/// Usage errors (the grid, the outputs, too many cases), the model's errors common to every
/// case, output errors; every case failing is an error with the first case's message.
pub fn sweep(args: &SweepArgs, out: &mut dyn Write) -> Result<(), Error> {
    let path = &args.model;
    if cardan_model::urdf::is_urdf(path) || cardan_model::asmt::is_asmt(path) {
        return Err(Error::usage(format!(
            "cardan sweep varies a cardan model's [parameters]; {} has none (an overlay model \
             file with [urdf] can have them)",
            path.display()
        )));
    }
    let cases = match (&args.cases, args.set.is_empty()) {
        (Some(_), false) => {
            return Err(Error::usage(
                "give the cases either as --set axes (a grid) or in a --cases file, not both",
            ))
        }
        (Some(file), true) => grid::read_cases(file)?,
        (None, true) => return Err(Error::usage(
            "nothing to sweep: give --set NAME=A:B:N (or V1,V2,...) per parameter, or --cases FILE",
        )),
        (None, false) => grid::Cases::Grid(
            (args.set.iter())
                .map(|(n, v)| grid::axis(n, v))
                .collect::<Result<_, _>>()?,
        ),
    };
    cases.check_count(args.allow_long)?;
    if args.outputs.is_empty() {
        return Err(Error::usage(
            "no outputs: give --output NAME=EXPR, e.g. --output \"peak=max(abs(motor.torque))\"",
        ));
    }
    let outputs = (args.outputs.iter())
        .map(|o| Output::parse(o).map_err(Error::usage))
        .collect::<Result<Vec<_>, _>>()?;
    let jobs = args
        .jobs
        .unwrap_or_else(|| std::thread::available_parallelism().map_or(1, |n| n.get()))
        .max(1);
    let spec = Sweep {
        cases,
        outputs,
        jobs,
    };
    let src = Source::read(path)?;
    crate::progress::catch_ctrl_c();
    let start = Instant::now();
    let rows = sweep::run(&src, &spec)?;
    let seconds = start.elapsed().as_secs_f64();
    let n = usize::try_from(spec.cases.count()).unwrap_or(usize::MAX);
    let failed: Vec<&Row> = rows.iter().filter(|r| r.error.is_some()).collect();
    if !rows.is_empty() && failed.len() == rows.len() {
        let first = failed[0].error.clone().unwrap_or_default();
        return Err(Error::input(format!(
            "every case failed; the first: {first}"
        )));
    }
    let target = match &args.dir {
        Some(d) => d.clone(),
        None => {
            let stem = path
                .file_stem()
                .map_or("model".into(), |s| s.to_string_lossy().into_owned());
            Path::new("out").join(format!("{stem}-sweep"))
        }
    };
    let mut dir = OutputDir::lock(&target)?;
    dir.write("sweep.csv", sweep::csv(&spec, &rows))?;
    for (name, svg) in sweep::plots::plots(&spec, &rows) {
        dir.write(&name, svg)?;
    }
    let stopped = rows.len() < n;
    let json = sweep::run_json(&spec, &rows, n, jobs, seconds, stopped, dir.files());
    dir.write("run.json", json)?;
    let files = dir.files().len();
    dir.commit()?;
    let io = |e: std::io::Error| Error::output(format!("cannot print the summary: {e}"));
    writeln!(
        out,
        "sweep of {n} cases on {jobs} thread(s): {} ok, {} failed{}, wall time {seconds:.3} s ({:.2} ms a case)",
        rows.len() - failed.len(),
        failed.len(),
        if stopped { format!(", {} not run (Ctrl-C)", n - rows.len()) } else { String::new() },
        1e3 * seconds / rows.len().max(1) as f64
    )
    .map_err(io)?;
    for r in failed.iter().take(LISTED_FAILURES) {
        let set: Vec<String> = r.set.iter().map(|(k, v)| format!("{k}={v}")).collect();
        let first = r
            .error
            .as_deref()
            .unwrap_or("")
            .lines()
            .next()
            .unwrap_or("");
        writeln!(out, "warning: case {}: {first}", set.join(" ")).map_err(io)?;
    }
    if failed.len() > LISTED_FAILURES {
        writeln!(
            out,
            "warning: {} more failed cases in sweep.csv",
            failed.len() - LISTED_FAILURES
        )
        .map_err(io)?;
    }
    writeln!(out, "wrote {files} files to {}", target.display()).map_err(io)?;
    Ok(())
}
