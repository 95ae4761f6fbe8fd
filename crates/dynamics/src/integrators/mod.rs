//! Time integrators: generic numerical schemes applied to the equations of motion, each a
//! `Stepper` (`stepper.rs`) run by one driver loop (`driver.rs`).
//!
//! - [`dopri5`]: explicit Dormand-Prince 5(4), adaptive or fixed step, dense output,
//!   projection or Baumgarte stabilization.
//! - [`generalized_alpha`]: implicit index-3 generalized-α (Arnold & Brüls 2007) with Newton on
//!   [v̇, λ] and the rotation update p ⊗ exp(Δπ'/2).
//!
//! ## The stepper and the driver
//! A stepper owns what its scheme keeps between steps (stages, history, factorization
//! policy, counters) and offers: `attempt` a step (accepted with its interval [t0, t1], or
//! rejected and retried), `interpolate` the state at any time of the last accepted step
//! (dense output), `output` the state to store at an output time in it, `advance` to the
//! step's end, `restart` from a new state, and its `stats`. It also says how its solves
//! refine a Schur solve (`refinement`, part of its configuration: DOPRI5 by its tolerance,
//! generalized-α as one-shot solves). The driver owns what every scheme shares: the output
//! times, the step limit and the progress callback checked before each attempt, and the
//! recorder (`record.rs`, whose acceleration solves use the stepper's refinement).
//!
//! ## Events and impulses
//! The driver sees every accepted step before it is closed, which is where the limits and
//! contact work plugs in: an event function g(t, y) evaluated at t1 that changed sign since
//! t0 is located on [t0, t1] by root finding on `interpolate` (no projection, no change to the
//! run); the outputs before the event are recorded, and instead of `advance` the stepper is
//! `restart`ed at the event with the state the impulse leaves (new velocities, projected onto
//! the constraints). `restart` forgets the step history, as a new run would. `events.rs`
//! does this for the stops of the model's limits (impacts, releases, holds; the physics in
//! [`crate::contacts`]), and `onsets.rs` for collision shapes that begin to touch
//! (the contact's kink, [`crate::collision`]); a model without limits or shapes evaluates
//! nothing there.
//!
//! ## Adding an integrator
//! A module beside these with a struct that implements `Stepper` (its options as
//! `Stepper::Options`), a variant of [`crate::Integrator`] with the options (and their
//! `validate`), and one match arm in `Dynamics::run` (`simulate.rs`) that hands it to
//! `driver::integrate`. The driver, the recorder, the stored outputs, the limits and the
//! streaming come with it.

pub mod dopri5;
pub(crate) mod driver;
pub(crate) mod events;
pub mod generalized_alpha;
pub(crate) mod onsets;
mod roots;
pub(crate) mod stepper;

#[cfg(test)]
mod seam_tests;
