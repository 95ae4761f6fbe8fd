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
//! A failure mid-run (singular configuration, no convergence) returns an error that carries the
//! time, the named equations, and the results up to the last successful step.

use crate::analysis::assembly::AssemblyOptions;
use crate::error::AnalysisError;
use crate::model::{BodyId, Model};
use crate::results::{BodyResults, JointResults, Outputs, PointResults, Results};
use crate::workspace::Workspace;
use cardan_constraints::{unwrap_angle, BodyPair};
use cardan_eulerparam::EulerParams;
use std::ops::ControlFlow;

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
}

impl KinematicOptions {
    /// `steps` intervals from `t0` to `t_end`, every output.
    pub fn new(t0: f64, t_end: f64, steps: usize) -> Self {
        Self {
            t0,
            t_end,
            steps,
            outputs: Outputs::default(),
        }
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

    fn validate(&self) -> Result<(), AnalysisError> {
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
        Ok(())
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
    /// # Errors
    /// As [`kinematics`](Self::kinematics).
    pub fn kinematics_with_control(
        &self,
        ws: &mut Workspace,
        options: &KinematicOptions,
        mut progress: impl FnMut(usize, f64) -> ControlFlow<()>,
    ) -> Result<Results, AnalysisError> {
        options.validate()?;
        if ws.kin.is_none() {
            // Joints first: the driver count is checked before the drivers can make the
            // assembly fail (an over-driven mechanism gets "superfluous", not "open").
            let joints_only = AssemblyOptions {
                include_drivers: false,
                ..AssemblyOptions::at(options.t0)
            };
            self.assemble(ws, &joints_only)?;
            let dof = self.dof(ws)?;
            if dof.dof != dof.drivers {
                return Err(AnalysisError::DriverCount {
                    dof: dof.dof,
                    drivers: dof.drivers,
                });
            }
            self.assemble(ws, &AssemblyOptions::at(options.t0))?;
            self.prepare_kinematics(ws)?;
        }
        let mut results = self.allocate_results(options);
        let mut joint_prev = vec![[0.0; 3]; self.joints.len()];
        for k in 0..=options.steps {
            let t = options.time(k);
            if let Err(e) = self.step(ws, options, k, t, &mut results, &mut joint_prev) {
                return Err(e.with_partial(results));
            }
            if progress(k, t).is_break() {
                break;
            }
        }
        Ok(results)
    }

    /// One step of the grid (no allocation after warm-up).
    pub(crate) fn step(
        &self,
        ws: &mut Workspace,
        options: &KinematicOptions,
        k: usize,
        t: f64,
        results: &mut Results,
        joint_prev: &mut [[f64; 3]],
    ) -> Result<(), AnalysisError> {
        let out = options.outputs;
        // x holds the solution of step k − 1, x_prev that of step k − 2.
        ws.x_tmp.copy_from_slice(&ws.x);
        if k > 0 {
            self.predict(ws, t - ws.t, k, out);
        }
        let rep = self.position(ws, t)?;
        ws.x_prev.copy_from_slice(&ws.x_tmp);
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

    /// Moves the poses in `ws` to the Taylor prediction x ⊕ (v dt + ½ v̇ dt² + ⅙ j dt³) at
    /// `ws.time() + dt` from the current velocities (and accelerations and jerk, when valid),
    /// body by body relative to a parent where that is the slower motion (module docs): the
    /// Newton start the time grid uses, for callers that step frames themselves
    /// ([`Model::position`] at t + dt then converges in fewer, cheaper iterations: the
    /// factorization is kept for chord steps). Does nothing when the velocities are not valid.
    /// No allocation.
    pub fn predict_poses(&self, ws: &mut Workspace, dt: f64) {
        if ws.velocity_valid {
            self.predict(ws, dt, 0, Outputs::default());
            ws.poses_moved();
        }
    }

    /// Moves the Newton start to the predicted poses at t + dt.
    fn predict(&self, ws: &mut Workspace, dt: f64, k: usize, out: Outputs) {
        let nb = self.num_bodies();
        if out.needs_velocity() && ws.velocity_valid {
            let acc = out.acceleration && ws.acceleration_valid;
            // Jerk from the last two accelerations (the last one is the current state's).
            let h = ws.vdot_last_time - ws.vdot_prev_time;
            let jerk = acc && ws.vdot_last_time == ws.t && h != 0.0 && h.is_finite();
            let c3 = if jerk { dt * dt * dt / (6.0 * h) } else { 0.0 };
            crate::analysis::predictor::predict(self, ws, dt, acc, c3);
        } else if k >= 2 {
            for b in 0..nb {
                let (xs, xp) = (&mut ws.x[7 * b..7 * b + 7], &ws.x_prev[7 * b..7 * b + 7]);
                for c in 0..3 {
                    xs[c] = 2.0 * xs[c] - xp[c];
                }
                let p = EulerParams::new(xs[3], xs[4], xs[5], xs[6]);
                let q = EulerParams::new(xp[3], xp[4], xp[5], xp[6]);
                let n = p.compose_unit(&q.conjugate().compose(&p));
                xs[3..].copy_from_slice(n.as_vector().as_slice());
            }
        }
        ws.sync_poses();
    }

    fn allocate_results(&self, options: &KinematicOptions) -> Results {
        let n = options.steps + 1;
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
                .map(|j| {
                    let g = cardan_constraints::BodyState::ground();
                    let c = j.joint.coordinates(&BodyPair::new(&g, &g));
                    JointResults {
                        name: j.name.clone(),
                        kind: j.joint.kind(),
                        coordinate_names: c.names,
                        values: Vec::with_capacity(n),
                    }
                })
                .collect()
        } else {
            Vec::new()
        };
        Results {
            outputs: Some(out),
            times: Vec::with_capacity(n),
            bodies,
            points,
            joints,
            residual: Vec::with_capacity(n),
            iterations: Vec::with_capacity(n),
        }
    }

    #[allow(clippy::too_many_arguments)]
    fn record(
        &self,
        ws: &Workspace,
        out: Outputs,
        k: usize,
        residual: f64,
        iterations: usize,
        res: &mut Results,
        joint_prev: &mut [[f64; 3]],
    ) {
        let v = out.needs_velocity();
        let a = out.acceleration;
        res.times.push(ws.t);
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
        if out.joints {
            for (idx, (j, h)) in self.joints.iter().zip(res.joints.iter_mut()).enumerate() {
                let (si, sj) = (ws.state_of(j.body_i), ws.state_of(j.body_j));
                let c = j.joint.coordinates(&BodyPair::new(&si, &sj));
                let mut vals = c.values;
                let prev = &mut joint_prev[idx];
                for (q, name) in c.names.iter().enumerate() {
                    if k > 0 && name.starts_with("angle") {
                        vals[q] = unwrap_angle(prev[q], vals[q]);
                    }
                }
                *prev = vals;
                h.values.push(vals);
            }
        }
    }
}
