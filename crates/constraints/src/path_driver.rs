//! Path driver: the curve parameter u of a point-on-curve element prescribed in time,
//! Φ = u − f(t) (a tool point sent along its path; arc length for lines, circles and helices,
//! so f(t) = v t moves the point at constant speed v), or, along a spline, the arc length
//! travelled, Φ = S(u) − f(t) ([`ArcLength`]: f(t) = v t moves the point at speed v there too).
//!
//! ```text
//! Φ = u − f(t)      Φ_q = 0      Φ_u = 1      ν = ḟ(t)      γ# = f̈(t)
//! Φ = S(u) − f(t)   Φ_q = 0      Φ_u = S_u    ν = ḟ(t)      γ# = f̈(t) − S_uu u̇²
//! ```
//!
//! A driver of the extra coordinate alone (Haug 1989 §9.4: drivers on any generalized
//! coordinate); its bodies are those of its curve element, on which it does not depend.
//! Oracle: `gen_curves.py`, elements `path_driver`, `path_driver_arc_cubic` and
//! `path_driver_arc_cubic_closed`.

use crate::constraint::{Constraint, Dimension, MAX_EXTRA};
use crate::curves::{ArcLength, Curve};
use crate::jet::Form;
use crate::state::{BlockUse, BodyPair, Footprint};
use crate::time_function::TimeFunction;

/// u = f(t), or S(u) = f(t), for the curve parameter u of a point-on-curve element.
#[derive(Debug, Clone, PartialEq)]
pub struct PathDriver {
    /// f(t), in the curve parameter's unit (m).
    pub function: TimeFunction,
    /// The spline's arc length S(u) when the driver prescribes the distance travelled along a
    /// spline; `None`: u itself (the arc length of a line, a circle, a helix).
    pub arc: Option<ArcLength>,
}

impl PathDriver {
    /// u = `function`(t).
    pub fn new(function: TimeFunction) -> Self {
        Self {
            function,
            arc: None,
        }
    }

    /// The arc length along `curve` = `function`(t): S(u) for a spline, u for the curves whose
    /// parameter is their arc length.
    pub fn along_arc(function: TimeFunction, curve: &Curve) -> Self {
        let arc = match curve {
            Curve::Cubic(c) => Some(ArcLength::new(c)),
            _ => None,
        };
        Self { function, arc }
    }

    /// (S, S_u, S_uu) at u: the arc length, or u itself.
    fn s(&self, u: f64) -> (f64, f64, f64) {
        self.arc.as_ref().map_or((u, 1.0, 0.0), |a| a.eval(u))
    }
}

impl Constraint for PathDriver {
    fn name(&self) -> &'static str {
        match &self.arc {
            None => "path_driver",
            Some(a) if a.is_closed() => "path_driver_arc_cubic_closed",
            Some(_) => "path_driver_arc_cubic",
        }
    }

    fn rows(&self) -> usize {
        1
    }

    fn dimension(&self, _row: usize) -> Dimension {
        Dimension::Length
    }

    fn footprint(&self) -> Footprint {
        Footprint {
            i: BlockUse::NONE,
            j: BlockUse::NONE,
        }
    }

    fn extra(&self) -> usize {
        1
    }

    fn phi(&self, x: &BodyPair, t: f64, out: &mut [f64]) {
        out[0] = self.s(x.u[0]).0 - self.function.eval(t).0;
    }

    fn jacobian<const N: usize, F: Form<N>>(
        &self,
        _x: &BodyPair,
        _t: f64,
        out_i: &mut [[f64; N]],
        out_j: &mut [[f64; N]],
    ) {
        out_i[0] = [0.0; N];
        out_j[0] = [0.0; N];
    }

    fn jacobian_extra(&self, x: &BodyPair, _t: f64, out: &mut [[f64; MAX_EXTRA]]) {
        out[0][0] = self.s(x.u[0]).1;
    }

    fn nu(&self, _x: &BodyPair, t: f64, out: &mut [f64]) {
        out[0] = self.function.eval(t).1;
    }

    fn gamma_sharp<const N: usize, F: Form<N>>(&self, x: &BodyPair, t: f64, out: &mut [f64]) {
        out[0] = self.function.eval(t).2 - self.s(x.u[0]).2 * x.u_dot[0] * x.u_dot[0];
    }
}
