//! The velocity projection after a generalized-α step that reuses the held factorization
//! ([`VelocityProjection::project`]).

use super::policy::{Factor, FactorPolicy, THETA_REFACTOR};
use super::scheme::mass_mul;
use crate::kkt::{eval_rows, Kkt, Rhs, SchurRefinement};
use crate::state::State;
use crate::system::Dynamics;
use crate::DynamicsError;

/// Fraction of the velocity projection's total correction below which its last refinement
/// step ends the refinement between outputs (see [`VelocityProjection::project`]); the part
/// left is about the contraction rate (≤ 0.05 for a held tangent matrix) times this of the
/// total. The slider-crank (h = 1 ms, 2 s): 3.8 refinement solves per step at 1e-6, 2.4 at
/// 1e-3, 1.9 at 1e-2, the same error (2.19e-4, 2.21e-4, 2.19e-4 m). The 5-link chain of
/// `tests/step_policy.rs` against full Newton with exact projections: 1.8e-10 m at 1e-6,
/// 4.6e-10 m at 1e-3, 2.0e-8 m at 1e-2 (the warm start's first correction then often ends
/// the refinement unchecked), against a discretization error of 6.0e-7 m.
const PROJECTION_FRACTION: f64 = 1e-3;

/// The projection's right-hand side and solutions: its own and those of the steps before,
/// which warm-start it.
#[derive(Debug, Clone)]
pub(super) struct VelocityProjection {
    /// The right-hand side ν − Φ_v v (kept rows).
    e: Vec<f64>,
    /// The solution [Δv; μ] (n + m_a).
    x: Vec<f64>,
    /// The solutions of the two steps before `x`'s (its warm start extrapolates from them),
    /// and how many of them (0–2) count: steps of the same size as the last, each projected
    /// by refinement.
    x_prev: Vec<f64>,
    x_prev2: Vec<f64>,
    history: usize,
}

impl VelocityProjection {
    /// For `n` unknowns and `na` kept rows, with no history.
    pub fn new(n: usize, na: usize) -> Self {
        Self {
            e: vec![0.0; na],
            x: vec![0.0; n + na],
            x_prev: vec![0.0; n + na],
            x_prev2: vec![0.0; n + na],
            history: 0,
        }
    }

    /// Forgets the solutions before (a restart).
    pub fn reset(&mut self) {
        self.x.fill(0.0);
        self.x_prev.fill(0.0);
        self.x_prev2.fill(0.0);
        self.history = 0;
    }

    /// Velocity projection onto Φ_v v = ν at `s` (the M-metric least-change projection of
    /// [`Dynamics::project_velocities`]) that reuses the factorization held by the solver when
    /// there is one: the exact system K [Δv; μ] = [0; ν − Φ_v v], K = [M Φ_vᵀ; Φ_v 0] at the new
    /// state, is solved by iterative refinement with the factored nearby matrix K̃ (residual
    /// with the exact K, correction with K̃⁻¹), which converges at the rate ‖K̃⁻¹(K − K̃)‖; a
    /// fresh factorization when it does not contract fast enough.
    ///
    /// Called right after a step of size `h` is accepted (`h_prev` the size of the step before
    /// it): the bodies and Φ_v in the solver are those of the step's last iterate, which is
    /// `s` (the attempt converges on the residual it evaluated there), so neither is evaluated
    /// again.
    ///
    /// `exact`: the step ends on an output time, whose velocities are stored, so the
    /// refinement runs to roundoff (the last correction below 1e-6 of the total or 1e-10 of the
    /// largest velocity). Between outputs it stops once the last correction is below
    /// [`PROJECTION_FRACTION`] of the total: what is left, a fraction of one step's drift, is
    /// removed with the next step's drift by the next projection (each projection corrects the
    /// whole residual ν − Φ_v v), so it does not accumulate. A fresh factorization projects
    /// with the Schur refinement `refine`.
    ///
    /// # Errors
    /// The failure of a fresh projection.
    pub fn project(
        &mut self,
        d: &mut Dynamics,
        policy: &mut FactorPolicy,
        s: &mut State,
        h: f64,
        h_prev: f64,
        exact: bool,
        refine: SchurRefinement,
    ) -> Result<(), DynamicsError> {
        // The warm start extrapolates only over equal steps (the step before of the same size,
        // up to the roundoff of the steps that divide an output interval), and only when no
        // redundant row is dropped: near a configuration where the kept rows lose rank the
        // corrections jump, and an extrapolated start sent the refinement of the Bennett
        // linkage in `tests/reselection.rs` to 1e8 m/s (its steps land on such configurations).
        let same = (h - h_prev).abs() <= 1e-9 * h;
        let all_rows = d.kkt.as_ref().is_some_and(Kkt::keeps_all_rows);
        let history = if same && all_rows { self.history } else { 0 };
        self.history = 0;
        if policy.factor == Factor::None {
            d.project_velocities_refined(s, refine)?;
            policy.hold_mass_matrix(Factor::Fresh);
            return Ok(());
        }
        if !self.residual(d, s) {
            return Ok(());
        }
        self.warm_start(history);
        if self.refine(d, s, exact) {
            for c in 0..s.v.len() {
                s.v[c] += self.x[c];
            }
            // The solutions before count for the next step if this step had their size.
            self.history = if same { (history + 1).min(2) } else { 0 };
        } else {
            // The refinement's last iterate is no warm start for the next step: near a singular
            // configuration it can be far off (the Bennett linkage of the re-selection test:
            // 1e8 m/s, and the steps after it diverged).
            self.x.fill(0.0);
            d.project_velocities_refined(s, refine)?;
            policy.hold_mass_matrix(Factor::Fresh);
        }
        Ok(())
    }

