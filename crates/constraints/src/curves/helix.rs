//! A circular helix about a marker's z axis, parametrized by arc length:
//! c'(u) = P + R cos φ x + R sin φ y + (h φ / 2π) z, φ = u / k, k = √(R² + (h/2π)²),
//! with R the radius and h the pitch (rise per turn; negative for a left-handed helix).
//!
//! Frenet closed forms (a unit-speed curve): curvature κ = R / k², torsion τ = (h/2π) / k²;
//! c'_uu = κ n with n = −(cos φ x + sin φ y), c'_uuu = −κ² t + κ τ b (Frenet–Serret).

use super::CurveJet;
use crate::error::ConstraintError;
use crate::marker::Marker;
use nalgebra::Vector3;
use std::f64::consts::TAU;

/// A circular helix about a marker's z axis.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Helix {
    centre: Vector3<f64>,
    x: Vector3<f64>,
    y: Vector3<f64>,
    z: Vector3<f64>,
    radius: f64,
    /// h / 2π, the rise per radian.
    rise: f64,
    /// k = √(R² + (h/2π)²), the length per radian.
    k: f64,
}

impl Helix {
    /// The helix of radius `radius` (positive) and pitch `pitch` (non-zero: a zero pitch is a
    /// circle) about `m`'s z axis, starting at `m.point + R x` for u = 0.
    pub fn new(m: &Marker, radius: f64, pitch: f64) -> Result<Self, ConstraintError> {
        if !(radius.is_finite() && radius > 0.0) {
            return Err(ConstraintError::NotPositive {
                what: "helix radius".into(),
                value: radius,
            });
        }
        if !pitch.is_finite() || pitch == 0.0 {
            return Err(ConstraintError::Curve(format!(
                "helix pitch must be a non-zero finite number (got {pitch}); for a pitch of 0 use a circle"
            )));
        }
        let rise = pitch / TAU;
        Ok(Self {
            centre: m.point,
            x: m.x(),
            y: m.y(),
            z: m.z(),
            radius,
            rise,
            k: radius.hypot(rise),
        })
    }

    /// R.
    pub fn radius(&self) -> f64 {
        self.radius
    }

    /// Curvature κ = R / k² (constant).
    pub fn curvature(&self) -> f64 {
        self.radius / (self.k * self.k)
    }

    /// Torsion τ = (h/2π) / k² (constant; positive for a right-handed helix).
    pub fn torsion(&self) -> f64 {
        self.rise / (self.k * self.k)
    }

    /// The parameter range of the turn of the helix nearest to `p` (one turn each side of the
    /// height of p along the axis), where [`super::Curve::closest`] searches.
    pub(crate) fn turn_near(&self, p: &Vector3<f64>) -> (f64, f64) {
        let phi = self.z.dot(&(p - self.centre)) / self.rise;
        let u = phi * self.k;
        let turn = TAU * self.k;
        (u - turn, u + turn)
    }

    /// c'(u) and its derivatives.
    pub fn jet(&self, u: f64) -> CurveJet {
        let (r, k) = (self.radius, self.k);
        let phi = u / k;
        let (s, c) = phi.sin_cos();
        let radial = self.x * c + self.y * s;
        let around = self.y * c - self.x * s;
        CurveJet {
            c: self.centre + radial * r + self.z * (self.rise * phi),
            c_u: (around * r + self.z * self.rise) / k,
            c_uu: -radial * (r / (k * k)),
            c_uuu: -around * (r / (k * k * k)),
        }
    }
}
