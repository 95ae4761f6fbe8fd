//! The impact of a closing stop: the impulse equations solved with the bilateral
//! factorization at the contact pose (module docs of [`super`]), the velocities' jump, the
//! event and the energy taken. Also the hold of the closed stops at a pose (positions and
//! velocities brought back onto g = 0, ġ = 0 for a scheme that does not carry the stop rows
//! in its own iteration). Allocates the event's name only.

use super::events::ImpactEvent;
use super::small::solve_small;
use crate::kkt::SchurRefinement;
use crate::state::State;
use crate::system::Dynamics;
use crate::DynamicsError;

impl Dynamics<'_> {
    /// Factors [M Φ_vᵀ; Φ_v 0] at `state` (positions synced).
    fn factor_mass_at(&mut self, state: &State) -> Result<(), DynamicsError> {
        if self.kkt.is_none() {
            self.prepare(state)?;
        }
        self.sync(state);
        let model = self.model;
        let kkt = self.kkt.as_mut().expect("prepared");
        kkt.eval_jacobian(model, &self.elements, &self.bodies, state.t);
        kkt.set_mass(&self.mass, &self.inertia);
        let r = kkt.factor();
        r.map_err(|e| self.solver_error(state.t, e))
    }

    /// Solves W p = b for the stops in `contacts.set` with right sides `rhs(s, G_s v)` at the
    /// synced velocities `v`; a stop of `set` other than `keep` whose p comes out tensile
    /// (> 0) leaves the set and the system is solved again. Returns with `contacts.b[..k]` = p.
    fn stop_impulses(
        &mut self,
        v: &[f64],
        t: f64,
        keep: Option<usize>,
        target: impl Fn(usize) -> f64,
    ) -> Result<(), DynamicsError> {
        loop {
            for a in 0..self.contacts.set.len() {
                let s = self.contacts.set[a];
                self.eval_stop_row(s, t);
            }
            self.stop_columns(SchurRefinement::ONE_SHOT)?;
            let k = self.contacts.set.len();
            for a in 0..k {
                let s = self.contacts.set[a];
                self.contacts.b[a] = self.stop_dot(s, v) - target(s);
            }
            // W = G M̃⁻¹ Gᵀ vanishes (relative to G's size) when the joints and drivers fix
            // the stop's coordinate: the stop cannot act (a motor drives into it).
            let wscale = (0..k).fold(0.0f64, |a, i| a.max(self.contacts.w[i * k + i].abs()));
            let tiny = wscale <= 1e-12 * self.stop_row_scale(self.contacts.set[0]);
            let c = &mut self.contacts;
            if tiny || !solve_small(&mut c.w[..k * k], &mut c.b[..k], k) {
                return Err(self.stop_cannot_act(t));
            }
            let tensile = (0..k).find(|&a| Some(c.set[a]) != keep && c.b[a] > 0.0);
            match tensile {
                Some(a) => {
                    c.held[c.set[a]] = false;
                    c.set.remove(a);
                }
                None => return Ok(()),
            }
        }
    }

    /// |G|² / (the largest mass) for the first stop of the set: the scale of W's diagonal.
    fn stop_row_scale(&self, s: usize) -> f64 {
        let (bi, bj) = self.contacts.rows[s];
        let g2: f64 = bi.iter().chain(&bj).map(|x| x * x).sum();
        let m = self.mass.iter().fold(1e-300f64, |a, &b| a.max(b));
        let j = self
            .inertia
            .iter()
            .fold(1e-300f64, |a, i| a.max(i.diagonal().max()));
        g2 / m.max(j)
    }

    /// The error of a stop whose coordinate the joints and drivers fix.
    fn stop_cannot_act(&self, t: f64) -> DynamicsError {
        let names: Vec<&str> = self
            .contacts
            .set
            .iter()
            .map(|&s| {
                self.model.limits()[self.model.stops()[s].limit]
                    .name
                    .as_str()
            })
            .collect();
        DynamicsError::Limit {
            limit: names.join("\", \""),
            reason: format!(
                "reached at t = {t}, but the joints and drivers fix its coordinate (a driver \
                 moves the joint into the stop): the stop cannot act; remove the limit or the \
                 driver, or end the motion before the stop"
            ),
        }
    }

    /// v −= X p for the stops of `contacts.set` (p in `contacts.b`).
    fn apply_impulses(&mut self, v: &mut [f64]) {
        let size = self.kkt.as_ref().expect("prepared").sol.len();
        let c = &self.contacts;
        for a in 0..c.set.len() {
            for (x, col) in v.iter_mut().zip(&c.cols[a * size..]) {
                *x -= col * c.b[a];
            }
        }
    }

    /// The impact of stop `s` closing at `state` (at contact; velocities v⁻): v⁺ from Newton's
    /// law with the limit's e (0 below the rest velocity), the held stops kept closed.
    ///
    /// # Errors
    /// A singular impulse system (the stop's row dependent on the joints').
    pub(crate) fn impact(
        &mut self,
        state: &mut State,
        s: usize,
    ) -> Result<ImpactEvent, DynamicsError> {
        self.factor_mass_at(state)?;
        let t = state.t;
        let (_, closing, _) = self.stop_state(s, t);
        // A stop reached while opening (ġ ≥ 0) takes no impulse: it stays open.
        let closing = closing.min(0.0);
        let limit = self.model.stops()[s].limit;
        let e = self.model.limits()[limit].restitution;
        let hold = e == 0.0 || closing.abs() < self.contacts.rest_velocity;
        let target_s = if hold { 0.0 } else { -e * closing };
        let before = self.energy(state).kinetic;
        self.contacts.set.clear();
        for q in 0..self.contacts.held.len() {
            if self.contacts.held[q] && q != s {
                self.contacts.set.push(q);
            }
        }
        self.contacts.set.push(s);
        self.sync(state);
        self.stop_impulses(
            &state.v,
            t,
            Some(s),
            |q| if q == s { target_s } else { 0.0 },
        )?;
        let a = self
            .contacts
            .set
            .iter()
            .position(|&q| q == s)
            .expect("kept");
        let p = self.contacts.b[a];
        self.apply_impulses(&mut state.v);
        self.contacts.held[s] = hold;
        self.sync(state);
        let (_, rebound, _) = self.stop_state(s, t);
        let after = self.energy(state).kinetic;
        self.contacts.impact_work[limit] += after - before;
        Ok(ImpactEvent {
            time: t,
            stop: self.model.stops()[s].name.clone(),
            limit,
            impact_velocity: closing,
            impulse: -p,
            rebound_velocity: rebound,
            held: hold,
            release: false,
            energy_change: after - before,
        })
    }

    /// Brings `state` back onto the held stops (g = 0 by one least-change step in the metric of
    /// M, the joints kept, then ġ = 0), for a scheme whose iteration does not carry the stop
    /// rows (generalized-α). Returns whether anything moved.
    ///
    /// # Errors
    /// The projections' failures.
    pub(crate) fn hold_stops(&mut self, state: &mut State, tol: f64) -> Result<(), DynamicsError> {
        for _ in 0..3 {
            self.factor_mass_at(state)?;
            self.contacts.set.clear();
            for q in 0..self.contacts.held.len() {
                if self.contacts.held[q] {
                    self.contacts.set.push(q);
                }
            }
            if self.contacts.set.is_empty() {
                return Ok(());
            }
            let t = state.t;
            let n = state.v.len();
            // Positions: G Δ = −g with Δ = −X π, so W π = g (a velocity-like step).
            let mut worst = 0.0f64;
            let mut delta = std::mem::take(&mut self.contacts.sol0);
            delta.resize(n.max(delta.len()), 0.0);
            delta[..n].fill(0.0);
            for a in 0..self.contacts.set.len() {
                let s = self.contacts.set[a];
                self.eval_stop_row(s, t);
                worst = worst.max(self.stop_state(s, t).0.abs());
            }
            self.stop_columns(SchurRefinement::ONE_SHOT)?;
            let k = self.contacts.set.len();
            for a in 0..k {
                self.contacts.b[a] = self.stop_state(self.contacts.set[a], t).0;
            }
            let c = &mut self.contacts;
            if !solve_small(&mut c.w[..k * k], &mut c.b[..k], k) {
                self.contacts.sol0 = delta;
                return Err(DynamicsError::Singular {
                    time: t,
                    dependent: Vec::new(),
                });
            }
            self.apply_impulses(&mut delta[..n]);
            self.contacts.sol0 = delta;
            cardan_mechanism::apply_rotation_step(&mut state.q, &self.contacts.sol0[..n]);
            self.project_positions(state, tol)?;
            // Velocities: G v = 0 for the held stops.
            self.factor_mass_at(state)?;
            self.sync(state);
            self.stop_impulses(&state.v, t, None, |_| 0.0)?;
            self.apply_impulses(&mut state.v);
            if worst <= tol {
                return Ok(());
            }
        }
        Ok(())
    }
}
