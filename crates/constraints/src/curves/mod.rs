//! Curves fixed in a body: the geometry that cams, slots and paths follow.
//!
//! A curve is a map u ↦ c'(u) into a body's coordinates (the body's frame; ground's is the
//! global frame). Higher pairs follow it with the curve parameter u as an *extra coordinate*
//! of the mechanism (Haug 1989 §9.4, "point-follower"; Nikravesh 1988 §11.2 for cams): the
//! constraint is written in (q, u) and the analyses solve for u with the body coordinates.
//! A constraint needs c' and its first derivatives in u ([`CurveJet`]): c'_u enters the Jacobian
//! column of u, c'_uu the velocity-quadratic term of γ# (with u̇²), c'_uuu the γ# of elements
//! written with the tangent (a curve in contact with another curve).
//!
//! Kinds (one file each):
//!
//! | kind | c'(u) | parameter |
//! |---|---|---|
//! | [`Line`] | P + u z (a marker's z axis) | arc length |
//! | [`Circle`] | P + R (cos(u/R) x + sin(u/R) y) | arc length |
//! | [`Helix`] | P + R cos φ x + R sin φ y + (h φ / 2π) z, φ = u / √(R² + (h/2π)²) | arc length |
//! | [`CubicCurve`] | the interpolating cubic spline through points, natural (open) or periodic (closed) | cumulative chord length |
//! | [`CubicCurve::quintic`] | the interpolating quintic spline (C⁴) through points, natural or periodic | cumulative chord length |
//!
//! Open curves of finite extent have a [`Curve::domain`]: analyses stop with an error naming
//! the time when u leaves it (the constraint itself is extended smoothly beyond it, so its
//! evaluation never fails). Closed curves have a [`Curve::period`] L: c'(u + L) = c'(u), so u
//! runs on over any number of turns (a cam turning). A spline's arc length S(u) is tabulated by
//! [`ArcLength`], for a path driver that prescribes the distance travelled.

mod arc_length;
mod circle;
mod cubic;
mod helix;
mod line;
mod quintic;

pub use arc_length::ArcLength;
pub use circle::Circle;
pub use cubic::CubicCurve;
pub use helix::Helix;
pub use line::Line;

use nalgebra::Vector3;

/// A curve point and its derivatives in u, in the curve body's coordinates.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CurveJet {
    /// c'(u).
    pub c: Vector3<f64>,
    /// dc'/du.
    pub c_u: Vector3<f64>,
    /// d²c'/du².
    pub c_uu: Vector3<f64>,
    /// d³c'/du³.
    pub c_uuu: Vector3<f64>,
}

/// A curve of any kind (closed enum: static dispatch, no allocation in evaluation).
#[derive(Debug, Clone, PartialEq)]
pub enum Curve {
    /// A straight line.
    Line(Line),
    /// A circle (an arc is a circle with a domain kept by the analysis).
    Circle(Circle),
    /// A circular helix.
    Helix(Helix),
    /// A cubic spline through points.
    Cubic(CubicCurve),
}

impl Curve {
    /// The kind names, as the oracle elements `point_on_curve_<kind>` spell them (a closed
    /// cubic is its own oracle element, `cubic_closed`).
    pub const KINDS: [&'static str; 7] = [
        "line",
        "circle",
        "helix",
        "cubic",
        "cubic_closed",
        "quintic",
        "quintic_closed",
    ];

