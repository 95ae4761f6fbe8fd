//! `Contacts`: the stops' state during a run (held, multipliers, events) and the buffers of
//! their solves; the constants of the stop treatment. A leaf: the equations are elsewhere.

use super::events::ImpactEvent;

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
    /// The stops of limits with a compliant law (forces, not impacts).
    pub compliant: Vec<usize>,
    /// Per limit: the power of its compliant stops at the last force evaluation, W.
    pub compliant_power: Vec<f64>,
    /// Per stop: a compliant stop's force along the coordinate at the last force evaluation.
    pub compliant_force: Vec<f64>,
    /// Per stop: held closed (persistent contact).
    pub held: Vec<bool>,
    /// Per stop: λ_s of the last solve (0 while open).
    pub lambda: Vec<f64>,
    /// Per stop: ġ⁻ (≤ 0) at the current impact.
    pub closing: Vec<f64>,
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
    /// The held stops and their forces at each output time.
    pub history: StopHistory,
}

/// The stops at each output time of a run (a front end's active set and stop forces; empty for
/// a model without limits).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct StopHistory {
    /// Output times.
    pub times: Vec<f64>,
    /// Per time, per stop ([`cardan_mechanism::Model::stops`]): held closed.
    pub held: Vec<Vec<bool>>,
    /// Per time, per stop: the stop's force along its joint coordinate (N or N m; positive
    /// along the coordinate, so ≥ 0 at a lower stop and ≤ 0 at an upper one while it pushes),
    /// −λ_s ∂g/∂c; 0 while open. A compliant stop's contact force likewise.
    pub force: Vec<Vec<f64>>,
}

impl Contacts {
    /// The stops of `model` (impacts for every limit without a compliant law).
    pub fn new(model: &cardan_mechanism::Model) -> Self {
        let ns = model.stops().len();
        let watched: Vec<usize> = (0..ns)
            .filter(|&s| model.limits()[model.stops()[s].limit].compliance.is_none())
            .collect();
        let compliant: Vec<usize> = (0..ns)
            .filter(|&s| model.limits()[model.stops()[s].limit].compliance.is_some())
            .collect();
        Self {
            watched,
            compliant,
            compliant_power: vec![0.0; model.limits().len()],
            compliant_force: vec![0.0; ns],
            held: vec![false; ns],
            lambda: vec![0.0; ns],
            closing: vec![0.0; ns],
            set: Vec::with_capacity(ns),
            cols: Vec::new(),
            sol0: Vec::new(),
            w: vec![0.0; ns * ns],
            b: vec![0.0; ns],
            rows: vec![([0.0; 6], [0.0; 6]); ns],
            events: Vec::new(),
            impact_work: vec![0.0; model.limits().len()],
            rest_velocity: REST_VELOCITY,
            history: StopHistory::default(),
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
        self.history = StopHistory::default();
    }
}

/// A held stop more than this far off g = 0 (times the coordinate's scale) at a step's end is
/// brought back onto it; a run may not start further than this beyond a stop.
pub const HOLD_TOLERANCE: f64 = 1e-9;
