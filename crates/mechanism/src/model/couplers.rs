//! Resolution of couplers ([`crate::CouplerSpec`]): the coupled joints checked (kinds, one shared
//! body), and the two-body equation of [`cardan_constraints::couplers`] set up so that it is
//! exactly the stated law in the joints' own coordinates.
//!
//! ## From the law to the two-body equation
//! Two joints A and B share one body C (the carrier: ground, a housing, a planet carrier); the
//! equation is written between their *other* bodies, G_A and G_B. Let σ = +1 when the other body
//! is body j of its joint and −1 when it is body i: the joint coordinate (θ = angle of x_j from
//! x_i about z_i, s = z_iᵀ(P_j − P_i)) is then σ times the motion of the other body relative to
//! C. On each other body the equation uses the joint's own marker on that body, so angles are
//! about the joint's own axis.
//!
//! | kind | law (Φ ≡ in joint coordinates) | bodies i, j | coefficients |
//! |---|---|---|---|
//! | gear | θ_j − ρ θ_i − c, ρ = −r_i/r_j or the given ratio | G_A, G_B | k_i = ρ σ_A, k_j = −σ_B (orbit angles ψ = β − σ θ) |
//! | rack_pinion | s + r θ − c | rack (slide joint), pinion | k_s = −σ_S, k_θ = r σ_R |
//! | screw, two joints | s − (pitch/2π) θ − c | nut (slide joint), screw | k_s = −ε σ_S, k_θ = −(pitch/2π) σ_R |
//! | screw, one cylindrical joint | s − (pitch/2π) θ − c | the joint's bodies | k_s = 1, k_θ = −pitch/2π |
//!
//! (ε = ±1: whether the slide axis and the screw axis point the same way.) The two-body
//! equation's constant is chosen at the initial poses so that both agree there, with c its value
//! at the initial poses unless given; the identity then holds at every pose that satisfies the
//! joints (the constants β of the derivation are geometry of C), so Φ = 0 *is* the law. The
//! rack's marker has x along the slide and z along the pinion axis (which must be perpendicular
//! to the slide); the screw's nut marker has z along the screw axis (which must be parallel to
//! the slide). The gear form needs the two axes apart (the orbit angle of a centre on the other
//! axis is undefined).

use super::elements::{BodyId, BodyInfo, CoupledCoordinate, CouplerInfo, JointInfo, ScatterMap};
use super::validate::{check_number, kinds_with, suggest};
use crate::builder::{CouplerKind, CouplerSpec, GearRatio};
use crate::error::ModelError;
use crate::sanity::Quantity;
use cardan_constraints::{BodyPair, BodyState, Coupler, Gear, KindInfo, Marker, RackPinion, Screw};
use nalgebra::Vector3;
use std::collections::HashMap;
use std::f64::consts::PI;

/// Smallest sine of the angle between two axes that must be perpendicular or parallel and are
/// not (1 mrad), and smallest distance of a gear centre from the other axis (relative to the
/// model length).
const AXIS_TOLERANCE: f64 = 1e-3;
const CENTRE_TOLERANCE: f64 = 1e-6;

/// The context a coupler is resolved in.
pub(super) struct Context<'a> {
    pub joints: &'a [JointInfo],
    pub bodies: &'a [BodyInfo],
    pub element_names: &'a HashMap<&'a str, Option<usize>>,
    pub length: f64,
}

/// One coupled joint: its index, and its other body (not the shared one) with the sign σ.
struct Side<'a> {
    index: usize,
    joint: &'a JointInfo,
    other: BodyId,
    sigma: f64,
}

impl Side<'_> {
    /// The joint's marker on its other body.
    fn marker(&self) -> Marker {
        if self.sigma > 0.0 {
            *self.joint.joint.marker_j()
        } else {
            *self.joint.joint.marker_i()
        }
    }
}

