//! The preallocated [`Workspace`]: the mutable state of an analysis (poses, velocities,
//! accelerations, residual and right-hand-side buffers, the Newton solvers).
//!
//! Every buffer is sized when the workspace is made ([`crate::Model::workspace`]) or when the
//! kinematic solver is prepared ([`crate::Model::prepare_kinematics`]); a kinematic step
//! (position Newton, velocity, acceleration) then refills values only and does not allocate.
//!
//! The state vector of Newton-Raphson is `x = [r_0; p_0; r_1; p_1; …]` (7 per moving body); the
//! step is `[Δr_k; Δπ'_k]` (6 per body) and the Euler parameters are updated by a rotation,
//! p ← normalize(p ⊗ exp(Δπ'/2)) ([`apply_rotation_step`]), so p stays on the unit sphere without
//! normalization rows.

use crate::dof::DofReport;
use crate::model::{BodyId, Model};
use cardan_constraints::joints::BodyAcceleration;
use cardan_constraints::BodyState;
use cardan_eulerparam::{p_ddot_from_local, p_dot_from_local, EulerParams};
use cardan_solver::{AutoSolver, Newton, NonlinearSystem};
use nalgebra::{Vector3, Vector4};

/// The mutable state of a mechanism analysis. Made by [`Model::workspace`].
///
/// Grouped by what each part is for; every vector is sized once, in [`Workspace::new`].
#[derive(Debug)]
pub struct Workspace {
    /// The current frame: time, Newton state, body states and coupler turns.
    pub(crate) pose: PoseState,
    /// Velocities and accelerations of the current frame, and whether they are current.
    pub(crate) motion: MotionState,
    /// The last two accelerations, from which the predictor estimates the jerk.
    pub(crate) jerk: JerkSamples,
    /// The length-m buffers: right-hand side and Φ.
    pub(crate) rows: RowBuffers,
    /// The predictor's scratch.
    pub(crate) prediction: PredictionBuffers,
    /// The time grid's copies of frames (subdivision, branch-jump test, extrapolation).
    pub(crate) grid: GridFrames,
    /// The start of the current grid step, for a limit's crossing.
    pub(crate) stop_frame: StopFrame,
    /// The prepared kinematic Newton solver and what it was prepared with.
    pub(crate) kin: KinematicSolver,
    /// The rows dropped as redundant and their worst residuals (`analysis::dropped`).
    pub(crate) dropped: DroppedRows,
    /// Counters of work done.
    pub(crate) counters: Counters,
}

/// The current frame.
#[derive(Debug)]
pub(crate) struct PoseState {
    pub(crate) t: f64,
    /// Newton state, 7 per body.
    pub(crate) x: Vec<f64>,
    pub(crate) bodies: Vec<BodyState>,
    /// Each coupler's angles at the last accepted pose, which its angles are continued from
    /// ([`Model::accept_turns`]).
    pub(crate) turns: Vec<[f64; 2]>,
}

impl PoseState {
    /// The extra coordinates (curve parameters) of the Newton state, after the bodies'.
    pub(crate) fn u(&self) -> &[f64] {
        &self.x[7 * self.bodies.len()..]
    }
}

/// Velocities and accelerations of the current frame.
#[derive(Debug)]
pub(crate) struct MotionState {
    /// v = [ṙ; ω'] per body.
    pub(crate) v: Vec<f64>,
    /// v̇ = [r̈; ω̇'] per body.
    pub(crate) vdot: Vec<f64>,
    pub(crate) velocity_valid: bool,
    pub(crate) acceleration_valid: bool,
}

/// The last two accelerations computed ([`Model::acceleration`]) and their times (NaN: none),
/// for the predictor's jerk estimate.
#[derive(Debug)]
pub(crate) struct JerkSamples {
    pub(crate) vdot_last: Vec<f64>,
    pub(crate) vdot_prev: Vec<f64>,
    pub(crate) vdot_last_time: f64,
    pub(crate) vdot_prev_time: f64,
    /// The relative accelerations [ë; ω̇'_rel] of the predictor's tree edges (6 per body) at the
    /// same two times.
    pub(crate) edge_acc_last: Vec<f64>,
    pub(crate) edge_acc_prev: Vec<f64>,
}

