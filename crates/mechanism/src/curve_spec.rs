//! [`CurveSpec`]: a point of one body held on a curve of another (a pin in a curved slot, a
//! roller on a track, a tool point on a path), as the builder collects it. The curve parameter
//! u is an extra coordinate of the mechanism (columns after the bodies'); see
//! [`cardan_constraints::PointOnCurve`] for the equations.

use cardan_constraints::{Curve, Surface, TimeFunction};
use nalgebra::Vector3;

/// A point of body j on a curve fixed in body i.
#[derive(Debug, Clone, PartialEq)]
pub struct CurveSpec {
    /// Name (unique among all elements).
    pub name: String,
    /// The body carrying the curve (ground allowed).
    pub body_i: String,
    /// The curve, in body i's coordinates (global for ground).
    pub curve: Curve,
    /// The body carrying the point.
    pub body_j: String,
    /// The name of the point on body j.
    pub point_j: String,
    /// The curve parameter at the drawn pose; when `None`, the parameter of the curve point
    /// nearest to the drawn point ([`Curve::closest`]).
    pub initial_u: Option<f64>,
}

impl CurveSpec {
    /// Point `point_j` of `body_j` on `curve` of `body_i`.
    pub fn new(
        name: impl Into<String>,
        body_i: &str,
        curve: impl Into<Curve>,
        body_j: &str,
        point_j: &str,
    ) -> Self {
        Self {
            name: name.into(),
            body_i: body_i.into(),
            curve: curve.into(),
            body_j: body_j.into(),
            point_j: point_j.into(),
            initial_u: None,
        }
    }

    /// The curve parameter at the drawn pose.
    pub fn initial_u(mut self, u: f64) -> Self {
        self.initial_u = Some(u);
        self
    }
}

/// A cam pair: a planar curve of body j (a roller's circle, a flat face's line, a follower's
/// profile) kept in tangent contact with a curve of body i (the cam's profile), both curve
/// parameters extra coordinates (u on the cam, w on the follower's curve); see
/// [`cardan_constraints::CurveOnCurve`] for the equations.
#[derive(Debug, Clone, PartialEq)]
pub struct CamSpec {
    /// Name (unique among all elements).
    pub name: String,
    /// The body carrying the cam's profile (ground allowed).
    pub body_i: String,
    /// The cam's profile, in body i's coordinates.
    pub curve_i: Curve,
    /// The normal of the cam's plane, in body i's coordinates.
    pub normal_i: Vector3<f64>,
    /// The follower.
    pub body_j: String,
    /// The follower's curve, in body j's coordinates.
    pub curve_j: Curve,
    /// (u, w) at the drawn pose; when `None`, the closest pair of points of the two curves as
    /// drawn.
    pub initial: Option<[f64; 2]>,
}

impl CamSpec {
    /// `curve_j` of `body_j` in tangent contact with `curve_i` of `body_i`, in the plane of
    /// normal `normal_i` (body i's coordinates).
    pub fn new(
        name: impl Into<String>,
        (body_i, curve_i, normal_i): (&str, impl Into<Curve>, Vector3<f64>),
        (body_j, curve_j): (&str, impl Into<Curve>),
    ) -> Self {
        Self {
            name: name.into(),
            body_i: body_i.into(),
            curve_i: curve_i.into(),
            normal_i,
            body_j: body_j.into(),
            curve_j: curve_j.into(),
            initial: None,
        }
    }

    /// (u, w) at the drawn pose.
    pub fn initial(mut self, u: f64, w: f64) -> Self {
        self.initial = Some([u, w]);
        self
    }
}

/// A point of body j on a surface fixed in body i (a ball on a dish, a stylus on a sculptured
/// surface); its two surface parameters (u, v) become extra coordinates. See
/// [`cardan_constraints::PointOnSurface`] for the equations.
#[derive(Debug, Clone, PartialEq)]
pub struct SurfaceSpec {
    /// Name (unique among all elements).
    pub name: String,
    /// The body carrying the surface (ground allowed).
    pub body_i: String,
    /// The surface, in body i's coordinates (global for ground).
    pub surface: Surface,
    /// The body carrying the point.
    pub body_j: String,
    /// The name of the point on body j.
    pub point_j: String,
    /// (u, v) at the drawn pose; when `None`, the parameters of the surface point nearest to
    /// the drawn point ([`Surface::closest`]).
    pub initial: Option<[f64; 2]>,
}

impl SurfaceSpec {
    /// Point `point_j` of `body_j` on `surface` of `body_i`.
    pub fn new(
        name: impl Into<String>,
        body_i: &str,
        surface: impl Into<Surface>,
        body_j: &str,
        point_j: &str,
    ) -> Self {
        Self {
            name: name.into(),
            body_i: body_i.into(),
            surface: surface.into(),
            body_j: body_j.into(),
            point_j: point_j.into(),
            initial: None,
        }
    }
}

/// A path driver: the curve parameter u of a point-on-curve element prescribed in time,
/// u = f(t) (arc length for lines, circles and helices: f = v t moves the point at speed v).
#[derive(Debug, Clone, PartialEq)]
pub struct PathSpec {
    /// Name (unique among all elements).
    pub name: String,
    /// The point-on-curve element whose parameter it drives.
    pub curve: String,
    /// f(t), m.
    pub function: TimeFunction,
    /// Whether f prescribes the arc length travelled along the curve, S(u) = f(t), rather
    /// than its parameter (the same for lines, circles and helices; a spline's parameter is
    /// its chord length).
    pub arc_length: bool,
}

impl PathSpec {
    /// u = `function`(t) for the curve parameter of element `curve`.
    pub fn new(name: impl Into<String>, curve: &str, function: TimeFunction) -> Self {
        Self {
            name: name.into(),
            curve: curve.into(),
            function,
            arc_length: false,
        }
    }

    /// The arc length travelled along the curve = `function`(t) (a point moved at speed v along
    /// a spline by f = v t).
    pub fn along_arc(mut self) -> Self {
        self.arc_length = true;
        self
    }
}
