//! [`Stepper`]: what every time integrator offers the driver loop ([`super::driver`]), and
//! what one of its steps hands back ([`Attempt`], [`Span`], [`Sample`]).
//!
//! A stepper advances one state of the equations of motion (module docs of
//! [`crate::integrators`]) by steps of its own choosing and keeps what it needs between them
//! (stage values, history, factorization state). The driver owns what is the same for every
//! scheme: the output times, the step and progress limits, the recorder. Between an accepted
//! step and [`Stepper::advance`] the step's interval [t0, t1] is open to the driver: it may
//! ask for the state at any time in it ([`Stepper::interpolate`], [`Stepper::output`]).

use crate::kkt::SchurRefinement;
use crate::results::IntegrationStats;
use crate::state::State;
use crate::system::Dynamics;
use crate::DynamicsError;

/// The interval of an accepted step.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Span {
    /// Start of the step.
    pub t0: f64,
    /// End of the step.
    pub t1: f64,
    /// Output times up to this one are taken from this step: t1 plus the roundoff the stepper
    /// allows its time (DOPRI5: 1e-12 of the step; generalized-α lands on output times).
    pub reach: f64,
}

/// The outcome of one step attempt.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum Attempt {
    /// The step was taken; the stepper holds its interval open until [`Stepper::advance`].
    Accepted(Span),
    /// The step was refused (error estimate, or the kept rows chosen again): the stepper
    /// tries again from the same state with what it learned.
    Rejected,
}

/// A state to record at an output time.
#[derive(Debug)]
pub(crate) struct Sample<'a> {
    /// The state (its time the output time).
    pub state: &'a State,
    /// The work of each channel there ([`crate::work`]).
    pub work: &'a [f64],
    /// Newton iterations to report for this output (the scheme's own count).
    pub iterations: usize,
}

/// A time integrator: one step at a time, with its dense output and counters.
///
/// The driver calls, for a run: [`new`](Self::new); [`output`](Self::output) for the output
/// times at the start; then, until the outputs are done or [`finished`](Self::finished):
/// [`prepare`](Self::prepare), [`attempt`](Self::attempt) until one is accepted,
/// [`output`](Self::output) for the output times in the step, [`advance`](Self::advance).
/// [`restart`](Self::restart) replaces the state between steps (after an impulse).
pub(crate) trait Stepper: Sized {
    /// The scheme's options.
    type Options;

    /// A stepper at the consistent `state` (laid out: `d.kkt` is prepared), to integrate up
    /// to `t_end`.
    ///
    /// # Errors
    /// Options out of range; the solve of the initial accelerations.
    fn new(
        d: &mut Dynamics,
        state: State,
        options: &Self::Options,
        t_end: f64,
    ) -> Result<Self, DynamicsError>;

    /// When the solves of this scheme refine a Schur solve (part of its configuration); the
    /// driver records its outputs with the same.
    fn refinement(&self) -> SchurRefinement;

    /// The time of the accepted state.
    fn time(&self) -> f64;

    /// Steps, rejections, evaluations and Newton iterations so far.
    fn stats(&self) -> &IntegrationStats;

    /// Whether the driver cuts the step at a contact's onset ([`super::onsets`]): a scheme
    /// whose dense output follows a stiff contact inside a step (DOPRI5's continuous
    /// extension of an adaptive step). Generalized-α's fixed steps are not cut: its Hermite
    /// interpolant across an unresolved impact is too coarse to restart from, and its pairs
    /// take their onset speed from the approach before the contact.
    fn locates_contact_onsets(&self) -> bool {
        true
    }

    /// Whether no step can follow (DOPRI5 at t_end). Generalized-α steps to each output time,
    /// so only the output times end its run.
    fn finished(&self) -> bool {
        false
    }

    /// Before the first attempt at a new accepted state: whatever the attempts start from
    /// (DOPRI5: the first stage and the step size).
    ///
    /// # Errors
    /// The evaluation's failure.
    fn prepare(&mut self, _d: &mut Dynamics) -> Result<(), DynamicsError> {
        Ok(())
    }

    /// One step attempt from the accepted state; `target` is the next output time (a scheme
    /// that lands on output times steps toward it).
    ///
    /// # Errors
    /// A failure the scheme cannot step around (step size below its minimum, too many
    /// halvings, a failed evaluation at a fixed step).
    fn attempt(&mut self, d: &mut Dynamics, target: f64) -> Result<Attempt, DynamicsError>;

    /// The state at `t` in the last accepted step's interval (dense output, not projected on
    /// the constraints), or the accepted state before any step. No allocation.
    fn interpolate(&mut self, t: f64) -> &State;

    /// The state to record at the output time `t` in the last accepted step's interval (or at
    /// the accepted state before any step), as the scheme stores it (DOPRI5: its dense output
    /// projected on the constraints). The recorder then solves the augmented system there.
    ///
    /// # Errors
    /// The projection's failure.
    fn output(&mut self, d: &mut Dynamics, t: f64) -> Result<Sample<'_>, DynamicsError>;

    /// Closes the accepted step: its end becomes the accepted state (DOPRI5 projects it).
    ///
    /// # Errors
    /// The projection's failure.
    fn advance(&mut self, _d: &mut Dynamics) -> Result<(), DynamicsError> {
        Ok(())
    }

    /// Restarts from `state` (consistent, at a time within the run) as from the start of a
    /// run, keeping the work integrated so far and the counters: the step history (step sizes,
    /// predictors, error estimates) is forgotten. The seam for an impulse that changes the
    /// velocities.
    ///
    /// # Errors
    /// The solve of the accelerations at `state`.
    fn restart(&mut self, d: &mut Dynamics, state: &State) -> Result<(), DynamicsError>;
}
