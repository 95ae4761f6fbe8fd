//! `cardan run MODEL.toml [-o DIR]`: the analysis the file describes, written as CSV and SVG
//! with a `run.json` that says how the run went (the directory rule: [`crate::output`]).

use super::{analysis_error, prepare, Prepared};
use crate::build::Outputs as Requested;
use crate::diag::Error;
use crate::output::OutputDir;
use crate::report::{ModelRef, RunReport, Status};
use crate::table::Table;
use cardan_mechanism::{KinematicOptions, Results};
use std::io::Write;
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

/// What a run did.
#[derive(Debug, Clone)]
pub struct Summary {
    /// The model name.
    pub name: String,
    /// Stored time steps.
    pub steps: usize,
    /// Total Newton iterations.
    pub iterations: usize,
    /// Largest max |Φ_i| over the run.
    pub max_residual: f64,
    /// Wall time of the analysis (not the writing).
    pub wall: Duration,
    /// Output directory.
    pub dir: PathBuf,
    /// Files written (`run.json` last).
    pub files: Vec<PathBuf>,
    /// Dynamic runs: integration counters and drifts.
    pub dynamic: Option<DynamicSummary>,
    /// Dynamic and inverse dynamics runs: per driver, its name, the largest |effort| over the
    /// run and the unit ("N m" or "N").
    pub peak_efforts: Vec<(String, f64, &'static str)>,
    /// Doubtful results and other remarks, one sentence each: printed after the summary line
    /// and written to `run.json`. Any check may push to it.
    pub warnings: Vec<String>,
    /// Kinematic and inverse dynamics runs: grid steps solved in substeps to stay on the
    /// assembly branch (`Results::subdivided_steps`; not a warning); `None` for dynamic runs.
    pub subdivided_steps: Option<usize>,
    /// Times the independent equations of a model with redundant equations were chosen again
    /// because the kept ones lost rank (a note, not a warning).
    pub row_reselections: usize,
}

/// What a dynamic run adds to the summary line.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DynamicSummary {
    /// Accepted integration steps.
    pub steps: usize,
    /// Rejected steps.
    pub rejected: usize,
    /// Newton iterations (implicit steps and projections).
    pub newton_iterations: usize,
    /// Largest max |Φ| over the stored times.
    pub max_constraint_drift: f64,
    /// max |E − E(t0)| (J).
    pub energy_drift: f64,
}

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

/// How `cardan run` was asked to run.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct RunFlags {
    /// Show a progress bar on stderr.
    pub progress: bool,
    /// `--strict`: warnings make the run fail with exit code 3 (the results are still written).
    pub strict: bool,
    /// `--allow-long`: run a dynamic analysis beyond [`crate::dynamic::MAX_STEPS`] estimated
    /// steps.
    pub allow_long: bool,
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

/// The summary: the files written, one line of numbers, then one line per warning.
pub fn print_summary(s: &Summary, out: &mut dyn Write) -> Result<(), Error> {
    let written: Vec<String> = s
        .files
        .iter()
        .map(|f| {
            f.file_name()
                .map_or(String::new(), |n| n.to_string_lossy().into_owned())
        })
        .collect();
    let io = super::output_tables::io;
    writeln!(
        out,
        "wrote {} files to {}: {}",
        written.len(),
        s.dir.display(),
        written.join(", ")
    )
    .map_err(io)?;
    let efforts = if s.peak_efforts.is_empty() {
        String::new()
    } else {
        let list: Vec<String> = s
            .peak_efforts
            .iter()
            .map(|(n, v, u)| format!("{n} {v:.4e} {u}"))
            .collect();
        format!(", peak |driver effort| {}", list.join(", "))
    };
    let efforts = match s.subdivided_steps {
        Some(1) => format!("{efforts}, 1 step subdivided to stay on the assembly branch"),
        Some(n) if n > 1 => {
            format!("{efforts}, {n} steps subdivided to stay on the assembly branch")
        }
        _ => efforts,
    };
    let efforts = match s.row_reselections {
        0 => efforts,
        1 => format!("{efforts}, redundant equations chosen again once"),
        n => format!("{efforts}, redundant equations chosen again {n} times"),
    };
    let efforts = match s.warnings.len() {
        0 => efforts,
        1 => format!("{efforts}, 1 warning (below)"),
        n => format!("{efforts}, {n} warnings (below)"),
    };
    match &s.dynamic {
        None => writeln!(
            out,
            "{}: {} steps, {} Newton iterations, largest residual {:.3e}{efforts}, wall time {:.3} s",
            s.name,
            s.steps,
            s.iterations,
            s.max_residual,
            s.wall.as_secs_f64()
        ),
        Some(d) => writeln!(
            out,
            "{}: {} outputs, {} steps ({} rejected), {} Newton iterations, max constraint drift \
             {:.3e}, energy drift {:.3e} J{efforts}, wall time {:.3} s",
            s.name,
            s.steps,
            d.steps,
            d.rejected,
            d.newton_iterations,
            d.max_constraint_drift,
            d.energy_drift,
            s.wall.as_secs_f64()
        ),
    }
    .map_err(io)?;
    for w in &s.warnings {
        writeln!(out, "warning: {w}").map_err(io)?;
    }
    Ok(())
}

