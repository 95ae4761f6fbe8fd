//! Resolution of a [`CurveSpec`]: its bodies and point by name, its curve parameter's index
//! among the extra coordinates and its value at the drawn pose (given, or the nearest curve
//! point to the drawn point; an open curve's parameter must lie on the curve); of a
//! [`PathSpec`]: its curve element by name and its function checked.

use super::elements::{CurveElement, CurveInfo, PathInfo, ScatterMap};
use super::resolve::{pose, Names};
use super::validate::check_number;
use super::{BodyId, BodyInfo};
use crate::curve_spec::{CamSpec, CurveSpec, PathSpec, SurfaceSpec};
use crate::error::ModelError;
use crate::sanity::Quantity;
use cardan_constraints::{Curve, CurveOnCurve, PathDriver, PointOnCurve, PointOnSurface};
use nalgebra::{Matrix3, Vector3};

/// The model form of `spec`, whose curve parameter is extra coordinate `extra`.
pub(super) fn curve(
    spec: &CurveSpec,
    extra: usize,
    names: &Names,
    bodies: &[BodyInfo],
) -> Result<CurveInfo, ModelError> {
    let el = format!("point-on-curve \"{}\"", spec.name);
    let (bi, bj) = names.pair(&el, &spec.body_i, &spec.body_j)?;
    let sp_j = names.feature(&el, &spec.body_j, &spec.point_j, false)?;
    let (si, sj) = (pose(bodies, bi), pose(bodies, bj));
    let initial_u = match spec.initial_u {
        Some(u) => {
            check_number(&el, "initial curve parameter", Quantity::Length, u)?;
            u
        }
        // The drawn point in the curve body's frame.
        None => spec
            .curve
            .closest(&(si.a.transpose() * (sj.point(&sp_j) - si.r))),
    };
    in_domain(|| el.clone(), spec.curve.domain(), initial_u)?;
    // The drawn point on its curve, within 1e-3 of the element's size.
    let drawn = si.a.transpose() * (sj.point(&sp_j) - si.r);
    let at = spec.curve.jet(initial_u).c;
    drawn_on(&el, "curve", (at, drawn), size(&spec.curve))?;
    let element = CurveElement::Point(PointOnCurve::new(spec.curve.clone(), sp_j));
    Ok(info(&spec.name, (bi, bj), element, extra, [initial_u, 0.0]))
}

/// The model form of point-on-surface `spec`, whose parameters are extra coordinates `extra`
/// (u) and `extra + 1` (v).
pub(super) fn surface(
    spec: &SurfaceSpec,
    extra: usize,
    names: &Names,
    bodies: &[BodyInfo],
) -> Result<CurveInfo, ModelError> {
    let el = format!("point-on-surface \"{}\"", spec.name);
    let (bi, bj) = names.pair(&el, &spec.body_i, &spec.body_j)?;
    let sp_j = names.feature(&el, &spec.body_j, &spec.point_j, false)?;
    let (si, sj) = (pose(bodies, bi), pose(bodies, bj));
    // The drawn point in the surface body's frame.
    let drawn = si.a.transpose() * (sj.point(&sp_j) - si.r);
    let initial = match spec.initial {
        Some([u, v]) => {
            check_number(&el, "initial surface parameter u", Quantity::Length, u)?;
            check_number(&el, "initial surface parameter v", Quantity::Length, v)?;
            [u, v]
        }
        None => spec.surface.closest(&drawn),
    };
    let domains = spec
        .surface
        .domain()
        .map_or([None; 2], |[a, b]| [Some(a), Some(b)]);
    for (x, domain) in initial.into_iter().zip(domains) {
        in_domain(|| el.clone(), domain, x)?;
    }
    let at = spec.surface.jet(initial[0], initial[1]).s;
    drawn_on(&el, "surface", (at, drawn), spec.surface.size())?;
    let element = CurveElement::Surface(PointOnSurface::new(spec.surface.clone(), sp_j));
    Ok(info(&spec.name, (bi, bj), element, extra, initial))
}

