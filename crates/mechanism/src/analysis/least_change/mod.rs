//! Least change: the pose nearest to a previous one, in a weighted metric, that satisfies the
//! constraints. It moves the free degrees of freedom of an under-driven mechanism as little as
//! the drivers allow ("hold still"), as OndselSolver does for FreeCAD assemblies with fewer
//! motions than degrees of freedom, and as a drag solve moves everything but the dragged part.
//!
//! # The problem
//! With q = [r; p] per body (the centre of mass and the Euler parameters) and q_old the previous
//! pose, find
//!
//! ```text
//!   min ½ (q − q_old)ᵀ W (q − q_old)   subject to   Φ(q, t) = 0,   pᵀp = 1 for every body,
//! ```
//!
//! W diagonal per body: w_r on each of r's three components, w_e = (w_e0, w_e1, w_e2, w_e3) on
//! the Euler parameters. The optimality conditions are Φ = 0 and
//! Qᵀ W (q − q_old) + Φ_vᵀ λ = 0, with Q = ∂q/∂[Δr; Δπ'] (for the rotation part
//! ∂p/∂π' = ½ [−eᵀ; e₀ I + ẽ], the derivative of p ⊗ exp(Δπ'/2); Δπ' the body-frame rotation
//! increment of the Newton state, `shared/notation.md`).
//!
//! # The iteration
//! A Gauss–Newton iteration on the constrained least-squares problem: at the iterate q_k, with
//! d = q_k − q_old, H = QᵀWQ (block diagonal: w_r I per translation, a 3 × 3 block per rotation)
//! and g = QᵀW d, the step δ solves
//!
//! ```text
//!   min ½ δᵀHδ + gᵀδ   subject to   Φ_v δ = −Φ,
//! ```
//!
//! the objective linearized about q_k but measured from q_old. Its fixed point (δ = 0) is
//! exactly the optimality condition above (g = −Φ_vᵀλ), so the iteration converges to the exact
//! minimizer, not to the first point Newton reaches on the constraint manifold; it converges
//! linearly at a rate proportional to the distance moved times the curvature of the
//! constraints, fast for the small changes between output times. With H = L Lᵀ (Cholesky per
//! block), z = Lᵀ δ, c = L⁻¹ g and Ĵ = Φ_v L⁻ᵀ, the step is a minimum-norm solve
//!
//! ```text
//!   y = Ĵ⁺ (−Φ + Ĵ c),   δ = L⁻ᵀ (y − c),
//! ```
//!
//! by the rank-revealing QR ([`cardan_solver::MinNormQr`]) that also drops redundant rows (the
//! rows of Ĵ scaled by the equation scales first, so the rank decision sees unit rows).
//! Where that rate is no contraction at all (a step at least [`SLOW_CONTRACTION`] of the one
//! before: a part drawn far from its place on a distance joint, a point near a hinge dragged
//! far), the solve goes on with Newton steps, which put back the curvature Gauss–Newton leaves
//! out (the constraints' λᵀΦ_qq, the rotation's own; `least_change/newton.rs`) and converge
//! quadratically.
//! Gauss–Newton stays the first choice because it is cheaper and, where it converges, finds the
//! minimum OndselSolver finds; Newton may reach another one (in the far-drawn survey of
//! `docs/asmt.md`, one with a sixth of the objective OndselSolver reaches).
//! Velocities and accelerations of the held motion are the H-weighted minimum-norm solutions of
//! Φ_v v = ν and Φ_v v̇ = γ# (the rates of the least-change motion as the output step tends to
//! zero, without the term from the rate of H, which is of the order of the free coordinates'
//! curvature; documented in docs/model-format.md).
//!
//! # The drag goal
//! A drag ([`crate::analysis::drag`]) adds ½ w_d ‖P − target‖² for a point P = r + A s' of one
//! body. Its Gauss–Newton term w_d BᵀB (B = [I, −A s̃']) leaves out the curvature of P's path,
//! w_d mᵀ (½ π̃'π̃' s') with m = Aᵀ (P − target): negligible when P is near its target, but when
//! the target is far from P against the radius |s'| of P's circle about the body's origin (a
//! point near a hinge pulled far away), Gauss–Newton overshoots by a factor of about
//! 1 + |P − target| / |s'| and does not converge. H gets that term's positive part (where it is
//! negative, leaving it out only shortens the step); the fixed point, hence the solution, is
//! unchanged. The curvature the constraints give P's path (a point near a hinge circles the
//! hinge, not the body's origin) and the goal's negative part are the Newton step's
//! (`newton.rs`); a drag step that still cannot converge is cut back and repeated
//! ([`crate::Drag::follow`]).
//!
//! # The weights
//! [`HoldMetric::Ondsel`] is OndselSolver's (`Part::fillqsuWeights`, in the raw coordinates of
//! the file's length unit): w_r = 1e3 + 1e6 m/m_max per component of the centre of mass,
//! w_ei = 1e3 + 1e6 J_i/J_max for i = 1, 2, 3 (J_i the principal moments, J_max the largest of
//! any part), w_e0 = 1e3, zero maxima taken as 1. [`HoldMetric::Scaled`] is the assembly's
//! scaled norm, ‖Δr‖²/L² + ‖Δθ‖² for small rotations (w_r = 1/L², every w_e = 4).