pub(super) fn coupler(spec: &CouplerSpec, cx: &Context) -> Result<CouplerInfo, ModelError> {
    let el = format!("coupler \"{}\"", spec.name);
    if let Some(c) = spec.constant {
        let q = match spec.kind {
            CouplerKind::Gear { .. } => Quantity::Angle,
            _ => Quantity::Length,
        };
        check_number(&el, "constant", q, c)?;
    }
    let mut info = match &spec.kind {
        CouplerKind::Gear {
            joint_i,
            joint_j,
            ratio,
        } => gear(spec, cx, (joint_i, joint_j), *ratio)?,
        CouplerKind::RackPinion {
            slide_joint,
            angle_joint,
            radius,
        } => rack_pinion(spec, cx, (slide_joint, angle_joint), *radius)?,
        CouplerKind::Screw {
            slide_joint,
            angle_joint,
            pitch,
        } => screw(spec, cx, (slide_joint, angle_joint), *pitch)?,
    };
    if spec.constant.is_some() {
        for c in info.coordinates {
            let j = &cx.joints[c.joint];
            if !c.slide && !j.has_x_axes {
                return Err(ModelError::AngleWithoutXAxes {
                    element: el.clone(),
                    joint: j.name.clone(),
                });
            }
        }
    }
    // The law's constant and the equation's: equal values at the initial poses.
    let (x_i, x_j) = (pose(cx.bodies, info.body_i), pose(cx.bodies, info.body_j));
    let pair = BodyPair::new(&x_i, &x_j);
    let coupler = info.coupler.with_reference(info.coupler.angles(&pair));
    let law = law_value(&info, cx);
    let c = spec.constant.unwrap_or(law);
    info.constant = c;
    info.coupler = coupler.with_constant(coupler.value(&pair) - law + c);
    Ok(info)
}

/// Σ a_k q_k at the initial poses (joint coordinates: principal angles, slides).
fn law_value(info: &CouplerInfo, cx: &Context) -> f64 {
    info.coordinates
        .iter()
        .zip(info.coefficients)
        .map(|(c, a)| {
            let j = &cx.joints[c.joint];
            let (xi, xj) = (pose(cx.bodies, j.body_i), pose(cx.bodies, j.body_j));
            a * coordinate(&j.joint, &BodyPair::new(&xi, &xj), c.slide)
        })
        .sum()
}

/// A joint's angle atan2(y_iᵀ x_j, x_iᵀ x_j) or slide z_iᵀ(P_j − P_i).
fn coordinate(j: &cardan_constraints::Joint, x: &BodyPair, slide: bool) -> f64 {
    let (mi, mj) = (j.marker_i(), j.marker_j());
    if slide {
        let d = x.j.point(&mj.point) - x.i.point(&mi.point);
        x.i.vector(&mi.z()).dot(&d)
    } else {
        let xj = x.j.vector(&mj.x());
        x.i.vector(&mi.y())
            .dot(&xj)
            .atan2(x.i.vector(&mi.x()).dot(&xj))
    }
}

/// The initial pose of a body (ground at the origin).
fn pose(bodies: &[BodyInfo], id: BodyId) -> BodyState {
    match id {
        BodyId::Ground => BodyState::ground(),
        BodyId::Moving(k) => BodyState::at(bodies[k].initial_r, bodies[k].initial_p),
    }
}

/// Joint `name` (the key `role` of coupler `spec`), of a kind `accepts` takes.
fn find<'a>(
    spec: &CouplerSpec,
    cx: &'a Context,
    role: &'static str,
    name: &str,
    accepts: fn(&KindInfo) -> bool,
) -> Result<(usize, &'a JointInfo), ModelError> {
    let el = format!("coupler \"{}\"", spec.name);
    let k = cx
        .element_names
        .get(name)
        .copied()
        .flatten()
        .ok_or_else(|| ModelError::UnknownJoint {
            element: el,
            name: name.into(),
            suggestion: suggest(name, cx.joints.iter().map(|j| j.name.as_str())),
            known: cx.joints.iter().map(|j| j.name.clone()).collect(),
        })?;
    let j = &cx.joints[k];
    if !accepts(j.joint.kind().info()) {
        return Err(ModelError::WrongCouplerJoint {
            coupler: spec.name.clone(),
            coupler_kind: spec.kind_name(),
            role,
            joint: j.name.clone(),
            kind: j.joint.kind().name(),
            expected: kinds_with(accepts),
        });
    }
    Ok((k, j))
}

fn turns(k: &KindInfo) -> bool {
    k.rotation.is_some()
}

fn slides(k: &KindInfo) -> bool {
    k.translation.is_some()
}

