//! The sparse path of the static and modal analyses (large models, see
//! [`SPARSE_MIN_BODIES`](crate::sparse_tangent::SPARSE_MIN_BODIES)): saddle-point matrices
//! factored by a sparse LU, and a few lowest modes by shift-invert Lanczos, with no dense
//! null-space basis.
//!
//! ## Theory
//! The modes of the constrained problem K_t x = ω² M x, Φ_v x = 0 (see [`crate::modal`]) are
//! the finite eigenvalues of the augmented pencil
//!
//! ```text
//! ⎡K_t  Φ_vᵀ⎤ ⎡x⎤      ⎡M  0⎤ ⎡x⎤
//! ⎣Φ_v   0  ⎦ ⎣μ⎦ = ω² ⎣0  0⎦ ⎣μ⎦
//! ```
//!
//! With a shift σ, the operator y ↦ x, where
//!
//! ```text
//! ⎡K_t − σM  Φ_vᵀ⎤ ⎡x⎤   ⎡M y⎤
//! ⎣  Φ_v      0  ⎦ ⎣μ⎦ = ⎣ 0 ⎦
//! ```
//!
//! maps into the constraint subspace Φ_v x = 0 and is symmetric in the M inner product there,
//! with eigenvalues θ = 1/(ω² − σ): the modes nearest the shift become the largest θ (Ericsson
//! & Ruhe 1980; Géradin & Cardona 2001 §10.4 for the constrained pencil). Lanczos' method in
//! the M inner product, with full reorthogonalization (twice), builds the tridiagonal
//! projection T; its eigenpairs (θ_i, s_i) give ω_i² = σ + 1/θ_i and the Ritz vectors, and
//! the pair has converged when the residual bound |β_m s_i,m| ≤ 1e-10 |θ_i| (Parlett 1998 §13).
//! One sparse LU of the shifted saddle-point matrix serves all the iterations.
//!
//! The shift σ = −10⁻⁶ κ with κ the largest ratio of a diagonal entry of K_t to that of M: below
//! the elastic spectrum (stable models), away from the rigid modes at ω² = 0 (the shifted matrix
//! is nonsingular there) and close enough to the lowest modes that a few tens of Lanczos steps
//! suffice. Rigid modes are those with |ω²| ≤ 10⁻¹⁰ κ + 10⁻¹²; unstable ones have ω² below that.
//!
//! Damping: the sparse path computes the undamped modes; with dampers, each mode's damping
//! ratio is the modal projection ζ = xᵀC_t x / (2ω xᵀMx) (exact for proportional damping, a
//! first-order estimate for light damping; the dense path solves the damped problem exactly).

use crate::modal::{Mode, ModeKind};
use crate::sparse_tangent::{BodyGraph, SparseMatrix};
use crate::state::State;
use crate::statics::{Equilibrium, StaticOptions, StaticResults};
use crate::system::Dynamics;
use crate::DynamicsError;
use cardan_mechanism::BodyId;
use cardan_solver::{AutoSolver, LinearSolver, SolverError, SparsityPattern};
use nalgebra::{DMatrix, DVector};

/// Residual bound of a converged Ritz pair, relative to |θ|.
const LANCZOS_TOL: f64 = 1e-10;

/// The shift σ = −SHIFT_FRACTION κ (module docs).
const SHIFT_FRACTION: f64 = 1e-6;

/// Rigid modes: |ω²| ≤ RIGID_FRACTION κ + 1e-12 (module docs). A converged Ritz value is
/// accurate to about 1e-10 |σ| = 1e-16 κ, so rigid modes come out far below this, while the
/// lowest elastic modes of long chains lie well above it (a hanging chain of 10,000 rods:
/// κ ≈ 3e5, ω₁² ≈ 1.4e-3). SHIFT_FRACTION itself, as the threshold, called those rigid.
const RIGID_FRACTION: f64 = 1e-10;

