//! The equations of motion as a first-order system y' = f(t, y) for an explicit scheme:
//! y = [q; v] (7 + 6 numbers per body), ṙ = ṙ, ṗ = ½ Lᵀ ω', v̇ from the augmented system.
//! Euler parameters are normalized whenever a state is read from y.

use crate::kkt::SchurRefinement;
use crate::options::Baumgarte;
use crate::state::State;
use crate::system::Dynamics;
use crate::work::Multipliers;
use crate::DynamicsError;
use cardan_eulerparam::p_dot_from_local;
use nalgebra::{Vector3, Vector4};

/// The state held in `y` at time `t`, into `s`, with each body's p normalized.
pub(super) fn to_state(y: &[f64], t: f64, s: &mut State) {
    let nq = s.q.len();
    s.t = t;
    s.q.copy_from_slice(&y[..nq]);
    s.v.copy_from_slice(&y[nq..]);
    for k in 0..s.v.len() / 6 {
        let p = Vector4::from_column_slice(&s.q[7 * k + 3..7 * k + 7]);
        let n = p.norm();
        for c in 0..4 {
            s.q[7 * k + 3 + c] = p[c] / n;
        }
    }
}

/// y = [q; v] of `s`.
pub(super) fn from_state(s: &State, y: &mut [f64]) {
    let nq = s.q.len();
    y[..nq].copy_from_slice(&s.q);
    y[nq..].copy_from_slice(&s.v);
}

/// How the equations of motion are solved at each evaluation: with Baumgarte's terms, and
/// when a Schur solve is refined.
#[derive(Debug, Clone, Copy)]
pub(super) struct Eom {
    /// Baumgarte's factors (zero without).
    pub baumgarte: Baumgarte,
    /// The refinement of a Schur solve.
    pub refine: SchurRefinement,
}

impl Eom {
    /// dy = f(t, y), and the power of each work channel there into `pw` ([`crate::work`]); `s`
    /// is scratch. No allocation.
    ///
    /// # Errors
    /// A state that is not finite; the solve's failure.
    pub fn rhs(
        &self,
        d: &mut Dynamics,
        t: f64,
        y: &[f64],
        dy: &mut [f64],
        s: &mut State,
        pw: &mut [f64],
    ) -> Result<(), DynamicsError> {
        if y.iter().any(|v| !v.is_finite()) {
            return Err(DynamicsError::NonFinite {
                time: t,
                what: "the state",
            });
        }
        to_state(y, t, s);
        d.sync(s);
        d.solve_eom(t, self.baumgarte, self.refine)?;
        let nb = s.v.len() / 6;
        let nq = 7 * nb;
        let sol = &d.kkt.as_ref().expect("prepared").sol;
        for k in 0..nb {
            let p = Vector4::from_column_slice(&y[7 * k + 3..7 * k + 7]);
            let w = Vector3::from_column_slice(&y[nq + 6 * k + 3..nq + 6 * k + 6]);
            let pd = p_dot_from_local(&p, &w);
            for c in 0..3 {
                dy[7 * k + c] = y[nq + 6 * k + c];
            }
            for c in 0..4 {
                dy[7 * k + 3 + c] = pd[c];
            }
        }
        dy[nq..].copy_from_slice(&sol[..6 * nb]);
        d.powers(t, Multipliers::Solution, pw);
        Ok(())
    }
}
