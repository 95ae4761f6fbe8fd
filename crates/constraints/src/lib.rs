//! # cardan-constraints: every equation a mechanism can contain
//!
//! Constraint primitives, joints and drivers in absolute coordinates with Euler parameters, each
//! with Φ, its exact Jacobian in the 7-coordinate form (Φ_q, columns [r_i, p_i, r_j, p_j]) and in
//! the 6-coordinate form (Φ_v, columns [ṙ_i, ω'_i, ṙ_j, ω'_j]), ν = −Φ_t and γ# in both forms
//! (Nikravesh 1988 ch. 7, Haug 1989 ch. 9; symbols of `shared/notation.md`).
//!
//! ## Theory
//! A constraint Φ(q, t) = 0 between bodies i and j is built from vectors fixed in the bodies:
//! directions s_k = A_k s'_k and points r^P_k = r_k + A_k s'^P_k. Differentiating once in time
//! gives the velocity equation Φ_q q̇ = ν = −Φ_t; twice, the acceleration equation
//! Φ_q q̈ = γ#, where γ# is minus everything in Φ̈ that is not Φ_q q̈:
//! γ# = −(Φ_q q̇)_q q̇ − 2 Φ_qt q̇ − Φ_tt. For a body-fixed vector the needed pieces are
//!
//! - 7-coordinate: ∂(A s')/∂p = 2 (G s̄' + s' pᵀ) (the seed's C and B), rate C(p) ṗ, and, because
//!   A(p) is quadratic in p, the velocity-quadratic acceleration C(ṗ) ṗ;
//! - 6-coordinate: ∂(A s')/∂π' = −A s̃', rate A (ω' × s'), acceleration A (ω' × (ω' × s')).
//!
//! [`jet`] holds these per-vector formulas and the product rules for dot and cross products;
//! every primitive is written once with them, generic over the form ([`Q7`] or [`V6`]).
//!
//! ## Primitives (one file each)
//! [`N1`] (s_iᵀ s_j), [`N2`] (s_iᵀ d), [`P1`] / [`P2`] (s̃_i s_j, s̃_i d: three rows, rank 2),
//! their two-row forms [`P1Perp`] / [`P2Perp`] (body-fixed f_i, g_i ⟂ s_i; always rank 2) and
//! [`P1Select`] / [`P2Select`] (the seed's choice of two rows, made once in body i's frame so it
//! never chatters), [`Spherical`] (r^P_i − r^P_j), [`Distance`] (dᵀd − ℓ²) and
//! [`Normalization`] (pᵀp − 1), [`RadialDistance`] ((f_iᵀd)² + (g_iᵀd)² − ℓ²: a point at a
//! distance from a line) and [`Homokinetic`] (x_iᵀy_j − y_iᵀx_j: no relative twist about z).
//! [`Primitive`] is the closed enum over them.
//!
//! ## Joints and drivers
//! [`Joint`]s are lists of primitives built from two [`Marker`]s (see [`joints`] for the table);
//! [`Driver`]s add time-dependent rows with a [`TimeFunction`].
//!
//! ## Couplers
//! [`Coupler`]s ([`couplers`]: gear, rack and pinion, screw) relate the coordinates of two
//! joints by one equation between two bodies, with angles continued over turns.
//!
//! ## Limits
//! A [`JointLimit`] ([`limit`]) is one unilateral row g = ±(c − lo/hi) ≥ 0 on a joint
//! coordinate c (any [`joints::Measure`]); analyses treat it as an equality only where it is
//! closed.
//!
//! ## Curves and higher pairs
//! [`curves`] holds curves fixed in a body (line, circle, helix, cubic spline through points, open
//! or closed) with their derivatives in the curve parameter u. A [`PointOnCurve`] keeps a point of
//! body j on a curve of body i with u as an *extra coordinate* of the element
//! ([`Constraint::extra`], [`Constraint::jacobian_extra`], read from [`BodyPair::u`]); a
//! [`PathDriver`] prescribes it in time. A [`CurveOnCurve`] keeps a planar curve of body j
//! tangent to one of body i (a cam and its roller, flat face or profile follower), both curve
//! parameters extra coordinates. [`surfaces`] holds surfaces (plane, sphere, cylinder, torus,
//! bicubic patch) with their derivatives in (u, v); a [`PointOnSurface`] keeps a point of body j
//! on a surface of body i with u and v two extra coordinates.
//!
//! ## Evaluation
//! All of them implement [`Constraint`]. Evaluation takes a [`BodyPair`] (pose, cached A and
//! velocities of bodies i and j; ground is [`BodyState::ground`]) and writes into caller slices:
//! it cannot fail and does not allocate. The [`Footprint`] says which coordinate blocks the rows
//! touch, before any evaluation.
//!
//! ```
//! use cardan_constraints::{BodyPair, BodyState, Constraint, Joint, JointKind, Marker};
//! use nalgebra::{Vector3, Vector4};
//! // A revolute joint about global z between ground and a body at (1, 0, 0).
//! let m_ground = Marker::from_axis(Vector3::new(0.0, 0.0, 0.0), Vector3::z()).unwrap();
//! let m_body = Marker::from_axis(Vector3::new(-1.0, 0.0, 0.0), Vector3::z()).unwrap();
//! let joint = Joint::new(JointKind::Revolute, m_ground, m_body).unwrap();
//! let ground = BodyState::ground();
//! let body = BodyState::at(Vector3::new(1.0, 0.0, 0.0), Vector4::new(1.0, 0.0, 0.0, 0.0));
//! let mut phi = [0.0; 5];
//! joint.phi(&BodyPair::new(&ground, &body), 0.0, &mut phi);
//! assert!(phi.iter().all(|v| v.abs() < 1e-15));
//! ```
//!
//! ## How to add a primitive
//! 1. Write `src/<name>.rs`: a struct with the body-fixed vectors, a module doc with Φ, the
//!    Jacobian blocks, γ#, the footprint and the book reference, and `impl Constraint`. Write
//!    `jacobian` and `gamma_sharp` once, generically, with [`jet::Grad`] and [`jet::Motion`]:
//!    e.g. for Φ = s_iᵀ d,
//!    `Grad::dir::<F>(.., Side::I, &s_i).dot(&Grad::between::<F>(.., &sp_i, &sp_j))` gives both
//!    Jacobian rows, and `-Motion::dir(..).dot(&Motion::between(..)).quad` gives γ#.
//! 2. Add a variant to [`Primitive`] and to its `dispatch!` and `from_variant!` lists.
//! 3. Add one line to the conformance test list in `tests/conformance.rs` (finite-difference
//!    checks of Φ_q, Φ_v, ν and γ# in both forms, footprint, curated + random inputs).
//! 4. Add it to the oracle (`oracle/README.md`), regenerate with `cargo xtask oracle`, and add it
//!    to the registry in `tests/src/registry.rs` of the workspace: the oracle gate fails for an
//!    element without reference data.