/// Length m: ν or γ# (the right-hand side of the last linear solve), and Φ.
#[derive(Debug)]
pub(crate) struct RowBuffers {
    pub(crate) rhs: Vec<f64>,
    pub(crate) phi: Vec<f64>,
}

/// The predictor's scratch (`analysis::predictor`).
#[derive(Debug)]
pub(crate) struct PredictionBuffers {
    /// The predicted relative poses [p_rel; e] (7 per body).
    pub(crate) pred: Vec<f64>,
    /// Whether the predictor took a body's absolute motion (it turns faster relative to its
    /// parent than absolutely).
    pub(crate) pred_absolute: Vec<bool>,
}

/// The time grid's copies of frames (see `analysis::grid`).
#[derive(Debug)]
pub(crate) struct GridFrames {
    /// The frame before the last accepted one, for the linear extrapolation of the poses.
    pub(crate) x_prev: Vec<f64>,
    /// The poses the current attempt started from (the frame a subdivided step returns to).
    pub(crate) x_tmp: Vec<f64>,
    /// The Newton start of the frame being solved (the prediction), for the branch-jump test.
    pub(crate) x_pred: Vec<f64>,
    /// The velocities, accelerations and coupler turns of the last accepted frame, to return
    /// to it when a step is subdivided.
    pub(crate) v_saved: Vec<f64>,
    pub(crate) vdot_saved: Vec<f64>,
    pub(crate) turns_saved: Vec<[f64; 2]>,
}

/// The frame a grid step started from, kept for locating a limit's crossing inside the step
/// (`analysis::limits`; empty for a model without limits).
#[derive(Debug)]
pub(crate) struct StopFrame {
    pub(crate) t: f64,
    pub(crate) x: Vec<f64>,
    pub(crate) turns: Vec<[f64; 2]>,
}

/// The kinematic Newton solver ([`Model::prepare_kinematics`]).
#[derive(Debug)]
pub(crate) struct KinematicSolver {
    pub(crate) newton: Option<Newton<AutoSolver>>,
    /// The DOF report it was prepared with.
    pub(crate) dof: Option<DofReport>,
    /// The Newton start of the current position solve, kept when the solver works on a
    /// selection of rows (to retry from it after a re-selection).
    pub(crate) x_start: Vec<f64>,
}

/// Length m: whether the kinematic solver keeps each row (false: dropped as redundant), and
/// each row's worst scaled residual while dropped, its value and time (`analysis::dropped`).
#[derive(Debug)]
pub(crate) struct DroppedRows {
    pub(crate) kept: Vec<bool>,
    pub(crate) worst: Vec<f64>,
    pub(crate) value: Vec<f64>,
    pub(crate) time: Vec<f64>,
}

/// Counters of work done in the workspace.
#[derive(Debug, Default)]
pub(crate) struct Counters {
    /// Times the kinematic solver re-selected its independent rows.
    pub(crate) reselections: usize,
    /// ν and γ# evaluations.
    pub(crate) evaluations: EvaluationCounts,
}

impl Model {
    /// A fresh workspace at the initial poses (allocates every buffer a run needs).
    pub fn workspace(&self) -> Workspace {
        Workspace::new(self)
    }
}

/// How many times the velocity and acceleration right-hand sides were evaluated in a workspace:
/// the evidence that an analysis computes only what it was asked for (a position-only run
/// evaluates neither ν nor γ#).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct EvaluationCounts {
    /// Evaluations of ν (velocity analysis).
    pub nu: u64,
    /// Evaluations of γ# (acceleration analysis).
    pub gamma: u64,
}

impl Workspace {
    /// How many times the kinematic solver of a mechanism with redundant equations re-selected
    /// its independent rows (see [`Model::position`]).
    pub fn row_reselections(&self) -> usize {
        self.counters.reselections
    }

