//! Rotation driver: the angle θ of a revolute or cylindrical joint follows θ(t).
//!
//! With u = y_iᵀ x_j and w = x_iᵀ x_j (x_j at angle φ from x_i about z_i: u = sin φ, w = cos φ):
//!
//! ```text
//! Φ  = cos θ(t) · u − sin θ(t) · w = sin(φ − θ(t))
//! Φ_q = cos θ · u_q − sin θ · w_q
//! ν  = −Φ_t = θ̇ (sin θ · u + cos θ · w)
//! γ# = −[cos θ · ü − sin θ · ẅ − 2 θ̇ (sin θ · u̇ + cos θ · ẇ)
//!        − θ̇² (cos θ · u − sin θ · w) − θ̈ (sin θ · u + cos θ · w)]      (ü, ẅ velocity-quadratic)
//! ```
//!
//! θ(t) enters only through its sine and cosine, so the equation is valid over any number of
//! turns, and ∂Φ/∂φ = cos(φ − θ) = 1 on the solution branch: there is no loss of rank at ±90° or
//! ±180°, unlike drivers written as a single dot product or with atan. (The spurious root
//! φ = θ + π has ∂Φ/∂φ = −1 and is far from any Newton start predicted from the previous step.)
//! Nikravesh 1988 §7.5 (rotational driver), with the two-term form that avoids branch loss.

use crate::constraint::{Constraint, Dimension};
use crate::jet::{Form, Grad, Motion, Side};
use crate::marker::Marker;
use crate::state::{BlockUse, BodyPair, Footprint};
use crate::time_function::TimeFunction;

/// θ(t) for the joint between `marker_i` and `marker_j` (the markers of the driven joint).
#[derive(Debug, Clone, PartialEq)]
pub struct RotationDriver {
    /// Marker on body i (x_i, y_i, z_i).
    pub marker_i: Marker,
    /// Marker on body j (x_j).
    pub marker_j: Marker,
    /// θ(t) in rad.
    pub function: TimeFunction,
}

impl RotationDriver {
    /// θ(t) between the two markers.
    pub fn new(marker_i: Marker, marker_j: Marker, function: TimeFunction) -> Self {
        Self {
            marker_i,
            marker_j,
            function,
        }
    }
}

impl Constraint for RotationDriver {
    fn dimension(&self, _row: usize) -> Dimension {
        Dimension::Dimensionless
    }
    fn rows(&self) -> usize {
        1
    }

    fn name(&self) -> &'static str {
        "rotation_driver"
    }

    fn footprint(&self) -> Footprint {
        Footprint {
            i: BlockUse::P,
            j: BlockUse::P,
        }
    }

    fn phi(&self, x: &BodyPair, t: f64, out: &mut [f64]) {
        let (th, _, _) = self.function.eval(t);
        let xj = x.j.vector(&self.marker_j.x());
        let u = x.i.vector(&self.marker_i.y()).dot(&xj);
        let w = x.i.vector(&self.marker_i.x()).dot(&xj);
        out[0] = th.cos() * u - th.sin() * w;
    }

    fn jacobian<const N: usize, F: Form<N>>(
        &self,
        x: &BodyPair,
        t: f64,
        out_i: &mut [[f64; N]],
        out_j: &mut [[f64; N]],
    ) {
        let (th, _, _) = self.function.eval(t);
        let xj = Grad::dir::<F>(x.i, x.j, Side::J, &self.marker_j.x());
        let u = Grad::dir::<F>(x.i, x.j, Side::I, &self.marker_i.y()).dot(&xj);
        let w = Grad::dir::<F>(x.i, x.j, Side::I, &self.marker_i.x()).dot(&xj);
        let (s, c) = th.sin_cos();
        let g = crate::jet::ScalarGrad {
            v: c * u.v - s * w.v,
            di: u.di * c - w.di * s,
            dj: u.dj * c - w.dj * s,
        };
        g.write(&mut out_i[0], &mut out_j[0]);
    }

    fn nu(&self, x: &BodyPair, t: f64, out: &mut [f64]) {
        let (th, dth, _) = self.function.eval(t);
        let xj = x.j.vector(&self.marker_j.x());
        let u = x.i.vector(&self.marker_i.y()).dot(&xj);
        let w = x.i.vector(&self.marker_i.x()).dot(&xj);
        let (s, c) = th.sin_cos();
        out[0] = dth * (s * u + c * w);
    }

    fn gamma_sharp<const N: usize, F: Form<N>>(&self, x: &BodyPair, t: f64, out: &mut [f64]) {
        let (th, dth, ddth) = self.function.eval(t);
        let xj = Motion::dir::<N, F>(x.i, x.j, Side::J, &self.marker_j.x());
        let u = Motion::dir::<N, F>(x.i, x.j, Side::I, &self.marker_i.y()).dot(&xj);
        let w = Motion::dir::<N, F>(x.i, x.j, Side::I, &self.marker_i.x()).dot(&xj);
        let (s, c) = th.sin_cos();
        let phi_ddot = c * u.quad
            - s * w.quad
            - 2.0 * dth * (s * u.rate + c * w.rate)
            - dth * dth * (c * u.v - s * w.v)
            - ddth * (s * u.v + c * w.v);
        out[0] = -phi_ddot;
    }
}
