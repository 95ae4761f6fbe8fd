//! Dragging a body in the live preview: the page picks a point of a body (Ctrl- or Alt-drag in
//! the 3D view) at the time it shows, and each move of the pointer is one drag step of
//! [`cardan_mechanism::Drag`] (FreeCAD's interaction: the point pulled toward the pointer,
//! every other body following by least change, the drivers held at that time, a step cut back
//! at an end stop). The steps start from the run's pose at the output time nearest the page's
//! and go on from each other's poses; the page shows them until its time moves.
//!
//! A fully driven model does not move (its drivers hold every body): the page says how far the
//! point stayed from the pointer. Dragging is meant for the under-driven models a drag
//! explores (a dynamic run's free mechanism, a kinematic run with `free_dof = "hold"`).

use cardan_mechanism::nalgebra::Vector3;
use cardan_mechanism::{Drag, DragReport, DragStop, Results, Workspace};
use cardan_model::prepare::{analysis_error, Prepared};
use std::sync::Arc;

/// Most drag steps toward one pointer position ([`Drag::follow`]).
const MAX_STEPS: usize = 16;

/// A solve's model and its results, kept for dragging.
pub struct Snapshot {
    /// The model as it was solved.
    pub prepared: Prepared,
    /// Its run's results: the output times and every moving body's poses at them.
    pub results: Results,
}

impl std::fmt::Debug for Snapshot {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Snapshot")
            .field("file", &self.prepared.file)
            .field("times", &self.results.times.len())
            .finish_non_exhaustive()
    }
}

impl Snapshot {
    /// The index of the output time nearest `t`.
    fn frame(&self, t: f64) -> usize {
        let times = &self.results.times;
        let k = times.partition_point(|x| *x < t);
        match k {
            0 => 0,
            k if k >= times.len() => times.len().saturating_sub(1),
            k if t - times[k - 1] <= times[k] - t => k - 1,
            k => k,
        }
    }
}

/// A drag in progress: the solver sized for the dragged point and the current poses.
#[derive(Debug)]
pub struct Session {
    /// The version of the solve it drags (a new solve ends it).
    pub version: u64,
    snapshot: Arc<Snapshot>,
    drag: Drag,
    ws: Workspace,
    t: f64,
    body: String,
}

/// What a drag step gives the page.
#[derive(Debug, Clone, PartialEq)]
pub struct Stepped {
    /// Per moving body: x, y, z (m), e0, e1, e2, e3.
    pub poses: Vec<[f64; 7]>,
    /// How far the step got.
    pub report: DragReport,
}

impl Session {
    /// Starts dragging the point `point` (world coordinates, m) of `body` at time `t` of the
    /// solve `version` whose model is `snapshot`.
    ///
    /// # Errors
    /// The body cannot be dragged (the ground, no such body, a model with curves), the point or
    /// time is not finite, the run has no poses.
    pub fn start(
        snapshot: Arc<Snapshot>,
        version: u64,
        body: &str,
        point: [f64; 3],
        t: f64,
    ) -> Result<Self, String> {
        let p = &snapshot.prepared;
        let model = &p.model;
        if !(t.is_finite() && point.iter().all(|x| x.is_finite())) {
            return Err("drag: the point and the time must be finite".into());
        }
        let results = &snapshot.results;
        if results.times.is_empty() || results.bodies.len() != model.num_bodies() {
            return Err("drag: the run has no poses to start from".into());
        }
        let k = snapshot.frame(t);
        let mut ws = model.workspace();
        for (b, body) in results.bodies.iter().enumerate() {
            let (Some(r), Some(q)) = (body.r.get(k), body.p.get(k)) else {
                return Err("drag: the run has no poses to start from".into());
            };
            ws.set_pose(b, *r, *q);
        }
        let t = results.times[k];
        ws.set_time(t);
        let local = match model.body_id(body) {
            Some(cardan_mechanism::BodyId::Moving(b)) => {
                cardan_eulerparam::a(&ws.p(b)).transpose() * (Vector3::from(point) - ws.r(b))
            }
            _ => Vector3::zeros(),
        };
        let (_, per_metre) = p.units.unit("m");
        let drag = Drag::new(model, body, local, 1.0 / per_metre)
            .map_err(|e| analysis_error(p, &e).to_string())?;
        Ok(Self {
            version,
            snapshot: snapshot.clone(),
            drag,
            ws,
            t,
            body: body.to_string(),
        })
    }

    /// The dragged body's name.
    pub fn body(&self) -> &str {
        &self.body
    }

    /// The model's units (the page's words give lengths in them).
    pub fn units(&self) -> cardan_model::units::UnitSystem {
        self.snapshot.prepared.units
    }

    /// One drag step toward `target` (world coordinates, m).
    ///
    /// # Errors
    /// The target is not finite; not even the smallest cut-back step converges (the message as
    /// `cardan run` gives a solver failure).
    pub fn step(&mut self, target: [f64; 3]) -> Result<Stepped, String> {
        let p = &self.snapshot.prepared;
        let report = self
            .drag
            .follow(
                &p.model,
                &mut self.ws,
                self.t,
                Vector3::from(target),
                MAX_STEPS,
            )
            .map_err(|e| analysis_error(p, &e).to_string())?;
        let poses = (0..p.model.num_bodies())
            .map(|b| {
                let (r, q) = (self.ws.r(b), self.ws.p(b));
                [r.x, r.y, r.z, q[0], q[1], q[2], q[3]]
            })
            .collect();
        Ok(Stepped { poses, report })
    }
}

/// The page's words for how far a step got.
pub fn describe(body: &str, s: &Stepped, per_metre: f64, unit: &str) -> String {
    let away = s.report.distance * per_metre;
    let why = match &s.report.stop {
        DragStop::None => String::new(),
        DragStop::Limit(name) => format!("; stopped by the end stop \"{name}\""),
        DragStop::NotConverged => {
            "; the mechanism cannot follow the pointer further in one step".into()
        }
    };
    format!(
        "dragging {body}: {:.0} % of the step, {away:.3e} {unit} from the pointer{why}",
        100.0 * s.report.reached
    )
}