    /// This curve's entry of [`Curve::KINDS`].
    pub fn kind(&self) -> &'static str {
        match self {
            Curve::Line(_) => "line",
            Curve::Circle(_) => "circle",
            Curve::Helix(_) => "helix",
            Curve::Cubic(c) => match (c.degree(), c.is_closed()) {
                (5, true) => "quintic_closed",
                (5, false) => "quintic",
                (_, true) => "cubic_closed",
                (_, false) => "cubic",
            },
        }
    }

    /// c'(u) and its first three derivatives.
    pub fn jet(&self, u: f64) -> CurveJet {
        match self {
            Curve::Line(c) => c.jet(u),
            Curve::Circle(c) => c.jet(u),
            Curve::Helix(c) => c.jet(u),
            Curve::Cubic(c) => c.jet(u),
        }
    }

    /// The interval of u on which the curve is defined by its data ([u_0, u_n] of an open
    /// spline); `None` for curves without ends (lines, circles, helices, closed splines).
    pub fn domain(&self) -> Option<(f64, f64)> {
        match self {
            Curve::Cubic(c) if !c.is_closed() => Some(c.knot_range()),
            _ => None,
        }
    }

    /// The period L (c'(u + L) = c'(u)) of a closed curve: 2πR for a circle, the total chord
    /// length of a closed spline; `None` otherwise.
    pub fn period(&self) -> Option<f64> {
        match self {
            Curve::Circle(c) => Some(c.period()),
            Curve::Cubic(c) if c.is_closed() => Some(c.knot_range().1),
            _ => None,
        }
    }

    /// The vector area ½∮ c' × c'_u du of a closed curve (64 chords over one period): normal to
    /// a planar curve's plane, along the side about which it runs counterclockwise, its length
    /// the enclosed area; `None` for an open curve.
    pub fn area_vector(&self) -> Option<Vector3<f64>> {
        let period = self.period()?;
        let n = 64;
        let at = |i: usize| self.jet(period * i as f64 / n as f64).c;
        Some(
            (0..n)
                .map(|i| at(i).cross(&at(i + 1)))
                .sum::<Vector3<f64>>()
                * 0.5,
        )
    }

    /// The parameter u of the curve point nearest to `p` (body coordinates): the best of
    /// samples over the curve's span (its domain, one period, or for a line and a helix the
    /// stretch near p) refined by Newton's method on c'_uᵀ(c' − p) = 0. Used to start the curve
    /// parameter at a drawn pose.
    pub fn closest(&self, p: &Vector3<f64>) -> f64 {
        let (a, b) = match self {
            Curve::Line(l) => {
                let j = l.jet(0.0);
                let u = j.c_u.dot(&(p - j.c));
                (u, u)
            }
            Curve::Helix(h) => h.turn_near(p),
            _ => match (self.domain(), self.period()) {
                (Some(d), _) => d,
                (None, Some(l)) => (0.0, l),
                (None, None) => (0.0, 0.0),
            },
        };
        const SAMPLES: usize = 256;
        let dist = |u: f64| (self.jet(u).c - p).norm_squared();
        let mut best = a;
        for k in 0..=SAMPLES {
            let u = a + (b - a) * k as f64 / SAMPLES as f64;
            if dist(u) < dist(best) {
                best = u;
            }
        }
        let step = (b - a) / SAMPLES as f64;
        let mut u = best;
        for _ in 0..50 {
            let j = self.jet(u);
            let d = j.c - p;
            let (f, df) = (j.c_u.dot(&d), j.c_uu.dot(&d) + j.c_u.norm_squared());
            if df <= 0.0 {
                break;
            }
            let du = (-f / df).clamp(-step.max(1e-300), step.max(1e-300));
            u += du;
            if du.abs() <= 1e-15 * (1.0 + u.abs()) {
                break;
            }
        }
        if dist(u) <= dist(best) {
            u
        } else {
            best
        }
    }
}

impl From<Line> for Curve {
    fn from(c: Line) -> Self {
        Curve::Line(c)
    }
}

impl From<Circle> for Curve {
    fn from(c: Circle) -> Self {
        Curve::Circle(c)
    }
}

impl From<Helix> for Curve {
    fn from(c: Helix) -> Self {
        Curve::Helix(c)
    }
}

impl From<CubicCurve> for Curve {
    fn from(c: CubicCurve) -> Self {
        Curve::Cubic(c)
    }
}

#[cfg(test)]
mod tests;
