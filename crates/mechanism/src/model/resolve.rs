//! Name resolution: every element of a [`MechanismBuilder`] checked and turned into its model
//! form, one function per element kind ([`bodies`], [`features`], [`joint`], [`driver`],
//! [`force`]). Names are looked up in [`Names`]; an unknown name gets a suggestion. The checks
//! of numbers and shapes are in [`super::validate`].

use super::elements::{
    BodyId, BodyInfo, DriverInfo, FeatureInfo, ForceInfo, JointInfo, ScatterMap,
};
use super::validate::{
    check_number, check_numbers, kinds_with, orientation_p, pair_check, suggest,
};
use crate::builder::{
    pose_row_name, DriverSpec, DriverTarget, ForceSpec, JointSpec, MechanismBuilder, PoseTarget,
    GROUND,
};
use crate::error::ModelError;
use crate::sanity::Quantity;
use cardan_constraints::joints::{Axes, Block, CONE_MARGIN};
use cardan_constraints::{
    BodyState, ConstraintError, CoordinateDriver, DistanceDriver, Driver, Joint, JointKind,
    JointParams, KindInfo, Marker, PoseDriver, RotationDriver, TranslationDriver,
};
use nalgebra::{Matrix3, Vector3};
use std::collections::HashMap;

/// A body and a point in its frame.
type BodyPoint = (BodyId, Vector3<f64>);

/// The name tables elements are resolved against: bodies, and the points and vectors of each.
pub(super) struct Names<'a> {
    bodies: HashMap<&'a str, BodyId>,
    body_list: Vec<&'a str>,
    points: HashMap<(&'a str, &'a str), Vector3<f64>>,
    vectors: HashMap<(&'a str, &'a str), Vector3<f64>>,
}

impl<'a> Names<'a> {
    pub(super) fn body(
        &self,
        element: impl std::fmt::Display,
        name: &str,
    ) -> Result<BodyId, ModelError> {
        self.bodies
            .get(name)
            .copied()
            .ok_or_else(|| ModelError::UnknownBody {
                element: element.to_string(),
                name: name.into(),
                suggestion: suggest(name, self.body_list.iter().copied()),
                known: self.body_list.iter().map(|b| b.to_string()).collect(),
            })
    }

    /// The two different bodies of a two-body element `element` (not both ground, not the
    /// same body twice).
    pub(super) fn pair(
        &self,
        element: &str,
        body_i: &str,
        body_j: &str,
    ) -> Result<(BodyId, BodyId), ModelError> {
        let bi = self.body(element, body_i)?;
        let bj = self.body(element, body_j)?;
        pair_check(element, bi, bj, body_i)?;
        Ok((bi, bj))
    }

    /// Two points on two different bodies (a two-point element: distance driver, spring):
    /// each body's id and the point in its frame.
    pub(super) fn point_pair(
        &self,
        element: &str,
        (body_i, point_i): (&str, &str),
        (body_j, point_j): (&str, &str),
    ) -> Result<(BodyPoint, BodyPoint), ModelError> {
        let (bi, bj) = self.pair(element, body_i, body_j)?;
        let pi = self.feature(element, body_i, point_i, false)?;
        let pj = self.feature(element, body_j, point_j, false)?;
        Ok(((bi, pi), (bj, pj)))
    }

    pub(super) fn feature(
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
        let mut known: Vec<String> = map
            .keys()
            .filter(|(b, _)| *b == body)
            .map(|(_, n)| n.to_string())
            .collect();
        known.sort();
        let suggestion = suggest(name, known.iter().map(String::as_str));
        Err(if vector {
            ModelError::UnknownVector {
                element: element.into(),
                body: body.into(),
                name: name.into(),
                suggestion,
                known,
            }
        } else {
            ModelError::UnknownPoint {
                element: element.into(),
                body: body.into(),
                name: name.into(),
                suggestion,
                known,
            }
        })
    }
}

