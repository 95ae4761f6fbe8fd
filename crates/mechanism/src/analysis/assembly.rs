//! Assembly: consistent poses from a rough initial guess.
//!
//! The constraint equations (joints, and the drivers at `t` unless excluded) are solved by
//! Newton-Raphson with the minimum-norm step of a rank-revealing QR ([`cardan_solver::MinNormQr`];
//! [`cardan_solver::SparseMinNorm`] from [`cardan_solver::SPARSE_RANK_MIN_UNKNOWNS`] unknowns on):
//! with fewer independent equations than unknowns (a mechanism with free degrees of freedom), each
//! step is the smallest correction (in the scaled norm ‖Δr‖/L, ‖Δπ'‖) that satisfies the
//! linearized equations, so the bodies move as little as possible and the free coordinates keep
//! their guessed values as far as the constraints allow. Redundant equations are handled the
//! same way. A cap on the scaled step (default 0.5: half the model size, or about 30°) and the
//! backtracking line search keep the iteration on the branch of the guess.
//!
//! ### The driven branch
//! A rotation driver's equation sin(φ − θ(t)) = 0 also holds at φ = θ(t) ± π, and a Newton start
//! more than 90° from θ(t) (a run starting at a late `t_start`, `cardan eval --t`) converges
//! there. After assembling with the drivers, every rotation driver is checked:
//! cos(φ − θ(t)) > 0. When one fails (or the direct assembly fails), the drivers are moved
//! from their values at the guess to their values at t by continuation: each driven
//! coordinate c_k goes along c_k⁰ + s (f_k(t) − c_k⁰) (an angle along the shorter way round,
//! so it ends at θ(t) mod 2π), in steps of s small enough that no angle moves by more than
//! [`CONTINUATION_MAX_ANGLE`], each step assembled from the last. If the branch is still wrong
//! the assembly fails with [`AnalysisError::DriverBranch`], never silently at θ ± π.

use crate::error::{AnalysisError, OpenElement};
use crate::model::Model;
use crate::workspace::{apply_step, set_poses, Workspace};
use cardan_constraints::{unwrap_angle, BodyPair, BodyState, Driver, TimeFunction};
use cardan_solver::{
    LineSearch, LinearSolver, MinNormQr, Newton, NewtonOptions, NewtonReport, NonlinearSystem,
    RankAnalysis, RowSelection, SolverError, SparseMinNorm, SparsityPattern, Tolerances,
    SPARSE_RANK_MIN_UNKNOWNS,
};

/// A minimum-norm Newton solve's report and the rank of its last factorization (`None`: no
/// equation to solve).
type MinNormSolve = Option<(NewtonReport, Option<usize>)>;

/// A Newton solve's outcome: its report and the rank of the last factorization.
type Solved = Result<MinNormSolve, SolverError>;

/// Newton with a minimum-norm linear solver: `Err` only when the solver cannot be set up; the
/// inner result is the solve's.
fn min_norm_newton<S: LinearSolver>(
    pattern: &SparsityPattern,
    solver: S,
    options: NewtonOptions,
    sys: &mut impl NonlinearSystem,
    x: &mut [f64],
) -> Result<Solved, SolverError> {
    let mut newton = Newton::new(pattern, solver, options)?;
    let r = newton.solve(sys, x);
    Ok(r.map(|rep| Some((rep, newton.linear_solver().rank()))))
}

/// Newton on the rows `selection` keeps, judged on them only (the dropped rows of an
/// inconsistent redundant model cannot vanish), with a minimum-norm linear solver.
fn kept_rows_newton<S: LinearSolver>(
    pattern: &SparsityPattern,
    selection: RowSelection,
    solver: S,
    options: NewtonOptions,
    sys: &mut impl NonlinearSystem,
    x: &mut [f64],
) -> Result<(NewtonReport, Option<usize>), SolverError> {
    let mut newton = Newton::with_row_selection(pattern, selection, solver, options)?;
    newton.judge_kept_rows_only(true);
    let rep = newton.solve(sys, x)?;
    Ok((rep, newton.linear_solver().rank()))
}