    /// Each coupler's angles at the last accepted pose ([`Model::accept_turns`]): the
    /// references its angles are continued from.
    pub fn turns(&self) -> &[[f64; 2]] {
        &self.pose.turns
    }

    /// The ν and γ# evaluation counts since the workspace was created.
    pub fn evaluation_counts(&self) -> EvaluationCounts {
        self.counters.evaluations
    }

    /// A workspace at the model's initial poses, at rest, t = 0.
    pub fn new(model: &Model) -> Self {
        let nb = model.num_bodies();
        let m = model.num_equations();
        // Vectors of unknowns hold the bodies' coordinates, then the extra ones.
        let (nx, nv) = (7 * nb + model.num_extra(), model.num_unknowns());
        let mut ws = Self {
            pose: PoseState {
                t: 0.0,
                x: vec![0.0; nx],
                bodies: vec![BodyState::ground(); nb],
                turns: model.initial_turns(),
            },
            motion: MotionState {
                v: vec![0.0; nv],
                vdot: vec![0.0; nv],
                velocity_valid: false,
                acceleration_valid: false,
            },
            jerk: JerkSamples {
                vdot_last: vec![0.0; nv],
                vdot_prev: vec![0.0; nv],
                vdot_last_time: f64::NAN,
                vdot_prev_time: f64::NAN,
                edge_acc_last: vec![0.0; 6 * nb],
                edge_acc_prev: vec![0.0; 6 * nb],
            },
            rows: RowBuffers {
                rhs: vec![0.0; m],
                phi: vec![0.0; m],
            },
            prediction: PredictionBuffers {
                pred: vec![0.0; 7 * nb],
                pred_absolute: vec![false; nb],
            },
            grid: GridFrames {
                x_prev: vec![0.0; nx],
                x_tmp: vec![0.0; nx],
                x_pred: vec![0.0; nx],
                v_saved: vec![0.0; nv],
                vdot_saved: vec![0.0; nv],
                turns_saved: model.initial_turns(),
            },
            stop_frame: StopFrame {
                t: 0.0,
                x: vec![0.0; if model.stops().is_empty() { 0 } else { nx }],
                turns: model.initial_turns(),
            },
            kin: KinematicSolver {
                newton: None,
                dof: None,
                x_start: vec![0.0; nx],
            },
            dropped: DroppedRows {
                kept: vec![true; m],
                worst: vec![0.0; m],
                value: vec![0.0; m],
                time: vec![f64::NAN; m],
            },
            counters: Counters::default(),
        };
        ws.reset(model);
        ws
    }

    /// Back to the model's initial poses, at rest (keeps the prepared kinematic solver).
    pub fn reset(&mut self, model: &Model) {
        for (k, b) in model.bodies().iter().enumerate() {
            self.pose.x[7 * k..7 * k + 3].copy_from_slice(b.initial_r.as_slice());
            self.pose.x[7 * k + 3..7 * k + 7].copy_from_slice(b.initial_p.as_slice());
        }
        let nb = model.num_bodies();
        for c in model.curves() {
            for (e, k) in c.extras().enumerate() {
                self.pose.x[7 * nb + k] = c.initial[e];
            }
        }
        self.motion.v.fill(0.0);
        self.motion.vdot.fill(0.0);
        self.pose.turns.copy_from_slice(&model.initial_turns());
        self.sync_poses();
        self.invalidate();
    }

    /// Time of the current state.
    pub fn time(&self) -> f64 {
        self.pose.t
    }

    /// The Newton state `[r_k; p_k]` (7 per moving body), then the extra coordinates (curve
    /// parameters, [`Model::extras_of`]).
    pub fn state(&self) -> &[f64] {
        &self.pose.x
    }

    /// The velocities `[ṙ_k; ω'_k]` (6 per body, then the extra coordinates' rates), valid
    /// after a velocity analysis.
    pub fn velocities(&self) -> &[f64] {
        &self.motion.v
    }

