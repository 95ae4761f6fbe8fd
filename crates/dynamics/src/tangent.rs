//! Dense tangents of the static equations, shared by the static and the modal analysis.
//!
//! In the 6-coordinate form (increments δ = [δr_k; δπ'_k] per body, applied as r += δr,
//! p ← p ⊗ exp(δπ'/2), see [`cardan_mechanism::apply_rotation_step`]) a static equilibrium at
//! time t under the load factor s solves
//!
//! ```text
//! r₁(q, λ) = Φ_vᵀ(q) λ − h_s(q) = 0      (n = 6 nb rows: forces and body-frame torques)
//! r₂(q)    = Φ(q, t)            = 0      (the active, independent constraint rows)
//! ```
//!
//! with h_s = s h_loads + h_elements at v = 0 (the equations of motion M v̇ + Φ_vᵀλ = h with
//! v = v̇ = 0; sign convention of the crate docs: the reaction is −Φ_vᵀλ). Loads are gravity,
//! point forces and torques and the user callback; the elements (translational and
//! rotational springs, with an actuator force at its value at t) are not scaled.
//!
//! The tangent stiffness is K_t = ∂r₁/∂δ at fixed λ: the stiffness of the force elements,
//! −∂h/∂δ, plus the geometric stiffness of the constraint forces, ∂(Φ_vᵀλ)/∂δ (Haug 1989
//! §13.3; Géradin & Cardona 2001 §6.7). It is computed by central differences over the 6 nb
//! increments (step 1e-6 L for a translation, 1e-6 rad for a rotation: truncation error of
//! order 1e-12 relative, round-off of order 1e-10). Dense: for the models of the tests and
//! examples (tens of bodies); large models need the sparse path (not done).
//!
//! The damping of the force elements is C_t = −∂h/∂v at v = 0, central differences too.
//!
//! A basis N of the null space of Φ_v (n × d, d = n − m_a) comes from the SVD of Φ_v with rows
//! scaled by their equation scales and translation columns by L; independent coordinates z
//! then parametrize δ = N z to first order, and the reduced matrices are M_r = NᵀMN,
//! C_r = NᵀC_tN, K_r = NᵀK_tN.

use crate::forces::AppliedForces;
use crate::forces::Resolved;
use crate::kkt::{eval_rows, Rhs};
use crate::state::State;
use crate::system::Dynamics;
use cardan_mechanism::{apply_rotation_step, BodyId};
use nalgebra::{DMatrix, DVector};

/// Relative finite-difference step of the tangents (times L for translations; rad).
const FD_STEP: f64 = 1e-6;

/// Which generalized forces h a tangent differentiates.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum Load {
    /// h_s of the static equations (module docs) under the load factor s; no inertial term.
    Static(f64),
    /// The full h = [f; n' − ω̃'J'ω'] of the equations of motion, velocities as given.
    Dynamic,
}

