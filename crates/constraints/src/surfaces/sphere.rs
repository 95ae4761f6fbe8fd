//! A sphere of radius R about a marker's origin P, parametrized by arc lengths along the
//! equator (the marker's x–y plane) and a meridian:
//!
//! ```text
//! S'(u, v) = P + R e(θ, φ),   e = cos φ cos θ x + cos φ sin θ y + sin φ z,   θ = u/R, φ = v/R
//! S'_u = cos φ t,   S'_v = −sin φ (cos θ x + sin θ y) + cos φ z,   t = −sin θ x + cos θ y
//! S'_uu = −cos φ (cos θ x + sin θ y)/R,   S'_uv = −sin φ t/R,   S'_vv = −e/R
//! ```
//!
//! At the poles (φ = ±π/2) S'_u vanishes: the parametrization is singular there (a point held on
//! a sphere through its poles is the distance joint `spherical_spherical`).

use super::{positive, Frame, SurfaceJet};
use crate::error::ConstraintError;
use crate::marker::Marker;
use nalgebra::Vector3;

/// A sphere about a marker's origin.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Sphere {
    frame: Frame,
    radius: f64,
}

impl Sphere {
    /// The sphere of radius `radius` (positive, finite) about `m.point`, its equator in `m`'s
    /// x–y plane.
    pub fn new(m: &Marker, radius: f64) -> Result<Self, ConstraintError> {
        Ok(Self {
            frame: Frame::of(m),
            radius: positive("sphere radius", radius)?,
        })
    }

    /// R.
    pub fn radius(&self) -> f64 {
        self.radius
    }

    /// S' and its derivatives.
    pub fn jet(&self, u: f64, v: f64) -> SurfaceJet {
        let (f, r) = (&self.frame, self.radius);
        let (st, ct) = (u / r).sin_cos();
        let (sp, cp) = (v / r).sin_cos();
        let radial = f.x * ct + f.y * st;
        let t = f.y * ct - f.x * st;
        let e = radial * cp + f.z * sp;
        SurfaceJet {
            s: f.origin + e * r,
            s_u: t * cp,
            s_v: f.z * cp - radial * sp,
            s_uu: -radial * (cp / r),
            s_uv: -t * (sp / r),
            s_vv: -e / r,
        }
    }

    /// The parameters of the radial projection of `p` (θ in (−π, π], φ in [−π/2, π/2]).
    pub fn closest(&self, p: &Vector3<f64>) -> [f64; 2] {
        let l = self.frame.local(p);
        let r = self.radius;
        [r * l.y.atan2(l.x), r * l.z.atan2(l.x.hypot(l.y))]
    }
}
