//! # cardan-mechanism: spatial mechanisms in absolute coordinates
//!
//! Build a mechanism by name ([`MechanismBuilder`]), get an immutable [`Model`] (row ranges,
//! sparsity pattern, index maps computed once) and a preallocated [`Workspace`], then assemble,
//! count degrees of freedom, and run position, velocity and acceleration analysis at one time or
//! over a time grid ([`KinematicOptions`] → [`Results`]). Symbols follow `shared/notation.md`.
//!
//! ## Theory
//! ### Absolute coordinates
//! Every moving body k has a position r_k (global) and Euler parameters p_k (Nikravesh 1988
//! ch. 6–7; Haug 1989 ch. 9). Joints and drivers are algebraic equations Φ(q, t) = 0 between
//! pairs of bodies, built from vectors fixed in the bodies ([`cardan_constraints`]). Ground is a
//! body with no unknowns: its coordinates are eliminated (its Jacobian blocks are never
//! scattered), not constrained.
//!
//! ### Newton-Raphson in the 6-coordinate form
//! The position unknowns per body are the step [Δr_k; Δπ'_k]: a translation and a small rotation
//! in the body frame. With Φ_π' = ½ Φ_p Lᵀ the Jacobian Φ_v has 6 columns per body and there are
//! no normalization rows; each iteration solves Φ_v Δ = −Φ and updates
//!
//! ```text
//! r_k ← r_k + Δr_k,      p_k ← normalize(p_k ⊗ exp(Δπ'_k / 2))
//! ```
//!
//! where exp(θ/2) = [cos(|θ|/2), sin(|θ|/2) θ/|θ|] is the Euler-parameter vector of the rotation
//! θ. Because A(p ⊗ q) = A(p) A(q), the update rotates the body by Δπ' about its own axes, which
//! is exactly the direction linearized by Φ_π'; p stays unit by construction.
//!
//! ### Velocity and acceleration
//! With v_k = [ṙ_k; ω'_k]: Φ_v v = ν (ν = −Φ_t) and Φ_v v̇ = γ#_v, both with the matrix factored
//! at the converged position. For output, ṗ = ½ Lᵀ ω', p̈ = ½ Lᵀ ω̇' − ¼ |ω'|² p, ω = A ω',
//! ω̇ = A ω̇'; a body point s' moves with ṙ + A (ω' × s') and accelerates with
//! r̈ + A (ω̇' × s' + ω' × (ω' × s')).
//!
//! ### Degrees of freedom and redundancy
//! DOF = 6 nb − rank Φ_v (joint rows only), found by a rank-revealing QR at an assembled
//! configuration ([`dof`]); the m − rank dependent rows are the redundant equations, named by
//! joint and primitive. A kinematic analysis requires exactly DOF drivers; the redundant rows are
//! then dropped once, so every step uses a square LU, and convergence is still checked on all
//! equations (consistent redundant equations are satisfied too).
//!
//! ## Example: a driven crank
//! ```
//! use cardan_mechanism::{Body, DriverSpec, JointSpec, KinematicOptions, MechanismBuilder, GROUND};
//! use cardan_constraints::{JointKind, TimeFunction};
//! use nalgebra::Vector3;
//!
//! let mut b = MechanismBuilder::new();
//! b.body(Body::new("crank").mass(1.0).inertia_diagonal(0.1, 0.1, 0.01)
//!     .position(Vector3::new(0.5, 0.0, 0.0)));
//! b.point(GROUND, "O", Vector3::zeros()).vector(GROUND, "z", Vector3::z()).vector(GROUND, "x", Vector3::x());
//! b.point("crank", "O", Vector3::new(-0.5, 0.0, 0.0)).point("crank", "tip", Vector3::new(0.5, 0.0, 0.0));
//! b.vector("crank", "z", Vector3::z()).vector("crank", "x", Vector3::x());
//! b.joint(JointSpec::new("pivot", JointKind::Revolute, (GROUND, "O"), ("crank", "O"))
//!     .axes("z", "z").x_axes("x", "x"));
//! b.driver(DriverSpec::rotation("motor", "pivot", TimeFunction::Polynomial(vec![0.0, 1.0])));
//! let model = b.build()?;
//!
//! let results = model.run_kinematics(&KinematicOptions::new(0.0, 1.0, 10))?;
//! let tip = results.point("crank", "tip").unwrap();
//! // After 1 s at 1 rad/s the tip is at (cos 1, sin 1, 0).
//! assert!((tip.position[10] - Vector3::new(1f64.cos(), 1f64.sin(), 0.0)).norm() < 1e-9);
//! assert!((results.joint("pivot").unwrap().values[10][0] - 1.0).abs() < 1e-9);
//! # Ok::<(), cardan_mechanism::Error>(())
//! ```
//!
//! ## Layout (one concept per file)
//! - [`equation`]: [`EquationName`], the name of a global equation.
//! - [`results`]: [`Results`] and [`DroppedRowResidual`]. [`error`]: [`ModelError`],
//!   [`AnalysisError`]. [`sanity`]: the magnitude limits of the builder's numbers.
//! - [`builder`]: [`MechanismBuilder`], [`Body`], [`Orientation`], [`JointSpec`], [`DriverSpec`].
//! - [`hold`]: a limit's stop held by a constant driver (statics and modes resting on a stop).
//! - [`model`]: the immutable [`Model`], its elements and its validation.
//! - [`dof`]: the [`DofReport`].
//! - [`workspace`]: the preallocated [`Workspace`] and the rotation update.
//! - [`analysis`]: degrees of freedom, assembly, position, velocity, acceleration, time grid.
//!
//! The files are layered in this order: a file imports only files listed before it (or below
//! it in its own folder), never one above it, so there is no import circle to untangle.

