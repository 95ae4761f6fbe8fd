//! The stops of a model's limits at body states: the gap g ≥ 0 of each, its rate, its row as a
//! [`JointLimit`] continued over turns from the references kept after the couplers' in a
//! workspace's (or a run's) `turns` ([`Model::initial_turns`]). No allocation.

use super::elements::{LimitInfo, StopInfo};
use super::Model;
use cardan_constraints::{BodyPair, BodyState, JointLimit};

impl Model {
    /// The limits on joint coordinates.
    pub fn limits(&self) -> &[LimitInfo] {
        &self.limits
    }

    /// The stops (one per bound of each limit, in limit order, lower first).
    pub fn stops(&self) -> &[StopInfo] {
        &self.stops
    }

    /// Stop `s`'s row continued from its reference in `turns` (a run's turns: the couplers'
    /// first, then one per stop).
    pub fn stop_row(&self, s: usize, turns: &[[f64; 2]]) -> JointLimit {
        let st = &self.stops[s];
        st.row.with_reference(turns[self.couplers.len() + s][0])
    }

    /// The body pair of stop `s` at `bodies` (`g` the ground's state).
    pub fn stop_pair<'a>(
        &self,
        s: usize,
        bodies: &'a [BodyState],
        g: &'a BodyState,
    ) -> BodyPair<'a> {
        let st = &self.stops[s];
        BodyPair::new(
            Self::state(bodies, g, st.body_i),
            Self::state(bodies, g, st.body_j),
        )
    }

    /// The scale of stop `s`'s gap, to which its tolerances are relative: 1 for an angle (rad),
    /// the model's characteristic length for a length.
    pub fn stop_scale(&self, s: usize) -> f64 {
        match self.stops[s].row.measure.quantity() {
            cardan_constraints::joints::CoordinateQuantity::Angle => 1.0,
            cardan_constraints::joints::CoordinateQuantity::Length => self.length,
        }
    }

    /// The gap g of stop `s` (≥ 0 inside the range; rad or m) at `bodies`.
    pub fn stop_gap(&self, s: usize, bodies: &[BodyState], turns: &[[f64; 2]]) -> f64 {
        let g = BodyState::ground();
        self.stop_row(s, turns).gap(&self.stop_pair(s, bodies, &g))
    }

    /// ġ of stop `s` from the bodies' velocities.
    pub fn stop_rate(&self, s: usize, bodies: &[BodyState], turns: &[[f64; 2]]) -> f64 {
        let g = BodyState::ground();
        let row = self.stop_row(s, turns);
        row.bound.sign() * row.rate(&self.stop_pair(s, bodies, &g))
    }

    /// The joint coordinate of stop `s` (continued over turns) at `bodies`.
    pub fn stop_coordinate(&self, s: usize, bodies: &[BodyState], turns: &[[f64; 2]]) -> f64 {
        let g = BodyState::ground();
        self.stop_row(s, turns)
            .coordinate(&self.stop_pair(s, bodies, &g))
    }

    /// Each stop's joint coordinate and gap g (≥ 0: the pose respects it) at the workspace's
    /// poses, in [`Model::stops`] order (e.g. for a front end's `check` of the drawn or the
    /// assembled pose). Allocates the list.
    pub fn stop_status(&self, ws: &crate::Workspace) -> Vec<(f64, f64)> {
        (0..self.stops.len())
            .map(|s| {
                (
                    self.stop_coordinate(s, &ws.pose.bodies, &ws.pose.turns),
                    self.stop_gap(s, &ws.pose.bodies, &ws.pose.turns),
                )
            })
            .collect()
    }

    /// The stops' references at `bodies`, continued from those in `stop_turns` (one per stop).
    pub(crate) fn accept_stop_turns(&self, bodies: &[BodyState], stop_turns: &mut [[f64; 2]]) {
        let g = BodyState::ground();
        for (s, refs) in stop_turns.iter_mut().enumerate() {
            if self.stops[s].row.measure.turns() {
                let pair = self.stop_pair(s, bodies, &g);
                refs[0] = self.stops[s].row.with_reference(refs[0]).coordinate(&pair);
            }
        }
    }
}
