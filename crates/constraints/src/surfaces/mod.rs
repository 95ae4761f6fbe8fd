//! Surfaces fixed in a body: the geometry a point follows with two parameters.
//!
//! A surface is a map (u, v) ↦ S'(u, v) into a body's coordinates (the body's frame; ground's is
//! the global frame). A [`crate::PointOnSurface`] keeps a point of another body on it with u and
//! v two *extra coordinates* of the mechanism, as a curve's parameter is one (Haug 1989 §9.4;
//! the module docs of [`crate::curves`]). A constraint needs S' and its first and second
//! derivatives ([`SurfaceJet`]): S'_u and S'_v are the Jacobian columns of u and v, the second
//! derivatives enter γ# with the parameters' rates.
//!
//! Kinds (one file each), each placed by a marker (origin P, axes x, y, z):
//!
//! | kind | S'(u, v) | parameters |
//! |---|---|---|
//! | [`Plane`] | P + u x + v y | lengths along x and y |
//! | [`Sphere`] | P + R (cos φ cos θ x + cos φ sin θ y + sin φ z), θ = u/R, φ = v/R | arc lengths along the equator and a meridian (singular at the poles) |
//! | [`Cylinder`] | P + R (cos θ x + sin θ y) + v z, θ = u/R | arc length around, length along z |
//! | [`Torus`] | P + (R + r cos φ)(cos θ x + sin θ y) + r sin φ z, θ = u/R, φ = v/r | arc lengths along the centre circle and around the tube |
//! | [`BicubicPatch`] | Σᵢ Σⱼ Bᵢ(u) Bⱼ(v) Pᵢⱼ, the Bernstein polynomials of degree 3 | u, v ∈ [0, 1] |
//!
//! A bicubic patch has a [`Surface::domain`], [0, 1]²: analyses stop with an error naming the
//! time when a parameter leaves it (the polynomial itself continues beyond, so evaluation never
//! fails). The other kinds have no ends: θ and the tube's φ run over any number of turns.

mod bicubic;
mod cylinder;
mod plane;
mod sphere;
mod torus;

pub use bicubic::BicubicPatch;
pub use cylinder::Cylinder;
pub use plane::Plane;
pub use sphere::Sphere;
pub use torus::Torus;

use nalgebra::Vector3;

/// A surface point and its first and second derivatives, in the surface body's coordinates.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SurfaceJet {
    /// S'(u, v).
    pub s: Vector3<f64>,
    /// ∂S'/∂u.
    pub s_u: Vector3<f64>,
    /// ∂S'/∂v.
    pub s_v: Vector3<f64>,
    /// ∂²S'/∂u².
    pub s_uu: Vector3<f64>,
    /// ∂²S'/∂u∂v.
    pub s_uv: Vector3<f64>,
    /// ∂²S'/∂v².
    pub s_vv: Vector3<f64>,
}

/// A surface of any kind (closed enum: static dispatch, no allocation in evaluation).
#[derive(Debug, Clone, PartialEq)]
pub enum Surface {
    /// A plane.
    Plane(Plane),
    /// A sphere.
    Sphere(Sphere),
    /// A circular cylinder.
    Cylinder(Cylinder),
    /// A torus.
    Torus(Torus),
    /// A bicubic Bézier patch.
    Bicubic(BicubicPatch),
}

impl Surface {
    /// The kind names, as the oracle elements `point_on_surface_<kind>` spell them.
    pub const KINDS: [&'static str; 5] = ["plane", "sphere", "cylinder", "torus", "bicubic"];

    /// This surface's entry of [`Surface::KINDS`].
    pub fn kind(&self) -> &'static str {
        match self {
            Surface::Plane(_) => "plane",
            Surface::Sphere(_) => "sphere",
            Surface::Cylinder(_) => "cylinder",
            Surface::Torus(_) => "torus",
            Surface::Bicubic(_) => "bicubic",
        }
    }

