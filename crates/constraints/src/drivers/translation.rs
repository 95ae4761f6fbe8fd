//! Translation driver: the slide of a prismatic or cylindrical joint follows s(t).
//!
//! ```text
//! d  = P_j − P_i = r_j + A_j s'^P_j − r_i − A_i s'^P_i
//! Φ  = z_iᵀ d − s(t)                        (z_i the joint axis, fixed in body i)
//! Φ_q = Φ_q of n2(z_i; P_i, P_j)
//! ν  = ṡ(t)
//! γ# = −(z̈_iᵀ d + 2 ż_iᵀ ḋ + z_iᵀ d̈) + s̈(t)
//! ```
//! Nikravesh 1988 §7.5 (translational driver).

use crate::constraint::{Constraint, Dimension};
use crate::jet::{Form, Grad, Motion, Side};
use crate::marker::Marker;
use crate::state::{BlockUse, BodyPair, Footprint};
use crate::time_function::TimeFunction;

/// s(t) along z_i between `marker_i` and `marker_j`.
#[derive(Debug, Clone, PartialEq)]
pub struct TranslationDriver {
    /// Marker on body i (point P_i, axis z_i).
    pub marker_i: Marker,
    /// Marker on body j (point P_j).
    pub marker_j: Marker,
    /// s(t) in m.
    pub function: TimeFunction,
}

impl TranslationDriver {
    /// s(t) between the two markers.
    pub fn new(marker_i: Marker, marker_j: Marker, function: TimeFunction) -> Self {
        Self {
            marker_i,
            marker_j,
            function,
        }
    }
}

impl Constraint for TranslationDriver {
    fn dimension(&self, _row: usize) -> Dimension {
        Dimension::Length
    }
    fn name(&self) -> &'static str {
        "translation_driver"
    }
    fn rows(&self) -> usize {
        1
    }
    fn footprint(&self) -> Footprint {
        Footprint {
            i: BlockUse::RP,
            j: BlockUse::RP,
        }
    }
    fn phi(&self, x: &BodyPair, t: f64, out: &mut [f64]) {
        let d = x.j.point(&self.marker_j.point) - x.i.point(&self.marker_i.point);
        out[0] = x.i.vector(&self.marker_i.z()).dot(&d) - self.function.eval(t).0;
    }
    fn jacobian<const N: usize, F: Form<N>>(
        &self,
        x: &BodyPair,
        _t: f64,
        out_i: &mut [[f64; N]],
        out_j: &mut [[f64; N]],
    ) {
        let z = Grad::dir::<F>(x.i, x.j, Side::I, &self.marker_i.z());
        let d = Grad::between::<F>(x.i, x.j, &self.marker_i.point, &self.marker_j.point);
        z.dot(&d).write(&mut out_i[0], &mut out_j[0]);
    }
    fn nu(&self, _x: &BodyPair, t: f64, out: &mut [f64]) {
        out[0] = self.function.eval(t).1;
    }
    fn gamma_sharp<const N: usize, F: Form<N>>(&self, x: &BodyPair, t: f64, out: &mut [f64]) {
        let z = Motion::dir::<N, F>(x.i, x.j, Side::I, &self.marker_i.z());
        let d = Motion::between::<N, F>(x.i, x.j, &self.marker_i.point, &self.marker_j.point);
        out[0] = -z.dot(&d).quad + self.function.eval(t).2;
    }
}
