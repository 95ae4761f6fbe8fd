//! Dragging: move a point of one body toward a target, every other body following by least
//! change, as FreeCAD's Assembly workbench does when a user drags a part (OndselSolver's
//! `PosICDragNewtonRaphson`).
//!
//! A drag step is the least-change problem of [`crate::analysis::least_change`] with q_old the
//! current poses and one more term, the dragged point's distance to the target,
//!
//! ```text
//!   min ½ (q − q_old)ᵀ W (q − q_old) + ½ w_d ‖r_b + A_b s' − target‖²   subject to   Φ = 0,
//! ```
//!
//! with OndselSolver's drag weights: 1e3 on every coordinate (each component of r in the model's
//! length unit, each Euler parameter) and w_d = 1e6 on the dragged point (OndselSolver puts it
//! on the dragged part's frame origin; a point of the part is the same when it is the origin).
//! The dragged point goes as close to the target as the joints and drivers allow, the rest
//! moves as little as it can; where the rest must move for the point to follow, the point
//! stays behind the target by about 1e3/1e6 of that motion (the soft pull of FreeCAD's drag: a
//! further step toward the same target closes most of what is left).
//!
//! # Stops
//! Joint limits hold during a drag: a step whose pose leaves a stop's range is cut back. The
//! target is moved back along the segment from the dragged point's start to the target
//! (fraction s ∈ [0, 1]) and s is bisected to the largest value whose pose keeps every stop
//! closed-or-open (gap ≥ 0): the mechanism stops at the stop, the dragged point as far along
//! as the stop lets it go. A step that does not converge (a target the mechanism cannot follow
//! in one step, through a singular pose) is cut back the same way, as OndselSolver retries a
//! drag step with the target moved back. [`DragReport`] says how far the step got and why.

use crate::analysis::least_change::{BodyWeights, LeastChange, PointGoal};
use crate::error::AnalysisError;
use crate::model::{BodyId, Model};
use crate::workspace::Workspace;
use nalgebra::Vector3;

/// Bisection steps on the fraction of a drag step that is cut back: 2⁻⁴⁰ of the step.
pub const DRAG_BISECTIONS: usize = 40;

/// OndselSolver's drag weights: the least (every coordinate) and the dragged body's
/// translation.
pub const DRAG_WEIGHTS: (f64, f64) = (1e3, 1e6);

/// Why a drag step ended short of its target.
#[derive(Debug, Clone, PartialEq)]
pub enum DragStop {
    /// The target was reached as closely as the joints and drivers allow.
    None,
    /// A stop: the limit's name.
    Limit(String),
    /// The least-change solve did not converge beyond the fraction reached (a target the
    /// mechanism cannot follow in one step).
    NotConverged,
}

/// Outcome of one drag step.
#[derive(Debug, Clone, PartialEq)]
pub struct DragReport {
    /// The fraction of the step taken (1: all of it).
    pub reached: f64,
    /// Why less than all of it.
    pub stop: DragStop,
    /// Distance from the dragged point to the target after the step (m).
    pub distance: f64,
    /// Least-change iterations of the accepted solve.
    pub iterations: usize,
}

/// A drag of one point of one body (module docs): the solver, sized once.
#[derive(Debug)]
pub struct Drag {
    solver: LeastChange,
    body: usize,
    point: Vector3<f64>,
    /// The weight of the dragged point's distance to its goal (1/m²).
    weight: f64,
    start: Vec<f64>,
    best: Vec<f64>,
    turns: Vec<[f64; 2]>,
}

impl Drag {
    /// A drag of the point `point` (body-frame coordinates, m) of moving body `body`;
    /// `metres_per_unit` is the length unit the weights are counted in (1 for SI, 0.001 for a
    /// FreeCAD file in millimetres). Allocates.
    ///
    /// # Errors
    /// [`AnalysisError::Options`] for an unknown body, the ground or a unit that is not positive.
    pub fn new(
        model: &Model,
        body: &str,
        point: Vector3<f64>,
        metres_per_unit: f64,
    ) -> Result<Self, AnalysisError> {
        let bad = |m: String| AnalysisError::Options(format!("drag: {m}"));
        if model.num_extra() > 0 {
            return Err(bad(
                "a model with point-on-curve elements cannot be dragged yet (their curve parameters have no least-change weight)".into(),
            ));
        }
        let k = match model.body_id(body) {
            Some(BodyId::Moving(k)) => k,
            Some(BodyId::Ground) => return Err(bad("the ground cannot be dragged".into())),
            None => return Err(bad(format!("no body \"{body}\""))),
        };
        if !(metres_per_unit > 0.0 && metres_per_unit.is_finite()) {
            return Err(bad(format!(
                "the length unit must be positive, got {metres_per_unit} m"
            )));
        }
        if !point.iter().all(|c| c.is_finite()) {
            return Err(bad("the dragged point must be finite".into()));
        }
        let (least, most) = DRAG_WEIGHTS;
        let u2 = metres_per_unit * metres_per_unit;
        let weights = (0..model.num_bodies())
            .map(|_| BodyWeights {
                translation: least / u2,
                rotation: [least; 4],
            })
            .collect();

        let solver =
            LeastChange::new(model, weights).map_err(|e| model.map_solver_error(0.0, e))?;
        let n = 7 * model.num_bodies();
        Ok(Self {
            solver,
            body: k,
            point,
            weight: most / u2,
            start: vec![0.0; n],
            best: vec![0.0; n],
            turns: model.initial_turns(),
        })
    }

