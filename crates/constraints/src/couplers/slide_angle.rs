//! The equation shared by the rack-and-pinion and screw couplers: a slide and a relative angle
//! between two bodies, linearly related (OndselSolver's `RackPinConstraintIJ` and
//! `ScrewConstraintIJ` are this form with the slide along x_i and z_i respectively).
//!
//! With markers i and j, d = P_j − P_i, e_i a unit axis of marker i (x_i or z_i):
//!
//! ```text
//! u  = e_iᵀ d                                    slide along e_i
//! θ  = atan2(y_iᵀ x_j, x_iᵀ x_j)                 angle of x_j from x_i about z_i, continued
//! Φ  = k_s u + k_θ θ − c                          1 row, a length (k_s = ±1, k_θ in m/rad)
//! Φ_q = k_s ∇(e_iᵀ d) + k_θ (w ∇u' − u' ∇w) / (u'² + w²),  u' = y_iᵀ x_j, w = x_iᵀ x_j
//! γ# = −(k_s (e_iᵀ d)¨ + k_θ θ̈)                  (velocity-quadratic parts)
//! ```
//!
//! Footprint: r and p of both bodies.

use super::angle::{angle_grad, angle_motion, continued_angle};
use crate::constraint::{Constraint, Dimension};
use crate::jet::{Form, Grad, Motion, ScalarGrad, Side};
use crate::marker::Marker;
use crate::state::{BlockUse, BodyPair, Footprint};
use nalgebra::Vector3;

/// k_s e_iᵀ d + k_θ θ(i → j) − c = 0, the slide along `axis` of marker i.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SlideAngle {
    /// Marker on body i (point P_i; axes x_i, y_i, z_i).
    pub marker_i: Marker,
    /// Marker on body j (point P_j; x_j).
    pub marker_j: Marker,
    /// The slide axis e'_i in body i's frame (a unit axis of marker i).
    pub axis: Vector3<f64>,
    /// k_s, the coefficient of the slide.
    pub k_slide: f64,
    /// k_θ, the coefficient of the angle (m/rad).
    pub k_angle: f64,
    /// c (m).
    pub constant: f64,
    /// The continued angle θ at the last accepted pose.
    pub reference: f64,
}

impl SlideAngle {
    /// θ = atan2(y_iᵀ x_j, x_iᵀ x_j) continued from [`SlideAngle::reference`].
    pub fn angle(&self, x: &BodyPair) -> f64 {
        let xj = x.j.vector(&self.marker_j.x());
        let s = x.i.vector(&self.marker_i.y()).dot(&xj);
        let c = x.i.vector(&self.marker_i.x()).dot(&xj);
        continued_angle(self.reference, s, c)
    }

    /// The slide e_iᵀ d.
    pub fn slide(&self, x: &BodyPair) -> f64 {
        let d = x.j.point(&self.marker_j.point) - x.i.point(&self.marker_i.point);
        x.i.vector(&self.axis).dot(&d)
    }
}

impl Constraint for SlideAngle {
    fn name(&self) -> &'static str {
        "slide_angle"
    }
    fn rows(&self) -> usize {
        1
    }
    fn dimension(&self, _row: usize) -> Dimension {
        Dimension::Length
    }
    fn footprint(&self) -> Footprint {
        Footprint {
            i: BlockUse::RP,
            j: BlockUse::RP,
        }
    }
    fn phi(&self, x: &BodyPair, _t: f64, out: &mut [f64]) {
        out[0] = self.k_slide * self.slide(x) + self.k_angle * self.angle(x) - self.constant;
    }
    fn jacobian<const N: usize, F: Form<N>>(
        &self,
        x: &BodyPair,
        _t: f64,
        out_i: &mut [[f64; N]],
        out_j: &mut [[f64; N]],
    ) {
        let (mi, mj) = (&self.marker_i, &self.marker_j);
        let d = Grad::between::<F>(x.i, x.j, &mi.point, &mj.point);
        let u = Grad::dir::<F>(x.i, x.j, Side::I, &self.axis).dot(&d);
        let xj = Grad::dir::<F>(x.i, x.j, Side::J, &mj.x());
        let s = Grad::dir::<F>(x.i, x.j, Side::I, &mi.y()).dot(&xj);
        let c = Grad::dir::<F>(x.i, x.j, Side::I, &mi.x()).dot(&xj);
        let th = angle_grad(&s, &c);
        let g = ScalarGrad {
            v: 0.0,
            di: u.di * self.k_slide + th.di * self.k_angle,
            dj: u.dj * self.k_slide + th.dj * self.k_angle,
        };
        g.write(&mut out_i[0], &mut out_j[0]);
    }
    fn gamma_sharp<const N: usize, F: Form<N>>(&self, x: &BodyPair, _t: f64, out: &mut [f64]) {
        let (mi, mj) = (&self.marker_i, &self.marker_j);
        let d = Motion::between::<N, F>(x.i, x.j, &mi.point, &mj.point);
        let u = Motion::dir::<N, F>(x.i, x.j, Side::I, &self.axis).dot(&d);
        let xj = Motion::dir::<N, F>(x.i, x.j, Side::J, &mj.x());
        let s = Motion::dir::<N, F>(x.i, x.j, Side::I, &mi.y()).dot(&xj);
        let c = Motion::dir::<N, F>(x.i, x.j, Side::I, &mi.x()).dot(&xj);
        let th = angle_motion(&s, &c);
        out[0] = -(self.k_slide * u.quad + self.k_angle * th.quad);
    }
}