    /// The accelerations `[r̈_k; ω̇'_k]` (6 per body, then the extra coordinates'), valid after
    /// an acceleration analysis.
    pub fn accelerations(&self) -> &[f64] {
        &self.motion.vdot
    }

    /// Pose and velocity of moving body `k` (A cached).
    pub fn body_state(&self, k: usize) -> &BodyState {
        &self.pose.bodies[k]
    }

    /// The state of a body (ground included).
    pub fn state_of(&self, id: BodyId) -> BodyState {
        match id {
            BodyId::Ground => BodyState::ground(),
            BodyId::Moving(k) => self.pose.bodies[k],
        }
    }

    /// The accelerations of a body (zero for ground, and for every body unless `valid`: the
    /// joint rates then use none).
    pub fn acceleration_of(&self, id: BodyId, valid: bool) -> BodyAcceleration {
        match id {
            BodyId::Moving(k) if valid => BodyAcceleration {
                r_ddot: self.r_ddot(k),
                omega_dot_local: self.omega_dot_local(k),
            },
            _ => BodyAcceleration::default(),
        }
    }

    /// Sets the pose of moving body `k` (p is normalized; zero p is replaced by the identity).
    /// Velocities and accelerations become invalid.
    pub fn set_pose(&mut self, k: usize, r: Vector3<f64>, p: Vector4<f64>) {
        let n = p.norm();
        let p = if n > 0.0 && n.is_finite() {
            p / n
        } else {
            Vector4::new(1.0, 0.0, 0.0, 0.0)
        };
        self.pose.x[7 * k..7 * k + 3].copy_from_slice(r.as_slice());
        self.pose.x[7 * k + 3..7 * k + 7].copy_from_slice(p.as_slice());
        // Body k only (setting every pose of a 10⁴-body model one by one stays linear).
        self.refresh_body(k);
        self.invalidate();
    }

    /// Sets the velocity of moving body `k` (ṙ and ω' in the body frame).
    pub fn set_velocity(&mut self, k: usize, r_dot: Vector3<f64>, omega_local: Vector3<f64>) {
        self.motion.v[6 * k..6 * k + 3].copy_from_slice(r_dot.as_slice());
        self.motion.v[6 * k + 3..6 * k + 6].copy_from_slice(omega_local.as_slice());
        self.pose.bodies[k] = self.pose.bodies[k].with_v(r_dot, omega_local);
    }

    /// Sets the time of the state.
    pub fn set_time(&mut self, t: f64) {
        self.pose.t = t;
    }

    /// Position r of moving body `k`.
    pub fn r(&self, k: usize) -> Vector3<f64> {
        self.pose.bodies[k].r
    }

    /// Euler parameters p of moving body `k`.
    pub fn p(&self, k: usize) -> Vector4<f64> {
        self.pose.bodies[k].p
    }

    /// ṙ of body `k`.
    pub fn r_dot(&self, k: usize) -> Vector3<f64> {
        Vector3::from_column_slice(&self.motion.v[6 * k..6 * k + 3])
    }

    /// ω' of body `k` (body frame).
    pub fn omega_local(&self, k: usize) -> Vector3<f64> {
        Vector3::from_column_slice(&self.motion.v[6 * k + 3..6 * k + 6])
    }

    /// ω = A ω' of body `k` (global).
    pub fn omega(&self, k: usize) -> Vector3<f64> {
        self.pose.bodies[k].a * self.omega_local(k)
    }

    /// ṗ = ½ Lᵀ ω' of body `k`.
    pub fn p_dot(&self, k: usize) -> Vector4<f64> {
        p_dot_from_local(&self.pose.bodies[k].p, &self.omega_local(k))
    }

    /// r̈ of body `k`.
    pub fn r_ddot(&self, k: usize) -> Vector3<f64> {
        Vector3::from_column_slice(&self.motion.vdot[6 * k..6 * k + 3])
    }