/// An analysis that has run, before anything is written.
struct Analysed {
    /// The output groups.
    tables: Vec<Table>,
    /// The summary (files and directory are filled in when written).
    summary: Summary,
    /// The results (the kinematic part for dynamic runs).
    results: Results,
    /// Dynamic and inverse dynamics runs: everything they computed.
    dynamic: Option<cardan_dynamics::DynamicResults>,
    /// The failure that stopped the run early; `None` when it reached `t_end`.
    failure: Option<Error>,
    /// `--strict` with warnings: the error to return after writing (the run is complete).
    strict_failure: Option<Error>,
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
        progress,
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
    let progress = flags.progress;
    let p = prepare(path)?;
    let Some(analysis) = p.loaded.analysis.clone() else {
        return Err(p.source.error(
            "the model file has no [analysis] table, so there is nothing to run; add e.g.\n\
             [analysis]\nkind = \"kinematic\"\nt_end = 1.0\nsteps = 100\n(`cardan check` validates a model without running it)",
        ));
    };
    let dir = match output {
        Some(d) => d.to_path_buf(),
        None => Path::new("out").join(&p.loaded.name),
    };
    // Locked before the analysis: a concurrent run is refused at once, not after its work.
    let out_dir = OutputDir::lock(&dir)?;
    let (kind, ran) = if analysis.dynamic.is_some() {
        ("dynamic", run_dynamic(&p, &analysis, flags))
    } else if analysis.inverse_dynamics {
        ("inverse_dynamics", run_inverse(&p, &analysis, progress))
    } else {
        ("kinematic", run_kinematic(&p, &analysis, progress))
    };
    let mut a = ran?;
    if a.results.times.is_empty() {
        // Nothing to write: the previous directory stays as it was.
        return Err(a.failure.unwrap_or_else(|| {
            Error::analysis("the analysis stored no result (no time was solved)")
        }));
    }
    if flags.strict && a.failure.is_none() && !a.summary.warnings.is_empty() {
        a.strict_failure = Some(strict_error(&a.summary.warnings));
    }
    let files = write_outputs(out_dir, &p, kind, &mut a, analysis.plots)?;
    a.summary.dir = dir;
    a.summary.files = files;
    Ok(RunOutcome {
        prepared: p,
        results: a.results,
        summary: a.summary,
        error: a.failure.or(a.strict_failure),
        dynamic: a.dynamic,
    })
}

/// The error of a `--strict` run with warnings.
fn strict_error(warnings: &[String]) -> Error {
    let n = warnings.len();
    Error::analysis(format!(
        "--strict: the run gave {n} warning{} about doubtful results (listed after the summary \
         and in run.json); the results were written",
        if n == 1 { "" } else { "s" }
    ))
}

/// Writes the tables and `run.json` into the locked directory and renames it into place.
/// Completes a failure's message with what was written. Returns the paths written.
fn write_outputs(
    mut dir: OutputDir,
    p: &Prepared,
    kind: &'static str,
    a: &mut Analysed,
    plots: bool,
) -> Result<Vec<PathBuf>, Error> {
    for t in &a.tables {
        dir.write(&format!("{}.csv", t.name), &t.to_csv())?;
        if plots && t.name != "residual" {
            dir.write(&format!("{}.svg", t.name), &t.to_svg())?;
        }
    }
    let unit = if kind == "dynamic" {
        "outputs"
    } else {
        "steps"
    };
    let target = dir.target().to_path_buf();
    if let Some(err) = &mut a.failure {
        err.message.push_str(&format!(
            ". The results up to t = {} s ({} {unit}) were written to {}",
            a.results.times.last().copied().unwrap_or(f64::NAN),
            a.results.len(),
            target.display()
        ));
    }
    let report = report(p, kind, a, dir.files().to_vec());
    dir.write("run.json", &report.to_json())?;
    let files = dir.files().iter().map(|f| target.join(f)).collect();
    dir.commit()?;
    Ok(files)
}