/// Largest change of a driven angle per continuation step of the assembly (rad, 22.5°): well
/// inside the 90° basin of the driven branch.
pub const CONTINUATION_MAX_ANGLE: f64 = std::f64::consts::PI / 8.0;

/// Options of [`Model::assemble`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AssemblyOptions {
    /// Time at which the drivers are evaluated.
    pub t: f64,
    /// Include the drivers (default true): the assembled pose then also satisfies them at `t`.
    pub include_drivers: bool,
    /// Iteration cap (default 50).
    pub max_iterations: usize,
    /// Scaled convergence tolerances (default residual 1e-10, step 1e-6).
    pub tolerances: Tolerances,
    /// Cap on the scaled step per iteration (default 0.5).
    pub max_step: Option<f64>,
    /// An over-constrained model whose redundant rows disagree grossly
    /// ([`AnalysisError::InconsistentJoints`]) is assembled anyway with those rows dropped and
    /// left open, as OndselSolver does (default false: refused). The rows dropped and how far
    /// they stay open are in [`AssemblyReport::dropped_residual`] and, in a run, its
    /// `dropped_rows` (warnings of the front end).
    pub drop_inconsistent: bool,
}

impl Default for AssemblyOptions {
    fn default() -> Self {
        Self {
            t: 0.0,
            include_drivers: true,
            max_iterations: 50,
            tolerances: Tolerances::default(),
            max_step: Some(0.5),
            drop_inconsistent: false,
        }
    }
}

impl AssemblyOptions {
    /// Defaults, with the drivers evaluated at `t`.
    pub fn at(t: f64) -> Self {
        Self {
            t,
            ..Self::default()
        }
    }

    /// Refuses options that cannot give a meaningful assembly: a non-finite time, tolerances
    /// outside their ranges ([`Tolerances::validate`]), no iterations, a step cap that is not
    /// positive.
    ///
    /// # Errors
    /// [`AnalysisError::Options`] naming the option.
    pub fn validate(&self) -> Result<(), AnalysisError> {
        let bad = |m: String| Err(AnalysisError::Options(format!("assembly: {m}")));
        if !self.t.is_finite() {
            return bad(format!("the time must be finite, got {}", self.t));
        }
        self.tolerances.validate().or_else(bad)?;
        if self.max_iterations == 0 {
            return bad("max_iterations must be at least 1".into());
        }
        if let Some(s) = self.max_step {
            if !(s > 0.0 && s.is_finite()) {
                return bad(format!("max_step must be positive and finite, got {s}"));
            }
        }
        Ok(())
    }
}

/// Outcome of a successful assembly.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AssemblyReport {
    /// Newton iterations.
    pub iterations: usize,
    /// Final scaled residual max |Φ_i| / e_i.
    pub residual: f64,
    /// Largest displacement of a body reference point from the guess (m).
    pub max_translation: f64,
    /// Largest rotation of a body from the guess (rad).
    pub max_rotation: f64,
    /// Rank of the last Jacobian (equations included).
    pub rank: Option<usize>,
    /// The largest scaled residual |Φ_r| / e_r of the equations dropped as redundant: 0 when
    /// every equation holds (a consistent model); positive for a slightly inconsistent
    /// redundant model assembled at its least-squares-consistent pose (kept rows exact, see
    /// `analysis::dropped`).
    pub dropped_residual: f64,
}

/// The equations of the first `m` rows (joints, or joints + drivers).
struct AssemblySystem<'a> {
    model: &'a Model,
    bodies: &'a mut [BodyState],
    turns: &'a [[f64; 2]],
    t: f64,
    m: usize,
    phi: Vec<f64>,
    slots: Vec<f64>,
}

