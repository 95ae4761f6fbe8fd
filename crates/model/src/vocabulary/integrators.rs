//! `[analysis] integrator = ...` of a dynamic analysis: the integrators and their keys (in
//! `[analysis]` too). Their ranges are the library's (`cardan_dynamics::Integrator::validate`),
//! and a refusal is placed at the key.

use super::{Default, Entry, Key, Value, Vocabulary};
use cardan_mechanism::Quantity;

const DT: Key = Key::new(
    "dt",
    Value::Number(Quantity::Time),
    Default::Is("DOPRI5: adaptive steps; generalized-α: 1e-3"),
    "the integration step (DOPRI5: fixed steps instead of rtol/atol)",
);
const RTOL: Key = Key::new(
    "rtol",
    Value::Number(Quantity::Unbounded),
    Default::Is("1e-6"),
    "relative tolerance of the adaptive steps",
);
const ATOL: Key = Key::new(
    "atol",
    Value::Number(Quantity::Unbounded),
    Default::Is("1e-8"),
    "absolute tolerance of the adaptive steps",
);
const H_MAX: Key = Key::new(
    "h_max",
    Value::Number(Quantity::Time),
    Default::Is("t_end − t_start"),
    "the largest adaptive step",
);
const RHO_INF: Key = Key::new(
    "rho_inf",
    Value::Number(Quantity::Unbounded),
    Default::Is("0.8"),
    "spectral radius at infinity ρ∞ ∈ [0, 1]: the damping of the highest frequencies",
);
const NEWTON_TOLERANCE: Key = Key::new(
    "newton_tolerance",
    Value::Number(Quantity::Unbounded),
    Default::Is("1e-10"),
    "the tolerance of each step's Newton iteration",
);

/// Every integrator key, for the dynamic analysis's entry.
pub(super) const KEYS: [Key; 6] = [DT, RTOL, ATOL, H_MAX, RHO_INF, NEWTON_TOLERANCE];

/// The integrators of a dynamic analysis.
pub const INTEGRATORS: Vocabulary = Vocabulary {
    what: "integrator",
    table: "[analysis] of kind = \"dynamic\"",
    selector: "integrator",
    common: &[],
    entries: &[
        Entry {
            name: "dopri5",
            aliases: &[],
            summary: "explicit Dormand–Prince 5(4), adaptive steps with error control (or fixed), the constraints projected after each step",
            keys: &[DT, RTOL, ATOL, H_MAX],
        },
        Entry {
            name: "generalized_alpha",
            aliases: &[],
            summary: "implicit index-3 generalized-α (Chung–Hulbert, Arnold–Brüls), fixed step: for stiff models",
            keys: &[DT, RHO_INF, NEWTON_TOLERANCE],
        },
    ],
};
