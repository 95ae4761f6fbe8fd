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
//! a step refills values and refactors. Never a dense inverse of M.
//!
//! Two factorizations, chosen at each [`Kkt::factor`]:
//!
//! * **Schur complement** ([`cardan_solver::SchurSolver`]) when the top-left is block diagonal
//!   and symmetric: [`Kkt::set_mass`] only (the coupling blocks are then zero), or
//!   [`Kkt::add_top`] on a layout without coupling blocks whose 6×6 blocks came out symmetric.
//!   With A = the top-left, S = Φ_v A⁻¹ Φ_vᵀ (m_a × m_a, SPD when Φ_v has full row rank) is
//!   assembled body by body and factored by a sparse Cholesky; λ = S⁻¹(Φ_v A⁻¹ h − γ#),
//!   v̇ = A⁻¹(h − Φ_vᵀ λ). Used at every size: it is faster than the dense LU even on
//!   the smallest models (measurements: docs/dev/performance-log.md, optimization 8).
//! * **LU of the full matrix** ([`cardan_solver::AutoSolver`]: dense LU for small models, sparse
//!   LU for large) otherwise, and as the fallback when the Cholesky fails: S squares the
//!   conditioning of Φ_v, so near a singular configuration (a four-bar passing a dead-centre
//!   position) its relative pivots drop below τ = min(1e-4, 0.1/m_a)
//!   ([`schur_pivot_tolerance`]) and the LU, which loses half as many digits, takes over for
//!   that factorization; and when a mass block is too ill-conditioned (a point mass with a
//!   negligible inertia), for every mass-only factorization.
//!
//! [`Kkt::solve`] uses whichever factored last. The slots of the full matrix are written only
//! when the LU path factors (Φ_v lives in `jac`, the mass blocks in their own array), so the
//! Schur path never touches them.

use cardan_constraints::{BodyPair, BodyState, Constraint};
use cardan_mechanism::{BodyId, Model};
use cardan_solver::{AutoSolver, LinearSolver, SchurSolver, SolverError, SparsityPattern};
use std::ops::Range;

mod path;
pub(crate) use path::KktSolve;
use path::SolvePath;

/// One joint, driver or coupler: its rows, bodies.
#[derive(Debug, Clone)]
pub(crate) struct Element {
    pub rows: Range<usize>,
    pub bi: BodyId,
    pub bj: BodyId,
    /// Joint index, or `joints.len() + driver index`, or
    /// `joints.len() + drivers.len() + coupler index`.
    pub index: usize,
}

/// The constraint of element `e` (a coupler with the model's references: right for Φ_v, ν and
/// γ#, which do not depend on them; Φ takes the references of the run, see [`eval_rows`]).
enum Of<'a> {
    Joint(&'a cardan_constraints::Joint),
    Driver(&'a cardan_constraints::Driver),
    Coupler(&'a cardan_constraints::Coupler, usize),
}

fn of<'a>(model: &'a Model, e: &Element) -> Of<'a> {
    let (nj, nd) = (model.joints().len(), model.drivers().len());
    if e.index < nj {
        Of::Joint(&model.joints()[e.index].joint)
    } else if e.index < nj + nd {
        Of::Driver(&model.drivers()[e.index - nj].driver)
    } else {
        let k = e.index - nj - nd;
        Of::Coupler(&model.couplers()[k].coupler, k)
    }
}

