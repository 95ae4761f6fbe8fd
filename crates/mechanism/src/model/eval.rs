//! Evaluation of the global system on body states (6-coordinate form): Φ, ν, γ# and the
//! Jacobian Φ_v, element by element, scattered into the global vectors and slot array. The
//! extra coordinates u (curve parameters, [`Model::extras_of`]) and their rates u̇ come beside
//! the body states; element k of [`Model::curves`] reads u[k].

use super::elements::{BodyId, ScatterMap, NO_SLOT};
use super::Model;
use crate::workspace::Workspace;
use cardan_constraints::{BodyPair, BodyState, Constraint, MAX_EXTRA};
use std::ops::Range;

impl Model {
    pub(crate) fn state<'a>(
        bodies: &'a [BodyState],
        ground: &'a BodyState,
        id: BodyId,
    ) -> &'a BodyState {
        match id {
            BodyId::Ground => ground,
            BodyId::Moving(k) => &bodies[k],
        }
    }

    pub(super) fn each<F>(&self, mut f: F)
    where
        F: FnMut(&dyn ElementEval, BodyId, BodyId, &Range<usize>, &ScatterMap),
    {
        for j in &self.joints {
            f(&j.joint, j.body_i, j.body_j, &j.rows, &j.map);
        }
        for c in &self.couplers {
            f(&c.coupler, c.body_i, c.body_j, &c.rows, &c.map);
        }
        for d in &self.drivers {
            f(&d.driver, d.body_i, d.body_j, &d.rows, &d.map);
        }
    }

    /// Fills `out` (one entry per equation) element by element with `eval`, which writes an
    /// element's rows for its body pair (with its curve parameter u[k] and rate u̇[k], if a
    /// point-on-curve element): the one loop behind Φ, ν and γ#.
    fn rows_into(
        &self,
        bodies: &[BodyState],
        (u, u_dot): (&[f64], &[f64]),
        t: f64,
        out: &mut [f64],
        eval: impl Fn(&dyn ElementEval, &BodyPair, f64, &mut [f64]),
    ) {
        let g = BodyState::ground();
        self.each(|e, bi, bj, rows, _| {
            let pair = BodyPair::new(Self::state(bodies, &g, bi), Self::state(bodies, &g, bj));
            eval(e, &pair, t, &mut out[rows.clone()]);
        });
        // The rates u̇ of extra coordinates `k`, or 0 for Φ and ν, which take no rates.
        let rate = |k: Range<usize>| {
            if u_dot.is_empty() {
                &[0.0; MAX_EXTRA][..k.len()]
            } else {
                &u_dot[k]
            }
        };
        for c in &self.curves {
            let k = c.extras();
            let pair = BodyPair::with_extra(
                Self::state(bodies, &g, c.body_i),
                Self::state(bodies, &g, c.body_j),
                &u[k.clone()],
                rate(k),
            );
            eval(&c.element, &pair, t, &mut out[c.rows.clone()]);
        }
        for p in &self.paths {
            let k = p.extra..p.extra + 1;
            let pair = BodyPair::with_extra(&g, &g, &u[k.clone()], rate(k));
            eval(&p.driver, &pair, t, &mut out[p.rows.clone()]);
        }
    }

    /// Φ, with each coupler's angles continued from `turns` (its references at the last
    /// accepted pose, [`Model::accept_turns`]; one entry per coupler).
    pub(crate) fn phi_into(
        &self,
        bodies: &[BodyState],
        u: &[f64],
        turns: &[[f64; 2]],
        t: f64,
        out: &mut [f64],
    ) {
        self.rows_into(bodies, (u, &[]), t, out, |e, x, t, o| e.phi_dyn(x, t, o));
        let g = BodyState::ground();
        for (c, refs) in self.couplers.iter().zip(turns) {
            let pair = BodyPair::new(
                Self::state(bodies, &g, c.body_i),
                Self::state(bodies, &g, c.body_j),
            );
            let e = c.coupler.with_reference(*refs);
            e.phi(&pair, t, &mut out[c.rows.clone()]);
        }
    }

    /// The couplers' references at their initial poses (one per coupler), then the stops'
    /// ([`Model::stops`]: `[θ_ref, 0]`, 0 for a coordinate that is not an angle), where a
    /// workspace's turn counts start.
    pub fn initial_turns(&self) -> Vec<[f64; 2]> {
        self.couplers
            .iter()
            .map(|c| c.coupler.reference())
            .chain(self.stops.iter().map(|s| [s.row.reference, 0.0]))
            .collect()
    }

    /// Accepts the bodies' poses for the couplers: each coupler's references `turns[k]` become
    /// its angles there, continued from the old ones ([`cardan_constraints::Coupler::accept`]).
    /// Call at each accepted pose, so that an angle never changes by π or more between two
    /// calls. No allocation.
    pub fn accept_turns(&self, bodies: &[BodyState], turns: &mut [[f64; 2]]) {
        let g = BodyState::ground();
        for (c, refs) in self.couplers.iter().zip(turns.iter_mut()) {
            let pair = BodyPair::new(
                Self::state(bodies, &g, c.body_i),
                Self::state(bodies, &g, c.body_j),
            );
            *refs = c.coupler.with_reference(*refs).angles(&pair);
        }
        self.accept_stop_turns(bodies, &mut turns[self.couplers.len()..]);
    }

    pub(crate) fn nu_into(&self, bodies: &[BodyState], u: &[f64], t: f64, out: &mut [f64]) {
        self.rows_into(bodies, (u, &[]), t, out, |e, x, t, o| e.nu_dyn(x, t, o));
    }

    pub(crate) fn gamma_into(
        &self,
        bodies: &[BodyState],
        (u, u_dot): (&[f64], &[f64]),
        t: f64,
        out: &mut [f64],
    ) {
        self.rows_into(bodies, (u, u_dot), t, out, |e, x, t, o| {
            e.gamma_dyn(x, t, o)
        });
    }

    pub(crate) fn jacobian_into(&self, bodies: &[BodyState], u: &[f64], t: f64, slots: &mut [f64]) {
        let g = BodyState::ground();
        self.each(|e, bi, bj, rows, map| {
            let pair = BodyPair::new(Self::state(bodies, &g, bi), Self::state(bodies, &g, bj));
            scatter(e, &pair, t, rows.len(), map, slots);
        });
        for c in &self.curves {
            let k = c.extras();
            let pair = BodyPair::with_extra(
                Self::state(bodies, &g, c.body_i),
                Self::state(bodies, &g, c.body_j),
                &u[k.clone()],
                &[0.0; MAX_EXTRA][..k.len()],
            );
            let n = c.rows.len();
            scatter(&c.element, &pair, t, n, &c.map, slots);
            let mut ju = [[0.0; MAX_EXTRA]; 6];
            c.element.jacobian_extra(&pair, t, &mut ju[..n]);
            // Row by row, each parameter's column (`layout`).
            for (s, &slot) in c.extra_slots.iter().enumerate() {
                slots[slot] = ju[s / k.len()][s % k.len()];
            }
        }
        for p in &self.paths {
            let k = p.extra..p.extra + 1;
            let pair = BodyPair::with_extra(&g, &g, &u[k], &[0.0]);
            let mut ju = [[0.0; MAX_EXTRA]; 1];
            p.driver.jacobian_extra(&pair, t, &mut ju);
            slots[p.slot] = ju[0][0];
        }
    }

    /// Φ at the workspace's poses and time `t` (length [`num_equations`](Self::num_equations)).
    /// No allocation.
    pub fn eval_phi(&self, ws: &Workspace, t: f64, out: &mut [f64]) {
        let u = self.extras_of(&ws.pose.x);
        self.phi_into(&ws.pose.bodies, u, &ws.pose.turns, t, out)
    }

    /// Φ_v slot values (pattern [`Model::pattern`]) at the workspace's poses. No allocation.
    pub fn eval_jacobian(&self, ws: &Workspace, t: f64, slots: &mut [f64]) {
        let u = self.extras_of(&ws.pose.x);
        self.jacobian_into(&ws.pose.bodies, u, t, slots)
    }

    /// ν = −Φ_t at the workspace's poses. No allocation.
    pub fn eval_nu(&self, ws: &Workspace, t: f64, out: &mut [f64]) {
        let u = self.extras_of(&ws.pose.x);
        self.nu_into(&ws.pose.bodies, u, t, out)
    }

    /// γ#_v (6-coordinate form) at the workspace's poses and velocities (ω'). No allocation.
    pub fn eval_gamma(&self, ws: &Workspace, t: f64, out: &mut [f64]) {
        let u = self.extras_of(&ws.pose.x);
        let u_dot = self.extra_rates_of(&ws.motion.v);
        self.gamma_into(&ws.pose.bodies, (u, u_dot), t, out)
    }
}

