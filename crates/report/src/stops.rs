//! End stops in the report: where each stop is drawn, when it is active, and the impacts.
//!
//! A [`StopMarker`] is one end stop of a joint (`limit.lower` or `limit.upper`), drawn by the
//! page as a red ring about the joint's axis at the joint's location on the body its part is
//! drawn on (body i, or body j when i is the ground), shown only in frames where the stop is
//! active. Frame k of [`crate::Scene::times`] stands for the interval (t_{k−1}, t_k] (frame 0:
//! up to t_0), so that a contact between two frames is not lost: the stop is active in frame k
//! if it was held closed or pressed (a nonzero force, a compliant stop in contact) at any output
//! time of that interval, or took an impact in it. The page shows, at a time t between two
//! frames, the later frame's state, so an impact shows at its own time. The force is the stop's
//! force along the joint coordinate at t_k, in the unit [`StopMarker::unit`].
//!
//! A [`StopEvent`] is an impact (or a release) at its own time, a tick on the page's timeline.
//!
//! The crate knows nothing of mechanics: `cardan-model` fills these from a run's stop history
//! and events. A page without stops holds none of this, and its text is that of a page written
//! before stops were drawn (`html.rs`).

use crate::scene::Scene;
use crate::Error;

/// One end stop: its joint's place and its state per frame.
#[derive(Debug, Clone, PartialEq)]
pub struct StopMarker {
    /// The stop's name (`limit.lower`, `limit.upper`).
    pub name: String,
    /// The joint it limits.
    pub joint: String,
    /// The body the marker moves with (index into [`Scene::bodies`]).
    pub body: usize,
    /// The joint's point on that body, body coordinates \[m\].
    pub point: [f64; 3],
    /// The joint's axis (the ring's axis), body coordinates; need not be unit.
    pub direction: [f64; 3],
    /// Per frame of [`Scene::times`]: held closed, pressed or struck in the frame's interval.
    pub active: Vec<bool>,
    /// Per frame: the stop's force along the joint coordinate at the frame's time.
    pub force: Vec<f64>,
    /// The force's unit (`N`, `N m`, `N mm`).
    pub unit: String,
}

/// What happened at a stop at one time.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum StopEventKind {
    /// An impact the stop rebounds from.
    Impact,
    /// An impact after which the stop is held closed.
    ImpactHeld,
    /// A held stop opened.
    Release,
}

impl StopEventKind {
    /// The name used in `events.csv` and the page.
    pub fn name(self) -> &'static str {
        match self {
            Self::Impact => "impact",
            Self::ImpactHeld => "impact_held",
            Self::Release => "release",
        }
    }
}

/// One impact or release, a tick on the timeline.
#[derive(Debug, Clone, PartialEq)]
pub struct StopEvent {
    /// Its time \[s\].
    pub time: f64,
    /// The stop (index into the page's stops).
    pub stop: usize,
    /// Impact or release.
    pub kind: StopEventKind,
}

/// Checks that the stops fit `scene`: a state and a force per frame, finite numbers, markers
/// on existing bodies, events on existing stops at finite times.
///
/// # Errors
/// [`Error::Scene`] naming the stop.
pub fn validate_stops(
    scene: &Scene,
    stops: &[StopMarker],
    events: &[StopEvent],
) -> Result<(), Error> {
    let bad = |m: String| Err(Error::Scene(m));
    let frames = scene.times.len();
    for s in stops {
        if s.body >= scene.bodies.len() {
            return bad(format!("stop \"{}\" names no body", s.name));
        }
        if s.active.len() != frames || s.force.len() != frames {
            return bad(format!(
                "stop \"{}\": {} states and {} forces for {frames} output times",
                s.name,
                s.active.len(),
                s.force.len()
            ));
        }
        let finite = |v: &[f64]| v.iter().all(|x| x.is_finite());
        if !finite(&s.point) || !finite(&s.direction) || !finite(&s.force) {
            return bad(format!("stop \"{}\": a number is not finite", s.name));
        }
    }
    if let Some(e) = events
        .iter()
        .find(|e| e.stop >= stops.len() || !e.time.is_finite())
    {
        return bad(format!(
            "a stop event at t = {} s names stop number {} of {}",
            e.time,
            e.stop,
            stops.len()
        ));
    }
    Ok(())
}

/// The page's data of the stops: per stop its name, joint, body, point, axis, unit, the
/// frames it is active in (as 0/1) and its force per frame; the events as
/// `[time, stop, kind]`.
pub(crate) fn stops_json(stops: &[StopMarker], events: &[StopEvent]) -> serde_json::Value {
    serde_json::json!({
        "list": stops.iter().map(|s| serde_json::json!({
            "name": s.name,
            "joint": s.joint,
            "body": s.body,
            "point": s.point,
            "direction": s.direction,
            "unit": s.unit,
            "active": s.active.iter().map(|&a| u8::from(a)).collect::<Vec<_>>(),
            "force": s.force,
        })).collect::<Vec<_>>(),
        "events": events.iter().map(|e| serde_json::json!([e.time, e.stop, e.kind.name()]))
            .collect::<Vec<_>>(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::Body;

    fn scene() -> Scene {
        Scene {
            name: "s".into(),
            times: vec![0.0, 0.1, 0.2],
            bodies: vec![Body {
                name: "rod".into(),
                colour: [0.5; 3],
                geometry: Vec::new(),
                points: Vec::new(),
                positions: vec![[0.0; 3]; 3],
                rotations: vec![[1.0, 0.0, 0.0, 0.0]; 3],
            }],
            axes: Vec::new(),
            extent: 1.0,
        }
    }

    fn stop() -> StopMarker {
        StopMarker {
            name: "stop.lower".into(),
            joint: "hinge".into(),
            body: 0,
            point: [-0.5, 0.0, 0.0],
            direction: [0.0, 0.0, 1.0],
            active: vec![false, true, true],
            force: vec![0.0, 0.0, 4.2],
            unit: "N m".into(),
        }
    }

    #[test]
    fn stops_that_do_not_fit_the_scene_are_refused_by_name() {
        let event = |stop| StopEvent {
            time: 0.05,
            stop,
            kind: StopEventKind::Impact,
        };
        assert!(validate_stops(&scene(), &[stop()], &[event(0)]).is_ok());
        let mut short = stop();
        short.active.pop();
        let e = validate_stops(&scene(), &[short], &[]).unwrap_err();
        assert!(
            e.to_string().contains("stop \"stop.lower\": 2 states"),
            "{e}"
        );
        let mut off = stop();
        off.body = 1;
        assert!(validate_stops(&scene(), &[off], &[]).is_err());
        assert!(validate_stops(&scene(), &[stop()], &[event(1)]).is_err());
    }

    #[test]
    fn the_page_data_lists_states_as_numbers_and_events_by_kind() {
        let events = [StopEvent {
            time: 0.05,
            stop: 0,
            kind: StopEventKind::ImpactHeld,
        }];
        let j = stops_json(&[stop()], &events);
        assert_eq!(j["list"][0]["active"], serde_json::json!([0, 1, 1]));
        assert_eq!(j["list"][0]["joint"], "hinge");
        assert_eq!(j["events"][0], serde_json::json!([0.05, 0, "impact_held"]));
    }
}