/// The saddle-point matrix [a_k K + a_m M, Φ_vᵀ; Φ_v, 0] of the sparse path, laid out once and
/// factored by [`AutoSolver`] (sparse LU for large models).
pub(crate) struct SparseKkt {
    n: usize,
    k_vals: Vec<f64>,
    m_vals: Vec<f64>,
    j_vals: Vec<f64>,
    solver: AutoSolver,
    slots: Vec<f64>,
    sol: Vec<f64>,
    rhs: Vec<f64>,
}

impl SparseKkt {
    /// Lays out K (may be empty), the block-diagonal M of `mass`, `inertia` and Φ_v (triplets
    /// on `ma` active rows).
    pub fn new(
        k: &SparseMatrix,
        mass: &[f64],
        inertia: &[nalgebra::Matrix3<f64>],
        jac: &[(usize, usize, f64)],
        ma: usize,
    ) -> Result<Self, SolverError> {
        let n = 6 * mass.len();
        let mut pos: Vec<(usize, usize)> = k.entries.iter().map(|e| (e.0, e.1)).collect();
        let mut m_vals = Vec::with_capacity(12 * mass.len());
        for (b, (&m, j)) in mass.iter().zip(inertia).enumerate() {
            for a in 0..3 {
                pos.push((6 * b + a, 6 * b + a));
                m_vals.push(m);
            }
            for r in 0..3 {
                for c in 0..3 {
                    pos.push((6 * b + 3 + r, 6 * b + 3 + c));
                    m_vals.push(j[(r, c)]);
                }
            }
        }
        for &(r, c, _) in jac {
            pos.push((n + r, c));
        }
        for &(r, c, _) in jac {
            pos.push((c, n + r));
        }
        let size = n + ma;
        let pattern = SparsityPattern::new(size, size, &pos)?;
        let mut solver = AutoSolver::default();
        solver.analyze(&pattern)?;
        Ok(Self {
            n,
            k_vals: k.entries.iter().map(|e| e.2).collect(),
            m_vals,
            j_vals: jac.iter().map(|e| e.2).collect(),
            solver,
            slots: vec![0.0; pos.len()],
            sol: vec![0.0; size],
            rhs: vec![0.0; size],
        })
    }

    /// Factors with the top-left a_k K + a_m M.
    pub fn factor(&mut self, a_k: f64, a_m: f64) -> Result<(), SolverError> {
        let (nk, nm, nj) = (self.k_vals.len(), self.m_vals.len(), self.j_vals.len());
        for (s, v) in self.slots[..nk].iter_mut().zip(&self.k_vals) {
            *s = a_k * v;
        }
        for (s, v) in self.slots[nk..nk + nm].iter_mut().zip(&self.m_vals) {
            *s = a_m * v;
        }
        self.slots[nk + nm..nk + nm + nj].copy_from_slice(&self.j_vals);
        self.slots[nk + nm + nj..].copy_from_slice(&self.j_vals);
        self.solver.factor(&self.slots)
    }

    /// Solves with the last factorization: [x; μ] for the right-hand side [top; bottom].
    pub fn solve(&mut self, top: &[f64], bottom: &[f64]) -> Result<&[f64], SolverError> {
        self.rhs[..self.n].copy_from_slice(top);
        self.rhs[self.n..].copy_from_slice(bottom);
        self.solver.solve(&self.rhs, &mut self.sol)?;
        if self.sol.iter().any(|v| !v.is_finite()) {
            // A non-finite solution: the shifted matrix is numerically singular.
            return Err(SolverError::Singular {
                dependent_equations: Vec::new(),
            });
        }
        Ok(&self.sol)
    }
}

/// The Newton matrix [K_t + μM, Φ_vᵀ; Φ_v, 0] of the static solve on the sparse path.
pub(crate) struct SparseNewton {
    kkt: SparseKkt,
    /// The start of the shift μ (as the dense path's `shift_scale`).
    pub shift_scale: f64,
}

