//! The stop rows against the bilateral factorization: G of each stop, the columns
//! K⁻¹ [Gᵀ; 0] = [X; Y] of the stops in the current set, the Delassus operator W = G X, and the
//! held stops' correction of the equations of motion (module docs of [`super`]). No allocation
//! after the first use at a layout size.

use super::small::solve_small;
use super::state::STOP_STABILIZATION;
use crate::kkt::SchurRefinement;
use crate::system::Dynamics;
use crate::DynamicsError;
use cardan_constraints::{BodyState, Constraint};
use cardan_mechanism::BodyId;

impl Dynamics<'_> {
    /// G (Φ_v blocks of bodies i, j) of stop `s` at the synced bodies into `contacts.rows[s]`.
    pub(crate) fn eval_stop_row(&mut self, s: usize, t: f64) {
        let g = BodyState::ground();
        let row = self.model.stop_row(s, &self.turns);
        let pair = self.model.stop_pair(s, &self.bodies, &g);
        let (mut bi, mut bj) = ([[0.0; 6]], [[0.0; 6]]);
        row.phi_v(&pair, t, &mut bi, &mut bj);
        self.contacts.rows[s] = (bi[0], bj[0]);
    }

    /// g, ġ and γ#_v of stop `s` at the synced bodies.
    pub(crate) fn stop_state(&self, s: usize, t: f64) -> (f64, f64, f64) {
        let g = BodyState::ground();
        let row = self.model.stop_row(s, &self.turns);
        let pair = self.model.stop_pair(s, &self.bodies, &g);
        let mut gamma = [0.0];
        row.gamma_sharp_v(&pair, t, &mut gamma);
        (row.gap(&pair), row.bound.sign() * row.rate(&pair), gamma[0])
    }

    /// G_s x for x over the n velocity unknowns (row evaluated by [`Self::eval_stop_row`]).
    pub(crate) fn stop_dot(&self, s: usize, x: &[f64]) -> f64 {
        let st = &self.model.stops()[s];
        let (bi, bj) = &self.contacts.rows[s];
        let mut r = 0.0;
        for (id, blk) in [(st.body_i, bi), (st.body_j, bj)] {
            if let BodyId::Moving(k) = id {
                r += (0..6).map(|c| blk[c] * x[6 * k + c]).sum::<f64>();
            }
        }
        r
    }

    /// With the KKT matrix factored at the synced bodies: the columns [X; Y] of the stops in
    /// `contacts.set` into `contacts.cols`, and W = G X into `contacts.w` (its rows evaluated).
    pub(crate) fn stop_columns(&mut self, refine: SchurRefinement) -> Result<(), DynamicsError> {
        let size = self.kkt.as_ref().expect("prepared").rhs.len();
        let k = self.contacts.set.len();
        if self.contacts.cols.len() < size * k {
            self.contacts.cols.resize(size * k, 0.0);
        }
        for a in 0..k {
            let s = self.contacts.set[a];
            let st = &self.model.stops()[s];
            let (bi, bj) = self.contacts.rows[s];
            let kkt = self.kkt.as_mut().expect("prepared");
            kkt.rhs.fill(0.0);
            for (id, blk) in [(st.body_i, bi), (st.body_j, bj)] {
                if let BodyId::Moving(b) = id {
                    for c in 0..6 {
                        kkt.rhs[6 * b + c] += blk[c];
                    }
                }
            }
            let r = kkt.solve(refine);
            if let Err(e) = r {
                return Err(self.solver_error(0.0, e));
            }
            let kkt = self.kkt.as_ref().expect("prepared");
            self.contacts.cols[a * size..(a + 1) * size].copy_from_slice(&kkt.sol);
        }
        for a in 0..k {
            for b in 0..k {
                let s = self.contacts.set[a];
                let col = &self.contacts.cols[b * size..b * size + 6 * self.model.num_bodies()];
                self.contacts.w[a * k + b] = self.stop_dot(s, col);
            }
        }
        Ok(())
    }

    /// After the bilateral solve of the equations of motion (`kkt.sol` = [v̇₀; λ₀]): the held
    /// stops' rows G v̇ = γ* added by the Schur complement on them, `kkt.sol` corrected and
    /// each held stop's λ_s in `contacts.lambda`. No allocation after the first call.
    pub(crate) fn add_held_stops(
        &mut self,
        t: f64,
        refine: SchurRefinement,
    ) -> Result<(), DynamicsError> {
        let ns = self.contacts.held.len();
        self.contacts.set.clear();
        for s in 0..ns {
            self.contacts.lambda[s] = 0.0;
            if self.contacts.held[s] {
                self.contacts.set.push(s);
            }
        }
        let size = self.kkt.as_ref().expect("prepared").sol.len();
        if self.contacts.sol0.len() != size {
            self.contacts.sol0.resize(size, 0.0);
        }
        self.contacts
            .sol0
            .copy_from_slice(&self.kkt.as_ref().expect("prepared").sol);
        for a in 0..self.contacts.set.len() {
            let s = self.contacts.set[a];
            self.eval_stop_row(s, t);
        }
        self.stop_columns(refine)?;
        let k = self.contacts.set.len();
        let n = 6 * self.model.num_bodies();
        for a in 0..k {
            let s = self.contacts.set[a];
            let (g, gdot, gamma) = self.stop_state(s, t);
            let w = STOP_STABILIZATION;
            let target = gamma - 2.0 * w * gdot - w * w * g;
            self.contacts.b[a] = self.stop_dot(s, &self.contacts.sol0[..n]) - target;
        }
        let c = &mut self.contacts;
        if !solve_small(&mut c.w[..k * k], &mut c.b[..k], k) {
            return Err(DynamicsError::Singular {
                time: t,
                dependent: Vec::new(),
            });
        }
        let kkt = self.kkt.as_mut().expect("prepared");
        kkt.sol.copy_from_slice(&c.sol0);
        for a in 0..k {
            let l = c.b[a];
            c.lambda[c.set[a]] = l;
            for (x, col) in kkt.sol.iter_mut().zip(&c.cols[a * size..(a + 1) * size]) {
                *x -= col * l;
            }
        }
        Ok(())
    }
}
