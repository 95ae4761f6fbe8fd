//! The top-left block A of the KKT matrix: the mass matrix M = diag(m_k I, J'_k) per body, or
//! the implicit method's iteration matrix M + γ' C_t + β' K_t.
//!
//! A mass-only A lives in its 36 nb diagonal-block values alone (column-major 6×6 per body),
//! which is all the Schur path reads; the slots of the full matrix are brought up to them only
//! when the LU path needs them. Tangent terms are added in the slots (they may have coupling
//! blocks between bodies); the Schur path then takes A only when it is still block diagonal
//! and symmetric, copying the diagonal blocks back from the slots.

use super::layout::Layout;
use nalgebra::Matrix3;

/// The values of A and where they are current.
#[derive(Debug)]
pub(crate) struct TopLeft {
    /// Diagonal blocks of A, column-major 6×6 per body (36 nb).
    blocks: Vec<f64>,
    /// The slots are behind `blocks` (`set_mass` wrote only `blocks`).
    stale: bool,
    /// Tangent terms were added since the last `set_mass` (A is in the slots).
    tangent: bool,
}

impl TopLeft {
    pub fn new(nb: usize) -> Self {
        Self {
            blocks: vec![0.0; 36 * nb],
            stale: false,
            tangent: false,
        }
    }

    /// The diagonal blocks (current for a mass-only A, or after [`Self::schur_blocks`]).
    pub fn blocks(&self) -> &[f64] {
        &self.blocks
    }

    /// A has tangent terms.
    pub fn tangent(&self) -> bool {
        self.tangent
    }

    /// Sets A = M = diag(m I, J') per body (coupling blocks zero). Returns whether A changed:
    /// tangent terms were there, or other masses.
    pub fn set_mass(&mut self, mass: &[f64], inertia: &[Matrix3<f64>]) -> bool {
        let mut changed = self.tangent;
        for (k, blk) in self.blocks.chunks_exact_mut(36).enumerate() {
            for c in 0..6 {
                for r in 0..6 {
                    let v = match (r < 3, c < 3) {
                        (true, true) if r == c => mass[k],
                        (false, false) => inertia[k][(r - 3, c - 3)],
                        _ => 0.0,
                    };
                    let i = 6 * c + r;
                    changed |= blk[i].to_bits() != v.to_bits();
                    blk[i] = v;
                }
            }
        }
        self.stale = true;
        self.tangent = false;
        changed
    }

    /// Adds `f(row, col)` to the entries of A in `slots` (tangent terms).
    pub fn add(
        &mut self,
        layout: &Layout,
        slots: &mut [f64],
        mut f: impl FnMut(usize, usize) -> f64,
    ) {
        self.write(layout, slots);
        for &(r, c, s) in &layout.top {
            slots[s] += f(r, c);
        }
        self.tangent = true;
    }

    /// Brings the slots of A up to `blocks` (coupling blocks zero) after a `set_mass`.
    pub fn write(&mut self, layout: &Layout, slots: &mut [f64]) {
        if !self.stale {
            return;
        }
        for (&s, &v) in layout.block_slots.iter().zip(&self.blocks) {
            slots[s] = v;
        }
        for &(_, _, s) in &layout.top[self.blocks.len()..] {
            slots[s] = 0.0;
        }
        self.stale = false;
    }

    /// Whether A is block diagonal and symmetric, so that the Schur complement applies: mass
    /// only, or tangent terms on a layout without coupling blocks whose diagonal blocks are
    /// symmetric (then copied from the slots into `blocks`).
    pub fn schur_blocks(&mut self, layout: &Layout, slots: &[f64]) -> bool {
        if !self.tangent {
            return true;
        }
        if layout.coupled {
            return false;
        }
        for (v, &s) in self.blocks.iter_mut().zip(&layout.block_slots) {
            *v = slots[s];
        }
        self.blocks.chunks_exact(36).all(|b| {
            let size = b.iter().fold(0.0f64, |m, v| m.max(v.abs()));
            (0..6).all(|c| (0..c).all(|r| (b[6 * c + r] - b[6 * r + c]).abs() <= 1e-14 * size))
        })
    }
}
