//! The Euler-parameter normalization constraint of one body (body i).
//!
//! ```text
//! Φ^(p) = p_iᵀ p_i − 1                                             1 row
//! Φ_q = [0, 2 p_iᵀ]         ν = 0         γ# = −2 ṗ_iᵀ ṗ_i         (7-coordinate form)
//! Φ_v = 0                   γ# = 0                                   (6-coordinate form)
//! ```
//! Nikravesh 1988 eq. 6.23, Haug 1989 eq. 9.1.x. In the 6-coordinate form the velocity is
//! v = [ṙ; ω'] and p is advanced on the unit sphere, so the row is identically satisfied to
//! first and second order: Φ_v = ½ Φ_p Lᵀ = (L p)ᵀ = 0. A mechanism in 6-coordinate form does not
//! include these rows; the zeros here state that fact for the conformance suite. Body j is unused.

use crate::constraint::{Constraint, Dimension};
use crate::jet::Form;
use crate::state::{BlockUse, BodyPair, Footprint};

/// p_iᵀ p_i − 1 = 0.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Normalization;

impl Constraint for Normalization {
    fn dimension(&self, _row: usize) -> Dimension {
        Dimension::Dimensionless
    }
    fn name(&self) -> &'static str {
        "normalization"
    }
    fn rows(&self) -> usize {
        1
    }
    fn footprint(&self) -> Footprint {
        Footprint {
            i: BlockUse::P,
            j: BlockUse::NONE,
        }
    }
    fn phi(&self, x: &BodyPair, _t: f64, out: &mut [f64]) {
        out[0] = x.i.p.norm_squared() - 1.0;
    }
    fn jacobian<const N: usize, F: Form<N>>(
        &self,
        x: &BodyPair,
        _t: f64,
        out_i: &mut [[f64; N]],
        out_j: &mut [[f64; N]],
    ) {
        out_i[0] = [0.0; N];
        out_j[0] = [0.0; N];
        if N == 7 {
            for k in 0..4 {
                out_i[0][3 + k] = 2.0 * x.i.p[k];
            }
        }
    }
    fn gamma_sharp<const N: usize, F: Form<N>>(&self, x: &BodyPair, _t: f64, out: &mut [f64]) {
        out[0] = if N == 7 {
            -2.0 * x.i.p_dot.norm_squared()
        } else {
            0.0
        };
    }
}
