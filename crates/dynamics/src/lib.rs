//! # cardan-dynamics: forward and inverse dynamics of spatial mechanisms
//!
//! Above [`cardan_mechanism`]: a [`Model`](cardan_mechanism::Model) with masses and inertias
//! becomes a [`Dynamics`] (with force elements, [`Force`], and an optional user callback);
//! [`Dynamics::simulate`] integrates the equations of motion (DOPRI5 or generalized-α,
//! [`Integrator`]), [`Dynamics::inverse_dynamics`] computes driver efforts and reactions of a
//! driven mechanism. Both return [`DynamicResults`]: the mechanism's kinematic [`Results`]
//! (poses, velocities, accelerations, points, joint coordinates) plus λ, joint reactions,
//! driver efforts, energy and constraint drift. For long runs, [`Dynamics::simulate_into`] and
//! [`Dynamics::inverse_dynamics_into`] hand each output time to a [`DynamicSink`] as it is
//! computed and keep none, so memory does not grow with the number of output times.
//! Symbols follow `shared/notation.md`.
//!
//! [`Results`]: cardan_mechanism::Results
//!
//! ## Theory
//! ### Newton-Euler equations in 6 coordinates
//! Each moving body k has q_k = [r_k; p_k] and velocity v_k = [ṙ_k; ω'_k] (ω' in the body frame).
//! **The body reference point is the centre of mass** (the builder's convention: points and
//! vectors are given relative to it; the inertia J'_k is about it, in body components), so the
//! mass matrix is block diagonal (Nikravesh 1988 §11.2; Haug 1989 §11.2):
//!
//! ```text
//! M = diag(m_1 I, J'_1, m_2 I, J'_2, …),     h_k = [f_k; n'_k − ω̃'_k J'_k ω'_k]
//! ```
//!
//! with f_k the resultant applied force (global) and n'_k the applied torque about the centre of
//! mass (body frame). A body whose natural reference point is elsewhere (a crank pinned at its
//! end) is modelled with its reference at the centre of mass and the joint point offset.
//!
//! ### The augmented system
//! With the constraints Φ(q, t) = 0 (joints and drivers), their velocity equations Φ_v v = ν and
//! acceleration equations Φ_v v̇ = γ#, the equations of motion are
//!
//! ```text
//! M v̇ + Φ_vᵀ λ = h,      Φ_v v̇ = γ#        ⟺      ⎡M  Φ_vᵀ⎤⎡v̇⎤   ⎡h ⎤
//!                                                 ⎣Φ_v  0 ⎦⎣λ ⎦ = ⎣γ#⎦
//! ```
//!
//! **Sign convention:** the generalized constraint (reaction) force is −Φ_vᵀλ. The reaction of a
//! joint on body k is F = −(Φ_r,k)ᵀλ_joint (global) and, about the centre of mass in body
//! components, n' = −(Φ_π',k)ᵀλ_joint; about the joint point P (body point s'^P) the torque is
//! n'_P = n' − s̃'^P F' with F' = A_kᵀ F ([`Reaction`]). A driver's effort is −λ ∂Φ/∂c, the force
//! or torque along its driven coordinate c ([`DriverEfforts`]; ∂Φ/∂c = 2ℓ for the distance driver's
//! dᵀd − ℓ², 1 for the others). The matrix is laid out once (M blocks, Φ_v, Φ_vᵀ) and refactored with
//! the solver crate's LU (dense for small models, sparse for large); M is never inverted.
//! Equations found redundant by a rank analysis at the initial configuration (a four-bar of
//! spatial revolutes, Bricard's linkage) are dropped once; their λ is reported as 0, so the
//! reactions of redundant joints are one admissible split, not the only one.
//!
//! ### Constraint stabilization and projection (explicit integration)
//! DOPRI5 integrates y = [q; v] with ṗ = ½ Lᵀ ω' and v̇ from the augmented system. After each
//! accepted step (and at each output time) the state is projected back: positions by Newton on
//! Φ = 0 with the least-change step in the metric of M,
//! [M Φ_vᵀ; Φ_v 0][Δ; μ] = [0; −Φ], r += Δr, p ← p ⊗ exp(Δπ'/2); velocities by
//! [M Φ_vᵀ; Φ_v 0][Δv; μ] = [0; ν − Φ_v v] (i.e. v ← v − M⁻¹Φ_vᵀ(Φ_v M⁻¹Φ_vᵀ)⁻¹(Φ_v v − ν), the
//! M-weighted version, computed without M⁻¹). Baumgarte stabilization replaces γ# by
//! γ# − 2α(Φ_v v − ν) − β²Φ ([`Stabilization`]).
//!
//! ### Generalized-α (implicit, index 3)
//! For stiff models (Arnold & Brüls 2007, Lie-group form as in Brüls, Cardona & Arnold 2012):
//! with αm = (2ρ∞ − 1)/(ρ∞ + 1), αf = ρ∞/(ρ∞ + 1), γ = ½ + αf − αm, β = ¼(γ + ½)², one step
//! of size h solves for v̇_{n+1} and λ_{n+1}
//!
//! ```text
//! M v̇_{n+1} + Φ_vᵀλ_{n+1} = h(q_{n+1}, v_{n+1}, t_{n+1}),     Φ(q_{n+1}, t_{n+1}) = 0
//! (1 − αm) a_{n+1} = (1 − αf) v̇_{n+1} + αf v̇_n − αm a_n
//! v_{n+1} = v_n + h (1 − γ) a_n + h γ a_{n+1}
//! Δ = h v_n + h² (½ − β) a_n + h² β a_{n+1},     r_{n+1} = r_n + Δr,  p_{n+1} = p_n ⊗ exp(Δπ'/2)
//! ```
//!
//! by Newton on [v̇_{n+1}, λ] with the position constraint scaled by 1/β' (β' = h²β(1−αf)/(1−αm),
//! γ' = hγ(1−αf)/(1−αm)) and the iteration matrix [M + γ' C_t + β' K_t, Φ_vᵀ; Φ_v, 0]; the force
//! tangents C_t = −∂h/∂v and K_t = −∂h/∂q are finite differences over each body's six
//! coordinates (blocks of a body and of bodies coupled by spring-dampers; a user callback is
//! differentiated on its body-diagonal blocks only); the constraint Hessian term (Φ_vᵀλ)_q is
//! left out, so the Newton iteration is quasi-Newton near large reactions. Second-order
//! accurate; ρ∞ < 1 damps the high frequencies of stiff elements.
//!
//! ## Example: a pendulum
//! ```
//! use cardan_dynamics::{Dynamics, Force, Integrator, Dopri5Options, SimulationOptions};
//! use cardan_mechanism::{Body, JointSpec, MechanismBuilder, GROUND, JointKind};
//! use nalgebra::Vector3;
//!
//! // A 1 kg rod of length 1 m pinned at its end; its reference point is the centre of mass.
//! let mut b = MechanismBuilder::new();
//! b.body(Body::new("rod").mass(1.0).inertia_diagonal(1.0 / 12.0, 1.0 / 12.0, 1e-4)
//!     .position(Vector3::new(0.5, 0.0, 0.0)));
//! b.point(GROUND, "O", Vector3::zeros()).vector(GROUND, "z", Vector3::z());
//! b.point("rod", "O", Vector3::new(-0.5, 0.0, 0.0)).vector("rod", "z", Vector3::z());
//! b.joint(JointSpec::new("pin", JointKind::Revolute, (GROUND, "O"), ("rod", "O")).axes("z", "z"));
//! let model = b.build()?;
//!
//! let mut dynamics = Dynamics::new(&model)?;
//! dynamics.add_force(Force::gravity(Vector3::new(0.0, -9.81, 0.0)))?;
//! let options = SimulationOptions::new(1.0, 10)
//!     .integrator(Integrator::Dopri5(Dopri5Options::tolerances(1e-8, 1e-10)));
//! let results = dynamics.simulate(&dynamics.initial_guess(), &options)?;
//! // Energy is conserved and the pin carries the weight plus the centripetal force.
//! assert!(results.energy.max_drift() < 1e-6);
//! let pin = results.joint_reactions("pin").unwrap();
//! assert!(pin.on_j[10].force.norm() > 0.0);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
//!
//! ## Layout (one concept per file)
//! - [`system`]: [`Dynamics`] (mass data, forces, the augmented system, projections, energy,
//!   reactions) and [`Energy`].
//! - [`forces`]: [`Force`], [`VectorFunction`], [`Frame`], [`PointRef`], [`AppliedForces`],
//!   [`UserForces`].
//! - [`state`]: [`State`]. [`options`]: [`SimulationOptions`] and the integrator options.
//! - [`simulate`]: forward dynamics; [`inverse`]: inverse dynamics.
//! - [`work`]: power and work of drivers and non-conservative forces, the energy balance
//!   E − E(t₀) − W_nc (the work-energy theorem and the quadratures).
//! - [`statics`]: static and quasi-static equilibria ([`Dynamics::statics`],
//!   [`Dynamics::quasi_statics`]) and their stability; [`modal`]: the linearization about an
//!   equilibrium ([`Linearization`]) and its vibration modes ([`Dynamics::modal`]); [`moving`]:
//!   the linearization about a moving state ([`Dynamics::linearize_moving`]); `tangent`
//!   (private): the dense tangent stiffness and damping, the null-space basis;
//!   [`state_space`]: A, B, C, D for chosen force inputs and point or joint outputs, and the
//!   MatrixMarket writer [`matrix_market`].
//! - [`integrators`]: [`integrators::dopri5`], [`integrators::generalized_alpha`], each a
//!   stepper run by one driver loop (output times, limits, recording; the seam for events).
//! - `kkt` (private): the laid-out augmented system. [`results`]: [`DynamicResults`].
//!   [`error`]: [`DynamicsError`].
//!
//! ## References
//! - P. E. Nikravesh, *Computer-Aided Analysis of Mechanical Systems*, 1988, ch. 11.
//! - E. J. Haug, *Computer Aided Kinematics and Dynamics of Mechanical Systems*, 1989, ch. 11.
//! - E. Hairer, S. P. Nørsett, G. Wanner, *Solving Ordinary Differential Equations I*, §II.4–6
//!   (DOPRI5, step control, dense output).
//! - M. Arnold, O. Brüls, *Convergence of the generalized-α scheme for constrained mechanical
//!   systems*, Multibody System Dynamics 18 (2007) 185–202.
//! - J. Chung, G. M. Hulbert, *A time integration algorithm for structural dynamics with
//!   improved numerical dissipation: the generalized-α method*, J. Appl. Mech. 60 (1993).

