//! `cardan run MODEL [-o DIR]`: the analysis the file describes
//! ([`cardan_model::analysis::analyse_into`]), its outputs written by the directory rule of
//! [`crate::output`] with `run.json`, and the summary printed with the warnings.

use crate::commands::asmt::SolvedSeries;
use crate::output::OutputDir;
use cardan_mechanism::Results;
use cardan_model::analysis::{
    analyse_into, animation, print_summary, run_report, Analysed, OutputSet, RunFlags, Summary,
};
use cardan_model::diag::Error;
use cardan_model::plot::PlotFiles;
use cardan_model::prepare::{prepare_with, Prepared};
use cardan_model::table::Table;
use std::io::Write;
use std::path::{Path, PathBuf};

/// The output of [`run_model`]: the results (complete, or partial with the error).
pub struct RunOutcome {
    /// The model as prepared.
    pub prepared: Prepared,
    /// Results (up to the failure if `error` is set).
    pub results: Results,
    /// What was written.
    pub summary: Summary,
    /// The analysis error, if the run stopped early.
    pub error: Option<Error>,
    /// The dynamic results (`kind = "dynamic"` or `"inverse_dynamics"`); `results` holds their
    /// kinematic part.
    pub dynamic: Option<cardan_dynamics::DynamicResults>,
}

/// `cardan run`: runs, writes, prints the summary.
///
/// # Errors
/// Input errors, analysis errors (after writing the partial results), output errors; with
/// `--strict`, warnings (after writing the results).
pub fn run(
    path: &Path,
    output: Option<&Path>,
    flags: &RunFlags,
    out: &mut dyn Write,
) -> Result<Summary, Error> {
    crate::progress::catch_ctrl_c();
    let o = run_model_with(path, output, flags)?;
    print_summary(&o.summary, out)?;
    match o.error {
        Some(e) => Err(e),
        None => Ok(o.summary),
    }
}

/// Runs the model file's analysis and writes its outputs to `output` (default
/// `out/<model name>/`) by the directory rule of [`crate::output`], with `run.json`. A failure
/// mid-run still writes the results up to the failure (marked partial) and is returned in
/// [`RunOutcome::error`].
///
/// # Errors
/// Input errors and failures before the first step (assembly, driver count): nothing is
/// written, the previous directory stays. Output errors (the previous directory stays).
pub fn run_model(path: &Path, output: Option<&Path>, progress: bool) -> Result<RunOutcome, Error> {
    let flags = RunFlags {
        progress: progress
            .then_some(crate::progress::terminal_bar as cardan_model::progress::MakeBar),
        ..RunFlags::default()
    };
    run_model_with(path, output, &flags)
}

/// [`run_model`] as `flags` say. With `flags.strict`, a run with warnings returns an error
/// (exit code 3) in [`RunOutcome::error`] after writing its results.
///
/// # Errors
/// As [`run_model`].
pub fn run_model_with(
    path: &Path,
    output: Option<&Path>,
    flags: &RunFlags,
) -> Result<RunOutcome, Error> {
    // A run that writes nothing says when its output directory holds an earlier run's results,
    // so those are not taken for this run's.
    let p = prepare_with(path, flags.asmt.clone()).map_err(|e| match output {
        Some(d) => earlier_results_note(e, d),
        None => e,
    })?;
    let dir = match output {
        Some(d) => d.to_path_buf(),
        None => Path::new("out").join(&p.loaded.name),
    };
    run_prepared(p, path, &dir, flags).map_err(|e| earlier_results_note(e, &dir))
}

/// `e` with a sentence saying that `dir` still holds an earlier run's results, when it holds
/// a `run.json` (a run that fails before its results replace the directory leaves it as it
/// was, [`crate::output`]).
fn earlier_results_note(mut e: Error, dir: &Path) -> Error {
    if e.kind != cardan_model::diag::ErrorKind::BrokenPipe && dir.join("run.json").is_file() {
        e.message.push_str(&format!(
            ". Nothing was written: {} still holds the results of an earlier run, unchanged \
             (its run.json says which)",
            dir.display()
        ));
    }
    e
}