/// The two joints' sides: exactly one body shared, the others with their signs.
fn sides<'a>(
    spec: &CouplerSpec,
    (ka, a): (usize, &'a JointInfo),
    (kb, b): (usize, &'a JointInfo),
) -> Result<(Side<'a>, Side<'a>), ModelError> {
    let bad = |reason: String| ModelError::CouplerBodies {
        coupler: spec.name.clone(),
        reason,
    };
    if ka == kb {
        return Err(bad(format!(
            "it couples joint \"{}\" with itself; a {} couples two joints",
            a.name,
            spec.kind_name()
        )));
    }
    let shared: Vec<BodyId> = [a.body_i, a.body_j]
        .into_iter()
        .filter(|x| *x == b.body_i || *x == b.body_j)
        .collect();
    if shared.len() != 1 {
        let why = if shared.is_empty() {
            "share no body"
        } else {
            "connect the same two bodies"
        };
        return Err(bad(format!(
            "joints \"{}\" and \"{}\" {why}; a coupler relates two joints on one common body \
             (the ground, a housing or a carrier that holds both axes)",
            a.name, b.name
        )));
    }
    let side = |index, j: &'a JointInfo| {
        let sigma = if j.body_j == shared[0] { -1.0 } else { 1.0 };
        let other = if sigma > 0.0 { j.body_j } else { j.body_i };
        Side {
            index,
            joint: j,
            other,
            sigma,
        }
    };
    Ok((side(ka, a), side(kb, b)))
}

fn nonzero(
    spec: &CouplerSpec,
    what: &str,
    q: Quantity,
    v: f64,
    positive: bool,
) -> Result<(), ModelError> {
    let el = format!("coupler \"{}\"", spec.name);
    check_number(&el, what, q, v)?;
    if positive && v <= 0.0 {
        return Err(ModelError::NonPositive {
            element: el,
            what: what.into(),
            value: v,
        });
    }
    if v == 0.0 {
        return Err(ModelError::Zero {
            element: el,
            what: what.into(),
        });
    }
    Ok(())
}

fn info(
    spec: &CouplerSpec,
    (body_i, body_j): (BodyId, BodyId),
    coupler: Coupler,
    coordinates: [CoupledCoordinate; 2],
    coefficients: [f64; 2],
) -> CouplerInfo {
    CouplerInfo {
        name: spec.name.clone(),
        body_i,
        body_j,
        coupler,
        coordinates,
        coefficients,
        constant: 0.0,
        gear_radius_j: match spec.kind {
            CouplerKind::Gear {
                ratio: GearRatio::Radii(_, rj),
                ..
            } => Some(rj),
            _ => None,
        },
        rows: 0..0,
        map: ScatterMap { slots: Vec::new() },
    }
}

fn gear(
    spec: &CouplerSpec,
    cx: &Context,
    (name_i, name_j): (&str, &str),
    ratio: GearRatio,
) -> Result<CouplerInfo, ModelError> {
    let rho = match ratio {
        GearRatio::Radii(ri, rj) => {
            nonzero(spec, "radius_i", Quantity::Length, ri, false)?;
            nonzero(spec, "radius_j", Quantity::Length, rj, false)?;
            -ri / rj
        }
        GearRatio::Ratio(k) => {
            nonzero(spec, "ratio", Quantity::Ratio, k, false)?;
            k
        }
    };
    let a = find(spec, cx, "joint_i", name_i, turns)?;
    let b = find(spec, cx, "joint_j", name_j, turns)?;
    let (a, b) = sides(spec, a, b)?;
    let (mi, mj) = (a.marker(), b.marker());
    let (xi, xj) = (pose(cx.bodies, a.other), pose(cx.bodies, b.other));
    let d = xj.point(&mj.point) - xi.point(&mi.point);
    for (m, x) in [(&mi, &xi), (&mj, &xj)] {
        let (u, v) = (x.vector(&m.x()).dot(&d), x.vector(&m.y()).dot(&d));
        if u.hypot(v) <= CENTRE_TOLERANCE * cx.length {
            return Err(ModelError::CouplerGeometry {
                coupler: spec.name.clone(),
                reason: format!(
                    "the axes of joints \"{}\" and \"{}\" are (nearly) the same line; a gear \
                     pair needs two axes apart (its equation uses the direction of each gear \
                     centre seen from the other gear)",
                    a.joint.name, b.joint.name
                ),
            });
        }
    }
    let gear = Gear {
        marker_i: mi,
        marker_j: mj,
        k_i: rho * a.sigma,
        k_j: -b.sigma,
        constant: 0.0,
        reference: [0.0; 2],
    };
    let coords = [angle(a.index), angle(b.index)];
    Ok(info(
        spec,
        (a.other, b.other),
        gear.into(),
        coords,
        [-rho, 1.0],
    ))
}