impl<'a> AssemblySystem<'a> {
    /// The first `m` equations of `model` at time `t` over `bodies` (couplers' angles
    /// continued from `turns`).
    fn new(
        model: &'a Model,
        bodies: &'a mut [BodyState],
        turns: &'a [[f64; 2]],
        t: f64,
        m: usize,
    ) -> Self {
        Self {
            model,
            bodies,
            turns,
            t,
            m,
            phi: vec![0.0; model.num_equations()],
            slots: vec![0.0; model.pattern.num_slots()],
        }
    }
}

impl NonlinearSystem for AssemblySystem<'_> {
    fn num_equations(&self) -> usize {
        self.m
    }
    fn num_unknowns(&self) -> usize {
        self.model.num_unknowns()
    }
    fn state_len(&self) -> usize {
        7 * self.model.num_bodies() + self.model.num_extra()
    }
    fn residual(&mut self, x: &[f64], out: &mut [f64]) {
        set_poses(self.bodies, x);
        let u = self.model.extras_of(x);
        self.model
            .phi_into(self.bodies, u, self.turns, self.t, &mut self.phi);
        out.copy_from_slice(&self.phi[..self.m]);
    }
    fn jacobian(&mut self, x: &[f64], slots: &mut [f64]) {
        set_poses(self.bodies, x);
        let u = self.model.extras_of(x);
        self.model
            .jacobian_into(self.bodies, u, self.t, &mut self.slots);
        let k = slots.len();
        slots.copy_from_slice(&self.slots[..k]);
    }
    fn apply_step(&mut self, x: &mut [f64], dx: &[f64]) {
        apply_step(x, dx, self.model.num_bodies());
    }
    fn equation_scales(&self, out: &mut [f64]) {
        out.copy_from_slice(&self.model.equation_scales()[..self.m]);
    }
    fn unknown_scales(&self, out: &mut [f64]) {
        out.copy_from_slice(self.model.unknown_scales());
    }
}

impl Model {
    /// Moves the bodies of `ws` as little as possible onto the constraint manifold (see the
    /// module docs). On success the workspace holds the assembled poses at time `options.t`, at
    /// rest, with every rotation driver on its driven branch; on failure it holds the last
    /// iterate.
    ///
    /// # Errors
    /// [`AnalysisError::AssemblyFailed`] naming the joints and drivers that stay open, with their
    /// residual norms; [`AnalysisError::DriverBranch`] when a rotation driver can only be
    /// assembled at θ(t) ± π.
    pub fn assemble(
        &self,
        ws: &mut Workspace,
        options: &AssemblyOptions,
    ) -> Result<AssemblyReport, AnalysisError> {
        options.validate()?;
        let guess = ws.pose.x.clone();
        let direct = self.assemble_direct(ws, options);
        if !options.include_drivers || self.drivers.is_empty() {
            return direct;
        }
        if direct.is_ok() && self.wrong_branch(ws, options.t).is_none() {
            return direct;
        }
        ws.pose.x.copy_from_slice(&guess);
        ws.sync_poses();
        match self.assemble_by_continuation(ws, options) {
            Ok(report) => match self.wrong_branch(ws, options.t) {
                None => Ok(report),
                Some((driver, reached, prescribed)) => Err(AnalysisError::DriverBranch {
                    time: options.t,
                    driver,
                    reached,
                    prescribed,
                }),
            },
            // The direct attempt's error names what stays open from the user's own guess.
            Err(e) => Err(direct.err().unwrap_or(e)),
        }
    }

