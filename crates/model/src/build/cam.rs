//! `[[cam]]` sections to [`CamSpec`]s: the cam's profile (a disc about a point of body i, or a
//! closed spline through points) in the plane normal to `axis_i`, and the follower's curve on
//! body j (a flat face: the line through point_j along axis_j; a roller: the circle of radius r
//! about point_j and axis_j), each curve's errors placed at its key.

use super::context::{missing, Ctx, Resolver};
use super::curve::{circle, marker, spline};
use crate::diag::Error;
use crate::file::CamSection;
use cardan_constraints::{Curve, Line};
use cardan_mechanism::{CamSpec, Quantity};
use toml::Spanned;

/// The cam pair of `section` (its follower kind checked against [`crate::vocabulary::CAMS`]:
/// `follower` is the entry's name).
pub(super) fn load_cam(
    r: &Resolver,
    section: &Spanned<CamSection>,
    follower: &str,
) -> Result<CamSpec, Error> {
    let cx: &Ctx = r.cx;
    let c = section.get_ref();
    let owner = format!("cam \"{}\"", c.name.get_ref());
    let bi = r.body(&c.body_i, &owner)?;
    let bj = r.body(&c.body_j, &owner)?;
    r.feature(bi, &c.axis_i, &owner, false)?;
    let normal = r.vector_value(bi, c.axis_i.get_ref());
    let need = |key: &str, why: &str| missing(cx, c.name.span(), &owner, key, why);
    let refuse = |span, key: &str, profile: &str| {
        cx.err(
            span,
            format!(
                "{owner}: {key} is for profile = \"{profile}\", not \"{}\"",
                c.profile.get_ref()
            ),
        )
    };
    let profile = match c.profile.get_ref().as_str() {
        "disc" => {
            if let Some(p) = &c.points {
                return Err(refuse(p.span(), "points", "spline"));
            }
            if let Some(i) = &c.interpolation {
                return Err(refuse(i.span(), "interpolation", "spline"));
            }
            let p =
                (c.point_i.as_ref()).ok_or_else(|| need("point_i", "a disc needs its centre"))?;
            let radius = (c.radius.as_ref()).ok_or_else(|| need("radius", "a disc needs it"))?;
            let m = marker(r, bi, (p, &c.axis_i, c.x_axis_i.as_ref()), &owner)?;
            circle(cx, &m, radius, "radius", &owner)?
        }
        "spline" => {
            for (key, span) in [
                ("point_i", c.point_i.as_ref().map(Spanned::span)),
                ("radius", c.radius.as_ref().map(|n| n.span())),
                ("x_axis_i", c.x_axis_i.as_ref().map(Spanned::span)),
            ] {
                if let Some(span) = span {
                    return Err(refuse(span, key, "disc"));
                }
            }
            let points =
                (c.points.as_ref()).ok_or_else(|| need("points", "a spline needs them"))?;
            spline(cx, points, (true, c.interpolation.as_ref()), &owner)?
        }
        other => {
            return Err(cx.err(
                c.profile.span(),
                format!("{owner}: unknown profile \"{other}\" (profiles: \"disc\", \"spline\")"),
            ))
        }
    };
    let axis_j = (c.axis_j.as_ref()).ok_or_else(|| need("axis_j", "the follower needs it"))?;
    let m = marker(r, bj, (&c.point_j, axis_j, None), &owner)?;
    let curve_j = if follower == "roller" {
        let radius =
            (c.roller_radius.as_ref()).ok_or_else(|| need("roller_radius", "a roller needs it"))?;
        circle(cx, &m, radius, "roller_radius", &owner)?
    } else {
        // The face: the line through point_j along axis_j (the marker's z).
        Curve::Line(Line::new(&m))
    };
    let mut spec = CamSpec::new(
        c.name.get_ref().clone(),
        (bi, profile, normal),
        (bj, curve_j),
    );
    match (&c.initial_u, &c.initial_w) {
        (Some(u), Some(w)) => {
            let u = cx.num(u, format_args!("{owner}: initial_u"), Quantity::Length)?;
            let w = cx.num(w, format_args!("{owner}: initial_w"), Quantity::Length)?;
            spec = spec.initial(u, w);
        }
        (None, None) => {}
        (Some(n), None) | (None, Some(n)) => {
            return Err(cx.err(
                n.span(),
                format!("{owner}: give both initial_u and initial_w, or neither"),
            ))
        }
    }
    Ok(spec)
}
