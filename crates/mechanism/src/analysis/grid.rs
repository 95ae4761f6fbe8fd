//! Kinematic analysis over a time grid.
//!
//! At each time t_k = t0 + k·dt: predict the poses from the previous steps, solve the position
//! equations, then (if asked) velocity and acceleration, and store the requested outputs. The
//! prediction is a Taylor step x ⊕ (v dt + ½ v̇ dt² + ⅙ j dt³) when velocities (and
//! accelerations) are computed, with the jerk j from the last two accelerations and the rotation
//! increment's second Magnus term (dt³/12) ω' × ω̇' (error O(dt⁴)), taken for each body relative
//! to its parent in a spanning tree of the joints where that motion is slower than the absolute
//! one (see `predictor`: a long chain's far links are then predicted exactly when its joints
//! turn uniformly); otherwise the linear extrapolation x_k ⊕ (x_k ⊖ x_{k−1}) (the same relative
//! rotation applied once more). The prediction keeps the kinematic factorization, so the
//! position solve starts with chord steps. Storage is reserved before the first step, so a step
//! does not allocate.
//!
//! # Coarse steps: staying on the assembly branch
//! A closed loop has several assembly branches (an RSSR four-bar's rocker can close the loop
//! on either side). On a fine grid the prediction lies close to the solution on the branch of
//! the previous step, so Newton stays there. On a coarse grid (two steps per crank turn) the
//! prediction can be far off and Newton may converge on the other branch. Each step is
//! therefore checked, body by body, by comparing the Newton correction C_b = |x ⊖ x_pred| with
//! the predicted motion M_b = |x_pred ⊖ x_{k−1}| (the larger of the rotation angle and the
//! translation over the characteristic length L):
//!
//! ```text
//! jump  ⇔  C_b > κ M_b + ε for some body b,      κ = 0.5,  ε = 1e-2
//! ```
//!
//! A good prediction misses by O(dt⁴) (Taylor) or O(dt²) (extrapolation) against a motion of
//! O(dt), so a fine grid never trips it and its output is unchanged; a branch change moves some
//! body by a finite amount the prediction did not foresee. The test reads three stored states
//! and allocates nothing. On a jump the step restarts from step k − 1 in 2 substeps; a substep
//! that jumps returns to the last accepted substep and halves the substep, down to
//! 1/2^[`MAX_SUBDIVISION_DEPTH`] of the grid step, where a jump is accepted: the mechanism is
//! then at a branch or limit point, which the next solves report as a singular configuration. Each
//! substep is predicted from the last, with its velocity and acceleration solved as on the grid;
//! only the grid times are stored, and [`Results::subdivided_steps`] counts the subdivided
//! steps (their Newton iterations, rejected attempts included, are summed into the step's).
//! A frame without a prediction (the first step of a run without velocities) is not checked.
//!
//! A failure mid-run (singular configuration, no convergence) returns an error that carries the
//! time, the named equations, and the results up to the last successful step.

use crate::analysis::assembly::AssemblyOptions;
use crate::analysis::least_change::{FreeDof, HeldRun};
use crate::analysis::position::{OpenRow, PositionReport};
use crate::error::AnalysisError;
use crate::model::{BodyId, CurveElement, Model};
use crate::results::{
    BodyResults, CurveResults, FrameSink, JointResults, Outputs, PointResults, Results, RunTotals,
};
use crate::workspace::Workspace;
use cardan_constraints::joints::{continue_angle, unwrap_angle};
use cardan_constraints::joints::{CoordinateQuantity, MAX_COORDINATES};
use cardan_constraints::BodyPair;
use cardan_eulerparam::EulerParams;
use cardan_solver::{NewtonOptions, Tolerances};
use nalgebra::Vector3;
use std::ops::ControlFlow;

/// κ of the branch-jump test: a step whose Newton correction exceeds κ times the predicted
/// motion (plus [`BRANCH_JUMP_FLOOR`]) is taken to have left the assembly branch.
pub const BRANCH_JUMP_RATIO: f64 = 0.5;

/// ε of the branch-jump test (radians, or lengths in units of the model's characteristic
/// length): corrections below it never count as a jump, whatever the predicted motion. It
/// covers the O(dt²) misses of the first-order predictors (velocity only, or extrapolation
/// without velocities) near a body's reversal, where its predicted motion is small: at 1e-4
/// a 50-step slider-crank run with velocities only solved 8 extra substeps.
pub const BRANCH_JUMP_FLOOR: f64 = 1e-2;

/// At most 2^10 = 1,024 substeps per grid step; a substep of that size that still jumps is
/// accepted (a branch or limit point: the following solves report it as singular).
pub const MAX_SUBDIVISION_DEPTH: u32 = 10;

/// The predicted relative rotation of a joint over one step (or substep) above which the step
/// is solved in substeps: π/3. The couplers' angles and the joint angles of the outputs are
/// continued over turns from one accepted pose to the next by the nearest value, which needs
/// each to change by less than π; a Newton start predicted from a step that turns a joint by π
/// or more may also converge a turn off (a rotation driver holds its angle only modulo 2π).
pub const MAX_TURN_PER_STEP: f64 = std::f64::consts::FRAC_PI_3;

/// A position-only run predicts a step's joint rotation from the rate of its last step, times
/// this margin for a motion that speeds up ([`MAX_TURN_PER_STEP`]).
pub const TURN_RATE_MARGIN: f64 = 1.5;

/// What became of one attempt at a step or substep ([`Model::try_step`]).
#[derive(Debug)]
enum Verdict {
    /// The solution is on the branch of the start and every solved equation holds.
    Accepted,
    /// The solution jumped to another assembly branch (module docs).
    Jumped,
    /// Newton converged, but once the couplers' angles are continued this solved row is open
    /// by its scaled residual ([`PositionReport::open`]).
    Open(OpenRow),
    /// Newton did not converge.
    Failed(Box<AnalysisError>),
}