/// The contents of `run.json` for an analysed run whose tables are `files`.
fn report(p: &Prepared, kind: &'static str, a: &Analysed, files: Vec<String>) -> RunReport {
    let s = &a.summary;
    let d = s.dynamic.as_ref();
    RunReport {
        model: ModelRef {
            path: p.source.path.display().to_string(),
            name: s.name.clone(),
        },
        analysis: kind,
        status: if a.failure.is_some() {
            Status::Partial
        } else {
            Status::Complete
        },
        reason: a.failure.as_ref().map(|e| e.message.clone()),
        exit_code: a
            .failure
            .as_ref()
            .or(a.strict_failure.as_ref())
            .map_or(0, |e| e.kind.exit_code()),
        t_reached: a.results.times.last().copied(),
        steps: s.steps,
        integration_steps: d.map(|d| d.steps),
        rejected_steps: d.map(|d| d.rejected),
        newton_iterations: s.iterations,
        largest_residual: s.max_residual,
        constraint_drift: d.map(|d| d.max_constraint_drift),
        energy_drift: d.map(|d| d.energy_drift),
        warnings: s.warnings.clone(),
        subdivided_steps: s.subdivided_steps,
        row_reselections: s.row_reselections,
        files,
        wall_time_s: s.wall.as_secs_f64(),
    }
}

/// `kind = "kinematic"`: the kinematics over the file's grid and its tables.
fn run_kinematic(
    p: &Prepared,
    analysis: &crate::build::Analysis,
    progress: bool,
) -> Result<Analysed, Error> {
    let opts = KinematicOptions::new(analysis.t_start, analysis.t_end, analysis.steps);
    let start = Instant::now();
    let mut bar = crate::progress::Progress::new(progress, opts.steps as u64 + 1);
    let mut ws = p.model.workspace();
    let run = p
        .model
        .kinematics_with_control(&mut ws, &opts, |k, t| bar.tick(k as u64 + 1, t));
    let wall = start.elapsed();
    let (results, failure) = match run {
        Ok(r) if bar.stopped() => {
            let e = crate::progress::interrupted(&r.times);
            (r, Some(e))
        }
        Ok(r) => (r, None),
        Err(e) => match e.partial_results() {
            Some(r) => (r.clone(), Some(analysis_error(p, &e))),
            None => return Err(analysis_error(p, &e)),
        },
    };
    drop(bar);
    let req = requested(p, &analysis.outputs);
    let tables = tables(p, &results, &req);
    let summary = Summary {
        name: p.loaded.name.clone(),
        steps: results.len(),
        iterations: results.iterations.iter().sum(),
        max_residual: results.residual.iter().fold(0.0, |a: f64, &b| a.max(b)),
        wall,
        dir: PathBuf::new(),
        files: Vec::new(),
        dynamic: None,
        peak_efforts: Vec::new(),
        warnings: Vec::new(),
        subdivided_steps: Some(results.subdivided_steps),
        row_reselections: results.row_reselections,
    };
    Ok(Analysed {
        tables,
        summary,
        results,
        dynamic: None,
        failure,
        strict_failure: None,
    })
}

/// `kind = "dynamic"`: simulate, the tables, the summary. A failure mid-run keeps the results
/// so far with the error.
fn run_dynamic(
    p: &Prepared,
    analysis: &crate::build::Analysis,
    flags: &RunFlags,
) -> Result<Analysed, Error> {
    let mut opts = crate::dynamic::options(p, None)?;
    crate::dynamic::check_length(p, &mut opts, flags.allow_long)?;
    let mut d = crate::dynamic::dynamics(p)?;
    let initial = crate::dynamic::initial_state(p);
    let start = Instant::now();
    // Progress in parts of the time span (the number of adaptive steps is not known).
    const PARTS: f64 = 10_000.0;
    let (t0, span) = (analysis.t_start, analysis.t_end - analysis.t_start);
    let mut bar = crate::progress::Progress::new(flags.progress, PARTS as u64);
    let outcome = d.simulate_with_progress(&initial, &opts, |t| {
        bar.tick(((t - t0) / span * PARTS) as u64, t)
    });
    drop(bar);
    let wall = start.elapsed();
    drop(d);
    let (r, failure) = match outcome {
        Ok(r) => (r, None),
        Err(e) => match e.partial_results() {
            Some(r) if matches!(e.cause(), cardan_dynamics::DynamicsError::Stopped { .. }) => {
                (r.clone(), Some(crate::progress::interrupted(r.times())))
            }
            Some(r) => (r.clone(), Some(crate::dynamic::located(p, &e))),
            None => return Err(crate::dynamic::located(p, &e)),
        },
    };
    let req = requested(p, &analysis.outputs);
    let tables = crate::dynamic::tables(p, &r, &req);
    let drift = r.position_drift.iter().fold(0.0, |a: f64, &b| a.max(b));
    let summary = Summary {
        name: p.loaded.name.clone(),
        steps: r.len(),
        iterations: r.stats.newton_iterations,
        max_residual: drift,
        wall,
        dir: PathBuf::new(),
        files: Vec::new(),
        dynamic: Some(DynamicSummary {
            steps: r.stats.steps,
            rejected: r.stats.rejected,
            newton_iterations: r.stats.newton_iterations,
            max_constraint_drift: drift,
            energy_drift: r.energy.max_drift(),
        }),
        peak_efforts: peak_efforts(p, &r),
        warnings: crate::dynamic::doubtful_results(p, &r, &opts.integrator),
        subdivided_steps: None,
        row_reselections: r.stats.row_reselections,
    };
    Ok(Analysed {
        tables,
        summary,
        results: r.kinematics.clone(),
        dynamic: Some(r),
        failure,
        strict_failure: None,
    })
}