use crate::error::AnalysisError;
use crate::model::Model;
use crate::workspace::{apply_rotation_step, Workspace};
use cardan_eulerparam::EulerParams;
use cardan_solver::{LinearSolver, MinNormQr, SolverError, SparsityPattern};
use nalgebra::{Matrix3, Matrix3x4, Matrix4x3, Matrix6, Vector3, Vector4, Vector6};

mod newton;

/// The drag goal's second-order term in the body-frame rotation increment π' (module docs,
/// "The drag goal"), split into its positive and negative parts: with m = Aᵀ (P − target) and
/// the dragged point s', the Hessian of mᵀ (½ π̃'π̃' s') is C = ½ (m s'ᵀ + s' mᵀ) − (m·s') I.
/// The positive part goes into H (which stays positive definite), the negative part into the
/// Newton step's curvature ([`newton`]). No allocation.
fn goal_curvature(m: &Vector3<f64>, s: &Vector3<f64>) -> (Matrix3<f64>, Matrix3<f64>) {
    let c = 0.5 * (m * s.transpose() + s * m.transpose()) - Matrix3::identity() * m.dot(s);
    let eig = c.symmetric_eigen();
    let mut out = Matrix3::zeros();
    for (k, lambda) in eig.eigenvalues.iter().enumerate() {
        if *lambda > 0.0 {
            let v = eig.eigenvectors.column(k);
            out += *lambda * v * v.transpose();
        }
    }
    (out, c - out)
}

/// The metric of the least change (module docs).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum HoldMetric {
    /// ‖Δr‖²/L² + 4 ‖Δp‖² (about ‖Δθ‖² for small rotations): the assembly's scaled norm.
    Scaled,
    /// OndselSolver's mass-weighted metric on coordinates in the file's length unit,
    /// `metres_per_unit` metres (0.001 for FreeCAD's millimetres).
    Ondsel {
        /// The file's length unit in metres.
        metres_per_unit: f64,
    },
}

/// What a kinematic run does with degrees of freedom no driver prescribes.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub enum FreeDof {
    /// Refuse the run ([`AnalysisError::DriverCount`]).
    #[default]
    Refuse,
    /// Hold them: each output time's pose is the least change from the last one in the metric.
    Hold(HoldMetric),
}

/// The weights of one moving body: w_r, and w_e in the order of p = (e₀, e₁, e₂, e₃).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BodyWeights {
    /// Weight of each component of the centre of mass (1/m²).
    pub translation: f64,
    /// Weights of e₀, e₁, e₂, e₃.
    pub rotation: [f64; 4],
}

