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
//!
//! The parts, one job each: [`elements`] (the constraint elements and their row blocks),
//! [`layout`] (where each value goes), [`phi_v`] (products with Φ_v), [`top_left`] (the values
//! of A), [`full_lu`] (the LU of the full matrix), [`path`] (which factorization to try, and
//! the back-off from the Schur path), [`last`] (what the last factorization holds),
//! [`refine`] (the refinement of a Schur solve). [`Kkt`] ties them together.

use cardan_mechanism::Model;
use cardan_solver::{SchurSolver, SolverError};

mod curves;
mod elements;
mod full_lu;
mod last;
mod layout;
mod path;
mod phi_v;
mod refine;
mod top_left;

pub(crate) use curves::CurveTrack;
pub(crate) use elements::{element_blocks, elements, eval_rows, Element, Rhs};
use full_lu::LU_EAGER_MAX_SIZE;
pub(crate) use last::Factored;
pub(crate) use path::KktSolve;

use full_lu::FullLu;
use last::LastFactorization;
use layout::Layout;
use path::SolvePath;
use refine::{Factors, Refinement};
use top_left::TopLeft;

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

/// Smallest pivot ratio of S below which a one-shot Schur solve is refined once (a 1,000-link
/// chain sits at 5e-4 to 7.6e-4, A02 near its horizontal positions goes below 1e-4, where the
/// Schur solver refuses S and the LU takes over): accelerations and multipliers, a first
/// velocity projection, and every solve of a generalized-α run outside its iterations (which do
/// not refine, see [`Kkt::solve_unrefined`]). DOPRI5 refines by its tolerance instead
/// ([`SchurRefinement::for_rtol`]).
pub(crate) const SCHUR_REFINE_RATIO: f64 = 5e-3;

/// When [`Kkt::solve`] refines a Schur solve once against the full system ([`refine`]): when
/// the smallest pivot ratio of S is below `below`. Part of the configuration of whoever solves
/// (an integrator's, [`crate::integrators`]), passed with each solve, so no setting of the
/// solver outlives a run.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct SchurRefinement {
    /// The pivot ratio below which a Schur solve is refined.
    pub below: f64,
}

impl SchurRefinement {
    /// For one-shot solves: below [`SCHUR_REFINE_RATIO`].
    pub const ONE_SHOT: Self = Self {
        below: SCHUR_REFINE_RATIO,
    };

    /// For an integrator that needs solves only to a backward error well below `rtol`: a plain
    /// Schur solve's backward error is about u / (smallest pivot ratio) (measured on the
    /// 1,000-link chain at ratio 5e-4: 2e-13 to 5e-13, u / ratio = 4.4e-13), so it is refined
    /// only when that exceeds 1e-3 rtol (rtol 1e-10: ratios below 2.2e-3 are refined; rtol
    /// 1e-8: below 2.2e-5, which only S of models beyond 4,500 rows reach, see
    /// [`schur_pivot_tolerance`]).
    pub fn for_rtol(rtol: f64) -> Self {
        Self {
            below: (f64::EPSILON / (1e-3 * rtol)).min(SCHUR_REFINE_RATIO),
        }
    }
}

