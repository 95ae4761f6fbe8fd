//! The immutable [`Model`]: moving bodies, joints and drivers with their row ranges, the global
//! sparsity pattern of Φ_v and the index maps that scatter each element's blocks into the
//! solver's slot array. Everything here is computed once, by [`crate::MechanismBuilder::build`].
//!
//! ## Layout of the global system
//! Unknowns (6-coordinate form): for moving body k, columns 6k..6k+3 are Δr_k (ṙ_k) and
//! 6k+3..6k+6 are Δπ'_k (ω'_k). Ground has no columns. Equations: the joints in declaration
//! order, then the couplers, then the drivers, each a contiguous row range. The pattern holds, for each row, the
//! declared r and p blocks ([`cardan_constraints::Footprint`]) of each moving body of its
//! element, so a step only refills values.

//!
//! The module is laid out by responsibility: this file holds the model and its accessors;
//! `build` checks a builder and assembles a model from `resolve` (name resolution, one
//! function per element kind, with the checks of `validate`) and `layout` (rows, pattern,
//! scatter maps, scales); `eval` evaluates Φ, ν, γ# and Φ_v on body states.

mod build;
mod couplers;
mod eval;
mod layout;
mod resolve;
mod validate;

pub(crate) use build::build;
pub use validate::{kinds_with, nearest};

use crate::builder::GROUND;
use crate::error::EquationName;
use crate::workspace::Workspace;
use cardan_constraints::{Constraint, Coupler, Driver, Joint};
use cardan_solver::SparsityPattern;
use nalgebra::{Matrix3, Vector3, Vector4};
use std::ops::Range;

/// Which body: ground or moving body `k` (index into [`Model::bodies`]).
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
    slots: Vec<usize>,
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
    /// The driven joint, for rotation and translation drivers (index into [`Model::joints`]).
    pub joint: Option<usize>,
    /// Its row in the global system.
    pub rows: Range<usize>,
    pub(crate) map: ScatterMap,
}

/// One joint coordinate a coupler relates.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct CoupledCoordinate {
    /// The joint (index into [`Model::joints`]).
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

/// The immutable mechanism. Build it with [`crate::MechanismBuilder`]; run analyses on a
/// [`Workspace`] made by [`Model::workspace`].
#[derive(Debug, Clone)]
pub struct Model {
    pub(crate) bodies: Vec<BodyInfo>,
    pub(crate) points: Vec<FeatureInfo>,
    pub(crate) vectors: Vec<FeatureInfo>,
    pub(crate) joints: Vec<JointInfo>,
    pub(crate) drivers: Vec<DriverInfo>,
    pub(crate) couplers: Vec<CouplerInfo>,
    pub(crate) forces: Vec<ForceInfo>,
    pub(crate) pattern: SparsityPattern,
    pub(crate) equation_scales: Vec<f64>,
    pub(crate) unknown_scales: Vec<f64>,
    pub(crate) length: f64,
    pub(crate) num_rows: usize,
    pub(crate) joint_rows: usize,
    /// The kinematic predictor's spanning tree.
    pub(crate) tree: crate::analysis::predictor::PredictorTree,
    /// Body index by name (names are unique).
    pub(crate) body_at: std::collections::HashMap<String, usize>,
    /// Joint index by name.
    pub(crate) joint_at: std::collections::HashMap<String, usize>,
}

impl Model {
    /// Number of moving bodies nb.
    pub fn num_bodies(&self) -> usize {
        self.bodies.len()
    }

    /// The moving bodies.
    pub fn bodies(&self) -> &[BodyInfo] {
        &self.bodies
    }

    /// The id of body `name` (`"ground"` → [`BodyId::Ground`]).
    pub fn body_id(&self, name: &str) -> Option<BodyId> {
        if name == GROUND {
            return Some(BodyId::Ground);
        }
        self.body_at.get(name).map(|&k| BodyId::Moving(k))
    }

