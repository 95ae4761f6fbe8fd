//! The constraints' curvature weighted by multipliers, for a Newton step on a Lagrangian
//! (the least change, [`crate::analysis::least_change`]).
//!
//! Along the retraction the Newton state uses (r + s ṙ, p ⊗ exp(s ω'/2): constant velocity
//! v = [ṙ; ω'], each body turning at a constant body-frame rate), a row's second derivative is
//! d²Φ_r/ds² = −γ#_r(v) for a row that does not depend on time: γ# is everything in Φ̈ that is
//! not Φ_v v̇ (`shared/notation.md`), and v̇ = 0 on that path. So the Hessian of −κᵀΦ in the
//! six velocity coordinates is the symmetric matrix C of the quadratic form
//!
//! ```text
//!   q(v) = Σ_r κ_r γ#_r(v) = vᵀ C v + bᵀ v + q₀,
//! ```
//!
//! where b and q₀ hold a driver's −2 Φ_vt v and −Φ_tt. C is read off element by element by
//! polarization, from values of q alone: C_kk = ½ (q(e_k) + q(−e_k)) − q₀ and
//! 2 C_kl = q(e_k + e_l) − q(e_k) − q(e_l) + q₀ over the (at most) 12 coordinates of the
//! element's two bodies, 91 evaluations of its γ#. No second derivative is written by hand; the
//! γ# it rests on is the one the oracle gate checks.

use super::elements::BodyId;
use super::Model;
use crate::workspace::Workspace;
use cardan_constraints::{BodyPair, BodyState};
use nalgebra::Vector3;

/// The most rows of one element (a joint).
const MAX_ROWS: usize = 6;

impl Model {
    /// Adds to `out` (dense, `n × n` row by row, n = 6 nb) the matrix C of the quadratic form
    /// vᵀ C v = Σ_r κ_r γ#_r(v) at the workspace's poses and time `t` (module docs): the
    /// Hessian of −κᵀΦ along the Newton state's retraction, for multipliers `kappa` (one per
    /// equation). Curve elements and path drivers contribute nothing. No allocation.
    pub fn eval_curvature(&self, ws: &Workspace, t: f64, kappa: &[f64], out: &mut [f64]) {
        self.curvature_into(&ws.pose.bodies, kappa, t, out)
    }

    /// Adds C (module docs) of every joint, coupler and driver to `out`, a dense symmetric
    /// `n × n` matrix row by row (n = 6 nb, curve elements have none), for multipliers `kappa`
    /// (one per equation) at the `bodies`' poses and time `t`. No allocation.
    pub(crate) fn curvature_into(
        &self,
        bodies: &[BodyState],
        kappa: &[f64],
        t: f64,
        out: &mut [f64],
    ) {
        let n = 6 * bodies.len();
        let g = BodyState::ground();
        self.each(|e, bi, bj, rows, _| {
            let k = &kappa[rows.clone()];
            if k.iter().all(|v| *v == 0.0) {
                return;
            }
            // The element's coordinates: (body side, column in `out`) of each moving side.
            let mut cols = [(0usize, 0usize); 12];
            let mut nc = 0;
            for (side, id) in [bi, bj].into_iter().enumerate() {
                if let BodyId::Moving(b) = id {
                    for c in 0..6 {
                        cols[nc] = (6 * side + c, 6 * b + c);
                        nc += 1;
                    }
                }
            }
            let (si, sj) = (Self::state(bodies, &g, bi), Self::state(bodies, &g, bj));
            let mut gamma = [0.0; MAX_ROWS];
            // q(d) for the element's local velocity d (12 entries: body i's, then body j's).
            let mut q = |d: &[f64; 12]| {
                let v = |o: usize| Vector3::new(d[o], d[o + 1], d[o + 2]);
                let vi = si.with_v(v(0), v(3));
                let vj = sj.with_v(v(6), v(9));
                let gamma = &mut gamma[..k.len()];
                e.gamma_dyn(&BodyPair::new(&vi, &vj), t, gamma);
                gamma.iter().zip(k).map(|(a, b)| a * b).sum::<f64>()
            };
            let unit = |a: usize, sa: f64, b: Option<usize>| {
                let mut d = [0.0; 12];
                d[a] += sa;
                if let Some(b) = b {
                    d[b] += 1.0;
                }
                d
            };
            let q0 = q(&[0.0; 12]);
            let mut plus = [0.0; 12];
            for a in 0..nc {
                let (la, ga) = cols[a];
                plus[a] = q(&unit(la, 1.0, None));
                let minus = q(&unit(la, -1.0, None));
                out[ga * n + ga] += 0.5 * (plus[a] + minus) - q0;
            }
            for a in 0..nc {
                for b in a + 1..nc {
                    let ((la, ga), (lb, gb)) = (cols[a], cols[b]);
                    let c = 0.5 * (q(&unit(la, 1.0, Some(lb))) - plus[a] - plus[b] + q0);
                    out[ga * n + gb] += c;
                    out[gb * n + ga] += c;
                }
            }
        });
    }
}