/// The frame a subdivided step returns to (its poses in `x_tmp`, velocities and accelerations
/// in `v_saved`, `vdot_saved`).
struct SavedFrame {
    t: f64,
    velocity_valid: bool,
    acceleration_valid: bool,
}

/// The change of a body between two poses (7 coordinates [r; p]): the larger of the rotation
/// angle of p_aᵀ ⊗ p_b (radians, in [0, π]) and |r_b − r_a| / L.
fn pose_distance(a: &[f64], b: &[f64], length: f64) -> f64 {
    let dr = (0..3).map(|c| (b[c] - a[c]).powi(2)).sum::<f64>().sqrt() / length;
    let pa = EulerParams::new(a[3], a[4], a[5], a[6]);
    let pb = EulerParams::new(b[3], b[4], b[5], b[6]);
    let q = *pa.conjugate().compose(&pb).as_vector();
    let angle = 2.0 * q.fixed_rows::<3>(1).norm().atan2(q[0].abs());
    dr.max(angle)
}

/// Options of a kinematic run.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct KinematicOptions {
    /// Start time.
    pub t0: f64,
    /// End time.
    pub t_end: f64,
    /// Number of intervals (the run stores `steps + 1` times).
    pub steps: usize,
    /// What to compute and store.
    pub outputs: Outputs,
    /// The position solves' tolerance on the scaled residual, max |Φ_i| / e_i (e_i the
    /// equation's scale: L, L² or 1), in [1e-14, 1e-6]; default 1e-10. Used when the run
    /// prepares the workspace (a workspace already prepared keeps its Newton options).
    pub tolerance: f64,
    /// Degrees of freedom no driver prescribes: refused (the default) or held by least change
    /// ([`crate::analysis::least_change`]). Read when the run prepares the workspace.
    pub free_dof: FreeDof,
    /// Assemble an inconsistent over-constrained model with its disagreeing rows dropped
    /// ([`AssemblyOptions::drop_inconsistent`]); default false. Read when the run prepares the
    /// workspace.
    pub drop_inconsistent: bool,
}

impl KinematicOptions {
    /// `steps` intervals from `t0` to `t_end`, every output.
    pub fn new(t0: f64, t_end: f64, steps: usize) -> Self {
        Self {
            t0,
            t_end,
            steps,
            outputs: Outputs::default(),
            tolerance: Tolerances::default().residual,
            free_dof: FreeDof::Refuse,
            drop_inconsistent: false,
        }
    }

    /// The same options with [`KinematicOptions::drop_inconsistent`] set.
    pub fn drop_inconsistent(mut self, drop: bool) -> Self {
        self.drop_inconsistent = drop;
        self
    }

    /// The assembly options of a run at t0 (drivers included).
    pub(crate) fn assembly(&self) -> AssemblyOptions {
        AssemblyOptions {
            drop_inconsistent: self.drop_inconsistent,
            ..AssemblyOptions::at(self.t0)
        }
    }

    /// The same options with free degrees of freedom held or refused ([`FreeDof`]).
    pub fn free_dof(mut self, free_dof: FreeDof) -> Self {
        self.free_dof = free_dof;
        self
    }

    /// The same options with the position tolerance `tolerance` (see [`KinematicOptions::tolerance`]).
    pub fn tolerance(mut self, tolerance: f64) -> Self {
        self.tolerance = tolerance;
        self
    }

    /// Steps of about `dt` from `t0` to `t_end` (the step is adjusted to land on `t_end`). A
    /// non-positive `dt` with `t_end > t0` gives zero steps, which the run rejects.
    pub fn with_dt(t0: f64, t_end: f64, dt: f64) -> Self {
        let usable = dt > 0.0 && dt.is_finite() && t_end > t0;
        let steps = if usable {
            (((t_end - t0) / dt).round() as usize).max(1)
        } else {
            0
        };
        Self::new(t0, t_end, steps)
    }

    /// The same options with other outputs.
    pub fn outputs(mut self, outputs: Outputs) -> Self {
        self.outputs = outputs;
        self
    }

    /// The time of step k.
    pub fn time(&self, k: usize) -> f64 {
        if self.steps == 0 {
            return self.t0;
        }
        self.t0 + (self.t_end - self.t0) * (k as f64 / self.steps as f64)
    }

    /// Checks the times, the step count and the tolerance's range.
    ///
    /// # Errors
    /// [`AnalysisError::Options`] saying which option and why.
    pub fn validate(&self) -> Result<(), AnalysisError> {
        if !self.t0.is_finite() || !self.t_end.is_finite() {
            return Err(AnalysisError::Options(format!(
                "times must be finite (t0 = {}, t_end = {})",
                self.t0, self.t_end
            )));
        }
        if self.t_end < self.t0 {
            return Err(AnalysisError::Options(format!(
                "t_end = {} is before t0 = {}",
                self.t_end, self.t0
            )));
        }
        if self.steps == 0 && self.t_end > self.t0 {
            return Err(AnalysisError::Options(
                "at least one step is needed (or dt must be positive)".into(),
            ));
        }
        self.newton_tolerances()
            .validate()
            .map_err(AnalysisError::Options)
    }

    fn newton_tolerances(&self) -> Tolerances {
        Tolerances {
            residual: self.tolerance,
            ..Tolerances::default()
        }
    }
}

impl Model {
    /// A complete kinematic run on a fresh workspace: assembly at `t0` (drivers included), the
    /// DOF/driver check, then [`Model::kinematics`].
    ///
    /// # Errors
    /// Assembly, driver-count and mid-run errors (the latter with partial results).
    pub fn run_kinematics(&self, options: &KinematicOptions) -> Result<Results, AnalysisError> {
        let mut ws = self.workspace();
        self.kinematics(&mut ws, options)
    }