    /// The first rotation driver whose assembled angle φ is on the spurious branch
    /// (cos(φ − θ(t)) ≤ 0), with φ and θ(t).
    fn wrong_branch(&self, ws: &Workspace, t: f64) -> Option<(String, f64, f64)> {
        self.drivers.iter().find_map(|d| {
            if !matches!(d.driver, Driver::Rotation(_)) {
                return None;
            }
            let (si, sj) = (ws.state_of(d.body_i), ws.state_of(d.body_j));
            let phi = d.driver.coordinate(&BodyPair::new(&si, &sj));
            let theta = d.driver.function().eval(t).0;
            ((phi - theta).cos() <= 0.0).then(|| (d.name.clone(), phi, theta))
        })
    }

    /// Assembly with every driver moved from its value at the guess to its value at
    /// `options.t` in steps (see the module docs), on a copy of the model whose drivers hold
    /// constant intermediate values; the last step assembles this model at `options.t`.
    fn assemble_by_continuation(
        &self,
        ws: &mut Workspace,
        options: &AssemblyOptions,
    ) -> Result<AssemblyReport, AnalysisError> {
        // Each driver's path: start value and total change.
        let paths: Vec<(f64, f64)> = self
            .drivers
            .iter()
            .map(|d| {
                let (si, sj) = (ws.state_of(d.body_i), ws.state_of(d.body_j));
                let c0 = d.driver.coordinate(&BodyPair::new(&si, &sj));
                let target = d.driver.function().eval(options.t).0;
                let change = match d.driver {
                    // The shorter way round: θ(t) taken within π of the drawn angle.
                    Driver::Rotation(_) => unwrap_angle(c0, target) - c0,
                    _ => target - c0,
                };
                (c0, change)
            })
            .collect();
        let largest_turn = self
            .drivers
            .iter()
            .zip(&paths)
            .filter(|(d, _)| matches!(d.driver, Driver::Rotation(_)))
            .fold(0.0f64, |a, (_, p)| a.max(p.1.abs()));
        let steps = ((largest_turn / CONTINUATION_MAX_ANGLE).ceil() as usize).max(4);
        let mut held = self.clone();
        for k in 1..steps {
            let s = k as f64 / steps as f64;
            for (d, (c0, change)) in held.drivers.iter_mut().zip(&paths) {
                // A pose driver's three angles are not separable row by row: it holds its
                // prescription at options.t throughout.
                if matches!(d.driver, Driver::Pose(_)) {
                    continue;
                }
                d.driver
                    .set_function(TimeFunction::Constant(c0 + s * change));
            }
            held.assemble_direct(ws, options)?;
        }
        self.assemble_direct(ws, options)
    }

    /// One minimum-norm Newton solve from the workspace's poses (see [`assemble`](Self::assemble)).
    fn assemble_direct(
        &self,
        ws: &mut Workspace,
        options: &AssemblyOptions,
    ) -> Result<AssemblyReport, AnalysisError> {
        let m = if options.include_drivers {
            self.num_equations()
        } else {
            self.num_joint_equations()
        };
        let n = self.num_unknowns();
        // Rows are laid out element by element, so the first m rows own the first k slots.
        let k = self.pattern.entries().take_while(|&(r, _)| r < m).count();
        let entries: Vec<(usize, usize)> = self.pattern.entries().take(k).collect();
        let pattern = SparsityPattern::new(m, n, &entries)
            .map_err(|e| crate::analysis::dof::solver(options.t, e))?;
        let nopts = NewtonOptions {
            tolerances: options.tolerances,
            max_iterations: options.max_iterations,
            line_search: LineSearch::Backtracking {
                max_halvings: 12,
                sufficient_decrease: 1e-4,
            },
            max_step: options.max_step,
            factor_at_solution: false,
            ..NewtonOptions::default()
        };
        let guess = ws.pose.x.clone();
        ws.pose.t = options.t;
        ws.motion.v.fill(0.0);
        ws.motion.vdot.fill(0.0);
        ws.invalidate();
        let result = self.min_norm_solve(ws, options.t, &pattern, nopts)?;
        match result {
            Ok(rep) => Ok(self.assembled(ws, &guess, rep, 0.0)),
            Err(e) => {
                let iterations = match &e {
                    SolverError::NotConverged { iterations, .. } => *iterations,
                    _ => 0,
                };
                if iterations > 0 {
                    // A slightly inconsistent redundant model: the iterate is near its
                    // least-squares pose, where the kept rows can be solved exactly.
                    if let Some(kept) = self.assemble_kept_rows(ws, options, &pattern, nopts, false)
                    {
                        return kept.map(|(rep, dropped)| self.assembled(ws, &guess, rep, dropped));
                    }
                }
                let open = self.open_elements(ws, m, options.tolerances.residual.max(1e-8));
                if let Some(fit) = self.assemble_from_best_fit(ws, options, &guess, &pattern, nopts)
                {
                    return fit;
                }
                Err(AnalysisError::AssemblyFailed { open, iterations })
            }
        }
    }

