//! The onset of a contact between collision shapes inside an accepted step
//! ([`crate::collision`]): a pair that touches at the step's end but did not at its start
//! began touching inside it. The contact force has a kink there and the pair's damping is
//! scaled by its approach speed at that instant, so the step is cut at the onset: located on
//! the stepper's dense output by the Illinois method on the pair's distance (0 once touching), to
//! [`EVENT_TIME_TOLERANCE`], and the state there takes the pair's onset speed
//! ([`apply_onset`]).

use super::roots::{illinois, EVENT_TIME_TOLERANCE};
use super::stepper::{Span, Stepper};
use crate::state::State;
use crate::system::Dynamics;

/// The distance of shapes (a, b) at the dense output's time `t` (0 once they touch).
fn distance_at<S: Stepper>(
    stepper: &mut S,
    d: &mut Dynamics,
    (a, b): (usize, usize),
    t: f64,
) -> f64 {
    let st = stepper.interpolate(t);
    d.sync(st);
    let c = d.collisions.as_ref().expect("collisions");
    c.distance(a, b, &d.bodies)
}

/// The earliest onset of a contact inside the step `span` (module docs), if any: the time of
/// the bracket's touching end.
pub(crate) fn first_onset<S: Stepper>(
    stepper: &mut S,
    d: &mut Dynamics,
    span: Span,
) -> Option<f64> {
    d.collisions.as_ref()?;
    if !stepper.locates_contact_onsets() {
        return None;
    }
    // The contacts at the step's end are those of the last evaluation: the step's last stage,
    // at its end (DOPRI5's first-same-as-last stage; nothing evaluates between the accepted
    // attempt and this check).
    let c = d.collisions.as_mut().expect("collisions");
    let mut onsets = std::mem::take(&mut c.scratch);
    c.new_contacts(&mut onsets);
    let mut first: Option<f64> = None;
    for &pair in &onsets {
        let f0 = distance_at(stepper, d, pair, span.t0);
        let f1 = distance_at(stepper, d, pair, span.t1);
        if !(f0 > 0.0 && f1 <= 0.0) {
            continue;
        }
        let at = |t: f64| distance_at(stepper, d, pair, t);
        // The distance is 0 all through the contact: no early return at a zero (the bracket
        // closes on its first time, bisecting where the secant lands on the touching end).
        let (_, time) = illinois(at, (span.t0, f0), (span.t1, f1), -1.0);
        if time > span.t0 + 10.0 * EVENT_TIME_TOLERANCE * (1.0 + span.t0.abs())
            && first.is_none_or(|f| time < f)
        {
            first = Some(time);
        }
    }
    d.collisions.as_mut().expect("collisions").scratch = onsets;
    first
}

/// At a located onset (`state`, projected): the onset speeds the step past it took are
/// forgotten and taken again from `state`.
pub(crate) fn apply_onset(d: &mut Dynamics, state: &State) {
    let Some(c) = d.collisions.as_mut() else {
        return;
    };
    c.forget_onsets();
    d.sync(state);
    d.eval_forces(state.t);
    d.collisions.as_mut().expect("collisions").accept();
}
