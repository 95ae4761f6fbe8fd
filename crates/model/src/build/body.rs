//! `[[body]]` sections to [`Body`]s: mass, inertia, position and orientation (one of the
//! orientation forms, converted by the builder's own rules), the points and vectors (local or
//! global, each name once), and the initial velocity a dynamic analysis starts from.

use super::context::{Ctx, Features};
use super::loaded::BodyVelocity;
use crate::diag::{Error, Source};
use crate::file::{BodySection, InertiaSpec, Name, OrientationSpec};
use crate::units::UnitSystem;
use cardan_mechanism::{Body, Orientation, Quantity};
use nalgebra::{Matrix3, Vector3};
use std::collections::BTreeMap;
use std::ops::Range;
use toml::Spanned;

/// The rotation matrix of an `orientation = { ... }` table (for the animation's geometry items),
/// with the checks and messages of a body's orientation.
///
/// # Errors
/// An input error located at the table (no or several forms, zero axes, bad numbers).
pub(crate) fn orientation_matrix(
    src: &Source,
    o: &Spanned<OrientationSpec>,
) -> Result<Matrix3<f64>, Error> {
    // Angles and directions only: the same in every unit system.
    let keys = crate::vocabulary::KeySpans::default();
    let parameters = crate::parameters::Parameters::default();
    let cx = Ctx {
        src,
        units: UnitSystem::Si,
        keys: &keys,
        parameters: &parameters,
    };
    orientation(&cx, o).map(|(_, a)| a)
}

fn orientation(
    cx: &Ctx,
    o: &Spanned<OrientationSpec>,
) -> Result<(Orientation, Matrix3<f64>), Error> {
    let s = o.get_ref();
    let given: Vec<&str> = [
        ("euler_parameters", s.euler_parameters.is_some()),
        ("axis/angle", s.axis.is_some() || s.angle.is_some()),
        ("euler313", s.euler313.is_some()),
        ("euler123", s.euler123.is_some()),
        ("z/x", s.z.is_some() || s.x.is_some()),
    ]
    .into_iter()
    .filter(|(_, g)| *g)
    .map(|(n, _)| n)
    .collect();
    if given.len() != 1 {
        return Err(cx.err(
            o.span(),
            format!(
                "orientation needs exactly one form: euler_parameters = [e0, e1, e2, e3], \
                 axis = [..] with angle = .., euler313 = [φ, θ, ψ], euler123 = [φ, θ, ψ], or z = [..] \
                 (with optional x = [..]); found {}",
                if given.is_empty() { "none".to_string() } else { given.join(", ") }
            ),
        ));
    }
    let bad = |e: cardan_eulerparam::EulerParamError| cx.err(o.span(), format!("orientation: {e}"));
    let orient = if let Some(ep) = &s.euler_parameters {
        let a = ep.get_ref();
        let mut v = [0.0; 4];
        for k in 0..4 {
            v[k] = cx.num(
                &a[k],
                format_args!("euler_parameters[{k}]"),
                Quantity::Direction,
            )?;
        }
        let n = (v.iter().map(|x| x * x).sum::<f64>()).sqrt();
        if (n - 1.0).abs() > 1e-6 {
            return Err(cx.err(
                ep.span(),
                format!(
                    "euler_parameters must have unit length (e0² + e1² + e2² + e3² = 1); |p| = {n}"
                ),
            ));
        }
        Orientation::EulerParams(v)
    } else if s.axis.is_some() || s.angle.is_some() {
        let (Some(axis), Some(angle)) = (&s.axis, &s.angle) else {
            return Err(cx.err(
                o.span(),
                "axis-angle orientation needs both axis = [x, y, z] and angle = θ [rad]",
            ));
        };
        let axis = cx.direction(axis, "orientation axis")?;
        let angle = cx.num(angle, "orientation angle", Quantity::Angle)?;
        Orientation::AxisAngle { axis, angle }
    } else if let Some(e) = &s.euler313 {
        let v = cx.vec3(e, "euler313", Quantity::Angle)?;
        Orientation::Euler313([v.x, v.y, v.z])
    } else if let Some(e) = &s.euler123 {
        let v = cx.vec3(e, "euler123", Quantity::Angle)?;
        Orientation::Euler123([v.x, v.y, v.z])
    } else {
        let Some(z) = &s.z else {
            return Err(cx.err(
                o.span(),
                "orientation by axes needs z = [..] (x = [..] is optional)",
            ));
        };
        let zv = cx.direction(z, "orientation z")?;
        let x = match &s.x {
            Some(x) => Some(cx.direction(x, "orientation x")?),
            None => None,
        };
        Orientation::Axes { z: zv, x }
    };
    // The conversion is the builder's own (`Orientation::euler_params`); errors located here.
    let p = orient.euler_params().map_err(bad)?;
    Ok((orient, p.a()))
}