impl SparseNewton {
    /// The Newton step for the shift `mu`: the solution of the saddle-point system with the
    /// right-hand side `rhs` (n + m_a), `None` when the matrix is singular.
    pub fn solve_shifted(&mut self, mu: f64, rhs: &DVector<f64>) -> Option<DVector<f64>> {
        self.kkt.factor(1.0, mu).ok()?;
        let n = self.kkt.n;
        let x = self
            .kkt
            .solve(&rhs.as_slice()[..n], &rhs.as_slice()[n..])
            .ok()?;
        Some(DVector::from_column_slice(x))
    }
}

/// A few lowest modes of the constrained pencil (module docs).
#[derive(Debug, Clone)]
pub(crate) struct LowestModes {
    /// ω² ascending.
    pub values: Vec<f64>,
    /// M-normalized directions δ (n each).
    pub vectors: Vec<Vec<f64>>,
    /// All asked pairs converged.
    pub converged: bool,
    /// Lanczos steps (= solves) taken.
    pub steps: usize,
    /// κ: the largest diagonal ratio of K_t to M (the scale of the rigid-mode threshold).
    pub scale: f64,
}

/// The results of a modal analysis on the sparse path ([`Dynamics::modal_sparse`]).
#[derive(Debug, Clone, PartialEq)]
pub struct SparseModalResults {
    /// The equilibrium (one output time).
    pub equilibrium: StaticResults,
    /// The lowest modes, by increasing frequency (unstable, then rigid, then elastic).
    pub modes: Vec<Mode>,
    /// K_t (n × n, sparse).
    pub stiffness: SparseMatrix,
    /// C_t (n × n, sparse).
    pub damping: SparseMatrix,
    /// Lanczos steps (solves with the one factorization).
    pub lanczos_steps: usize,
    /// Whether every asked mode converged (module docs); `false` is reported as a warning.
    pub converged: bool,
}