/// The laid-out KKT system and its solver.
#[derive(Debug)]
pub(crate) struct Kkt {
    pub n: usize,
    /// Active model rows, increasing.
    pub active: Vec<usize>,
    /// Position of each model row among the active rows (usize::MAX if dropped).
    pub active_of: Vec<usize>,
    layout: Layout,
    /// Φ_v values, six per group of the layout.
    pub jac: Vec<f64>,
    top_left: TopLeft,
    lu: FullLu,
    schur: SchurSolver,
    /// Schur complement or LU, and the back-off from the Schur path.
    path: SolvePath,
    last: LastFactorization,
    refinement: Refinement,
    pub rhs: Vec<f64>,
    pub sol: Vec<f64>,
    /// All-row buffers (m).
    pub full: Vec<f64>,
    /// Scratch of length n.
    pub work_n: Vec<f64>,
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
        let na = active.len();
        let mut active_of = vec![usize::MAX; m];
        for (a, &r) in active.iter().enumerate() {
            active_of[r] = a;
        }
        let (layout, entries) = Layout::new(model, elements, &active_of, pairs);
        let size = n + na;
        let ne = 6 * layout.groups.len();
        let mut schur = SchurSolver::new().with_pivot_tolerance(schur_pivot_tolerance(na));
        schur.analyze(6, nb, na, &layout.phi_v_entries())?;
        let mut lu = FullLu::new(entries, size);
        if size <= LU_EAGER_MAX_SIZE || layout.coupled {
            lu.solver()?;
        }
        Ok(Self {
            n,
            active,
            active_of,
            jac: vec![0.0; ne],
            layout,
            top_left: TopLeft::new(nb),
            lu,
            schur,
            path: SolvePath::default(),
            last: LastFactorization::new(ne),
            refinement: Refinement::new(size),
            rhs: vec![0.0; size],
            sol: vec![0.0; size],
            full: vec![0.0; m],
            work_n: vec![0.0; n],
            work_a: vec![0.0; na],
            factorizations: 0,
            fallbacks: 0,
        })
    }

    /// Forces a factorization path (tests and measurements).
    #[allow(dead_code)]
    pub fn set_solve_path(&mut self, mode: KktSolve) {
        self.path.set_mode(mode);
        self.last.clear();
    }

    /// The factorization the last successful [`factor`](Self::factor) made.
    #[allow(dead_code)]
    pub fn factored(&self) -> Option<Factored> {
        self.last.kind()
    }

    /// Whether every row is active (no redundant row dropped).
    pub fn keeps_all_rows(&self) -> bool {
        self.active.len() == self.full.len()
    }

    /// Evaluates Φ_v at the bodies' poses into `jac`. No allocation.
    pub fn eval_jacobian(
        &mut self,
        model: &Model,
        elements: &[Element],
        bodies: &[cardan_constraints::BodyState],
        curves: &CurveTrack,
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
            element_blocks(model, e, bodies, curves, t, &mut bi, &mut bj);
            for (lr, r) in e.rows.clone().enumerate() {
                if self.active_of[r] == usize::MAX {
                    continue;
                }
                for (id, blk) in [(e.bi, &bi), (e.bj, &bj)] {
                    if let cardan_mechanism::BodyId::Moving(_) = id {
                        self.jac[cursor..cursor + 6].copy_from_slice(&blk[lr]);
                        cursor += 6;
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
        if self.top_left.set_mass(mass, inertia) {
            self.last.mass_changed();
        }
    }

    /// Adds `f(row, col)` to the top-left entries (for tangent terms).
    pub fn add_top(&mut self, f: impl FnMut(usize, usize) -> f64) {
        self.top_left.add(&self.layout, &mut self.lu.slots, f);
    }

    /// Factors the current matrix: the Schur complement when it applies (see the module docs),
    /// else, or when its Cholesky fails, the LU of the full matrix.
    ///
    /// A mass-only matrix equal to the one factored last (same Φ_v values, same mass blocks) is
    /// not factored again (see [`last`]).
    pub fn factor(&mut self) -> Result<(), SolverError> {
        let tangent = self.top_left.tangent();
        if self.last.unchanged(&self.jac, tangent) {
            return Ok(());
        }
        self.factorizations += 1;
        self.last.clear();
        if self.path.try_schur(tangent) && self.top_left.schur_blocks(&self.layout, &self.lu.slots)
        {
            match self.schur.factor(self.top_left.blocks(), &self.jac) {
                Ok(()) => {
                    self.path.accepted();
                    self.last.remember(Factored::Schur, &self.jac, tangent);
                    return Ok(());
                }
                Err(e) if self.path.strict() => return Err(self.kkt_rows(e)),
                Err(e) => {
                    self.fallbacks += 1;
                    // A block failure lists no equations.
                    self.path.refused(
                        !tangent
                            && matches!(&e, SolverError::Singular { dependent_equations } if dependent_equations.is_empty()),
                    );
                }
            }
        }
        self.top_left.write(&self.layout, &mut self.lu.slots);
        self.lu.write_phi_v(&self.layout, &self.jac);
        self.lu.factor()?;
        self.last.remember(Factored::Lu, &self.jac, tangent);
        Ok(())
    }

    /// A Schur solver's error with its equations renumbered as KKT rows (rows of S are active
    /// rows: KKT rows n + a).
    fn kkt_rows(&self, e: SolverError) -> SolverError {
        match e {
            SolverError::Singular {
                dependent_equations,
            } => SolverError::Singular {
                dependent_equations: dependent_equations
                    .into_iter()
                    .map(|a| self.n + a)
                    .collect(),
            },
            e => e,
        }
    }

    /// Solves with `rhs` into `sol`, with the last factorization. A Schur solve whose smallest
    /// pivot ratio is below `refine.below` is refined once against the full system ([`refine`]).
    pub fn solve(&mut self, refine: SchurRefinement) -> Result<(), SolverError> {
        self.solve_refined(Some(refine))
    }

    /// [`solve`](Self::solve) without the refinement of a Schur solve, for a caller that
    /// iterates on residuals of the exact system itself (generalized-α's Newton iteration and
    /// its velocity projection): there the next residual corrects the error of this solve,
    /// whose backward error is about u / (smallest pivot ratio), below u / τ where the Schur
    /// path is taken ([`schur_pivot_tolerance`]: 2e-12 for models under 1,000 rows; 4e-12 on
    /// the 10,000-link chain, ratio ≈ 5e-5). That slows the iteration by nothing measurable,
    /// and a refinement would only repeat the iteration's work.
    pub fn solve_unrefined(&mut self) -> Result<(), SolverError> {
        self.solve_refined(None)
    }

    fn solve_refined(&mut self, refine: Option<SchurRefinement>) -> Result<(), SolverError> {
        match self.last.kind() {
            Some(Factored::Schur) => {
                self.schur.solve(&self.rhs, &mut self.sol)?;
                if refine.is_some_and(|r| self.schur.min_pivot_ratio() < r.below) {
                    let k = Factors {
                        blocks: self.top_left.blocks(),
                        groups: &self.layout.groups,
                        jac: self.last.jac(),
                        schur: &mut self.schur,
                    };
                    self.refinement.refine(k, &self.rhs, &mut self.sol)?;
                }
                Ok(())
            }
            Some(Factored::Lu) => self.lu.solve(&self.rhs, &mut self.sol),
            None => Err(SolverError::NotReady { missing: "factor" }),
        }
    }

    /// y (active rows) = Φ_v x.
    pub fn phi_v_mul(&self, x: &[f64], y: &mut [f64]) {
        phi_v::mul(&self.layout.groups, &self.jac, x, y);
    }

    /// y (n) += Φ_vᵀ λ and size (n) += |Φ_vᵀ| |λ| (see [`phi_v::t_mul_add_with_size`]).
    pub fn phi_v_t_mul_add_with_size(&self, lambda: &[f64], y: &mut [f64], size: &mut [f64]) {
        phi_v::t_mul_add_with_size(&self.layout.groups, &self.jac, lambda, y, size);
    }

    /// y (n) += Φ_vᵀ λ (λ over active rows).
    pub fn phi_v_t_mul_add(&self, lambda: &[f64], y: &mut [f64]) {
        phi_v::t_mul_add(&self.layout.groups, &self.jac, lambda, y);
    }
}

#[cfg(test)]
#[path = "kkt_tests.rs"]
mod tests;
