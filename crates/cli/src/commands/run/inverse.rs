//! `kind = "inverse_dynamics"`: the kinematics on the file's time grid and, at every time, the
//! driver efforts and joint reactions that produce that motion under the file's forces
//! ([`cardan_dynamics::Dynamics::inverse_dynamics`]). Its output groups are the kinematic ones
//! (with the residual of the position analysis), the driver efforts and the reactions. It needs
//! a fully driven mechanism ([`crate::commands::not_fully_driven`] says what is missing;
//! `cardan check` uses it too).

use super::dynamic::{dynamics_as, located_as};
use super::kinematic;
use super::summary::{Analysed, Summary};
use crate::build::Outputs as Requested;
use crate::commands::output_tables::{
    coupler_efforts_table, driver_efforts_table, energy_table, peak_efforts, reaction_tables,
    requested,
};
use crate::commands::{analysis_error, Prepared};
use crate::diag::Error;
use crate::table::Table;
use cardan_dynamics::{DynamicResults, DynamicsError};
use cardan_mechanism::{AssemblyOptions, KinematicOptions};
use std::ops::ControlFlow;
use std::path::PathBuf;
use std::time::Instant;

/// `kind = "inverse_dynamics"`: kinematics with driver efforts and reactions, the tables, the
/// summary. A kinematic failure mid-run keeps the results so far with the error.
pub(super) fn run_inverse(
    p: &Prepared,
    analysis: &crate::build::Analysis,
    progress: bool,
) -> Result<Analysed, Error> {
    let start = Instant::now();
    // Two passes over the grid: the kinematics, then the efforts.
    let frames = 2 * (analysis.steps as u64 + 1);
    let mut bar = crate::progress::Progress::new(progress, frames);
    let (r, failure) = inverse_dynamics_with(p, |k, t| bar.tick(k as u64 + 1, t))?;
    drop(bar);
    let wall = start.elapsed();
    let req = requested(p, &analysis.outputs);
    let tables = inverse_tables(p, &r, &req);
    let k = &r.kinematics;
    let summary = Summary {
        name: p.loaded.name.clone(),
        steps: k.len(),
        noun: ["step", "steps"],
        iterations: k.iterations.iter().sum(),
        max_residual: k.residual.iter().fold(0.0, |a: f64, &b| a.max(b)),
        wall,
        dir: PathBuf::new(),
        files: Vec::new(),
        dynamic: None,
        energy_balance: Some(super::summary::EnergyBalance::of(&r.energy)),
        peak_efforts: peak_efforts(p, &r),
        warnings: kinematic::dropped_row_warnings(p, &k.dropped_rows),
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
        files: Vec::new(),
        modes: Vec::new(),
        streamed: None,
    })
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
    const WHAT: &str = "inverse dynamics";
    let a = p
        .loaded
        .analysis
        .as_ref()
        .filter(|a| a.inverse_dynamics)
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
        return Err(crate::commands::not_fully_driven(p, dof.dof, 0));
    }
    let mut d = dynamics_as(p, WHAT)?;
    let opts = KinematicOptions::new(a.t_start, a.t_end, a.steps).tolerance(a.tolerance);
    let e = match d.inverse_dynamics_with_progress(&opts, progress) {
        Ok(r) => return Ok((r, None)),
        Err(e) => e,
    };
    match e.cause() {
        DynamicsError::Stopped { .. } => match e.partial_results() {
            Some(r) => Ok((r.clone(), Some(crate::progress::interrupted(r.times())))),
            None => Err(located_as(p, &e, WHAT)),
        },
        DynamicsError::NotFullyDriven { dof, drivers } => {
            Err(crate::commands::not_fully_driven(p, *dof, *drivers))
        }
        DynamicsError::Mechanism(ae) => {
            let err = analysis_error(p, ae);
            match e.partial_results() {
                // The kinematics stopped mid-run: the results so far, and the error.
                Some(r) => Ok((r.clone(), Some(err))),
                None => Err(err),
            }
        }
        _ => Err(located_as(p, &e, WHAT)),
    }
}

/// The output groups of an inverse dynamics run: the kinematic groups (with the residual of the
/// position analysis), then driver efforts, reactions (global and body components) and energy
/// (with the drivers' power and work along the prescribed motion, the work by the trapezoidal
/// rule on the time grid).
pub fn inverse_tables(p: &Prepared, r: &DynamicResults, req: &Requested) -> Vec<Table> {
    let mut out = kinematic::tables(&r.kinematics, req);
    out.extend(driver_efforts_table(p, r));
    out.extend(coupler_efforts_table(p, r));
    out.extend(reaction_tables(r, req));
    if req.energy {
        out.push(energy_table(r));
    }
    out
}