pub(super) fn load_body(cx: &Ctx, b: &BodySection) -> Result<(Body, Features), Error> {
    let name = b.name.get_ref();
    let mut body = Body::new(name.clone());
    if let Some(m) = &b.mass {
        // Positive: checked by the builder (located here through its error's site).
        let m_v = cx.num(m, format_args!("mass of body \"{name}\""), Quantity::Mass)?;
        body = body.mass(m_v);
    }
    if let Some(i) = &b.inertia {
        let mut j = match i.get_ref() {
            InertiaSpec::Matrix(m) => Matrix3::from_fn(|r, c| m[r][c].0),
            InertiaSpec::Diag { diag } => Matrix3::from_diagonal(&Vector3::from(diag.map(|x| x.0))),
        };
        for v in j.iter_mut() {
            // Checked and converted to SI (kg m²).
            *v = cx.raw_num(
                i.span(),
                *v,
                format_args!("inertia of body \"{name}\""),
                Quantity::Inertia,
            )?;
        }
        // Symmetric, positive definite, triangle inequality: checked by the builder.
        body = body.inertia(j);
    }
    let position = match &b.position {
        Some(p) => cx.vec3(
            p,
            format_args!("position of body \"{name}\""),
            Quantity::Length,
        )?,
        None => Vector3::zeros(),
    };
    body = body.position(position);
    let mut a = Matrix3::identity();
    if let Some(o) = &b.orientation {
        let (orient, a_) = orientation(cx, o)?;
        a = a_;
        body = body.orientation(orient);
    }

    let mut f = Features::default();
    // One named feature (point or vector) into its map; a second definition of the name is an
    // error located at the repeat, naming the line of the first.
    let add = |what: &str,
               map: &mut BTreeMap<String, (Range<usize>, Vector3<f64>)>,
               k: &Name,
               v: Vector3<f64>|
     -> Result<(), Error> {
        if let Some((s, _)) = map.get(k.get_ref()) {
            let l = cx.src.location(s.start);
            return Err(cx.err(
                k.span(),
                format!(
                    "duplicate {what} \"{}\" on body \"{name}\" (also defined at line {})",
                    k.get_ref(),
                    l.line
                ),
            ));
        }
        map.insert(k.get_ref().clone(), (k.span(), v));
        Ok(())
    };
    let at = a.transpose();
    for (k, v) in &b.points {
        let p = cx.vec3(
            v,
            format_args!("point \"{}\" of body \"{name}\"", k.get_ref()),
            Quantity::Length,
        )?;
        add("point", &mut f.points, k, p)?;
    }
    for (k, v) in &b.global_points {
        let g = cx.vec3(
            v,
            format_args!("point \"{}\" of body \"{name}\"", k.get_ref()),
            Quantity::Length,
        )?;
        add("point", &mut f.points, k, at * (g - position))?;
    }
    for (k, v) in &b.vectors {
        let d = cx.direction(
            v,
            format_args!("vector \"{}\" of body \"{name}\"", k.get_ref()),
        )?;
        add("vector", &mut f.vectors, k, d)?;
    }
    for (k, v) in &b.global_vectors {
        let d = cx.direction(
            v,
            format_args!("vector \"{}\" of body \"{name}\"", k.get_ref()),
        )?;
        add("vector", &mut f.vectors, k, at * d)?;
    }
    Ok((body, f))
}

/// `velocity`, `angular_velocity` / `angular_velocity_local` of a body, if any is given.
pub(super) fn body_velocity(cx: &Ctx, b: &BodySection) -> Result<Option<BodyVelocity>, Error> {
    let name = b.name.get_ref();
    if b.velocity.is_none() && b.angular_velocity.is_none() && b.angular_velocity_local.is_none() {
        return Ok(None);
    }
    if let (Some(_), Some(l)) = (&b.angular_velocity, &b.angular_velocity_local) {
        return Err(cx.err(
            l.span(),
            format!(
                "body \"{name}\": give angular_velocity (global components) or \
                 angular_velocity_local (body components), not both"
            ),
        ));
    }
    let velocity = match &b.velocity {
        Some(v) => cx.vec3(
            v,
            format_args!("velocity of body \"{name}\""),
            Quantity::Velocity,
        )?,
        None => Vector3::zeros(),
    };
    let (omega, omega_local) = match (&b.angular_velocity, &b.angular_velocity_local) {
        (Some(w), _) => (
            cx.vec3(
                w,
                format_args!("angular_velocity of body \"{name}\""),
                Quantity::AngularVelocity,
            )?,
            false,
        ),
        (None, Some(w)) => (
            cx.vec3(
                w,
                format_args!("angular_velocity_local of body \"{name}\""),
                Quantity::AngularVelocity,
            )?,
            true,
        ),
        (None, None) => (Vector3::zeros(), false),
    };
    Ok(Some(BodyVelocity {
        body: name.clone(),
        velocity,
        omega,
        omega_local,
    }))
}
