//! The augmented (KKT) system of the equations of motion, laid out once:
//!
//! ```text
//! ⎡ M   Φ_vᵀ ⎤ ⎡ v̇ ⎤   ⎡ h  ⎤
//! ⎣ Φ_v  0   ⎦ ⎣ λ ⎦ = ⎣ γ# ⎦
//! ```
//!
//! n = 6 nb unknowns and the m_a active (independent) constraint rows. The top-left holds a
//! full 6×6 block per body (M_k = diag(m_k I, J'_k), or the implicit method's iteration matrix
//! M + γ' C_t + β' K_t) and 6×6 coupling blocks for each two-body force element; Φ_v and Φ_vᵀ
//! get six entries per active row and moving body of its element. The slot layout is fixed, so
//! a step refills values and refactors ([`cardan_solver::AutoSolver`]: dense LU for small
//! models, sparse LU for large; never a dense inverse of M).

use cardan_constraints::{BodyPair, BodyState, Constraint};
use cardan_mechanism::{BodyId, Model};
use cardan_solver::{AutoSolver, LinearSolver, SolverError, SparsityPattern};
use std::ops::Range;

/// One joint or driver: its rows, bodies.
#[derive(Debug, Clone)]
pub(crate) struct Element {
    pub rows: Range<usize>,
    pub bi: BodyId,
    pub bj: BodyId,
    /// Joint index, or `joints.len() + driver index`.
    pub index: usize,
}

pub(crate) fn elements(model: &Model) -> Vec<Element> {
    let nj = model.joints().len();
    let mut v: Vec<Element> = model
        .joints()
        .iter()
        .enumerate()
        .map(|(k, j)| Element {
            rows: j.rows.clone(),
            bi: j.body_i,
            bj: j.body_j,
            index: k,
        })
        .collect();
    v.extend(model.drivers().iter().enumerate().map(|(k, d)| Element {
        rows: d.rows.clone(),
        bi: d.body_i,
        bj: d.body_j,
        index: nj + k,
    }));
    v
}

fn st<'a>(bodies: &'a [BodyState], g: &'a BodyState, id: BodyId) -> &'a BodyState {
    match id {
        BodyId::Ground => g,
        BodyId::Moving(k) => &bodies[k],
    }
}

/// Evaluates one element's Φ_v blocks (rows × 6 for body i and j).
pub(crate) fn element_blocks(
    model: &Model,
    e: &Element,
    bodies: &[BodyState],
    t: f64,
    bi: &mut [[f64; 6]; 6],
    bj: &mut [[f64; 6]; 6],
) {
    let g = BodyState::ground();
    let pair = BodyPair::new(st(bodies, &g, e.bi), st(bodies, &g, e.bj));
    let n = e.rows.len();
    let nj = model.joints().len();
    if e.index < nj {
        model.joints()[e.index]
            .joint
            .phi_v(&pair, t, &mut bi[..n], &mut bj[..n]);
    } else {
        model.drivers()[e.index - nj]
            .driver
            .phi_v(&pair, t, &mut bi[..n], &mut bj[..n]);
    }
}

/// Which vector of an element to evaluate.
#[derive(Clone, Copy)]
pub(crate) enum Rhs {
    Phi,
    Nu,
    Gamma,
}

/// Φ, ν or γ#_v of all model rows. No allocation.
pub(crate) fn eval_rows(
    model: &Model,
    elements: &[Element],
    bodies: &[BodyState],
    t: f64,
    what: Rhs,
    out: &mut [f64],
) {
    let g = BodyState::ground();
    let nj = model.joints().len();
    for e in elements {
        let pair = BodyPair::new(st(bodies, &g, e.bi), st(bodies, &g, e.bj));
        let o = &mut out[e.rows.clone()];
        if e.index < nj {
            let c = &model.joints()[e.index].joint;
            match what {
                Rhs::Phi => c.phi(&pair, t, o),
                Rhs::Nu => c.nu(&pair, t, o),
                Rhs::Gamma => c.gamma_sharp_v(&pair, t, o),
            }
        } else {
            let c = &model.drivers()[e.index - nj].driver;
            match what {
                Rhs::Phi => c.phi(&pair, t, o),
                Rhs::Nu => c.nu(&pair, t, o),
                Rhs::Gamma => c.gamma_sharp_v(&pair, t, o),
            }
        }
    }
}

