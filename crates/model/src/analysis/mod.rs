//! `cardan run`'s analyses as a library: the analysis the model file describes, run into output
//! tables with a summary ([`analyse`]; [`analyse_into`] streams the CSV files as it runs), the
//! summary line with the warnings ([`print_summary`]), `run.json` ([`run_report`]) and the
//! report page with its animation ([`animation`]). The command (`cardan-cli`) writes them into
//! its output directory.
//!
//! # Layout
//! The files use only the files below them:
//! - this module, on top: picks the analysis by kind and puts its results in the model's units;
//! - one file per analysis: [`kinematic`], [`dynamic`] (with `linearize`, the linearization
//!   about a state of the run), [`inverse`] dynamics and [`statics`] (static, quasi-static,
//!   modal), each returning an [`Analysed`] run;
//! - the pieces they share, at the bottom:
//!   - the frames as they are computed: [`stream`] (the recorder), `csv_files` (its files),
//!     `layout` and [`dynamic_layout`] (each frame's rows), `tables` (the groups held whole);
//!   - the dynamics problem: `setup` (forces, initial state, integrator settings) and `located`
//!     (its errors located in the file);
//!   - what a run reports: `summary` ([`Summary`], [`Analysed`], [`RunFlags`]), `energy` (the
//!     energy balance), `tally` (the numbers taken over every frame), `warnings` (doubtful
//!     results);
//!   - a modal run's outputs: `modes` (the mode tables) and `matrices` (MatrixMarket files).

pub mod contacts;
mod csv_files;
pub mod dynamic;
pub mod dynamic_layout;
mod energy;
mod friction;
pub mod inverse;
pub mod joint_space;
pub mod kinematic;
mod layout;
mod linearize;
mod located;
mod matrices;
pub(crate) mod modes;
mod quasi_stops;
mod resting;
mod setup;
pub mod statics;
mod stops;
pub mod stream;
mod summary;
mod tables;
mod tally;
mod warnings;

pub use energy::EnergyBalance;
pub(crate) use resting::resting_motion;
pub use summary::{Analysed, DynamicSummary, OutputSet, RunFlags, Summary};

use crate::build::AnalysisKind;
use crate::diag::Error;
use crate::files::{FrameTap, OutputFiles};
use crate::prepare::Prepared;
use crate::run_json::{Accuracy, ModelRef, Progress, RunReport, Status};
use dynamic::run_dynamic;
use inverse::run_inverse;
use kinematic::run_kinematic;
use std::io::Write;

/// Drivers the summary line names at most; a larger model's line names the largest efforts and
/// says how many more `driver_efforts.csv` holds.
const MAX_LISTED_EFFORTS: usize = 8;

/// `name value unit` of each driver, in model order, or of the [`MAX_LISTED_EFFORTS`] largest.
fn effort_list(efforts: &[(String, f64, &str)]) -> String {
    let item = |(n, v, u): &(String, f64, &str)| format!("{n} {v:.4e} {u}");
    if efforts.len() <= MAX_LISTED_EFFORTS {
        return efforts.iter().map(item).collect::<Vec<_>>().join(", ");
    }
    let mut order: Vec<usize> = (0..efforts.len()).collect();
    order.sort_by(|&a, &b| efforts[b].1.abs().total_cmp(&efforts[a].1.abs()));
    let largest: Vec<String> = order[..MAX_LISTED_EFFORTS]
        .iter()
        .map(|&k| item(&efforts[k]))
        .collect();
    format!(
        "{} (the {MAX_LISTED_EFFORTS} largest; {} more drivers in driver_efforts.csv)",
        largest.join(", "),
        efforts.len() - MAX_LISTED_EFFORTS
    )
}

