//! The rows dropped as redundant, checked at the solution.
//!
//! A mechanism with redundant equations (a planar loop of spatial revolutes: 3 of its rows
//! follow from the others) is solved on the independent rows its rank analysis keeps
//! ([`Model::prepare_kinematics`]). On the constraint manifold of a *consistent* model the
//! dropped rows then hold too. A real model is often slightly inconsistent: the revolute axes
//! of a "planar" loop are not quite parallel, or its pins not quite in one plane (a CAD export
//! rounded), so no pose satisfies every equation. The rows still solve where the kept ones do,
//! but the dropped ones are left with a residual
//!
//! ```text
//!   d_r = |Φ_r(q, t)| / e_r,   r dropped,
//! ```
//!
//! in the scaled units of the convergence test (`e_r`: 1 for a dimensionless row, the model
//! size L for a length, L² for an area; [`Model::equation_scales`]), which says how far the
//! joints disagree relative to the mechanism's size.
//!
//! * **Assembly** ([`Model::assemble`]) first solves all equations at once (minimum-norm
//!   Newton). When that does not converge and the last iterate is off by at most
//!   [`LEAST_SQUARES_MAX_RESIDUAL`], it is close to the least-squares pose of an inconsistent
//!   redundant system; the rank analysis there, with its tolerance widened to
//!   [`RANK_TOLERANCE_PER_RESIDUAL`] times the residual (the inconsistency perturbs the
//!   Jacobian by about as much), finds the redundant rows, and Newton solves the kept rows
//!   exactly from there: the *least-squares-consistent pose*. Dropped rows off by more than
//!   [`gross_inconsistency`] make it an [`crate::AnalysisError::InconsistentJoints`] error that
//!   names the joints; below it the pose is accepted and the residuals are reported.
//! * **Kinematics** ([`Model::position`]) evaluates Φ at every solved frame anyway; the dropped
//!   rows' d_r are read from it (no extra factorization) and the worst per row is kept with its
//!   time ([`Model::dropped_row_residuals`]). When the dropped rows are off at the prepared pose,
//!   the kinematic Newton judges convergence on the kept rows only
//!   ([`cardan_solver::Newton::judge_kept_rows_only`]): the dropped rows cannot vanish.
//!
//! A dropped row with d_r at most the position tolerance is fine (as satisfied as the kept
//! rows); above it, the front end reports a warning naming the joint, its worst residual and the
//! time (`cardan run`'s summary and run.json).

use crate::model::Model;
pub use crate::results::DroppedRowResidual;
use crate::workspace::Workspace;
use cardan_constraints::{Constraint, Dimension};
use cardan_solver::RankOptions;

/// The rank analysis at a pose whose equations are off by a scaled residual `r` uses the
/// relative tolerance `max(1e-9, RANK_TOLERANCE_PER_RESIDUAL · r)` (at most
/// [`MAX_RANK_TOLERANCE`]): an inconsistency of `r` moves the dependent rows of a redundant
/// set apart by about `r`, so the default 1e-9 would call them independent.
pub const RANK_TOLERANCE_PER_RESIDUAL: f64 = 1e3;

/// Assembly looks for the least-squares-consistent pose only when the failed solve's last
/// iterate is off by at most this scaled residual: joints that disagree by more than 1 % of the
/// model's size are a model that cannot close (a link too short, a wrong point), reported as
/// such ([`crate::AnalysisError::AssemblyFailed`]), not a redundancy; at such a stretched pose
/// the Jacobian is singular and a widened rank test would mistake that for redundancy.
pub const LEAST_SQUARES_MAX_RESIDUAL: f64 = 1e-2;

/// The widest relative rank tolerance [`RANK_TOLERANCE_PER_RESIDUAL`] may give.
pub const MAX_RANK_TOLERANCE: f64 = 1e-3;

/// The scaled residual of a dropped row above which the joints disagree grossly (an error at
/// assembly, [`crate::AnalysisError::InconsistentJoints`]): `max(1e3 · tol, 1e-6)`, with
/// `tol` the position tolerance. 1e-6 of the model's size is far beyond what a CAD export's
/// rounding leaves.
pub fn gross_inconsistency(tol: f64) -> f64 {
    (1e3 * tol).max(1e-6)
}

/// One row's residual at one time, as [`Model::worst_dropped_rows`] takes it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DroppedRowSample {
    /// The global row.
    pub row: usize,
    /// Its scaled residual |Φ_r| / e_r.
    pub residual: f64,
    /// Its residual Φ_r (SI units).
    pub value: f64,
    /// The time (s).
    pub time: f64,
}

impl From<(usize, f64, f64, f64)> for DroppedRowSample {
    /// From (row, scaled residual, value, time), the form callers passed before the type
    /// existed.
    fn from((row, residual, value, time): (usize, f64, f64, f64)) -> Self {
        Self {
            row,
            residual,
            value,
            time,
        }
    }
}

impl Model {
    /// The largest scaled residual |Φ_r| / e_r of the first `m` equations in `phi` (unscaled).
    pub(crate) fn scaled_residual(&self, phi: &[f64], m: usize) -> f64 {
        phi[..m]
            .iter()
            .zip(&self.equation_scales)
            .map(|(v, e)| (v / e).abs())
            .fold(0.0f64, f64::max)
    }

