//! Unilateral constraints in the dynamics: the stops of the model's limits
//! ([`cardan_mechanism::Model::stops`], rows g(q) ≥ 0), their impacts and their persistent
//! contact.
//!
//! ## Theory
//! A closed stop adds a row G = ∂g/∂v (1 × n, the [`cardan_constraints::JointLimit`]'s Φ_v) to
//! the bilateral constraints. Its multiplier λ_s has the sign convention of the others (the
//! reaction is −Gᵀλ_s), so a stop that pushes has λ_s ≤ 0.
//!
//! **Persistent contact** (a stop held closed: after an impact with e = 0, or when the impacts
//! accumulate, below): the augmented system gains the row G v̇ = γ#_s. It is solved with the
//! bilateral system's factorization K = [M Φ_vᵀ; Φ_v 0] by the Schur complement on the few
//! stop rows (the Delassus operator W = G X with K [X; Y] = [Gᵀ; 0], one solve per closed
//! stop, no new layout):
//!
//! ```text
//! [v̇₀; λ₀] = K⁻¹ [h; γ#],    W λ_S = G v̇₀ − γ*,    [v̇; λ] = [v̇₀; λ₀] − [X; Y] λ_S
//! γ* = γ#_s − 2ω ġ − ω² g    (Baumgarte on the stop rows, ω = [`STOP_STABILIZATION`])
//! ```
//!
//! A runs without closed stops solves exactly as before. The stop leaves when its multiplier
//! changes sign (λ_s > 0: it would have to pull), located inside the step.
//!
//! **Impacts** (Newton's law of restitution; Haug 1989 §11.6, Pfeiffer & Glocker 1996 §6):
//! at the located contact time the velocities jump by Δv with the impulse equations of the
//! closing stop and the stops held closed, the bilateral joints' rows kept:
//!
//! ```text
//! ⎡M  Φ_vᵀ⎤ ⎡Δv⎤   ⎡−Gᵀ p⎤          G v⁺ = −e G v⁻  (the closing stop),   0 (held stops)
//! ⎣Φ_v  0 ⎦ ⎣μ ⎦ = ⎣  0  ⎦    ⟹    W p = G v⁻ − G v⁺,   Δv = −X p
//! ```
//!
//! (p ≤ 0 for a compressive impulse, reported as the impulse magnitude −p ≥ 0; a held stop
//! whose p comes out tensile leaves the set and the system is solved again). The kinetic
//! energy lost, ½ (v⁺ᵀ M v⁺ − v⁻ᵀ M v⁻) (for one stop with the joints ideal:
//! −½ (1 − e²) ġ⁻² / W), is the work of the limit's channel, so the energy balance closes.
//!
//! **Accumulation** (a ball coming to rest: infinitely many impacts in a finite time): an
//! impact whose closing rate |ġ⁻| is below the rest velocity ([`Contacts::rest_velocity`],
//! default [`REST_VELOCITY`]) holds the stop closed (e = 0), so the run rests on the stop.

mod delassus;
mod events;
mod impact;

pub use events::ImpactEvent;

/// ω (1/s) of the Baumgarte terms on the rows of held stops: drift of g (from the integrator's
/// error) is pulled back with this rate, far slower than any step.
pub const STOP_STABILIZATION: f64 = 10.0;

/// Default rest velocity (m/s or rad/s): a closing rate below it holds the stop closed.
pub const REST_VELOCITY: f64 = 1e-5;