    /// Newton with the minimum-norm step on `pattern`'s rows from the workspace's poses at `t`
    /// (dense QR, or sparse from [`SPARSE_RANK_MIN_UNKNOWNS`] unknowns); the poses synced.
    fn min_norm_solve(
        &self,
        ws: &mut Workspace,
        t: f64,
        pattern: &SparsityPattern,
        nopts: NewtonOptions,
    ) -> Result<Solved, AnalysisError> {
        let m = pattern.nrows();
        if m == 0 {
            return Ok(Ok(None));
        }
        let mut sys = AssemblySystem::new(self, &mut ws.pose.bodies, &ws.pose.turns, t, m);
        let solved = if self.num_unknowns() >= SPARSE_RANK_MIN_UNKNOWNS {
            min_norm_newton(
                pattern,
                SparseMinNorm::new(),
                nopts,
                &mut sys,
                &mut ws.pose.x,
            )
        } else {
            min_norm_newton(pattern, MinNormQr::new(), nopts, &mut sys, &mut ws.pose.x)
        }
        .map_err(|e| crate::analysis::dof::solver(t, e))?;
        ws.sync_poses();
        Ok(solved)
    }

    /// After Newton failed from the drawn pose `guess`: the best fit of the equations from
    /// there (`analysis::best_fit`). When it satisfies them, Newton from it (a part drawn far
    /// from its place: the best fit globalizes); when it does not and the model is
    /// over-constrained as drawn (more equations than unknowns, and rows redundant at the drawn
    /// pose), it is inconsistent:
    /// the rows the rank analysis drops there, with the others solved
    /// ([`Self::assemble_kept_rows`]: [`AnalysisError::InconsistentJoints`] naming them and
    /// how far they stay open, or the pose with them dropped under
    /// [`AssemblyOptions::drop_inconsistent`]). `None` when the best fit cannot be found or
    /// leads nowhere (the caller reports the Newton failure).
    fn assemble_from_best_fit(
        &self,
        ws: &mut Workspace,
        options: &AssemblyOptions,
        guess: &[f64],
        pattern: &SparsityPattern,
        nopts: NewtonOptions,
    ) -> Option<Result<AssemblyReport, AnalysisError>> {
        let failed = ws.pose.x.clone();
        ws.pose.x.copy_from_slice(guess);
        ws.sync_poses();
        // Over-constrained as drawn: some equations are redundant at the drawn pose. A loop
        // that merely cannot close (a coupler too short) has none there; at its best fit it is
        // stretched, singular, and the rank analysis would take that for redundancy.
        let mut slots = vec![0.0; self.pattern.num_slots()];
        self.jacobian_into(&ws.pose.bodies, ws.pose.u(), options.t, &mut slots);
        // A row that vanishes as drawn (a distance joint drawn with its points together) is
        // degenerate there, not redundant.
        let mut row_size = vec![0.0f64; pattern.nrows()];
        for ((r, _), v) in pattern.entries().zip(&slots) {
            row_size[r] = row_size[r].max(v.abs());
        }
        let largest = row_size.iter().fold(0.0f64, |a, &b| a.max(b));
        // More equations than unknowns as well: a loop drawn in a singular pose (two distance
        // joints drawn in line) has dependent rows there without being over-constrained.
        let redundant_as_drawn = pattern.nrows() > pattern.ncols()
            && RankAnalysis::compute_auto(
                pattern,
                &slots[..pattern.num_slots()],
                Default::default(),
            )
            .is_ok_and(|ra| (ra.dependent_rows().iter()).any(|&r| row_size[r] > 1e-12 * largest));
        let off = self.best_fit(ws, options.t, pattern.nrows());
        let outcome = match off {
            Some(off) if off <= options.tolerances.residual => {
                match self.min_norm_solve(ws, options.t, pattern, nopts) {
                    Ok(Ok(rep)) => Some(Ok(self.assembled(ws, guess, rep, 0.0))),
                    _ => None,
                }
            }
            Some(_) if !redundant_as_drawn => None,
            Some(_) => self
                .assemble_kept_rows(ws, options, pattern, nopts, true)
                .map(|kept| kept.map(|(rep, dropped)| self.assembled(ws, guess, rep, dropped))),
            None => None,
        };
        if outcome.is_none() {
            ws.pose.x.copy_from_slice(&failed);
            ws.sync_poses();
        }
        outcome
    }