pub mod collision;
pub mod contacts;
pub mod error;
pub mod forces;
pub mod friction;
pub mod integrators;
pub mod inverse;
mod joint_angles;
pub mod joint_space;
mod kkt;
pub mod modal;
pub mod moving;
pub mod options;
mod record;
pub mod results;
pub mod simulate;
pub mod sparse_linearization;
pub mod sparse_modal;
pub mod sparse_tangent;
pub mod state;
pub mod state_space;
pub mod statics;
pub mod system;
mod tangent;
pub mod work;

pub use contacts::events::ImpactEvent;
pub use contacts::StopHistory;
pub use error::DynamicsError;
pub use forces::{AppliedForces, Force, Frame, PointRef, UserForces, VectorFunction};
pub use friction::state::FrictionHistory;
pub use joint_space::{JointSpaceHistory, JointSpacePoint};
pub use modal::{BodyShape, Linearization, ModalOptions, ModalResults, Mode, ModeKind};
pub use options::{
    Baumgarte, Dopri5Options, GeneralizedAlphaOptions, Integrator, IterationMatrix, OptionError,
    OutputTimes, SimulationOptions, Stabilization, StepControl, ATOL_MAX, NEWTON_TOLERANCE_RANGE,
    RTOL_RANGE,
};
pub use results::{
    ContactHistory, CouplerEfforts, DriverEfforts, DynamicResults, DynamicSink, ElementWork,
    EnergyHistory, IntegrationStats, JointReactions, Reaction,
};
pub use sparse_linearization::{
    LinearizationMatrices, SparseTriplets, SPARSE_LINEARIZATION_MAX_DOF,
    SPARSE_LINEARIZATION_MAX_UNKNOWNS,
};
pub use sparse_modal::SparseModalResults;
pub use sparse_tangent::{SparseMatrix, SPARSE_MIN_BODIES};
pub use state::State;
pub use state_space::{matrix_market, matrix_market_sparse, Input, Output, StateSpace};
pub use statics::{Equilibrium, Stability, StaticOptions, StaticResults};
pub use system::{Dynamics, Energy};
