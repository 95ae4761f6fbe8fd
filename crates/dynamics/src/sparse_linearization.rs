//! The linearized equations of the sparse path (large models): the full matrices M, C_t, K_t
//! and Φ_v as sparse triplets ([`Dynamics::linearization_matrices`]), and, for models of
//! moderate size, the reduced [`Linearization`] in independent coordinates
//! ([`Dynamics::linearize_sparse`]) from which the state-space model is formed.
//!
//! ## Theory
//! About an equilibrium the linearized equations in the body increments δ (6 per body) are
//! (see [`crate::modal`])
//!
//! ```text
//! M δv̇ + C_t δv + K_t δ + Φ_vᵀ δλ = 0,      Φ_v δ = 0
//! ```
//!
//! M is block diagonal, K_t and C_t have a 6×6 block per coupled pair of bodies
//! ([`crate::sparse_tangent`]) and Φ_v a row per independent constraint equation: all four are
//! sparse, O(n) entries, and are what a user of a large model can take to another tool.
//!
//! The reduced form M_r z̈ + C_r ż + K_r z = 0 needs a basis N of the null space of Φ_v, dense
//! (n × d). The dense path takes it from an SVD of Φ_v (O(n³)); here it comes from the sparse
//! factorization of the saddle-point matrix [M Φ_vᵀ; Φ_v 0], as in the modal analysis: the
//! solution x of
//!
//! ```text
//! ⎡M  Φ_vᵀ⎤ ⎡x⎤   ⎡M y⎤
//! ⎣Φ_v  0 ⎦ ⎣μ⎦ = ⎣ 0 ⎦
//! ```
//!
//! is the M-orthogonal projection of y onto the null space. The projections Y of d
//! pseudo-random vectors span it (with probability one); two Cholesky orthonormalizations in
//! the M inner product (Cholesky QR twice: G = YᵀMY = LLᵀ, Y ← Y L⁻ᵀ, repeated; Fukaya et al.
//! 2014) make N M-orthonormal, NᵀMN = I to round-off, so M_r = I. One factorization, d solves
//! and O(n d²) dense work: moderate d only (the state-space matrices are dense 2d × 2d anyway).
//! N is a different basis from the dense path's (any basis gives the same frequencies and the
//! same input–output behaviour of the state-space model).

use crate::modal::Linearization;
use crate::sparse_tangent::SparseMatrix;
use crate::state::State;
use crate::statics::Equilibrium;
use crate::system::Dynamics;
use crate::DynamicsError;
use nalgebra::DMatrix;

/// The sparse path writes the reduced matrices and the state-space model only up to this many
/// independent coordinates d (the state-space matrices are dense, 2d × 2d: 10⁶ entries at
/// d = 500, tens of megabytes of text).
pub const SPARSE_LINEARIZATION_MAX_DOF: usize = 500;

/// … and up to this many unknowns n = 6 nb (the basis N is dense n × d, the full K_t and C_t
/// of [`Linearization`] dense n × n).
pub const SPARSE_LINEARIZATION_MAX_UNKNOWNS: usize = 3000;

/// A sparse rectangular matrix as (row, column, value) triplets (no duplicates).
#[derive(Debug, Clone, PartialEq, Default)]
pub struct SparseTriplets {
    /// Rows.
    pub rows: usize,
    /// Columns.
    pub cols: usize,
    /// The entries.
    pub entries: Vec<(usize, usize, f64)>,
}

/// The full linearized matrices about an equilibrium (module docs).
#[derive(Debug, Clone, PartialEq)]
pub struct LinearizationMatrices {
    /// M (n × n, block diagonal: m I and the body-frame inertia J' per body).
    pub mass: SparseMatrix,
    /// Φ_v on the independent constraint rows (m_a × n).
    pub jacobian: SparseTriplets,
}

