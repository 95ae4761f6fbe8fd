//! The elements of a [`Model`](super::Model) as resolved by the builder: bodies, named points and
//! vectors, joints, drivers, couplers and force elements, each with its bodies as [`BodyId`]s,
//! its rows in the global system and the [`ScatterMap`] of its Jacobian blocks. Plain data; the
//! model (`mod.rs`), the steps that build it and the predictor's spanning tree (`tree.rs`)
//! all use these types.

pub use super::curve_element::CurveElement;
use crate::builder::Compliance;
use cardan_constraints::joints::Measure;
use cardan_constraints::{Constraint, Coupler, Driver, Joint, JointLimit, PathDriver};
use nalgebra::{Matrix3, Vector3, Vector4};
use std::ops::Range;

/// Which body: ground or moving body `k` (index into [`Model::bodies`](super::Model::bodies)).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum BodyId {
    /// The ground (fixed, no unknowns).
    Ground,
    /// Moving body k.
    Moving(usize),
}

/// A moving body of the model.
#[derive(Debug, Clone, PartialEq)]
pub struct BodyInfo {
    /// Name.
    pub name: String,
    /// Mass, if given.
    pub mass: Option<f64>,
    /// Inertia about the centre of mass (body frame), if given.
    pub inertia: Option<Matrix3<f64>>,
    /// Initial position (as given).
    pub initial_r: Vector3<f64>,
    /// Initial Euler parameters (normalized).
    pub initial_p: Vector4<f64>,
}

/// A named point or vector of the model.
#[derive(Debug, Clone, PartialEq)]
pub struct FeatureInfo {
    /// The body.
    pub body: BodyId,
    /// The body's name.
    pub body_name: String,
    /// The name.
    pub name: String,
    /// Body-frame components (global for ground).
    pub local: Vector3<f64>,
}

/// Index maps of one element: where each entry of its Jacobian blocks goes.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct ScatterMap {
    /// `rows × 12` entries: `[row][side·6 + c]` → slot, or [`NO_SLOT`].
    pub(super) slots: Vec<usize>,
}

pub(crate) const NO_SLOT: usize = usize::MAX;

/// A joint of the model.
#[derive(Debug, Clone, PartialEq)]
pub struct JointInfo {
    /// Name.
    pub name: String,
    /// Body i.
    pub body_i: BodyId,
    /// Body j.
    pub body_j: BodyId,
    /// The joint (kind, markers, primitives).
    pub joint: Joint,
    /// Whether x axes were given (the zero of the joint angle): required by rotation drivers
    /// and rotational springs; without them the markers' x axes are perpendiculars the program
    /// picks and the angle is meaningful only relative to its initial value.
    pub has_x_axes: bool,
    /// Its rows in the global system.
    pub rows: Range<usize>,
    pub(crate) map: ScatterMap,
}

/// A curve element of the model (a point on a curve of body i, or a cam pair of a curve of body
/// i and one of body j), with its curve parameters as extra coordinates `extra`, `extra + 1`...
/// (columns after the bodies': 6 nb + `extra` in the 6-coordinate form, 7 nb + `extra` in the
/// Newton state).
#[derive(Debug, Clone, PartialEq)]
pub struct CurveInfo {
    /// Name.
    pub name: String,
    /// Body i (the curve's; the cam's).
    pub body_i: BodyId,
    /// Body j (the point's; the follower's).
    pub body_j: BodyId,
    /// The equations.
    pub element: CurveElement,
    /// Index of its first curve parameter among the model's extra coordinates.
    pub extra: usize,
    /// The parameters at the drawn pose (the first [`Constraint::extra`] entries).
    pub initial: [f64; cardan_constraints::MAX_EXTRA],
    /// Its rows in the global system (joint rows: they fix degrees of freedom).
    pub rows: Range<usize>,
    pub(crate) map: ScatterMap,
    /// `rows` × parameters entries, row by row: the slot of each row's parameter columns.
    pub(crate) extra_slots: Vec<usize>,
}

impl CurveInfo {
    /// The extra coordinates it owns: `extra..extra + n`.
    pub fn extras(&self) -> Range<usize> {
        self.extra..self.extra + self.element.extra()
    }
}

/// A path driver of the model: u = f(t) for the first curve parameter of curve element k.
#[derive(Debug, Clone, PartialEq)]
pub struct PathInfo {
    /// Name.
    pub name: String,
    /// The curve element (index into [`Model::curves`](super::Model::curves)).
    pub curve: usize,
    /// The extra coordinate it drives (the element's first).
    pub extra: usize,
    /// The equation.
    pub driver: PathDriver,
    /// Its row in the global system (after the drivers').
    pub rows: Range<usize>,
    /// The slot of its u column.
    pub(crate) slot: usize,
}

/// A driver of the model.
#[derive(Debug, Clone, PartialEq)]
pub struct DriverInfo {
    /// Name.
    pub name: String,
    /// Body i.
    pub body_i: BodyId,
    /// Body j.
    pub body_j: BodyId,
    /// The driver.
    pub driver: Driver,
    /// The driven joint, for rotation and translation drivers (index into [`Model::joints`](super::Model::joints)).
    pub joint: Option<usize>,
    /// Its row in the global system.
    pub rows: Range<usize>,
    pub(crate) map: ScatterMap,
}

