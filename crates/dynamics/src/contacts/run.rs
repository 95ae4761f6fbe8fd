//! What a run does with the stops at its start, and what it offers afterwards: the events, the
//! held stops and their multipliers, the rest velocity.

use super::events::ImpactEvent;
use super::state::HOLD_TOLERANCE;

impl crate::system::Dynamics<'_> {
    /// At the start of a run from `state`: every stop open, no events; a stop beyond its
    /// bound (more than [`HOLD_TOLERANCE`] of its scale) is an
    /// error.
    ///
    /// # Errors
    /// [`crate::DynamicsError::Limit`] naming the limit, the coordinate and the bound.
    pub(crate) fn start_stops(&mut self, state: &crate::State) -> Result<(), crate::DynamicsError> {
        self.contacts.reset();
        if self.contacts.watched.is_empty() {
            return Ok(());
        }
        self.sync(state);
        let model = self.model;
        for &s in &self.contacts.watched {
            let st = &model.stops()[s];
            let scale = model.stop_scale(s);
            let g = model.stop_gap(s, &self.bodies, &self.turns);
            if g < -HOLD_TOLERANCE * scale {
                let l = &model.limits()[st.limit];
                let c = model.stop_coordinate(s, &self.bodies, &self.turns);
                return Err(crate::DynamicsError::Limit {
                    limit: l.name.clone(),
                    reason: format!(
                        "the initial state has {} = {c} beyond its {} bound {} (joint \"{}\")",
                        l.coordinate,
                        st.row.bound.name(),
                        st.row.value,
                        model.joints()[l.joint].name
                    ),
                });
            }
        }
        Ok(())
    }

    /// The impacts and releases of the last run, in time order (a front end writes them as
    /// `events.csv`).
    pub fn impact_events(&self) -> &[ImpactEvent] {
        &self.contacts.events
    }

    /// Which stops ([`cardan_mechanism::Model::stops`]) are held closed now, and their
    /// multipliers λ_s (≤ 0 while pushing; the stop's reaction is −Gᵀλ_s) from the last solve.
    pub fn stop_states(&self) -> (&[bool], &[f64]) {
        (&self.contacts.held, &self.contacts.lambda)
    }

    /// The closing rate below which an impact holds its stop closed (default
    /// [`crate::contacts::REST_VELOCITY`], m/s or rad/s; must be positive and finite).
    ///
    /// # Errors
    /// [`crate::DynamicsError::Options`] for a value that is not positive and finite.
    pub fn set_rest_velocity(&mut self, v: f64) -> Result<&mut Self, crate::DynamicsError> {
        if !(v.is_finite() && v > 0.0) {
            return Err(crate::DynamicsError::Options(format!(
                "rest velocity must be positive and finite, got {v}"
            )));
        }
        self.contacts.rest_velocity = v;
        Ok(self)
    }
}

impl crate::system::Dynamics<'_> {
    /// Appends the stops' state at the output time `t` to the run's history (after the
    /// equations of motion were solved there). Nothing for a model without limits.
    pub(crate) fn record_stops(&mut self, t: f64) {
        let ns = self.contacts.held.len();
        if ns == 0 {
            return;
        }
        let stops = self.model.stops();
        let c = &mut self.contacts;
        let force = (0..ns)
            .map(|s| -c.lambda[s] * stops[s].row.bound.sign() + c.compliant_force[s])
            .collect();
        c.history.times.push(t);
        c.history.held.push(c.held.clone());
        c.history.force.push(force);
    }

    /// The stops at each output time of the last run (held, force along the coordinate).
    pub fn stop_history(&self) -> &super::state::StopHistory {
        &self.contacts.history
    }
}