    /// Runs position (and, as asked, velocity and acceleration) analysis over the time grid,
    /// starting from the poses in `ws`. If the kinematic solver is not prepared yet, the
    /// workspace is first assembled (joints only), the driver count is checked against the
    /// degrees of freedom, then it is assembled with the drivers at `t0` and prepared
    /// ([`Model::prepare_kinematics`]).
    ///
    /// # Errors
    /// [`AnalysisError::Options`], assembly and driver-count errors before the run; on a failure
    /// at a step, [`AnalysisError::Singular`] / [`AnalysisError::NotConverged`] with the results
    /// so far ([`AnalysisError::partial_results`]).
    pub fn kinematics(
        &self,
        ws: &mut Workspace,
        options: &KinematicOptions,
    ) -> Result<Results, AnalysisError> {
        self.kinematics_with_progress(ws, options, |_, _| {})
    }

    /// [`kinematics`](Self::kinematics), calling `progress(k, t_k)` after each stored step
    /// (k = 0..=steps), e.g. to drive a progress bar.
    ///
    /// # Errors
    /// As [`kinematics`](Self::kinematics).
    pub fn kinematics_with_progress(
        &self,
        ws: &mut Workspace,
        options: &KinematicOptions,
        mut progress: impl FnMut(usize, f64),
    ) -> Result<Results, AnalysisError> {
        self.kinematics_with_control(ws, options, |k, t| {
            progress(k, t);
            ControlFlow::Continue(())
        })
    }

    /// [`kinematics_with_progress`](Self::kinematics_with_progress) whose callback may stop the
    /// run: when `progress(k, t_k)` returns [`ControlFlow::Break`], the results of steps 0..=k
    /// are returned (fewer than `steps + 1` times; e.g. Ctrl-C in the command line).
    ///
    /// The results are collected by a [`FrameSink`] over [`kinematics_into`](Self::kinematics_into)
    /// that appends each frame to storage reserved at the first frame.
    ///
    /// # Errors
    /// As [`kinematics`](Self::kinematics).
    pub fn kinematics_with_control(
        &self,
        ws: &mut Workspace,
        options: &KinematicOptions,
        mut progress: impl FnMut(usize, f64) -> ControlFlow<()>,
    ) -> Result<Results, AnalysisError> {
        let mut all: Option<Results> = None;
        let run = self.kinematics_into(ws, options, &mut |k: usize, frame: &Results| {
            all.get_or_insert_with(|| frame.empty_like(options.steps + 1))
                .extend_from(frame);
            progress(k, frame.times[0])
        });
        let mut results = all.unwrap_or_default();
        match run {
            Ok(totals) => {
                results.set_totals(totals);
                Ok(results)
            }
            Err(e) => match e.partial_results() {
                Some(totals) => {
                    results.set_totals(totals.totals());
                    Err(e.with_partial(results))
                }
                None => Err(e),
            },
        }
    }

    /// The time grid of [`kinematics`](Self::kinematics), streamed: each solved frame goes to
    /// `sink` as it is computed, in storage reserved for one frame and reused, so memory does
    /// not grow with the steps and a step does not allocate. Returns the run's counters and the
    /// dropped rows not satisfied ([`RunTotals`]); the sink stops the run early with
    /// [`ControlFlow::Break`].
    ///
    /// # Errors
    /// As [`kinematics`](Self::kinematics); a failure at a step carries as its
    /// [`partial_results`](AnalysisError::partial_results) a [`Results`] without frames (those
    /// went to the sink) holding the run's counters and dropped rows.
    pub fn kinematics_into(
        &self,
        ws: &mut Workspace,
        options: &KinematicOptions,
        sink: &mut impl FrameSink,
    ) -> Result<RunTotals, AnalysisError> {
        options.validate()?;
        if ws.kin.newton.is_none() {
            if let Some(held) = self.prepare_run(ws, options)? {
                return self.held_into(ws, options, sink, held);
            }
        }
        let mut frame = self.allocate_results(options, 1);
        let mut memory = JointMemory::new(self.joints.len());
        let reselections = ws.counters.reselections;
        let mut frames = 0;
        for k in 0..=options.steps {
            let t = options.time(k);
            frame.clear_frames();
            let step = self.step(ws, options, k, t, &mut frame, &mut memory);
            frame.row_reselections = ws.counters.reselections - reselections;
            if let Err(e) = step {
                frame.clear_frames();
                frame.dropped_rows = self.dropped_rows_of_run(ws);
                return Err(e.with_partial(frame));
            }
            frames += 1;
            if sink.frame(k, &frame).is_break() {
                break;
            }
        }
        Ok(RunTotals {
            frames,
            subdivided_steps: frame.subdivided_steps,
            row_reselections: frame.row_reselections,
            dropped_rows: self.dropped_rows_of_run(ws),
            held_dof: 0,
            held_from_assembly: false,
        })
    }

    /// Assembles an unprepared workspace for a run (joints, the driver count, then the drivers
    /// at t0) and prepares the kinematic solver with the run's tolerance.
    ///
    /// With `free_dof = "hold"` the driven run is tried first: a mechanism whose drivers take
    /// every degree of freedom runs as without the option (the least-change assembly would be
    /// solved, its DOF counted and its pose then thrown away: a fifth of a small fully driven
    /// ASMT file's run). When that preparation fails (too few drivers, or an assembly the
    /// least change may still reach from the drawn pose), the workspace goes back to the drawn
    /// pose and the held run is prepared; a mechanism the least change finds fully driven too
    /// gets the driven run's error.
    fn prepare_run(
        &self,
        ws: &mut Workspace,
        options: &KinematicOptions,
    ) -> Result<Option<HeldRun>, AnalysisError> {
        let FreeDof::Hold(metric) = options.free_dof else {
            return self.prepare_driven(ws, options).map(|()| None);
        };
        let drawn = ws.pose.x.clone();
        let Err(driven) = self.prepare_driven(ws, options) else {
            return Ok(None);
        };
        ws.pose.x.copy_from_slice(&drawn);
        ws.sync_poses();
        ws.reset_dropped_rows();
        ws.invalidate();
        match self.prepare_held(ws, options, metric)? {
            Some(held) => Ok(Some(held)),
            None => Err(driven),
        }
    }

