//! The immutable [`Model`]: moving bodies, joints and drivers with their row ranges, the global
//! sparsity pattern of Φ_v and the index maps that scatter each element's blocks into the
//! solver's slot array. Everything here is computed once, by [`crate::MechanismBuilder::build`].
//!
//! ## Layout of the global system
//! Unknowns (6-coordinate form): for moving body k, columns 6k..6k+3 are Δr_k (ṙ_k) and
//! 6k+3..6k+6 are Δπ'_k (ω'_k). Ground has no columns. Equations: the joints in declaration
//! order, then the drivers, each a contiguous row range. The pattern holds, for each row, the
//! declared r and p blocks ([`cardan_constraints::Footprint`]) of each moving body of its
//! element, so a step only refills values.

use crate::builder::{DriverTarget, ForceSpec, MechanismBuilder, Orientation, GROUND};
use crate::error::{EquationName, ModelError};
use crate::sanity::Quantity;
use crate::workspace::Workspace;
use cardan_constraints::{
    BodyPair, BodyState, Constraint, CoordinateDriver, DistanceDriver, Driver, Footprint, Joint,
    JointKind, Marker, RotationDriver, TranslationDriver,
};
use cardan_solver::SparsityPattern;
use nalgebra::{Matrix3, Vector3, Vector4};
use std::collections::HashMap;
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
    pub(crate) forces: Vec<ForceInfo>,
    pub(crate) pattern: SparsityPattern,
    pub(crate) equation_scales: Vec<f64>,
    pub(crate) unknown_scales: Vec<f64>,
    pub(crate) length: f64,
    pub(crate) num_rows: usize,
    pub(crate) joint_rows: usize,
    /// The kinematic predictor's spanning tree.
    pub(crate) tree: crate::analysis::predictor::PredictorTree,
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
        self.bodies
            .iter()
            .position(|b| b.name == name)
            .map(BodyId::Moving)
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

    /// The force elements, in declaration order (for dynamic analysis).
    pub fn forces(&self) -> &[ForceInfo] {
        &self.forces
    }

    /// Index of joint `name`.
    pub fn joint_index(&self, name: &str) -> Option<usize> {
        self.joints.iter().position(|j| j.name == name)
    }

    /// Total number of equations m (joints + drivers).
    pub fn num_equations(&self) -> usize {
        self.num_rows
    }

    /// Number of joint equations (the first rows).
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
        for j in &self.joints {
            if j.rows.contains(&row) {
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
        }
        for d in &self.drivers {
            if d.rows.contains(&row) {
                return Some(EquationName {
                    row,
                    element: d.name.clone(),
                    kind: d.driver.name(),
                    primitive: d.driver.name(),
                    local_row: row - d.rows.start,
                });
            }
        }
        None
    }

    /// A fresh workspace at the initial poses (allocates every buffer a run needs).
    pub fn workspace(&self) -> Workspace {
        Workspace::new(self)
    }

    // ----- evaluation (6-coordinate form) on given body states -----

    pub(crate) fn state<'a>(
        bodies: &'a [BodyState],
        ground: &'a BodyState,
        id: BodyId,
    ) -> &'a BodyState {
        match id {
            BodyId::Ground => ground,
            BodyId::Moving(k) => &bodies[k],
        }
    }

    fn each<F>(&self, mut f: F)
    where
        F: FnMut(&dyn ElementEval, BodyId, BodyId, &Range<usize>, &ScatterMap),
    {
        for j in &self.joints {
            f(&j.joint, j.body_i, j.body_j, &j.rows, &j.map);
        }
        for d in &self.drivers {
            f(&d.driver, d.body_i, d.body_j, &d.rows, &d.map);
        }
    }

    /// Fills `out` (one entry per equation) element by element with `eval`, which writes an
    /// element's rows for its body pair: the one loop behind Φ, ν and γ#.
    fn rows_into(
        &self,
        bodies: &[BodyState],
        t: f64,
        out: &mut [f64],
        eval: impl Fn(&dyn ElementEval, &BodyPair, f64, &mut [f64]),
    ) {
        let g = BodyState::ground();
        self.each(|e, bi, bj, rows, _| {
            let pair = BodyPair::new(Self::state(bodies, &g, bi), Self::state(bodies, &g, bj));
            eval(e, &pair, t, &mut out[rows.clone()]);
        });
    }

    pub(crate) fn phi_into(&self, bodies: &[BodyState], t: f64, out: &mut [f64]) {
        self.rows_into(bodies, t, out, |e, x, t, o| e.phi_dyn(x, t, o));
    }

    pub(crate) fn nu_into(&self, bodies: &[BodyState], t: f64, out: &mut [f64]) {
        self.rows_into(bodies, t, out, |e, x, t, o| e.nu_dyn(x, t, o));
    }

    pub(crate) fn gamma_into(&self, bodies: &[BodyState], t: f64, out: &mut [f64]) {
        self.rows_into(bodies, t, out, |e, x, t, o| e.gamma_dyn(x, t, o));
    }

    pub(crate) fn jacobian_into(&self, bodies: &[BodyState], t: f64, slots: &mut [f64]) {
        let g = BodyState::ground();
        self.each(|e, bi, bj, rows, map| {
            let pair = BodyPair::new(Self::state(bodies, &g, bi), Self::state(bodies, &g, bj));
            let n = rows.len();
            let mut bi_blk = [[0.0; 6]; 6];
            let mut bj_blk = [[0.0; 6]; 6];
            e.phi_v_dyn(&pair, t, &mut bi_blk[..n], &mut bj_blk[..n]);
            for r in 0..n {
                let m = &map.slots[r * 12..r * 12 + 12];
                for c in 0..6 {
                    if m[c] != NO_SLOT {
                        slots[m[c]] = bi_blk[r][c];
                    }
                    if m[6 + c] != NO_SLOT {
                        slots[m[6 + c]] = bj_blk[r][c];
                    }
                }
            }
        });
    }

    /// Φ at the workspace's poses and time `t` (length [`num_equations`](Self::num_equations)).
    /// No allocation.
    pub fn eval_phi(&self, ws: &Workspace, t: f64, out: &mut [f64]) {
        self.phi_into(&ws.bodies, t, out)
    }

    /// Φ_v slot values (pattern [`Model::pattern`]) at the workspace's poses. No allocation.
    pub fn eval_jacobian(&self, ws: &Workspace, t: f64, slots: &mut [f64]) {
        self.jacobian_into(&ws.bodies, t, slots)
    }

    /// ν = −Φ_t at the workspace's poses. No allocation.
    pub fn eval_nu(&self, ws: &Workspace, t: f64, out: &mut [f64]) {
        self.nu_into(&ws.bodies, t, out)
    }

    /// γ#_v (6-coordinate form) at the workspace's poses and velocities (ω'). No allocation.
    pub fn eval_gamma(&self, ws: &Workspace, t: f64, out: &mut [f64]) {
        self.gamma_into(&ws.bodies, t, out)
    }
}

