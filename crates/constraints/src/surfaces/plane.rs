//! A plane through a marker's origin P spanned by its x and y axes: S'(u, v) = P + u x + v y.
//! S'_u = x, S'_v = y, every second derivative 0.

use super::{Frame, SurfaceJet};
use crate::marker::Marker;
use nalgebra::Vector3;

/// The x–y plane of a marker.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Plane {
    frame: Frame,
}

impl Plane {
    /// The plane through `m.point` spanned by `m`'s x and y axes.
    pub fn new(m: &Marker) -> Self {
        Self {
            frame: Frame::of(m),
        }
    }

    /// S' and its derivatives.
    pub fn jet(&self, u: f64, v: f64) -> SurfaceJet {
        let f = &self.frame;
        SurfaceJet {
            s: f.origin + f.x * u + f.y * v,
            s_u: f.x,
            s_v: f.y,
            s_uu: Vector3::zeros(),
            s_uv: Vector3::zeros(),
            s_vv: Vector3::zeros(),
        }
    }

    /// The foot of the perpendicular from `p`.
    pub fn closest(&self, p: &Vector3<f64>) -> [f64; 2] {
        let l = self.frame.local(p);
        [l.x, l.y]
    }
}
