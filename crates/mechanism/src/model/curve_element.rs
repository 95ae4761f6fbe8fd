//! [`CurveElement`]: the higher pairs whose curve parameters are extra coordinates of the
//! mechanism: a point on a curve (one parameter u), a cam pair (two curves in tangent contact,
//! parameters u and w) and a point on a surface (parameters u and v). One closed enum, so the model stores them in one list, gives them their
//! columns in order (element k's first parameter follows element k − 1's last) and evaluates them
//! by static dispatch.

use cardan_constraints::{BodyState, Curve, CurveOnCurve, PointOnCurve, PointOnSurface, MAX_EXTRA};
use nalgebra::Vector3;

/// A point-on-curve element or a cam pair.
#[derive(Debug, Clone, PartialEq)]
pub enum CurveElement {
    /// A point of body j on a curve of body i (u).
    Point(PointOnCurve),
    /// A curve of body j tangent to a curve of body i (u on curve i, w on curve j).
    Cam(CurveOnCurve),
    /// A point of body j on a surface of body i (u, v).
    Surface(PointOnSurface),
}

impl CurveElement {
    /// The curve each parameter runs on, in parameter order (u, then w for a cam).
    pub fn curves(&self) -> [Option<&Curve>; MAX_EXTRA] {
        match self {
            CurveElement::Point(p) => [Some(&p.curve), None],
            CurveElement::Cam(c) => [Some(&c.curve_i), Some(&c.curve_j)],
            CurveElement::Surface(_) => [None, None],
        }
    }

    /// The interval each parameter must stay in (an open curve's data, a patch's [0, 1]), in
    /// parameter order; `None` for a parameter without ends.
    pub fn domains(&self) -> [Option<(f64, f64)>; MAX_EXTRA] {
        match self {
            CurveElement::Surface(s) => match s.surface.domain() {
                Some([a, b]) => [Some(a), Some(b)],
                None => [None, None],
            },
            other => other.curves().map(|c| c.and_then(Curve::domain)),
        }
    }

    /// The parameters' names, in order ("u"; "u" and "w" for a cam).
    pub fn parameters(&self) -> &'static [&'static str] {
        match self {
            CurveElement::Point(_) => &["u"],
            CurveElement::Cam(_) => &["u", "w"],
            CurveElement::Surface(_) => &["u", "v"],
        }
    }

    /// The element kind as equation listings name it ("point_on_curve", "cam").
    pub fn kind(&self) -> &'static str {
        match self {
            CurveElement::Point(_) => "point_on_curve",
            CurveElement::Cam(_) => "cam",
            CurveElement::Surface(_) => "point_on_surface",
        }
    }

    /// A cam pair's contact at parameters `u` (u, w) with its bodies in states `si`, `sj`: the
    /// contact point (global), the common unit normal (the cam's in-plane normal, global) and
    /// the point of body j at the contact in body j's coordinates; `None` for other elements.
    pub fn contact(
        &self,
        si: &BodyState,
        sj: &BodyState,
        u: &[f64],
    ) -> Option<(Vector3<f64>, Vector3<f64>, Vector3<f64>)> {
        let CurveElement::Cam(c) = self else {
            return None;
        };
        let (ci, cj) = (c.curve_i.jet(u[0]), c.curve_j.jet(u[1]));
        let normal = si.a * c.normal_i.cross(&ci.c_u).normalize();
        Some((sj.point(&cj.c), normal, cj.c))
    }

    /// The direction in which a pressing contact of a cam pair pushes body j (the follower),
    /// global, at parameters `u` (u, w) with the bodies in states `si`, `sj`: out of a closed
    /// cam profile, else into a closed follower curve (a roller); `None` for a point on a curve
    /// and for two open curves (a flat face on an open profile), where the curves alone do not
    /// tell which side the bodies are on. The contact force along it is positive while the cam
    /// pushes and negative where the bilateral constraint pulls the follower on (it would lift
    /// off).
    pub fn push_direction(
        &self,
        si: &BodyState,
        sj: &BodyState,
        u: &[f64],
    ) -> Option<Vector3<f64>> {
        let CurveElement::Cam(c) = self else {
            return None;
        };
        let k = c.normal_i;
        let [area_i, area_j] = c.areas();
        if let Some(area) = area_i {
            // A counterclockwise profile (about k) has k × c' inward: outward is its opposite.
            let left = si.a * k.cross(&c.curve_i.jet(u[0]).c_u).normalize();
            return Some(-area.dot(&k).signum() * left);
        }
        let kj = sj.a.tr_mul(&(si.a * k));
        let turn = area_j?.dot(&kj).signum();
        // Into the follower's curve: its left normal if counterclockwise.
        let left = sj.a * kj.cross(&c.curve_j.jet(u[1]).c_u).normalize();
        Some(turn * left)
    }

    /// The pressure angle between the contact's common normal `normal` and the direction the
    /// follower's point at the contact moves: its velocity `v`, or, where the point is at rest
    /// (|v| ≤ 1e-9 `scale`, a follower at the end of its stroke), its acceleration `a`, the
    /// direction it starts to move in; `None` where both vanish. In [0, π/2] (the normal's sense
    /// does not matter).
    pub fn pressure_angle(
        normal: &Vector3<f64>,
        v: &Vector3<f64>,
        a: Option<&Vector3<f64>>,
        scale: f64,
    ) -> Option<f64> {
        let tiny = 1e-9 * scale;
        let moving = [Some(v), a]
            .into_iter()
            .flatten()
            .find(|d| d.norm() > tiny)?;
        Some(normal.cross(moving).norm().atan2(normal.dot(moving).abs()))
    }

    /// What the element is in messages ("point-on-curve", "cam").
    pub fn what(&self) -> &'static str {
        match self {
            CurveElement::Point(_) => "point-on-curve",
            CurveElement::Cam(_) => "cam",
            CurveElement::Surface(_) => "point-on-surface",
        }
    }
}

cardan_constraints::delegate_constraint!(CurveElement {
    CurveElement::Point,
    CurveElement::Cam,
    CurveElement::Surface,
});