/// Object-safe view of a joint or driver (the [`Constraint`] trait has generic methods).
pub(crate) trait ElementEval {
    fn phi_dyn(&self, x: &BodyPair, t: f64, out: &mut [f64]);
    fn nu_dyn(&self, x: &BodyPair, t: f64, out: &mut [f64]);
    fn gamma_dyn(&self, x: &BodyPair, t: f64, out: &mut [f64]);
    fn phi_v_dyn(&self, x: &BodyPair, t: f64, oi: &mut [[f64; 6]], oj: &mut [[f64; 6]]);
}

impl<C: Constraint> ElementEval for C {
    fn phi_dyn(&self, x: &BodyPair, t: f64, out: &mut [f64]) {
        self.phi(x, t, out)
    }
    fn nu_dyn(&self, x: &BodyPair, t: f64, out: &mut [f64]) {
        self.nu(x, t, out)
    }
    fn gamma_dyn(&self, x: &BodyPair, t: f64, out: &mut [f64]) {
        self.gamma_sharp_v(x, t, out)
    }
    fn phi_v_dyn(&self, x: &BodyPair, t: f64, oi: &mut [[f64; 6]], oj: &mut [[f64; 6]]) {
        self.phi_v(x, t, oi, oj)
    }
}

// ------------------------------------------------------------------------------------------
// Building and validation
// ------------------------------------------------------------------------------------------

