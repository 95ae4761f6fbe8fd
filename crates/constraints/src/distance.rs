//! distance (ss, spherical-spherical): two points at a constant distance ℓ.
//!
//! ```text
//! d = r^P_j − r^P_i
//! Φ = dᵀ d − ℓ²                                                    1 row
//! Φ_q = 2 dᵀ [−I, −B_i, I, B_j]
//! γ#  = −(2 ḋᵀ ḋ + 2 dᵀ d̈)         (d̈ the velocity-quadratic part)
//! ```
//! Nikravesh 1988 §7.3 (eq. 7.29), Haug 1989 §9.2 (SS). The squared form has no square root
//! (smooth at d = 0) but its Jacobian vanishes there: ℓ must be positive, checked by the joint.

use crate::constraint::{Constraint, Dimension};
use crate::jet::{Form, Grad, Motion};
use crate::state::{BlockUse, BodyPair, Footprint};
use nalgebra::Vector3;

/// dᵀd − ℓ² = 0.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Distance {
    /// s'^P_i.
    pub sp_i: Vector3<f64>,
    /// s'^P_j.
    pub sp_j: Vector3<f64>,
    /// ℓ.
    pub length: f64,
}

impl Distance {
    /// Points s'^P_i and s'^P_j kept `length` apart.
    pub fn new(sp_i: Vector3<f64>, sp_j: Vector3<f64>, length: f64) -> Self {
        Self { sp_i, sp_j, length }
    }
}

impl Constraint for Distance {
    fn dimension(&self, _row: usize) -> Dimension {
        Dimension::Area
    }
    fn name(&self) -> &'static str {
        "distance"
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
    fn phi(&self, x: &BodyPair, _t: f64, out: &mut [f64]) {
        let d = x.j.point(&self.sp_j) - x.i.point(&self.sp_i);
        out[0] = d.norm_squared() - self.length * self.length;
    }
    fn jacobian<const N: usize, F: Form<N>>(
        &self,
        x: &BodyPair,
        _t: f64,
        out_i: &mut [[f64; N]],
        out_j: &mut [[f64; N]],
    ) {
        let d = Grad::between::<F>(x.i, x.j, &self.sp_i, &self.sp_j);
        d.dot(&d).write(&mut out_i[0], &mut out_j[0]);
    }
    fn gamma_sharp<const N: usize, F: Form<N>>(&self, x: &BodyPair, _t: f64, out: &mut [f64]) {
        let d = Motion::between::<N, F>(x.i, x.j, &self.sp_i, &self.sp_j);
        out[0] = -d.dot(&d).quad;
    }
}
