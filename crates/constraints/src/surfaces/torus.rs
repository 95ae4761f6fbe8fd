//! A torus about a marker's z axis: the points at distance r (the tube's radius) from the circle
//! of radius R (the centre circle) in the marker's x–y plane, R > r:
//!
//! ```text
//! S'(u, v) = P + (R + r cos φ) ρ + r sin φ z,   ρ = cos θ x + sin θ y,   θ = u/R, φ = v/r
//! S'_u = ((R + r cos φ)/R) τ,   τ = −sin θ x + cos θ y
//! S'_v = −sin φ ρ + cos φ z
//! S'_uu = −((R + r cos φ)/R²) ρ,   S'_uv = −(sin φ / R) τ,   S'_vv = −(cos φ ρ + sin φ z)/r
//! ```
//!
//! u is the arc length along the centre circle, v around the tube (from the outer equator
//! toward +z).

use super::{positive, Frame, SurfaceJet};
use crate::error::ConstraintError;
use crate::marker::Marker;
use nalgebra::Vector3;

/// A torus about a marker's z axis.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Torus {
    frame: Frame,
    major: f64,
    minor: f64,
}

impl Torus {
    /// The torus about `m`'s z axis through `m.point` with centre-circle radius `major` and tube
    /// radius `minor` (both positive and finite, `minor` < `major`: a ring torus).
    pub fn new(m: &Marker, major: f64, minor: f64) -> Result<Self, ConstraintError> {
        let (major, minor) = (
            positive("torus major radius", major)?,
            positive("torus tube radius", minor)?,
        );
        if minor >= major {
            return Err(ConstraintError::Curve(format!(
                "a torus' tube radius ({minor}) must be smaller than its major radius ({major})"
            )));
        }
        Ok(Self {
            frame: Frame::of(m),
            major,
            minor,
        })
    }

    /// (R, r).
    pub fn radii(&self) -> (f64, f64) {
        (self.major, self.minor)
    }

    /// S' and its derivatives.
    pub fn jet(&self, u: f64, v: f64) -> SurfaceJet {
        let (f, big, r) = (&self.frame, self.major, self.minor);
        let (st, ct) = (u / big).sin_cos();
        let (sp, cp) = (v / r).sin_cos();
        let rho = f.x * ct + f.y * st;
        let tau = f.y * ct - f.x * st;
        let arm = big + r * cp;
        SurfaceJet {
            s: f.origin + rho * arm + f.z * (r * sp),
            s_u: tau * (arm / big),
            s_v: f.z * cp - rho * sp,
            s_uu: -rho * (arm / (big * big)),
            s_uv: -tau * (sp / big),
            s_vv: -(rho * cp + f.z * sp) / r,
        }
    }

    /// The parameters of the nearest torus point to `p`: its angle about the axis, then its
    /// angle about the nearest centre-circle point.
    pub fn closest(&self, p: &Vector3<f64>) -> [f64; 2] {
        let l = self.frame.local(p);
        let theta = l.y.atan2(l.x);
        let out = l.x.hypot(l.y) - self.major;
        [self.major * theta, self.minor * l.z.atan2(out)]
    }
}
