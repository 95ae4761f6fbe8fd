//! `kind = "inverse_dynamics"`: the kinematics on the file's time grid and, at every time, the
//! driver efforts and joint reactions that produce that motion under the file's forces
//! ([`cardan_dynamics::Dynamics::inverse_dynamics`]). Its output groups are the kinematic ones
//! (with the residual of the position analysis), the driver efforts and the reactions. It needs
//! a fully driven mechanism ([`crate::prepare::not_fully_driven`] says what is missing;
//! `cardan check` uses it too), or one whose start rests on as many end stops as the drivers
//! leave degrees of freedom: those stops are held, their reactions reported as efforts, and a
//! reaction that changes sign (the motion leaves the stop) is a warning
//! (`super::resting::resting_motion`).

use super::dynamic_layout::{DynamicLayout, Kind};
use super::energy::ENERGY_BALANCE_BOUND;
use super::located::located_as;
use super::setup::dynamics_as;
use super::stream::{Recorder, Tap};
use super::summary::{Analysed, Summary};
use super::tally::DynamicTally;
use super::warnings::dropped_row_warnings;
use crate::diag::Error;
use crate::files::{FrameTap, OutputFiles};
use crate::output_tables::{computed, peak_efforts_of, requested};
use crate::prepare::{analysis_error, Prepared};
use cardan_dynamics::{DynamicResults, DynamicsError};
use cardan_mechanism::{AssemblyOptions, KinematicOptions};
use std::ops::ControlFlow;
use std::path::PathBuf;
use std::time::Instant;

/// The output groups of an inverse dynamics run held whole (shared with the static kinds).
pub use super::tables::inverse_tables;