impl Dynamics<'_> {
    /// h_s = s h_loads + h_elements at the synced bodies (velocities as synced), time t, into
    /// `self.h`. Loads: gravity, point forces and torques, the user callback; elements: springs.
    pub(crate) fn eval_static_forces(&mut self, t: f64, s: f64) {
        let model = self.model;
        let h = &mut self.h;
        h.fill(0.0);
        let mut acc = AppliedForces {
            h,
            bodies: &self.bodies,
        };
        for f in &self.forces {
            if !is_element(f) {
                f.apply(model, &self.mass, t, &mut acc);
            }
        }
        if let Some(u) = &mut self.user {
            u(t, &mut acc);
        }
        if s != 1.0 {
            for x in self.h.iter_mut() {
                *x *= s;
            }
        }
        let h = &mut self.h;
        let mut acc = AppliedForces {
            h,
            bodies: &self.bodies,
        };
        for f in &self.forces {
            if is_element(f) {
                f.apply(model, &self.mass, t, &mut acc);
            }
        }
        // Contacts between shapes are elements (at v = 0: their elastic force alone, no
        // damping, no friction).
        if let Some(c) = &mut self.collisions {
            c.apply(model, &mut acc);
        }
    }

    /// Φ_vᵀλ (n) at the synced bodies with full-row multipliers `lambda` (0 on dropped rows),
    /// and |Φ_v|ᵀ|λ|, the size of its terms.
    pub(crate) fn constraint_forces(&self, t: f64, lambda: &[f64]) -> (DVector<f64>, DVector<f64>) {
        let n = 6 * self.model.num_bodies();
        let mut y = DVector::zeros(n);
        let mut size = DVector::zeros(n);
        let mut bi = [[0.0; 6]; 6];
        let mut bj = [[0.0; 6]; 6];
        for e in &self.elements {
            self.element_blocks(e, t, &mut bi, &mut bj);
            for (lr, r) in e.rows.clone().enumerate() {
                let l = lambda[r];
                if l == 0.0 {
                    continue;
                }
                for (id, blk) in [(e.bi, &bi), (e.bj, &bj)] {
                    if let BodyId::Moving(k) = id {
                        for c in 0..6 {
                            y[6 * k + c] += blk[lr][c] * l;
                            size[6 * k + c] += (blk[lr][c] * l).abs();
                        }
                    }
                }
            }
        }
        (y, size)
    }

    /// A basis N of the null space of Φ_v on the rows `active` at `state` (bodies synced to it):
    /// the independent coordinates of the linearizations ([`null_space`]).
    pub(crate) fn constraint_null_space(
        &mut self,
        state: &State,
        active: &[usize],
    ) -> DMatrix<f64> {
        self.sync(state);
        let j = self.phi_v_dense(state.t, active);
        let model = self.model;
        null_space(
            &j,
            model.equation_scales(),
            active,
            model.characteristic_length(),
        )
        .0
    }

    /// Φ_v on the rows `active` (dense m_a × n) at the synced bodies.
    pub(crate) fn phi_v_dense(&self, t: f64, active: &[usize]) -> DMatrix<f64> {
        let model = self.model;
        let n = 6 * model.num_bodies();
        let mut of = vec![usize::MAX; model.num_equations()];
        for (a, &r) in active.iter().enumerate() {
            of[r] = a;
        }
        let mut j = DMatrix::zeros(active.len(), n);
        let mut bi = [[0.0; 6]; 6];
        let mut bj = [[0.0; 6]; 6];
        for e in &self.elements {
            self.element_blocks(e, t, &mut bi, &mut bj);
            for (lr, r) in e.rows.clone().enumerate() {
                let a = of[r];
                if a == usize::MAX {
                    continue;
                }
                for (id, blk) in [(e.bi, &bi), (e.bj, &bj)] {
                    if let BodyId::Moving(k) = id {
                        for c in 0..6 {
                            j[(a, 6 * k + c)] += blk[lr][c];
                        }
                    }
                }
            }
        }
        j
    }

    /// Φ(q, t) of all model rows at the synced bodies.
    pub(crate) fn phi_all(&self, t: f64) -> Vec<f64> {
        let mut phi = vec![0.0; self.model.num_equations()];
        eval_rows(
            self.model,
            &self.elements,
            &self.bodies,
            &self.turns,
            &self.curves,
            t,
            Rhs::Phi,
            &mut phi,
        );
        phi
    }

    /// r₁ = Φ_vᵀλ − h_s at `state` (its velocities are used as given: zero for statics) and the
    /// size of its terms, |Φ_v|ᵀ|λ| + |h_s| (for the convergence test).
    pub(crate) fn static_residual(
        &mut self,
        state: &State,
        lambda: &[f64],
        s: f64,
    ) -> (DVector<f64>, DVector<f64>) {
        self.force_residual(state, lambda, Load::Static(s))
    }

    /// h of `load` at the synced bodies, time t, into `self.h`.
    fn eval_load(&mut self, t: f64, load: Load) {
        match load {
            Load::Static(s) => self.eval_static_forces(t, s),
            Load::Dynamic => self.eval_forces(t),
        }
    }

    /// r₁ = Φ_vᵀλ − h at `state` with h of `load`, and the size of its terms.
    pub(crate) fn force_residual(
        &mut self,
        state: &State,
        lambda: &[f64],
        load: Load,
    ) -> (DVector<f64>, DVector<f64>) {
        self.sync(state);
        self.eval_load(state.t, load);
        let (mut r, mut size) = self.constraint_forces(state.t, lambda);
        for c in 0..r.len() {
            r[c] -= self.h[c];
            size[c] += self.h[c].abs();
        }
        (r, size)
    }

    /// K_t = ∂r₁/∂δ at fixed λ by central differences (module docs), n × n.
    pub(crate) fn static_tangent(&mut self, state: &State, lambda: &[f64], s: f64) -> DMatrix<f64> {
        self.stiffness_tangent(state, lambda, Load::Static(s))
    }

    /// K_t = ∂(Φ_vᵀλ − h)/∂δ at fixed λ and fixed v (body-frame ω') for h of `load`, by central
    /// differences (module docs), n × n.
    pub(crate) fn stiffness_tangent(
        &mut self,
        state: &State,
        lambda: &[f64],
        load: Load,
    ) -> DMatrix<f64> {
        let n = state.v.len();
        let l = self.model.characteristic_length();
        let mut k = DMatrix::zeros(n, n);
        let mut p = state.clone();
        let mut dq = vec![0.0; n];
        for c in 0..n {
            let e = if c % 6 < 3 { FD_STEP * l } else { FD_STEP };
            let mut col = [DVector::zeros(0), DVector::zeros(0)];
            for (i, sign) in [1.0, -1.0].into_iter().enumerate() {
                p.q.copy_from_slice(&state.q);
                dq.fill(0.0);
                dq[c] = sign * e;
                apply_rotation_step(&mut p.q, &dq);
                col[i] = self.force_residual(&p, lambda, load).0;
            }
            let d = (&col[0] - &col[1]) / (2.0 * e);
            k.set_column(c, &d);
        }
        self.sync(state);
        k
    }

    /// C_t = −∂h/∂v at `state` by central differences, n × n, with h of `load` (at full load
    /// for statics; with the inertial term −ω̃'J'ω', whose derivative is the gyroscopic matrix,
    /// for a moving state).
    pub(crate) fn damping_tangent(&mut self, state: &State, load: Load) -> DMatrix<f64> {
        let n = state.v.len();
        let mut c = DMatrix::zeros(n, n);
        let mut p = state.clone();
        for col in 0..n {
            let e = FD_STEP * (1.0 + state.v[col].abs());
            let mut h = [DVector::zeros(0), DVector::zeros(0)];
            for (i, sign) in [1.0, -1.0].into_iter().enumerate() {
                p.v.copy_from_slice(&state.v);
                p.v[col] += sign * e;
                self.sync(&p);
                self.eval_load(state.t, load);
                h[i] = DVector::from_column_slice(&self.h);
            }
            c.set_column(col, &(-(&h[0] - &h[1]) / (2.0 * e)));
        }
        self.sync(state);
        c
    }

    /// The block-diagonal mass matrix diag(m_k I, J'_k), n × n.
    pub(crate) fn mass_matrix(&self) -> DMatrix<f64> {
        let nb = self.mass.len();
        let mut m = DMatrix::zeros(6 * nb, 6 * nb);
        for k in 0..nb {
            for a in 0..3 {
                m[(6 * k + a, 6 * k + a)] = self.mass[k];
                for b in 0..3 {
                    m[(6 * k + 3 + a, 6 * k + 3 + b)] = self.inertia[k][(a, b)];
                }
            }
        }
        m
    }
}

