//! The continuous extension of a DOPRI5 step (Hairer, Nørsett & Wanner, *Solving ODEs I*,
//! §II.6, and their DOPRI5 code): for θ = (t − t₀)/h in [0, 1],
//!
//! ```text
//! y(t₀ + θh) = c₀ + θ (c₁ + (1 − θ) (c₂ + θ (c₃ + (1 − θ) c₄)))
//! c₀ = y₀,  c₁ = y₁ − y₀,  c₂ = h k₁ − c₁,  c₃ = c₁ − h k₇ − c₂,  c₄ = h Σ d_j k_j
//! ```
//!
//! 4th order, from the stages of the step alone. The work W ([`crate::work`]) has the same
//! extension with the stage powers in place of the k_j.

use super::buffers::{Stages, Values};
use super::tableau::{A, D};

/// The coefficients c₀..c₄ of the state and of the work for the last accepted step.
#[derive(Debug)]
pub(super) struct DenseOutput {
    cont: [Vec<f64>; 5],
    wcont: [Vec<f64>; 5],
}

impl DenseOutput {
    /// Zeros for states of `len` numbers and `channels` work channels.
    pub fn new(len: usize, channels: usize) -> Self {
        Self {
            cont: std::array::from_fn(|_| vec![0.0; len]),
            wcont: std::array::from_fn(|_| vec![0.0; channels]),
        }
    }

    /// The state's coefficients for the step of size `hs` from `v.y0` to `v.y1` (unprojected).
    /// No allocation.
    pub fn fill_state(&mut self, v: &Values, st: &Stages, hs: f64) {
        let (b, k) = (&mut self.cont, &st.k);
        for i in 0..v.y0.len() {
            let ydiff = v.y1[i] - v.y0[i];
            let bspl = hs * k[0][i] - ydiff;
            b[0][i] = v.y0[i];
            b[1][i] = ydiff;
            b[2][i] = bspl;
            b[3][i] = ydiff - hs * k[6][i] - bspl;
            let mut dd = 0.0;
            for j in 0..7 {
                dd += D[j] * k[j][i];
            }
            b[4][i] = hs * dd;
        }
    }

    /// The work at the end of the step of size `hs` (`v.w1`, the step's weights applied to the
    /// stage powers, as for the state) and its coefficients. No allocation.
    pub fn fill_work(&mut self, v: &mut Values, st: &Stages, hs: f64) {
        let (c, kw) = (&mut self.wcont, &st.kw);
        for i in 0..v.w0.len() {
            let mut acc = 0.0;
            for j in 0..6 {
                acc += A[6][j] * kw[j][i];
            }
            v.w1[i] = v.w0[i] + hs * acc;
            let wdiff = v.w1[i] - v.w0[i];
            let bspl = hs * kw[0][i] - wdiff;
            let mut dd = 0.0;
            for j in 0..7 {
                dd += D[j] * kw[j][i];
            }
            c[0][i] = v.w0[i];
            c[1][i] = wdiff;
            c[2][i] = bspl;
            c[3][i] = wdiff - hs * kw[6][i] - bspl;
            c[4][i] = hs * dd;
        }
    }

    /// The state and the work at θ into `v.yt` and `v.wt`. No allocation.
    pub fn eval(&self, th: f64, v: &mut Values) {
        let th1 = 1.0 - th;
        let b = &self.cont;
        for i in 0..v.yt.len() {
            v.yt[i] = b[0][i] + th * (b[1][i] + th1 * (b[2][i] + th * (b[3][i] + th1 * b[4][i])));
        }
        let c = &self.wcont;
        for i in 0..v.wt.len() {
            v.wt[i] = c[0][i] + th * (c[1][i] + th1 * (c[2][i] + th * (c[3][i] + th1 * c[4][i])));
        }
    }
}
