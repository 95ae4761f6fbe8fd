//! Point on a surface: a point P of body j stays on a surface S'(u, v) fixed in body i, the
//! surface parameters u and v two extra coordinates of the mechanism (Haug 1989 §9.4, the
//! point-follower with a surface in place of the curve; a ball on a dish, a stylus on a
//! sculptured surface, a bead on a torus).
//!
//! ```text
//! Φ    = r_j + A_j s'^P_j − r_i − A_i S'(u, v)                        (3 rows, length)
//! Φ_q  = [−I, −∂(A_i S')/∂p_i, I, ∂(A_j s'^P)/∂p_j]    (the spherical joint's blocks at S')
//! Φ_u  = −A_i S'_u,   Φ_v = −A_i S'_v
//! γ#   = −(A_j s'^P)¨_quad + (A_i S')¨_quad + 2 (A_i S'_u)˙ u̇ + 2 (A_i S'_v)˙ v̇
//!        + A_i (S'_uu u̇² + 2 S'_uv u̇ v̇ + S'_vv v̇²)
//! ```
//!
//! as [`crate::PointOnCurve`]'s with two parameters: γ# is minus everything in Φ̈ but
//! Φ_q q̈ + Φ_u ü + Φ_v v̈. Three equations for five coordinates (u, v included): the point keeps
//! two relative translational DOF on the surface, its rotations are free. Oracle:
//! `gen_surfaces.py`.

use crate::constraint::{Constraint, Dimension, MAX_EXTRA};
use crate::jet::{write_rows, Form, Grad, Motion, Side};
use crate::state::{BlockUse, BodyPair, Footprint};
use crate::surfaces::Surface;
use nalgebra::Vector3;

/// A point of body j on a surface of body i.
#[derive(Debug, Clone, PartialEq)]
pub struct PointOnSurface {
    /// The surface, in body i's coordinates.
    pub surface: Surface,
    /// s'^P_j, the point in body j's coordinates.
    pub sp_j: Vector3<f64>,
}

impl PointOnSurface {
    /// The point `sp_j` of body j on `surface` of body i.
    pub fn new(surface: Surface, sp_j: Vector3<f64>) -> Self {
        Self { surface, sp_j }
    }
}

impl Constraint for PointOnSurface {
    fn name(&self) -> &'static str {
        match &self.surface {
            Surface::Plane(_) => "point_on_surface_plane",
            Surface::Sphere(_) => "point_on_surface_sphere",
            Surface::Cylinder(_) => "point_on_surface_cylinder",
            Surface::Torus(_) => "point_on_surface_torus",
            Surface::Bicubic(_) => "point_on_surface_bicubic",
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
        2
    }

    fn phi(&self, x: &BodyPair, _t: f64, out: &mut [f64]) {
        let s = self.surface.jet(x.u[0], x.u[1]).s;
        let d = x.j.point(&self.sp_j) - x.i.point(&s);
        out.copy_from_slice(d.as_slice());
    }

    fn jacobian<const N: usize, F: Form<N>>(
        &self,
        x: &BodyPair,
        _t: f64,
        out_i: &mut [[f64; N]],
        out_j: &mut [[f64; N]],
    ) {
        let s = self.surface.jet(x.u[0], x.u[1]).s;
        write_rows(&Grad::between::<F>(x.i, x.j, &s, &self.sp_j), out_i, out_j);
    }

    fn jacobian_extra(&self, x: &BodyPair, _t: f64, out: &mut [[f64; MAX_EXTRA]]) {
        let j = self.surface.jet(x.u[0], x.u[1]);
        let (su, sv) = (x.i.vector(&j.s_u), x.i.vector(&j.s_v));
        for (r, row) in out.iter_mut().enumerate().take(3) {
            row[0] = -su[r];
            row[1] = -sv[r];
        }
    }

    fn gamma_sharp<const N: usize, F: Form<N>>(&self, x: &BodyPair, _t: f64, out: &mut [f64]) {
        let j = self.surface.jet(x.u[0], x.u[1]);
        let (ud, vd) = (x.u_dot[0], x.u_dot[1]);
        let quad = Motion::between::<N, F>(x.i, x.j, &j.s, &self.sp_j).quad;
        let rate_u = Motion::dir::<N, F>(x.i, x.j, Side::I, &j.s_u).rate;
        let rate_v = Motion::dir::<N, F>(x.i, x.j, Side::I, &j.s_v).rate;
        let second = j.s_uu * (ud * ud) + j.s_uv * (2.0 * ud * vd) + j.s_vv * (vd * vd);
        let g = -quad + rate_u * (2.0 * ud) + rate_v * (2.0 * vd) + x.i.vector(&second);
        out.copy_from_slice(g.as_slice());
    }
}
