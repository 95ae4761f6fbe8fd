//! A circle of radius R about a marker's z axis, in its x–y plane, parametrized by arc length:
//! c'(u) = P + R (cos θ x + sin θ y), θ = u / R (θ measured from x toward y).
//!
//! c'_u = cos θ y − sin θ x, c'_uu = −(cos θ x + sin θ y) / R, c'_uuu = −c'_u / R²: unit speed,
//! curvature 1/R toward the centre.

use super::CurveJet;
use crate::error::ConstraintError;
use crate::marker::Marker;
use nalgebra::Vector3;
use std::f64::consts::TAU;

/// A circle about a marker's z axis.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Circle {
    centre: Vector3<f64>,
    x: Vector3<f64>,
    y: Vector3<f64>,
    radius: f64,
}

impl Circle {
    /// The circle of radius `radius` (positive, finite) about `m`'s z axis through `m.point`.
    pub fn new(m: &Marker, radius: f64) -> Result<Self, ConstraintError> {
        if !(radius.is_finite() && radius > 0.0) {
            return Err(ConstraintError::NotPositive {
                what: "circle radius".into(),
                value: radius,
            });
        }
        Ok(Self {
            centre: m.point,
            x: m.x(),
            y: m.y(),
            radius,
        })
    }

    /// R.
    pub fn radius(&self) -> f64 {
        self.radius
    }

    /// The circumference 2πR, the period in u.
    pub fn period(&self) -> f64 {
        TAU * self.radius
    }

    /// c'(u) and its derivatives.
    pub fn jet(&self, u: f64) -> CurveJet {
        let r = self.radius;
        let (s, c) = (u / r).sin_cos();
        let radial = self.x * c + self.y * s;
        let tangent = self.y * c - self.x * s;
        CurveJet {
            c: self.centre + radial * r,
            c_u: tangent,
            c_uu: -radial / r,
            c_uuu: -tangent / (r * r),
        }
    }
}