    /// S' and its derivatives at (u, v).
    pub fn jet(&self, u: f64, v: f64) -> SurfaceJet {
        match self {
            Surface::Plane(s) => s.jet(u, v),
            Surface::Sphere(s) => s.jet(u, v),
            Surface::Cylinder(s) => s.jet(u, v),
            Surface::Torus(s) => s.jet(u, v),
            Surface::Bicubic(s) => s.jet(u, v),
        }
    }

    /// The intervals of u and v on which the surface is defined by its data ([0, 1] each for
    /// a bicubic patch); `None` for surfaces without edges.
    pub fn domain(&self) -> Option<[(f64, f64); 2]> {
        match self {
            Surface::Bicubic(_) => Some([(0.0, 1.0); 2]),
            _ => None,
        }
    }

    /// A length of the surface: a sphere's, a cylinder's or a torus' (major) radius, a patch's
    /// largest control-point distance from its first; 0 for a plane.
    pub fn size(&self) -> f64 {
        match self {
            Surface::Plane(_) => 0.0,
            Surface::Sphere(s) => s.radius(),
            Surface::Cylinder(s) => s.radius(),
            Surface::Torus(s) => s.radii().0,
            Surface::Bicubic(s) => s.size(),
        }
    }

    /// The parameters (u, v) of the surface point nearest to `p` (body coordinates): the kind's
    /// own projection (a bicubic patch: the best of a 17 × 17 grid of samples refined by
    /// Gauss–Newton). Used to start the parameters at a drawn pose.
    pub fn closest(&self, p: &Vector3<f64>) -> [f64; 2] {
        let start = match self {
            Surface::Plane(s) => return s.closest(p),
            Surface::Sphere(s) => return s.closest(p),
            Surface::Cylinder(s) => return s.closest(p),
            Surface::Torus(s) => return s.closest(p),
            Surface::Bicubic(s) => s.sample_nearest(p),
        };
        let [mut u, mut v] = start;
        for _ in 0..50 {
            let j = self.jet(u, v);
            let d = j.s - p;
            // Gauss–Newton on ½|S' − p|²: the 2 × 2 normal equations.
            let (a, b, c) = (j.s_u.dot(&j.s_u), j.s_u.dot(&j.s_v), j.s_v.dot(&j.s_v));
            let (g0, g1) = (j.s_u.dot(&d), j.s_v.dot(&d));
            let det = a * c - b * b;
            if det.abs() <= f64::EPSILON * (a * c).abs() {
                break;
            }
            let (du, dv) = ((c * g0 - b * g1) / det, (a * g1 - b * g0) / det);
            u -= du;
            v -= dv;
            if du.abs().max(dv.abs()) < 1e-15 {
                break;
            }
        }
        [u, v]
    }
}

macro_rules! surface_from {
    ($($t:ident),*) => {$(
        impl From<$t> for Surface {
            fn from(s: $t) -> Self {
                Surface::$t(s)
            }
        }
    )*};
}
surface_from!(Plane, Sphere, Cylinder, Torus);

impl From<BicubicPatch> for Surface {
    fn from(s: BicubicPatch) -> Self {
        Surface::Bicubic(s)
    }
}

/// A marker's origin and axes (the frame a surface is placed by).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Frame {
    pub origin: Vector3<f64>,
    pub x: Vector3<f64>,
    pub y: Vector3<f64>,
    pub z: Vector3<f64>,
}

impl Frame {
    pub fn of(m: &crate::marker::Marker) -> Self {
        Self {
            origin: m.point,
            x: m.x(),
            y: m.y(),
            z: m.z(),
        }
    }

    /// `p` − origin in the frame's axes.
    pub fn local(&self, p: &Vector3<f64>) -> Vector3<f64> {
        let d = p - self.origin;
        Vector3::new(d.dot(&self.x), d.dot(&self.y), d.dot(&self.z))
    }
}

/// A positive, finite radius or a [`crate::error::ConstraintError::NotPositive`].
pub(crate) fn positive(what: &str, value: f64) -> Result<f64, crate::error::ConstraintError> {
    if value.is_finite() && value > 0.0 {
        Ok(value)
    } else {
        Err(crate::error::ConstraintError::NotPositive {
            what: what.into(),
            value,
        })
    }
}

#[cfg(test)]
mod tests;