    /// [`Self::prepare_run`] for a run whose drivers take every degree of freedom.
    fn prepare_driven(
        &self,
        ws: &mut Workspace,
        options: &KinematicOptions,
    ) -> Result<(), AnalysisError> {
        // Joints first, then the drivers. The preparation below checks the driver count
        // (one rank analysis); when the drivers make the assembly fail, the count is
        // checked at the joints' pose first (an over-driven mechanism gets "superfluous",
        // not "open").
        let joints_only = AssemblyOptions {
            include_drivers: false,
            ..options.assembly()
        };
        self.assemble(ws, &joints_only)?;
        ws.grid.x_tmp.copy_from_slice(&ws.pose.x);
        if let Err(e) = self.assemble(ws, &options.assembly()) {
            ws.pose.x.copy_from_slice(&ws.grid.x_tmp);
            ws.sync_poses();
            ws.invalidate();
            let dof = self.dof(ws)?;
            if dof.dof != dof.drivers {
                return Err(AnalysisError::DriverCount {
                    dof: dof.dof,
                    drivers: dof.drivers,
                });
            }
            return Err(e);
        }
        let newton = NewtonOptions {
            tolerances: options.newton_tolerances(),
            ..Self::kinematic_newton_options()
        };
        self.prepare_kinematics_with(ws, newton)?;
        Ok(())
    }

    /// The dropped rows off by more than the kinematic solver's residual tolerance during the
    /// run (`analysis::dropped`).
    fn dropped_rows_of_run(&self, ws: &Workspace) -> Vec<crate::results::DroppedRowResidual> {
        let tol = ws
            .kin
            .newton
            .as_ref()
            .map_or(Tolerances::default().residual, |n| {
                n.options().tolerances.residual
            });
        self.dropped_row_residuals(ws, tol)
    }

    /// One step of the grid (no allocation after warm-up): the position at t_k (subdivided when
    /// the full step jumps branches, module docs), then velocity and acceleration as asked.
    pub(crate) fn step(
        &self,
        ws: &mut Workspace,
        options: &KinematicOptions,
        k: usize,
        t: f64,
        results: &mut Results,
        joint_prev: &mut JointMemory,
    ) -> Result<(), AnalysisError> {
        let out = options.outputs;
        let rep = if k == 0 {
            // x_prev holds the solution of step k − 2 (for the linear extrapolation).
            ws.grid.x_tmp.copy_from_slice(&ws.pose.x);
            let rep = self.position(ws, t)?;
            ws.grid.x_prev.copy_from_slice(&ws.grid.x_tmp);
            self.check_stops(ws, t, true)?;
            rep
        } else {
            self.save_stop_frame(ws);
            let rep = self.advance(ws, t, k, out, &mut results.subdivided_steps, joint_prev)?;
            self.check_stops(ws, t, false)?;
            rep
        };
        self.check_curve_ends(ws, t)?;
        if out.needs_velocity() {
            self.velocity(ws)?;
        }
        if out.acceleration {
            self.acceleration(ws)?;
        }
        self.record(
            ws,
            out,
            k,
            rep.residual,
            rep.iterations,
            results,
            joint_prev,
        );
        Ok(())
    }

    /// Solves the position at grid time `t` from the accepted frame in `ws` (step k − 1): the
    /// full step first when no joint is predicted to turn by more than [`MAX_TURN_PER_STEP`];
    /// when it is, or when the full step's solution is rejected (a branch jump, equations left
    /// open once the couplers' turns are continued, or a Newton failure), again from step
    /// k − 1 in 2^d substeps (halved again on a rejection, [`MAX_SUBDIVISION_DEPTH`] halvings at
    /// most), counting the step in `subdivided`.
    fn advance(
        &self,
        ws: &mut Workspace,
        t: f64,
        k: usize,
        out: Outputs,
        subdivided: &mut usize,
        memory: &mut JointMemory,
    ) -> Result<PositionReport, AnalysisError> {
        let depth = self.motion_depth(ws, t - ws.pose.t, memory);
        let saved = self.save_frame(ws);
        let mut iterations = 0;
        if depth == 0 {
            let (rep, verdict) = self.try_step(ws, t, k, out, memory)?;
            if matches!(verdict, Verdict::Accepted) {
                return Ok(rep);
            }
            self.restore_frame(ws, &saved);
            // The iterations of the rejected full step count too.
            iterations = rep.iterations;
        }
        *subdivided += 1;
        let mut rep_sub = self.substeps(ws, saved, t, k, out, depth.max(1), memory)?;
        rep_sub.iterations += iterations;
        Ok(rep_sub)
    }

    /// The substep depth d (2^d substeps) that keeps every joint's predicted relative rotation
    /// over a substep of `dt` / 2^d within [`MAX_TURN_PER_STEP`]. With velocities (the run's
    /// outputs need them), from the relative angular velocity ω_rel = ω_j − ω_i (and
    /// acceleration ω̇_rel when valid) at the step's start: |ω_rel| dt + ½ |ω̇_rel| dt². A
    /// position-only run takes the largest joint rotation rate of its last accepted (sub)step
    /// (`memory.turn_rate`, times [`TURN_RATE_MARGIN`] for a motion that speeds up); before its
    /// first step it solves the velocities once for this alone (the prediction does not use
    /// them). Where they cannot be solved (a singular pose) no substep is asked for. Capped at
    /// [`MAX_SUBDIVISION_DEPTH`].
    fn motion_depth(&self, ws: &mut Workspace, dt: f64, memory: &JointMemory) -> u32 {
        let turn = match memory.turn_rate {
            Some(rate) if !ws.motion.velocity_valid => TURN_RATE_MARGIN * rate * dt.abs(),
            _ => {
                if !ws.motion.velocity_valid && self.velocity(ws).is_err() {
                    return 0;
                }
                self.predicted_turn(ws, dt)
            }
        };
        if !turn.is_finite() {
            return 0;
        }
        let ratio = turn / MAX_TURN_PER_STEP;
        if ratio <= 1.0 {
            return 0;
        }
        (ratio.log2().ceil() as u32).min(MAX_SUBDIVISION_DEPTH)
    }