    /// e = ν − Φ_v v at `s` (Φ_v held by the solver); `false` when it is zero.
    fn residual(&mut self, d: &mut Dynamics, s: &State) -> bool {
        let kkt = d.kkt.as_mut().expect("prepared");
        eval_rows(
            d.model,
            &d.elements,
            &d.bodies,
            &d.turns,
            &d.curves,
            s.t,
            Rhs::Nu,
            &mut kkt.full,
        );
        kkt.phi_v_mul(&s.v, &mut self.e);
        for (a, &r) in kkt.active.iter().enumerate() {
            self.e[a] = kkt.full[r] - self.e[a];
        }
        let e_max = self.e.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        e_max != 0.0
    }

    /// Starts from the last steps' corrections, extrapolated (quadratically from three equal
    /// steps, linearly from two): the drift a step leaves changes slowly and smoothly (the
    /// slider-crank: 5.89e-5, 5.92e-5, 5.95e-5 m/s in three steps), so the first residual is a
    /// small fraction of the whole and the first refinement usually ends it. The last
    /// correction alone left about 1 %, and a second refinement was needed (the slider-crank
    /// at h = 1 ms: 1.8 instead of 2.5 solves per step, −7.5 % instructions of a whole run).
    fn warm_start(&mut self, history: usize) {
        for ((x, p), p2) in self
            .x
            .iter_mut()
            .zip(self.x_prev.iter_mut())
            .zip(self.x_prev2.iter_mut())
        {
            let last = *x;
            if history >= 2 {
                *x = 3.0 * last - 3.0 * *p + *p2;
            } else if history == 1 {
                *x = 2.0 * last - *p;
            }
            *p2 = *p;
            *p = last;
        }
    }

    /// Iterative refinement of x with the held factorization, at most six solves; `true` when
    /// converged: the last correction is below 1e-6 (`exact`) or [`PROJECTION_FRACTION`] of
    /// the total (itself a small drift correction), or below 1e-10 of the largest velocity.
    /// `false` when a correction grows by more than [`THETA_REFACTOR`] or a solve fails.
    fn refine(&mut self, d: &mut Dynamics, s: &State, exact: bool) -> bool {
        let kkt = d.kkt.as_mut().expect("prepared");
        let n = kkt.n;
        let na = kkt.active.len();
        let vmax = s.v.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        let mut d_prev = f64::INFINITY;
        for _ in 0..6 {
            // Residual of the exact system at x: [−(M x_v + Φ_vᵀ x_μ); e − Φ_v x_v].
            let (xv, xm) = self.x.split_at(n);
            mass_mul(&d.mass, &d.inertia, xv, &mut kkt.rhs[..n]);
            let mut top = std::mem::take(&mut kkt.work_n);
            top.fill(0.0);
            kkt.phi_v_t_mul_add(xm, &mut top);
            for i in 0..n {
                kkt.rhs[i] = -(kkt.rhs[i] + top[i]);
            }
            kkt.work_n = top;
            let mut wa = std::mem::take(&mut kkt.work_a);
            kkt.phi_v_mul(xv, &mut wa);
            for a in 0..na {
                kkt.rhs[n + a] = self.e[a] - wa[a];
            }
            kkt.work_a = wa;
            if kkt.solve_unrefined().is_err() {
                return false;
            }
            let mut dmax = 0.0f64;
            let mut xmax = 0.0f64;
            for i in 0..n + na {
                self.x[i] += kkt.sol[i];
                if i < n {
                    dmax = dmax.max(kkt.sol[i].abs());
                    xmax = xmax.max(self.x[i].abs());
                }
            }
            let fraction = if exact { 1e-6 } else { PROJECTION_FRACTION };
            if dmax <= fraction * xmax || dmax <= 1e-10 * vmax || dmax == 0.0 {
                return true;
            }
            if dmax > THETA_REFACTOR * d_prev {
                return false;
            }
            d_prev = dmax;
        }
        false
    }
}