/// [`ModelError::CurveApart`] for element `el` when its point drawn at `drawn` is farther from
/// its nearest point `at` on the `what` ("curve", "surface") than 1e-3 of the larger of the
/// geometry's `size` and the point's distance from the origin of the geometry's body.
fn drawn_on(
    el: &str,
    what: &str,
    (at, drawn): (Vector3<f64>, Vector3<f64>),
    size: f64,
) -> Result<(), ModelError> {
    let gap = (at - drawn).norm();
    let tolerance = 1e-3 * size.max(drawn.norm());
    if gap > tolerance {
        return Err(ModelError::CurveApart {
            element: el.to_string(),
            what: format!("the point is off its {what}"),
            gap,
            tolerance,
            unit: " m",
            advice: match what {
                "surface" => {
                    "draw the point on the surface (the assembly would pull the bodies together \
                     silently): check point_j and the bodies' positions, or the surface's data"
                }
                _ => {
                    "draw the point on the curve (the assembly would pull the bodies together \
                     silently): check point_j and the bodies' positions, or the curve's data"
                }
            },
        });
    }
    Ok(())
}

/// [`ModelError::CurveParameterOff`] (for the element `element()` names) when `u` lies outside
/// `domain` (an open curve's data, a patch's [0, 1]).
fn in_domain(
    element: impl Fn() -> String,
    domain: Option<(f64, f64)>,
    u: f64,
) -> Result<(), ModelError> {
    match domain {
        Some((a, b)) if !(a..=b).contains(&u) => Err(ModelError::CurveParameterOff {
            element: element(),
            u,
            start: a,
            end: b,
        }),
        _ => Ok(()),
    }
}

/// A curve element before the layout gives it its rows and slots.
fn info(
    name: &str,
    (body_i, body_j): (BodyId, BodyId),
    element: CurveElement,
    extra: usize,
    initial: [f64; 2],
) -> CurveInfo {
    CurveInfo {
        name: name.to_string(),
        body_i,
        body_j,
        element,
        extra,
        initial,
        rows: 0..0,
        map: ScatterMap { slots: Vec::new() },
        extra_slots: Vec::new(),
    }
}

/// The model form of cam pair `spec`, whose curve parameters are extra coordinates `extra` (u)
/// and `extra + 1` (w).
pub(super) fn cam(
    spec: &CamSpec,
    extra: usize,
    names: &Names,
    bodies: &[BodyInfo],
) -> Result<CurveInfo, ModelError> {
    let el = format!("cam \"{}\"", spec.name);
    let (bi, bj) = names.pair(&el, &spec.body_i, &spec.body_j)?;
    let element = CurveOnCurve::new(spec.curve_i.clone(), spec.normal_i, spec.curve_j.clone())
        .map_err(|e| ModelError::CamGeometry {
            cam: spec.name.clone(),
            reason: match e {
                cardan_constraints::ConstraintError::Curve(why) => why,
                e => e.to_string(),
            },
        })?;
    let initial = match spec.initial {
        Some([u, w]) => {
            check_number(&el, "initial cam parameter", Quantity::Length, u)?;
            check_number(&el, "initial follower parameter", Quantity::Length, w)?;
            [u, w]
        }
        None => {
            let (si, sj) = (pose(bodies, bi), pose(bodies, bj));
            // Curve j's points in body i's frame: A_iᵀ (r_j + A_j c'_j − r_i).
            let rel = si.a.transpose() * sj.a;
            let off = si.a.transpose() * (sj.r - si.r);
            closest_pair(&spec.curve_i, &spec.curve_j, &rel, &off)
        }
    };
    for (k, (curve, v)) in [&spec.curve_i, &spec.curve_j]
        .iter()
        .zip(initial)
        .enumerate()
    {
        let which = ["cam curve", "follower curve"][k];
        in_domain(|| format!("{el} ({which})"), curve.domain(), v)?;
    }
    drawn_in_contact(&el, &element, (bi, bj), bodies, initial)?;
    let element = CurveElement::Cam(element);
    Ok(info(&spec.name, (bi, bj), element, extra, initial))
}

/// A length of a curve: a circle's or a helix's radius, a spline's chord length over 2π (a
/// closed one's) or its chord length (an open one's); 0 for a line.
fn size(curve: &Curve) -> f64 {
    match curve {
        Curve::Line(_) => 0.0,
        Curve::Circle(c) => c.radius(),
        Curve::Helix(h) => h.radius(),
        Curve::Cubic(c) if c.is_closed() => c.knot_range().1 / std::f64::consts::TAU,
        Curve::Cubic(c) => c.knot_range().1 - c.knot_range().0,
    }
}