impl HoldMetric {
    /// The weights of every moving body of `model` (module docs).
    pub fn weights(&self, model: &Model) -> Vec<BodyWeights> {
        match *self {
            HoldMetric::Scaled => {
                let l = model.characteristic_length();
                let w = BodyWeights {
                    translation: 1.0 / (l * l),
                    rotation: [4.0; 4],
                };
                vec![w; model.num_bodies()]
            }
            HoldMetric::Ondsel { metres_per_unit } => {
                let bodies = model.bodies();
                let mass = |b: &crate::model::BodyInfo| b.mass.unwrap_or(0.0);
                let moments = |b: &crate::model::BodyInfo| {
                    b.inertia
                        .map_or([0.0; 3], |j| [j[(0, 0)], j[(1, 1)], j[(2, 2)]])
                };
                let or_one = |x: f64| if x > 0.0 { x } else { 1.0 };
                let m_max = or_one(bodies.iter().map(mass).fold(0.0, f64::max));
                let j_max = or_one((bodies.iter().flat_map(moments)).fold(0.0, f64::max));
                let (min_w, max_w) = (1e3, 1e6);
                let u2 = metres_per_unit * metres_per_unit;
                bodies
                    .iter()
                    .map(|b| {
                        let j = moments(b);
                        BodyWeights {
                            translation: (min_w + max_w * mass(b) / m_max) / u2,
                            rotation: [
                                min_w,
                                min_w + max_w * j[0] / j_max,
                                min_w + max_w * j[1] / j_max,
                                min_w + max_w * j[2] / j_max,
                            ],
                        }
                    })
                    .collect()
            }
        }
    }
}

/// ∂p/∂π' = ½ [−eᵀ; e₀ I + ẽ] at p = (e₀, e) (4 × 3).
fn rotation_tangent(p: &Vector4<f64>) -> Matrix4x3<f64> {
    let (e0, e) = (p[0], Vector3::new(p[1], p[2], p[3]));
    let lower = Matrix3::identity() * e0 + e.cross_matrix();
    let mut q = Matrix4x3::zeros();
    q.fixed_view_mut::<1, 3>(0, 0).copy_from(&(-e.transpose()));
    q.fixed_view_mut::<3, 3>(1, 0).copy_from(&lower);
    q * 0.5
}

/// A prepared held run: the least-change solver, the free DOF it holds, and whether it starts
/// from the minimum-norm assembly's pose ([`crate::Results::held_from_assembly`]).
#[derive(Debug)]
pub(crate) struct HeldRun {
    pub(crate) solver: LeastChange,
    pub(crate) held: usize,
    pub(crate) from_assembly: bool,
}

/// One solve's outcome.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LeastChangeReport {
    /// Iterations.
    pub iterations: usize,
    /// Max scaled residual |Φ_i| / e_i at the solution.
    pub residual: f64,
}

/// A point of a body pulled toward a target: the term ½ w ‖r + A s' − target‖² added to the
/// objective (a drag, [`crate::analysis::drag`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PointGoal {
    /// The moving body.
    pub body: usize,
    /// The point, body frame (m).
    pub point: Vector3<f64>,
    /// Where it is pulled (m).
    pub target: Vector3<f64>,
    /// The weight w (1/m²).
    pub weight: f64,
}