fn angle(joint: usize) -> CoupledCoordinate {
    CoupledCoordinate {
        joint,
        slide: false,
    }
}

fn slide(joint: usize) -> CoupledCoordinate {
    CoupledCoordinate { joint, slide: true }
}

/// The unit axis `z'` of body `from` in the frame of body `to`, at the initial poses.
fn carried(cx: &Context, from: BodyId, z: &Vector3<f64>, to: BodyId) -> Vector3<f64> {
    let g = pose(cx.bodies, from).vector(z);
    pose(cx.bodies, to).a.transpose() * g
}

fn rack_pinion(
    spec: &CouplerSpec,
    cx: &Context,
    (slide_name, angle_name): (&str, &str),
    radius: f64,
) -> Result<CouplerInfo, ModelError> {
    nonzero(spec, "radius", Quantity::Length, radius, true)?;
    let s = find(spec, cx, "slide_joint", slide_name, slides)?;
    let r = find(spec, cx, "angle_joint", angle_name, turns)?;
    let (s, r) = sides(spec, s, r)?;
    let (ms, mr) = (s.marker(), r.marker());
    // Rack marker: x along the slide, z along the pinion axis (carried into the rack's frame).
    let x = ms.z();
    let z = carried(cx, r.other, &mr.z(), s.other);
    let cos = x.dot(&z) / (x.norm() * z.norm());
    if cos.abs() > AXIS_TOLERANCE {
        return Err(geometry(spec, format!(
            "the slide of joint \"{}\" is not perpendicular to the axis of joint \"{}\" ({:.2}° off); \
             a rack slides across its pinion's axis",
            s.joint.name, r.joint.name, cos.abs().asin().to_degrees()
        )));
    }
    let mi = Marker::from_axes(ms.point, z, x).map_err(|e| geometry(spec, e.to_string()))?;
    let c = RackPinion::new(mi, mr, -s.sigma, radius * r.sigma, 0.0, 0.0);
    let coords = [slide(s.index), angle(r.index)];
    Ok(info(
        spec,
        (s.other, r.other),
        c.into(),
        coords,
        [1.0, radius],
    ))
}

fn geometry(spec: &CouplerSpec, reason: String) -> ModelError {
    ModelError::CouplerGeometry {
        coupler: spec.name.clone(),
        reason,
    }
}

fn screw(
    spec: &CouplerSpec,
    cx: &Context,
    (slide_name, angle_name): (&str, &str),
    pitch: f64,
) -> Result<CouplerInfo, ModelError> {
    nonzero(spec, "pitch", Quantity::Length, pitch, false)?;
    let lead = pitch / (2.0 * PI);
    let s = find(spec, cx, "slide_joint", slide_name, slides)?;
    let r = find(spec, cx, "angle_joint", angle_name, turns)?;
    if s.0 == r.0 {
        // One cylindrical joint: its own markers give s and θ exactly.
        let j = s.1;
        let (mi, mj) = (*j.joint.marker_i(), *j.joint.marker_j());
        let c = Screw::new(mi, mj, 1.0, -lead, 0.0, 0.0);
        let coords = [slide(s.0), angle(s.0)];
        return Ok(info(
            spec,
            (j.body_i, j.body_j),
            c.into(),
            coords,
            [1.0, -lead],
        ));
    }
    let (s, r) = sides(spec, s, r)?;
    let (ms, mr) = (s.marker(), r.marker());
    // Nut marker: z along the screw axis (carried into the nut's frame).
    let z = carried(cx, r.other, &mr.z(), s.other);
    let cos = ms.z().dot(&z) / z.norm();
    if (1.0 - cos * cos).max(0.0).sqrt() > AXIS_TOLERANCE {
        return Err(geometry(
            spec,
            format!(
            "the slide of joint \"{}\" is not along the axis of joint \"{}\" ({:.2}° off); a screw \
             advances along the axis it turns about",
            s.joint.name, r.joint.name, cos.abs().min(1.0).acos().to_degrees()
        ),
        ));
    }
    let eps = cos.signum();
    let mi = Marker::from_axis(ms.point, z).map_err(|e| geometry(spec, e.to_string()))?;
    let c = Screw::new(mi, mr, -eps * s.sigma, -lead * r.sigma, 0.0, 0.0);
    let coords = [slide(s.index), angle(r.index)];
    Ok(info(
        spec,
        (s.other, r.other),
        c.into(),
        coords,
        [1.0, -lead],
    ))
}