    /// The name of a body.
    pub fn body_name(&self, id: BodyId) -> &str {
        match id {
            BodyId::Ground => GROUND,
            BodyId::Moving(k) => &self.bodies[k].name,
        }
    }

    /// All named points (ground's included), in declaration order.
    pub fn points(&self) -> &[FeatureInfo] {
        &self.points
    }

    /// All named vectors, in declaration order.
    pub fn vectors(&self) -> &[FeatureInfo] {
        &self.vectors
    }

    /// Index (into [`Model::points`]) of point `name` on `body`.
    pub fn point_index(&self, body: &str, name: &str) -> Option<usize> {
        self.points
            .iter()
            .position(|p| p.body_name == body && p.name == name)
    }

    /// The joints, in declaration order (rows first).
    pub fn joints(&self) -> &[JointInfo] {
        &self.joints
    }

    /// The drivers, in declaration order (rows after the joints).
    pub fn drivers(&self) -> &[DriverInfo] {
        &self.drivers
    }

    /// The couplers, in declaration order (rows after the joints, before the drivers).
    pub fn couplers(&self) -> &[CouplerInfo] {
        &self.couplers
    }

    /// The force elements, in declaration order (for dynamic analysis).
    pub fn forces(&self) -> &[ForceInfo] {
        &self.forces
    }

    /// Index of joint `name`.
    pub fn joint_index(&self, name: &str) -> Option<usize> {
        self.joint_at.get(name).copied()
    }

    /// Total number of equations m (joints + drivers).
    pub fn num_equations(&self) -> usize {
        self.num_rows
    }

    /// Number of joint and coupler equations (the first rows: the constraints that are not
    /// drivers, which fix the degrees of freedom).
    pub fn num_joint_equations(&self) -> usize {
        self.joint_rows
    }

    /// Number of unknowns n = 6 nb (6-coordinate form).
    pub fn num_unknowns(&self) -> usize {
        6 * self.bodies.len()
    }

    /// The sparsity pattern of Φ_v (all equations × 6 nb).
    pub fn pattern(&self) -> &SparsityPattern {
        &self.pattern
    }

    /// Characteristic length L of the model (m), used to scale convergence tests.
    pub fn characteristic_length(&self) -> f64 {
        self.length
    }

    /// Scale of each equation (L for lengths, L² for squared distances, 1 for directions).
    pub fn equation_scales(&self) -> &[f64] {
        &self.equation_scales
    }

    /// Scale of each unknown (L for Δr, 1 for Δπ').
    pub fn unknown_scales(&self) -> &[f64] {
        &self.unknown_scales
    }

    /// The name of global equation `row` (element, kind, primitive).
    pub fn equation(&self, row: usize) -> Option<EquationName> {
        // Elements own consecutive row ranges in declaration order: a binary search each.
        let k = self.joints.partition_point(|j| j.rows.end <= row);
        if let Some(j) = self.joints.get(k).filter(|j| j.rows.contains(&row)) {
            let local = row - j.rows.start;
            let primitive = j.joint.row_origin(local).map_or("?", |(_, n)| n);
            return Some(EquationName {
                row,
                element: j.name.clone(),
                kind: j.joint.kind().name(),
                primitive,
                local_row: local,
            });
        }
        let k = self.couplers.partition_point(|c| c.rows.end <= row);
        if let Some(c) = self.couplers.get(k).filter(|c| c.rows.contains(&row)) {
            return Some(EquationName {
                row,
                element: c.name.clone(),
                kind: c.kind(),
                primitive: c.kind(),
                local_row: 0,
            });
        }
        let k = self.drivers.partition_point(|d| d.rows.end <= row);
        if let Some(d) = self.drivers.get(k).filter(|d| d.rows.contains(&row)) {
            return Some(EquationName {
                row,
                element: d.name.clone(),
                kind: d.driver.name(),
                primitive: d.driver.name(),
                local_row: row - d.rows.start,
            });
        }
        None
    }

    /// A fresh workspace at the initial poses (allocates every buffer a run needs).
    pub fn workspace(&self) -> Workspace {
        Workspace::new(self)
    }
}