impl Dynamics<'_> {
    /// Φ_v on the rows `active` as triplets (active-row index, column, value) at the synced
    /// bodies.
    pub(crate) fn phi_v_triplets(&self, t: f64, active: &[usize]) -> Vec<(usize, usize, f64)> {
        let model = self.model;
        let mut of = vec![usize::MAX; model.num_equations()];
        for (a, &r) in active.iter().enumerate() {
            of[r] = a;
        }
        let mut out = Vec::new();
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
                            out.push((a, 6 * k + c, blk[lr][c]));
                        }
                    }
                }
            }
        }
        out
    }

    /// y = M x (block-diagonal mass matrix).
    pub(crate) fn mass_mul(&self, x: &[f64]) -> Vec<f64> {
        block_mass_mul(&self.mass, &self.inertia, x)
    }

    /// The saddle-point layout with K (possibly empty) at the synced bodies.
    fn sparse_kkt(
        &self,
        k: &SparseMatrix,
        t: f64,
        active: &[usize],
    ) -> Result<SparseKkt, DynamicsError> {
        let jac = self.phi_v_triplets(t, active);
        SparseKkt::new(k, &self.mass, &self.inertia, &jac, active.len())
            .map_err(|e| self.solver_error(t, e))
    }

    /// The Newton matrix of the static solve at `state` (sparse path).
    pub(crate) fn sparse_newton(
        &mut self,
        graph: &BodyGraph,
        state: &State,
        lambda: &[f64],
        s: f64,
        active: &[usize],
        f: f64,
    ) -> Result<SparseNewton, DynamicsError> {
        let k = self.static_tangent_sparse(graph, state, lambda, s);
        let kappa = self.diagonal_ratio(&k);
        let shift_scale = if kappa > 0.0 {
            0.1 * kappa
        } else {
            let mmax = self.mass.iter().fold(0.0f64, |a, &m| a.max(m));
            0.1 * (f / (self.model.characteristic_length() * mmax)).max(1e-12)
        };
        self.sync(state);
        let kkt = self.sparse_kkt(&k, state.t, active)?;
        Ok(SparseNewton { kkt, shift_scale })
    }

    /// κ = max |K_cc| / M_cc over the diagonal.
    fn diagonal_ratio(&self, k: &SparseMatrix) -> f64 {
        let mut kappa = 0.0f64;
        for &(r, c, v) in &k.entries {
            if r == c {
                let b = r / 6;
                let m = if r % 6 < 3 {
                    self.mass[b]
                } else {
                    self.inertia[b][(r % 6 - 3, r % 6 - 3)]
                };
                kappa = kappa.max((v / m).abs());
            }
        }
        kappa
    }

    /// The multipliers at rest (as the dense `rest_multipliers`): [M Φ_vᵀ; Φ_v 0] [x; λ] =
    /// [h_s; 0] by the sparse LU (full rows, 0 on dropped rows and on failure).
    pub(crate) fn rest_multipliers_sparse(
        &mut self,
        state: &State,
        s: f64,
        active: &[usize],
    ) -> Vec<f64> {
        self.sync(state);
        self.eval_static_forces(state.t, s);
        let h = self.h.clone();
        let mut lambda = vec![0.0; self.model.num_equations()];
        let Ok(mut kkt) = self.sparse_kkt(&SparseMatrix::default(), state.t, active) else {
            return lambda;
        };
        if kkt.factor(0.0, 1.0).is_err() {
            return lambda;
        }
        let zero = vec![0.0; active.len()];
        if let Ok(x) = kkt.solve(&h, &zero) {
            let n = h.len();
            for (a, &r) in active.iter().enumerate() {
                lambda[r] = x[n + a];
            }
        }
        lambda
    }

    /// The `nev` lowest modes of the constrained pencil at `state` (multipliers `lambda`, load
    /// factor `s`) by shift-invert Lanczos (module docs).
    pub(crate) fn lowest_modes(
        &mut self,
        graph: &BodyGraph,
        state: &State,
        lambda: &[f64],
        s: f64,
        active: &[usize],
        nev: usize,
    ) -> Result<(LowestModes, SparseMatrix), DynamicsError> {
        let k = self.static_tangent_sparse(graph, state, lambda, s);
        if k.entries.iter().any(|e| !e.2.is_finite()) {
            return Err(DynamicsError::NonFinite {
                time: state.t,
                what: "the tangent stiffness",
            });
        }
        self.sync(state);
        let n = state.v.len();
        let d = n.saturating_sub(active.len());
        let kappa = self.diagonal_ratio(&k).max(1e-12);
        let empty = LowestModes {
            values: Vec::new(),
            vectors: Vec::new(),
            converged: true,
            steps: 0,
            scale: kappa,
        };
        if d == 0 || nev == 0 {
            return Ok((empty, k));
        }
        let mut kkt = self.sparse_kkt(&k, state.t, active)?;
        let mut sigma = -SHIFT_FRACTION * kappa;
        // A singular shifted matrix (σ an eigenvalue, or a singular configuration): move σ.
        let mut tries = 0;
        while let Err(e) = kkt.factor(1.0, -sigma) {
            tries += 1;
            if tries > 3 {
                return Err(self.solver_error(state.t, e));
            }
            sigma *= 7.3;
        }
        let zero = vec![0.0; active.len()];
        let (mass, inertia) = (&self.mass, &self.inertia);
        let mass_mul = |y: &[f64]| block_mass_mul(mass, inertia, y);
        let mut op = |y: &[f64]| -> Result<Vec<f64>, SolverError> {
            let my = mass_mul(y);
            Ok(kkt.solve(&my, &zero)?[..n].to_vec())
        };
        let modes = lanczos(&mut op, &mass_mul, n, d, nev, sigma, kappa)
            .map_err(|e| self.solver_error(state.t, e))?;
        Ok((modes, k))
    }

    /// Eigenvalues ω² (ascending) of the `nev` lowest modes at `state` and their directions
    /// (columns, n each): the sparse counterpart of the dense `reduced_eigen`.
    pub(crate) fn reduced_eigen_sparse(
        &mut self,
        state: &State,
        lambda: &[f64],
        s: f64,
        active: &[usize],
        nev: usize,
    ) -> Result<(Vec<f64>, DMatrix<f64>), DynamicsError> {
        let graph = self.body_graph();
        let (modes, _) = self.lowest_modes(&graph, state, lambda, s, active, nev)?;
        let n = state.v.len();
        let mut x = DMatrix::zeros(n, modes.vectors.len());
        for (c, v) in modes.vectors.iter().enumerate() {
            x.set_column(c, &DVector::from_column_slice(v));
        }
        Ok((modes.values, x))
    }

    /// Modal analysis on the sparse path: the static equilibrium ([`Dynamics::statics`], which
    /// takes the sparse path itself for large models) and its `modes` lowest modes by
    /// shift-invert Lanczos (module docs). Usable at any size (the tests compare it with the
    /// dense [`Dynamics::modal`] on small models).
    ///
    /// # Errors
    /// As [`Dynamics::statics`]; [`DynamicsError::NonFinite`] for a non-finite tangent;
    /// solver errors when the shifted saddle-point matrix stays singular.
    pub fn modal_sparse(
        &mut self,
        statics: &StaticOptions,
        modes: usize,
    ) -> Result<SparseModalResults, DynamicsError> {
        let equilibrium = self.statics(statics)?;
        let eq = equilibrium.equilibria[0].clone();
        let found = self.sparse_modes(&eq, modes)?;
        Ok(SparseModalResults {
            equilibrium,
            modes: found.modes,
            stiffness: found.stiffness,
            damping: found.damping,
            lanczos_steps: found.lanczos_steps,
            converged: found.converged,
        })
    }

    /// The `nev` lowest modes about the equilibrium `eq` (found by this [`Dynamics`]) on the
    /// sparse path, with K_t, C_t, the Lanczos steps and whether all converged.
    fn sparse_modes(&mut self, eq: &Equilibrium, nev: usize) -> Result<SparseModes, DynamicsError> {
        let state = &eq.state;
        if self.kkt.is_none() {
            self.prepare(state)?;
        }
        let active: Vec<usize> = self
            .kkt
            .as_ref()
            .map(|k| k.active.clone())
            .unwrap_or_default();
        let graph = self.body_graph();
        let (low, k) = self.lowest_modes(&graph, state, &eq.lambda, 1.0, &active, nev)?;
        let c = self.damping_tangent_sparse(&graph, state);
        if c.entries.iter().any(|e| !e.2.is_finite()) {
            return Err(DynamicsError::NonFinite {
                time: state.t,
                what: "the tangent damping",
            });
        }
        let thr = RIGID_FRACTION * low.scale + 1e-12;
        let two_pi = 2.0 * std::f64::consts::PI;
        let mut modes = Vec::new();
        for (&w2, x) in low.values.iter().zip(&low.vectors) {
            let kind = if w2 < -thr {
                ModeKind::Unstable
            } else if w2 <= thr {
                ModeKind::Rigid
            } else {
                ModeKind::Elastic
            };
            let (f, fd, zeta, s) = match kind {
                ModeKind::Rigid => (0.0, 0.0, 0.0, [0.0, 0.0]),
                ModeKind::Unstable => {
                    let r = (-w2).sqrt();
                    (r / two_pi, 0.0, 0.0, [r, 0.0])
                }
                _ => {
                    let w = w2.sqrt();
                    let cx = c.mul(x);
                    let mx = self.mass_mul(x);
                    let xcx: f64 = x.iter().zip(&cx).map(|(a, b)| a * b).sum();
                    let xmx: f64 = x.iter().zip(&mx).map(|(a, b)| a * b).sum();
                    let zeta = xcx / (2.0 * w * xmx);
                    let wd = w * (1.0 - zeta * zeta).max(0.0).sqrt();
                    (w / two_pi, wd / two_pi, zeta, [-zeta * w, wd])
                }
            };
            let kind = if kind == ModeKind::Elastic && zeta >= 1.0 {
                ModeKind::Overdamped
            } else {
                kind
            };
            modes.push(self.mode(state, kind, f, fd, zeta, s, x));
        }
        modes.sort_by(|a, b| {
            let key = |m: &Mode| match m.kind {
                ModeKind::Unstable => (0, m.frequency),
                ModeKind::Rigid => (1, 0.0),
                _ => (2, m.frequency),
            };
            let (ka, kb) = (key(a), key(b));
            ka.0.cmp(&kb.0).then(ka.1.total_cmp(&kb.1))
        });
        Ok(SparseModes {
            modes,
            stiffness: k,
            damping: c,
            lanczos_steps: low.steps,
            converged: low.converged,
        })
    }
}

