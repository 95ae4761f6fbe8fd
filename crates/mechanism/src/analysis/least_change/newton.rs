//! The least change's Newton step: the Gauss–Newton step of the parent module with the
//! curvature it leaves out put back, so that the iteration converges where Gauss–Newton
//! oscillates (a part drawn far from its place on a distance joint, a point near a hinge
//! dragged far).
//!
//! # The step
//! The least change minimizes f(q) subject to Φ(q) = 0; its Lagrangian is L = f − κᵀΦ.
//! Gauss–Newton uses H = QᵀWQ (and the drag goal's Gauss–Newton term with the positive part
//! of its curvature) for ∇²L; the Newton step uses ∇²L = H + C with
//!
//! - the constraints' curvature, vᵀ C_Φ v = Σ_r κ_r γ#_r(v)
//!   ([`Model::curvature_into`](crate::model::Model), by polarization of γ#);
//! - the objective's own curvature along the retraction p ⊗ exp(s ω'/2), whose second
//!   derivative of p is −¼ |ω'|² p: −¼ Σ_i w_ei (e_i − e_i,old) e_i on each rotation block;
//! - the negative part of the drag goal's curvature (the positive part is in H).
//!
//! The multipliers κ are those of the Gauss–Newton step's own optimality conditions: in the
//! transformed unknowns z = Lᵀδ the step solves min ½‖z‖² + cᵀz subject to Ĵ z = b, so
//! y = z + c = Ĵᵀμ ([`cardan_solver::MinNormQr::solve_transpose`]) and κ_r = μ_r / e_r
//! (Ĵ's rows are Φ_v's over the equation scales e_r): the least-squares multiplier estimate of
//! SQP (Nocedal & Wright, *Numerical Optimization*, 2nd ed., §18.1).
//!
//! With Ĉ = L⁻¹ C L⁻ᵀ the Newton step minimizes ½ zᵀ(I + Ĉ)z + cᵀz on the same affine set.
//! Starting from the Gauss–Newton z₀, projected conjugate gradients (Nocedal & Wright §16.3,
//! Algorithm 16.2) iterate in the null space of Ĵ with the projection P = I − Ĵ⁺Ĵ (the
//! factored QR); the null space has the dimension of the free degrees of freedom, so the
//! iteration ends after at most that many steps. Where the reduced Hessian is not positive
//! along a direction (far from a minimum), the iteration stops there with the step it has,
//! which is at least as good for the model as Gauss–Newton's (Steihaug's rule).

use super::LeastChange;
use crate::model::Model;
use crate::workspace::Workspace;
use cardan_solver::{LinearSolver, MinNormQr, SolverError, SparsityPattern};
use nalgebra::{Matrix3, Matrix6, Vector6};

/// The buffers of the Newton step, sized once.
#[derive(Debug)]
pub(super) struct NewtonBuffers {
    /// μ of the scaled rows, then κ_r = μ_r / e_r (m).
    kappa: Vec<f64>,
    /// C, then Ĉ (n × n, row by row).
    c: Vec<f64>,
    /// The Gauss–Newton z₀, then the Newton z (n).
    z: Vec<f64>,
    /// Conjugate-gradient vectors (n each): the null-space correction, the projected residual,
    /// the direction, (I + Ĉ) times it, a scratch for projections.
    w: Vec<f64>,
    r: Vec<f64>,
    p: Vec<f64>,
    ap: Vec<f64>,
    scratch_n: Vec<f64>,
    /// Scratch for Ĵ v (m).
    scratch_m: Vec<f64>,
}

impl NewtonBuffers {
    fn new(m: usize, n: usize) -> Self {
        Self {
            kappa: vec![0.0; m],
            c: vec![0.0; n * n],
            z: vec![0.0; n],
            w: vec![0.0; n],
            r: vec![0.0; n],
            p: vec![0.0; n],
            ap: vec![0.0; n],
            scratch_n: vec![0.0; n],
            scratch_m: vec![0.0; m],
        }
    }
}

/// Relative size of the projected residual at which the conjugate gradients stop.
const CG_TOLERANCE: f64 = 1e-13;

