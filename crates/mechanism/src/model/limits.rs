//! Limits: a [`LimitSpec`] checked against its joint and turned into a [`LimitInfo`] and its
//! stops ([`StopInfo`], one [`JointLimit`] row per bound), each with the errors that name the
//! limit and the key. The drawn pose must respect the limit.

use super::elements::{BodyId, BodyInfo, JointInfo, LimitInfo, StopInfo};
use super::validate::suggest;
use crate::builder::{Compliance, LimitSpec};
use crate::error::ModelError;
use crate::sanity::Quantity;
use cardan_constraints::joints::{Coordinate, CoordinateQuantity};
use cardan_constraints::{BodyPair, BodyState, Bound, JointLimit};

/// How far (relative to the model's length, or in rad) the drawn pose may lie beyond a bound.
pub(crate) const DRAWN_TOLERANCE: f64 = 1e-9;

fn bad(spec: &LimitSpec, key: &str, reason: String) -> ModelError {
    ModelError::BadLimit {
        limit: spec.name.clone(),
        joint: spec.joint.clone(),
        key: key.into(),
        reason,
    }
}

/// The limit `spec` on one of `joints` (at index `limit`) and its stops.
pub(crate) fn limit(
    spec: &LimitSpec,
    index: usize,
    joints: &[JointInfo],
    bodies: &[BodyInfo],
    length: f64,
) -> Result<(LimitInfo, Vec<StopInfo>), ModelError> {
    let element = format!("limit \"{}\"", spec.name);
    let k = joints
        .iter()
        .position(|j| j.name == spec.joint)
        .ok_or_else(|| ModelError::UnknownJoint {
            element: element.clone(),
            name: spec.joint.clone(),
            suggestion: suggest(&spec.joint, joints.iter().map(|j| j.name.as_str())),
            known: joints.iter().map(|j| j.name.clone()).collect(),
        })?;
    let j = &joints[k];
    let c = coordinate(spec, j)?;
    if c.measure == cardan_constraints::joints::Measure::Angle && !j.has_x_axes {
        // As for a rotation driver: without x axes the angle's zero is a perpendicular the
        // program picks, and a bound on it means nothing.
        return Err(bad(
            spec,
            "coordinate",
            format!(
                "a limit on the angle of joint \"{}\" needs its x axes (x_axis_i, x_axis_j: the \
                 zero of the angle)",
                j.name
            ),
        ));
    }
    let quantity = match c.measure.quantity() {
        CoordinateQuantity::Angle => Quantity::Angle,
        CoordinateQuantity::Length => Quantity::Length,
    };
    for (key, v) in [("lower", spec.lower), ("upper", spec.upper)] {
        if let Some(v) = v {
            if !v.is_finite() {
                return Err(bad(spec, key, format!("is not finite ({v})")));
            }
            if v.abs() > quantity.limit() {
                let (lim, unit) = (quantity.limit(), quantity.unit());
                return Err(bad(
                    spec,
                    key,
                    format!("{v:e} {unit} is beyond the limit of {lim:e} {unit} (in SI units)"),
                ));
            }
        }
    }
    if spec.lower.is_none() && spec.upper.is_none() {
        return Err(bad(
            spec,
            "lower",
            "give a lower bound, an upper bound or both".into(),
        ));
    }
    if let (Some(lo), Some(hi)) = (spec.lower, spec.upper) {
        if lo > hi {
            return Err(bad(
                spec,
                "upper",
                format!("lower {lo} > upper {hi}: the range is empty"),
            ));
        }
    }
    let e = spec.restitution;
    if !(0.0..=1.0).contains(&e) {
        return Err(bad(
            spec,
            "restitution",
            format!("e = {e} must lie in [0, 1]"),
        ));
    }
    if let Some(law) = spec.compliance {
        compliance(spec, &law)?;
    }
    let info = LimitInfo {
        name: spec.name.clone(),
        joint: k,
        coordinate: c.name,
        measure: c.measure,
        lower: spec.lower,
        upper: spec.upper,
        restitution: e,
        compliance: spec.compliance,
    };
    let stops = stops(spec, index, j, &info, bodies, length)?;
    Ok((info, stops))
}