impl Dynamics<'_> {
    /// M and Φ_v (independent rows) at `state` (module docs); K_t and C_t come with the
    /// analysis ([`crate::SparseModalResults`], or [`Linearization`] on the dense path).
    ///
    /// # Errors
    /// As [`Dynamics::statics`] when the model's rows cannot be prepared at `state`.
    pub fn linearization_matrices(
        &mut self,
        state: &State,
    ) -> Result<LinearizationMatrices, DynamicsError> {
        let active = self.prepared_rows(state)?;
        self.sync(state);
        let n = state.v.len();
        let mut entries = Vec::with_capacity(12 * self.mass.len());
        for (k, (&m, j)) in self.mass.iter().zip(&self.inertia).enumerate() {
            for a in 0..3 {
                entries.push((6 * k + a, 6 * k + a, m));
            }
            for c in 0..3 {
                for r in 0..3 {
                    if j[(r, c)] != 0.0 {
                        entries.push((6 * k + 3 + r, 6 * k + 3 + c, j[(r, c)]));
                    }
                }
            }
        }
        let jac = self
            .phi_v_triplets(state.t, &active)
            .into_iter()
            .filter(|e| e.2 != 0.0)
            .collect();
        Ok(LinearizationMatrices {
            mass: SparseMatrix { n, entries },
            jacobian: SparseTriplets {
                rows: active.len(),
                cols: n,
                entries: jac,
            },
        })
    }

    /// The independent constraint rows at `state` (preparing them first if needed).
    fn prepared_rows(&mut self, state: &State) -> Result<Vec<usize>, DynamicsError> {
        if self.kkt.is_none() {
            self.prepare(state)?;
        }
        Ok(self
            .kkt
            .as_ref()
            .map(|k| k.active.clone())
            .unwrap_or_default())
    }

    /// The linearized equations about `eq` in independent coordinates from the sparse tangents
    /// `stiffness` (K_t) and `damping` (C_t) of the sparse path, with an M-orthonormal basis N
    /// (module docs): M_r = I, C_r = NᵀC_tN, K_r = NᵀK_tN. Cost O(n d²) and dense n × n copies
    /// of K_t and C_t: for moderate sizes ([`SPARSE_LINEARIZATION_MAX_DOF`],
    /// [`SPARSE_LINEARIZATION_MAX_UNKNOWNS`]).
    ///
    /// # Errors
    /// Solver errors when the saddle-point matrix is singular; [`DynamicsError::NonFinite`]
    /// when the projections do not span the null space (a numerically singular configuration).
    pub fn linearize_sparse(
        &mut self,
        eq: &Equilibrium,
        stiffness: &SparseMatrix,
        damping: &SparseMatrix,
    ) -> Result<Linearization, DynamicsError> {
        let state = &eq.state;
        self.refuse_curves()?;
        let active = self.prepared_rows(state)?;
        let basis = self.null_space_sparse(state, &active)?;
        let d = basis.ncols();
        let apply = |f: &dyn Fn(&[f64]) -> Vec<f64>| {
            let mut out = DMatrix::zeros(basis.nrows(), d);
            for c in 0..d {
                let y = f(basis.column(c).as_slice());
                out.column_mut(c).copy_from_slice(&y);
            }
            out
        };
        let bt = basis.transpose();
        let mass = &bt * apply(&|x| self.mass_mul(x));
        let k = &bt * apply(&|x| stiffness.mul(x));
        let c = &bt * apply(&|x| damping.mul(x));
        if k.iter().chain(c.iter()).any(|v| !v.is_finite()) {
            return Err(DynamicsError::NonFinite {
                time: state.t,
                what: "the tangent stiffness or damping",
            });
        }
        Ok(Linearization {
            transport: DMatrix::zeros(d, d),
            mass,
            damping: c,
            stiffness: k,
            basis,
            full_stiffness: stiffness.to_dense(),
            full_damping: damping.to_dense(),
        })
    }

    /// An M-orthonormal basis of the null space of Φ_v (rows `active`) at `state` by projected
    /// pseudo-random vectors and Cholesky QR twice (module docs).
    fn null_space_sparse(
        &mut self,
        state: &State,
        active: &[usize],
    ) -> Result<DMatrix<f64>, DynamicsError> {
        self.sync(state);
        let n = state.v.len();
        let d = n.saturating_sub(active.len());
        let jac = self.phi_v_triplets(state.t, active);
        let mut kkt = crate::sparse_modal::SparseKkt::new(
            &SparseMatrix::default(),
            &self.mass,
            &self.inertia,
            &jac,
            active.len(),
        )
        .map_err(|e| self.solver_error(state.t, e))?;
        kkt.factor(0.0, 1.0)
            .map_err(|e| self.solver_error(state.t, e))?;
        let zero = vec![0.0; active.len()];
        let mut seed: u64 = 0x9e37_79b9_7f4a_7c15;
        let mut y = DMatrix::zeros(n, d);
        for c in 0..d {
            let r: Vec<f64> = (0..n).map(|_| uniform(&mut seed)).collect();
            let x = kkt
                .solve(&self.mass_mul(&r), &zero)
                .map_err(|e| self.solver_error(state.t, e))?;
            y.column_mut(c).copy_from_slice(&x[..n]);
        }
        let t = state.t;
        let singular = || DynamicsError::NonFinite {
            time: t,
            what: "the null-space basis of the constraint Jacobian",
        };
        for _ in 0..2 {
            let mut my = DMatrix::zeros(n, d);
            for c in 0..d {
                let v = self.mass_mul(y.column(c).as_slice());
                my.column_mut(c).copy_from_slice(&v);
            }
            let g = y.transpose() * my;
            let l = g.cholesky().ok_or_else(singular)?.l();
            // Y ← Y L⁻ᵀ: solve L Yᵀ_new = Yᵀ.
            let yt = l
                .solve_lower_triangular(&y.transpose())
                .ok_or_else(singular)?;
            y = yt.transpose();
        }
        if y.iter().any(|v| !v.is_finite()) {
            return Err(singular());
        }
        Ok(y)
    }
}

/// A pseudo-random number in [−1, 1) (xorshift64*; deterministic, so runs repeat exactly).
fn uniform(state: &mut u64) -> f64 {
    let mut x = *state;
    x ^= x >> 12;
    x ^= x << 25;
    x ^= x >> 27;
    *state = x;
    let r = x.wrapping_mul(0x2545_f491_4f6c_dd1d) >> 11;
    2.0 * (r as f64 / (1u64 << 53) as f64) - 1.0
}

#[cfg(test)]
mod tests {
    use super::uniform;

    #[test]
    fn uniform_stays_in_range_and_varies() {
        let mut s = 1u64;
        let v: Vec<f64> = (0..1000).map(|_| uniform(&mut s)).collect();
        assert!(v.iter().all(|x| (-1.0..1.0).contains(x)));
        let mean = v.iter().sum::<f64>() / 1000.0;
        assert!(mean.abs() < 0.1, "{mean}");
    }
}
