//! `[[force]]` sections to [`Force`] specs. Which keys a type takes was checked from
//! [`crate::vocabulary::FORCES`]; here the names are resolved (bodies, points, joints, with the
//! nearest name on a typo), the numbers read in the quantity their key gives (the model's units
//! converted, the magnitude limits) and the functions loaded. Whether the element makes sense
//! (coefficients ≥ 0, a spring between two bodies that does something, a rotational spring on
//! a joint with an angle and x axes, a translational one on a joint that slides) is checked
//! once, by the dynamics' own validation ([`Force::validate`]) when the model is prepared,
//! located at the key it names ([`super::Spans::force_keys`]).

use super::context::{missing, Resolver};
use super::driver::load_function;
use super::loaded::Spans;
use crate::diag::{did_you_mean, list, Error};
use crate::file::{ForceSection, Name, Num};
use crate::vocabulary::Entry;
use cardan_constraints::JointKind;
use cardan_dynamics::{Force, Frame, PointRef, VectorFunction};
use std::collections::HashMap;

/// One `[[force]]` of the type `entry`.
pub(super) fn load_force(
    r: &Resolver,
    f: &ForceSection,
    entry: &Entry,
    joint_kinds: &HashMap<String, JointKind>,
    spans: &Spans,
) -> Result<Force, Error> {
    let name = f.name.get_ref().clone();
    let owner = format!("force \"{name}\"");
    let number = |v: &Option<Num>, key: &str| -> Result<Option<f64>, Error> {
        v.as_ref()
            .map(|n| {
                r.cx.num(n, format_args!("{owner}: {key}"), entry.quantity(key))
            })
            .transpose()
    };
    let need = |v: &Option<Name>, key: &str| -> Result<Name, Error> {
        v.clone().ok_or_else(|| {
            let why = format!("a {} force needs it", entry.name);
            missing(r.cx, f.name.span(), &owner, key, &why)
        })
    };
    match entry.name {
        "point_force" | "torque" => applied(r, f, entry, &owner),
        "spring_damper" => {
            let (bi, pi, bj, pj) = (
                need(&f.body_i, "body_i")?,
                need(&f.point_i, "point_i")?,
                need(&f.body_j, "body_j")?,
                need(&f.point_j, "point_j")?,
            );
            let bi_s = r.body(&bi, &owner)?;
            let bj_s = r.body(&bj, &owner)?;
            r.feature(bi_s, &pi, &owner, true)?;
            r.feature(bj_s, &pj, &owner, true)?;
            let actuator = match &f.actuator {
                Some(a) => Some(load_function(r.cx, a, &owner, entry.quantity("actuator"))?),
                None => None,
            };
            Ok(Force::SpringDamperActuator {
                point_i: PointRef::Local(r.point_value(bi_s, pi.get_ref())),
                point_j: PointRef::Local(r.point_value(bj_s, pj.get_ref())),
                body_i: bi_s.into(),
                body_j: bj_s.into(),
                stiffness: number(&f.stiffness, "stiffness")?.unwrap_or(0.0),
                damping: number(&f.damping, "damping")?.unwrap_or(0.0),
                free_length: number(&f.free_length, "free_length")?,
                actuator,
                name,
            })
        }
        _ => {
            let j = need(&f.joint, "joint")?;
            let jn = j.get_ref();
            if !joint_kinds.contains_key(jn) {
                let hint = did_you_mean(jn, joint_kinds.keys().map(String::as_str));
                let mut names: Vec<&str> = joint_kinds.keys().map(String::as_str).collect();
                names.sort_by_key(|n| spans.joints.get(*n).map(|s| s.start));
                return Err(r.cx.err(
                    j.span(),
                    format!(
                        "{owner}: unknown joint \"{jn}\"{hint} (joints: {})",
                        list(names)
                    ),
                ));
            }
            let (k, c) = (
                number(&f.stiffness, "stiffness")?.unwrap_or(0.0),
                number(&f.damping, "damping")?.unwrap_or(0.0),
            );
            Ok(if entry.name == "translational_spring_damper" {
                let s0 = number(&f.rest_position, "rest_position")?.unwrap_or(0.0);
                Force::translational_spring_damper(&name, jn, k, c, s0)
            } else {
                let theta0 = number(&f.rest_angle, "rest_angle")?.unwrap_or(0.0);
                Force::rotational_spring_damper(&name, jn, k, c, theta0)
            })
        }
    }
}

/// A `point_force` or a `torque`: the body (and point), a constant `value` or three
/// `components` functions, and the frame.
fn applied(r: &Resolver, f: &ForceSection, entry: &Entry, owner: &str) -> Result<Force, Error> {
    let cx = r.cx;
    let name = f.name.get_ref();
    let b = f
        .body
        .clone()
        .ok_or_else(|| missing(cx, f.name.span(), owner, "body", "the moving body"))?;
    let body = r.body(&b, owner)?;
    let value_q = entry.quantity("value");
    let value =
        match (&f.value, &f.components) {
            (Some(v), None) => {
                VectorFunction::Constant(cx.vec3(v, format_args!("{owner}: value"), value_q)?)
            }
            (None, Some(c)) => {
                let list = c.get_ref();
                if list.len() != 3 {
                    return Err(cx.err(
                        c.span(),
                        format!(
                            "{owner}: components needs three functions (x, y, z), got {}",
                            list.len()
                        ),
                    ));
                }
                let mut fs = Vec::with_capacity(3);
                for g in list {
                    fs.push(load_function(cx, g, owner, value_q)?);
                }
                let [fx, fy, fz]: [_; 3] = fs.try_into().expect("three functions");
                VectorFunction::Components(Box::new([fx, fy, fz]))
            }
            (Some(_), Some(c)) => {
                return Err(cx.err(
                    c.span(),
                    format!("{owner}: give value (constant) or components (functions), not both"),
                ))
            }
            (None, None) => return Err(missing(
                cx,
                f.name.span(),
                owner,
                "value",
                "a constant vector, or components = [{...}, {...}, {...}] for functions of time",
            )),
        };
    // The choices were checked by the vocabulary.
    let frame = match f.frame.as_ref().map(|fr| fr.get_ref().as_str()) {
        Some("body" | "local") => Frame::Body,
        _ => Frame::Global,
    };
    if entry.name == "torque" {
        return Ok(Force::torque(name, body, value, frame));
    }
    let p = f.point.clone().ok_or_else(|| {
        missing(
            cx,
            f.name.span(),
            owner,
            "point",
            "the point of application",
        )
    })?;
    r.feature(body, &p, owner, true)?;
    let local = r.point_value(body, p.get_ref());
    Ok(Force::point_force(
        name,
        body,
        PointRef::Local(local),
        value,
        frame,
    ))
}
