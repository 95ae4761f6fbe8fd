//! Events of the stops inside an accepted step (the driver's seam, [`super::driver`]): a stop
//! that closes (its gap g crosses 0 downwards, also when it opens again inside the same step:
//! a graze, found from the rate ġ turning from closing to opening), a compliant stop's contact
//! beginning or ending (its force's kink: the step is cut there), a held stop whose multiplier changes sign
//! (it would pull: it opens), a held stop found off g = 0 at the step's end by a scheme that
//! does not carry the stop rows (generalized-α: the step's end is brought back onto it).
//!
//! Each is located on the stepper's dense output ([`Stepper::interpolate`]): the closing by
//! the Illinois variant of regula falsi on g(t) to [`EVENT_TIME_TOLERANCE`] (relative to the
//! time) or |g| ≤ 1e-15 of the coordinate's scale, the release by bisection on λ_s(t) (the
//! augmented system solved at the interpolated state) to the same time tolerance. The driver
//! records the outputs before the event, applies it (impact, release or hold) and restarts
//! the stepper there. A model without limits evaluates nothing here.

use super::stepper::{Span, Stepper};
use crate::contacts::state::HOLD_TOLERANCE;
use crate::kkt::SchurRefinement;
use crate::options::Baumgarte;
use crate::state::State;
use crate::system::Dynamics;
use crate::DynamicsError;

pub use super::roots::EVENT_TIME_TOLERANCE;
use super::roots::{illinois as illinois_on, MAX_LOCATE};

/// What happens at an event.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum Action {
    /// Stop `s` closes: an impact.
    Impact(usize),
    /// Held stop `s` opens.
    Release(usize),
    /// The held stops are brought back onto g = 0, ġ = 0.
    Hold,
    /// A compliant stop's contact begins or ends: its force law has a kink there, so the
    /// step ends at it and the next starts from it (nothing jumps).
    Kink,
    /// Collision shapes begin to touch ([`super::onsets`]).
    Onset,
}

/// An event at `time`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Event {
    pub time: f64,
    pub action: Action,
}

fn scale(d: &Dynamics, s: usize) -> f64 {
    d.model.stop_scale(s)
}

/// g of stop `s` at the dense output's time `t`.
fn gap_at<S: Stepper>(stepper: &mut S, d: &mut Dynamics, s: usize, t: f64) -> f64 {
    let st = stepper.interpolate(t);
    d.sync(st);
    d.model.stop_gap(s, &d.bodies, &d.turns)
}

/// λ_s of held stop `s` at the dense output's time `t` (the augmented system with the held
/// stops solved there).
fn multiplier_at<S: Stepper>(
    stepper: &mut S,
    d: &mut Dynamics,
    s: usize,
    t: f64,
) -> Result<f64, DynamicsError> {
    let st = stepper.interpolate(t);
    d.sync(st);
    d.solve_eom(t, Baumgarte::NONE, SchurRefinement::ONE_SHOT)?;
    Ok(d.contacts.lambda[s])
}

/// The first closing of g_s in the step (g < 0 at its end) by the Illinois method. A step that
/// starts on the stop (g(t0) ≈ 0 after a rebound) and ends beyond it has two crossings when the
/// rebound carried it off the stop in between: the bracket then starts at the largest g in the
/// step (golden-section search: g rises, then falls); if g stays ≤ 0 the stop closes at t0.
fn locate_closing<S: Stepper>(stepper: &mut S, d: &mut Dynamics, s: usize, span: Span) -> f64 {
    let sc = scale(d, s);
    let (mut a, b) = (span.t0, span.t1);
    let mut ga = gap_at(stepper, d, s, a);
    if ga <= 1e-15 * sc {
        let (t, g) = highest(stepper, d, s, span);
        if g <= 1e-15 * sc {
            return span.t0;
        }
        (a, ga) = (t, g);
    }
    let gb = gap_at(stepper, d, s, b);
    // The open side: the state there has not passed the stop (or g = 0 there).
    illinois(stepper, d, s, 1.0, (a, ga), (b, gb), 1e-15 * sc).0
}

/// The sign change of `sign` g_s in [a, b] (`sign` g > 0 at a, < 0 at b) by the Illinois
/// method ([`illinois_on`]): the final bracket, both ends at a time where |g| ≤ `zero`.
fn illinois<S: Stepper>(
    stepper: &mut S,
    d: &mut Dynamics,
    s: usize,
    sign: f64,
    a: (f64, f64),
    b: (f64, f64),
    zero: f64,
) -> (f64, f64) {
    illinois_on(|t| sign * gap_at(stepper, d, s, t), a, b, zero)
}

