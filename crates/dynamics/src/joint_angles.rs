//! Joint angles continued over turns along a dynamic run's accepted steps, for the joint
//! coordinates of its output times.
//!
//! A joint's angle is measured as a principal value, atan2(…) ∈ (−π, π]; the results give it
//! continued over turns. Between two output times a joint may turn by many revolutions, and
//! the rates at the two ends do not say how many (a swinging or tumbling body). The
//! integrator's steps are short enough that a joint turns by less than π in one (the same
//! assumption the couplers' and the rotational springs' continued angles make, see
//! [`crate::Dynamics`]'s `accept_turns`), so each angle is continued from step to step here
//! ([`JointAngles::accept`]) and an output time takes the value nearest to the last accepted
//! one ([`JointAngles::continued`]). Kept only while a run records joint coordinates.

use cardan_constraints::joints::{unwrap_angle, CoordinateQuantity, MAX_COORDINATES};
use cardan_constraints::{BodyPair, BodyState};
use cardan_mechanism::{BodyId, Model};

/// Each joint's coordinates at the last accepted step, its angles continued over turns.
#[derive(Debug)]
pub(crate) struct JointAngles {
    /// One entry per joint (allocated with the dynamics: a run allocates nothing here).
    values: Vec<[f64; MAX_COORDINATES]>,
    /// Whether a run tracks the angles.
    on: bool,
    /// Whether `values` holds an accepted step.
    accepted: bool,
}

impl JointAngles {
    /// Room for the model's joints, tracking nothing yet.
    pub(crate) fn new(model: &Model) -> Self {
        Self {
            values: vec![[0.0; MAX_COORDINATES]; model.joints().len()],
            on: false,
            accepted: false,
        }
    }

    /// Tracks the joint angles from the next accepted step on (`on`), or stops.
    pub(crate) fn start(&mut self, on: bool) {
        self.on = on && !self.values.is_empty();
        self.accepted = false;
    }

    /// Continues each tracked angle to the accepted poses `bodies`. No allocation.
    pub(crate) fn accept(&mut self, model: &Model, bodies: &[BodyState]) {
        if !self.on {
            return;
        }
        let g = BodyState::ground();
        let st = |id: BodyId| match id {
            BodyId::Ground => &g,
            BodyId::Moving(k) => &bodies[k],
        };
        for (j, last) in model.joints().iter().zip(&mut self.values) {
            let c = j
                .joint
                .coordinates(&BodyPair::new(st(j.body_i), st(j.body_j)));
            for (i, coord) in c.coordinates.iter().enumerate() {
                last[i] = match coord.measure.quantity() {
                    CoordinateQuantity::Angle if self.accepted => {
                        unwrap_angle(last[i], c.values[i])
                    }
                    _ => c.values[i],
                };
            }
        }
        self.accepted = true;
    }

    /// Coordinate `i` of joint `joint`, an angle of principal value `principal`, continued
    /// from the last accepted step; `None` when no step is tracked.
    pub(crate) fn continued(&self, joint: usize, i: usize, principal: f64) -> Option<f64> {
        (self.on && self.accepted).then(|| unwrap_angle(self.values[joint][i], principal))
    }
}
