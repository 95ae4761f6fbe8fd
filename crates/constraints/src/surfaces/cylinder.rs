//! A circular cylinder of radius R about a marker's z axis:
//!
//! ```text
//! S'(u, v) = P + R (cos θ x + sin θ y) + v z,   θ = u/R
//! S'_u = −sin θ x + cos θ y,   S'_v = z,   S'_uu = −(cos θ x + sin θ y)/R,   S'_uv = S'_vv = 0
//! ```

use super::{positive, Frame, SurfaceJet};
use crate::error::ConstraintError;
use crate::marker::Marker;
use nalgebra::Vector3;

/// A cylinder about a marker's z axis.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Cylinder {
    frame: Frame,
    radius: f64,
}

impl Cylinder {
    /// The cylinder of radius `radius` (positive, finite) about `m`'s z axis through `m.point`.
    pub fn new(m: &Marker, radius: f64) -> Result<Self, ConstraintError> {
        Ok(Self {
            frame: Frame::of(m),
            radius: positive("cylinder radius", radius)?,
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
        let radial = f.x * ct + f.y * st;
        SurfaceJet {
            s: f.origin + radial * r + f.z * v,
            s_u: f.y * ct - f.x * st,
            s_v: f.z,
            s_uu: -radial / r,
            s_uv: Vector3::zeros(),
            s_vv: Vector3::zeros(),
        }
    }

    /// The parameters of the radial projection of `p` onto the cylinder.
    pub fn closest(&self, p: &Vector3<f64>) -> [f64; 2] {
        let l = self.frame.local(p);
        [self.radius * l.y.atan2(l.x), l.z]
    }
}