    /// The largest relative rotation of a joint over `dt` predicted from the bodies' angular
    /// velocities (and accelerations when valid) in `ws`: |ω_rel| dt + ½ |ω̇_rel| dt².
    fn predicted_turn(&self, ws: &Workspace, dt: f64) -> f64 {
        let acc = ws.motion.acceleration_valid;
        let omega = |id: BodyId| match id {
            BodyId::Ground => (Vector3::zeros(), Vector3::zeros()),
            BodyId::Moving(b) => (
                ws.omega(b),
                if acc {
                    ws.omega_dot(b)
                } else {
                    Vector3::zeros()
                },
            ),
        };
        self.joints.iter().fold(0.0f64, |worst, j| {
            let ((wi, ai), (wj, aj)) = (omega(j.body_i), omega(j.body_j));
            let turn = (wj - wi).norm() * dt.abs() + 0.5 * (aj - ai).norm() * dt * dt;
            worst.max(turn)
        })
    }

    /// The largest relative rotation of a joint between the poses `x_tmp` (an attempt's start)
    /// and `x` (its solution) of `ws`: the angle of (p_i* ⊗ p_j)_startᵀ ⊗ (p_i* ⊗ p_j)_end.
    fn largest_turn(&self, ws: &Workspace) -> f64 {
        let p = |x: &[f64], id: BodyId| match id {
            BodyId::Ground => EulerParams::new(1.0, 0.0, 0.0, 0.0),
            BodyId::Moving(b) => {
                EulerParams::new(x[7 * b + 3], x[7 * b + 4], x[7 * b + 5], x[7 * b + 6])
            }
        };
        self.joints.iter().fold(0.0f64, |worst, j| {
            let relative = |x: &[f64]| p(x, j.body_i).conjugate().compose(&p(x, j.body_j));
            let q = *relative(&ws.grid.x_tmp)
                .conjugate()
                .compose(&relative(&ws.pose.x))
                .as_vector();
            worst.max(2.0 * q.fixed_rows::<3>(1).norm().atan2(q[0].abs()))
        })
    }

    /// Marches from the frame in `ws` (time t_a) to `t_b` in substeps of (t_b − t_a) / 2^depth,
    /// each predicted from the last; a substep that is rejected returns to the last accepted
    /// substep and halves the substep (depth + 1). The substep times are t_a + (t_b − t_a)·i/2^D
    /// with D = [`MAX_SUBDIVISION_DEPTH`] (the last is t_b itself), so no rounding accumulates.
    /// At the finest substep a branch jump is accepted (the mechanism is at a branch or limit
    /// point); equations left open or a Newton failure there end the run with an error.
    fn substeps(
        &self,
        ws: &mut Workspace,
        mut saved: SavedFrame,
        t_b: f64,
        k: usize,
        out: Outputs,
        mut depth: u32,
        memory: &mut JointMemory,
    ) -> Result<PositionReport, AnalysisError> {
        let t_a = ws.pose.t;
        let full = 1usize << MAX_SUBDIVISION_DEPTH;
        let mut done = 0usize;
        let mut iterations = 0;
        loop {
            let next = (done + (full >> depth)).min(full);
            let s = if next == full {
                t_b
            } else {
                t_a + (t_b - t_a) * (next as f64 / full as f64)
            };
            // After an accepted substep x_prev is the frame before: linear extrapolation works.
            let k_sub = if done > 0 { k.max(2) } else { k };
            let (rep, verdict) = self.try_step(ws, s, k_sub, out, memory)?;
            iterations += rep.iterations;
            let finest = depth == MAX_SUBDIVISION_DEPTH;
            let accept = match verdict {
                Verdict::Accepted => true,
                // The following solves report the singular configuration with its equations.
                Verdict::Jumped if finest => {
                    ws.grid.x_prev.copy_from_slice(&ws.grid.x_tmp);
                    true
                }
                Verdict::Open(open) if finest => {
                    return Err(AnalysisError::Discontinuous {
                        time: s,
                        worst: self
                            .equation(open.row)
                            .map(|n| (n, open.scaled_residual))
                            .into_iter()
                            .collect(),
                        partial: None,
                    });
                }
                Verdict::Failed(e) if finest => return Err(*e),
                _ => false,
            };
            match accept {
                true if next == full => return Ok(PositionReport { iterations, ..rep }),
                true => {
                    // The predictor of the next substep needs this one's velocity (and
                    // acceleration), as on the grid.
                    if out.needs_velocity() {
                        self.velocity(ws)?;
                    }
                    if out.acceleration {
                        self.acceleration(ws)?;
                    }
                    if out.joints {
                        self.follow_angles(ws, memory);
                    }
                    saved = self.save_frame(ws);
                    done = next;
                }
                false => {
                    self.restore_frame(ws, &saved);
                    depth += 1;
                }
            }
        }
    }

