//! `[[curve]]` sections to [`CurveSpec`]s: the curve built in body i's coordinates from the
//! body's named point and vectors (a line, a circle, a helix) or from a list of points (a
//! spline), its own errors (a zero radius, repeated points, a closed spline whose ends do not
//! meet) placed at the key. Body j and its point are resolved by the builder, whose errors
//! [`super::Spans::locate`] places at the key.

use super::context::{missing, Ctx, Resolver};
use crate::diag::Error;
use crate::file::{CurveSection, Name, Num, Vec3};
use cardan_constraints::{Circle, ConstraintError, CubicCurve, Curve, Helix, Line, Marker};
use cardan_mechanism::{CurveSpec, Quantity};
use nalgebra::Vector3;
use std::ops::Range;
use toml::Spanned;

/// The curve of `c` (its kind checked against [`crate::vocabulary::CURVES`]: `kind` is the
/// entry's name) and the element.
pub(super) fn load_curve(
    r: &Resolver,
    section: &Spanned<CurveSection>,
    kind: &str,
) -> Result<CurveSpec, Error> {
    let cx = r.cx;
    let c = section.get_ref();
    let owner = format!("curve \"{}\"", c.name.get_ref());
    let bi = r.body(&c.body_i, &owner)?;
    let curve = if kind == "spline" {
        let Some(points) = &c.points else {
            return Err(missing(
                cx,
                c.name.span(),
                &owner,
                "points",
                "a spline needs them",
            ));
        };
        let closed = c.closed.as_ref().is_some_and(|f| *f.get_ref());
        spline(cx, points, (closed, c.interpolation.as_ref()), &owner)?
    } else {
        let (Some(p), Some(z)) = (&c.point_i, &c.axis_i) else {
            let key = if c.point_i.is_none() {
                "point_i"
            } else {
                "axis_i"
            };
            return Err(missing(
                cx,
                c.name.span(),
                &owner,
                key,
                "the curve needs it",
            ));
        };
        let m = marker(r, bi, (p, z, c.x_axis_i.as_ref()), &owner)?;
        let radius = || {
            (c.radius.as_ref())
                .ok_or_else(|| missing(cx, c.name.span(), &owner, "radius", "the curve needs it"))
        };
        match kind {
            "line" => Curve::Line(Line::new(&m)),
            "circle" => circle(cx, &m, radius()?, "radius", &owner)?,
            _ => {
                let Some(pitch) = &c.pitch else {
                    return Err(missing(
                        cx,
                        c.name.span(),
                        &owner,
                        "pitch",
                        "a helix needs it",
                    ));
                };
                let h = cx.num(pitch, format_args!("{owner}: pitch"), Quantity::Length)?;
                let r = cx.num(radius()?, format_args!("{owner}: radius"), Quantity::Length)?;
                let helix = Helix::new(&m, r, h).map_err(placed(cx, pitch.span(), &owner))?;
                Curve::Helix(helix)
            }
        }
    };
    let mut spec = CurveSpec::new(
        c.name.get_ref().clone(),
        bi,
        curve,
        c.body_j.get_ref(),
        c.point_j.get_ref(),
    );
    if let Some(u) = &c.initial_u {
        spec = spec.initial_u(cx.num(u, format_args!("{owner}: initial_u"), Quantity::Length)?);
    }
    Ok(spec)
}

/// A constraint-layer error about a curve, as an error of `owner` at `span` (a curve's own
/// reason without its "curve:" prefix).
pub(super) fn placed<'a>(
    cx: &'a Ctx,
    span: Range<usize>,
    owner: &'a str,
) -> impl Fn(ConstraintError) -> Error + 'a {
    move |e: ConstraintError| {
        let why = match e {
            ConstraintError::Curve(why) => why,
            e => e.to_string(),
        };
        cx.err(span.clone(), format!("{owner}: {why}"))
    }
}

/// The circle of radius `radius` (the value of key `key`) about marker `m`'s z axis.
pub(super) fn circle(
    cx: &Ctx,
    m: &Marker,
    radius: &Num,
    key: &str,
    owner: &str,
) -> Result<Curve, Error> {
    let r = cx.num(radius, format_args!("{owner}: {key}"), Quantity::Length)?;
    let circle = Circle::new(m, r).map_err(placed(cx, radius.span(), owner))?;
    Ok(Curve::Circle(circle))
}

/// The spline through `points` (body i's coordinates), open or `closed`, cubic or (key
/// `interpolation = "quintic"`, checked by the vocabulary) quintic.
pub(super) fn spline(
    cx: &Ctx,
    points: &Spanned<Vec<Vec3>>,
    (closed, interpolation): (bool, Option<&Name>),
    owner: &str,
) -> Result<Curve, Error> {
    let mut p = Vec::with_capacity(points.get_ref().len());
    for (k, v) in points.get_ref().iter().enumerate() {
        p.push(cx.vec3(v, format_args!("{owner}: points[{k}]"), Quantity::Length)?);
    }
    let spline = match interpolation.map(|n| n.get_ref().as_str()) {
        Some("quintic") => CubicCurve::quintic(p, closed),
        _ => CubicCurve::new(p, closed),
    };
    Ok(Curve::Cubic(spline.map_err(placed(
        cx,
        points.span(),
        owner,
    ))?))
}

/// The frame of a line, a circle or a helix (or a cam's disc, a follower's face or roller):
/// origin `p`, z along `z`, x along the part of `x` perpendicular to it (any perpendicular when
/// absent), all features of body `bi`.
pub(super) fn marker(
    r: &Resolver,
    bi: &str,
    (p, z, x): (&Name, &Name, Option<&Name>),
    owner: &str,
) -> Result<Marker, Error> {
    let cx: &Ctx = r.cx;
    r.feature(bi, p, owner, true)?;
    r.feature(bi, z, owner, false)?;
    let origin = r.point_value(bi, p.get_ref());
    let axis = r.vector_value(bi, z.get_ref());
    let frame = match x {
        Some(x) => {
            r.feature(bi, x, owner, false)?;
            let xv: Vector3<f64> = r.vector_value(bi, x.get_ref());
            if axis.normalize().cross(&xv.normalize()).norm() < 1e-6 {
                return Err(cx.err(
                    x.span(),
                    format!(
                        "{owner}: x axis \"{}\" is parallel to axis \"{}\"; it must point \
                         from the centre to where u = 0, across the axis",
                        x.get_ref(),
                        z.get_ref()
                    ),
                ));
            }
            Marker::from_axes(origin, axis, xv)
        }
        None => Marker::from_axis(origin, axis),
    };
    frame.map_err(|e| cx.err(z.span(), format!("{owner}: {e}")))
}