fn suggest<'a>(name: &str, candidates: impl Iterator<Item = &'a str>) -> Option<String> {
    let mut best: Option<(f64, &str)> = None;
    for c in candidates {
        let s = strsim::jaro_winkler(&name.to_lowercase(), &c.to_lowercase());
        if best.is_none_or(|(b, _)| s > b) {
            best = Some((s, c));
        }
    }
    best.filter(|(s, _)| *s >= 0.7).map(|(_, c)| c.to_string())
}

/// A finite number within the SI magnitude limit of its quantity ([`crate::sanity`]).
fn check_number(element: &str, what: &str, q: Quantity, v: f64) -> Result<(), ModelError> {
    if !v.is_finite() {
        return Err(ModelError::NotFinite {
            element: element.into(),
            what: what.into(),
            value: v,
        });
    }
    if v.abs() > q.limit() {
        return Err(ModelError::Absurd {
            element: element.into(),
            what: what.into(),
            value: v,
            limit: q.limit(),
            unit: q.unit(),
        });
    }
    Ok(())
}

fn check_numbers(element: &str, what: &str, q: Quantity, v: &[f64]) -> Result<(), ModelError> {
    v.iter()
        .try_for_each(|&x| check_number(element, what, q, x))
}

fn orientation_p(body: &str, o: &Orientation) -> Result<Vector4<f64>, ModelError> {
    let el = format!("body \"{body}\"");
    match o {
        Orientation::Identity => {}
        Orientation::EulerParams(e) => {
            check_numbers(&el, "Euler parameters", Quantity::Direction, e)?
        }
        Orientation::AxisAngle { axis, angle } => {
            check_numbers(
                &el,
                "orientation axis",
                Quantity::Direction,
                axis.as_slice(),
            )?;
            check_number(&el, "orientation angle", Quantity::Angle, *angle)?;
        }
        Orientation::Euler313(a) | Orientation::Euler123(a) => {
            check_numbers(&el, "Euler angles", Quantity::Angle, a)?
        }
        Orientation::Axes { z, x } => {
            check_numbers(&el, "orientation z axis", Quantity::Direction, z.as_slice())?;
            if let Some(x) = x {
                check_numbers(&el, "orientation x axis", Quantity::Direction, x.as_slice())?;
            }
        }
    }
    let p = o.euler_params().map_err(|e| ModelError::BadOrientation {
        body: body.into(),
        reason: e.to_string(),
    })?;
    Ok(*p.as_vector())
}

struct Names<'a> {
    bodies: HashMap<&'a str, BodyId>,
    body_list: Vec<&'a str>,
    points: HashMap<(&'a str, &'a str), Vector3<f64>>,
    vectors: HashMap<(&'a str, &'a str), Vector3<f64>>,
}

impl<'a> Names<'a> {
    fn body(&self, element: &str, name: &str) -> Result<BodyId, ModelError> {
        self.bodies
            .get(name)
            .copied()
            .ok_or_else(|| ModelError::UnknownBody {
                element: element.into(),
                name: name.into(),
                suggestion: suggest(name, self.body_list.iter().copied()),
            })
    }