    /// ω̇' of body `k` (body frame).
    pub fn omega_dot_local(&self, k: usize) -> Vector3<f64> {
        Vector3::from_column_slice(&self.motion.vdot[6 * k + 3..6 * k + 6])
    }

    /// ω̇ = A ω̇' of body `k` (global).
    pub fn omega_dot(&self, k: usize) -> Vector3<f64> {
        self.pose.bodies[k].a * self.omega_dot_local(k)
    }

    /// p̈ = ½ Lᵀ ω̇' − ¼ |ω'|² p of body `k`.
    pub fn p_ddot(&self, k: usize) -> Vector4<f64> {
        p_ddot_from_local(
            &self.pose.bodies[k].p,
            &self.omega_local(k),
            &self.omega_dot_local(k),
        )
    }

    /// Global position of a point given in the frame of `body`.
    pub fn point_position(&self, body: BodyId, local: &Vector3<f64>) -> Vector3<f64> {
        match body {
            BodyId::Ground => *local,
            BodyId::Moving(k) => self.pose.bodies[k].point(local),
        }
    }

    /// Global velocity of a body-fixed point: ṙ + A (ω' × s').
    pub fn point_velocity(&self, body: BodyId, local: &Vector3<f64>) -> Vector3<f64> {
        match body {
            BodyId::Ground => Vector3::zeros(),
            BodyId::Moving(k) => {
                self.r_dot(k) + self.pose.bodies[k].a * self.omega_local(k).cross(local)
            }
        }
    }

    /// Global acceleration of a body-fixed point: r̈ + A (ω̇' × s' + ω' × (ω' × s')).
    pub fn point_acceleration(&self, body: BodyId, local: &Vector3<f64>) -> Vector3<f64> {
        match body {
            BodyId::Ground => Vector3::zeros(),
            BodyId::Moving(k) => {
                let w = self.omega_local(k);
                self.r_ddot(k)
                    + self.pose.bodies[k].a
                        * (self.omega_dot_local(k).cross(local) + w.cross(&w.cross(local)))
            }
        }
    }

    /// Factorizations of Φ_v made by the kinematic solver of this workspace (position, velocity
    /// and acceleration analyses): 0 before [`Model::prepare_kinematics`], which builds a new
    /// solver (the count restarts, and may include a factorization of the preparation). With
    /// the iteration counts of [`Model::position`], the difference over a run of frames tells how
    /// much work they did.
    pub fn kinematic_factorizations(&self) -> u64 {
        self.kin
            .newton
            .as_ref()
            .map_or(0, |n| n.factorization_count())
    }

    /// The degrees-of-freedom report of the last [`Model::prepare_kinematics`].
    pub fn dof_report(&self) -> Option<&DofReport> {
        self.kin.dof.as_ref()
    }

    /// Whether the velocities are those of the current poses and time.
    pub fn velocity_is_valid(&self) -> bool {
        self.motion.velocity_valid
    }

    /// Whether the accelerations are those of the current poses and time.
    pub fn acceleration_is_valid(&self) -> bool {
        self.motion.acceleration_valid
    }

    pub(crate) fn invalidate(&mut self) {
        self.motion.velocity_valid = false;
        self.motion.acceleration_valid = false;
        self.jerk.vdot_last_time = f64::NAN;
        self.jerk.vdot_prev_time = f64::NAN;
        if let Some(k) = &mut self.kin.newton {
            k.invalidate();
        }
    }

    /// The poses were moved by a predictor: velocities and accelerations become invalid, the
    /// kinematic factorization is kept as the start of a modified-Newton solve.
    pub(crate) fn poses_moved(&mut self) {
        self.motion.velocity_valid = false;
        self.motion.acceleration_valid = false;
        if let Some(k) = &mut self.kin.newton {
            k.state_moved();
        }
    }

    /// Refreshes the body states (A, p) from the Newton state; keeps ω' from `v`.
    pub(crate) fn sync_poses(&mut self) {
        for k in 0..self.pose.bodies.len() {
            self.refresh_body(k);
        }
    }