    /// One attempt from the frame in `ws` to time `t`: predict, solve, and judge the solution
    /// ([`Verdict`]). When it is not accepted `ws` holds what the solve left (the caller
    /// restores the frame); otherwise x_prev becomes the frame the step started from. A Newton
    /// failure to converge is a verdict (the step can be subdivided); other errors return.
    fn try_step(
        &self,
        ws: &mut Workspace,
        t: f64,
        k: usize,
        out: Outputs,
        memory: &mut JointMemory,
    ) -> Result<(PositionReport, Verdict), AnalysisError> {
        let dt = t - ws.pose.t;
        ws.grid.x_tmp.copy_from_slice(&ws.pose.x);
        let predicted = self.predict(ws, t - ws.pose.t, k, out);
        ws.grid.x_pred.copy_from_slice(&ws.pose.x);
        let rep = match self.position(ws, t) {
            Ok(rep) => rep,
            Err(e @ AnalysisError::NotConverged { iterations, .. }) => {
                let rep = PositionReport {
                    iterations,
                    residual: f64::NAN,
                    open: None,
                };
                return Ok((rep, Verdict::Failed(Box::new(e))));
            }
            Err(e) => return Err(e),
        };
        if let Some(open) = rep.open {
            return Ok((rep, Verdict::Open(open)));
        }
        if predicted && self.jumped(ws) {
            return Ok((rep, Verdict::Jumped));
        }
        if !out.needs_velocity() && dt != 0.0 {
            memory.turn_rate = Some(self.largest_turn(ws) / dt.abs());
        }
        ws.grid.x_prev.copy_from_slice(&ws.grid.x_tmp);
        Ok((rep, Verdict::Accepted))
    }

    /// Empty histories of the curve elements' parameters (one per parameter, in the order of
    /// the extra coordinates), room for `n` times; rates and accelerations when `(v, a)` say
    /// so. A cam pair's first entry also holds its contact and pressure angle.
    pub fn curve_histories(&self, n: usize, (v, a): (bool, bool)) -> Vec<CurveResults> {
        let cap = |on: bool| if on { n } else { 0 };
        (self.curves.iter())
            .flat_map(|c| c.element.parameters().iter().map(move |&p| (c, p)))
            .map(|(c, parameter)| {
                let cam = matches!(c.element, CurveElement::Cam(_)) && parameter == "u";
                CurveResults {
                    name: c.name.clone(),
                    parameter,
                    cam,
                    contact: Vec::with_capacity(if cam { n } else { 0 }),
                    pressure_angle: Vec::with_capacity(if cam { cap(v) } else { 0 }),
                    u: Vec::with_capacity(n),
                    u_dot: Vec::with_capacity(cap(v)),
                    u_ddot: Vec::with_capacity(cap(a)),
                }
            })
            .collect()
    }

    /// Each cam pair's contact point and, with velocities, its pressure angle
    /// ([`CurveElement::pressure_angle`]: the follower's point at the contact against the
    /// larger of its speed and the cam's point's; where neither velocity nor acceleration gives
    /// a direction, the last frame's angle, or 0 at the first). No allocation (room reserved).
    fn record_cams(&self, ws: &Workspace, (v, a): (bool, bool), res: &mut Results) {
        let u = ws.pose.u();
        for c in &self.curves {
            let (si, sj) = (ws.state_of(c.body_i), ws.state_of(c.body_j));
            let Some((point, normal, local)) = c.element.contact(&si, &sj, &u[c.extras()]) else {
                continue;
            };
            let h = &mut res.curves[c.extra];
            h.contact.push(point);
            if v {
                let vj = ws.point_velocity(c.body_j, &local);
                let vi = ws.point_velocity(c.body_i, &(si.a.transpose() * (point - si.r)));
                let acc = a.then(|| ws.point_acceleration(c.body_j, &local));
                let scale = vi.norm().max(vj.norm());
                let angle = CurveElement::pressure_angle(&normal, &vj, acc.as_ref(), scale)
                    .or_else(|| h.pressure_angle.last().copied())
                    .unwrap_or(0.0);
                h.pressure_angle.push(angle);
            }
        }
    }

    /// [`AnalysisError::CurveEnd`] when a point-on-curve element's parameter has left its open
    /// curve's data (beyond them the curve is only the straight continuation that keeps the
    /// equations smooth). Within a relative 1e-9 of the curve's length the end still counts.
    fn check_curve_ends(&self, ws: &Workspace, t: f64) -> Result<(), AnalysisError> {
        let u = ws.pose.u();
        for c in &self.curves {
            let names = c.element.parameters().iter();
            let on = c.element.domains().into_iter().zip(c.extras().zip(names));
            for (domain, (k, parameter)) in on {
                let Some((a, b)) = domain else {
                    continue;
                };
                let slack = 1e-9 * (b - a);
                let uk = u[k];
                if uk < a - slack || uk > b + slack {
                    let cam = matches!(c.element, CurveElement::Cam(_));
                    return Err(AnalysisError::CurveEnd {
                        what: c.element.what(),
                        element: c.name.clone(),
                        contact: if cam { "contact point" } else { "point" },
                        parameter,
                        time: t,
                        u: uk,
                        start: a,
                        end: b,
                        partial: None,
                    });
                }
            }
        }
        Ok(())
    }

    /// The branch-jump test (module docs): for some body, C_b > κ M_b + ε, with M_b its
    /// predicted motion (x_pred ⊖ x_start) and C_b its correction (x ⊖ x_pred).
    fn jumped(&self, ws: &Workspace) -> bool {
        let l = self.characteristic_length();
        let bodies = 7 * self.num_bodies();
        let start = ws.grid.x_tmp[..bodies].chunks_exact(7);
        let pred = ws.grid.x_pred[..bodies].chunks_exact(7);
        let solved = ws.pose.x[..bodies].chunks_exact(7);
        start.zip(pred).zip(solved).any(|((x0, xp), x)| {
            let motion = pose_distance(x0, xp, l);
            let correction = pose_distance(xp, x, l);
            correction > BRANCH_JUMP_RATIO * motion + BRANCH_JUMP_FLOOR
        })
    }

