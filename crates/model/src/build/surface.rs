//! `[[surface]]` sections to [`SurfaceSpec`]s: the surface built in body i's coordinates from
//! the body's named point and vectors (a plane, a sphere, a cylinder, a torus) or from 16
//! control points (a bicubic patch), its own errors (a zero radius, a tube wider than the torus,
//! a wrong number of points) placed at the key. Body j and its point are resolved by the
//! builder, whose errors [`super::Spans::locate`] places at the key.

use super::context::{missing, Resolver};
use super::curve::{marker, placed};
use crate::diag::Error;
use crate::file::SurfaceSection;
use cardan_constraints::{BicubicPatch, ConstraintError, Cylinder, Plane, Sphere, Surface, Torus};
use cardan_mechanism::{Quantity, SurfaceSpec};
use nalgebra::Vector3;
use toml::Spanned;

/// The surface of `s` (its kind checked against [`crate::vocabulary::SURFACES`]: `kind` is the
/// entry's name) and the element.
pub(super) fn load_surface(
    r: &Resolver,
    section: &Spanned<SurfaceSection>,
    kind: &str,
) -> Result<SurfaceSpec, Error> {
    let cx = r.cx;
    let s = section.get_ref();
    let owner = format!("surface \"{}\"", s.name.get_ref());
    let bi = r.body(&s.body_i, &owner)?;
    let need = |key: &str| missing(cx, s.name.span(), &owner, key, "the surface needs it");
    let surface: Surface = if kind == "patch" {
        let points = s.points.as_ref().ok_or_else(|| need("points"))?;
        if points.get_ref().len() != 16 {
            return Err(cx.err(
                points.span(),
                format!(
                    "{owner}: a bicubic patch takes 16 control points (4 rows of 4), got {}",
                    points.get_ref().len()
                ),
            ));
        }
        let mut p = [[Vector3::zeros(); 4]; 4];
        for (k, v) in points.get_ref().iter().enumerate() {
            p[k / 4][k % 4] = cx.vec3(v, format_args!("{owner}: points[{k}]"), Quantity::Length)?;
        }
        let patch = BicubicPatch::new(p).map_err(placed(cx, points.span(), &owner))?;
        patch.into()
    } else {
        let p = s.point_i.as_ref().ok_or_else(|| need("point_i"))?;
        let z = s.axis_i.as_ref().ok_or_else(|| need("axis_i"))?;
        let m = marker(r, bi, (p, z, s.x_axis_i.as_ref()), &owner)?;
        if kind == "plane" {
            Plane::new(&m).into()
        } else {
            let radius = s.radius.as_ref().ok_or_else(|| need("radius"))?;
            let big = cx.num(radius, format_args!("{owner}: radius"), Quantity::Length)?;
            let at = placed(cx, radius.span(), &owner);
            match kind {
                "sphere" => Sphere::new(&m, big).map_err(at)?.into(),
                "cylinder" => Cylinder::new(&m, big).map_err(at)?.into(),
                _ => {
                    let tube = s.tube_radius.as_ref().ok_or_else(|| need("tube_radius"))?;
                    let r = cx.num(tube, format_args!("{owner}: tube_radius"), Quantity::Length)?;
                    // A bad major radius at its key, the rest at the tube's.
                    let torus = Torus::new(&m, big, r).map_err(|e| match &e {
                        ConstraintError::NotPositive { what, .. } if what.contains("major") => {
                            placed(cx, radius.span(), &owner)(e)
                        }
                        _ => placed(cx, tube.span(), &owner)(e),
                    })?;
                    torus.into()
                }
            }
        }
    };
    let mut spec = SurfaceSpec::new(
        s.name.get_ref().clone(),
        bi,
        surface,
        s.body_j.get_ref(),
        s.point_j.get_ref(),
    );
    match (&s.initial_u, &s.initial_v) {
        (Some(u), Some(v)) => {
            let u = cx.num(u, format_args!("{owner}: initial_u"), Quantity::Length)?;
            let v = cx.num(v, format_args!("{owner}: initial_v"), Quantity::Length)?;
            spec.initial = Some([u, v]);
        }
        (None, None) => {}
        (Some(u), None) => {
            return Err(cx.err(u.span(), format!("{owner}: initial_u needs initial_v")));
        }
        (None, Some(v)) => {
            return Err(cx.err(v.span(), format!("{owner}: initial_v needs initial_u")));
        }
    }
    Ok(spec)
}
