//! Coordinate projection of a DOPRI5 state onto the constraint manifolds (positions by Newton
//! on Φ = 0, then velocities onto Φ_v v = ν, both least-change in the metric of M:
//! [`Dynamics::project_positions`], [`Dynamics::project_velocities`]), and the choice of the
//! kept rows again for a mechanism with redundant equations.

use super::ode::{from_state, to_state};
use crate::kkt::SchurRefinement;
use crate::state::State;
use crate::system::Dynamics;
use crate::DynamicsError;

/// [`Dynamics::reselect`] at the state held in `y` at time `t` (when finite): whether the
/// independent rows of a mechanism with redundant equations changed.
pub(super) fn reselect_at(d: &mut Dynamics, y: &[f64], t: f64, s: &mut State) -> bool {
    if d.redundant.is_empty() || y.iter().any(|v| !v.is_finite()) {
        return false;
    }
    to_state(y, t, s);
    d.sync(s);
    d.reselect(t)
}

/// Projects the state held in `y` (positions to the scaled residual `tol`, then velocities);
/// returns the Newton iterations.
///
/// # Errors
/// The projection's failure (also after the rows were chosen again).
pub(super) fn project(
    d: &mut Dynamics,
    t: f64,
    y: &mut [f64],
    s: &mut State,
    tol: f64,
    refine: SchurRefinement,
) -> Result<usize, DynamicsError> {
    to_state(y, t, s);
    let it = match d.project_positions_refined(s, tol, refine) {
        Ok(it) => it,
        // The kept rows of a mechanism with redundant equations may have lost rank here:
        // choose them again at the unprojected state and project again from it.
        Err(e) => {
            if !reselect_at(d, y, t, s) {
                return Err(e);
            }
            to_state(y, t, s);
            d.project_positions_refined(s, tol, refine)?
        }
    };
    d.project_velocities_refined(s, refine)?;
    from_state(s, y);
    Ok(it)
}
