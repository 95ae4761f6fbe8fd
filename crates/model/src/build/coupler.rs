//! `[[coupler]]` sections to [`CouplerSpec`]s: the numbers (the type and which keys it takes
//! are checked from [`crate::vocabulary::COUPLERS`] before). The joints (existence, kinds, a shared body, the
//! geometry of their axes) and the signs of radii and pitch are checked by the builder, whose
//! errors [`super::Spans::locate`] places at the key.

use super::context::{missing, Ctx};
use crate::diag::Error;
use crate::file::{CouplerSection, Name, Num};
use cardan_mechanism::{CouplerSpec, GearRatio, Quantity};

pub(super) fn load_coupler(cx: &Ctx, c: &CouplerSection) -> Result<CouplerSpec, Error> {
    let name = c.name.get_ref().clone();
    let owner = format!("coupler \"{name}\"");
    let kind = c.kind.get_ref().as_str();
    let span = c.name.span();
    let need = |v: &Option<Name>, key: &str, why: &str| -> Result<String, Error> {
        v.as_ref()
            .map(|n| n.get_ref().clone())
            .ok_or_else(|| missing(cx, span.clone(), &owner, key, why))
    };
    let number = |v: &Option<Num>, key: &str, q: Quantity, why: &str| -> Result<f64, Error> {
        match v {
            Some(n) => cx.num(n, format_args!("{owner} {key}"), q),
            None => Err(missing(cx, span.clone(), &owner, key, why)),
        }
    };
    let spec = match kind {
        "gear" => {
            let ji = need(&c.joint_i, "joint_i", "the joint of gear i")?;
            let jj = need(&c.joint_j, "joint_j", "the joint of gear j")?;
            let ratio = match (&c.radius_i, &c.radius_j, &c.ratio) {
                (_, _, Some(r)) if c.radius_i.is_some() || c.radius_j.is_some() => {
                    return Err(cx.err(
                        r.span(),
                        format!("{owner}: give radius_i and radius_j, or ratio, not both"),
                    ))
                }
                (_, _, Some(r)) => {
                    GearRatio::Ratio(cx.num(r, format_args!("{owner} ratio"), Quantity::Ratio)?)
                }
                _ => {
                    let why = "the pitch radii (or give ratio)";
                    GearRatio::Radii(
                        number(&c.radius_i, "radius_i", Quantity::Length, why)?,
                        number(&c.radius_j, "radius_j", Quantity::Length, why)?,
                    )
                }
            };
            CouplerSpec::gear(name, &ji, &jj, ratio)
        }
        "rack_pinion" => {
            let s = need(&c.slide_joint, "slide_joint", "the rack's prismatic joint")?;
            let a = need(&c.angle_joint, "angle_joint", "the pinion's revolute joint")?;
            let r = number(
                &c.radius,
                "radius",
                Quantity::Length,
                "the pinion's pitch radius",
            )?;
            CouplerSpec::rack_pinion(name, &s, &a, r)
        }
        _ => {
            let p = number(
                &c.pitch,
                "pitch",
                Quantity::Length,
                "the advance per revolution",
            )?;
            let (s, a) = match (&c.joint, &c.slide_joint, &c.angle_joint) {
                (Some(j), None, None) => (j.get_ref().clone(), j.get_ref().clone()),
                (None, _, _) => (
                    need(
                        &c.slide_joint,
                        "slide_joint",
                        "or one cylindrical joint as \"joint\"",
                    )?,
                    need(
                        &c.angle_joint,
                        "angle_joint",
                        "or one cylindrical joint as \"joint\"",
                    )?,
                ),
                (Some(j), _, _) => {
                    return Err(cx.err(
                        j.span(),
                        format!(
                            "{owner}: give \"joint\" (one cylindrical joint) or \"slide_joint\" \
                             and \"angle_joint\", not both"
                        ),
                    ))
                }
            };
            CouplerSpec::screw(name, &s, &a, p)
        }
    };
    Ok(match &c.constant {
        Some(n) => {
            let q = if kind == "gear" {
                Quantity::Angle
            } else {
                Quantity::Length
            };
            spec.constant(cx.num(n, format_args!("{owner} constant"), q)?)
        }
        None => spec,
    })
}
