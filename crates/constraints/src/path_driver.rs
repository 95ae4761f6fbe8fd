//! Path driver: the curve parameter u of a point-on-curve element prescribed in time,
//! Φ = u − f(t) (a tool point sent along its path; arc length for lines, circles and helices,
//! so f(t) = v t moves the point at constant speed v).
//!
//! ```text
//! Φ = u − f(t)      Φ_q = 0      Φ_u = 1      ν = ḟ(t)      γ# = f̈(t)
//! ```
//!
//! A driver of the extra coordinate alone (Haug 1989 §9.4: drivers on any generalized
//! coordinate); its bodies are those of its curve element, on which it does not depend.
//! Oracle: `gen_curves.py`, element `path_driver`.

use crate::constraint::{Constraint, Dimension, MAX_EXTRA};
use crate::jet::Form;
use crate::state::{BlockUse, BodyPair, Footprint};
use crate::time_function::TimeFunction;

/// u = f(t) for the curve parameter u of a point-on-curve element.
#[derive(Debug, Clone, PartialEq)]
pub struct PathDriver {
    /// f(t), in the curve parameter's unit (m).
    pub function: TimeFunction,
}

impl PathDriver {
    /// u = `function`(t).
    pub fn new(function: TimeFunction) -> Self {
        Self { function }
    }
}

impl Constraint for PathDriver {
    fn name(&self) -> &'static str {
        "path_driver"
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
        out[0] = x.u[0] - self.function.eval(t).0;
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

    fn jacobian_extra(&self, _x: &BodyPair, _t: f64, out: &mut [[f64; MAX_EXTRA]]) {
        out[0][0] = 1.0;
    }

    fn nu(&self, _x: &BodyPair, t: f64, out: &mut [f64]) {
        out[0] = self.function.eval(t).1;
    }

    fn gamma_sharp<const N: usize, F: Form<N>>(&self, _x: &BodyPair, t: f64, out: &mut [f64]) {
        out[0] = self.function.eval(t).2;
    }
}