/// `kind = "inverse_dynamics"`: kinematics with driver efforts and reactions, the tables, the
/// summary. A kinematic failure mid-run keeps the results so far with the error. With `dir`,
/// the CSV files are written there frame by frame and only a decimated copy of the results is
/// kept (every frame goes to `solved`, an ASMT run's TimeSeries); without, every frame is
/// kept ([`super::stream`]). The summary is
/// taken over every frame.
pub(super) fn run_inverse(
    p: &Prepared,
    analysis: &crate::build::Analysis,
    progress: Option<crate::progress::MakeBar>,
    dir: Option<&mut (dyn OutputFiles + 'static)>,
    solved: Option<&mut (dyn FrameTap + 'static)>,
) -> Result<Analysed, Error> {
    let resting = super::resting::resting_motion(p, analysis.t_start)?;
    let p = resting.as_ref().unwrap_or(p);
    let mut pulls = super::resting::PullWatch::new(p);
    let (mut d, opts) = setup(p)?;
    let req = requested(p, &analysis.outputs);
    let opts = opts.outputs(computed(&req));
    let make = |f: &DynamicResults| DynamicLayout::new(p, f, &req, Kind::Inverse);
    let tap = solved.map(|s| s as &mut dyn Tap<DynamicResults>);
    let mut rec = Recorder::new(p.units, opts.steps + 1, dir, tap, make);
    let start = Instant::now();
    let mut bar = crate::progress::Progress::new(progress, opts.steps as u64 + 1);
    let mut sink = |k: usize, frame: &DynamicResults| {
        pulls.take(frame);
        if rec.frame(frame).is_break() {
            return ControlFlow::Break(());
        }
        bar.tick(k as u64 + 1, frame.times()[0])
    };
    let run = d.inverse_dynamics_into(&opts, &mut sink);
    let friction = super::friction::friction_table(p, d.friction_history());
    let stopped = bar.stopped();
    drop(bar);
    let wall = start.elapsed();
    let outcome = match run {
        Ok(totals) => Ok((totals, None)),
        Err(e) => failure(p, e, stopped, rec.last_time()),
    };
    // A write error stopped the run: it is the error.
    let rec = rec.finish()?;
    let (totals, failure) = outcome?;
    let mut r = rec.results;
    r.stats = totals.stats;
    r.redundant = totals.redundant;
    r.kinematics.set_totals(totals.kinematics.totals());
    // The error's diagnosis reads the last solved frame: the kept copy ends with it.
    let failure = failure.map(|f| match f {
        Failure::Analysis(e) => analysis_error(p, &e.with_partial(r.kinematics.clone())),
        Failure::Other(e) => e,
    });
    let k = &r.kinematics;
    let tally = rec.tally;
    let summary = Summary {
        name: p.loaded.name.clone(),
        steps: rec.frames,
        noun: ["step", "steps"],
        iterations: tally.iterations,
        max_residual: tally.max_drift,
        wall,
        dir: PathBuf::new(),
        files: Vec::new(),
        dynamic: None,
        energy_balance: Some(tally.energy_balance()),
        peak_efforts: peak_efforts_of(p, &r, &tally.peak_efforts),
        warnings: (inverse_warnings(p, &tally, &k.dropped_rows).into_iter())
            .chain(pulls.warning(p))
            .collect(),
        subdivided_steps: Some(k.subdivided_steps),
        row_reselections: k.row_reselections + r.stats.row_reselections,
    };
    Ok(Analysed {
        tables: rec.tables.into_iter().chain(friction).collect(),
        summary,
        results: r.kinematics.clone(),
        dynamic: Some(r),
        failure,
        strict_failure: None,
        files: Vec::new(),
        modes: Vec::new(),
        events: Vec::new(),
        streamed: rec.streamed,
    })
}

/// Why an inverse dynamics run stopped early, before its diagnosis.
enum Failure {
    /// The kinematics failed (diagnosed at the last solved frame).
    Analysis(cardan_mechanism::AnalysisError),
    /// Stopped, or another error.
    Other(Error),
}

/// The counters of a run that stopped mid-run and why; the error of one that stored nothing.
/// `stopped`: the progress bar asked to stop (Ctrl-C); `last_time`: the last time streamed.
fn failure(
    p: &Prepared,
    e: DynamicsError,
    stopped: bool,
    last_time: Option<f64>,
) -> Result<(DynamicResults, Option<Failure>), Error> {
    let Some(partial) = e.partial_results().cloned() else {
        return Err(error(p, &e));
    };
    let why = match e.cause() {
        DynamicsError::Stopped { .. } if stopped => {
            Failure::Other(crate::progress::interrupted(last_time.as_slice()))
        }
        DynamicsError::Mechanism(ae) => Failure::Analysis(ae.clone()),
        _ => Failure::Other(error(p, &e)),
    };
    Ok((partial, Some(why)))
}

/// The error of an inverse dynamics run that stored nothing (or failed in its efforts).
fn error(p: &Prepared, e: &DynamicsError) -> Error {
    match e.cause() {
        DynamicsError::NotFullyDriven { dof, drivers } => {
            crate::prepare::not_fully_driven(p, *dof, *drivers)
        }
        DynamicsError::Mechanism(ae) => analysis_error(p, ae),
        _ => located_as(p, e, WHAT),
    }
}

const WHAT: &str = "inverse dynamics";

/// The file's inverse dynamics analysis ready to run: the dynamics with the file's forces and
/// the kinematic options of its grid.
///
/// # Errors
/// As [`inverse_dynamics`], before the run.
fn setup(p: &Prepared) -> Result<(cardan_dynamics::Dynamics<'_>, KinematicOptions), Error> {
    let a = p
        .loaded
        .analysis
        .as_ref()
        .filter(|a| a.kind == crate::build::AnalysisKind::InverseDynamics)
        .ok_or_else(|| {
            p.source
                .error("the model file has no [analysis] with kind = \"inverse_dynamics\"")
        })?;
    if p.model.drivers().is_empty() {
        // Without drivers the run would succeed on a structure and compute nothing useful; say
        // how many DOF the joints leave (assembling without drivers, as `cardan check` does).
        let mut ws = p.model.workspace();
        let opts = AssemblyOptions {
            include_drivers: false,
            ..AssemblyOptions::at(a.t_start)
        };
        p.model
            .assemble(&mut ws, &opts)
            .map_err(|e| analysis_error(p, &e))?;
        let dof = p.model.dof(&ws).map_err(|e| analysis_error(p, &e))?;
        return Err(crate::prepare::not_fully_driven(p, dof.dof, 0));
    }
    let mut d = dynamics_as(p, WHAT)?;
    super::joint_space::request(p, &mut d, &a.outputs)?;
    let opts = KinematicOptions::new(a.t_start, a.t_end, a.steps)
        .tolerance(a.tolerance)
        .drop_inconsistent(a.drop_inconsistent);
    Ok((d, opts))
}

/// Runs the file's `kind = "inverse_dynamics"` analysis: the kinematics on the file's time grid
/// and, at every time, the driver efforts and joint reactions that produce that motion under the
/// file's forces ([`cardan_dynamics::Dynamics::inverse_dynamics`]).
///
/// Returns the results and, when the kinematics stopped early (a singular configuration, a
/// limit of the motion), the error with the results up to the last solved time.
///
/// # Errors
/// No such analysis; a mechanism that is not fully driven (no drivers, or fewer or more than the
/// joints leave degrees of freedom: an input error naming the DOF and the drivers); a body
/// without mass or inertia; assembly failures and failures at the first step.
pub fn inverse_dynamics(p: &Prepared) -> Result<(DynamicResults, Option<Error>), Error> {
    inverse_dynamics_with(p, |_, _| ControlFlow::Continue(()))
}

/// [`inverse_dynamics`] with a progress callback
/// ([`cardan_dynamics::Dynamics::inverse_dynamics_with_progress`]); when it breaks (Ctrl-C),
/// the results so far and an interrupted error ([`crate::progress::interrupted`]).
///
/// # Errors
/// As [`inverse_dynamics`].
pub fn inverse_dynamics_with(
    p: &Prepared,
    progress: impl FnMut(usize, f64) -> ControlFlow<()>,
) -> Result<(DynamicResults, Option<Error>), Error> {
    let t_start = (p.loaded.analysis.as_ref()).map_or(0.0, |a| a.t_start);
    let resting = super::resting::resting_motion(p, t_start)?;
    let p = resting.as_ref().unwrap_or(p);
    let (mut d, opts) = setup(p)?;
    let e = match d.inverse_dynamics_with_progress(&opts, progress) {
        Ok(r) => return Ok((r, None)),
        Err(e) => e,
    };
    match e.cause() {
        DynamicsError::Stopped { .. } => match e.partial_results() {
            Some(r) => Ok((r.clone(), Some(crate::progress::interrupted(r.times())))),
            None => Err(located_as(p, &e, WHAT)),
        },
        DynamicsError::Mechanism(ae) => match e.partial_results() {
            // The kinematics stopped mid-run: the results so far, and the error (diagnosed
            // at the last solved frame).
            Some(r) => {
                let ae = ae.clone().with_partial(r.kinematics.clone());
                Ok((r.clone(), Some(analysis_error(p, &ae))))
            }
            None => Err(analysis_error(p, ae)),
        },
        _ => Err(error(p, &e)),
    }
}

/// The doubtful results of an inverse dynamics run: an energy balance beyond
/// [`ENERGY_BALANCE_BOUND`] of the energy scale (the motion is prescribed, so
/// the balance measures the quadrature of the work on the output grid and the position
/// tolerance: the output step is too coarse for the motion), and the dropped rows left open.
fn inverse_warnings(
    p: &Prepared,
    tally: &DynamicTally,
    dropped_rows: &[cardan_mechanism::DroppedRowResidual],
) -> Vec<String> {
    let mut warnings = Vec::new();
    let (balance, scale) = (tally.max_balance, tally.energy_scale());
    if balance > ENERGY_BALANCE_BOUND * scale {
        warnings.push(format!(
            "energy balance {balance:.3e} J (the energy change less the work of the drivers and \
             non-conservative forces) is {:.1} % of the model's energy scale {scale:.3e} J, more \
             than the {} % allowed: the work is integrated over the output times, which are too \
             far apart for this motion; use more steps",
            100.0 * balance / scale,
            100.0 * ENERGY_BALANCE_BOUND
        ));
    }
    warnings.extend(dropped_row_warnings(p, dropped_rows));
    warnings.extend(super::warnings::cam_pull_warnings(tally));
    warnings.extend(super::warnings::rating_warnings(p, &tally.peak_efforts));
    warnings
}