    /// The relative rank tolerance at poses whose first `m` equations (`phi`, unscaled) are off:
    /// see [`RANK_TOLERANCE_PER_RESIDUAL`].
    pub(crate) fn rank_options_for(&self, phi: &[f64], m: usize) -> RankOptions {
        let r = self.scaled_residual(phi, m);
        let default = RankOptions::default();
        let widened = (RANK_TOLERANCE_PER_RESIDUAL * r).min(MAX_RANK_TOLERANCE);
        RankOptions {
            relative_tolerance: default.relative_tolerance.max(widened),
            ..default
        }
    }

    /// The largest scaled residual of the rows not in `kept` (a mask over all rows), from Φ in
    /// `phi`.
    pub(crate) fn dropped_residual(&self, phi: &[f64], kept: &[bool]) -> f64 {
        phi.iter()
            .zip(&self.equation_scales)
            .zip(kept)
            .filter(|(_, &k)| !k)
            .map(|((v, e), _)| (v / e).abs())
            .fold(0.0f64, f64::max)
    }

    /// Records the dropped rows' residuals from `ws.rows.phi` (Φ at the solution of time `t`): the
    /// worst per row. No allocation.
    pub(crate) fn record_dropped_rows(&self, ws: &mut Workspace, t: f64) {
        for r in 0..ws.dropped.kept.len() {
            if ws.dropped.kept[r] {
                continue;
            }
            let d = (ws.rows.phi[r] / self.equation_scales[r]).abs();
            if d > ws.dropped.worst[r] || d.is_nan() {
                ws.dropped.worst[r] = d;
                ws.dropped.value[r] = ws.rows.phi[r];
                ws.dropped.time[r] = t;
            }
        }
    }

    /// The rows dropped as redundant whose scaled residual exceeded `tol` at some solved frame
    /// since the kinematic solver was prepared: one per element (its worst row), in model
    /// order. Empty for a consistent model (see the module docs). Allocates.
    pub fn dropped_row_residuals(&self, ws: &Workspace, tol: f64) -> Vec<DroppedRowResidual> {
        let rows = (0..ws.dropped.worst.len()).map(|r| DroppedRowSample {
            row: r,
            residual: ws.dropped.worst[r],
            value: ws.dropped.value[r],
            time: ws.dropped.time[r],
        });
        self.worst_dropped_rows(rows, tol)
    }

    /// The rows not in `kept` (a mask over the first `phi.len()` rows) whose scaled residual in
    /// Φ = `phi` at time `t` exceeds `tol`, one per element (its worst row). Allocates.
    pub(crate) fn dropped_rows_at(
        &self,
        phi: &[f64],
        kept: &[bool],
        t: f64,
        tol: f64,
    ) -> Vec<DroppedRowResidual> {
        let rows = phi
            .iter()
            .enumerate()
            .filter(|&(r, _)| !kept[r])
            .map(|(r, &v)| DroppedRowSample {
                row: r,
                residual: (v / self.equation_scales[r]).abs(),
                value: v,
                time: t,
            });
        self.worst_dropped_rows(rows, tol)
    }

    /// `rows` (increasing rows; a [`DroppedRowSample`] or a tuple (row, scaled residual, value,
    /// time)) whose scaled residual exceeds `tol`, the worst per element, as
    /// [`DroppedRowResidual`]s (for analyses outside this crate that track dropped rows
    /// themselves: dynamics). Allocates.
    pub fn worst_dropped_rows<S: Into<DroppedRowSample>>(
        &self,
        rows: impl Iterator<Item = S>,
        tol: f64,
    ) -> Vec<DroppedRowResidual> {
        let mut out: Vec<DroppedRowResidual> = Vec::new();
        for sample in rows {
            let DroppedRowSample {
                row: r,
                residual: d,
                value,
                time,
            } = sample.into();
            if !(d > tol || d.is_nan()) {
                continue;
            }
            let (Some(equation), Some(dimension)) = (self.equation(r), self.equation_dimension(r))
            else {
                continue;
            };
            let row = DroppedRowResidual {
                equation,
                residual: d,
                value,
                dimension,
                time,
            };
            match out.last_mut() {
                Some(last) if last.equation.element == row.equation.element => {
                    if row.residual > last.residual {
                        *last = row;
                    }
                }
                _ => out.push(row),
            }
        }
        out
    }
}

impl Model {
    /// The dimension of equation `row` (what its residual measures), `None` out of range.
    pub fn equation_dimension(&self, row: usize) -> Option<Dimension> {
        if let Some(j) = self.joints.iter().find(|j| j.rows.contains(&row)) {
            return Some(j.joint.dimension(row - j.rows.start));
        }
        if let Some(c) = self.couplers.iter().find(|c| c.rows.contains(&row)) {
            return Some(c.coupler.dimension(0));
        }
        let d = self.drivers.iter().find(|d| d.rows.contains(&row))?;
        Some(d.driver.dimension(0))
    }
}

impl Workspace {
    /// Forgets the recorded residuals of dropped rows and marks every row kept (a new
    /// preparation of the kinematic solver).
    pub(crate) fn reset_dropped_rows(&mut self) {
        self.dropped.kept.fill(true);
        self.dropped.worst.fill(0.0);
        self.dropped.value.fill(0.0);
        self.dropped.time.fill(f64::NAN);
    }

    /// Marks the rows the kinematic solver keeps (the others are dropped as redundant).
    pub(crate) fn set_kept_rows(&mut self, rows: &[usize]) {
        self.dropped.kept.fill(false);
        for &r in rows {
            self.dropped.kept[r] = true;
        }
    }
}