/// The joint coordinate named by the spec, or the kind's default (its only coordinate, else
/// its rotation, else its translation).
fn coordinate(spec: &LimitSpec, j: &JointInfo) -> Result<Coordinate, ModelError> {
    let info = j.joint.kind().info();
    let names: Vec<&str> = info.coordinates.iter().map(|c| c.name).collect();
    let list = if names.is_empty() {
        "none".to_string()
    } else {
        names.join(", ")
    };
    if let Some(c) = info.coordinate(spec.coordinate.as_deref()) {
        return Ok(*c);
    }
    let message = match spec.coordinate.as_deref() {
        None => format!(
            "joint \"{}\" ({}) has coordinates {list}: name one",
            j.name, info.name
        ),
        Some(name) => {
            let hint = suggest(name, names.iter().copied())
                .map(|s| format!(" (did you mean \"{s}\"?)"))
                .unwrap_or_default();
            format!(
                "a {} joint has no coordinate \"{name}\"{hint}; its coordinates: {list}",
                info.name
            )
        }
    };
    Err(bad(spec, "coordinate", message))
}

fn compliance(spec: &LimitSpec, law: &Compliance) -> Result<(), ModelError> {
    let Compliance {
        stiffness,
        damping,
        exponent,
    } = *law;
    if !(stiffness.is_finite() && stiffness > 0.0) {
        return Err(bad(
            spec,
            "stiffness",
            format!("must be positive, got {stiffness}"),
        ));
    }
    if !(damping.is_finite() && damping >= 0.0) {
        return Err(bad(spec, "damping", format!("must be ≥ 0, got {damping}")));
    }
    if !(exponent.is_finite() && exponent >= 1.0) {
        return Err(bad(
            spec,
            "exponent",
            format!("must be ≥ 1, got {exponent}"),
        ));
    }
    Ok(())
}

/// The stops of a checked limit, their angles continued from the drawn pose, which must lie in
/// the range.
fn stops(
    spec: &LimitSpec,
    index: usize,
    j: &JointInfo,
    info: &LimitInfo,
    bodies: &[BodyInfo],
    length: f64,
) -> Result<Vec<StopInfo>, ModelError> {
    let drawn = |id: BodyId| match id {
        BodyId::Ground => BodyState::ground(),
        BodyId::Moving(k) => BodyState::at(bodies[k].initial_r, bodies[k].initial_p),
    };
    let (si, sj) = (drawn(j.body_i), drawn(j.body_j));
    let pair = BodyPair::new(&si, &sj);
    let (mi, mj) = (*j.joint.marker_i(), *j.joint.marker_j());
    let scale = match info.measure.quantity() {
        CoordinateQuantity::Angle => 1.0,
        CoordinateQuantity::Length => length,
    };
    let mut out = Vec::new();
    for (bound, value) in [(Bound::Lower, info.lower), (Bound::Upper, info.upper)] {
        let Some(value) = value else { continue };
        let mut row = JointLimit::new(mi, mj, info.measure, bound, value);
        // The drawn angle's principal value is the reference the run continues.
        row.accept(&pair);
        let c = row.coordinate(&pair);
        if row.definition(&pair) < 1e-6 * if scale == 1.0 { 1.0 } else { scale } {
            return Err(bad(
                spec,
                "coordinate",
                format!(
                    "the {} of joint \"{}\" is undefined at the drawn pose",
                    info.coordinate, j.name
                ),
            ));
        }
        if row.gap(&pair) < -DRAWN_TOLERANCE * scale {
            return Err(ModelError::LimitViolated {
                limit: spec.name.clone(),
                key: bound.name(),
                joint: j.name.clone(),
                coordinate: info.coordinate,
                value: c,
                bound: value,
            });
        }
        out.push(StopInfo {
            name: format!("{}.{}", spec.name, bound.name()),
            limit: index,
            body_i: j.body_i,
            body_j: j.body_j,
            row,
        });
    }
    Ok(out)
}
