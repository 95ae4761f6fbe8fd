//! The impact of a closing stop: the impulse equations solved with the bilateral
//! factorization at the contact pose (module docs of [`super`]), the velocities' jump, the
//! event and the energy taken. Also the hold of the closed stops at a pose (positions and
//! velocities brought back onto g = 0, ġ = 0 for a scheme that does not carry the stop rows
//! in its own iteration). Allocates the event's name only.

use super::events::ImpactEvent;
use super::small::solve_small;
use super::state::HOLD_TOLERANCE;
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
        kkt.eval_jacobian(model, &self.elements, &self.bodies, &self.curves, state.t);
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
            if self.contacts.set.is_empty() {
                return Ok(());
            }
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
            // Tensile beyond round-off: a held stop at rest gets impulses of ~1e-21 of either
            // sign, which must not release it.
            let pmax = c.b[..k].iter().fold(0.0f64, |m, p| m.max(p.abs()));
            let floor = 1e-9 * pmax + 1e-12 * self.mass.iter().sum::<f64>() * c.rest_velocity;
            let tensile = (0..k).find(|&a| Some(c.set[a]) != keep && c.b[a] > floor);
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

    /// The impact of stop `s` closing at `state` (at contact; velocities v⁻), solved together
    /// with every other stop at contact (|g| within [`HOLD_TOLERANCE`]) that closes too
    /// (Newton's law on each: ġ⁺ = −e ġ⁻, 0 below the rest velocity) and the held stops
    /// (ġ⁺ = 0); a stop at contact that the impulse would drive closing is added with ġ⁺ = 0
    /// and the system solved again. The events are recorded (the kinetic energy taken is the
    /// initiating stop's, its limit's work).
    ///
    /// # Errors
    /// A stop whose coordinate the joints and drivers fix (W vanishes).
    pub(crate) fn impact(&mut self, state: &mut State, s: usize) -> Result<(), DynamicsError> {
        self.factor_mass_at(state)?;
        let t = state.t;
        let ns = self.contacts.held.len();
        let stops = self.model.stops();
        let limits = self.model.limits();
        let scale = |q: usize| self.model.stop_scale(q);
        // ġ⁻ of every stop, and the set: held, the initiating one, the others at contact that
        // close.
        self.contacts.set.clear();
        for q in 0..ns {
            let (g, rate, _) = self.stop_state(q, t);
            self.contacts.closing[q] = rate.min(0.0);
            let at_contact = g.abs() <= HOLD_TOLERANCE * scale(q) && rate < 0.0;
            let watched = limits[stops[q].limit].compliance.is_none();
            if q == s || self.contacts.held[q] || (watched && at_contact) {
                self.contacts.set.push(q);
            }
        }
        let before = self.energy(state).kinetic;
        let rest = self.contacts.rest_velocity;
        let target = |held: &[bool], closing: &[f64], q: usize| {
            let e = limits[stops[q].limit].restitution;
            if held[q] || e == 0.0 || closing[q].abs() < rest {
                0.0
            } else {
                -e * closing[q]
            }
        };
        for _ in 0..=ns {
            let (held, closing) = (self.contacts.held.clone(), self.contacts.closing.clone());
            self.sync(state);
            self.stop_impulses(&state.v, t, Some(s), |q| target(&held, &closing, q))?;
            let mut v = state.v.clone();
            self.apply_impulses(&mut v);
            // A stop at contact driven closing by the impulse joins the set.
            let mut trial = state.clone();
            trial.v.copy_from_slice(&v);
            self.sync(&trial);
            let added = (0..ns).find(|&q| {
                let (g, rate, _) = self.stop_state(q, t);
                !self.contacts.set.contains(&q)
                    && limits[stops[q].limit].compliance.is_none()
                    && g.abs() <= HOLD_TOLERANCE * scale(q)
                    && rate < -rest
            });
            match added {
                Some(q) => {
                    self.contacts.held[q] = true;
                    self.contacts.set.clear();
                    for k in 0..ns {
                        if k == s
                            || self.contacts.held[k]
                            || self.contacts.closing[k] < 0.0 && {
                                let (g, _, _) = self.stop_state(k, t);
                                g.abs() <= HOLD_TOLERANCE * scale(k)
                            }
                        {
                            self.contacts.set.push(k);
                        }
                    }
                    self.sync(state);
                }
                None => {
                    state.v.copy_from_slice(&v);
                    break;
                }
            }
        }
        self.sync(state);
        let after = self.energy(state).kinetic;
        let limit = stops[s].limit;
        self.contacts.impact_work[limit] += after - before;
        for a in 0..self.contacts.set.len() {
            let q = self.contacts.set[a];
            let closing = self.contacts.closing[q];
            if closing >= 0.0 && q != s {
                continue;
            }
            let e = limits[stops[q].limit].restitution;
            let hold = self.contacts.held[q] || e == 0.0 || closing.abs() < rest;
            self.contacts.held[q] = hold;
            let (_, rebound, _) = self.stop_state(q, t);
            let event = ImpactEvent {
                time: t,
                stop: stops[q].name.clone(),
                limit: stops[q].limit,
                impact_velocity: closing,
                impulse: -self.contacts.b[a],
                rebound_velocity: rebound,
                held: hold,
                release: false,
                energy_change: if q == s { after - before } else { 0.0 },
            };
            self.contacts.events.push(event);
        }
        Ok(())
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
