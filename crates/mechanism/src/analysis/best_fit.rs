//! The best fit of equations that Newton could not solve: the pose that minimizes the scaled
//! residual ½ ‖E⁻¹ Φ(q)‖² (E the equation scales), by Levenberg–Marquardt from the drawn pose
//! (Nocedal & Wright, *Numerical Optimization*, 2006, §10.3).
//!
//! Two things follow from it when an assembly fails. When the best fit's residual vanishes the
//! equations are consistent and Newton failed only for want of globalization (a part drawn far
//! from its place): the best fit is a pose from which Newton converges, and the assembly goes
//! on from there. When it does not vanish the model is over-constrained and inconsistent: at the
//! best fit the rank analysis finds the rows that make it over-constrained, and with the others
//! solved exactly those rows stay open by the amount the message reports
//! ([`crate::AnalysisError::InconsistentJoints`]).
//!
//! Each iteration solves (ĴᵀĴ + μ I) δ = −Ĵᵀ r with Ĵ the Jacobian with rows over e_i and
//! columns times the unknown scales (δ in scaled unknowns: lengths over L, rotations in
//! radians), r = E⁻¹ Φ; a step that lowers the residual is taken and μ divided by 3, else μ is
//! multiplied by 4. Dense (an error path, for models up to [`MAX_BEST_FIT_UNKNOWNS`] unknowns).

use crate::model::Model;
use crate::workspace::{apply_step, Workspace};
use nalgebra::{DMatrix, DVector};

/// Largest model the best fit is tried on (a dense n × n solve per iteration).
pub const MAX_BEST_FIT_UNKNOWNS: usize = 600;

/// Iteration cap.
pub const MAX_BEST_FIT_ITERATIONS: usize = 500;

/// Largest scaled step of an iteration (as the assembly's cap): half the model's size or about
/// 30°.
const MAX_STEP: f64 = 0.5;

impl Model {
    /// Moves the workspace's poses to the best fit of the first `m` equations at time `t`
    /// (module docs) and returns its largest scaled residual max |Φ_i| / e_i; `None` for a
    /// model too large to try or a non-finite residual. Allocates.
    pub(crate) fn best_fit(&self, ws: &mut Workspace, t: f64, m: usize) -> Option<f64> {
        let n = self.num_unknowns();
        if n > MAX_BEST_FIT_UNKNOWNS || n == 0 || m == 0 {
            return None;
        }
        let scales = self.unknown_scales().to_vec();
        let e = self.equation_scales()[..m].to_vec();
        let cost = |model: &Model, ws: &mut Workspace, r: &mut DVector<f64>| {
            ws.sync_poses();
            model.phi_into(
                &ws.pose.bodies,
                ws.pose.u(),
                &ws.pose.turns,
                t,
                &mut ws.rows.phi,
            );
            for i in 0..m {
                r[i] = ws.rows.phi[i] / e[i];
            }
            0.5 * r.norm_squared()
        };
        let mut r = DVector::zeros(m);
        let mut f = cost(self, ws, &mut r);
        let mut slots = vec![0.0; self.pattern.num_slots()];
        let mut x_try = ws.pose.x.clone();
        let mut r_try = DVector::zeros(m);
        let mut mu = -1.0;
        for _ in 0..MAX_BEST_FIT_ITERATIONS {
            if !f.is_finite() {
                return None;
            }
            self.jacobian_into(&ws.pose.bodies, ws.pose.u(), t, &mut slots);
            let mut j = DMatrix::zeros(m, n);
            for ((row, col), v) in self.pattern.entries().zip(&slots) {
                if row < m {
                    j[(row, col)] = v * scales[col] / e[row];
                }
            }
            let g = j.transpose() * &r;
            if g.amax() <= 1e-15 * (1.0 + r.amax()) {
                break;
            }
            let a = j.transpose() * &j;
            if mu < 0.0 {
                mu = 1e-3 * a.diagonal().amax().max(1e-12);
            }
            let mut improved = false;
            for _ in 0..40 {
                let mut lhs = a.clone();
                for k in 0..n {
                    lhs[(k, k)] += mu;
                }
                let Some(chol) = lhs.cholesky() else {
                    mu *= 4.0;
                    continue;
                };
                let mut d = -chol.solve(&g);
                let size = d.amax();
                if size > MAX_STEP {
                    d *= MAX_STEP / size;
                }
                let dx: Vec<f64> = (0..n).map(|k| d[k] * scales[k]).collect();
                x_try.copy_from_slice(&ws.pose.x);
                std::mem::swap(&mut ws.pose.x, &mut x_try);
                apply_step(&mut ws.pose.x, &dx, self.num_bodies());
                let f_try = cost(self, ws, &mut r_try);
                if f_try < f {
                    f = f_try;
                    std::mem::swap(&mut r, &mut r_try);
                    mu = (mu / 3.0).max(1e-20);
                    improved = true;
                    break;
                }
                // Back to the last pose.
                std::mem::swap(&mut ws.pose.x, &mut x_try);
                mu *= 4.0;
            }
            ws.sync_poses();
            if !improved {
                break;
            }
        }
        cost(self, ws, &mut r);
        Some(r.amax())
    }
}
