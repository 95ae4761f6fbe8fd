//! radial distance (cylinder–sphere): a point of body j at a constant distance ℓ from a line of
//! body i.
//!
//! ```text
//! d = r^P_j − r^P_i,   u = f_iᵀ d,   w = g_iᵀ d        (f'_i, g'_i ⟂ the line's direction s'_i)
//! Φ = u² + w² − ℓ²                                                 1 row
//! Φ_q = 2 u ∂u/∂q + 2 w ∂w/∂q                (∂u/∂q, ∂w/∂q those of n2, Nikravesh 1988 eq. 7.16)
//! γ#  = −(2 u̇² + 2 u ü + 2 ẇ² + 2 w ẅ)                (ü, ẅ the velocity-quadratic parts)
//! ```
//! The line passes through P_i along s_i; u and w are the components of d across the line, so
//! √(u² + w²) is the distance of P_j from it (OndselSolver's `DistancexyConstraintIJ`). As for
//! [`crate::Distance`], the squared form has no square root but its Jacobian vanishes on the
//! line: ℓ must be positive, checked by the joint. Haug 1989 §9.2 builds the same from two n2
//! rows. Footprint: r and p of both bodies.

use crate::constraint::{Constraint, Dimension};
use crate::jet::{Form, Grad, Motion, Side};
use crate::state::{BlockUse, BodyPair, Footprint};
use nalgebra::Vector3;

/// (f_iᵀ d)² + (g_iᵀ d)² − ℓ² = 0.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RadialDistance {
    /// f'_i ⟂ the line, body-i components.
    pub f_i: Vector3<f64>,
    /// g'_i ⟂ the line and f'_i, body-i components.
    pub g_i: Vector3<f64>,
    /// s'^P_i, a point of the line.
    pub sp_i: Vector3<f64>,
    /// s'^P_j.
    pub sp_j: Vector3<f64>,
    /// ℓ.
    pub length: f64,
}

impl RadialDistance {
    /// P_j at distance `length` from the line through P_i across which f'_i and g'_i point.
    pub fn new(
        f_i: Vector3<f64>,
        g_i: Vector3<f64>,
        sp_i: Vector3<f64>,
        sp_j: Vector3<f64>,
        length: f64,
    ) -> Self {
        Self {
            f_i,
            g_i,
            sp_i,
            sp_j,
            length,
        }
    }
}

impl Constraint for RadialDistance {
    fn dimension(&self, _row: usize) -> Dimension {
        Dimension::Area
    }
    fn name(&self) -> &'static str {
        "radial_distance"
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
        let (u, w) = (x.i.vector(&self.f_i).dot(&d), x.i.vector(&self.g_i).dot(&d));
        out[0] = u * u + w * w - self.length * self.length;
    }
    fn jacobian<const N: usize, F: Form<N>>(
        &self,
        x: &BodyPair,
        _t: f64,
        out_i: &mut [[f64; N]],
        out_j: &mut [[f64; N]],
    ) {
        let d = Grad::between::<F>(x.i, x.j, &self.sp_i, &self.sp_j);
        let u = Grad::dir::<F>(x.i, x.j, Side::I, &self.f_i).dot(&d);
        let w = Grad::dir::<F>(x.i, x.j, Side::I, &self.g_i).dot(&d);
        u.square()
            .add(&w.square())
            .write(&mut out_i[0], &mut out_j[0]);
    }
    fn gamma_sharp<const N: usize, F: Form<N>>(&self, x: &BodyPair, _t: f64, out: &mut [f64]) {
        let d = Motion::between::<N, F>(x.i, x.j, &self.sp_i, &self.sp_j);
        let u = Motion::dir::<N, F>(x.i, x.j, Side::I, &self.f_i).dot(&d);
        let w = Motion::dir::<N, F>(x.i, x.j, Side::I, &self.g_i).dot(&d);
        out[0] = -u.square().add(&w.square()).quad;
    }
}