/// The initial pose of a body (ground at the origin).
pub(super) fn pose(bodies: &[BodyInfo], id: BodyId) -> BodyState {
    match id {
        BodyId::Ground => BodyState::ground(),
        BodyId::Moving(k) => BodyState::at(bodies[k].initial_r, bodies[k].initial_p),
    }
}

/// The moving bodies: names unique, numbers within their limits, orientation and inertia
/// checked; with the name tables the other elements are resolved against.
pub(super) fn bodies(b: &MechanismBuilder) -> Result<(Names<'_>, Vec<BodyInfo>), ModelError> {
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
    Ok((names, bodies))
}

/// The named points and vectors of the bodies (entered into `names`): on known bodies, unique
/// per body, finite, vectors not zero.
pub(super) fn features<'a>(
    b: &'a MechanismBuilder,
    names: &mut Names<'a>,
) -> Result<(Vec<FeatureInfo>, Vec<FeatureInfo>), ModelError> {
    let mut points = Vec::new();
    let mut vectors = Vec::new();
    for (list, out, is_vec) in [
        (&b.points, &mut points, false),
        (&b.vectors, &mut vectors, true),
    ] {
        let what = if is_vec { "vector" } else { "point" };
        for f in list {
            let id = names.body(format_args!("{what} \"{}\"", f.name), &f.body)?;
            if f.name.is_empty() {
                return Err(ModelError::EmptyName {
                    what: format!("a {what} on body \"{}\"", f.body),
                });
            }
            let q = if is_vec {
                Quantity::Direction
            } else {
                Quantity::Length
            };
            // The element is named (formatted) only in an error.
            let el = format_args!("{what} \"{}\" on body \"{}\"", f.name, f.body);
            check_numbers(el, "components", q, f.value.as_slice())?;
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
    Ok((points, vectors))
}

/// One joint: its bodies, points and axes resolved and checked, its markers, and the joint
/// built from its kind's description.
pub(super) fn joint(
    spec: &JointSpec,
    names: &Names,
    bodies: &[BodyInfo],
) -> Result<JointInfo, ModelError> {
    let el = format!("joint \"{}\"", spec.name);
    let (bi, bj) = names.pair(&el, &spec.body_i, &spec.body_j)?;
    let pi = names.feature(&el, &spec.body_i, &spec.point_i, false)?;
    let pj = names.feature(&el, &spec.body_j, &spec.point_j, false)?;
    let kind = spec.kind;
    let info = kind.info();
    refuse_unused_keys(spec, info)?;
    let axis = |which: &'static str, needed: bool, body: &str, name: &Option<String>| match name {
        Some(n) => names.feature(&el, body, n, true).map(Some),
        None if needed => Err(ModelError::MissingAxis {
            joint: spec.name.clone(),
            kind: kind.name(),
            which,
        }),
        None => Ok(None),
    };
    let zi = axis("axis_i", info.axes.required(), &spec.body_i, &spec.axis_i)?;
    let needs_j = matches!(info.axes, Axes::Required(_));
    let zj = axis("axis_j", needs_j, &spec.body_j, &spec.axis_j)?;
    let xi = axis("x_axis_i", false, &spec.body_i, &spec.x_axis_i)?;
    let xj = axis("x_axis_j", false, &spec.body_j, &spec.x_axis_j)?;
    let (si, sj) = (pose(bodies, bi), pose(bodies, bj));
    let xi = match (xi, zi, zj) {
        // An angle joint measures about x_i: by default the axes' common perpendicular.
        (None, Some(zi), Some(zj)) if info.blocks.contains(&Block::AtAngle) => {
            common_perpendicular(&si, &sj, zi, zj)
        }
        _ => xi,
    };
    let mi = marker(&spec.name, "i", &spec.body_i, pi, zi, xi)?;
    let mj = marker(&spec.name, "j", &spec.body_j, pj, zj, xj)?;
    if let (JointKind::Universal, Some(zi), Some(zj)) = (kind, zi, zj) {
        crate::sanity::check_universal_arms(&spec.name, &si.vector(&zi), &sj.vector(&zj))?;
    }
    let params = joint_params(spec, &el, info, (&si, &mi), (&sj, &mj))?;
    let joint = Joint::with_params(kind, mi, mj, params).map_err(|e| ModelError::BadMarker {
        joint: spec.name.clone(),
        body: spec.body_i.clone(),
        reason: e.to_string(),
    })?;
    Ok(JointInfo {
        name: spec.name.clone(),
        body_i: bi,
        body_j: bj,
        joint,
        has_x_axes: xi.is_some() && (xj.is_some() || !info.axes.on_j()),
        rows: 0..0,
        map: ScatterMap { slots: Vec::new() },
    })
}

/// Keys the kind does not use are refused, not ignored.
fn refuse_unused_keys(spec: &JointSpec, info: &KindInfo) -> Result<(), ModelError> {
    let unused = |key: &'static str| ModelError::UnusedKey {
        joint: spec.name.clone(),
        kind: info.name,
        key,
    };
    let given = |k: &Option<String>| k.is_some();
    if !info.axes.accepted() && (given(&spec.axis_i) || given(&spec.axis_j)) {
        return Err(unused("axis_i and axis_j"));
    }
    if info.axes.accepted() && !info.axes.on_j() && (given(&spec.axis_j) || given(&spec.x_axis_j)) {
        return Err(unused(
            "axis_j and x_axis_j (the kind uses the frame on body i only)",
        ));
    }
    if !info.x_axes && (given(&spec.x_axis_i) || given(&spec.x_axis_j)) {
        return Err(unused("x_axis_i and x_axis_j"));
    }
    for (key, takes, value) in [
        ("length", info.length, spec.length),
        ("offset", info.offset, spec.offset),
        ("angle", info.angle, spec.angle),
    ] {
        if !takes && value.is_some() {
            return Err(unused(key));
        }
    }
    Ok(())
}