pub mod analysis;
pub mod builder;
pub mod curve_spec;
pub mod dof;
pub mod equation;
pub mod error;
pub mod hold;
pub mod model;
pub mod results;
pub mod sanity;
pub mod shape_spec;
pub mod workspace;

pub use analysis::assembly::{AssemblyOptions, AssemblyReport};
pub use analysis::drag::{Drag, DragReport, DragStop, DRAG_WEIGHTS};
pub use analysis::dropped::{gross_inconsistency, DroppedRowResidual, DroppedRowSample};
pub use analysis::grid::KinematicOptions;
pub use analysis::least_change::{
    BodyWeights, FreeDof, HoldMetric, LeastChange, LeastChangeReport, PointGoal,
};
pub use analysis::position::{
    OpenRow, PositionReport, FAST_RANK_MIN_UNKNOWNS, KINEMATIC_MAX_CHORD_STEPS,
    SELECTION_PIVOT_TOLERANCE,
};
pub use builder::{
    pose_row_name, Axis, Body, Compliance, CouplerKind, CouplerSpec, DriverSpec, DriverTarget,
    ForceSpec, FrictionSpec, GearRatio, JointSpec, LimitSpec, MechanismBuilder, Orientation,
    PoseTarget, GROUND,
};
pub use curve_spec::{CamSpec, CurveSpec, PathSpec, SurfaceSpec};
pub use dof::DofReport;
pub use error::{
    runs_on, AnalysisError, ElementKind, EquationName, Error, ModelError, OpenElement, Site,
};
pub use model::{
    kinds_with, may_touch, nearest, BodyId, BodyInfo, CoupledCoordinate, CouplerInfo, CurveElement,
    CurveInfo, DriverInfo, FeatureInfo, ForceInfo, FrictionInfo, JointInfo, LimitInfo,
    MaterialInfo, Model, PathInfo, ShapeInfo, StopInfo, FRICTION_KINDS, MESH_VERTEX_LIMIT,
};
pub use results::{
    BodyResults, CurveResults, FrameSink, JointResults, Outputs, PointResults, Results, RunTotals,
};
pub use sanity::{check_inertia, Quantity};
pub use shape_spec::{Geometry, MaterialSpec, ShapeSpec, Stiffness};
pub use workspace::{apply_rotation_step, EvaluationCounts, Workspace};

/// Re-exported so users name the same types.
pub use cardan_constraints::{JointKind, TimeFunction};

/// The README's Rust example, compiled and run as a doctest (`cargo test --doc`), so the
/// README cannot show Rust that does not build.
#[cfg(doctest)]
#[doc = include_str!("../../../README.md")]
pub struct ReadmeDoctests;
pub use nalgebra;
