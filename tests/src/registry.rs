//! The registry of every constraint element, by the name the oracle files use.
//!
//! [`elements`] lists every primitive, joint and driver the Rust code has: the joints from the
//! kind table ([`KINDS`]), the primitives and drivers from [`PRIMITIVES`] and [`DRIVERS`], which
//! sit beside the exhaustive matches [`primitive_name`] and [`driver_name`] (a new variant must
//! be named there, and a test checks every name is built by [`build`]). The oracle gate fails for
//! any listed element without oracle data, for oracle data naming no element, and for a time
//! function kind ([`TimeFunction::KINDS`]) that no driver case exercises. Nothing can be added
//! unchecked.

use cardan_constraints::joints::Measure;
use cardan_constraints::{
    BicubicPatch, Bound, Circle, Constraint, CoordinateDriver, Coupler, CubicCurve, Curve,
    CurveOnCurve, Cylinder, Distance, DistanceDriver, Driver, Gear, Helix, Homokinetic, Joint,
    JointKind, JointLimit, JointParams, Line, Marker, Normalization, P1Perp, P1Select, P2Perp,
    P2Select, PathDriver, Plane, PointOnCurve, PointOnSurface, PoseDriver, Primitive, RackPinion,
    RadialDistance, RotationDriver, RotationOrder, Screw, Sphere, Spherical, Surface, TimeFunction,
    Torus, TranslationDriver, KINDS, N1, N2, P1, P2,
};
use nalgebra::{Matrix3, Vector3};
use serde_json::Value;
use std::sync::OnceLock;

/// Every primitive, as the oracle names them (see [`primitive_name`]).
pub const PRIMITIVES: &[&str] = &[
    "n1",
    "n2",
    "p1",
    "p1_select",
    "p1_perp",
    "p2",
    "p2_select",
    "p2_perp",
    "s",
    "distance",
    "normalization",
    "radial_distance",
    "homokinetic",
];

/// Every driver, as the oracle names them (see [`driver_name`]).
pub const DRIVERS: &[&str] = &[
    "rotation_driver",
    "translation_driver",
    "distance_driver",
    "coordinate_driver",
    "pose_driver",
];

/// Every coupler, as the oracle names them (see [`coupler_name`]).
pub const COUPLERS: &[&str] = &["gear", "rack_pinion", "screw"];

/// Every joint-coordinate limit, as the oracle names them: `limit_<key>` for each measure of
/// [`Measure::ALL`] (a measure added there needs oracle data).
pub fn limits() -> &'static [&'static str] {
    static NAMES: OnceLock<Vec<&'static str>> = OnceLock::new();
    NAMES.get_or_init(|| {
        Measure::ALL
            .iter()
            .map(|m| &*Box::leak(format!("limit_{}", m.key()).into_boxed_str()))
            .collect()
    })
}

/// Every point-on-curve element, as the oracle names them: `point_on_curve_<kind>` for each
/// kind of [`Curve::KINDS`] (a curve kind added there needs oracle data).
pub fn curves() -> &'static [&'static str] {
    static NAMES: OnceLock<Vec<&'static str>> = OnceLock::new();
    NAMES.get_or_init(|| {
        Curve::KINDS
            .iter()
            .map(|k| &*Box::leak(format!("point_on_curve_{k}").into_boxed_str()))
            .collect()
    })
}

/// The oracle name of a point-on-curve element (`point_on_curve_<kind>` of its curve).
pub fn curve_name(c: &PointOnCurve) -> &'static str {
    let k = Curve::KINDS
        .iter()
        .position(|k| *k == c.curve.kind())
        .expect("every curve kind is in Curve::KINDS");
    curves()[k]
}

/// Every point-on-surface element, as the oracle names them: `point_on_surface_<kind>` for
/// each kind of [`Surface::KINDS`] (a surface kind added there needs oracle data).
pub fn surfaces() -> &'static [&'static str] {
    static NAMES: std::sync::OnceLock<Vec<&'static str>> = std::sync::OnceLock::new();
    NAMES.get_or_init(|| {
        Surface::KINDS
            .iter()
            .map(|k| &*Box::leak(format!("point_on_surface_{k}").into_boxed_str()))
            .collect()
    })
}

/// The oracle name of a point-on-surface element (`point_on_surface_<kind>` of its surface).
pub fn surface_name(c: &PointOnSurface) -> &'static str {
    let k = Surface::KINDS
        .iter()
        .position(|k| *k == c.surface.kind())
        .expect("every surface kind is in Surface::KINDS");
    surfaces()[k]
}