/// The lowest modes about an equilibrium on the sparse path ([`SparseModalResults`] without
/// the equilibrium).
struct SparseModes {
    modes: Vec<Mode>,
    /// K_t.
    stiffness: SparseMatrix,
    /// C_t.
    damping: SparseMatrix,
    lanczos_steps: usize,
    converged: bool,
}

/// Shift-invert Lanczos in the M inner product with full reorthogonalization (module docs):
/// the `nev` eigenpairs of the pencil nearest the shift `sigma`. `op(y)` applies the
/// shift-inverted operator; the subspace dimension is at most `d`.
fn lanczos(
    op: &mut impl FnMut(&[f64]) -> Result<Vec<f64>, SolverError>,
    mass_mul: &impl Fn(&[f64]) -> Vec<f64>,
    n: usize,
    d: usize,
    nev: usize,
    sigma: f64,
    kappa: f64,
) -> Result<LowestModes, SolverError> {
    let nev = nev.min(d);
    let max_steps = d.min((10 * nev).max(nev + 100));
    let dot = |a: &[f64], b: &[f64]| a.iter().zip(b).map(|(x, y)| x * y).sum::<f64>();
    // A start vector with every component present, mapped into the constraint subspace.
    let start: Vec<f64> = (0..n)
        .map(|i| 1.0 + 0.37 * ((i as f64) * 0.7).sin())
        .collect();
    let mut w = op(&start)?;
    let mut vs: Vec<Vec<f64>> = Vec::new();
    let mut mvs: Vec<Vec<f64>> = Vec::new();
    let mut alpha: Vec<f64> = Vec::new();
    let mut beta: Vec<f64> = Vec::new();
    let mut steps = 1;
    let mut result = None;
    loop {
        let mw = mass_mul(&w);
        let b = dot(&w, &mw).max(0.0).sqrt();
        let breakdown = b <= 1e-13 * alpha.iter().fold(1e-300f64, |a, x| a.max(x.abs()));
        if !vs.is_empty() {
            beta.push(b);
        }
        let m = vs.len();
        let check = m >= nev && (m.is_multiple_of(5) || m >= max_steps || breakdown);
        if check {
            let r = ritz(&vs, &alpha, &beta, b, nev, breakdown);
            if r.converged || m >= max_steps || breakdown {
                result = Some(r);
                break;
            }
        }
        if breakdown {
            break;
        }
        let v: Vec<f64> = w.iter().map(|x| x / b).collect();
        let mv: Vec<f64> = mw.iter().map(|x| x / b).collect();
        w = op(&v)?;
        steps += 1;
        let a = dot(&mv, &w);
        for (x, (vi, pv)) in w.iter_mut().zip(v.iter().zip(vs.last().map_or(&v, |p| p))) {
            *x -= a * vi;
            if let Some(&bl) = beta.last() {
                *x -= bl * pv;
            }
        }
        alpha.push(a);
        vs.push(v);
        mvs.push(mv);
        for _ in 0..2 {
            for (vi, mvi) in vs.iter().zip(&mvs) {
                let c = dot(mvi, &w);
                for (x, y) in w.iter_mut().zip(vi) {
                    *x -= c * y;
                }
            }
        }
    }
    let Some(Ritz {
        thetas,
        coefficients: coeffs,
        converged,
        dimension: m,
    }) = result
    else {
        return Ok(LowestModes {
            values: Vec::new(),
            vectors: Vec::new(),
            converged: false,
            steps,
            scale: kappa,
        });
    };
    let mut pairs: Vec<(f64, Vec<f64>)> = thetas
        .iter()
        .zip(&coeffs)
        .map(|(&th, s)| {
            let mut x = vec![0.0; n];
            for (j, &sj) in s.iter().enumerate().take(m) {
                for (xi, vj) in x.iter_mut().zip(&vs[j]) {
                    *xi += sj * vj;
                }
            }
            (sigma + 1.0 / th, x)
        })
        .collect();
    pairs.sort_by(|a, b| a.0.total_cmp(&b.0));
    Ok(LowestModes {
        values: pairs.iter().map(|p| p.0).collect(),
        vectors: pairs.into_iter().map(|p| p.1).collect(),
        converged,
        steps,
        scale: kappa,
    })
}