/// The least-change solver of a model (module docs): its weights, the pattern of Ĵ and the
/// buffers of an iteration, all sized once.
#[derive(Debug)]
pub struct LeastChange {
    weights: Vec<BodyWeights>,
    /// Pattern of Ĵ: Φ_v's, with each row that touches a body touching all six of its columns.
    pattern: SparsityPattern,
    /// For each slot of Φ_v, its row, and the slot of Ĵ of its row at its body's first column
    /// (the six of the body follow in order).
    targets: Vec<(usize, usize)>,
    qr: MinNormQr,
    slots: Vec<f64>,
    hat: Vec<f64>,
    /// L⁻¹ per body (H = L Lᵀ, 6 × 6).
    l_inv: Vec<Matrix6<f64>>,
    g: Vec<Vector6<f64>>,
    c: Vec<f64>,
    b: Vec<f64>,
    y: Vec<f64>,
    delta: Vec<f64>,
    phi: Vec<f64>,
    /// The rows solved for (all, unless [`keep_rows`](Self::keep_rows) dropped some).
    kept: Vec<bool>,
    /// The pose of the last factorization (7 per body; NaN before the first): rates at a
    /// converged solve's pose reuse its factors.
    factored_x: Vec<f64>,
    /// The pose the change is measured from (7 per body).
    pub(crate) old: Vec<f64>,
    /// A point pulled toward a target, if any.
    pub(crate) goal: Option<PointGoal>,
    /// The weighted negative part of the goal's curvature at the last factorization.
    goal_negative: Matrix3<f64>,
    /// The Newton step's buffers (a dense n × n curvature among them), made at its first use.
    newton: Option<newton::NewtonBuffers>,
}

/// Iteration cap of a least-change solve.
pub const MAX_ITERATIONS: usize = 500;

/// Scaled step (|Δr|/L, |Δθ|) below which a converged least-change iteration stops: near
/// roundoff, since the weights (up to 1e6 against 1e3) amplify what is left of the step in the
/// optimality conditions. An iteration whose step stops shrinking (by [`STAGNATION`]) below
/// [`STAGNATION_STEP`] has reached roundoff and stops too.
pub const STEP_TOLERANCE: f64 = 1e-15;

/// A step at most this small that is no smaller than [`STAGNATION`] times the last one ends the
/// iteration (roundoff reached).
pub const STAGNATION_STEP: f64 = 1e-12;

/// See [`STAGNATION_STEP`].
pub const STAGNATION: f64 = 0.9;

/// A Gauss–Newton step at least this fraction of the one before it switches the solve to
/// Newton steps (`newton.rs`): Gauss–Newton converges linearly at a rate that grows with the
/// distance moved times the constraints' curvature, fast between nearby output times (where
/// the cheaper step is kept) and not at all for a part drawn far from its place.
pub const SLOW_CONTRACTION: f64 = 0.9;

/// Scaled step below which a slow contraction is roundoff, not curvature, and changes nothing.
pub const NEWTON_STEP: f64 = 1e-9;

/// Largest scaled step of one iteration (as the assembly's cap): half the model's size or about
/// 30°.
pub const MAX_STEP: f64 = 0.5;

impl LeastChange {
    /// The solver of `model` with `weights` (one per moving body). Allocates.
    ///
    /// # Errors
    /// A solver error when the pattern cannot be analyzed, or for a model with curve elements
    /// (points on curves, cam pairs).
    pub fn new(model: &Model, weights: Vec<BodyWeights>) -> Result<Self, SolverError> {
        if let Some(c) = model.curves().first() {
            // Its metric is per body (6 × 6 blocks); a curve parameter has no weight yet.
            return Err(SolverError::Backend(format!(
                "the least change does not take curve elements yet ({} \"{}\": its curve parameters have no weight)",
                c.element.what(),
                c.name
            )));
        }
        let (m, n) = (model.num_equations(), model.num_unknowns());
        let src = model.pattern();
        // Each entry's row touches all six columns of its body: sorted (row, column), once.
        let mut entries: Vec<(usize, usize)> = src
            .entries()
            .flat_map(|(r, c)| (0..6).map(move |k| (r, 6 * (c / 6) + k)))
            .collect();
        entries.sort_unstable();
        entries.dedup();
        let slot_of = |e: (usize, usize)| entries.binary_search(&e).unwrap_or_else(|k| k);
        let targets = src
            .entries()
            .map(|(r, c)| (r, slot_of((r, 6 * (c / 6)))))
            .collect();
        let pattern = SparsityPattern::new(m, n, &entries)?;
        let mut qr = MinNormQr::new();
        qr.analyze(&pattern)?;
        let nb = model.num_bodies();
        Ok(Self {
            weights,
            hat: vec![0.0; pattern.num_slots()],
            pattern,
            targets,
            qr,
            slots: vec![0.0; src.num_slots()],
            l_inv: vec![Matrix6::identity(); nb],
            g: vec![Vector6::zeros(); nb],
            c: vec![0.0; n],
            b: vec![0.0; m],
            y: vec![0.0; n],
            delta: vec![0.0; n],
            phi: vec![0.0; m],
            kept: vec![true; m],
            factored_x: vec![f64::NAN; 7 * nb],
            old: vec![0.0; 7 * nb],
            goal: None,
            goal_negative: Matrix3::zeros(),
            newton: None,
        })
    }