/// Writes an element's Φ_v blocks (its `n` rows) into the slots of its scatter map.
fn scatter(
    e: &dyn ElementEval,
    pair: &BodyPair,
    t: f64,
    n: usize,
    map: &ScatterMap,
    slots: &mut [f64],
) {
    let mut bi_blk = [[0.0; 6]; 6];
    let mut bj_blk = [[0.0; 6]; 6];
    e.phi_v_dyn(pair, t, &mut bi_blk[..n], &mut bj_blk[..n]);
    for r in 0..n {
        let m = &map.slots[r * 12..r * 12 + 12];
        for c in 0..6 {
            if m[c] != NO_SLOT {
                slots[m[c]] = bi_blk[r][c];
            }
            if m[6 + c] != NO_SLOT {
                slots[m[6 + c]] = bj_blk[r][c];
            }
        }
    }
}

/// Object-safe view of a joint, coupler or driver (the [`Constraint`] trait has generic methods).
pub(super) trait ElementEval {
    fn phi_dyn(&self, x: &BodyPair, t: f64, out: &mut [f64]);
    fn nu_dyn(&self, x: &BodyPair, t: f64, out: &mut [f64]);
    fn gamma_dyn(&self, x: &BodyPair, t: f64, out: &mut [f64]);
    fn phi_v_dyn(&self, x: &BodyPair, t: f64, oi: &mut [[f64; 6]], oj: &mut [[f64; 6]]);
}

impl<C: Constraint> ElementEval for C {
    fn phi_dyn(&self, x: &BodyPair, t: f64, out: &mut [f64]) {
        self.phi(x, t, out)
    }
    fn nu_dyn(&self, x: &BodyPair, t: f64, out: &mut [f64]) {
        self.nu(x, t, out)
    }
    fn gamma_dyn(&self, x: &BodyPair, t: f64, out: &mut [f64]) {
        self.gamma_sharp_v(x, t, out)
    }
    fn phi_v_dyn(&self, x: &BodyPair, t: f64, oi: &mut [[f64; 6]], oj: &mut [[f64; 6]]) {
        self.phi_v(x, t, oi, oj)
    }
}
