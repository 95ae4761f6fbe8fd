//! Point on a curve: a point P of body j stays on a curve c'(u) fixed in body i, the curve
//! parameter u an extra coordinate of the mechanism (Haug 1989 §9.4.1, the point-follower
//! joint; a pin in a curved slot, a roller on a track, a tool tip on a path).
//!
//! ```text
//! Φ    = r_j + A_j s'^P_j − r_i − A_i c'(u)                       (3 rows, length)
//! Φ_q  = [−I, −∂(A_i c')/∂p_i, I, ∂(A_j s'^P)/∂p_j]   (the spherical joint's blocks at c'(u))
//! Φ_u  = −A_i c'_u
//! γ#   = −(A_j s'^P)¨_quad + (A_i c')¨_quad + 2 (A_i c'_u)˙ u̇ + A_i c'_uu u̇²
//! ```
//!
//! (·)¨_quad is the velocity-quadratic part of a body-fixed vector's acceleration (`jet`), and
//! (A_i c'_u)˙ the rate of the tangent held fixed in body i: γ# is minus everything in Φ̈ but
//! Φ_q q̈ + Φ_u ü, from (A_i c'(u))¨ = Ä_i c' + 2 Ȧ_i c'_u u̇ + A_i c'_uu u̇² + A_i c'_u ü.
//! Rows 3, three equations for four coordinates (u included): the point keeps one relative
//! translational DOF along the curve, its rotations are free. Oracle: `gen_curves.py`.

use crate::constraint::{Constraint, Dimension, MAX_EXTRA};
use crate::curves::Curve;
use crate::jet::{write_rows, Form, Grad, Motion, Side};
use crate::state::{BlockUse, BodyPair, Footprint};
use nalgebra::Vector3;

/// A point of body j on a curve of body i.
#[derive(Debug, Clone, PartialEq)]
pub struct PointOnCurve {
    /// The curve, in body i's coordinates.
    pub curve: Curve,
    /// s'^P_j, the point in body j's coordinates.
    pub sp_j: Vector3<f64>,
}

impl PointOnCurve {
    /// The point `sp_j` of body j on `curve` of body i.
    pub fn new(curve: Curve, sp_j: Vector3<f64>) -> Self {
        Self { curve, sp_j }
    }
}

impl Constraint for PointOnCurve {
    fn name(&self) -> &'static str {
        match &self.curve {
            Curve::Line(_) => "point_on_curve_line",
            Curve::Circle(_) => "point_on_curve_circle",
            Curve::Helix(_) => "point_on_curve_helix",
            Curve::Cubic(c) => match (c.degree(), c.is_closed()) {
                (5, true) => "point_on_curve_quintic_closed",
                (5, false) => "point_on_curve_quintic",
                (_, true) => "point_on_curve_cubic_closed",
                (_, false) => "point_on_curve_cubic",
            },
        }
    }

    fn rows(&self) -> usize {
        3
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

    fn extra(&self) -> usize {
        1
    }

    fn phi(&self, x: &BodyPair, _t: f64, out: &mut [f64]) {
        let c = self.curve.jet(x.u[0]).c;
        let d = x.j.point(&self.sp_j) - x.i.point(&c);
        out.copy_from_slice(d.as_slice());
    }

    fn jacobian<const N: usize, F: Form<N>>(
        &self,
        x: &BodyPair,
        _t: f64,
        out_i: &mut [[f64; N]],
        out_j: &mut [[f64; N]],
    ) {
        let c = self.curve.jet(x.u[0]).c;
        write_rows(&Grad::between::<F>(x.i, x.j, &c, &self.sp_j), out_i, out_j);
    }

    fn jacobian_extra(&self, x: &BodyPair, _t: f64, out: &mut [[f64; MAX_EXTRA]]) {
        let tangent = x.i.vector(&self.curve.jet(x.u[0]).c_u);
        for (r, row) in out.iter_mut().enumerate().take(3) {
            row[0] = -tangent[r];
        }
    }

    fn gamma_sharp<const N: usize, F: Form<N>>(&self, x: &BodyPair, _t: f64, out: &mut [f64]) {
        let jet = self.curve.jet(x.u[0]);
        let u_dot = x.u_dot[0];
        let quad = Motion::between::<N, F>(x.i, x.j, &jet.c, &self.sp_j).quad;
        let tangent_rate = Motion::dir::<N, F>(x.i, x.j, Side::I, &jet.c_u).rate;
        let g = -quad + tangent_rate * (2.0 * u_dot) + x.i.vector(&jet.c_uu) * (u_dot * u_dot);
        out.copy_from_slice(g.as_slice());
    }
}