/// A stop closed and opened again inside the step (a graze): g ≥ 0 at both ends, but the
/// stop was closing at the start (ġ < 0) and opening at the end (ġ > 0), so g has a minimum
/// inside; when that minimum (golden-section search) is below the hold tolerance (a dip
/// within it is the roundoff of a stop just released, whose g and ġ start at drift level),
/// the closing before it. Only the end's rate is evaluated for a step that ends closing or at
/// rest (most steps), and the search runs only where the gap can reach that depth: with g
/// convex over the step (its rate rising from ġ₀ < 0 to ġ₁ > 0), g ≥ g₀ + ġ₀ Δt and
/// g ≥ g₁ − ġ₁ Δt, so a turn well away from the stop (a swing reversing far from it) costs two
/// rates and a gap. `g1`: the gap at the step's end.
fn grazed<S: Stepper>(
    stepper: &mut S,
    d: &mut Dynamics,
    s: usize,
    span: Span,
    g1: f64,
) -> Option<f64> {
    // `d` holds the step's end (the gap was just evaluated there).
    let r1 = d.model.stop_rate(s, &d.bodies, &d.turns);
    if r1 <= 0.0 {
        return None;
    }
    let st = stepper.interpolate(span.t0);
    d.sync(st);
    let r0 = d.model.stop_rate(s, &d.bodies, &d.turns);
    if r0 >= 0.0 {
        return None;
    }
    let depth = -HOLD_TOLERANCE * scale(d, s);
    let g0 = d.model.stop_gap(s, &d.bodies, &d.turns);
    let dt = span.t1 - span.t0;
    if (g0 + r0 * dt).max(g1 - r1 * dt) >= depth {
        return None;
    }
    let (t_min, g_min) = extremum(stepper, d, s, span, -1.0);
    (g_min < depth).then(|| {
        let before = Span { t1: t_min, ..span };
        locate_closing(stepper, d, s, before)
    })
}

/// Where compliant stop `s`'s gap changes sign inside the step (its contact begins or ends:
/// the force's kink), by the Illinois method on ±g; `None` without a change, or when the
/// change is at the step's start (the step that began at the kink).
fn contact_kink<S: Stepper>(
    stepper: &mut S,
    d: &mut Dynamics,
    s: usize,
    span: Span,
) -> Option<f64> {
    let g0 = gap_at(stepper, d, s, span.t0);
    let g1 = gap_at(stepper, d, s, span.t1);
    if g0 == 0.0 || (g0 > 0.0) == (g1 > 0.0) {
        return None;
    }
    let sign = g0.signum();
    let (_, b) = illinois(
        stepper,
        d,
        s,
        sign,
        (span.t0, sign * g0),
        (span.t1, sign * g1),
        0.0,
    );
    (b > span.t0 + 10.0 * EVENT_TIME_TOLERANCE * (1.0 + span.t0.abs())).then_some(b)
}

/// The largest g_s in the step and its time, by golden-section search (g unimodal there).
fn highest<S: Stepper>(stepper: &mut S, d: &mut Dynamics, s: usize, span: Span) -> (f64, f64) {
    extremum(stepper, d, s, span, 1.0)
}

/// The largest `sign` g_s in the step (golden-section search, g unimodal there) and its time
/// and g.
fn extremum<S: Stepper>(
    stepper: &mut S,
    d: &mut Dynamics,
    s: usize,
    span: Span,
    sign: f64,
) -> (f64, f64) {
    let r = 0.5 * (5f64.sqrt() - 1.0);
    let (mut a, mut b) = (span.t0, span.t1);
    let mut x1 = b - r * (b - a);
    let mut x2 = a + r * (b - a);
    let mut f = |t: f64| sign * gap_at(stepper, d, s, t);
    let (mut f1, mut f2) = (f(x1), f(x2));
    for _ in 0..MAX_LOCATE {
        if b - a <= EVENT_TIME_TOLERANCE * (1.0 + b.abs()) {
            break;
        }
        if f1 < f2 {
            (a, x1, f1) = (x1, x2, f2);
            x2 = a + r * (b - a);
            f2 = f(x2);
        } else {
            (b, x2, f2) = (x2, x1, f1);
            x1 = b - r * (b - a);
            f1 = f(x1);
        }
    }
    if f1 > f2 {
        (x1, sign * f1)
    } else {
        (x2, sign * f2)
    }
}

