//! Coordinate driver: one global coordinate of a point of body i follows c(t).
//!
//! ```text
//! Φ  = e_kᵀ (r_i + A_i s'^P_i) − c(t)       k ∈ {0 (x), 1 (y), 2 (z)}
//! Φ_q = e_kᵀ [I, B_i]          ν = ċ(t)          γ# = −e_kᵀ B_i(ṗ_i) ṗ_i + c̈(t)
//! ```
//! Nikravesh 1988 §7.5 (absolute drivers). Body j is unused (ground).

use crate::constraint::{Constraint, Dimension};
use crate::error::ConstraintError;
use crate::jet::{Form, Grad, Motion, Side};
use crate::state::{BlockUse, BodyPair, Footprint};
use crate::time_function::TimeFunction;
use nalgebra::Vector3;

/// (r_i + A_i s'^P_i)\[axis\] = c(t).
#[derive(Debug, Clone, PartialEq)]
pub struct CoordinateDriver {
    /// s'^P_i (zero for the body reference point).
    pub point_i: Vector3<f64>,
    /// 0, 1 or 2 for x, y, z.
    pub axis: usize,
    /// c(t) in m.
    pub function: TimeFunction,
}

impl CoordinateDriver {
    /// Drives global coordinate `axis` (0, 1, 2) of the point s'^P_i of body i.
    pub fn new(
        point_i: Vector3<f64>,
        axis: usize,
        function: TimeFunction,
    ) -> Result<Self, ConstraintError> {
        if axis > 2 {
            return Err(ConstraintError::BadAxis(axis));
        }
        Ok(Self {
            point_i,
            axis,
            function,
        })
    }
}

impl Constraint for CoordinateDriver {
    fn dimension(&self, _row: usize) -> Dimension {
        Dimension::Length
    }
    fn name(&self) -> &'static str {
        "coordinate_driver"
    }
    fn rows(&self) -> usize {
        1
    }
    fn footprint(&self) -> Footprint {
        Footprint {
            i: BlockUse::RP,
            j: BlockUse::NONE,
        }
    }
    fn phi(&self, x: &BodyPair, t: f64, out: &mut [f64]) {
        out[0] = x.i.point(&self.point_i)[self.axis] - self.function.eval(t).0;
    }
    fn jacobian<const N: usize, F: Form<N>>(
        &self,
        x: &BodyPair,
        _t: f64,
        out_i: &mut [[f64; N]],
        out_j: &mut [[f64; N]],
    ) {
        let p = Grad::point::<F>(x.i, x.j, Side::I, &self.point_i);
        for c in 0..N {
            out_i[0][c] = p.di[(self.axis, c)];
            out_j[0][c] = 0.0;
        }
    }
    fn nu(&self, _x: &BodyPair, t: f64, out: &mut [f64]) {
        out[0] = self.function.eval(t).1;
    }
    fn gamma_sharp<const N: usize, F: Form<N>>(&self, x: &BodyPair, t: f64, out: &mut [f64]) {
        let p = Motion::point::<N, F>(x.i, x.j, Side::I, &self.point_i);
        out[0] = -p.quad[self.axis] + self.function.eval(t).2;
    }
}