/// The curve kinds a cam pair takes (`Curve::KINDS` but the helix, which is not planar).
pub const PLANAR_KINDS: [&str; 6] = [
    "line",
    "circle",
    "cubic",
    "cubic_closed",
    "quintic",
    "quintic_closed",
];

/// Every cam pair, as the oracle names them: `curve_on_curve_<i>_<j>` for each pair of
/// [`PLANAR_KINDS`].
pub fn cams() -> &'static [&'static str] {
    static NAMES: OnceLock<Vec<&'static str>> = OnceLock::new();
    NAMES.get_or_init(|| {
        (PLANAR_KINDS.iter())
            .flat_map(|i| PLANAR_KINDS.iter().map(move |j| (i, j)))
            .map(|(i, j)| &*Box::leak(format!("curve_on_curve_{i}_{j}").into_boxed_str()))
            .collect()
    })
}

/// The oracle name of a cam pair (`curve_on_curve_<i>_<j>` of its curves).
pub fn cam_name(c: &CurveOnCurve) -> &'static str {
    let k = |curve: &Curve| {
        (PLANAR_KINDS.iter())
            .position(|k| *k == curve.kind())
            .expect("a cam pair's curves are planar")
    };
    cams()[k(&c.curve_i) * PLANAR_KINDS.len() + k(&c.curve_j)]
}

/// The oracle name of a limit (`limit_<key>` of its measure).
pub fn limit_name(l: &JointLimit) -> &'static str {
    let k = Measure::ALL
        .iter()
        .position(|m| *m == l.measure)
        .expect("every measure is in Measure::ALL");
    limits()[k]
}

/// Every element name the Rust side implements: primitives, the joint kinds of the kind table,
/// drivers, couplers, limits.
pub fn elements() -> Vec<&'static str> {
    let joints = KINDS.iter().map(|k| k.name);
    PRIMITIVES
        .iter()
        .copied()
        .chain(joints)
        .chain(DRIVERS.iter().copied())
        .chain(COUPLERS.iter().copied())
        .chain(limits().iter().copied())
        .chain(curves().iter().copied())
        .chain(cams().iter().copied())
        .chain(surfaces().iter().copied())
        .chain([
            "path_driver",
            "path_driver_arc_cubic",
            "path_driver_arc_cubic_closed",
        ])
        .collect()
}

/// The oracle name of a coupler variant (exhaustive).
pub fn coupler_name(c: &Coupler) -> &'static str {
    match c {
        Coupler::Gear(_) => "gear",
        Coupler::RackPinion(_) => "rack_pinion",
        Coupler::Screw(_) => "screw",
    }
}

/// The oracle name of a primitive variant (exhaustive: a new variant must be named here).
pub fn primitive_name(p: &Primitive) -> &'static str {
    match p {
        Primitive::N1(_) => "n1",
        Primitive::N2(_) => "n2",
        Primitive::P1(_) => "p1",
        Primitive::P1Select(_) => "p1_select",
        Primitive::P1Perp(_) => "p1_perp",
        Primitive::P2(_) => "p2",
        Primitive::P2Select(_) => "p2_select",
        Primitive::P2Perp(_) => "p2_perp",
        Primitive::Spherical(_) => "s",
        Primitive::Distance(_) => "distance",
        Primitive::Normalization(_) => "normalization",
        Primitive::RadialDistance(_) => "radial_distance",
        Primitive::Homokinetic(_) => "homokinetic",
    }
}

/// The oracle name of a joint kind (`JointKind::name` is itself an exhaustive match).
pub fn joint_name(k: JointKind) -> &'static str {
    k.name()
}

/// The oracle name of a driver variant (exhaustive).
pub fn driver_name(d: &Driver) -> &'static str {
    match d {
        Driver::Rotation(_) => "rotation_driver",
        Driver::Translation(_) => "translation_driver",
        Driver::Distance(_) => "distance_driver",
        Driver::Coordinate(_) => "coordinate_driver",
        Driver::Pose(_) => "pose_driver",
    }
}