    /// The report of an assembly that reached the workspace's poses from `guess` (the turns of
    /// its couplers accepted).
    fn assembled(
        &self,
        ws: &mut Workspace,
        guess: &[f64],
        rep: MinNormSolve,
        dropped_residual: f64,
    ) -> AssemblyReport {
        self.accept_turns(&ws.pose.bodies, &mut ws.pose.turns);
        let (mut dt, mut dr) = (0.0f64, 0.0f64);
        for b in 0..self.num_bodies() {
            let (g, x) = (&guess[7 * b..7 * b + 7], &ws.pose.x[7 * b..7 * b + 7]);
            let d = ((x[0] - g[0]).powi(2) + (x[1] - g[1]).powi(2) + (x[2] - g[2]).powi(2)).sqrt();
            dt = dt.max(d);
            let dot: f64 = (3..7).map(|c| x[c] * g[c]).sum();
            dr = dr.max(2.0 * dot.abs().min(1.0).acos());
        }
        AssemblyReport {
            iterations: rep.map_or(0, |r| r.0.iterations),
            residual: rep.map_or(0.0, |r| r.0.residual_norm),
            max_translation: dt,
            max_rotation: dr,
            rank: rep.and_then(|r| r.1),
            dropped_residual,
        }
    }

    /// The least-squares-consistent pose of a slightly inconsistent redundant model, from the
    /// last iterate of a minimum-norm solve of all `pattern.nrows()` equations that did not
    /// converge (`analysis::dropped`): the rank analysis there, with the tolerance widened by
    /// the residual, picks the independent rows, and Newton solves those exactly. `None` when
    /// the iterate is off by more than
    /// [`LEAST_SQUARES_MAX_RESIDUAL`](crate::analysis::dropped::LEAST_SQUARES_MAX_RESIDUAL), no
    /// row is redundant there or the kept rows do not converge (the caller reports the
    /// original failure); otherwise the solve and the largest scaled residual of the dropped
    /// rows, or [`AnalysisError::InconsistentJoints`] when it exceeds
    /// [`gross_inconsistency`](crate::analysis::dropped::gross_inconsistency).
    fn assemble_kept_rows(
        &self,
        ws: &mut Workspace,
        options: &AssemblyOptions,
        pattern: &SparsityPattern,
        nopts: NewtonOptions,
        at_best_fit: bool,
    ) -> Option<Result<(MinNormSolve, f64), AnalysisError>> {
        let (m, t) = (pattern.nrows(), options.t);
        self.phi_into(
            &ws.pose.bodies,
            ws.pose.u(),
            &ws.pose.turns,
            t,
            &mut ws.rows.phi,
        );
        let off = self.scaled_residual(&ws.rows.phi, m);
        if (off > crate::analysis::dropped::LEAST_SQUARES_MAX_RESIDUAL && !at_best_fit)
            || off.is_nan()
        {
            // Not close: a model that cannot close (or a non-finite iterate).
            return None;
        }
        let rank_options = self.rank_options_for(&ws.rows.phi, m);
        let mut slots = vec![0.0; self.pattern.num_slots()];
        self.jacobian_into(&ws.pose.bodies, ws.pose.u(), t, &mut slots);
        let ra = RankAnalysis::compute_auto(pattern, &slots[..pattern.num_slots()], rank_options)
            .ok()?;
        if ra.dependent_rows().is_empty() {
            return None;
        }
        let selection = pattern.select_rows(ra.independent_rows()).ok()?;
        let mut sys = AssemblySystem::new(self, &mut ws.pose.bodies, &ws.pose.turns, t, m);
        let solved = if self.num_unknowns() >= SPARSE_RANK_MIN_UNKNOWNS {
            kept_rows_newton(
                pattern,
                selection,
                SparseMinNorm::new(),
                nopts,
                &mut sys,
                &mut ws.pose.x,
            )
        } else {
            kept_rows_newton(
                pattern,
                selection,
                MinNormQr::new(),
                nopts,
                &mut sys,
                &mut ws.pose.x,
            )
        };
        ws.sync_poses();
        let rep = solved.ok()?;
        self.phi_into(
            &ws.pose.bodies,
            ws.pose.u(),
            &ws.pose.turns,
            t,
            &mut ws.rows.phi,
        );
        let mut kept = vec![false; m];
        for &r in ra.independent_rows() {
            kept[r] = true;
        }
        let dropped = self.dropped_residual(&ws.rows.phi[..m], &kept);
        if dropped > crate::analysis::dropped::gross_inconsistency(options.tolerances.residual)
            && !options.drop_inconsistent
        {
            let rows =
                self.dropped_rows_at(&ws.rows.phi[..m], &kept, t, options.tolerances.residual);
            return Some(Err(AnalysisError::InconsistentJoints {
                time: t,
                limit: crate::analysis::dropped::gross_inconsistency(options.tolerances.residual),
                dropped: rows,
            }));
        }
        Some(Ok((Some(rep), dropped)))
    }

