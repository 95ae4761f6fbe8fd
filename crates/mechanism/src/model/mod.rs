//! The immutable [`Model`]: moving bodies, joints and drivers with their row ranges, the global
//! sparsity pattern of Φ_v and the index maps that scatter each element's blocks into the
//! solver's slot array. Everything here is computed once, by [`crate::MechanismBuilder::build`].
//!
//! ## Layout of the global system
//! Unknowns (6-coordinate form): for moving body k, columns 6k..6k+3 are Δr_k (ṙ_k) and
//! 6k+3..6k+6 are Δπ'_k (ω'_k); after the bodies, column 6 nb + k is the extra coordinate k (the
//! curve parameter u of point-on-curve element k; entry 7 nb + k of the Newton state). Ground
//! has no columns. Equations: the joints in declaration order, then the point-on-curve
//! elements, the couplers, the drivers, each a contiguous row range. The pattern holds, for
//! each row, the declared r and p blocks ([`cardan_constraints::Footprint`]) of each moving
//! body of its element (and a curve element's u column), so a step only refills values.

//!
//! The module is laid out by responsibility, in layers: `elements` holds the element records
//! (bodies, features, joints, drivers, couplers, forces, with [`BodyId`] and the scatter maps)
//! and `tree` the predictor's spanning tree of the joints; this file holds the model and its
//! accessors; `build` checks a builder and assembles a model from `resolve` (name resolution,
//! one function per element kind, with the checks of `validate`) and `layout` (rows, pattern,
//! scatter maps, scales); `eval` evaluates Φ, ν, γ# and Φ_v on body states.

mod build;
mod couplers;
mod curvature;
mod curve;
mod curve_element;
mod elements;
mod eval;
mod friction;
mod layout;
mod limits;
mod resolve;
mod shapes;
mod stops;
mod tree;
mod validate;

pub use elements::{
    BodyId, BodyInfo, CoupledCoordinate, CouplerInfo, CurveElement, CurveInfo, DriverInfo,
    FeatureInfo, ForceInfo, FrictionInfo, JointInfo, LimitInfo, PathInfo, StopInfo,
};
pub use friction::FRICTION_KINDS;
pub use shapes::{may_touch, MaterialInfo, ShapeInfo, MESH_VERTEX_LIMIT};
pub(crate) use tree::{PredictorTree, TreeEdge};
pub use validate::{kinds_with, nearest};

use crate::builder::GROUND;
use crate::equation::EquationName;
use cardan_constraints::Constraint;
use cardan_solver::SparsityPattern;

/// The immutable mechanism. Build it with [`crate::MechanismBuilder`]; run analyses on a
/// [`Workspace`](crate::Workspace) made by [`Model::workspace`].
#[derive(Debug, Clone)]
pub struct Model {
    pub(crate) bodies: Vec<BodyInfo>,
    pub(crate) points: Vec<FeatureInfo>,
    pub(crate) vectors: Vec<FeatureInfo>,
    pub(crate) joints: Vec<JointInfo>,
    pub(crate) curves: Vec<CurveInfo>,
    pub(crate) paths: Vec<PathInfo>,
    pub(crate) drivers: Vec<DriverInfo>,
    pub(crate) couplers: Vec<CouplerInfo>,
    pub(crate) forces: Vec<ForceInfo>,
    pub(crate) limits: Vec<LimitInfo>,
    pub(crate) stops: Vec<StopInfo>,
    pub(crate) frictions: Vec<FrictionInfo>,
    pub(crate) shapes: Vec<ShapeInfo>,
    pub(crate) materials: Vec<MaterialInfo>,
    pub(crate) pattern: SparsityPattern,
    pub(crate) equation_scales: Vec<f64>,
    pub(crate) unknown_scales: Vec<f64>,
    pub(crate) length: f64,
    pub(crate) num_rows: usize,
    pub(crate) joint_rows: usize,
    /// The kinematic predictor's spanning tree.
    pub(crate) tree: PredictorTree,
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

    /// Number of unknowns n = 6 nb + n_u (6-coordinate form): the bodies', then the extra
    /// coordinates (the curve parameters of the curve elements).
    pub fn num_unknowns(&self) -> usize {
        6 * self.bodies.len() + self.num_extra()
    }

    /// Number of extra coordinates n_u (curve parameters), after the bodies' in every vector
    /// of unknowns: column 6 nb + k of Φ_v, entry 7 nb + k of the Newton state.
    pub fn num_extra(&self) -> usize {
        self.curves.last().map_or(0, |c| c.extras().end)
    }

    /// The curve elements (points on curves, then cam pairs), in declaration order, each owning
    /// the extra coordinates [`CurveInfo::extras`] (in element order).
    pub fn curves(&self) -> &[CurveInfo] {
        &self.curves
    }

    /// The path drivers (each prescribes a curve element's parameter), after the drivers.
    pub fn paths(&self) -> &[PathInfo] {
        &self.paths
    }

    /// The extra coordinates (curve parameters) of a Newton state `x` (7 nb + n_u entries).
    pub fn extras_of<'a>(&self, x: &'a [f64]) -> &'a [f64] {
        &x[7 * self.bodies.len()..]
    }

    /// The extra coordinates' rates of a velocity vector `v` (6 nb + n_u entries).
    pub fn extra_rates_of<'a>(&self, v: &'a [f64]) -> &'a [f64] {
        &v[6 * self.bodies.len()..]
    }

    /// The sparsity pattern of Φ_v (all equations × (6 nb + n_u)).
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
        let k = self.curves.partition_point(|c| c.rows.end <= row);
        if let Some(c) = self.curves.get(k).filter(|c| c.rows.contains(&row)) {
            return Some(EquationName {
                row,
                element: c.name.clone(),
                kind: c.element.kind(),
                primitive: c.element.name(),
                local_row: row - c.rows.start,
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
        let k = self.paths.partition_point(|p| p.rows.end <= row);
        if let Some(p) = self.paths.get(k).filter(|p| p.rows.contains(&row)) {
            return Some(EquationName {
                row,
                element: p.name.clone(),
                kind: "path_driver",
                primitive: "path_driver",
                local_row: 0,
            });
        }
        None
    }
}