/// Any element, for uniform evaluation.
#[derive(Debug, Clone)]
pub enum Element {
    /// A primitive.
    Primitive(Primitive),
    /// A joint.
    Joint(Joint),
    /// A driver.
    Driver(Driver),
    /// A coupler.
    Coupler(Coupler),
    /// A joint-coordinate limit.
    Limit(JointLimit),
    /// A point on a curve (one extra coordinate).
    Curve(PointOnCurve),
    /// Two curves in tangent contact (two extra coordinates).
    Cam(CurveOnCurve),
    /// A point on a surface (two extra coordinates).
    Surface(PointOnSurface),
    /// A curve parameter prescribed in time.
    Path(PathDriver),
}

impl Element {
    /// The oracle name (from the exhaustive name functions, not from the element's own `name`,
    /// so that a mislabelled element is caught by `Element::check_name`).
    pub fn oracle_name(&self) -> &'static str {
        match self {
            Element::Primitive(p) => primitive_name(p),
            Element::Joint(j) => joint_name(j.kind()),
            Element::Driver(d) => driver_name(d),
            Element::Coupler(c) => coupler_name(c),
            Element::Limit(l) => limit_name(l),
            Element::Curve(c) => curve_name(c),
            Element::Cam(c) => cam_name(c),
            Element::Surface(c) => surface_name(c),
            Element::Path(p) => match &p.arc {
                None => "path_driver",
                Some(a) if a.is_closed() => "path_driver_arc_cubic_closed",
                Some(_) => "path_driver_arc_cubic",
            },
        }
    }
}

cardan_constraints::delegate_constraint!(Element {
    Element::Primitive,
    Element::Joint,
    Element::Driver,
    Element::Coupler,
    Element::Limit,
    Element::Curve,
    Element::Cam,
    Element::Surface,
    Element::Path,
});

/// An error reading oracle parameters.
pub type ParamError = String;

fn v3(p: &Value, key: &str) -> Result<Vector3<f64>, ParamError> {
    let a = p
        .get(key)
        .and_then(Value::as_array)
        .ok_or_else(|| format!("missing 3-vector parameter `{key}`"))?;
    if a.len() != 3 {
        return Err(format!("parameter `{key}` has {} entries, want 3", a.len()));
    }
    let f = |k: usize| {
        a[k].as_f64()
            .ok_or_else(|| format!("`{key}`[{k}] is not a number"))
    };
    Ok(Vector3::new(f(0)?, f(1)?, f(2)?))
}

fn num(p: &Value, key: &str) -> Result<f64, ParamError> {
    p.get(key)
        .and_then(Value::as_f64)
        .ok_or_else(|| format!("missing number parameter `{key}`"))
}

fn marker(p: &Value, key: &str) -> Result<Marker, ParamError> {
    let m = p
        .get(key)
        .ok_or_else(|| format!("missing marker `{key}`"))?;
    let frame = Matrix3::from_columns(&[v3(m, "x")?, v3(m, "y")?, v3(m, "z")?]);
    Marker::new(v3(m, "point")?, frame).map_err(|e| format!("marker `{key}`: {e}"))
}

fn nums(v: &Value, key: &str) -> Result<Vec<f64>, ParamError> {
    v.get(key)
        .and_then(Value::as_array)
        .ok_or_else(|| format!("time function: missing array `{key}`"))?
        .iter()
        .map(|x| {
            x.as_f64()
                .ok_or_else(|| format!("time function: `{key}` holds a non-number"))
        })
        .collect()
}

/// A [`TimeFunction`] from its oracle description.
pub fn time_function(f: &Value) -> Result<TimeFunction, ParamError> {
    let kind = f
        .get("kind")
        .and_then(Value::as_str)
        .ok_or("time function without `kind`")?;
    let tf = match kind {
        "constant" => TimeFunction::Constant(num(f, "value")?),
        "polynomial" => TimeFunction::Polynomial(nums(f, "coefficients")?),
        "harmonic" => TimeFunction::Harmonic {
            amplitude: num(f, "amplitude")?,
            frequency: num(f, "frequency")?,
            phase: num(f, "phase")?,
            offset: num(f, "offset")?,
        },
        "ramp" => TimeFunction::Ramp {
            t0: num(f, "t0")?,
            t1: num(f, "t1")?,
            f0: num(f, "f0")?,
            f1: num(f, "f1")?,
        },
        "spline" => {
            TimeFunction::spline(nums(f, "t")?, nums(f, "f")?).map_err(|e| e.to_string())?
        }
        "expression" => {
            let text = f.get("text").and_then(Value::as_str).ok_or("no `text`")?;
            TimeFunction::expression(text).map_err(|e| e.to_string())?
        }
        other => return Err(format!("unknown time function kind `{other}`")),
    };
    tf.validate().map_err(|e| e.to_string())?;
    Ok(tf)
}

