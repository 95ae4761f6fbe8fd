//! `[[limit]]` and `[[friction]]`: end stops on joint coordinates and Coulomb friction in
//! joints, read into the builder's [`LimitSpec`] and [`FrictionSpec`] (their tables were
//! checked against [`LIMITS`] and [`FRICTIONS`] first). The builder checks the rest against the
//! joints (the coordinate exists, lo ≤ hi, e ∈ \[0, 1\], the drawn pose inside the range, a
//! rotating joint's radius); its errors are placed at the limit's or the friction's key
//! (`prepare`).
//!
//! A bound is in its coordinate's unit: rad for an angle, the file's length unit for a slide or
//! a distance. A compliant law's k and c follow the coordinate too: for a length in mm, k is in
//! N/mmⁿ and c in N s/mmⁿ⁺¹.

use super::context::Ctx;
use crate::diag::Error;
use crate::file::{FrictionSection, LimitSection, Name};
use crate::vocabulary::{FRICTIONS, LIMITS};
use cardan_constraints::joints::CoordinateQuantity;
use cardan_constraints::JointKind;
use cardan_mechanism::{Compliance, FrictionSpec, LimitSpec, Quantity};
use std::collections::HashMap;
use toml::Spanned;

/// The law named by `law`, or `default` (placed at the element's name) when the key is absent.
fn law(law: &Option<Name>, name: &Name, default: &str) -> Name {
    law.clone()
        .unwrap_or_else(|| Spanned::new(name.span(), default.to_string()))
}

/// The quantity of the coordinate a limit names on a joint of `kind` (its default as the
/// builder picks it); `None` when the kind has no such coordinate (the builder says so).
fn coordinate_quantity(kind: JointKind, coordinate: Option<&str>) -> Option<CoordinateQuantity> {
    (kind.info().coordinate(coordinate)).map(|c| c.measure.quantity())
}

/// `[[limit]]`: one limit, its law checked against [`LIMITS`].
pub(super) fn load_limit(
    cx: &Ctx,
    section: &Spanned<LimitSection>,
    kinds: &HashMap<String, JointKind>,
) -> Result<LimitSpec, Error> {
    let l = section.get_ref();
    let owner = format!("limit \"{}\"", l.name.get_ref());
    let selected = law(&l.law, &l.name, "impact");
    let entry = cx.check(
        &LIMITS,
        &owner,
        &selected,
        section.span().start,
        l.name.span(),
    )?;
    let coordinate = l.coordinate.as_ref().map(|c| c.get_ref().as_str());
    let measure = kinds
        .get(l.joint.get_ref())
        .and_then(|&k| coordinate_quantity(k, coordinate));
    let (q, length_power): (Quantity, u8) = match measure {
        Some(CoordinateQuantity::Length) => (Quantity::Length, 1),
        _ => (Quantity::Angle, 0),
    };
    let mut spec = LimitSpec::new(l.name.get_ref().clone(), l.joint.get_ref());
    if let Some(c) = &l.coordinate {
        spec = spec.coordinate(c.get_ref());
    }
    if let Some(lo) = &l.lower {
        spec = spec.lower(cx.num(lo, format_args!("{owner}: lower"), q)?);
    }
    if let Some(hi) = &l.upper {
        spec = spec.upper(cx.num(hi, format_args!("{owner}: upper"), q)?);
    }
    if let Some(e) = &l.restitution {
        spec =
            spec.restitution(cx.num(e, format_args!("{owner}: restitution"), Quantity::Ratio)?);
    }
    if entry.name == "compliant" {
        let exponent = match &l.exponent {
            Some(n) => cx.num(n, format_args!("{owner}: exponent"), Quantity::Ratio)?,
            None => 1.0,
        };
        // A slide's k δⁿ with δ in the file's length unit u: k_SI = k · u^(−n), and c δⁿ δ̇
        // one power more; an angle's torque is in N·u: k_SI = k · u, c likewise.
        let unit = cx.units.length();
        let per_length = |power: f64| {
            if length_power == 1 {
                unit.powf(-power)
            } else {
                unit
            }
        };
        let stiffness = l.stiffness.as_ref().map_or(Ok(0.0), |k| {
            cx.num(k, format_args!("{owner}: stiffness"), Quantity::Unbounded)
        })? * per_length(exponent);
        let damping = l.damping.as_ref().map_or(Ok(0.0), |c| {
            cx.num(c, format_args!("{owner}: damping"), Quantity::Unbounded)
        })? * per_length(exponent + 1.0);
        spec = spec.compliant(Compliance {
            stiffness,
            damping,
            exponent,
        });
    }
    Ok(spec)
}

/// `[[friction]]`: one joint friction, its law checked against [`FRICTIONS`]. The stiction
/// velocity is a rate of the file's length unit for a prismatic joint, rad/s otherwise (a
/// cylindrical joint's one value serves its slide in m/s too).
pub(super) fn load_friction(
    cx: &Ctx,
    section: &Spanned<FrictionSection>,
    kinds: &HashMap<String, JointKind>,
) -> Result<FrictionSpec, Error> {
    let f = section.get_ref();
    let owner = format!("friction \"{}\"", f.name.get_ref());
    let selected = law(&f.law, &f.name, "coulomb");
    cx.check(
        &FRICTIONS,
        &owner,
        &selected,
        section.span().start,
        f.name.span(),
    )?;
    let mu = match &f.coefficient {
        Some(m) => cx.num(m, format_args!("{owner}: coefficient"), Quantity::Ratio)?,
        None => 0.0,
    };
    let mut spec = FrictionSpec::new(f.name.get_ref().clone(), f.joint.get_ref(), mu);
    if let Some(r) = &f.radius {
        spec = spec.radius(cx.num(r, format_args!("{owner}: radius"), Quantity::Length)?);
    }
    if let Some(n0) = &f.preload {
        spec = spec.preload(cx.num(n0, format_args!("{owner}: preload"), Quantity::Force)?);
    }
    if let Some(fc) = &f.force {
        spec = spec.constant_force(cx.num(fc, format_args!("{owner}: force"), Quantity::Force)?);
    }
    if let Some(tc) = &f.torque {
        let tc = cx.num(tc, format_args!("{owner}: torque"), Quantity::Torque)?;
        spec = spec.constant_torque(tc);
    }
    if selected.get_ref() == "constant" && spec.force == 0.0 && spec.torque == 0.0 {
        return Err(cx.src.error_at(
            f.name.span(),
            format!(
                "{owner}: a constant friction needs a force (N, a slide) or a torque (N m, a pin \
                 or ball) above 0; without one it does nothing"
            ),
        ));
    }
    if let Some(v) = &f.stiction_velocity {
        let q = match kinds.get(f.joint.get_ref()) {
            Some(JointKind::Prismatic) => Quantity::Velocity,
            _ => Quantity::AngularVelocity,
        };
        let v = cx.num(v, format_args!("{owner}: stiction_velocity"), q)?;
        spec = spec.stiction_velocity(v);
    }
    Ok(spec)
}