/// The `nev` Ritz pairs of largest |θ| of the Lanczos tridiagonal (diagonal `alpha`,
/// off-diagonal `beta[..m-1]`, next β `b`), with their coefficient vectors, and whether all
/// converged (|b s_m| ≤ tol |θ|, or an invariant subspace).
fn ritz(vs: &[Vec<f64>], alpha: &[f64], beta: &[f64], b: f64, nev: usize, breakdown: bool) -> Ritz {
    let m = vs.len();
    let mut t = DMatrix::zeros(m, m);
    for i in 0..m {
        t[(i, i)] = alpha[i];
        if i + 1 < m {
            t[(i, i + 1)] = beta[i];
            t[(i + 1, i)] = beta[i];
        }
    }
    let eig = t.symmetric_eigen();
    let mut order: Vec<usize> = (0..m).collect();
    order.sort_by(|&i, &j| {
        eig.eigenvalues[j]
            .abs()
            .total_cmp(&eig.eigenvalues[i].abs())
    });
    let mut converged = true;
    let mut thetas = Vec::new();
    let mut coeffs = Vec::new();
    for &i in order.iter().take(nev) {
        let th = eig.eigenvalues[i];
        let s = eig.eigenvectors.column(i);
        if !breakdown && (b * s[m - 1]).abs() > LANCZOS_TOL * th.abs() {
            converged = false;
        }
        thetas.push(th);
        coeffs.push(s.iter().copied().collect());
    }
    Ritz {
        thetas,
        coefficients: coeffs,
        converged,
        dimension: m,
    }
}

/// Ritz pairs of a Lanczos tridiagonal ([`ritz`]).
struct Ritz {
    /// θ, largest |θ| first.
    thetas: Vec<f64>,
    /// Each θ's coefficients over the Lanczos vectors.
    coefficients: Vec<Vec<f64>>,
    /// All converged.
    converged: bool,
    /// The subspace dimension m (Lanczos vectors).
    dimension: usize,
}

/// y = M x for the block-diagonal mass matrix diag(m_k I, J'_k).
fn block_mass_mul(mass: &[f64], inertia: &[nalgebra::Matrix3<f64>], x: &[f64]) -> Vec<f64> {
    let mut y = vec![0.0; x.len()];
    for (k, (&m, j)) in mass.iter().zip(inertia).enumerate() {
        for a in 0..3 {
            y[6 * k + a] = m * x[6 * k + a];
            y[6 * k + 3 + a] = (0..3).map(|b| j[(a, b)] * x[6 * k + 3 + b]).sum();
        }
    }
    y
}