/// Builds the Rust element `name` from oracle parameters.
pub fn build(name: &str, p: &Value) -> Result<Element, ParamError> {
    use Element as E;
    let prim = |x: Primitive| Ok(E::Primitive(x));
    let joint = |k: JointKind| {
        let at = |key| {
            v3(p, key).map(|point| Marker {
                point,
                frame: Matrix3::identity(),
            })
        };
        let (mi, mj) = match p.get("marker_i") {
            Some(_) => (marker(p, "marker_i")?, marker(p, "marker_j")?),
            None => (at("point_i")?, at("point_j")?),
        };
        let opt = |key| {
            if p.get(key).is_some() {
                num(p, key)
            } else {
                Ok(0.0)
            }
        };
        let params = JointParams {
            length: opt("length")?,
            offset: opt("offset")?,
            angle: opt("angle")?,
        };
        Joint::with_params(k, mi, mj, params)
            .map(E::Joint)
            .map_err(|e| e.to_string())
    };
    match name {
        "n1" => prim(N1::new(v3(p, "s_i")?, v3(p, "s_j")?).into()),
        "n2" => prim(N2::new(v3(p, "s_i")?, v3(p, "sp_i")?, v3(p, "sp_j")?).into()),
        "p1" => prim(P1::new(v3(p, "s_i")?, v3(p, "s_j")?).into()),
        "p1_select" => prim(P1Select::new(v3(p, "s_i")?, v3(p, "s_j")?).into()),
        "p1_perp" => prim(P1Perp::new(v3(p, "f_i")?, v3(p, "g_i")?, v3(p, "s_j")?).into()),
        "p2" => prim(P2::new(v3(p, "s_i")?, v3(p, "sp_i")?, v3(p, "sp_j")?).into()),
        "p2_select" => prim(P2Select::new(v3(p, "s_i")?, v3(p, "sp_i")?, v3(p, "sp_j")?).into()),
        "p2_perp" => {
            prim(P2Perp::new(v3(p, "f_i")?, v3(p, "g_i")?, v3(p, "sp_i")?, v3(p, "sp_j")?).into())
        }
        "s" => prim(Spherical::new(v3(p, "sp_i")?, v3(p, "sp_j")?).into()),
        "distance" => prim(Distance::new(v3(p, "sp_i")?, v3(p, "sp_j")?, num(p, "length")?).into()),
        "normalization" => prim(Normalization.into()),
        "radial_distance" => prim(
            RadialDistance::new(
                v3(p, "f_i")?,
                v3(p, "g_i")?,
                v3(p, "sp_i")?,
                v3(p, "sp_j")?,
                num(p, "length")?,
            )
            .into(),
        ),
        "homokinetic" => prim(
            Homokinetic::new(v3(p, "x_i")?, v3(p, "y_i")?, v3(p, "x_j")?, v3(p, "y_j")?).into(),
        ),
        // A joint kind of the table: markers (or, for spherical_spherical, two points) and the
        // numbers the kind takes.
        _ if JointKind::from_name(name).is_some_and(|k| k.name() == name) => {
            let kind = JointKind::from_name(name).expect("checked");
            joint(kind)
        }
        "rotation_driver" => Ok(E::Driver(
            RotationDriver::new(
                marker(p, "marker_i")?,
                marker(p, "marker_j")?,
                time_function(&p["function"])?,
            )
            .into(),
        )),
        "translation_driver" => Ok(E::Driver(
            TranslationDriver::new(
                marker(p, "marker_i")?,
                marker(p, "marker_j")?,
                time_function(&p["function"])?,
            )
            .into(),
        )),
        "distance_driver" => Ok(E::Driver(
            DistanceDriver::new(
                v3(p, "point_i")?,
                v3(p, "point_j")?,
                time_function(&p["function"])?,
            )
            .into(),
        )),
        "coordinate_driver" => {
            let axis = p
                .get("axis")
                .and_then(Value::as_u64)
                .ok_or("missing integer `axis`")? as usize;
            CoordinateDriver::new(v3(p, "point_i")?, axis, time_function(&p["function"])?)
                .map(|d| E::Driver(d.into()))
                .map_err(|e| e.to_string())
        }
        "gear" => {
            let reference = nums(p, "reference")?;
            let [r_i, r_j] = reference[..] else {
                return Err("`reference` of a gear has two angles".into());
            };
            Ok(E::Coupler(
                Gear {
                    marker_i: marker(p, "marker_i")?,
                    marker_j: marker(p, "marker_j")?,
                    k_i: num(p, "k_i")?,
                    k_j: num(p, "k_j")?,
                    constant: num(p, "constant")?,
                    reference: [r_i, r_j],
                }
                .into(),
            ))
        }
        "rack_pinion" | "screw" => {
            let (mi, mj) = (marker(p, "marker_i")?, marker(p, "marker_j")?);
            let (ks, ka) = (num(p, "k_slide")?, num(p, "k_angle")?);
            let (c, r) = (num(p, "constant")?, num(p, "reference")?);
            Ok(E::Coupler(if name == "screw" {
                Screw::new(mi, mj, ks, ka, c, r).into()
            } else {
                RackPinion::new(mi, mj, ks, ka, c, r).into()
            }))
        }
        "path_driver" => Ok(E::Path(PathDriver::new(time_function(
            p.get("function").ok_or("missing `function`")?,
        )?))),
        "path_driver_arc_cubic" | "path_driver_arc_cubic_closed" => {
            let f = time_function(p.get("function").ok_or("missing `function`")?)?;
            let c = curve(p.get("curve").ok_or("missing `curve`")?)?;
            let e = PathDriver::along_arc(f, &c);
            if e.name() != name {
                return Err(format!("`{name}` holds a {} curve", c.kind()));
            }
            Ok(E::Path(e))
        }
        _ if name.starts_with("point_on_curve_") => {
            let e = PointOnCurve::new(
                curve(p.get("curve").ok_or("missing `curve`")?)?,
                v3(p, "sp_j")?,
            );
            if curve_name(&e) != name {
                return Err(format!("`{name}` holds a {} curve", e.curve.kind()));
            }
            Ok(E::Curve(e))
        }
        _ if name.starts_with("point_on_surface_") => {
            let e = PointOnSurface::new(
                surface(p.get("surface").ok_or("missing `surface`")?)?,
                v3(p, "sp_j")?,
            );
            if surface_name(&e) != name {
                return Err(format!("`{name}` holds a {} surface", e.surface.kind()));
            }
            Ok(E::Surface(e))
        }
        _ if name.starts_with("curve_on_curve_") => {
            let side = |k: &str| curve(p.get(k).ok_or_else(|| format!("missing `{k}`"))?);
            let e = CurveOnCurve::new(side("curve_i")?, v3(p, "normal_i")?, side("curve_j")?)
                .map_err(|e| e.to_string())?;
            if cam_name(&e) != name {
                return Err(format!(
                    "`{name}` holds a {} and a {} curve",
                    e.curve_i.kind(),
                    e.curve_j.kind()
                ));
            }
            Ok(E::Cam(e))
        }
        _ if name.starts_with("limit_") => {
            let measure = Measure::ALL
                .into_iter()
                .find(|m| name == format!("limit_{}", m.key()))
                .ok_or_else(|| format!("no measure for `{name}`"))?;
            let bound = match p.get("bound").and_then(Value::as_str) {
                Some("lower") => Bound::Lower,
                Some("upper") => Bound::Upper,
                _ => return Err("`bound` must be \"lower\" or \"upper\"".into()),
            };
            let (mi, mj) = (marker(p, "marker_i")?, marker(p, "marker_j")?);
            Ok(E::Limit(
                JointLimit::new(mi, mj, measure, bound, num(p, "value")?)
                    .with_reference(num(p, "reference")?),
            ))
        }
        "pose_driver" => {
            let order = p
                .get("order")
                .and_then(Value::as_str)
                .and_then(RotationOrder::parse)
                .ok_or("missing or invalid `order`")?;
            let row = p
                .get("row")
                .and_then(Value::as_u64)
                .filter(|&r| r < 6)
                .ok_or("missing or invalid `row`")? as usize;
            let specs = p
                .get("functions")
                .and_then(Value::as_array)
                .filter(|a| a.len() == 6)
                .ok_or("`functions` must hold six time functions")?;
            let f: Vec<TimeFunction> = specs.iter().map(time_function).collect::<Result<_, _>>()?;
            let f: [TimeFunction; 6] = f.try_into().expect("six");
            let (mi, mj) = (marker(p, "marker_i")?, marker(p, "marker_j")?);
            Ok(E::Driver(PoseDriver::new(mi, mj, order, f, row).into()))
        }
        other => Err(format!(
            "no Rust element is registered under the oracle name `{other}`"
        )),
    }
}