/// [`ModelError::CurveApart`] when a cam's curves are drawn apart (their contact points more
/// than 1e-3 of the smaller curve's size apart) or crossing (the follower's tangent more than
/// 1e-3 rad off the cam's).
fn drawn_in_contact(
    el: &str,
    cam: &CurveOnCurve,
    (bi, bj): (BodyId, BodyId),
    bodies: &[BodyInfo],
    [u, w]: [f64; 2],
) -> Result<(), ModelError> {
    let (si, sj) = (pose(bodies, bi), pose(bodies, bj));
    let (ci, cj) = (cam.curve_i.jet(u), cam.curve_j.jet(w));
    let gap = (sj.point(&cj.c) - si.point(&ci.c)).norm();
    let sizes = [size(&cam.curve_i), size(&cam.curve_j)];
    let scale = (sizes.into_iter().filter(|&s| s > 0.0)).fold(f64::INFINITY, f64::min);
    let tolerance = 1e-3
        * if scale.is_finite() {
            scale
        } else {
            (sj.r - si.r).norm()
        };
    let apart = |what: &str, gap: f64, tolerance: f64, unit| ModelError::CurveApart {
        element: el.to_string(),
        what: what.to_string(),
        gap,
        tolerance,
        unit,
        advice: "draw the follower touching the cam (the assembly would pull it on silently, \
                 maybe onto the other side of the cam): check the bodies' positions and the \
                 curves' data",
    };
    if gap > tolerance {
        let what = "the follower's curve is off the cam's profile";
        return Err(apart(what, gap, tolerance, " m"));
    }
    let normal = si.a * cam.normal_i.cross(&ci.c_u).normalize();
    let misalignment = normal.dot(&(sj.a * cj.c_u.normalize())).abs();
    if misalignment > 1e-3 {
        let what = "the follower's curve crosses the cam's profile instead of touching it";
        return Err(apart(what, misalignment, 1e-3, ""));
    }
    Ok(())
}

/// The parameters (u, w) of the nearest points of curve i and curve j (whose points are
/// `rel` c'_j + `off` in curve i's frame): the best of samples of curve i (its domain or period;
/// a line near curve j's w = 0), each with curve j's nearest point, refined by alternating
/// projections (the contact point of touching curves).
fn closest_pair(ci: &Curve, cj: &Curve, rel: &Matrix3<f64>, off: &Vector3<f64>) -> [f64; 2] {
    let on_j = |w: f64| rel * cj.jet(w).c + off;
    // Curve i's point in curve j's frame.
    let to_j = |u: f64| rel.transpose() * (ci.jet(u).c - off);
    let (a, b) = match (ci.domain(), ci.period()) {
        (Some(d), _) => d,
        (None, Some(l)) => (0.0, l),
        (None, None) => {
            let u = ci.closest(&on_j(0.0));
            (u, u)
        }
    };
    const SAMPLES: usize = 64;
    let mut best = (f64::INFINITY, [a, 0.0]);
    for k in 0..=SAMPLES {
        let u = a + (b - a) * k as f64 / SAMPLES as f64;
        let w = cj.closest(&to_j(u));
        let d = (on_j(w) - ci.jet(u).c).norm();
        if d < best.0 {
            best = (d, [u, w]);
        }
    }
    let [mut u, mut w] = best.1;
    for _ in 0..50 {
        u = ci.closest(&on_j(w));
        w = cj.closest(&to_j(u));
    }
    [u, w]
}

/// The model form of path driver `spec` on one of `curves`.
pub(super) fn path(spec: &PathSpec, curves: &[CurveInfo]) -> Result<PathInfo, ModelError> {
    let curve = curves
        .iter()
        .position(|c| c.name == spec.curve)
        .ok_or_else(|| ModelError::UnknownJoint {
            element: format!("path driver \"{}\"", spec.name),
            name: spec.curve.clone(),
            suggestion: crate::model::nearest(&spec.curve, curves.iter().map(|c| c.name.as_str()))
                .map(str::to_string),
            known: curves.iter().map(|c| c.name.clone()).collect(),
        })?;
    spec.function
        .validate()
        .map_err(|e| ModelError::BadTimeFunction {
            driver: spec.name.clone(),
            reason: e.to_string(),
        })?;
    Ok(PathInfo {
        name: spec.name.clone(),
        curve,
        extra: curves[curve].extra,
        driver: match (spec.arc_length, curves[curve].element.curves()[0]) {
            (true, Some(c)) => PathDriver::along_arc(spec.function.clone(), c),
            _ => PathDriver::new(spec.function.clone()),
        },
        rows: 0..0,
        slot: 0,
    })
}