    /// Solves for the rows marked in `kept` only (one flag per equation): the redundant rows
    /// of an inconsistent model, dropped as the kinematic solver drops them
    /// (`analysis::dropped`), cannot vanish with the others. Their rows of Ĵ and of the
    /// right-hand side are zero (the minimum-norm factorization gives them no multiplier) and
    /// the convergence test leaves them out.
    pub(crate) fn keep_rows(&mut self, kept: &[bool]) {
        self.kept.copy_from_slice(kept);
        self.factored_x.fill(f64::NAN);
    }

    /// The weights.
    pub fn weights(&self) -> &[BodyWeights] {
        &self.weights
    }

    /// H and g per body at the workspace's poses, H's inverse Cholesky factors, and Ĵ factored.
    /// No allocation.
    fn factor(&mut self, model: &Model, ws: &Workspace, t: f64) -> Result<(), SolverError> {
        let not_definite = || SolverError::Singular {
            dependent_equations: Vec::new(),
        };
        for (b, w) in self.weights.iter().enumerate() {
            let x = &ws.pose.x[7 * b..7 * b + 7];
            let old = &self.old[7 * b..7 * b + 7];
            let p = Vector4::from_column_slice(&x[3..7]);
            let q = rotation_tangent(&p);
            let mut h = Matrix6::zeros();
            h.fixed_view_mut::<3, 3>(0, 0)
                .copy_from(&(Matrix3::identity() * w.translation));
            h.fixed_view_mut::<3, 3>(3, 3)
                .copy_from(&(weighted(&q, &w.rotation) * q));
            let mut g = Vector6::zeros();
            for i in 0..3 {
                g[i] = w.translation * (x[i] - old[i]);
            }
            let dp = Vector4::from_fn(|i, _| w.rotation[i] * (x[3 + i] - old[3 + i]));
            g.fixed_rows_mut::<3>(3).copy_from(&(q.transpose() * dp));
            if let Some(goal) = self.goal.filter(|goal| goal.body == b) {
                // P = r + A s', ∂P/∂[Δr; Δπ'] = [I, −A s̃'] (body-frame rotation increments).
                let a = EulerParams::new(p[0], p[1], p[2], p[3]).a();
                let mut jac = nalgebra::Matrix3x6::zeros();
                jac.fixed_view_mut::<3, 3>(0, 0)
                    .copy_from(&Matrix3::identity());
                jac.fixed_view_mut::<3, 3>(0, 3)
                    .copy_from(&(-(a * goal.point.cross_matrix())));
                let miss = Vector3::new(x[0], x[1], x[2]) + a * goal.point - goal.target;
                h += goal.weight * jac.transpose() * jac;
                g += goal.weight * jac.transpose() * miss;
                // The goal's curvature term (module docs, "The drag goal"), its positive part.
                let (positive, negative) = goal_curvature(&(a.transpose() * miss), &goal.point);
                let mut rot = h.fixed_view_mut::<3, 3>(3, 3);
                rot += goal.weight * positive;
                self.goal_negative = goal.weight * negative;
            }
            let l = h.cholesky().ok_or_else(not_definite)?.l();
            self.l_inv[b] = l.try_inverse().ok_or_else(not_definite)?;
            self.g[b] = g;
        }
        model.jacobian_into(&ws.pose.bodies, ws.pose.u(), t, &mut self.slots);
        self.factored_x.copy_from_slice(&ws.pose.x);
        self.hat.iter_mut().for_each(|h| *h = 0.0);
        let scales = model.equation_scales();
        // Ĵ = J L⁻ᵀ: row r, body b: Ĵ[r, b·] = J[r, b·] L_b⁻ᵀ, i.e. Ĵ[r, 6b+i] = Σ_j J[r, 6b+j] L⁻¹[i, j].
        for (k, (&(r, first), &v)) in self.targets.iter().zip(&self.slots).enumerate() {
            if !self.kept[r] {
                continue;
            }
            let (_, c) = model.pattern().entry(k);
            let (b, j) = (c / 6, c % 6);
            let v = v / scales[r];
            let l_inv = &self.l_inv[b];
            for i in 0..6 {
                self.hat[first + i] += v * l_inv[(i, j)];
            }
        }
        self.qr.factor(&self.hat)
    }