/// One Φ_v entry: active row a, column c, its KKT slots (Φ_v and Φ_vᵀ).
#[derive(Debug, Clone, Copy)]
struct Entry {
    row: usize,
    col: usize,
    slot: usize,
    slot_t: usize,
}

/// The laid-out KKT system and its solver.
#[derive(Debug)]
pub(crate) struct Kkt {
    pub n: usize,
    /// Active model rows, increasing.
    pub active: Vec<usize>,
    /// Position of each model row among the active rows (usize::MAX if dropped).
    pub active_of: Vec<usize>,
    solver: AutoSolver,
    pub slots: Vec<f64>,
    /// Top-left block slots: (row, col, slot).
    top: Vec<(usize, usize, usize)>,
    entries: Vec<Entry>,
    /// Φ_v values aligned with `entries`.
    pub jac: Vec<f64>,
    pub rhs: Vec<f64>,
    pub sol: Vec<f64>,
    /// All-row buffers (m).
    pub full: Vec<f64>,
    /// Scratch of length n.
    pub work_n: Vec<f64>,
    /// Scratch of length m_a.
    pub work_a: Vec<f64>,
    pub factorizations: usize,
}

impl Kkt {
    /// Lays out the system. `pairs`: body pairs coupled by force elements.
    pub fn new(
        model: &Model,
        elements: &[Element],
        active: Vec<usize>,
        pairs: &[(usize, usize)],
    ) -> Result<Self, SolverError> {
        let nb = model.num_bodies();
        let n = 6 * nb;
        let m = model.num_equations();
        let mut active_of = vec![usize::MAX; m];
        for (a, &r) in active.iter().enumerate() {
            active_of[r] = a;
        }
        let mut pos: Vec<(usize, usize)> = Vec::new();
        let mut top = Vec::new();
        let mut block = |bi: usize, bj: usize, pos: &mut Vec<(usize, usize)>| {
            for r in 0..6 {
                for c in 0..6 {
                    top.push((6 * bi + r, 6 * bj + c, pos.len()));
                    pos.push((6 * bi + r, 6 * bj + c));
                }
            }
        };
        for k in 0..nb {
            block(k, k, &mut pos);
        }
        let mut seen: Vec<(usize, usize)> = Vec::new();
        for &(i, j) in pairs {
            let key = (i.min(j), i.max(j));
            if i != j && !seen.contains(&key) {
                seen.push(key);
                block(i, j, &mut pos);
                block(j, i, &mut pos);
            }
        }
        let mut entries = Vec::new();
        for e in elements {
            for r in e.rows.clone() {
                let a = active_of[r];
                if a == usize::MAX {
                    continue;
                }
                for id in [e.bi, e.bj] {
                    if let BodyId::Moving(k) = id {
                        for c in 0..6 {
                            let col = 6 * k + c;
                            entries.push(Entry {
                                row: a,
                                col,
                                slot: pos.len(),
                                slot_t: pos.len() + 1,
                            });
                            pos.push((n + a, col));
                            pos.push((col, n + a));
                        }
                    }
                }
            }
        }
        let size = n + active.len();
        let pattern = SparsityPattern::new(size, size, &pos)?;
        let mut solver = AutoSolver::default();
        solver.analyze(&pattern)?;
        let ns = pattern.num_slots();
        let ne = entries.len();
        Ok(Self {
            n,
            active_of,
            solver,
            slots: vec![0.0; ns],
            top,
            entries,
            jac: vec![0.0; ne],
            rhs: vec![0.0; size],
            sol: vec![0.0; size],
            full: vec![0.0; m],
            work_n: vec![0.0; n],
            work_a: vec![0.0; active.len()],
            active,
            factorizations: 0,
        })
    }