    fn feature(
        &self,
        element: &str,
        body: &str,
        name: &str,
        vector: bool,
    ) -> Result<Vector3<f64>, ModelError> {
        let map = if vector { &self.vectors } else { &self.points };
        if let Some(v) = map.get(&(body, name)) {
            return Ok(*v);
        }
        let suggestion = suggest(
            name,
            map.keys().filter(|(b, _)| *b == body).map(|(_, n)| *n),
        );
        Err(if vector {
            ModelError::UnknownVector {
                element: element.into(),
                body: body.into(),
                name: name.into(),
                suggestion,
            }
        } else {
            ModelError::UnknownPoint {
                element: element.into(),
                body: body.into(),
                name: name.into(),
                suggestion,
            }
        })
    }
}

fn pair_check(element: &str, bi: BodyId, bj: BodyId, name_i: &str) -> Result<(), ModelError> {
    if bi == bj {
        return Err(match bi {
            BodyId::Ground => ModelError::GroundToGround {
                element: element.into(),
            },
            BodyId::Moving(_) => ModelError::SelfConnection {
                element: element.into(),
                body: name_i.into(),
            },
        });
    }
    Ok(())
}

fn pose(bodies: &[BodyInfo], id: BodyId) -> BodyState {
    match id {
        BodyId::Ground => BodyState::ground(),
        BodyId::Moving(k) => BodyState::at(bodies[k].initial_r, bodies[k].initial_p),
    }
}

/// Appends the pattern entries of an element with `rows` rows starting at `*row`.
fn layout(
    row: &mut usize,
    entries: &mut Vec<(usize, usize)>,
    rows: usize,
    fp: Footprint,
    bi: BodyId,
    bj: BodyId,
) -> (Range<usize>, ScatterMap) {
    let start = *row;
    let mut slots = vec![NO_SLOT; rows * 12];
    for r in 0..rows {
        for (side, id, use_) in [(0, bi, fp.i), (1, bj, fp.j)] {
            let BodyId::Moving(k) = id else { continue };
            for c in 0..6 {
                let used = if c < 3 { use_.r } else { use_.p };
                if used {
                    slots[r * 12 + side * 6 + c] = entries.len();
                    entries.push((start + r, 6 * k + c));
                }
            }
        }
    }
    *row += rows;
    (start..*row, ScatterMap { slots })
}