    /// Copies what a return to the current frame needs (the poses stay in `x` and are copied
    /// to `x_tmp` by the next attempt).
    fn save_frame(&self, ws: &mut Workspace) -> SavedFrame {
        ws.grid.v_saved.copy_from_slice(&ws.motion.v);
        ws.grid.vdot_saved.copy_from_slice(&ws.motion.vdot);
        ws.grid.turns_saved.copy_from_slice(&ws.pose.turns);
        SavedFrame {
            t: ws.pose.t,
            velocity_valid: ws.motion.velocity_valid,
            acceleration_valid: ws.motion.acceleration_valid,
        }
    }

    /// Returns `ws` to the frame an attempt started from (poses in `x_tmp`).
    fn restore_frame(&self, ws: &mut Workspace, saved: &SavedFrame) {
        ws.pose.x.copy_from_slice(&ws.grid.x_tmp);
        ws.motion.v.copy_from_slice(&ws.grid.v_saved);
        ws.motion.vdot.copy_from_slice(&ws.grid.vdot_saved);
        ws.pose.turns.copy_from_slice(&ws.grid.turns_saved);
        ws.pose.t = saved.t;
        ws.poses_moved();
        ws.sync_poses();
        ws.motion.velocity_valid = saved.velocity_valid;
        ws.motion.acceleration_valid = saved.acceleration_valid;
    }

    /// Moves the poses in `ws` to the Taylor prediction x ⊕ (v dt + ½ v̇ dt² + ⅙ j dt³) at
    /// `ws.time() + dt` from the current velocities (and accelerations and jerk, when valid),
    /// body by body relative to a parent where that is the slower motion (module docs): the
    /// Newton start the time grid uses, for callers that step frames themselves
    /// ([`Model::position`] at t + dt then converges in fewer, cheaper iterations: the
    /// factorization is kept for chord steps). Does nothing when the velocities are not valid.
    /// No allocation.
    pub fn predict_poses(&self, ws: &mut Workspace, dt: f64) {
        if ws.motion.velocity_valid {
            let _ = self.predict(ws, dt, 0, Outputs::default());
            ws.poses_moved();
        }
    }

    /// Moves the Newton start to the predicted poses at t + dt. False when there is nothing to
    /// predict from (no valid velocities and fewer than two earlier frames): the start stays
    /// at the last frame.
    fn predict(&self, ws: &mut Workspace, dt: f64, k: usize, out: Outputs) -> bool {
        let nb = self.num_bodies();
        if out.needs_velocity() && ws.motion.velocity_valid {
            let acc = out.acceleration && ws.motion.acceleration_valid;
            // Jerk from the last two accelerations (the last one is the current state's).
            let h = ws.jerk.vdot_last_time - ws.jerk.vdot_prev_time;
            let jerk = acc && ws.jerk.vdot_last_time == ws.pose.t && h != 0.0 && h.is_finite();
            let c3 = if jerk { dt * dt * dt / (6.0 * h) } else { 0.0 };
            crate::analysis::predictor::predict(self, ws, dt, acc, c3);
            // The extra coordinates (curve parameters) by their Taylor series.
            for e in 0..self.num_extra() {
                let (x, v) = (7 * nb + e, 6 * nb + e);
                let a = if acc { ws.motion.vdot[v] } else { 0.0 };
                ws.pose.x[x] += ws.motion.v[v] * dt + 0.5 * a * dt * dt;
            }
        } else if k >= 2 {
            for e in 7 * nb..ws.pose.x.len() {
                ws.pose.x[e] = 2.0 * ws.pose.x[e] - ws.grid.x_prev[e];
            }
            for b in 0..nb {
                let (xs, xp) = (
                    &mut ws.pose.x[7 * b..7 * b + 7],
                    &ws.grid.x_prev[7 * b..7 * b + 7],
                );
                for c in 0..3 {
                    xs[c] = 2.0 * xs[c] - xp[c];
                }
                let p = EulerParams::new(xs[3], xs[4], xs[5], xs[6]);
                let q = EulerParams::new(xp[3], xp[4], xp[5], xp[6]);
                let n = p.compose_unit(&q.conjugate().compose(&p));
                xs[3..].copy_from_slice(n.as_vector().as_slice());
            }
        } else {
            return false;
        }
        ws.sync_poses();
        true
    }

    /// Continues the joint angles of the outputs to an accepted substep (not stored): each by
    /// the nearest value, valid because a substep turns no joint by more than
    /// [`MAX_TURN_PER_STEP`]. The next stored frame continues from here by the nearest value
    /// too (the rates of the last stored frame are for another time). No allocation.
    fn follow_angles(&self, ws: &Workspace, memory: &mut JointMemory) {
        for (j, prev) in self.joints.iter().zip(memory.values.iter_mut()) {
            let (si, sj) = (ws.state_of(j.body_i), ws.state_of(j.body_j));
            let c = j.joint.coordinates(&BodyPair::new(&si, &sj));
            for (q, coord) in c.coordinates.iter().enumerate() {
                if coord.measure.quantity() == CoordinateQuantity::Angle {
                    prev[q] = unwrap_angle(prev[q], c.values[q]);
                }
            }
        }
        memory.t = Some(ws.pose.t);
        memory.rates_valid = false;
    }