macro_rules! with_constraint {
    ($of:expr, $c:ident => $e:expr) => {
        match $of {
            Of::Joint($c) => $e,
            Of::Driver($c) => $e,
            Of::Coupler($c, _) => $e,
        }
    };
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
    let nd = model.drivers().len();
    v.extend(model.couplers().iter().enumerate().map(|(k, c)| Element {
        rows: c.rows.clone(),
        bi: c.body_i,
        bj: c.body_j,
        index: nj + nd + k,
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
    with_constraint!(of(model, e), c => c.phi_v(&pair, t, &mut bi[..n], &mut bj[..n]));
}

/// Which vector of an element to evaluate.
#[derive(Clone, Copy)]
pub(crate) enum Rhs {
    Phi,
    Nu,
    Gamma,
}

/// Φ, ν or γ#_v of all model rows; the couplers' angles continued from `turns` (one entry per
/// coupler, see [`cardan_mechanism::Model::accept_turns`]). No allocation.
pub(crate) fn eval_rows(
    model: &Model,
    elements: &[Element],
    bodies: &[BodyState],
    turns: &[[f64; 2]],
    t: f64,
    what: Rhs,
    out: &mut [f64],
) {
    let g = BodyState::ground();
    for e in elements {
        let pair = BodyPair::new(st(bodies, &g, e.bi), st(bodies, &g, e.bj));
        let o = &mut out[e.rows.clone()];
        match of(model, e) {
            Of::Coupler(c, k) => rows(&c.with_reference(turns[k]), &pair, t, what, o),
            other => with_constraint!(other, c => rows(c, &pair, t, what, o)),
        }
    }
}

/// Φ, ν or γ#_v of one constraint.
fn rows<C: Constraint>(c: &C, pair: &BodyPair, t: f64, what: Rhs, o: &mut [f64]) {
    match what {
        Rhs::Phi => c.phi(pair, t, o),
        Rhs::Nu => c.nu(pair, t, o),
        Rhs::Gamma => c.gamma_sharp_v(pair, t, o),
    }
}

/// Six Φ_v entries: active row a, the six columns c..c+6 of one moving body (values
/// `jac[6 g..6 g + 6]` for group g).
#[derive(Debug, Clone, Copy)]
struct Group {
    row: usize,
    col: usize,
}

/// Size n + m_a up to which the LU of the full matrix is analyzed with the layout. Beyond it,
/// and without coupling blocks (so that the Schur complement is the usual path), the analysis
/// (a fill-reducing ordering and trial factorizations, 25 ms at 1,000 bodies: more than ten
/// steps) waits for the first LU factorization, a fallback near a singular configuration; that
/// step allocates, once.
pub(crate) const LU_EAGER_MAX_SIZE: usize = 2000;

/// After this many consecutive refusals of S (`.0`), the Schur complement is skipped for the
/// next `.1` factorizations: a model whose S is always refused (a mechanism held in a
/// near-singular configuration) pays for the attempt once in 16 factorizations instead of at
/// each, and a singular passage returns to the Schur path at most 15 factorizations after it.
pub(crate) const SCHUR_BACKOFF: (usize, usize) = (3, 15);

/// Relative pivot tolerance τ of S for m active rows: τ = min(1e-4, 0.1/m). Below it the
/// Schur complement is refused and the LU takes over. The solver's 1e-4 (see
/// [`cardan_solver::SchurSolver`]) keeps a plain solve's constraint residual near 1e-12 and
/// lets the LU take the passages of singular positions (the A02 four-bar N = 2 fails one at
/// 1e-5). But a healthy large model has small ratios too: a chain of N links has
/// ≈ 1/(2N) = 1.5/m, so a fixed 1e-4 refused every chain beyond ~5,000 links and sent the
/// 10,000-link chain to the LU. 0.1/m stays 15× below that law, leaves models under 1,000 rows
/// at 1e-4, and [`Kkt::solve`] refines such solves (one-shot solves; an iteration on exact
/// residuals corrects them itself, see [`Kkt::solve_unrefined`]).
pub(crate) fn schur_pivot_tolerance(m: usize) -> f64 {
    (0.1 / m.max(1) as f64).min(cardan_solver::DEFAULT_SCHUR_PIVOT_TOLERANCE)
}

/// Smallest pivot ratio of S below which [`Kkt::solve`] refines a Schur solve once (a
/// 1,000-link chain sits at 5e-4 to 7.6e-4, A02 near its horizontal positions goes below
/// 1e-4, where the Schur solver refuses S and the LU takes over). The default, for one-shot
/// solves (accelerations and multipliers, a first velocity projection); DOPRI5 sets
/// [`refine_ratio_for`] its tolerance; generalized-α's iterations do not refine (see
/// [`Kkt::solve_unrefined`]).
pub(crate) const SCHUR_REFINE_RATIO: f64 = 5e-3;

/// The refinement threshold for an integrator that needs solves only to a backward error
/// well below `rtol`: a plain Schur solve's backward error is about u / (smallest pivot
/// ratio) (measured on the 1,000-link chain at ratio 5e-4: 2e-13 to 5e-13, u / ratio =
/// 4.4e-13), so it is refined only when that exceeds 1e-3 rtol (rtol 1e-10: ratios below
/// 2.2e-3 are refined; rtol 1e-8: below 2.2e-5, which only S of models beyond 4,500 rows
/// reach, see [`schur_pivot_tolerance`]).
pub(crate) fn refine_ratio_for(rtol: f64) -> f64 {
    (f64::EPSILON / (1e-3 * rtol)).min(SCHUR_REFINE_RATIO)
}

/// The factorization held for [`Kkt::solve`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Factored {
    Schur,
    Lu,
}

/// The laid-out KKT system and its solver.
#[derive(Debug)]
pub(crate) struct Kkt {
    pub n: usize,
    /// Active model rows, increasing.
    pub active: Vec<usize>,
    /// Position of each model row among the active rows (usize::MAX if dropped).
    pub active_of: Vec<usize>,
    /// LU of the full matrix; `None` until its first use for large systems without coupling
    /// blocks (see [`LU_EAGER_MAX_SIZE`]).
    solver: Option<AutoSolver>,
    /// Entries of the full matrix in slot order, kept for a deferred LU analysis.
    lu_entries: Vec<(usize, usize)>,
    /// Slots of the full matrix (LU path only; written by `factor` when it takes that path).
    pub slots: Vec<f64>,
    /// Top-left block slots: (row, col, slot); the 36 nb diagonal-block entries first (body,
    /// row, column order), then the coupling blocks.
    top: Vec<(usize, usize, usize)>,
    /// Coupling blocks were laid out (a force element joins two moving bodies).
    coupled: bool,
    /// Φ_v by groups of six entries, in evaluation order.
    groups: Vec<Group>,
    /// Φ_v values, six per group.
    pub jac: Vec<f64>,
    /// KKT slots (Φ_v, Φ_vᵀ) of each `jac` value (LU path).
    jac_slots: Vec<(usize, usize)>,
    /// Diagonal blocks of the top-left, column-major 6×6 per body (36 nb).
    blocks: Vec<f64>,
    /// Slot of each `blocks` entry.
    block_slots: Vec<usize>,
    /// The top-left slots are behind `blocks` (set_mass wrote only `blocks`).
    top_stale: bool,
    /// add_top added terms since the last set_mass (the top-left is in the slots).
    tangent: bool,
    schur: Option<SchurSolver>,
    /// Schur complement or LU, and the back-off from the Schur path ([`path`]).
    path: SolvePath,
    factored: Option<Factored>,
    pub rhs: Vec<f64>,
    pub sol: Vec<f64>,
    /// All-row buffers (m).
    pub full: Vec<f64>,
    /// Scratch of length n.
    pub work_n: Vec<f64>,
    /// Pivot ratio below which a Schur solve is refined ([`SCHUR_REFINE_RATIO`]).
    pub(crate) refine_below: f64,
    /// Φ_v values of the last factorization (for the Schur refinement, and to recognize an
    /// unchanged matrix).
    jac_factored: Vec<f64>,
    /// The last factorization was of a mass-only matrix, and `blocks` has not changed since.
    factored_mass_only: bool,
    /// Scratch of the Schur refinement (n + m_a each).
    refine_r: Vec<f64>,
    refine_d: Vec<f64>,
    /// Scratch of length m_a.
    pub work_a: Vec<f64>,
    pub factorizations: usize,
    /// Schur factorizations that failed and were replaced by an LU.
    pub fallbacks: usize,
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
        let mut groups = Vec::new();
        let mut jac_slots = Vec::new();
        for e in elements {
            for r in e.rows.clone() {
                let a = active_of[r];
                if a == usize::MAX {
                    continue;
                }
                for id in [e.bi, e.bj] {
                    if let BodyId::Moving(k) = id {
                        groups.push(Group { row: a, col: 6 * k });
                        for c in 0..6 {
                            let col = 6 * k + c;
                            jac_slots.push((pos.len(), pos.len() + 1));
                            pos.push((n + a, col));
                            pos.push((col, n + a));
                        }
                    }
                }
            }
        }
        let size = n + active.len();
        let coupled = top.len() > 36 * nb;
        let ns = pos.len();
        let ne = jac_slots.len();
        // `blocks` is column-major per body; `top` lists the diagonal blocks row by row.
        let mut block_slots = vec![0; 36 * nb];
        for &(r, c, s) in &top[..36 * nb] {
            block_slots[36 * (r / 6) + 6 * (c % 6) + r % 6] = s;
        }
        let mut kkt = Self {
            n,
            active_of,
            solver: None,
            lu_entries: pos,
            slots: vec![0.0; ns],
            coupled,
            top,
            groups,
            jac: vec![0.0; ne],
            jac_slots,
            blocks: vec![0.0; 36 * nb],
            block_slots,
            top_stale: false,
            tangent: false,
            schur: None,
            path: SolvePath::default(),
            factored: None,
            rhs: vec![0.0; size],
            sol: vec![0.0; size],
            full: vec![0.0; m],
            work_n: vec![0.0; n],
            refine_below: SCHUR_REFINE_RATIO,
            jac_factored: vec![0.0; ne],
            factored_mass_only: false,
            refine_r: vec![0.0; n + active.len()],
            refine_d: vec![0.0; n + active.len()],
            work_a: vec![0.0; active.len()],
            active,
            factorizations: 0,
            fallbacks: 0,
        };
        kkt.analyze_schur()?;
        if size <= LU_EAGER_MAX_SIZE || coupled {
            kkt.lu()?;
        }
        Ok(kkt)
    }

    /// The LU of the full matrix, analyzed on first use.
    fn lu(&mut self) -> Result<&mut AutoSolver, SolverError> {
        if self.solver.is_none() {
            let size = self.rhs.len();
            let pattern = SparsityPattern::new(size, size, &self.lu_entries)?;
            let mut solver = AutoSolver::default();
            solver.analyze(&pattern)?;
            self.solver = Some(solver);
            self.lu_entries = Vec::new();
        }
        Ok(self.solver.as_mut().expect("analyzed"))
    }

    /// Lays out the Schur-complement solver (entries of Φ_v in `jac` order).
    fn analyze_schur(&mut self) -> Result<(), SolverError> {
        let b: Vec<(usize, usize)> = self
            .groups
            .iter()
            .flat_map(|g| (0..6).map(move |c| (g.row, g.col + c)))
            .collect();
        let mut schur =
            SchurSolver::new().with_pivot_tolerance(schur_pivot_tolerance(self.active.len()));
        schur.analyze(6, self.n / 6, self.active.len(), &b)?;
        self.schur = Some(schur);
        Ok(())
    }

    /// Forces a factorization path (tests and measurements).
    #[allow(dead_code)]
    pub fn set_solve_path(&mut self, mode: KktSolve) {
        self.path.set_mode(mode);
        self.factored = None;
    }

    /// The factorization the last successful [`factor`](Self::factor) made.
    #[allow(dead_code)]
    pub fn factored(&self) -> Option<Factored> {
        self.factored
    }

    /// Evaluates Φ_v at the bodies' poses into `jac`. No allocation.
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
                            self.jac[cursor] = blk[lr][c];
                            cursor += 1;
                        }
                    }
                }
            }
        }
        debug_assert_eq!(cursor, self.jac.len());
    }

    /// Sets the top-left to M = diag(m I, J') per body (coupling blocks zero).
    /// When the values written differ from the blocks held (a tangent iteration matrix was
    /// there, or other masses), the last factorization no longer counts as this matrix's.
    pub fn set_mass(&mut self, mass: &[f64], inertia: &[nalgebra::Matrix3<f64>]) {
        let mut changed = self.tangent;
        for (k, blk) in self.blocks.chunks_exact_mut(36).enumerate() {
            let mut set = |i: usize, v: f64| {
                changed |= blk[i].to_bits() != v.to_bits();
                blk[i] = v;
            };
            for c in 0..6 {
                for r in 0..6 {
                    let v = match (r < 3, c < 3) {
                        (true, true) if r == c => mass[k],
                        (false, false) => inertia[k][(r - 3, c - 3)],
                        _ => 0.0,
                    };
                    set(6 * c + r, v);
                }
            }
        }
        if changed {
            self.factored_mass_only = false;
        }
        self.top_stale = true;
        self.tangent = false;
    }

    /// Adds `f(row, col)` to the top-left entries (for tangent terms).
    pub fn add_top(&mut self, mut f: impl FnMut(usize, usize) -> f64) {
        self.write_top();
        for &(r, c, s) in &self.top {
            self.slots[s] += f(r, c);
        }
        self.tangent = true;
    }

    /// Brings the top-left slots up to `blocks` (coupling blocks zero) after a set_mass.
    fn write_top(&mut self) {
        if !self.top_stale {
            return;
        }
        for (&s, &v) in self.block_slots.iter().zip(&self.blocks) {
            self.slots[s] = v;
        }
        for &(_, _, s) in &self.top[self.blocks.len()..] {
            self.slots[s] = 0.0;
        }
        self.top_stale = false;
    }

    /// The top-left is block diagonal and symmetric, so the Schur complement applies: mass only,
    /// or tangent terms on a layout without coupling blocks whose diagonal blocks are symmetric
    /// (then copied from the slots into `blocks`).
    fn schur_applies(&mut self) -> bool {
        if !self.tangent {
            return true;
        }
        if self.coupled {
            return false;
        }
        for (v, &s) in self.blocks.iter_mut().zip(&self.block_slots) {
            *v = self.slots[s];
        }
        self.blocks.chunks_exact(36).all(|b| {
            let size = b.iter().fold(0.0f64, |m, v| m.max(v.abs()));
            (0..6).all(|c| (0..c).all(|r| (b[6 * c + r] - b[6 * r + c]).abs() <= 1e-14 * size))
        })
    }

    /// Factors the current matrix: the Schur complement when it applies (see the module docs),
    /// else, or when its Cholesky fails, the LU of the full matrix.
    ///
    /// A mass-only matrix equal to the one factored last (same Φ_v values, same mass blocks) is
    /// not factored again: DOPRI5's velocity projection of a step end whose positions did not
    /// move, the evaluation of the equations of motion there and the recording of an output
    /// time all share the factorization of the step's last stage.
    pub fn factor(&mut self) -> Result<(), SolverError> {
        if self.unchanged() {
            return Ok(());
        }
        self.factorizations += 1;
        self.factored = None;
        if self.path.try_schur(self.tangent) && self.schur.is_some() && self.schur_applies() {
            let schur = self.schur.as_mut().expect("checked");
            match schur.factor(&self.blocks, &self.jac) {
                Ok(()) => {
                    self.path.accepted();
                    self.factored = Some(Factored::Schur);
                    self.remember_factored();
                    return Ok(());
                }
                Err(e) if self.path.strict() => {
                    // Rows of S are active rows: KKT rows n + a.
                    return Err(match e {
                        SolverError::Singular {
                            dependent_equations,
                        } => SolverError::Singular {
                            dependent_equations: dependent_equations
                                .into_iter()
                                .map(|a| self.n + a)
                                .collect(),
                        },
                        e => e,
                    });
                }
                Err(e) => {
                    self.fallbacks += 1;
                    // A block failure lists no equations.
                    self.path.refused(
                        !self.tangent
                            && matches!(&e, SolverError::Singular { dependent_equations } if dependent_equations.is_empty()),
                    );
                }
            }
        }
        self.write_top();
        for (&(s, st), &v) in self.jac_slots.iter().zip(&self.jac) {
            self.slots[s] = v;
            self.slots[st] = v;
        }
        let slots = std::mem::take(&mut self.slots);
        let r = self.lu().and_then(|lu| lu.factor(&slots));
        self.slots = slots;
        r?;
        self.factored = Some(Factored::Lu);
        self.remember_factored();
        Ok(())
    }

    /// The last factorization holds this mass-only matrix (see [`factor`](Self::factor)).
    fn unchanged(&self) -> bool {
        self.factored.is_some()
            && self.factored_mass_only
            && !self.tangent
            && self.jac == self.jac_factored
    }

    /// Keeps what [`unchanged`](Self::unchanged) compares with.
    fn remember_factored(&mut self) {
        self.jac_factored.copy_from_slice(&self.jac);
        self.factored_mass_only = !self.tangent;
    }

    /// Solves with `rhs` into `sol`, with the last factorization. A Schur solve whose smallest
    /// pivot ratio is below `refine_below` ([`SCHUR_REFINE_RATIO`], or [`refine_ratio_for`]
    /// DOPRI5's tolerance) is refined once against the full system
    /// (residual with K, correction with the Schur factors): S squares the conditioning of Φ_v,
    /// and near a singular configuration (A02's horizontal positions) the plain solve is less
    /// accurate than the LU of K would be.
    pub fn solve(&mut self) -> Result<(), SolverError> {
        self.solve_refined(true)
    }

    /// [`solve`](Self::solve) without the refinement of a Schur solve, for a caller that
    /// iterates on residuals of the exact system itself (generalized-α's Newton iteration and
    /// its velocity projection): there the next residual corrects the error of this solve,
    /// whose backward error is about u / (smallest pivot ratio), below u / τ where the Schur
    /// path is taken ([`schur_pivot_tolerance`]: 2e-12 for models under 1,000 rows; 4e-12 on
    /// the 10,000-link chain, ratio ≈ 5e-5). That slows the iteration by nothing measurable,
    /// and a refinement would only repeat the iteration's work.
    pub fn solve_unrefined(&mut self) -> Result<(), SolverError> {
        self.solve_refined(false)
    }

    fn solve_refined(&mut self, refine: bool) -> Result<(), SolverError> {
        match self.factored {
            Some(Factored::Schur) => {
                let schur = self.schur.as_mut().expect("factored");
                schur.solve(&self.rhs, &mut self.sol)?;
                if refine && schur.min_pivot_ratio() < self.refine_below {
                    self.refine_schur()?;
                }
                Ok(())
            }
            Some(Factored::Lu) => self
                .solver
                .as_mut()
                .expect("factored")
                .solve(&self.rhs, &mut self.sol),
            None => Err(SolverError::NotReady { missing: "factor" }),
        }
    }

    /// One step of iterative refinement of `sol` on the Schur path: r = rhs − K sol with
    /// K = [A Φ_vᵀ; Φ_v 0] the factored matrix (A the block-diagonal top-left held in
    /// `blocks`, Φ_v as it was at the factorization: a modified Newton iteration solves with a
    /// matrix older than the current `jac`), sol += K⁻¹ r by the Schur factors. No allocation.
    fn refine_schur(&mut self) -> Result<(), SolverError> {
        let n = self.n;
        let mut r = std::mem::take(&mut self.refine_r);
        r.copy_from_slice(&self.rhs);
        let (xv, xl) = self.sol.split_at(n);
        for (k, a) in self.blocks.chunks_exact(36).enumerate() {
            let x = &xv[6 * k..6 * k + 6];
            for i in 0..6 {
                let mut s = 0.0;
                for j in 0..6 {
                    s += a[6 * j + i] * x[j];
                }
                r[6 * k + i] -= s;
            }
        }
        for (g, v) in self.groups.iter().zip(self.jac_factored.chunks_exact(6)) {
            let l = xl[g.row];
            let mut s = 0.0;
            for c in 0..6 {
                r[g.col + c] -= v[c] * l;
                s += v[c] * xv[g.col + c];
            }
            r[n + g.row] -= s;
        }
        let mut d = std::mem::take(&mut self.refine_d);
        let solved = self.schur.as_mut().expect("factored").solve(&r, &mut d);
        if solved.is_ok() {
            for (x, dx) in self.sol.iter_mut().zip(&d) {
                *x += dx;
            }
        }
        self.refine_r = r;
        self.refine_d = d;
        solved
    }

    /// y (active rows) = Φ_v x.
    pub fn phi_v_mul(&self, x: &[f64], y: &mut [f64]) {
        y.fill(0.0);
        for (g, v) in self.groups.iter().zip(self.jac.chunks_exact(6)) {
            let x = &x[g.col..g.col + 6];
            let mut s = y[g.row];
            for c in 0..6 {
                s += v[c] * x[c];
            }
            y[g.row] = s;
        }
    }

    /// y (n) += Φ_vᵀ λ and size (n) += |Φ_vᵀ| |λ| (entrywise absolute values: the size of the
    /// terms of Φ_vᵀλ), in one pass over Φ_v.
    pub fn phi_v_t_mul_add_with_size(&self, lambda: &[f64], y: &mut [f64], size: &mut [f64]) {
        for (g, v) in self.groups.iter().zip(self.jac.chunks_exact(6)) {
            let l = lambda[g.row];
            let y = &mut y[g.col..g.col + 6];
            let size = &mut size[g.col..g.col + 6];
            for c in 0..6 {
                let t = v[c] * l;
                y[c] += t;
                size[c] += t.abs();
            }
        }
    }

    /// y (n) += Φ_vᵀ λ (λ over active rows).
    pub fn phi_v_t_mul_add(&self, lambda: &[f64], y: &mut [f64]) {
        for (g, v) in self.groups.iter().zip(self.jac.chunks_exact(6)) {
            let l = lambda[g.row];
            let y = &mut y[g.col..g.col + 6];
            for c in 0..6 {
                y[c] += v[c] * l;
            }
        }
    }
}

#[cfg(test)]
#[path = "kkt_tests.rs"]
mod tests;
