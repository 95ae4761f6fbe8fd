//! The integration loop every [`Stepper`] runs in: output times, the step and progress
//! limits, and recording, written once.
//!
//! ```text
//! outputs at t0
//! until the outputs are done (or the stepper is finished):
//!     prepare
//!     attempt (after each: the step limit and the progress callback) until one is accepted
//!     outputs in the step's interval [t0, t1] (up to its reach)
//!     advance
//! ```
//!
//! Events and impulses go here: after an attempt is accepted, an event function g(t, y) is
//! evaluated at t1 and, on a sign change, located on [t0, t1] with
//! [`Stepper::interpolate`]; the step is then cut at the event (its outputs up to it
//! recorded) and the stepper restarted there ([`Stepper::restart`]) with the velocities the
//! impulse leaves.

use super::stepper::{Attempt, Stepper};
use crate::options::SimulationOptions;
use crate::record::Recorder;
use crate::results::IntegrationStats;
use crate::state::State;
use crate::system::Dynamics;
use crate::DynamicsError;
use std::ops::ControlFlow;

/// Integrates from the consistent `state` with the stepper `S` (its `options`) and records
/// the output `times` (increasing, from `state.t`) into `rec`. `stats` receives the stepper's
/// counters, also when the run fails.
///
/// # Errors
/// The stepper's failures; [`DynamicsError::TooManySteps`] past `run.max_steps` attempts;
/// [`DynamicsError::Stopped`] when `progress` or the recorder's sink breaks.
pub(crate) fn integrate<S: Stepper>(
    d: &mut Dynamics,
    state: State,
    options: &S::Options,
    run: &SimulationOptions,
    times: &[f64],
    rec: &mut Recorder,
    stats: &mut IntegrationStats,
    progress: &mut dyn FnMut(f64) -> ControlFlow<()>,
) -> Result<(), DynamicsError> {
    let mut stepper = S::new(d, state, options, run.t_end)?;
    let r = drive(&mut stepper, d, times, run.max_steps, rec, progress);
    *stats = *stepper.stats();
    r
}

/// The loop (module docs).
fn drive<S: Stepper>(
    stepper: &mut S,
    d: &mut Dynamics,
    times: &[f64],
    max_steps: usize,
    rec: &mut Recorder,
    progress: &mut dyn FnMut(f64) -> ControlFlow<()>,
) -> Result<(), DynamicsError> {
    let mut next = 0;
    let t0 = stepper.time();
    record_outputs(stepper, d, times, &mut next, t0, rec)?;
    while next < times.len() && !stepper.finished() {
        stepper.prepare(d)?;
        let span = loop {
            check_limits(stepper, max_steps, progress)?;
            if let Attempt::Accepted(span) = stepper.attempt(d, times[next])? {
                break span;
            }
        };
        debug_assert!(span.t0 <= span.t1 && span.t1 <= span.reach);
        record_outputs(stepper, d, times, &mut next, span.reach, rec)?;
        stepper.advance(d)?;
    }
    Ok(())
}

/// Records the output times from `times[*next]` up to `reach`
/// ([`Span::reach`](super::stepper::Span::reach)).
fn record_outputs<S: Stepper>(
    stepper: &mut S,
    d: &mut Dynamics,
    times: &[f64],
    next: &mut usize,
    reach: f64,
    rec: &mut Recorder,
) -> Result<(), DynamicsError> {
    let refine = stepper.refinement();
    while *next < times.len() && times[*next] <= reach {
        let sample = stepper.output(d, times[*next])?;
        rec.record(
            d,
            sample.state,
            sample.iterations,
            Some(sample.work),
            refine,
        )?;
        *next += 1;
    }
    Ok(())
}

/// Before each attempt: the step limit (accepted and rejected attempts) and the progress
/// callback, at the accepted state's time.
fn check_limits<S: Stepper>(
    stepper: &S,
    max_steps: usize,
    progress: &mut dyn FnMut(f64) -> ControlFlow<()>,
) -> Result<(), DynamicsError> {
    let (stats, time) = (stepper.stats(), stepper.time());
    if stats.steps + stats.rejected >= max_steps {
        return Err(DynamicsError::TooManySteps { time, max_steps });
    }
    if progress(time).is_break() {
        return Err(DynamicsError::Stopped { time });
    }
    Ok(())
}