/// [`run_model_with`] once the model is read: the analysis into `dir`.
fn run_prepared(
    p: Prepared,
    path: &Path,
    dir: &Path,
    flags: &RunFlags,
) -> Result<RunOutcome, Error> {
    let Some(analysis) = p.loaded.analysis.clone() else {
        return Err(p.source.error(
            "the model file has no [analysis] table, so there is nothing to run; add e.g.\n\
             [analysis]\nkind = \"kinematic\"\nt_end = 1.0\nsteps = 100\n(`cardan check` validates a model without running it)",
        ));
    };
    // The animation's geometry (mesh files included) is checked before any work is done.
    let declared = p.geometry.declared()?;
    // Locked before the analysis: a concurrent run is refused at once, not after its work.
    let mut out_dir = OutputDir::lock(dir)?;
    // The results of an ASMT file back in ASMT, streamed as the CSV files are and committed
    // with the other outputs.
    let outputs = flags.outputs;
    let mut solved = match cardan_model::asmt::is_asmt(path) && outputs.asmt {
        true => Some(SolvedSeries::new(path, flags.asmt.units, &mut out_dir)?),
        false => None,
    };
    // A static or modal run has one time: nothing to plot against it.
    let one_time = matches!(
        analysis.statics(),
        Some(cardan_model::build::StaticKind::Static | cardan_model::build::StaticKind::Modal)
    );
    let svg = analysis.plots && !one_time && outputs.plots;
    let plots = PlotFiles {
        svg,
        png: svg && flags.png,
    };
    // Created while the analysis runs (crate::output::opener), with the streamed CSV files and
    // their plots.
    out_dir.set_plots(plots);
    if outputs.report {
        out_dir.announce(["animation.glb", "index.html"])?;
    }
    out_dir.announce(["run.json"])?;
    // Without CSV files the tables are kept whole (for the plots and the report) instead of
    // streamed.
    let (kind, mut a) = analyse_into(
        &p,
        &analysis,
        flags,
        outputs.csv.then_some(&mut out_dir),
        solved
            .as_mut()
            .map(|s| s as &mut dyn cardan_model::files::FrameTap),
    )?;
    let files = write_outputs(
        out_dir,
        &p,
        (kind, outputs),
        &mut a,
        plots,
        &declared,
        solved,
    )?;
    a.summary.dir = dir.to_path_buf();
    a.summary.files = files;
    Ok(RunOutcome {
        prepared: p,
        results: a.results,
        summary: a.summary,
        error: a.failure.or(a.strict_failure),
        dynamic: a.dynamic,
    })
}

/// Writes the SVG plot of a table and, with `png`, its PNG rendering; returns the SVG.
fn write_plot(dir: &mut OutputDir, t: &Table, png: bool) -> Result<String, Error> {
    let svg = t.to_svg();
    if png {
        let bytes = cardan_plot::png::svg_to_png(&svg)
            .map_err(|e| Error::output(format!("{}.png: {e}", t.name)))?;
        dir.write(&format!("{}.png", t.name), bytes)?;
    }
    dir.write(&format!("{}.svg", t.name), &svg)?;
    Ok(svg)
}

/// Writes the tables, `solved` (an ASMT run's `*.solved.asmt`) and `run.json` into the locked
/// directory and renames it into place.
/// Completes a failure's message with what was written. Returns the paths written.
fn write_outputs(
    mut dir: OutputDir,
    p: &Prepared,
    (kind, outputs): (&'static str, OutputSet),
    a: &mut Analysed,
    plots: PlotFiles,
    declared: &cardan_model::geometry::Declared,
    solved: Option<SolvedSeries>,
) -> Result<Vec<PathBuf>, Error> {
    let mut svgs = Vec::new();
    let (mut streams, frames) = match a.streamed.as_mut() {
        Some(s) => (std::mem::take(&mut s.csv), s.frames),
        None => (Vec::new(), a.results.len()),
    };
    for t in &a.tables {
        let name = format!("{}.csv", t.name);
        match streams.iter().position(|(n, _)| *n == name) {
            Some(i) => {
                let (name, writer) = streams.swap_remove(i);
                dir.finish(&name, writer)?;
            }
            None if outputs.csv => dir.write(&name, t.to_csv())?,
            None => {}
        }
        if plots.plots(&t.name) {
            svgs.push((t.name.clone(), write_plot(&mut dir, t, plots.png)?));
        }
    }
    for (name, text) in &a.files {
        dir.write(name, text)?;
    }
    if let Some(s) = solved {
        s.write(&mut dir)?;
    }
    let unit = match kind {
        "dynamic" => "outputs",
        "static" | "quasi_static" | "modal" => "equilibria",
        _ => "steps",
    };
    let target = dir.target().to_path_buf();
    if let Some(err) = &mut a.failure {
        err.message.push_str(&format!(
            ". The results up to t = {} s ({} {unit}) were written to {}",
            a.results.times.last().copied().unwrap_or(f64::NAN),
            frames,
            target.display()
        ));
    }
    if outputs.report {
        write_animation(&mut dir, p, kind, a, declared, svgs)?;
    }
    let report = run_report(p, kind, a, dir.files().to_vec());
    dir.write("run.json", report.to_json())?;
    let files = dir.files().iter().map(|f| target.join(f)).collect();
    dir.commit()?;
    Ok(files)
}

/// Writes `animation.glb` and `index.html` (crates/report; the scene from [`crate::scene`]),
/// the page showing the plots `svgs` and the run summary. A scene the writers refuse (output
/// times that single precision cannot order) is a warning, not a failure of the run.
fn write_animation(
    dir: &mut OutputDir,
    p: &Prepared,
    kind: &'static str,
    a: &mut Analysed,
    declared: &cardan_model::geometry::Declared,
    svgs: Vec<(String, String)>,
) -> Result<(), Error> {
    let mut files = dir.files().to_vec();
    files.extend(["animation.glb".to_string(), "index.html".to_string()]);
    match animation(p, kind, a, declared, svgs, files) {
        Some(shown) => {
            let html = shown.html()?;
            dir.write("animation.glb", shown.glb)?;
            dir.write_parts("index.html", &html.parts().map(str::as_bytes))
        }
        None => Ok(()),
    }
}