    /// The elements among the first `m` rows whose scaled residual exceeds `tol`, largest first.
    pub(crate) fn open_elements(&self, ws: &mut Workspace, m: usize, tol: f64) -> Vec<OpenElement> {
        self.phi_into(
            &ws.pose.bodies,
            ws.pose.u(),
            &ws.pose.turns,
            ws.pose.t,
            &mut ws.rows.phi,
        );
        let mut open = Vec::new();
        let mut check = |name: &str, rows: &std::ops::Range<usize>| {
            if rows.start >= m {
                return;
            }
            let scaled = rows
                .clone()
                .map(|r| (ws.rows.phi[r] / self.equation_scales[r]).abs())
                .fold(0.0, f64::max);
            if scaled > tol || scaled.is_nan() {
                let norm = rows
                    .clone()
                    .map(|r| ws.rows.phi[r] * ws.rows.phi[r])
                    .sum::<f64>()
                    .sqrt();
                open.push((
                    scaled,
                    OpenElement {
                        element: name.to_string(),
                        residual: norm,
                    },
                ));
            }
        };
        for j in &self.joints {
            check(&j.name, &j.rows);
        }
        for c in &self.couplers {
            check(&c.name, &c.rows);
        }
        for d in &self.drivers {
            check(&d.name, &d.rows);
        }
        open.sort_by(|a, b| b.0.total_cmp(&a.0));
        open.into_iter().map(|(_, e)| e).collect()
    }
}