    /// Refreshes body k's state (A, p) from the Newton state, with ṙ and ω' from `v`.
    fn refresh_body(&mut self, k: usize) {
        let r = Vector3::from_column_slice(&self.pose.x[7 * k..7 * k + 3]);
        let p = Vector4::from_column_slice(&self.pose.x[7 * k + 3..7 * k + 7]);
        let rd = Vector3::from_column_slice(&self.motion.v[6 * k..6 * k + 3]);
        let w = Vector3::from_column_slice(&self.motion.v[6 * k + 3..6 * k + 6]);
        self.pose.bodies[k] = BodyState::at(r, p).with_v(rd, w);
    }
}

/// Sets each body's pose from the Newton state (velocities zeroed).
pub(crate) fn set_poses(bodies: &mut [BodyState], x: &[f64]) {
    for (k, b) in bodies.iter_mut().enumerate() {
        let r = Vector3::from_column_slice(&x[7 * k..7 * k + 3]);
        let p = Vector4::from_column_slice(&x[7 * k + 3..7 * k + 7]);
        *b = BodyState::at(r, p);
    }
}

/// `x ← x ⊕ dx`: r += Δr, p ← normalize(p ⊗ exp(Δπ'/2)) for every body. No allocation.
///
/// exp(θ/2) is the unit Euler-parameter vector [cos(|θ|/2), sin(|θ|/2) θ/|θ|] of a rotation by
/// |θ| about θ (body frame), so A(p_new) = A(p) exp(θ̃) and, to first order, Δ(A s') = A (θ × s'),
/// which is the direction Φ_π' = ½ Φ_p Lᵀ linearizes.
pub fn apply_rotation_step(x: &mut [f64], dx: &[f64]) {
    let nb = dx.len() / 6;
    for k in 0..nb {
        for c in 0..3 {
            x[7 * k + c] += dx[6 * k + c];
        }
        let th = Vector3::from_column_slice(&dx[6 * k + 3..6 * k + 6]);
        let p = EulerParams::new(x[7 * k + 3], x[7 * k + 4], x[7 * k + 5], x[7 * k + 6]);
        let n = p.compose_unit(&EulerParams::from_rotation_vector(&th));
        x[7 * k + 3..7 * k + 7].copy_from_slice(n.as_vector().as_slice());
    }
}

/// `x ← x ⊕ dx` for `nb` bodies ([`apply_rotation_step`]) and the extra coordinates after
/// them, which add: x[7 nb + k] += dx[6 nb + k]. No allocation.
pub fn apply_step(x: &mut [f64], dx: &[f64], nb: usize) {
    apply_rotation_step(&mut x[..7 * nb], &dx[..6 * nb]);
    for (xk, dk) in x[7 * nb..].iter_mut().zip(&dx[6 * nb..]) {
        *xk += dk;
    }
}

/// The position system handed to Newton-Raphson: Φ(x, t) = 0 in the 6-coordinate form.
pub(crate) struct PositionSystem<'a> {
    pub model: &'a Model,
    pub bodies: &'a mut [BodyState],
    pub turns: &'a [[f64; 2]],
    pub t: f64,
}

impl NonlinearSystem for PositionSystem<'_> {
    fn num_equations(&self) -> usize {
        self.model.num_equations()
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
        self.model.phi_into(self.bodies, u, self.turns, self.t, out);
    }
    fn jacobian(&mut self, x: &[f64], slots: &mut [f64]) {
        set_poses(self.bodies, x);
        let u = self.model.extras_of(x);
        self.model.jacobian_into(self.bodies, u, self.t, slots);
    }
    fn apply_step(&mut self, x: &mut [f64], dx: &[f64]) {
        apply_step(x, dx, self.model.num_bodies());
    }
    fn equation_scales(&self, out: &mut [f64]) {
        out.copy_from_slice(self.model.equation_scales());
    }
    fn unknown_scales(&self, out: &mut [f64]) {
        out.copy_from_slice(self.model.unknown_scales());
    }
}
