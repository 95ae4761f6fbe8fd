//! Joint friction: a [`FrictionSpec`] checked against its joint (a kind that slides or turns
//! about an axis, or a ball joint) and turned into a [`FrictionInfo`], with errors naming the
//! element and the key.

use super::elements::{FrictionInfo, JointInfo};
use super::validate::suggest;
use super::Model;
use crate::builder::FrictionSpec;
use crate::error::ModelError;
use cardan_constraints::JointKind;

fn bad(spec: &FrictionSpec, key: &str, reason: String) -> ModelError {
    ModelError::BadFriction {
        friction: spec.name.clone(),
        joint: spec.joint.clone(),
        key: key.into(),
        reason,
    }
}

/// The kinds friction applies to.
pub const FRICTION_KINDS: [JointKind; 4] = [
    JointKind::Revolute,
    JointKind::Prismatic,
    JointKind::Cylindrical,
    JointKind::Spherical,
];

pub(crate) fn friction(
    spec: &FrictionSpec,
    joints: &[JointInfo],
) -> Result<FrictionInfo, ModelError> {
    let k = joints
        .iter()
        .position(|j| j.name == spec.joint)
        .ok_or_else(|| ModelError::UnknownJoint {
            element: format!("friction \"{}\"", spec.name),
            name: spec.joint.clone(),
            suggestion: suggest(&spec.joint, joints.iter().map(|j| j.name.as_str())),
            known: joints.iter().map(|j| j.name.clone()).collect(),
        })?;
    let kind = joints[k].joint.kind();
    if !FRICTION_KINDS.contains(&kind) {
        return Err(bad(
            spec,
            "joint",
            format!(
                "joint \"{}\" is {}; friction applies to revolute, prismatic, cylindrical and \
                 spherical joints",
                spec.joint,
                kind.name()
            ),
        ));
    }
    let mu = spec.coefficient;
    if !(mu.is_finite() && mu >= 0.0) {
        return Err(bad(spec, "coefficient", format!("μ = {mu} must be ≥ 0")));
    }
    let n0 = spec.preload;
    if !(n0.is_finite() && n0 >= 0.0) {
        return Err(bad(spec, "preload", format!("must be ≥ 0, got {n0}")));
    }
    let vs = spec.stiction_velocity;
    if !(vs.is_finite() && vs > 0.0) {
        return Err(bad(
            spec,
            "stiction_velocity",
            format!("must be positive, got {vs}"),
        ));
    }
    let radius = match (kind, spec.radius) {
        (JointKind::Prismatic, None) => 0.0,
        (JointKind::Prismatic, Some(_)) => {
            return Err(bad(
                spec,
                "radius",
                "a prismatic joint's friction takes no radius".into(),
            ))
        }
        (_, Some(r)) if r.is_finite() && r > 0.0 => r,
        // A constant torque alone needs no pin radius.
        (_, None) if mu == 0.0 => 0.0,
        (_, r) => {
            return Err(bad(
                spec,
                "radius",
                format!(
                    "a {} joint's friction needs a pin radius > 0, got {r:?}",
                    kind.name()
                ),
            ))
        }
    };
    constants(spec, kind)?;
    Ok(FrictionInfo {
        name: spec.name.clone(),
        joint: k,
        coefficient: mu,
        radius,
        preload: n0,
        stiction_velocity: vs,
        force: spec.force,
        torque: spec.torque,
    })
}

/// The constant friction force and torque: finite, ≥ 0, each on a joint with that motion (a
/// force on a slide, a torque on a pin or ball).
fn constants(spec: &FrictionSpec, kind: JointKind) -> Result<(), ModelError> {
    let slides = matches!(kind, JointKind::Prismatic | JointKind::Cylindrical);
    let turns = kind != JointKind::Prismatic;
    for (key, value, fits, motion) in [
        ("force", spec.force, slides, "slide"),
        ("torque", spec.torque, turns, "rotation"),
    ] {
        if !(value.is_finite() && value >= 0.0) {
            return Err(bad(spec, key, format!("must be ≥ 0, got {value}")));
        }
        if value > 0.0 && !fits {
            return Err(bad(
                spec,
                key,
                format!(
                    "joint \"{}\" is {}, which has no {motion}: a slide takes a force (N), a \
                     pin or ball a torque (N m)",
                    spec.joint,
                    kind.name()
                ),
            ));
        }
    }
    Ok(())
}

impl Model {
    /// The joints' friction elements.
    pub fn frictions(&self) -> &[FrictionInfo] {
        &self.frictions
    }
}
