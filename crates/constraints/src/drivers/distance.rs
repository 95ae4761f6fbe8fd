//! Distance driver: two points at a prescribed distance ℓ(t).
//!
//! ```text
//! d  = r^P_j − r^P_i
//! Φ  = dᵀd − ℓ(t)²
//! ν  = 2 ℓ ℓ̇
//! γ# = −(2 ḋᵀḋ + 2 dᵀd̈) + 2 (ℓ̇² + ℓ ℓ̈)
//! ```
//! Nikravesh 1988 §7.5; the squared form of [`crate::Distance`] with a time-dependent length.

use crate::constraint::{Constraint, Dimension};
use crate::jet::{Form, Grad, Motion};
use crate::state::{BlockUse, BodyPair, Footprint};
use crate::time_function::TimeFunction;
use nalgebra::Vector3;

/// |P_j − P_i| = ℓ(t).
#[derive(Debug, Clone, PartialEq)]
pub struct DistanceDriver {
    /// s'^P_i.
    pub point_i: Vector3<f64>,
    /// s'^P_j.
    pub point_j: Vector3<f64>,
    /// ℓ(t) in m.
    pub function: TimeFunction,
}

impl DistanceDriver {
    /// ℓ(t) between the two points.
    pub fn new(point_i: Vector3<f64>, point_j: Vector3<f64>, function: TimeFunction) -> Self {
        Self {
            point_i,
            point_j,
            function,
        }
    }
}

impl Constraint for DistanceDriver {
    fn dimension(&self, _row: usize) -> Dimension {
        Dimension::Area
    }
    fn name(&self) -> &'static str {
        "distance_driver"
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
        let d = x.j.point(&self.point_j) - x.i.point(&self.point_i);
        let l = self.function.eval(t).0;
        out[0] = d.norm_squared() - l * l;
    }
    fn jacobian<const N: usize, F: Form<N>>(
        &self,
        x: &BodyPair,
        _t: f64,
        out_i: &mut [[f64; N]],
        out_j: &mut [[f64; N]],
    ) {
        let d = Grad::between::<F>(x.i, x.j, &self.point_i, &self.point_j);
        d.dot(&d).write(&mut out_i[0], &mut out_j[0]);
    }
    fn nu(&self, _x: &BodyPair, t: f64, out: &mut [f64]) {
        let (l, dl, _) = self.function.eval(t);
        out[0] = 2.0 * l * dl;
    }
    fn gamma_sharp<const N: usize, F: Form<N>>(&self, x: &BodyPair, t: f64, out: &mut [f64]) {
        let d = Motion::between::<N, F>(x.i, x.j, &self.point_i, &self.point_j);
        let (l, dl, ddl) = self.function.eval(t);
        out[0] = -d.dot(&d).quad + 2.0 * (dl * dl + l * ddl);
    }
}
