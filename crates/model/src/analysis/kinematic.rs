//! `kind = "kinematic"`: the position, velocity and acceleration analysis over the file's time
//! grid ([`cardan_mechanism::Model::kinematics_with_control`]) and its output groups: points,
//! joint coordinates, body poses, velocities and accelerations, and the residual of the
//! position analysis. The dynamic and inverse dynamics runs write the same kinematic groups.
//! The frames stream to the CSV files as they are solved ([`super::stream`]).

use super::layout::Layout;
use super::stream::{Recorder, Tap};
use super::summary::{Analysed, Summary};
use super::warnings::dropped_row_warnings;
use crate::diag::Error;
use crate::files::{FrameTap, OutputFiles};
use crate::output_tables::requested;
use crate::prepare::{analysis_error, Prepared};
use cardan_mechanism::{KinematicOptions, Results};
use std::ops::ControlFlow;
use std::path::PathBuf;
use std::time::Instant;

/// The output groups of a kinematic run held whole (shared with the other runs).
pub use super::tables::kinematic_tables as tables;

/// `kind = "kinematic"`: the kinematics over the file's grid and its tables. With `dir`, the
/// CSV files are written there frame by frame (and every frame goes to `solved`, an ASMT run's
/// TimeSeries) and only a decimated copy of the results is kept; without, every frame is kept
/// ([`super::stream`]).
pub(super) fn run_kinematic(
    p: &Prepared,
    analysis: &crate::build::Analysis,
    progress: Option<crate::progress::MakeBar>,
    dir: Option<&mut (dyn OutputFiles + 'static)>,
    solved: Option<&mut (dyn FrameTap + 'static)>,
) -> Result<Analysed, Error> {
    let opts = KinematicOptions::new(analysis.t_start, analysis.t_end, analysis.steps)
        .tolerance(analysis.tolerance)
        .free_dof(analysis.free_dof)
        .drop_inconsistent(analysis.drop_inconsistent);
    let start = Instant::now();
    let mut bar = crate::progress::Progress::new(progress, opts.steps as u64 + 1);
    let mut ws = p.model.workspace();
    let req = requested(p, &analysis.outputs);
    let make = move |f: &Results| Layout::new(f, &req);
    let tap = solved.map(|s| s as &mut dyn Tap<Results>);
    let mut rec = Recorder::new(p.units, opts.steps + 1, dir, tap, make);
    let run = p
        .model
        .kinematics_into(&mut ws, &opts, &mut |k: usize, frame: &Results| {
            if rec.frame(frame).is_break() {
                return ControlFlow::Break(());
            }
            bar.tick(k as u64 + 1, frame.times[0])
        });
    let wall = start.elapsed();
    let (totals, failure) = match run {
        Ok(t) if bar.stopped() => {
            let e = crate::progress::interrupted(rec.last_time().as_slice());
            (t, Some(Failure::Stopped(e)))
        }
        Ok(t) => (t, None),
        Err(e) => match e.partial_results() {
            Some(r) => (r.totals(), Some(Failure::Analysis(e))),
            None => return Err(analysis_error(p, &e)),
        },
    };
    drop(bar);
    let rec = rec.finish()?;
    // The error's diagnosis reads the last solved frame: the kept copy ends with it.
    let failure = failure.map(|f| match f {
        Failure::Analysis(e) => analysis_error(p, &e.with_partial(rec.results.clone())),
        Failure::Stopped(e) => e,
    });
    let mut results = rec.results;
    results.set_totals(totals.clone());
    let summary = Summary {
        name: p.loaded.name.clone(),
        steps: rec.frames,
        noun: ["step", "steps"],
        iterations: rec.tally.iterations,
        max_residual: rec.tally.max_residual,
        wall,
        dir: PathBuf::new(),
        files: Vec::new(),
        dynamic: None,
        energy_balance: None,
        peak_efforts: Vec::new(),
        warnings: (dropped_row_warnings(p, &totals.dropped_rows).into_iter())
            .chain(super::warnings::held_dof_warning(p, analysis, &totals))
            .chain(super::warnings::rating_warnings(p, &[]))
            .collect(),
        subdivided_steps: Some(totals.subdivided_steps),
        row_reselections: totals.row_reselections,
    };
    Ok(Analysed {
        tables: rec.tables,
        summary,
        results,
        dynamic: None,
        failure,
        strict_failure: None,
        files: Vec::new(),
        modes: Vec::new(),
        events: Vec::new(),
        streamed: rec.streamed,
    })
}

/// Why a run stopped early, before its diagnosis.
enum Failure {
    Analysis(cardan_mechanism::AnalysisError),
    Stopped(Error),
}