impl LeastChange {
    /// Replaces the Gauss–Newton step in `delta` (made by `step` from the factors at the
    /// workspace's poses, with `y` = z + c) by the Newton step (module docs). No allocation
    /// after the first call, which sizes the buffers.
    ///
    /// # Errors
    /// Solver errors of the projections.
    pub(super) fn newton_step(
        &mut self,
        model: &Model,
        ws: &Workspace,
        t: f64,
    ) -> Result<(), SolverError> {
        let n = self.c.len();
        let m = self.b.len();
        let nw = self.newton.get_or_insert_with(|| NewtonBuffers::new(m, n));
        self.qr.solve_transpose(&self.y, &mut nw.kappa)?;
        for (k, e) in nw.kappa.iter_mut().zip(model.equation_scales()) {
            *k /= e;
        }
        nw.c.fill(0.0);
        model.curvature_into(&ws.pose.bodies, &nw.kappa, t, &mut nw.c);
        for (b, w) in self.weights.iter().enumerate() {
            let x = &ws.pose.x[7 * b + 3..7 * b + 7];
            let old = &self.old[7 * b + 3..7 * b + 7];
            let s: f64 = (0..4).map(|i| w.rotation[i] * (x[i] - old[i]) * x[i]).sum();
            let mut extra = -0.25 * s * Matrix3::identity();
            if self.goal.is_some_and(|g| g.body == b) {
                extra += self.goal_negative;
            }
            for i in 0..3 {
                for j in 0..3 {
                    nw.c[(6 * b + 3 + i) * n + 6 * b + 3 + j] += extra[(i, j)];
                }
            }
        }
        transform(&mut nw.c, &self.l_inv);
        for ((z, y), c) in nw.z.iter_mut().zip(&self.y).zip(&self.c) {
            *z = y - c;
        }
        let proj = |v: &mut [f64], nw_m: &mut [f64], nw_n: &mut [f64], qr: &mut MinNormQr| {
            project(&self.pattern, &self.hat, qr, v, nw_m, nw_n)
        };
        // r = P((I + Ĉ) z₀ + c) = P(y + Ĉ z₀).
        mul(&nw.c, &nw.z, &mut nw.r);
        for (r, y) in nw.r.iter_mut().zip(&self.y) {
            *r += y;
        }
        proj(
            &mut nw.r,
            &mut nw.scratch_m,
            &mut nw.scratch_n,
            &mut self.qr,
        )?;
        nw.w.fill(0.0);
        let r0 = dot(&nw.r, &nw.r);
        let mut rr = r0;
        for (p, r) in nw.p.iter_mut().zip(&nw.r) {
            *p = -r;
        }
        for _ in 0..n {
            if rr <= CG_TOLERANCE * CG_TOLERANCE * r0 || rr == 0.0 {
                break;
            }
            mul(&nw.c, &nw.p, &mut nw.ap);
            for (a, p) in nw.ap.iter_mut().zip(&nw.p) {
                *a += p;
            }
            let curvature = dot(&nw.p, &nw.ap);
            if curvature <= 1e-12 * dot(&nw.p, &nw.p) {
                break;
            }
            let alpha = rr / curvature;
            for ((w, p), a) in nw.w.iter_mut().zip(&nw.p).zip(nw.ap.iter_mut()) {
                *w += alpha * p;
                *a *= alpha;
            }
            proj(
                &mut nw.ap,
                &mut nw.scratch_m,
                &mut nw.scratch_n,
                &mut self.qr,
            )?;
            for (r, a) in nw.r.iter_mut().zip(&nw.ap) {
                *r += a;
            }
            let rr_new = dot(&nw.r, &nw.r);
            let beta = rr_new / rr;
            rr = rr_new;
            for (p, r) in nw.p.iter_mut().zip(&nw.r) {
                *p = -r + beta * *p;
            }
        }
        for (b, l_inv) in self.l_inv.iter().enumerate() {
            let z = Vector6::from_fn(|i, _| nw.z[6 * b + i] + nw.w[6 * b + i]);
            let d = l_inv.transpose() * z;
            self.delta[6 * b..6 * b + 6].copy_from_slice(d.as_slice());
        }
        Ok(())
    }
}

/// C ← L⁻¹ C L⁻ᵀ block by block (6 × 6 blocks, `l_inv` per body).
fn transform(c: &mut [f64], l_inv: &[Matrix6<f64>]) {
    let n = 6 * l_inv.len();
    for (a, la) in l_inv.iter().enumerate() {
        for (b, lb) in l_inv.iter().enumerate() {
            let block = Matrix6::from_fn(|i, j| c[(6 * a + i) * n + 6 * b + j]);
            if block.iter().all(|v| *v == 0.0) {
                continue;
            }
            let out = la * block * lb.transpose();
            for i in 0..6 {
                for j in 0..6 {
                    c[(6 * a + i) * n + 6 * b + j] = out[(i, j)];
                }
            }
        }
    }
}

/// out = C v for a dense n × n C (row by row).
fn mul(c: &[f64], v: &[f64], out: &mut [f64]) {
    for (o, row) in out.iter_mut().zip(c.chunks_exact(v.len())) {
        *o = dot(row, v);
    }
}

fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

/// v ← P v = v − Ĵ⁺(Ĵ v) with Ĵ's slots `hat` and its factored QR. No allocation.
fn project(
    pattern: &SparsityPattern,
    hat: &[f64],
    qr: &mut MinNormQr,
    v: &mut [f64],
    scratch_m: &mut [f64],
    scratch_n: &mut [f64],
) -> Result<(), SolverError> {
    pattern.mul_vec(hat, v, scratch_m)?;
    qr.solve(scratch_m, scratch_n)?;
    for (x, s) in v.iter_mut().zip(scratch_n.iter()) {
        *x -= s;
    }
    Ok(())
}