/// x_i along z_i × z_j as drawn (body-i components), if the axes are not parallel.
fn common_perpendicular(
    si: &BodyState,
    sj: &BodyState,
    zi: Vector3<f64>,
    zj: Vector3<f64>,
) -> Option<Vector3<f64>> {
    let c = si
        .vector(&zi)
        .normalize()
        .cross(&sj.vector(&zj).normalize());
    (c.norm() > 1e-6).then(|| si.a.transpose() * c)
}

/// A joint's numbers: each as given (finite, within limits) or its default: the drawn length
/// and angle ([`KindInfo::drawn_length`], the marker angle about x_i), offset 0.
fn joint_params(
    spec: &JointSpec,
    el: &str,
    info: &KindInfo,
    (si, mi): (&BodyState, &Marker),
    (sj, mj): (&BodyState, &Marker),
) -> Result<JointParams, ModelError> {
    let given = |what: &str, q: Quantity, v: Option<f64>| match v {
        Some(v) => check_number(el, what, q, v).map(|_| Some(v)),
        None => Ok(None),
    };
    let d = sj.point(&mj.point) - si.point(&mi.point);
    let (zi, yi, zj) = (si.vector(&mi.z()), si.vector(&mi.y()), sj.vector(&mj.z()));
    let mut params = JointParams::default();
    if info.length {
        let l = given("length", Quantity::Length, spec.length)?
            .unwrap_or_else(|| info.drawn_length(&d, &zi));
        if l <= 0.0 {
            return Err(ModelError::NonPositive {
                element: el.into(),
                what: "length".into(),
                value: l,
            });
        }
        params.length = l;
    }
    if info.offset {
        params.offset = given("offset", Quantity::Length, spec.offset)?.unwrap_or(0.0);
    }
    if info.blocks.contains(&Block::Cone) {
        let drawn = || zi.cross(&zj).norm().atan2(zi.dot(&zj));
        let a = given("angle", Quantity::Angle, spec.angle)?.unwrap_or_else(drawn);
        cone_angle(el, a, spec.angle.is_some())?;
        params.angle = a;
    } else if info.angle {
        params.angle = given("angle", Quantity::Angle, spec.angle)?
            .unwrap_or_else(|| (-yi.dot(&zj)).atan2(zi.dot(&zj)));
    }
    Ok(params)
}