/// A curve from its oracle parameters (`kind` and the kind's fields, CONTRACT.md "Curves").
fn curve(c: &Value) -> Result<Curve, ParamError> {
    let kind = c
        .get("kind")
        .and_then(Value::as_str)
        .ok_or("curve without `kind`")?;
    let at_axis =
        |o: &str, z: &str| Marker::from_axis(v3(c, o)?, v3(c, z)?).map_err(|e| e.to_string());
    let frame = || -> Result<Marker, ParamError> {
        let (x, y) = (v3(c, "x")?, v3(c, "y")?);
        Marker::new(
            v3(c, "center")?,
            Matrix3::from_columns(&[x, y, x.cross(&y)]),
        )
        .map_err(|e| e.to_string())
    };
    Ok(match kind {
        "line" => Line::new(&at_axis("origin", "direction")?).into(),
        "circle" => Circle::new(&frame()?, num(c, "radius")?)
            .map_err(|e| e.to_string())?
            .into(),
        "helix" => Helix::new(&frame()?, num(c, "radius")?, num(c, "pitch")?)
            .map_err(|e| e.to_string())?
            .into(),
        "cubic" | "quintic" => {
            let pts = c
                .get("points")
                .and_then(Value::as_array)
                .ok_or("cubic curve without `points`")?;
            let pts: Vec<Vector3<f64>> = pts
                .iter()
                .map(|v| {
                    let a: Vec<f64> = v
                        .as_array()
                        .into_iter()
                        .flatten()
                        .filter_map(Value::as_f64)
                        .collect();
                    (a.len() == 3)
                        .then(|| Vector3::new(a[0], a[1], a[2]))
                        .ok_or_else(|| "a curve point is not a 3-vector".to_string())
                })
                .collect::<Result<_, _>>()?;
            let closed = c.get("closed").and_then(Value::as_bool).unwrap_or(false);
            let spline = match kind {
                "quintic" => CubicCurve::quintic(pts, closed),
                _ => CubicCurve::new(pts, closed),
            };
            spline.map_err(|e| e.to_string())?.into()
        }
        other => return Err(format!("unknown curve kind `{other}`")),
    })
}

