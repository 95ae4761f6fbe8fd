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
//! A run without held stops solves exactly as before. The stop leaves when its multiplier
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
//! impact whose closing rate |ġ⁻| is below the rest velocity (`Dynamics::set_rest_velocity`,
//! default [`REST_VELOCITY`]) holds the stop closed (e = 0), so the run rests on the stop.

mod compliant;
mod delassus;
pub(crate) mod events;
mod impact;
mod run;
pub(crate) mod small;
pub mod state;

pub use events::ImpactEvent;
pub use state::{StopHistory, HOLD_TOLERANCE, REST_VELOCITY, STOP_STABILIZATION};