/// A cone's half-angle α must lie in [CONE_MARGIN, π − CONE_MARGIN]: at 0 or π the row
/// z_iᵀz_j − cos α has a zero gradient at its solution (it loses rank).
fn cone_angle(el: &str, a: f64, given: bool) -> Result<(), ModelError> {
    if (CONE_MARGIN..=std::f64::consts::PI - CONE_MARGIN).contains(&a) {
        return Ok(());
    }
    Err(ModelError::ConeAngle {
        element: el.into(),
        value: a,
        given,
    })
}

/// The joint frame on side `side` ("i" or "j") of joint `joint`: from its axis and x axis when
/// given; a refusal is worded with the builder's keys (axis_i, x_axis_i), not the internal
/// "marker".
fn marker(
    joint: &str,
    side: &str,
    body: &str,
    p: Vector3<f64>,
    z: Option<Vector3<f64>>,
    x: Option<Vector3<f64>>,
) -> Result<Marker, ModelError> {
    let bad = |e: ConstraintError| ModelError::BadMarker {
        joint: joint.into(),
        body: body.into(),
        reason: match e {
            ConstraintError::ParallelAxes { .. } => format!(
                "x_axis_{side} is parallel to axis_{side}; the x axis must be perpendicular to \
                 the joint axis (it is the zero of the joint angle)"
            ),
            ConstraintError::ZeroAxis { .. } => {
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
}

/// One driver's rows: its joint (looked up in `element_names`, which maps every element name to
/// its joint index, if a joint) or its bodies and points, and its time function checked. A pose
/// driver gives six rows, the others one.
pub(super) fn driver(
    spec: &DriverSpec,
    names: &Names,
    joints: &[JointInfo],
    element_names: &HashMap<&str, Option<usize>>,
) -> Result<Vec<DriverInfo>, ModelError> {
    if let DriverTarget::Pose(target) = &spec.target {
        return pose_driver(&spec.name, target, names);
    }
    single_driver(spec, names, joints, element_names).map(|d| vec![d])
}

/// The six rows of a pose driver: its two frames resolved like a joint's markers (body frames
/// when no axes are given), its six laws checked.
fn pose_driver(name: &str, t: &PoseTarget, names: &Names) -> Result<Vec<DriverInfo>, ModelError> {
    let el = format!("driver \"{name}\"");
    for f in &t.functions {
        f.validate().map_err(|e| ModelError::BadTimeFunction {
            driver: name.into(),
            reason: e.to_string(),
        })?;
    }
    let (bi, bj) = names.pair(&el, &t.body_i, &t.body_j)?;
    let vector = |body: &str, v: &Option<String>| match v {
        Some(n) => names.feature(&el, body, n, true).map(Some),
        None => Ok(None),
    };
    let frame = |side, body: &str, point: &str, z: &Option<String>, x: &Option<String>| {
        let p = names.feature(&el, body, point, false)?;
        marker(name, side, body, p, vector(body, z)?, vector(body, x)?)
    };
    let mi = frame("i", &t.body_i, &t.point_i, &t.axis_i, &t.x_axis_i)?;
    let mj = frame("j", &t.body_j, &t.point_j, &t.axis_j, &t.x_axis_j)?;
    Ok((0..6)
        .map(|k| DriverInfo {
            name: pose_row_name(name, k),
            body_i: bi,
            body_j: bj,
            driver: PoseDriver::new(mi, mj, t.order, t.functions.clone(), k).into(),
            joint: None,
            rows: 0..0,
            map: ScatterMap { slots: Vec::new() },
        })
        .collect())
}

fn single_driver(
    spec: &DriverSpec,
    names: &Names,
    joints: &[JointInfo],
    element_names: &HashMap<&str, Option<usize>>,
) -> Result<DriverInfo, ModelError> {
    let el = format!("driver \"{}\"", spec.name);
    spec.function
        .validate()
        .map_err(|e| ModelError::BadTimeFunction {
            driver: spec.name.clone(),
            reason: e.to_string(),
        })?;
    let f = spec.function.clone();
    let find_joint = |joint: &str| {
        element_names
            .get(joint)
            .copied()
            .flatten()
            .ok_or_else(|| ModelError::UnknownJoint {
                element: el.clone(),
                name: joint.into(),
                suggestion: suggest(joint, joints.iter().map(|j| j.name.as_str())),
                known: joints.iter().map(|j| j.name.clone()).collect(),
            })
    };
    let (driver, bi, bj, jidx): (Driver, BodyId, BodyId, Option<usize>) = match &spec.target {
        DriverTarget::JointRotation { joint } => {
            let k = find_joint(joint)?;
            let j = &joints[k];
            drivable(spec, j, "rotation", |k| k.rotation.is_some())?;
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
            drivable(spec, j, "translation", |k| k.translation.is_some())?;
            let d = TranslationDriver::new(*j.joint.marker_i(), *j.joint.marker_j(), f);
            (d.into(), j.body_i, j.body_j, Some(k))
        }
        DriverTarget::Distance {
            body_i,
            point_i,
            body_j,
            point_j,
        } => {
            let ((bi, pi), (bj, pj)) =
                names.point_pair(&el, (body_i, point_i), (body_j, point_j))?;
            (DistanceDriver::new(pi, pj, f).into(), bi, bj, None)
        }
        DriverTarget::Coordinate { body, point, axis } => {
            let bi = names.body(&el, body)?;
            if bi == BodyId::Ground {
                return Err(ModelError::OnGround { element: el });
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
        DriverTarget::Pose(_) => unreachable!("pose drivers are resolved by pose_driver"),
    };
    Ok(DriverInfo {
        name: spec.name.clone(),
        body_i: bi,
        body_j: bj,
        driver,
        joint: jidx,
        rows: 0..0,
        map: ScatterMap { slots: Vec::new() },
    })
}

/// The joint `j` of driver `spec` is of a kind a `driver_kind` driver can act on (`accepts`,
/// from the kind table).
fn drivable(
    spec: &DriverSpec,
    j: &JointInfo,
    driver_kind: &'static str,
    accepts: fn(&cardan_constraints::KindInfo) -> bool,
) -> Result<(), ModelError> {
    let kind = j.joint.kind();
    if accepts(kind.info()) {
        return Ok(());
    }
    Err(ModelError::WrongJointKind {
        driver: spec.name.clone(),
        joint: j.name.clone(),
        kind: kind.name(),
        driver_kind,
        expected: kinds_with(accepts),
    })
}

/// One force element: its bodies and points resolved, its coefficients checked.
pub(super) fn force(
    spec: &ForceSpec,
    name: &str,
    names: &Names,
    bodies: &[BodyInfo],
) -> Result<ForceInfo, ModelError> {
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
    Ok(match spec {
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
            let ((bi, pi), (bj, pj)) =
                names.point_pair(&el, (body_i, point_i), (body_j, point_j))?;
            non_negative("stiffness", Quantity::Stiffness, *stiffness)?;
            non_negative("damping", Quantity::Damping, *damping)?;
            let l0 = match free_length {
                Some(l) => {
                    non_negative("free length", Quantity::Length, *l)?;
                    *l
                }
                None => (pose(bodies, bj).point(&pj) - pose(bodies, bi).point(&pi)).norm(),
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
    })
}