    /// The dragged point's position at the workspace's poses.
    pub fn point_position(&self, ws: &Workspace) -> Vector3<f64> {
        ws.r(self.body) + cardan_eulerparam::a(&ws.p(self.body)) * self.point
    }

    /// One drag step at time `t` (the drivers' time): the workspace's poses move toward
    /// `target` (the dragged point's goal, m) by least change, cut back at a stop or where the
    /// solve fails (module docs). The workspace must hold an assembled pose; on return it holds
    /// the accepted one. No allocation.
    ///
    /// # Errors
    /// [`AnalysisError::Options`] for a target that is not finite; the solve's error when not
    /// even the smallest cut-back step converges.
    pub fn step(
        &mut self,
        model: &Model,
        ws: &mut Workspace,
        t: f64,
        target: Vector3<f64>,
    ) -> Result<DragReport, AnalysisError> {
        if !target.iter().all(|c| c.is_finite()) {
            return Err(AnalysisError::Options(
                "drag: the target must be finite".into(),
            ));
        }
        self.start.copy_from_slice(&ws.pose.x);
        self.turns.copy_from_slice(&ws.pose.turns);
        let from = self.point_position(ws);
        let mut report = match self.attempt(model, ws, t, from, target, 1.0) {
            Ok(iterations) => DragReport {
                reached: 1.0,
                stop: DragStop::None,
                distance: 0.0,
                iterations,
            },
            Err(first) => self.cut_back(model, ws, t, from, target, first)?,
        };
        model.accept_turns(&ws.pose.bodies, &mut ws.pose.turns);
        ws.invalidate();
        report.distance = (self.point_position(ws) - target).norm();
        Ok(report)
    }

    /// Follows the pointer to `target`: [`Self::step`], repeated from where it got while a step
    /// is cut back because the solve could not follow all of it ([`DragStop::NotConverged`])
    /// and still gets further, at most `max_steps` steps; the last step's report. A long step
    /// can need that where the dragged point's path curves through the constraints (a point
    /// near a hinge pulled far away): the least-change iteration leaves out the constraints'
    /// curvature (`least_change`, "The iteration"), which the reaction of a far goal makes
    /// large. No allocation.
    ///
    /// # Errors
    /// As [`Self::step`].
    pub fn follow(
        &mut self,
        model: &Model,
        ws: &mut Workspace,
        t: f64,
        target: Vector3<f64>,
        max_steps: usize,
    ) -> Result<DragReport, AnalysisError> {
        let mut report = self.step(model, ws, t, target)?;
        for _ in 1..max_steps {
            if report.stop != DragStop::NotConverged || report.reached <= 1e-6 {
                break;
            }
            report = self.step(model, ws, t, target)?;
        }
        Ok(report)
    }

    /// Bisects the fraction of the step to the largest that passes ([`Self::attempt`]), leaving
    /// its pose in the workspace; `first` is why the whole step failed.
    fn cut_back(
        &mut self,
        model: &Model,
        ws: &mut Workspace,
        t: f64,
        from: Vector3<f64>,
        target: Vector3<f64>,
        first: Attempt,
    ) -> Result<DragReport, AnalysisError> {
        let (mut lo, mut hi) = (0.0, 1.0);
        let mut why = first;
        let mut iterations = 0;
        self.best.copy_from_slice(&self.start);
        for _ in 0..DRAG_BISECTIONS {
            let s = 0.5 * (lo + hi);
            match self.attempt(model, ws, t, from, target, s) {
                Ok(it) => {
                    lo = s;
                    iterations = it;
                    self.best.copy_from_slice(&ws.pose.x);
                }
                Err(e) => {
                    hi = s;
                    why = e;
                }
            }
        }
        ws.pose.x.copy_from_slice(&self.best);
        ws.pose.turns.copy_from_slice(&self.turns);
        ws.sync_poses();
        if lo == 0.0 {
            if let Attempt::Failed(e) = why {
                return Err(e);
            }
        }
        Ok(DragReport {
            reached: lo,
            stop: match why {
                Attempt::Stop(s) => {
                    DragStop::Limit(model.limits()[model.stops()[s].limit].name.clone())
                }
                Attempt::Failed(_) => DragStop::NotConverged,
            },
            distance: 0.0,
            iterations,
        })
    }

    /// The least change from the step's start with the dragged point's goal a fraction `s` of
    /// the way to `target`; `Err` when it does not converge or leaves a stop's range.
    fn attempt(
        &mut self,
        model: &Model,
        ws: &mut Workspace,
        t: f64,
        from: Vector3<f64>,
        target: Vector3<f64>,
        s: f64,
    ) -> Result<usize, Attempt> {
        ws.pose.x.copy_from_slice(&self.start);
        ws.pose.turns.copy_from_slice(&self.turns);
        ws.sync_poses();
        self.solver.old.copy_from_slice(&self.start);
        self.solver.goal = Some(PointGoal {
            body: self.body,
            point: self.point,
            target: from + s * (target - from),
            weight: self.weight,
        });
        let rep = self
            .solver
            .solve(model, ws, t, 1e-12)
            .map_err(Attempt::Failed)?;
        match model.closed_stop(ws) {
            Some(stop) => Err(Attempt::Stop(stop)),
            None => Ok(rep.iterations),
        }
    }
}

/// Why an attempt failed.
#[derive(Debug)]
enum Attempt {
    Stop(usize),
    Failed(AnalysisError),
}
