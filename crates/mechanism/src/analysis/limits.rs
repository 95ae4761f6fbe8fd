//! Limits in kinematic runs: a prescribed motion may not drive a joint coordinate past a
//! limit. After each grid step the stops' gaps g are checked at the solved pose; where one is
//! negative (beyond the scaled tolerance), the crossing g(t*) = 0 is located inside the step by
//! the Illinois variant of regula falsi on the position solutions at trial times (each solved
//! from the last pose on the open side), and the run stops there with
//! [`AnalysisError::LimitReached`] naming the limit, the joint, the time and the value. The
//! assembled pose at t0 is checked the same way (the crossing is then t0 itself). Nothing is
//! evaluated for a model without limits.

use crate::error::AnalysisError;
use crate::model::Model;
use crate::workspace::Workspace;

/// A gap below −`GAP_TOLERANCE` × scale (1 rad, or the model's length) is a crossing: the
/// position solve's own accuracy is far below it.
pub const GAP_TOLERANCE: f64 = 1e-9;

/// The crossing is located to this relative time (or until the gap is within round-off).
pub const CROSSING_TIME_TOLERANCE: f64 = 1e-12;

/// At most this many trial solves locate a crossing.
const MAX_LOCATE: usize = 100;

impl Model {
    /// The stop most beyond its bound at the workspace's pose (scaled gap below
    /// −[`GAP_TOLERANCE`]), if any.
    pub(crate) fn closed_stop(&self, ws: &Workspace) -> Option<usize> {
        let mut worst: Option<(usize, f64)> = None;
        for s in 0..self.stops.len() {
            let g = self.stop_gap(s, &ws.pose.bodies, &ws.pose.turns) / self.stop_scale(s);
            if g < -GAP_TOLERANCE && worst.is_none_or(|(_, w)| g < w) {
                worst = Some((s, g));
            }
        }
        worst.map(|(s, _)| s)
    }

    /// Keeps the accepted frame as the start of the next grid step (no allocation).
    pub(crate) fn save_stop_frame(&self, ws: &mut Workspace) {
        if self.stops.is_empty() {
            return;
        }
        ws.stop_frame.t = ws.pose.t;
        ws.stop_frame.x.copy_from_slice(&ws.pose.x);
        ws.stop_frame.turns.copy_from_slice(&ws.pose.turns);
    }

    /// After the position solve of a grid step to `t` (or the assembly at t0, `first`): `Ok`
    /// while every stop is open, else the located crossing as
    /// [`AnalysisError::LimitReached`]. The workspace is left at the crossing.
    pub(crate) fn check_stops(
        &self,
        ws: &mut Workspace,
        t: f64,
        first: bool,
    ) -> Result<(), AnalysisError> {
        if self.stops.is_empty() {
            return Ok(());
        }
        let Some(s) = self.closed_stop(ws) else {
            return Ok(());
        };
        let time = if first {
            t
        } else {
            self.locate_crossing(ws, s, t)
        };
        let st = &self.stops[s];
        let limit = &self.limits[st.limit];
        let row = self.stop_row(s, &ws.pose.turns);
        Err(AnalysisError::LimitReached {
            limit: limit.name.clone(),
            joint: self.joints[limit.joint].name.clone(),
            coordinate: limit.coordinate,
            bound_name: row.bound.name(),
            bound: row.value,
            time,
            value: self.stop_coordinate(s, &ws.pose.bodies, &ws.pose.turns),
            partial: None,
        })
    }

    /// The time of g_s = 0 in [start of the step, `t1`] by the Illinois method on the solved
    /// poses (the gap is positive at the start and negative at `t1`).
    fn locate_crossing(&self, ws: &mut Workspace, s: usize, t1: f64) -> f64 {
        let scale = self.stop_scale(s);
        let (mut a, mut b) = (ws.stop_frame.t, t1);
        let mut ga = self.gap_at_start(ws, s);
        let mut gb = self.stop_gap(s, &ws.pose.bodies, &ws.pose.turns);
        let mut side = 0i8;
        for _ in 0..MAX_LOCATE {
            if (b - a).abs() <= CROSSING_TIME_TOLERANCE * (1.0 + b.abs()) {
                break;
            }
            let mut tm = (a * gb - b * ga) / (gb - ga);
            if !(tm > a && tm < b) {
                tm = 0.5 * (a + b);
            }
            // Each trial from the last pose on the open side.
            ws.pose.x.copy_from_slice(&ws.stop_frame.x);
            ws.pose.turns.copy_from_slice(&ws.stop_frame.turns);
            ws.sync_poses();
            if self.position(ws, tm).is_err() {
                break;
            }
            let g = self.stop_gap(s, &ws.pose.bodies, &ws.pose.turns);
            if g.abs() <= 1e-15 * scale {
                return tm;
            }
            if g > 0.0 {
                (a, ga) = (tm, g);
                self.save_stop_frame(ws);
                if side == 1 {
                    gb *= 0.5;
                }
                side = 1;
            } else {
                (b, gb) = (tm, g);
                if side == -1 {
                    ga *= 0.5;
                }
                side = -1;
            }
        }
        0.5 * (a + b)
    }

    fn gap_at_start(&self, ws: &mut Workspace, s: usize) -> f64 {
        let (bodies, turns) = (&mut ws.pose.bodies, &ws.stop_frame.turns);
        for (k, b) in bodies.iter_mut().enumerate() {
            let x = &ws.stop_frame.x[7 * k..7 * k + 7];
            *b = cardan_constraints::BodyState::at(
                nalgebra::Vector3::new(x[0], x[1], x[2]),
                nalgebra::Vector4::new(x[3], x[4], x[5], x[6]),
            );
        }
        let g = self.stop_gap(s, bodies, turns);
        ws.sync_poses();
        g
    }
}
