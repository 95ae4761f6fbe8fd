//! The energy balance of a dynamic or inverse dynamics run, E − E(t₀) − W_nc: what the
//! work-energy theorem leaves unexplained ([`cardan_dynamics::work`]), measured against the
//! run's energy scale ([`energy_scale`]) and flagged beyond [`ENERGY_BALANCE_BOUND`] of it.
//! The summary line and `run.json` report it ([`EnergyBalance`]); the warnings of both runs
//! check it.

/// A run whose energy balance (E − E(t₀) − W_nc, [`cardan_dynamics::work`]) exceeds this
/// fraction of its energy scale ([`energy_scale`]) is flagged (docs/model-format.md,
/// "Warnings").
pub const ENERGY_BALANCE_BOUND: f64 = 0.01;

/// The energy scale of a run: the largest kinetic energy, plus the range of the potential energy
/// (gravity and springs), plus the largest |work| of each driver and non-conservative force
/// element over the stored times, in J. It measures how much energy the motion exchanges and
/// the elements put in or take out, independently of the arbitrary zero of the potential.
pub fn energy_scale(e: &cardan_dynamics::EnergyHistory) -> f64 {
    let kinetic = e.kinetic.iter().fold(0.0f64, |a, &t| a.max(t));
    let potential = e.gravity.iter().zip(&e.spring).map(|(g, s)| g + s);
    let (lo, hi) = potential.fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| {
        (lo.min(v), hi.max(v))
    });
    let range = if hi >= lo { hi - lo } else { 0.0 };
    let work: f64 = e
        .elements
        .iter()
        .map(|w| w.work.iter().fold(0.0f64, |a, x| a.max(x.abs())))
        .sum();
    kinetic + range + work
}

/// The energy balance of a dynamic or inverse dynamics run: what the work-energy theorem leaves
/// unexplained, the integration (or quadrature) error ([`cardan_dynamics::work`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct EnergyBalance {
    /// max |E − E(t₀) − W_nc| over the stored times (J).
    pub max_abs: f64,
    /// The run's energy scale ([`energy_scale`], J).
    pub scale: f64,
}

impl EnergyBalance {
    /// The balance of the energy histories `e`.
    pub fn of(e: &cardan_dynamics::EnergyHistory) -> Self {
        Self {
            max_abs: e.max_balance(),
            scale: energy_scale(e),
        }
    }

    /// ", energy balance … J (… of the energy scale … J)" for the summary line.
    pub fn describe(&self) -> String {
        let mut s = format!(", energy balance {:.3e} J", self.max_abs);
        if self.scale > 0.0 {
            s.push_str(&format!(
                " ({:.1e} of the energy scale {:.3e} J)",
                self.max_abs / self.scale,
                self.scale
            ));
        }
        s
    }
}