/// The state of the stops during a run, and the buffers their solves use (sized at setup;
/// empty for a model without limits).
#[derive(Debug, Clone)]
pub(crate) struct Contacts {
    /// The stops that take impacts (not compliant), in [`cardan_mechanism::Model::stops`] order.
    pub watched: Vec<usize>,
    /// Per stop: held closed (persistent contact).
    pub held: Vec<bool>,
    /// Per stop: λ_s of the last solve (0 while open).
    pub lambda: Vec<f64>,
    /// The stops of the current Schur solve.
    pub set: Vec<usize>,
    /// X columns (and Y) of the stops in `set`, each of the KKT size.
    pub cols: Vec<f64>,
    /// The bilateral solution saved while the columns are solved.
    pub sol0: Vec<f64>,
    /// W (row-major, |set|²) and the right side / solution of W x = b.
    pub w: Vec<f64>,
    pub b: Vec<f64>,
    /// Each stop's Φ_v blocks (body i, body j) and γ# at the synced bodies.
    pub rows: Vec<([f64; 6], [f64; 6])>,
    /// The impacts so far.
    pub events: Vec<ImpactEvent>,
    /// Per limit: the kinetic energy its impacts took (≤ 0), J.
    pub impact_work: Vec<f64>,
    /// Below this closing rate an impact holds the stop closed.
    pub rest_velocity: f64,
}

impl Contacts {
    /// The stops of `model` (impacts for every limit without a compliant law).
    pub fn new(model: &cardan_mechanism::Model) -> Self {
        let ns = model.stops().len();
        let watched: Vec<usize> = (0..ns)
            .filter(|&s| model.limits()[model.stops()[s].limit].compliance.is_none())
            .collect();
        Self {
            watched,
            held: vec![false; ns],
            lambda: vec![0.0; ns],
            set: Vec::with_capacity(ns),
            cols: Vec::new(),
            sol0: Vec::new(),
            w: vec![0.0; ns * ns],
            b: vec![0.0; ns],
            rows: vec![([0.0; 6], [0.0; 6]); ns],
            events: Vec::new(),
            impact_work: vec![0.0; model.limits().len()],
            rest_velocity: REST_VELOCITY,
        }
    }

    /// Whether any stop is held closed.
    pub fn any_held(&self) -> bool {
        self.held.iter().any(|&h| h)
    }

    /// Back to every stop open, no events (the start of a run).
    pub fn reset(&mut self) {
        self.held.fill(false);
        self.lambda.fill(0.0);
        self.events.clear();
        self.impact_work.fill(0.0);
    }
}

/// Solves the dense k × k system `w` x = `b` in place (x into `b`) by Gaussian elimination
/// with partial pivoting; `false` when singular. No allocation.
pub(crate) fn solve_small(w: &mut [f64], b: &mut [f64], k: usize) -> bool {
    for c in 0..k {
        let p = (c..k)
            .max_by(|&x, &y| w[x * k + c].abs().total_cmp(&w[y * k + c].abs()))
            .expect("k > 0");
        if w[p * k + c].abs() < 1e-300 || !w[p * k + c].is_finite() {
            return false;
        }
        if p != c {
            for j in 0..k {
                w.swap(p * k + j, c * k + j);
            }
            b.swap(p, c);
        }
        for r in c + 1..k {
            let f = w[r * k + c] / w[c * k + c];
            for j in c..k {
                w[r * k + j] -= f * w[c * k + j];
            }
            b[r] -= f * b[c];
        }
    }
    for c in (0..k).rev() {
        let mut s = b[c];
        for j in c + 1..k {
            s -= w[c * k + j] * b[j];
        }
        b[c] = s / w[c * k + c];
    }
    true
}

impl crate::system::Dynamics<'_> {
    /// At the start of a run from `state`: every stop open, no events; a stop beyond its
    /// bound (more than [`crate::integrators::events::HOLD_TOLERANCE`] of its scale) is an
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
            let scale = match st.row.measure.quantity() {
                cardan_constraints::joints::CoordinateQuantity::Angle => 1.0,
                cardan_constraints::joints::CoordinateQuantity::Length => {
                    model.characteristic_length()
                }
            };
            let g = model.stop_gap(s, &self.bodies, &self.turns);
            if g < -crate::integrators::events::HOLD_TOLERANCE * scale {
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
    /// [`REST_VELOCITY`], m/s or rad/s; must be positive and finite).
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