    /// Evaluates Φ_v at the bodies' poses into `jac` (and the KKT slots). No allocation.
    pub fn eval_jacobian(
        &mut self,
        model: &Model,
        elements: &[Element],
        bodies: &[BodyState],
        t: f64,
    ) {
        let mut bi = [[0.0; 6]; 6];
        let mut bj = [[0.0; 6]; 6];
        let mut cursor = 0;
        for e in elements {
            let any_active = e.rows.clone().any(|r| self.active_of[r] != usize::MAX);
            if !any_active {
                continue;
            }
            element_blocks(model, e, bodies, t, &mut bi, &mut bj);
            for (lr, r) in e.rows.clone().enumerate() {
                if self.active_of[r] == usize::MAX {
                    continue;
                }
                for (id, blk) in [(e.bi, &bi), (e.bj, &bj)] {
                    if let BodyId::Moving(_) = id {
                        for c in 0..6 {
                            let en = self.entries[cursor];
                            let v = blk[lr][c];
                            self.jac[cursor] = v;
                            self.slots[en.slot] = v;
                            self.slots[en.slot_t] = v;
                            cursor += 1;
                        }
                    }
                }
            }
        }
        debug_assert_eq!(cursor, self.entries.len());
    }

    /// Sets the top-left to M = diag(m I, J') per body (coupling blocks zero).
    pub fn set_mass(&mut self, mass: &[f64], inertia: &[nalgebra::Matrix3<f64>]) {
        for &(r, c, s) in &self.top {
            self.slots[s] = mass_entry(mass, inertia, r, c);
        }
    }

    /// Adds `f(row, col)` to the top-left entries (for tangent terms).
    pub fn add_top(&mut self, mut f: impl FnMut(usize, usize) -> f64) {
        for &(r, c, s) in &self.top {
            self.slots[s] += f(r, c);
        }
    }

    /// Factors the current slots.
    pub fn factor(&mut self) -> Result<(), SolverError> {
        self.factorizations += 1;
        self.solver.factor(&self.slots)
    }

    /// Solves with `rhs` into `sol`.
    pub fn solve(&mut self) -> Result<(), SolverError> {
        self.solver.solve(&self.rhs, &mut self.sol)
    }

    /// y (active rows) = Φ_v x.
    pub fn phi_v_mul(&self, x: &[f64], y: &mut [f64]) {
        y.fill(0.0);
        for (e, v) in self.entries.iter().zip(&self.jac) {
            y[e.row] += v * x[e.col];
        }
    }

    /// y (n) += |Φ_vᵀ| |λ| (entrywise absolute values: the size of the terms of Φ_vᵀλ).
    pub fn phi_v_t_abs_mul_add(&self, lambda: &[f64], y: &mut [f64]) {
        for (e, v) in self.entries.iter().zip(&self.jac) {
            y[e.col] += (v * lambda[e.row]).abs();
        }
    }

    /// y (n) += Φ_vᵀ λ (λ over active rows).
    pub fn phi_v_t_mul_add(&self, lambda: &[f64], y: &mut [f64]) {
        for (e, v) in self.entries.iter().zip(&self.jac) {
            y[e.col] += v * lambda[e.row];
        }
    }
}

/// Entry (r, c) of the block-diagonal M.
pub(crate) fn mass_entry(
    mass: &[f64],
    inertia: &[nalgebra::Matrix3<f64>],
    r: usize,
    c: usize,
) -> f64 {
    let (k, l) = (r / 6, c / 6);
    if k != l {
        return 0.0;
    }
    let (a, b) = (r % 6, c % 6);
    if a < 3 && b < 3 {
        if a == b {
            mass[k]
        } else {
            0.0
        }
    } else if a >= 3 && b >= 3 {
        inertia[k][(a - 3, b - 3)]
    } else {
        0.0
    }
}