/// `kind = "inverse_dynamics"`: kinematics with driver efforts and reactions, the tables, the
/// summary. A kinematic failure mid-run keeps the results so far with the error.
fn run_inverse(
    p: &Prepared,
    analysis: &crate::build::Analysis,
    progress: bool,
) -> Result<Analysed, Error> {
    let start = Instant::now();
    // Two passes over the grid: the kinematics, then the efforts.
    let frames = 2 * (analysis.steps as u64 + 1);
    let mut bar = crate::progress::Progress::new(progress, frames);
    let (r, failure) = crate::dynamic::inverse_dynamics_with(p, |k, t| bar.tick(k as u64 + 1, t))?;
    drop(bar);
    let wall = start.elapsed();
    let req = requested(p, &analysis.outputs);
    let tables = crate::dynamic::inverse_tables(p, &r, &req);
    let k = &r.kinematics;
    let summary = Summary {
        name: p.loaded.name.clone(),
        steps: k.len(),
        iterations: k.iterations.iter().sum(),
        max_residual: k.residual.iter().fold(0.0, |a: f64, &b| a.max(b)),
        wall,
        dir: PathBuf::new(),
        files: Vec::new(),
        dynamic: None,
        peak_efforts: peak_efforts(p, &r),
        warnings: Vec::new(),
        subdivided_steps: Some(k.subdivided_steps),
        row_reselections: k.row_reselections + r.stats.row_reselections,
    };
    Ok(Analysed {
        tables,
        summary,
        results: r.kinematics.clone(),
        dynamic: Some(r),
        failure,
        strict_failure: None,
    })
}

/// Per driver: name, largest |effort| over the run, unit.
fn peak_efforts(
    p: &Prepared,
    r: &cardan_dynamics::DynamicResults,
) -> Vec<(String, f64, &'static str)> {
    r.drivers
        .iter()
        .map(|d| {
            let peak = d.effort.iter().fold(0.0f64, |a, e| a.max(e.abs()));
            (
                d.name.clone(),
                peak,
                crate::dynamic::effort_kind(p, &d.name).1,
            )
        })
        .collect()
}

/// The outputs to write: as requested, or everything when the file has no `[analysis.outputs]`.
fn requested(p: &Prepared, req: &Requested) -> Requested {
    if !req.points.is_empty() || !req.joints.is_empty() || !req.bodies.is_empty() {
        return req.clone();
    }
    let _ = &req.reactions;
    let m = &p.model;
    Requested {
        points: m
            .points()
            .iter()
            .filter(|f| f.body_name != cardan_mechanism::GROUND)
            .map(|f| (f.body_name.clone(), f.name.clone()))
            .collect(),
        joints: m.joints().iter().map(|j| j.name.clone()).collect(),
        bodies: m.bodies().iter().map(|b| b.name.clone()).collect(),
        reactions: req.reactions.clone(),
        energy: req.energy,
    }
}

/// The unit of a joint coordinate, from its name.
fn joint_unit(name: &str) -> &'static str {
    if name.starts_with("angle") {
        "rad"
    } else {
        "m"
    }
}