/// The sign change of λ_s (≤ 0 at a, > 0 at b) by bisection.
fn locate_release<S: Stepper>(
    stepper: &mut S,
    d: &mut Dynamics,
    s: usize,
    span: Span,
) -> Result<f64, DynamicsError> {
    let (mut a, mut b) = (span.t0, span.t1);
    for _ in 0..MAX_LOCATE {
        if b - a <= EVENT_TIME_TOLERANCE * (1.0 + b.abs()) {
            break;
        }
        let tm = 0.5 * (a + b);
        if multiplier_at(stepper, d, s, tm)? > 0.0 {
            b = tm;
        } else {
            a = tm;
        }
    }
    Ok(b)
}

/// The first event in the accepted step `span`, if any.
///
/// # Errors
/// The solves of the multipliers.
pub(crate) fn first_event<S: Stepper>(
    stepper: &mut S,
    d: &mut Dynamics,
    span: Span,
) -> Result<Option<Event>, DynamicsError> {
    let mut first: Option<Event> = None;
    let take = |e: Event, first: &mut Option<Event>| {
        if first.is_none_or(|f| e.time < f.time) {
            *first = Some(e);
        }
    };
    for k in 0..d.contacts.watched.len() {
        let s = d.contacts.watched[k];
        if d.contacts.held[s] {
            continue;
        }
        let g1 = gap_at(stepper, d, s, span.t1);
        let closing = if g1 < 0.0 {
            Some(locate_closing(stepper, d, s, span))
        } else {
            grazed(stepper, d, s, span, g1)
        };
        if let Some(time) = closing {
            take(
                Event {
                    time,
                    action: Action::Impact(s),
                },
                &mut first,
            );
        }
    }
    for k in 0..d.contacts.compliant.len() {
        let s = d.contacts.compliant[k];
        if let Some(time) = contact_kink(stepper, d, s, span) {
            take(
                Event {
                    time,
                    action: Action::Kink,
                },
                &mut first,
            );
        }
    }
    if let Some(time) = super::onsets::first_onset(stepper, d, span) {
        take(
            Event {
                time,
                action: Action::Onset,
            },
            &mut first,
        );
    }
    if !d.contacts.any_held() {
        return Ok(first);
    }
    let mut off = false;
    for s in 0..d.contacts.held.len() {
        if !d.contacts.held[s] {
            continue;
        }
        if multiplier_at(stepper, d, s, span.t1)? > 0.0 {
            let time = locate_release(stepper, d, s, span)?;
            take(
                Event {
                    time,
                    action: Action::Release(s),
                },
                &mut first,
            );
        } else {
            off |= gap_at(stepper, d, s, span.t1).abs() > HOLD_TOLERANCE * scale(d, s);
        }
    }
    if off && first.is_none() {
        first = Some(Event {
            time: span.t1,
            action: Action::Hold,
        });
    }
    Ok(first)
}

/// Applies `event` to `state` (the dense output at its time, projected onto the joints): an
/// impact's velocity jump, a release, or the hold of the closed stops. Records the impact or
/// release.
///
/// # Errors
/// The projections' and the impulse solve's failures.
pub(crate) fn apply(
    d: &mut Dynamics,
    event: Event,
    state: &mut State,
    tol: f64,
) -> Result<(), DynamicsError> {
    d.project_positions(state, tol)?;
    d.project_velocities(state)?;
    match event.action {
        Action::Impact(s) => {
            d.impact(state, s)?;
        }
        Action::Release(s) => {
            d.contacts.held[s] = false;
            let st = &d.model.stops()[s];
            d.contacts
                .events
                .push(crate::contacts::events::ImpactEvent {
                    time: event.time,
                    stop: st.name.clone(),
                    limit: st.limit,
                    impact_velocity: 0.0,
                    impulse: 0.0,
                    rebound_velocity: 0.0,
                    held: false,
                    release: true,
                    energy_change: 0.0,
                });
        }
        Action::Onset => super::onsets::apply_onset(d, state),
        Action::Hold | Action::Kink => {}
    }
    if d.contacts.any_held() {
        d.hold_stops(state, tol)?;
    }
    Ok(())
}
