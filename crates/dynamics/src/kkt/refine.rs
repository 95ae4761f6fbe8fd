//! One step of iterative refinement of a Schur-complement solve against the full system.
//!
//! S = Φ_v A⁻¹ Φ_vᵀ squares the conditioning of Φ_v, so near a singular configuration (A02's
//! horizontal positions) a plain Schur solve is less accurate than the LU of K would be. With
//! K = [A Φ_vᵀ; Φ_v 0] the factored matrix (A block diagonal, Φ_v as it was at the
//! factorization: a modified Newton iteration solves with a matrix older than the current
//! Φ_v), one step r = b − K x, x += K⁻¹ r (Higham, *Accuracy and Stability of Numerical
//! Algorithms*, ch. 12) with the Schur factors recovers the digits S lost.

use super::layout::Group;
use cardan_solver::{SchurSolver, SolverError};

/// Scratch of the refinement (n + m_a each). No allocation after construction.
#[derive(Debug)]
pub(crate) struct Refinement {
    r: Vec<f64>,
    d: Vec<f64>,
}

/// The factored K: its diagonal blocks of A (column-major 6×6 per body) and its Φ_v by groups.
pub(crate) struct Factors<'a> {
    pub blocks: &'a [f64],
    pub groups: &'a [Group],
    pub jac: &'a [f64],
    pub schur: &'a mut SchurSolver,
}

impl Refinement {
    pub fn new(size: usize) -> Self {
        Self {
            r: vec![0.0; size],
            d: vec![0.0; size],
        }
    }

    /// Refines `sol` ≈ K⁻¹ `rhs` once.
    pub fn refine(
        &mut self,
        k: Factors<'_>,
        rhs: &[f64],
        sol: &mut [f64],
    ) -> Result<(), SolverError> {
        // 36 values per body, six unknowns per body.
        let n = k.blocks.len() / 6;
        let r = &mut self.r;
        r.copy_from_slice(rhs);
        let (xv, xl) = sol.split_at(n);
        for (b, a) in k.blocks.chunks_exact(36).enumerate() {
            let x = &xv[6 * b..6 * b + 6];
            for i in 0..6 {
                let mut s = 0.0;
                for j in 0..6 {
                    s += a[6 * j + i] * x[j];
                }
                r[6 * b + i] -= s;
            }
        }
        for (g, v) in k.groups.iter().zip(k.jac.chunks_exact(6)) {
            let l = xl[g.row];
            let mut s = 0.0;
            for c in 0..6 {
                r[g.col + c] -= v[c] * l;
                s += v[c] * xv[g.col + c];
            }
            r[n + g.row] -= s;
        }
        k.schur.solve(r, &mut self.d)?;
        for (x, dx) in sol.iter_mut().zip(&self.d) {
            *x += dx;
        }
        Ok(())
    }
}