/// Builds the output groups from the results.
pub fn tables(p: &Prepared, r: &Results, req: &Requested) -> Vec<Table> {
    let n = r.len();
    let xyz = ["x", "y", "z"];
    let mut out = Vec::new();
    let vec_table =
        |name: &str,
         title: &str,
         unit: &str,
         pick: &dyn Fn(&cardan_mechanism::PointResults) -> &Vec<nalgebra::Vector3<f64>>| {
            let mut cols = Vec::new();
            let mut series = Vec::new();
            for (b, pt) in &req.points {
                if let Some(h) = r.point(b, pt) {
                    for (c, ax) in xyz.iter().enumerate() {
                        cols.push(format!("{b}.{pt}.{ax} [{unit}]"));
                        series.push((pick(h), c));
                    }
                }
            }
            let mut t = Table::new(name, title, cols);
            for k in 0..n {
                let mut row = vec![r.times[k]];
                row.extend(
                    series
                        .iter()
                        .map(|(v, c)| v.get(k).map_or(f64::NAN, |x| x[*c])),
                );
                t.rows.push(row);
            }
            t
        };
    if !req.points.is_empty() {
        out.push(vec_table("points", "point positions", "m", &|h| {
            &h.position
        }));
        out.push(vec_table(
            "point_velocities",
            "point velocities",
            "m/s",
            &|h| &h.velocity,
        ));
        out.push(vec_table(
            "point_accelerations",
            "point accelerations",
            "m/s²",
            &|h| &h.acceleration,
        ));
    }
    if !req.joints.is_empty() {
        let mut cols = Vec::new();
        let mut src = Vec::new();
        for j in &req.joints {
            if let Some(h) = r.joint(j) {
                for (q, c) in h.coordinate_names.iter().enumerate() {
                    cols.push(format!("{j}.{c} [{}]", joint_unit(c)));
                    src.push((h, q));
                }
            }
        }
        let mut t = Table::new("joints", "joint coordinates", cols);
        for k in 0..n {
            let mut row = vec![r.times[k]];
            row.extend(
                src.iter()
                    .map(|(h, q)| h.values.get(k).map_or(f64::NAN, |v| v[*q])),
            );
            t.rows.push(row);
        }
        out.push(t);
    }
    if !req.bodies.is_empty() {
        let bodies: Vec<_> = req.bodies.iter().filter_map(|b| r.body(b)).collect();
        let mut cols = Vec::new();
        for b in &bodies {
            for ax in xyz {
                cols.push(format!("{}.r.{ax} [m]", b.name));
            }
            for e in ["e0", "e1", "e2", "e3"] {
                cols.push(format!("{}.p.{e} [-]", b.name));
            }
        }
        let mut t = Table::new("bodies", "body poses (r, Euler parameters p)", cols);
        for k in 0..n {
            let mut row = vec![r.times[k]];
            for b in &bodies {
                row.extend((0..3).map(|c| b.r.get(k).map_or(f64::NAN, |v| v[c])));
                row.extend((0..4).map(|c| b.p.get(k).map_or(f64::NAN, |v| v[c])));
            }
            t.rows.push(row);
        }
        out.push(t);
        for (name, title, u1, u2, first, second) in [
            (
                "body_velocities",
                "body velocities (ṙ, ω global)",
                "m/s",
                "rad/s",
                "r_dot",
                "omega",
            ),
            (
                "body_accelerations",
                "body accelerations (r̈, ω̇ global)",
                "m/s²",
                "rad/s²",
                "r_ddot",
                "omega_dot",
            ),
        ] {
            let mut cols = Vec::new();
            for b in &bodies {
                for ax in xyz {
                    cols.push(format!("{}.{first}.{ax} [{u1}]", b.name));
                }
                for ax in xyz {
                    cols.push(format!("{}.{second}.{ax} [{u2}]", b.name));
                }
            }
            let mut t = Table::new(name, title, cols);
            for k in 0..n {
                let mut row = vec![r.times[k]];
                for b in &bodies {
                    let (a, w) = if first == "r_dot" {
                        (&b.r_dot, &b.omega)
                    } else {
                        (&b.r_ddot, &b.omega_dot)
                    };
                    row.extend((0..3).map(|c| a.get(k).map_or(f64::NAN, |v| v[c])));
                    row.extend((0..3).map(|c| w.get(k).map_or(f64::NAN, |v| v[c])));
                }
                t.rows.push(row);
            }
            out.push(t);
        }
    }
    let mut t = Table::new(
        "residual",
        "constraint residual",
        vec!["max |Φ| [m or -]".into(), "newton_iterations [-]".into()],
    );
    for k in 0..n {
        t.rows.push(vec![
            r.times[k],
            r.residual.get(k).copied().unwrap_or(f64::NAN),
            r.iterations.get(k).map_or(f64::NAN, |&i| i as f64),
        ]);
    }
    out.push(t);
    let _ = p;
    out
}
