//! A straight line c'(u) = P + u z along a marker's z axis, u the arc length from P.
//! A point held on it by a point-on-curve constraint moves as in a point-in-line joint
//! (`joints::kinds`, two rows): the curve form adds u as a coordinate and gives three rows.

use super::CurveJet;
use crate::marker::Marker;
use nalgebra::Vector3;

/// A straight line through a marker's point along its z axis.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Line {
    origin: Vector3<f64>,
    direction: Vector3<f64>,
}

impl Line {
    /// The line through `m.point` along `m.z()` (a unit vector, so u is arc length).
    pub fn new(m: &Marker) -> Self {
        Self {
            origin: m.point,
            direction: m.z(),
        }
    }

    /// The point at u = 0.
    pub fn origin(&self) -> Vector3<f64> {
        self.origin
    }

    /// c' = P + u z, c'_u = z, higher derivatives zero.
    pub fn jet(&self, u: f64) -> CurveJet {
        CurveJet {
            c: self.origin + self.direction * u,
            c_u: self.direction,
            c_uu: Vector3::zeros(),
            c_uuu: Vector3::zeros(),
        }
    }
}