pub(crate) fn build(b: &MechanismBuilder) -> Result<Model, ModelError> {
    // Bodies.
    let mut names = Names {
        bodies: HashMap::new(),
        body_list: vec![GROUND],
        points: HashMap::new(),
        vectors: HashMap::new(),
    };
    names.bodies.insert(GROUND, BodyId::Ground);
    let mut bodies = Vec::with_capacity(b.bodies.len());
    for (k, body) in b.bodies.iter().enumerate() {
        if body.name.is_empty() {
            return Err(ModelError::EmptyName {
                what: format!("body #{}", k + 1),
            });
        }
        if names.bodies.contains_key(body.name.as_str()) {
            return Err(ModelError::DuplicateBody {
                name: body.name.clone(),
            });
        }
        let el = format!("body \"{}\"", body.name);
        check_numbers(&el, "position", Quantity::Length, body.position.as_slice())?;
        let p = orientation_p(&body.name, &body.orientation)?;
        if let Some(m) = body.mass {
            check_number(&el, "mass", Quantity::Mass, m)?;
            if m <= 0.0 {
                return Err(ModelError::NonPositiveMass {
                    body: body.name.clone(),
                    mass: m,
                });
            }
        }
        if let Some(i) = &body.inertia {
            check_numbers(&el, "inertia", Quantity::Inertia, i.as_slice())?;
            crate::sanity::check_inertia(&body.name, i)?;
        }
        names.bodies.insert(&body.name, BodyId::Moving(k));
        names.body_list.push(&body.name);
        bodies.push(BodyInfo {
            name: body.name.clone(),
            mass: body.mass,
            inertia: body.inertia,
            initial_r: body.position,
            initial_p: p,
        });
    }
    if bodies.is_empty() {
        return Err(ModelError::NoBodies);
    }

    // Points and vectors.
    let mut points = Vec::new();
    let mut vectors = Vec::new();
    for (list, out, is_vec) in [
        (&b.points, &mut points, false),
        (&b.vectors, &mut vectors, true),
    ] {
        let what = if is_vec { "vector" } else { "point" };
        for f in list {
            let el = format!("{what} \"{}\"", f.name);
            let id = names.body(&el, &f.body)?;
            if f.name.is_empty() {
                return Err(ModelError::EmptyName {
                    what: format!("a {what} on body \"{}\"", f.body),
                });
            }
            let el = format!("{what} \"{}\" on body \"{}\"", f.name, f.body);
            let q = if is_vec {
                Quantity::Direction
            } else {
                Quantity::Length
            };
            check_numbers(&el, "components", q, f.value.as_slice())?;
            if is_vec && (f.value.amax() == 0.0 || !f.value.amax().is_normal()) {
                return Err(ModelError::ZeroVector {
                    body: f.body.clone(),
                    name: f.name.clone(),
                });
            }
            let map = if is_vec {
                &mut names.vectors
            } else {
                &mut names.points
            };
            if map
                .insert((f.body.as_str(), f.name.as_str()), f.value)
                .is_some()
            {
                return Err(ModelError::DuplicateFeature {
                    what,
                    body: f.body.clone(),
                    name: f.name.clone(),
                });
            }
            out.push(FeatureInfo {
                body: id,
                body_name: f.body.clone(),
                name: f.name.clone(),
                local: f.value,
            });
        }
    }

    // Characteristic length.
    let mut length: f64 = 0.0;
    for bd in &bodies {
        length = length.max(bd.initial_r.norm());
    }
    for p in &points {
        length = length.max(p.local.norm());
    }
    for j in &b.joints {
        if let Some(l) = j.length {
            if l.is_finite() {
                length = length.max(l.abs());
            }
        }
    }
    if !(length > 0.0 && length.is_finite()) {
        length = 1.0;
    }

    // Joints. Every element name, with the joint index for joints (drivers look their joint up
    // here: a linear search would make building a long driven chain quadratic).
    let mut element_names: HashMap<&str, Option<usize>> = HashMap::new();
    let mut joints: Vec<JointInfo> = Vec::with_capacity(b.joints.len());
    for spec in &b.joints {
        if spec.name.is_empty() {
            return Err(ModelError::EmptyName {
                what: format!("a {} joint", spec.kind.name()),
            });
        }
        if element_names
            .insert(&spec.name, Some(joints.len()))
            .is_some()
        {
            return Err(ModelError::DuplicateElement {
                name: spec.name.clone(),
            });
        }
        let el = format!("joint \"{}\"", spec.name);
        let bi = names.body(&el, &spec.body_i)?;
        let bj = names.body(&el, &spec.body_j)?;
        pair_check(&el, bi, bj, &spec.body_i)?;
        let pi = names.feature(&el, &spec.body_i, &spec.point_i, false)?;
        let pj = names.feature(&el, &spec.body_j, &spec.point_j, false)?;
        let kind = spec.kind;
        let info = kind.info();
        let needs_axes = info.axes.is_some();
        let axis = |which: &'static str, body: &str, name: &Option<String>| match name {
            Some(n) => names.feature(&el, body, n, true).map(Some),
            None if needs_axes => Err(ModelError::MissingAxis {
                joint: spec.name.clone(),
                kind: kind.name(),
                which,
            }),
            None => Ok(None),
        };
        let zi = axis("axis_i", &spec.body_i, &spec.axis_i)?;
        let zj = axis("axis_j", &spec.body_j, &spec.axis_j)?;
        let xi = match &spec.x_axis_i {
            Some(n) => Some(names.feature(&el, &spec.body_i, n, true)?),
            None => None,
        };
        let xj = match &spec.x_axis_j {
            Some(n) => Some(names.feature(&el, &spec.body_j, n, true)?),
            None => None,
        };
        // The joint frame on one side (`side` = "i" or "j"); a refusal is worded with the
        // builder's keys (axis_i, x_axis_i), not the internal "marker".
        let marker = |side: &str,
                      body: &str,
                      p: Vector3<f64>,
                      z: Option<Vector3<f64>>,
                      x: Option<Vector3<f64>>| {
            let bad = |e: cardan_constraints::ConstraintError| ModelError::BadMarker {
                joint: spec.name.clone(),
                body: body.into(),
                reason: match e {
                    cardan_constraints::ConstraintError::ParallelAxes { .. } => format!(
                        "x_axis_{side} is parallel to axis_{side}; the x axis must be \
                             perpendicular to the joint axis (it is the zero of the joint angle)"
                    ),
                    cardan_constraints::ConstraintError::ZeroAxis { .. } => {
                        format!("axis_{side} or x_axis_{side} has zero length")
                    }
                    other => other.to_string().replace("marker ", ""),
                },
            };
            match (z, x) {
                (Some(z), Some(x)) => Marker::from_axes(p, z, x).map_err(bad),
                (Some(z), None) => Marker::from_axis(p, z).map_err(bad),
                _ => Ok(Marker {
                    point: p,
                    frame: Matrix3::identity(),
                }),
            }
        };
        let mi = marker("i", &spec.body_i, pi, zi, xi)?;
        let mj = marker("j", &spec.body_j, pj, zj, xj)?;
        if let (JointKind::Universal, Some(zi), Some(zj)) = (kind, zi, zj) {
            let (si, sj) = (pose(&bodies, bi).vector(&zi), pose(&bodies, bj).vector(&zj));
            crate::sanity::check_universal_arms(&spec.name, &si, &sj)?;
        }
        let joint = if info.length {
            let l = match spec.length {
                Some(l) => {
                    check_number(&el, "length", Quantity::Length, l)?;
                    l
                }
                None => {
                    let (si, sj) = (pose(&bodies, bi), pose(&bodies, bj));
                    (sj.point(&pj) - si.point(&pi)).norm()
                }
            };
            if l <= 0.0 {
                return Err(ModelError::NonPositive {
                    element: el,
                    what: "length".into(),
                    value: l,
                });
            }
            Joint::with_length(kind, mi, mj, l)
        } else {
            Joint::new(kind, mi, mj)
        }
        .map_err(|e| ModelError::BadMarker {
            joint: spec.name.clone(),
            body: spec.body_i.clone(),
            reason: e.to_string(),
        })?;
        joints.push(JointInfo {
            name: spec.name.clone(),
            body_i: bi,
            body_j: bj,
            joint,
            has_x_axes: xi.is_some() && xj.is_some(),
            rows: 0..0,
            map: ScatterMap { slots: Vec::new() },
        });
    }

    // Drivers.
    let mut drivers: Vec<DriverInfo> = Vec::with_capacity(b.drivers.len());
    for spec in &b.drivers {
        if spec.name.is_empty() {
            return Err(ModelError::EmptyName {
                what: "a driver".into(),
            });
        }
        if element_names.insert(&spec.name, None).is_some() {
            return Err(ModelError::DuplicateElement {
                name: spec.name.clone(),
            });
        }
        let el = format!("driver \"{}\"", spec.name);
        spec.function
            .validate()
            .map_err(|e| ModelError::BadTimeFunction {
                driver: spec.name.clone(),
                reason: e.to_string(),
            })?;
        let f = spec.function.clone();
        let find_joint =
            |joint: &str| {
                element_names.get(joint).copied().flatten().ok_or_else(|| {
                    ModelError::UnknownJoint {
                        element: el.clone(),
                        name: joint.into(),
                        suggestion: suggest(joint, joints.iter().map(|j| j.name.as_str())),
                    }
                })
            };
        let (driver, bi, bj, jidx): (Driver, BodyId, BodyId, Option<usize>) = match &spec.target {
            DriverTarget::JointRotation { joint } => {
                let k = find_joint(joint)?;
                let j = &joints[k];
                if j.joint.kind().info().rotation.is_none() {
                    return Err(ModelError::WrongJointKind {
                        driver: spec.name.clone(),
                        joint: joint.clone(),
                        kind: j.joint.kind().name(),
                        driver_kind: "rotation",
                        expected: kinds_with(|k| k.rotation.is_some()),
                    });
                }
                if !j.has_x_axes {
                    return Err(ModelError::AngleWithoutXAxes {
                        element: el.clone(),
                        joint: joint.clone(),
                    });
                }
                let d = RotationDriver::new(*j.joint.marker_i(), *j.joint.marker_j(), f);
                (d.into(), j.body_i, j.body_j, Some(k))
            }
            DriverTarget::JointTranslation { joint } => {
                let k = find_joint(joint)?;
                let j = &joints[k];
                if j.joint.kind().info().translation.is_none() {
                    return Err(ModelError::WrongJointKind {
                        driver: spec.name.clone(),
                        joint: joint.clone(),
                        kind: j.joint.kind().name(),
                        driver_kind: "translation",
                        expected: kinds_with(|k| k.translation.is_some()),
                    });
                }
                let d = TranslationDriver::new(*j.joint.marker_i(), *j.joint.marker_j(), f);
                (d.into(), j.body_i, j.body_j, Some(k))
            }
            DriverTarget::Distance {
                body_i,
                point_i,
                body_j,
                point_j,
            } => {
                let bi = names.body(&el, body_i)?;
                let bj = names.body(&el, body_j)?;
                pair_check(&el, bi, bj, body_i)?;
                let pi = names.feature(&el, body_i, point_i, false)?;
                let pj = names.feature(&el, body_j, point_j, false)?;
                (DistanceDriver::new(pi, pj, f).into(), bi, bj, None)
            }
            DriverTarget::Coordinate { body, point, axis } => {
                let bi = names.body(&el, body)?;
                if bi == BodyId::Ground {
                    return Err(ModelError::GroundToGround { element: el });
                }
                let pi = names.feature(&el, body, point, false)?;
                let d = CoordinateDriver::new(pi, axis.index(), f).map_err(|e| {
                    ModelError::BadTimeFunction {
                        driver: spec.name.clone(),
                        reason: e.to_string(),
                    }
                })?;
                (d.into(), bi, BodyId::Ground, None)
            }
        };
        drivers.push(DriverInfo {
            name: spec.name.clone(),
            body_i: bi,
            body_j: bj,
            driver,
            joint: jidx,
            rows: 0..0,
            map: ScatterMap { slots: Vec::new() },
        });
    }

    // Force elements.
    let mut forces = Vec::with_capacity(b.forces.len());
    for spec in &b.forces {
        let name = spec.name();
        if name.is_empty() {
            return Err(ModelError::EmptyName {
                what: "a force element".into(),
            });
        }
        if element_names.insert(name, None).is_some() {
            return Err(ModelError::DuplicateElement { name: name.into() });
        }
        let el = format!("force \"{name}\"");
        let moving = |body: &str| -> Result<BodyId, ModelError> {
            let id = names.body(&el, body)?;
            if id == BodyId::Ground {
                return Err(ModelError::OnGround {
                    element: el.clone(),
                });
            }
            Ok(id)
        };
        let non_negative = |what: &str, q: Quantity, v: f64| {
            check_number(&el, what, q, v)?;
            if v < 0.0 {
                return Err(ModelError::NonPositive {
                    element: el.clone(),
                    what: format!("{what} (≥ 0 required)"),
                    value: v,
                });
            }
            Ok(())
        };
        forces.push(match spec {
            ForceSpec::Gravity { g } => {
                check_numbers(&el, "gravity", Quantity::Acceleration, g.as_slice())?;
                ForceInfo::Gravity { g: *g }
            }
            ForceSpec::SpringDamper {
                name,
                body_i,
                point_i,
                body_j,
                point_j,
                stiffness,
                damping,
                free_length,
            } => {
                let bi = names.body(&el, body_i)?;
                let bj = names.body(&el, body_j)?;
                pair_check(&el, bi, bj, body_i)?;
                let pi = names.feature(&el, body_i, point_i, false)?;
                let pj = names.feature(&el, body_j, point_j, false)?;
                non_negative("stiffness", Quantity::Stiffness, *stiffness)?;
                non_negative("damping", Quantity::Damping, *damping)?;
                let l0 = match free_length {
                    Some(l) => {
                        non_negative("free length", Quantity::Length, *l)?;
                        *l
                    }
                    None => (pose(&bodies, bj).point(&pj) - pose(&bodies, bi).point(&pi)).norm(),
                };
                ForceInfo::SpringDamper {
                    name: name.clone(),
                    body_i: bi,
                    point_i: pi,
                    body_j: bj,
                    point_j: pj,
                    stiffness: *stiffness,
                    damping: *damping,
                    free_length: l0,
                }
            }
            ForceSpec::PointForce {
                name,
                body,
                point,
                force,
            } => {
                let id = moving(body)?;
                let p = names.feature(&el, body, point, false)?;
                check_numbers(&el, "force", Quantity::Force, force.as_slice())?;
                ForceInfo::PointForce {
                    name: name.clone(),
                    body: id,
                    point: p,
                    force: *force,
                }
            }
            ForceSpec::Torque { name, body, torque } => {
                let id = moving(body)?;
                check_numbers(&el, "torque", Quantity::Torque, torque.as_slice())?;
                ForceInfo::Torque {
                    name: name.clone(),
                    body: id,
                    torque: *torque,
                }
            }
        });
    }

    // Rows, pattern, index maps, scales.
    let mut entries: Vec<(usize, usize)> = Vec::new();
    let mut equation_scales = Vec::new();
    let mut row = 0;
    for j in &mut joints {
        let (rows, map) = layout(
            &mut row,
            &mut entries,
            j.joint.rows(),
            j.joint.footprint(),
            j.body_i,
            j.body_j,
        );
        j.rows = rows;
        j.map = map;
        // Each row's scale from its dimension: 1, L or L².
        for r in 0..j.joint.rows() {
            equation_scales.push(j.joint.dimension(r).scale(length));
        }
    }
    let joint_rows = row;
    for d in &mut drivers {
        let (rows, map) = layout(
            &mut row,
            &mut entries,
            1,
            d.driver.footprint(),
            d.body_i,
            d.body_j,
        );
        d.rows = rows;
        d.map = map;
        equation_scales.push(d.driver.dimension(0).scale(length));
    }
    let num_rows = row;
    let nb = bodies.len();
    let pattern = SparsityPattern::new(num_rows, 6 * nb, &entries)
        .expect("entries are inside the matrix by construction");
    let unknown_scales = (0..6 * nb)
        .map(|c| if c % 6 < 3 { length } else { 1.0 })
        .collect();
    let tree = crate::analysis::predictor::PredictorTree::new(nb, &joints);
    Ok(Model {
        tree,
        bodies,
        points,
        vectors,
        joints,
        drivers,
        forces,
        pattern,
        equation_scales,
        unknown_scales,
        length,
        num_rows,
        joint_rows,
    })
}

/// "a revolute or cylindrical joint": the kinds whose description passes `pick`, for messages.
pub fn kinds_with(pick: impl Fn(&cardan_constraints::KindInfo) -> bool) -> String {
    let names: Vec<&str> = cardan_constraints::KINDS
        .iter()
        .filter(|k| pick(k))
        .map(|k| k.name)
        .collect();
    match names.as_slice() {
        [] => "no joint".into(),
        [one] => format!("a {one} joint"),
        [init @ .., last] => format!("a {} or {last} joint", init.join(", ")),
    }
}
