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
//! Events and impulses go here: after an attempt is accepted, the stops of the model's limits
//! are checked on the step ([`events::first_event`]: a closing located on g(t) over
//! [`Stepper::interpolate`], a held stop's release, a held stop off its bound); the outputs
//! before the event are recorded, the event applied to the state there (an impulse, a release,
//! a hold: [`events::apply`]), the stepper restarted there ([`Stepper::restart`]) and the
//! outputs at the event's time recorded from the new state. A model without limits checks
//! nothing and runs the loop above unchanged.

use super::events;
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
    let mut stops = Stops::new(d, stepper.interpolate(t0));
    record_outputs(stepper, d, times, &mut next, t0, false, rec, &mut stops)?;
    while next < times.len() && !stepper.finished() {
        stepper.prepare(d)?;
        let span = loop {
            check_limits(stepper, max_steps, progress)?;
            if let Attempt::Accepted(span) = stepper.attempt(d, times[next])? {
                break span;
            }
        };
        debug_assert!(span.t0 <= span.t1 && span.t1 <= span.reach);
        if stops.watch {
            if let Some(ev) = events::first_event(stepper, d, span)? {
                record_outputs(stepper, d, times, &mut next, ev.time, true, rec, &mut stops)?;
                stops.event(ev.time)?;
                stops.state.clone_from(stepper.interpolate(ev.time));
                events::apply(d, ev, &mut stops.state, EVENT_PROJECTION_TOLERANCE)?;
                stepper.restart(d, &stops.state)?;
                // Outputs at the event's time from the state after it (a scheme that lands on
                // output times would otherwise be asked for a step of zero length).
                record_outputs(
                    stepper, d, times, &mut next, ev.time, false, rec, &mut stops,
                )?;
                continue;
            }
        }
        record_outputs(
            stepper, d, times, &mut next, span.reach, false, rec, &mut stops,
        )?;
        stepper.advance(d)?;
    }
    Ok(())
}

/// The projection tolerance (scaled residual) of the state at an event.
const EVENT_PROJECTION_TOLERANCE: f64 = 1e-12;

/// Events in a row at one time beyond which a run is chattering (an error, not a hang).
const MAX_EVENTS_AT_ONE_TIME: usize = 100;

/// The driver's part of the stops (a model without limits: nothing is watched).
struct Stops {
    watch: bool,
    /// The state at an event (its storage reused).
    state: State,
    /// The work of the channels at an output, the impacts' work added (storage reused).
    work: Vec<f64>,
    last_event: f64,
    repeats: usize,
}

impl Stops {
    fn new(d: &Dynamics, state: &State) -> Self {
        let watch = !d.contacts.watched.is_empty()
            || !d.contacts.compliant.is_empty()
            || d.collisions.is_some();
        Self {
            watch,
            state: if watch {
                state.clone()
            } else {
                State {
                    t: 0.0,
                    q: Vec::new(),
                    v: Vec::new(),
                }
            },
            work: if watch {
                vec![0.0; d.num_work_channels()]
            } else {
                Vec::new()
            },
            last_event: f64::NEG_INFINITY,
            repeats: 0,
        }
    }

    /// Counts events at one time: a run that makes no progress between events stops with an
    /// error.
    fn event(&mut self, t: f64) -> Result<(), DynamicsError> {
        if t <= self.last_event {
            self.repeats += 1;
            if self.repeats > MAX_EVENTS_AT_ONE_TIME {
                return Err(DynamicsError::Limit {
                    limit: "(all)".into(),
                    reason: format!(
                        "{MAX_EVENTS_AT_ONE_TIME} events at t = {t} without progress (chattering)"
                    ),
                });
            }
        } else {
            self.repeats = 0;
        }
        self.last_event = t;
        Ok(())
    }
}

/// Records the output times from `times[*next]` up to `reach`
/// ([`Span::reach`](super::stepper::Span::reach)), or strictly before it (`strict`: an event
/// there).
#[allow(clippy::too_many_arguments)]
fn record_outputs<S: Stepper>(
    stepper: &mut S,
    d: &mut Dynamics,
    times: &[f64],
    next: &mut usize,
    reach: f64,
    strict: bool,
    rec: &mut Recorder,
    stops: &mut Stops,
) -> Result<(), DynamicsError> {
    let refine = stepper.refinement();
    while *next < times.len() && (times[*next] < reach || (!strict && times[*next] == reach)) {
        let sample = stepper.output(d, times[*next])?;
        let work = if stops.watch {
            stops.work.copy_from_slice(sample.work);
            d.add_impact_work(&mut stops.work);
            &stops.work[..]
        } else {
            sample.work
        };
        rec.record(d, sample.state, sample.iterations, Some(work), refine)?;
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