#[macro_use]
mod macros;

pub mod conformance;
pub mod constraint;
pub mod couplers;
pub mod curve_on_curve;
pub mod curves;
pub mod distance;
pub mod drivers;
pub mod error;
pub mod expression;
pub mod homokinetic;
pub mod jet;
pub mod joints;
pub mod limit;
pub mod marker;
pub mod n1;
pub mod n2;
pub mod normalization;
pub mod p1;
pub mod p1_perp;
pub mod p1_select;
pub mod p2;
pub mod p2_perp;
pub mod p2_select;
pub mod path_driver;
pub mod point_on_curve;
pub mod point_on_surface;
pub mod primitive;
pub mod radial_distance;
pub mod spherical;
pub mod spline;
pub mod state;
pub mod surfaces;
pub mod time_function;

pub use constraint::{Constraint, Dimension, MAX_EXTRA};
pub use couplers::{Coupler, Gear, RackPinion, Screw};
pub use curve_on_curve::CurveOnCurve;
pub use curves::{ArcLength, Circle, CubicCurve, Curve, CurveJet, Helix, Line};
pub use distance::Distance;
pub use drivers::{
    CoordinateDriver, DistanceDriver, Driver, PoseDriver, RotationDriver, RotationOrder,
    TranslationDriver,
};
pub use error::ConstraintError;
pub use expression::Expression;
pub use homokinetic::Homokinetic;
pub use jet::{Form, Q7, V6};
pub use joints::{unwrap_angle, Joint, JointCoordinates, JointKind, JointParams, KindInfo, KINDS};
pub use limit::{Bound, JointLimit};
pub use marker::Marker;
pub use n1::N1;
pub use n2::N2;
pub use normalization::Normalization;
pub use p1::P1;
pub use p1_perp::P1Perp;
pub use p1_select::P1Select;
pub use p2::P2;
pub use p2_perp::P2Perp;
pub use p2_select::P2Select;
pub use path_driver::PathDriver;
pub use point_on_curve::PointOnCurve;
pub use point_on_surface::PointOnSurface;
pub use primitive::Primitive;
pub use radial_distance::RadialDistance;
pub use spherical::Spherical;
pub use spline::Spline;
pub use state::{BlockUse, BodyPair, BodyState, Footprint};
pub use surfaces::{BicubicPatch, Cylinder, Plane, Sphere, Surface, SurfaceJet, Torus};
pub use time_function::TimeFunction;