/// A surface from its oracle parameters (`kind` and the kind's fields, CONTRACT.md "Surfaces").
fn surface(c: &Value) -> Result<Surface, ParamError> {
    let kind = c
        .get("kind")
        .and_then(Value::as_str)
        .ok_or("surface without `kind`")?;
    if kind == "bicubic" {
        let rows = c
            .get("points")
            .and_then(Value::as_array)
            .ok_or("bicubic surface without `points`")?;
        let mut pts = [[Vector3::zeros(); 4]; 4];
        for (i, row) in rows.iter().enumerate().take(4) {
            for (j, p) in row.as_array().into_iter().flatten().enumerate().take(4) {
                let a: Vec<f64> = p
                    .as_array()
                    .into_iter()
                    .flatten()
                    .filter_map(Value::as_f64)
                    .collect();
                if a.len() != 3 {
                    return Err("a control point is not a 3-vector".into());
                }
                pts[i][j] = Vector3::new(a[0], a[1], a[2]);
            }
        }
        return Ok(BicubicPatch::new(pts).map_err(|e| e.to_string())?.into());
    }
    let (x, y) = (v3(c, "x")?, v3(c, "y")?);
    let m = Marker::new(
        v3(c, "center")?,
        Matrix3::from_columns(&[x, y, x.cross(&y)]),
    )
    .map_err(|e| e.to_string())?;
    let err = |e: cardan_constraints::ConstraintError| e.to_string();
    Ok(match kind {
        "plane" => Plane::new(&m).into(),
        "sphere" => Sphere::new(&m, num(c, "radius")?).map_err(err)?.into(),
        "cylinder" => Cylinder::new(&m, num(c, "radius")?).map_err(err)?.into(),
        "torus" => Torus::new(&m, num(c, "major")?, num(c, "minor")?)
            .map_err(err)?
            .into(),
        other => return Err(format!("unknown surface kind `{other}`")),
    })
}