/// Whether a force element belongs to the structure (springs, not scaled by the load factor).
fn is_element(f: &Resolved) -> bool {
    matches!(f, Resolved::Spring { .. } | Resolved::Rotational { .. })
}

/// A basis of the null space of `phi_v` (m_a × n, rows = model rows `active`): n × d with
/// d = n − rank, from the SVD of the scaled matrix (rows / equation scale, translation
/// columns × L). Returns the basis and the ratio σ_min/σ_max of the scaled rows (near zero at a
/// singular configuration).
pub(crate) fn null_space(
    phi_v: &DMatrix<f64>,
    scales: &[f64],
    active: &[usize],
    length: f64,
) -> (DMatrix<f64>, f64) {
    let (m, n) = phi_v.shape();
    let col_scale = |c: usize| if c % 6 < 3 { length } else { 1.0 };
    let mut a = DMatrix::zeros(n.max(m), n);
    for r in 0..m {
        for c in 0..n {
            a[(r, c)] = phi_v[(r, c)] / scales[active[r]] * col_scale(c);
        }
    }
    let svd = a.svd(false, true);
    let v_t = svd.v_t.expect("requested");
    let mut order: Vec<usize> = (0..svd.singular_values.len()).collect();
    order.sort_by(|&i, &j| svd.singular_values[j].total_cmp(&svd.singular_values[i]));
    let smax = svd.singular_values.iter().fold(0.0f64, |x, &y| x.max(y));
    let ratio = if m == 0 || smax == 0.0 {
        if m == 0 {
            1.0
        } else {
            0.0
        }
    } else {
        svd.singular_values[order[m.min(order.len()) - 1]] / smax
    };
    let d = n.saturating_sub(m);
    let mut basis = DMatrix::zeros(n, d);
    for (col, &i) in order[m..].iter().enumerate().take(d) {
        for c in 0..n {
            basis[(c, col)] = v_t[(i, c)] * col_scale(c);
        }
    }
    (basis, ratio)
}