    /// Empty results for the run's outputs with room for `n` frames.
    pub(crate) fn allocate_results(&self, options: &KinematicOptions, n: usize) -> Results {
        let out = options.outputs;
        let v = out.needs_velocity();
        let a = out.acceleration;
        let cap = |on: bool| if on { n } else { 0 };
        let bodies = self
            .bodies
            .iter()
            .map(|b| BodyResults {
                name: b.name.clone(),
                r: Vec::with_capacity(n),
                p: Vec::with_capacity(n),
                r_dot: Vec::with_capacity(cap(v)),
                p_dot: Vec::with_capacity(cap(v)),
                omega: Vec::with_capacity(cap(v)),
                omega_local: Vec::with_capacity(cap(v)),
                r_ddot: Vec::with_capacity(cap(a)),
                p_ddot: Vec::with_capacity(cap(a)),
                omega_dot: Vec::with_capacity(cap(a)),
                omega_dot_local: Vec::with_capacity(cap(a)),
            })
            .collect();
        let points = if out.points {
            self.points
                .iter()
                .filter(|p| p.body != BodyId::Ground)
                .map(|p| PointResults {
                    body: p.body_name.clone(),
                    name: p.name.clone(),
                    position: Vec::with_capacity(n),
                    velocity: Vec::with_capacity(cap(v)),
                    acceleration: Vec::with_capacity(cap(a)),
                })
                .collect()
        } else {
            Vec::new()
        };
        let joints = if out.joints {
            self.joints
                .iter()
                .map(|j| JointResults {
                    name: j.name.clone(),
                    kind: j.joint.kind(),
                    coordinates: j.joint.kind().info().coordinates,
                    values: Vec::with_capacity(n),
                    rates: Vec::with_capacity(cap(v)),
                    accelerations: Vec::with_capacity(cap(a)),
                })
                .collect()
        } else {
            Vec::new()
        };
        let curves = self.curve_histories(n, (v, a));
        Results {
            outputs: Some(out),
            times: Vec::with_capacity(n),
            bodies,
            points,
            joints,
            curves,
            residual: Vec::with_capacity(n),
            iterations: Vec::with_capacity(n),
            subdivided_steps: 0,
            held_dof: 0,
            held_from_assembly: false,
            row_reselections: 0,
            dropped_rows: Vec::new(),
        }
    }

    #[allow(clippy::too_many_arguments)]
    pub(crate) fn record(
        &self,
        ws: &Workspace,
        out: Outputs,
        k: usize,
        residual: f64,
        iterations: usize,
        res: &mut Results,
        memory: &mut JointMemory,
    ) {
        let v = out.needs_velocity();
        let a = out.acceleration;
        res.times.push(ws.pose.t);
        res.residual.push(residual);
        res.iterations.push(iterations);
        for (b, h) in res.bodies.iter_mut().enumerate() {
            h.r.push(ws.r(b));
            h.p.push(ws.p(b));
            if v {
                h.r_dot.push(ws.r_dot(b));
                h.p_dot.push(ws.p_dot(b));
                h.omega.push(ws.omega(b));
                h.omega_local.push(ws.omega_local(b));
            }
            if a {
                h.r_ddot.push(ws.r_ddot(b));
                h.p_ddot.push(ws.p_ddot(b));
                h.omega_dot.push(ws.omega_dot(b));
                h.omega_dot_local.push(ws.omega_dot_local(b));
            }
        }
        if out.points {
            let moving = self.points.iter().filter(|p| p.body != BodyId::Ground);
            for (i, p) in moving.enumerate() {
                let h = &mut res.points[i];
                h.position.push(ws.point_position(p.body, &p.local));
                if v {
                    h.velocity.push(ws.point_velocity(p.body, &p.local));
                }
                if a {
                    h.acceleration.push(ws.point_acceleration(p.body, &p.local));
                }
            }
        }
        let nb = self.num_bodies();
        for (e, h) in res.curves.iter_mut().enumerate() {
            h.u.push(ws.pose.x[7 * nb + e]);
            if v {
                h.u_dot.push(ws.motion.v[6 * nb + e]);
            }
            if a {
                h.u_ddot.push(ws.motion.vdot[6 * nb + e]);
            }
        }
        self.record_cams(ws, (v, a), res);
        let dt = memory.t.map_or(0.0, |t_prev| ws.pose.t - t_prev);
        memory.t = Some(ws.pose.t);
        if out.joints {
            for (idx, (j, h)) in self.joints.iter().zip(res.joints.iter_mut()).enumerate() {
                let (si, sj) = (ws.state_of(j.body_i), ws.state_of(j.body_j));
                let pair = BodyPair::new(&si, &sj);
                let c = j.joint.coordinates(&pair);
                let acc = |id| ws.acceleration_of(id, a);
                let rates = v.then(|| {
                    j.joint
                        .coordinate_rates(&pair, &acc(j.body_i), &acc(j.body_j))
                });
                let mut vals = c.values;
                let prev = &mut memory.values[idx];
                let prev_rates = memory.rates_valid.then_some(&memory.rates[idx]);
                for (q, coord) in c.coordinates.iter().enumerate() {
                    if k > 0 && coord.measure.quantity() == CoordinateQuantity::Angle {
                        let w = prev_rates
                            .zip(rates.as_ref())
                            .map(|(p, r)| (p[q], r.rates[q]));
                        vals[q] = continue_angle(prev[q], w, dt, vals[q]);
                    }
                }
                *prev = vals;
                h.values.push(vals);
                if let Some(r) = rates {
                    memory.rates[idx] = r.rates;
                    h.rates.push(r.rates);
                    if a {
                        h.accelerations.push(r.accelerations);
                    }
                }
            }
            memory.rates_valid = v;
        }
    }
}

/// What the joint coordinates of the next frame are continued from (angles over turns): the
/// last frame's values, rates (when computed) and time.
pub(crate) struct JointMemory {
    values: Vec<[f64; MAX_COORDINATES]>,
    rates: Vec<[f64; MAX_COORDINATES]>,
    rates_valid: bool,
    t: Option<f64>,
    /// A position-only run's largest joint rotation rate over its last accepted (sub)step
    /// (rad/s), for the next step's substeps ([`Model::motion_depth`]).
    turn_rate: Option<f64>,
}

impl JointMemory {
    pub(crate) fn new(joints: usize) -> Self {
        Self {
            values: vec![[0.0; MAX_COORDINATES]; joints],
            rates: vec![[0.0; MAX_COORDINATES]; joints],
            rates_valid: false,
            t: None,
            turn_rate: None,
        }
    }
}
