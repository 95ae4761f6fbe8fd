//! Time integrators (generic numerical schemes applied to the equations of motion).
//!
//! - [`dopri5`]: explicit Dormand-Prince 5(4), adaptive or fixed step, dense output,
//!   projection or Baumgarte stabilization.
//! - [`generalized_alpha`]: implicit index-3 generalized-α (Arnold & Brüls 2007) with Newton on
//!   [v̇, λ] and the rotation update p ⊗ exp(Δπ'/2).
//! - `tangents`: the force tangents of generalized-α's iteration matrix (block-sparse,
//!   coloured finite differences).

pub mod dopri5;
pub mod generalized_alpha;
mod tangents;