/// One joint coordinate a coupler relates.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct CoupledCoordinate {
    /// The joint (index into [`Model::joints`](super::Model::joints)).
    pub joint: usize,
    /// Its slide z_iᵀ(P_j − P_i) (m) when true, else its angle (rad).
    pub slide: bool,
}

/// A coupler of the model: one equation between two bodies
/// ([`cardan_constraints::couplers`]) that is the law a₀ q₀ + a₁ q₁ − c = 0 between two joint
/// coordinates q₀, q₁ (gear: θ_j − ρ θ_i − c; rack and pinion: s + r θ − c; screw:
/// s − (pitch/2π) θ − c).
#[derive(Debug, Clone, PartialEq)]
pub struct CouplerInfo {
    /// Name.
    pub name: String,
    /// Body i of the equation (a gear, the rack, the nut).
    pub body_i: BodyId,
    /// Body j of the equation (the other gear, the pinion, the screw).
    pub body_j: BodyId,
    /// The equation, with its angles' references at the initial poses.
    pub coupler: Coupler,
    /// q₀ and q₁ (gear: θ_i, θ_j; rack and pinion, screw: s, θ).
    pub coordinates: [CoupledCoordinate; 2],
    /// a₀, a₁ = ∂Φ/∂q₀, ∂Φ/∂q₁.
    pub coefficients: [f64; 2],
    /// c of the law (rad for a gear, m otherwise).
    pub constant: f64,
    /// The pitch radius r_j of gear j, when the gear was given by radii (for the tooth force).
    pub gear_radius_j: Option<f64>,
    /// Its row in the global system.
    pub rows: Range<usize>,
    pub(crate) map: ScatterMap,
}

impl CouplerInfo {
    /// The kind: "gear", "rack_pinion" or "screw".
    pub fn kind(&self) -> &'static str {
        self.coupler.name()
    }
}

/// A validated force element (see [`crate::ForceSpec`]); points are body-frame vectors.
#[derive(Debug, Clone, PartialEq)]
pub enum ForceInfo {
    /// Uniform gravity.
    Gravity {
        /// g, global.
        g: Vector3<f64>,
    },
    /// Linear spring-damper between two points.
    SpringDamper {
        /// Name.
        name: String,
        /// Body i.
        body_i: BodyId,
        /// Point on body i (body frame).
        point_i: Vector3<f64>,
        /// Body j.
        body_j: BodyId,
        /// Point on body j (body frame).
        point_j: Vector3<f64>,
        /// k.
        stiffness: f64,
        /// c.
        damping: f64,
        /// ℓ0.
        free_length: f64,
    },
    /// Constant global force at a body point.
    PointForce {
        /// Name.
        name: String,
        /// The body.
        body: BodyId,
        /// Point of application (body frame).
        point: Vector3<f64>,
        /// Force, global.
        force: Vector3<f64>,
    },
    /// Constant global torque on a body.
    Torque {
        /// Name.
        name: String,
        /// The body.
        body: BodyId,
        /// Torque, global.
        torque: Vector3<f64>,
    },
}

/// A limit of the model on one joint coordinate (see [`crate::LimitSpec`]): one or two stops.
#[derive(Debug, Clone, PartialEq)]
pub struct LimitInfo {
    /// Name.
    pub name: String,
    /// The joint (index into [`Model::joints`](super::Model::joints)).
    pub joint: usize,
    /// The coordinate's name among the joint kind's coordinates.
    pub coordinate: &'static str,
    /// What it measures.
    pub measure: Measure,
    /// lo.
    pub lower: Option<f64>,
    /// hi.
    pub upper: Option<f64>,
    /// Newton's coefficient of restitution e ∈ [0, 1].
    pub restitution: f64,
    /// The compliant law, if the limit is a force rather than impacts.
    pub compliance: Option<Compliance>,
}

/// One end stop: a unilateral row g ≥ 0 of a limit (its lower or upper bound).
#[derive(Debug, Clone, PartialEq)]
pub struct StopInfo {
    /// The limit's name and the end, `name.lower` or `name.upper`.
    pub name: String,
    /// The limit (index into [`Model::limits`](super::Model::limits)).
    pub limit: usize,
    /// Body i of the joint.
    pub body_i: BodyId,
    /// Body j of the joint.
    pub body_j: BodyId,
    /// The row, with its angle's reference at the drawn pose.
    pub row: JointLimit,
}

/// Coulomb friction in a joint of the model (see [`crate::FrictionSpec`]).
#[derive(Debug, Clone, PartialEq)]
pub struct FrictionInfo {
    /// Name.
    pub name: String,
    /// The joint (index into [`Model::joints`](super::Model::joints)).
    pub joint: usize,
    /// μ.
    pub coefficient: f64,
    /// r of a rotating joint (0 for a prismatic one), m.
    pub radius: f64,
    /// N₀, N.
    pub preload: f64,
    /// v_s.
    pub stiction_velocity: f64,
    /// F_c, N: a slide's friction force independent of the load.
    pub force: f64,
    /// T_c, N m: a pin's or ball's friction torque independent of the load.
    pub torque: f64,
}