    /// δ = L⁻ᵀ (Ĵ⁺ b − c) for the scaled right-hand side already in `b` (rows / e_r).
    fn step(&mut self) -> Result<(), SolverError> {
        self.qr.solve(&self.b, &mut self.y)?;
        for (b, l_inv) in self.l_inv.iter().enumerate() {
            let z = Vector6::from_fn(|i, _| self.y[6 * b + i] - self.c[6 * b + i]);
            let d = l_inv.transpose() * z;
            self.delta[6 * b..6 * b + 6].copy_from_slice(d.as_slice());
        }
        Ok(())
    }

    /// Moves the workspace's poses to the least change from the pose set as `old` that satisfies
    /// Φ(q, t) = 0 (module docs). No allocation. `tolerance`: the scaled residual.
    ///
    /// # Errors
    /// [`AnalysisError::NotConverged`] naming the worst equations; solver errors.
    pub fn solve(
        &mut self,
        model: &Model,
        ws: &mut Workspace,
        t: f64,
        tolerance: f64,
    ) -> Result<LeastChangeReport, AnalysisError> {
        let l = model.characteristic_length();
        let scales = model.equation_scales();
        ws.pose.t = t;
        let mut last_size = f64::INFINITY;
        let mut newton = false;
        for it in 0..MAX_ITERATIONS {
            self.phi_at(model, ws, t);
            self.factor(model, ws, t)
                .map_err(|e| model.map_solver_error(t, e))?;
            // c = L⁻¹ g.
            for (b, l_inv) in self.l_inv.iter().enumerate() {
                let c = l_inv * self.g[b];
                self.c[6 * b..6 * b + 6].copy_from_slice(c.as_slice());
            }
            // b = (−Φ + Ĵ c) row by row over e_r (Ĵ already scaled).
            self.pattern
                .mul_vec(&self.hat, &self.c, &mut self.b)
                .map_err(|e| model.map_solver_error(t, e))?;
            for (r, bv) in self.b.iter_mut().enumerate() {
                *bv = if self.kept[r] {
                    *bv - self.phi[r] / scales[r]
                } else {
                    0.0
                };
            }
            self.step().map_err(|e| model.map_solver_error(t, e))?;
            if newton {
                self.newton_step(model, ws, t)
                    .map_err(|e| model.map_solver_error(t, e))?;
            }
            let size = scaled_size(&self.delta, l);
            // Gauss–Newton contracting slowly (or capped): the curvature from here on.
            newton |= it >= 1 && size > NEWTON_STEP && size > SLOW_CONTRACTION * last_size;
            if size > MAX_STEP {
                let f = MAX_STEP / size;
                self.delta.iter_mut().for_each(|d| *d *= f);
            }
            let residual = max_scaled(&self.phi, scales, &self.kept);
            let stagnant = size <= STAGNATION_STEP && size >= STAGNATION * last_size;
            last_size = size;
            if residual <= tolerance && (size <= STEP_TOLERANCE || stagnant) {
                return Ok(LeastChangeReport {
                    iterations: it,
                    residual,
                });
            }
            apply_rotation_step(&mut ws.pose.x, &self.delta);
        }
        self.phi_at(model, ws, t);
        Err(AnalysisError::NotConverged {
            time: t,
            iterations: MAX_ITERATIONS,
            worst: worst_rows(model, &self.phi, &self.kept),
            partial: None,
        })
    }

