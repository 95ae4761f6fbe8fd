//! [`ImpactEvent`]: what a run records at each impact on a stop (a front end writes them as
//! `events.csv`).

/// One impact on a stop, or a stop's release.
#[derive(Debug, Clone, PartialEq)]
pub struct ImpactEvent {
    /// The contact time, located on the integrator's dense output.
    pub time: f64,
    /// The stop's name (`limit.lower` or `limit.upper`).
    pub stop: String,
    /// The limit (index into [`cardan_mechanism::Model::limits`]).
    pub limit: usize,
    /// ġ just before (≤ 0: closing), m/s or rad/s.
    pub impact_velocity: f64,
    /// The impulse the stop gave, ≥ 0 (N s or N m s along the coordinate's rate: −p of the
    /// impulse equations).
    pub impulse: f64,
    /// ġ just after (−e times the impact velocity; 0 when the stop is held).
    pub rebound_velocity: f64,
    /// Whether the stop is held closed afterwards (e = 0, or a closing rate below the rest
    /// velocity), or, for a release, false.
    pub held: bool,
    /// A release: the held stop's multiplier changed sign here and it opened (no impulse).
    pub release: bool,
    /// The kinetic energy the impact took, J (≤ 0).
    pub energy_change: f64,
}