/// The summary: the files written, one line of numbers, one line per warning, then where to
/// look: the report page and the directory.
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
        format!(", peak |driver effort| {}", effort_list(&s.peak_efforts))
    };
    let efforts = match s.subdivided_steps {
        Some(1) => format!("{efforts}, 1 step subdivided to follow the motion continuously"),
        Some(n) if n > 1 => {
            format!("{efforts}, {n} steps subdivided to follow the motion continuously")
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
    let balance = s.energy_balance.map_or(String::new(), |b| b.describe());
    match &s.dynamic {
        None => writeln!(
            out,
            "{}: {} {}, {} Newton iterations, largest residual {:.3e}{balance}{efforts}, wall \
             time {:.3} s",
            s.name,
            s.steps,
            s.noun[usize::from(s.steps != 1)],
            s.iterations,
            s.max_residual,
            s.wall.as_secs_f64()
        ),
        Some(d) => writeln!(
            out,
            "{}: {} outputs, {} steps ({} rejected), {} Newton iterations, max constraint drift \
             {:.3e}, energy drift {:.3e} J{balance}{efforts}{}, wall time {:.3} s",
            s.name,
            s.steps,
            d.steps,
            d.rejected,
            d.newton_iterations,
            d.max_constraint_drift,
            d.energy_drift,
            d.stops.map(stop_counts).unwrap_or_default(),
            s.wall.as_secs_f64()
        ),
    }
    .map_err(io)?;
    for w in &s.warnings {
        writeln!(out, "warning: {w}").map_err(io)?;
    }
    writeln!(out, "{}", where_to_look(s)).map_err(io)
}

/// The summary line's account of the end stops: `, 21 impacts (1 held), 0 releases, 1 stop
/// held at the end`.
fn stop_counts(c: crate::run_json::StopCounts) -> String {
    let plural =
        |n: usize, one: &str, many: &str| format!("{n} {}", if n == 1 { one } else { many });
    format!(
        ", {} ({} held), {}, {} at the end",
        plural(c.impacts, "impact", "impacts"),
        c.held_impacts,
        plural(c.releases, "release", "releases"),
        plural(c.held_at_end, "stop held", "stops held"),
    )
}

/// The summary's last line: the report page to open (when the run wrote one) and the
/// directory with every file.
fn where_to_look(s: &Summary) -> String {
    let mut dir = s.dir.display().to_string();
    if !dir.ends_with(std::path::MAIN_SEPARATOR) {
        dir.push(std::path::MAIN_SEPARATOR);
    }
    match s
        .files
        .iter()
        .find(|f| f.file_name() == Some("index.html".as_ref()))
    {
        Some(_) => format!(
            "report: {} (open it in a browser); every file is in {dir}",
            s.dir.join("index.html").display()
        ),
        None => format!("every file is in {dir}"),
    }
}

/// Runs `analysis` on the prepared model without writing anything: the analysis kind
/// (`"kinematic"`, `"inverse_dynamics"` or `"dynamic"`) and what it computed, complete or up to
/// its failure ([`Analysed::failure`]). With `flags.strict`, warnings set
/// [`Analysed::strict_failure`].
///
/// # Errors
/// Failures before the first stored time (assembly, driver count), or a run that stored no
/// time at all.
pub fn analyse(
    p: &Prepared,
    analysis: &crate::build::Analysis,
    flags: &RunFlags,
) -> Result<(&'static str, Analysed), Error> {
    analyse_into(p, analysis, flags, None, None)
}

/// [`analyse`], writing into `dir` what the analysis streams as it runs (the CSV files of a
/// kinematic, dynamic or inverse dynamics run, [`stream`], and every frame to `solved`, the
/// TimeSeries of an ASMT run) and keeping a decimated copy of the results for the plots, the
/// animation and the report ([`Analysed::streamed`] says how decimated). Without `dir`,
/// nothing is written and every frame is kept.
///
/// # Errors
/// As [`analyse`]; a write error of a streamed file.
pub fn analyse_into(
    p: &Prepared,
    analysis: &crate::build::Analysis,
    flags: &RunFlags,
    dir: Option<&mut (dyn OutputFiles + 'static)>,
    solved: Option<&mut (dyn FrameTap + 'static)>,
) -> Result<(&'static str, Analysed), Error> {
    let progress = flags.progress;
    let kind = analysis.kind.name();
    let ran = match analysis.kind {
        AnalysisKind::Static(k) if quasi_stops::applies(p, k) => quasi_stops::run(p, analysis),
        AnalysisKind::Static(k) => statics::run_statics(p, analysis, k),
        AnalysisKind::Dynamic(_) => run_dynamic(p, analysis, flags, dir, solved),
        AnalysisKind::InverseDynamics => run_inverse(p, analysis, progress, dir, solved),
        AnalysisKind::Kinematic => run_kinematic(p, analysis, progress, dir, solved),
    };
    let mut a = ran?;
    a.summary.warnings.splice(0..0, p.warnings.iter().cloned());
    in_units(p.units, &mut a);
    if a.results.times.is_empty() {
        return Err(a.failure.unwrap_or_else(|| {
            Error::analysis("the analysis stored no result (no time was solved)")
        }));
    }
    if flags.strict && a.failure.is_none() && !a.summary.warnings.is_empty() {
        a.strict_failure = Some(strict_error(&a.summary.warnings));
    }
    Ok((kind, a))
}

/// The outputs of a run in the model's units (the analyses work in SI): tables and peak efforts.
fn in_units(units: crate::units::UnitSystem, a: &mut Analysed) {
    for t in &mut a.tables {
        units.convert_table(t);
    }
    for (_, v, u) in &mut a.summary.peak_efforts {
        let (unit, factor) = units.unit(u);
        *v *= factor;
        *u = if unit == "N mm" { "N mm" } else { *u };
    }
}

/// The contents `run.json` would have for an analysed run writing `files` (the Python bindings
/// attach it to their results).
pub fn run_json(p: &Prepared, kind: &'static str, a: &Analysed, files: Vec<String>) -> String {
    run_report(p, kind, a, files).to_json()
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

/// What the report page shows: the scene, its animation (`.glb`) and the page's other parts.
#[derive(Debug, Clone)]
pub struct Shown {
    /// The bodies, their geometry and poses over the run.
    pub scene: cardan_report::Scene,
    /// The scene as `animation.glb`.
    pub glb: Vec<u8>,
    /// The plots, the summary, the modes and the stops.
    pub page: cardan_report::Page,
}

impl Shown {
    /// The report page (`index.html`).
    ///
    /// # Errors
    /// The page cannot be written (modes or stops that do not fit the scene).
    pub fn html(&self) -> Result<cardan_report::Html, Error> {
        cardan_report::write_html(&self.scene, &self.glb, &self.page)
            .map_err(|e| Error::output(format!("index.html: {e}")))
    }

    /// The same for a page already open ([`cardan_report::write_update`]).
    ///
    /// # Errors
    /// As [`Self::html`].
    pub fn update(&self) -> Result<String, Error> {
        cardan_report::write_update(&self.scene, &self.glb, &self.page)
            .map_err(|e| Error::output(format!("index.html: {e}")))
    }
}

/// The animation (`animation.glb`) and the parts of the report page (`index.html`:
/// [`Shown::html`]; the live preview also sends them to a page already open, [`Shown::update`])
/// of an analysed run whose output files are `files`, the page showing the plots `svgs` (name,
/// SVG) and the run summary. `None` (with a warning in the summary) when the scene cannot be
/// written as glTF; modes the page cannot animate (not finite) are left out of it with a
/// warning.
pub fn animation(
    p: &Prepared,
    kind: &'static str,
    a: &mut Analysed,
    declared: &crate::geometry::Declared,
    svgs: Vec<(String, String)>,
    files: Vec<String>,
) -> Option<Shown> {
    let scene = crate::scene::scene(&p.loaded.name, &p.model, &a.results, declared);
    let glb = match cardan_report::write_glb(&scene) {
        Ok(g) => g,
        Err(e) => {
            a.summary.warnings.push(format!(
                "animation.glb and index.html were not written: {e}"
            ));
            return None;
        }
    };
    let mut modes = crate::scene::mode_shapes(&p.model, &a.results, &a.modes);
    if let Err(e) = cardan_report::validate_modes(&scene, &modes) {
        a.summary
            .warnings
            .push(format!("index.html does not animate the modes: {e}"));
        modes.clear();
    }
    // A dynamic run's end stops, from its stops table and events.csv (none without limits).
    let (stops, stop_events) = crate::scene::stop_markers(
        &p.model,
        &scene,
        a.tables.iter().find(|t| t.name == "stops"),
        &a.events,
    );
    let page = cardan_report::Page {
        plots: svgs,
        summary: serde_json::from_str(&run_report(p, kind, a, files).to_json()).ok(),
        up: declared.up,
        modes,
        stops,
        stop_events,
    };
    Some(Shown { scene, glb, page })
}

/// The contents of `run.json` for an analysed run whose tables are `files`.
pub fn run_report(p: &Prepared, kind: &'static str, a: &Analysed, files: Vec<String>) -> RunReport {
    let s = &a.summary;
    let d = s.dynamic.as_ref();
    RunReport {
        model: ModelRef {
            path: p.file.display().to_string(),
            name: s.name.clone(),
        },
        analysis: kind,
        units: match p.units {
            crate::units::UnitSystem::Si => "SI",
            crate::units::UnitSystem::Mm => "mm",
        },
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
        progress: Progress {
            t_reached: a.results.times.last().copied(),
            steps: s.steps,
            integration_steps: d.map(|d| d.steps),
            rejected_steps: d.map(|d| d.rejected),
            newton_iterations: s.iterations,
            stops: d.and_then(|d| d.stops),
        },
        accuracy: Accuracy {
            largest_residual: s.max_residual,
            constraint_drift: d.map(|d| d.max_constraint_drift),
            energy_drift: d.map(|d| d.energy_drift),
            energy_balance: s.energy_balance.map(|b| b.max_abs),
            energy_scale: s.energy_balance.map(|b| b.scale),
        },
        warnings: s.warnings.clone(),
        subdivided_steps: s.subdivided_steps,
        row_reselections: s.row_reselections,
        plotted_frames: (a.streamed.as_ref()).filter(|d| d.stride > 1).map(|d| {
            crate::run_json::PlottedFrames {
                kept: d.kept,
                of: d.frames,
                every: d.stride,
            }
        }),
        files,
        wall_time_s: s.wall.as_secs_f64(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_summary_names_every_driver_of_a_small_model_and_the_largest_of_a_large_one() {
        let few = vec![
            ("motor".to_string(), -2.5, "N m"),
            ("jack".to_string(), 10.0, "N"),
        ];
        assert_eq!(effort_list(&few), "motor -2.5000e0 N m, jack 1.0000e1 N");
        let many: Vec<(String, f64, &str)> = (0..1000)
            .map(|k| (format!("d{k}"), (k as f64 - 500.0).abs(), "N m"))
            .collect();
        let line = effort_list(&many);
        assert!(
            line.starts_with("d0 5.0000e2 N m, d1 4.9900e2 N m, d999 4.9900e2 N m"),
            "{line}"
        );
        assert!(line.ends_with("(the 8 largest; 992 more drivers in driver_efforts.csv)"));
        assert_eq!(line.matches(" N m").count(), 8);
    }
}
