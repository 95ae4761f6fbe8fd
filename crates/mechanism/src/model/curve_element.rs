//! [`CurveElement`]: the higher pairs whose curve parameters are extra coordinates of the
//! mechanism: a point on a curve (one parameter u) and a cam pair (two curves in tangent contact,
//! parameters u and w). One closed enum, so the model stores them in one list, gives them their
//! columns in order (element k's first parameter follows element k − 1's last) and evaluates them
//! by static dispatch.

use cardan_constraints::{Curve, CurveOnCurve, PointOnCurve, MAX_EXTRA};

/// A point-on-curve element or a cam pair.
#[derive(Debug, Clone, PartialEq)]
pub enum CurveElement {
    /// A point of body j on a curve of body i (u).
    Point(PointOnCurve),
    /// A curve of body j tangent to a curve of body i (u on curve i, w on curve j).
    Cam(CurveOnCurve),
}

impl CurveElement {
    /// The curve each parameter runs on, in parameter order (u, then w for a cam).
    pub fn curves(&self) -> [Option<&Curve>; MAX_EXTRA] {
        match self {
            CurveElement::Point(p) => [Some(&p.curve), None],
            CurveElement::Cam(c) => [Some(&c.curve_i), Some(&c.curve_j)],
        }
    }

    /// The parameters' names, in order ("u"; "u" and "w" for a cam).
    pub fn parameters(&self) -> &'static [&'static str] {
        match self {
            CurveElement::Point(_) => &["u"],
            CurveElement::Cam(_) => &["u", "w"],
        }
    }

    /// The element kind as equation listings name it ("point_on_curve", "cam").
    pub fn kind(&self) -> &'static str {
        match self {
            CurveElement::Point(_) => "point_on_curve",
            CurveElement::Cam(_) => "cam",
        }
    }

    /// What the element is in messages ("point-on-curve", "cam").
    pub fn what(&self) -> &'static str {
        match self {
            CurveElement::Point(_) => "point-on-curve",
            CurveElement::Cam(_) => "cam",
        }
    }
}

cardan_constraints::delegate_constraint!(CurveElement {
    CurveElement::Point,
    CurveElement::Cam,
});