    /// Φ at the workspace's poses (synced first) into `phi`. No allocation.
    fn phi_at(&mut self, model: &Model, ws: &mut Workspace, t: f64) {
        ws.sync_poses();
        let p = &ws.pose;
        model.phi_into(&p.bodies, p.u(), &p.turns, t, &mut self.phi);
    }

    /// Φ at the pose the last [`solve`](Self::solve) ended at, every row (the rows not kept
    /// too: a held run records theirs from it).
    pub(crate) fn residuals(&self) -> &[f64] {
        &self.phi
    }

    /// The H-weighted minimum-norm solution of Φ_v x = `rhs` at the workspace's poses
    /// (velocities with ν, accelerations with γ#; module docs), then in
    /// [`solution`](Self::solution). The factors of the last solve are reused when they were
    /// made at these poses (a converged solve ends there), so a held frame's velocity and
    /// acceleration factor nothing. No allocation.
    ///
    /// # Errors
    /// Solver errors.
    pub fn rates(
        &mut self,
        model: &Model,
        ws: &Workspace,
        rhs: &[f64],
    ) -> Result<(), AnalysisError> {
        let t = ws.pose.t;
        if self.factored_x != ws.pose.x {
            self.factor(model, ws, t)
                .map_err(|e| model.map_solver_error(t, e))?;
        }
        let scales = model.equation_scales();
        for (r, bv) in self.b.iter_mut().enumerate() {
            *bv = if self.kept[r] {
                rhs[r] / scales[r]
            } else {
                0.0
            };
        }
        self.c.iter_mut().for_each(|c| *c = 0.0);
        self.step().map_err(|e| model.map_solver_error(t, e))
    }

    /// The last [`rates`](Self::rates) solution, [ṙ; ω'] (or [r̈; ω̇']) per body.
    pub fn solution(&self) -> &[f64] {
        &self.delta
    }
}

/// Qᵀ diag(w) (3 × 4).
fn weighted(q: &Matrix4x3<f64>, w: &[f64; 4]) -> Matrix3x4<f64> {
    Matrix3x4::from_fn(|i, j| q[(j, i)] * w[j])
}

/// max over bodies of |Δr|/L and |Δθ|.
fn scaled_size(delta: &[f64], l: f64) -> f64 {
    delta
        .chunks(6)
        .map(|d| {
            let r = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt() / l;
            let a = (d[3] * d[3] + d[4] * d[4] + d[5] * d[5]).sqrt();
            r.max(a)
        })
        .fold(0.0, f64::max)
}

/// max |Φ_r| / e_r over the kept rows.
fn max_scaled(phi: &[f64], scales: &[f64], kept: &[bool]) -> f64 {
    (phi.iter().zip(scales).zip(kept))
        .filter(|(_, &k)| k)
        .map(|((p, e), _)| (p / e).abs())
        .fold(0.0, f64::max)
}

/// The three kept equations with the largest scaled residuals, largest first. Allocates (error
/// path).
fn worst_rows(model: &Model, phi: &[f64], kept: &[bool]) -> Vec<(crate::EquationName, f64)> {
    let scales = model.equation_scales();
    let mut rows: Vec<(usize, f64)> = (phi.iter().zip(scales))
        .map(|(p, e)| (p / e).abs())
        .enumerate()
        .filter(|&(r, _)| kept[r])
        .collect();
    rows.sort_by(|a, b| b.1.total_cmp(&a.1));
    rows.iter()
        .take(3)
        .filter_map(|&(r, v)| model.equation(r).map(|n| (n, v)))
        .collect()
}
