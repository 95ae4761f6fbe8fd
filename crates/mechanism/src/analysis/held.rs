//! A kinematic run of an under-driven mechanism with its free degrees of freedom held
//! ([`FreeDof::Hold`](crate::analysis::least_change::FreeDof)): at t0 the least change from the
//! drawn pose that satisfies the joints and the drivers, then at each output time the least
//! change from the last output's pose ([`crate::analysis::least_change`]), straight from one
//! output time to the next, without a predictor, as OndselSolver's quasi-kinematic stepping
//! does. The free parts therefore hold still where the drivers leave them free, and follow
//! them as little as the joints allow elsewhere; the poses depend on the output step (a path
//! of least changes), which the front end says in its warning.
//!
//! Velocities and accelerations are the weighted minimum-norm solutions of Φ_v v = ν and
//! Φ_v v̇ = γ# at each solved pose.

use crate::analysis::grid::{JointMemory, KinematicOptions};
use crate::analysis::least_change::{HeldRun, HoldMetric, LeastChange, LeastChangeReport};
use crate::error::AnalysisError;
use crate::model::Model;
use crate::results::{FrameSink, Results, RunTotals};
use crate::workspace::Workspace;

impl Model {
    /// Prepares a held run at `options.t0`: the least change from the workspace's (drawn)
    /// poses with the drivers; when the joints leave more DOF than there are drivers, the
    /// run ([`HeldRun`]). `None` (the pose restored) for a model the usual preparation
    /// handles: fully or over-driven.
    ///
    /// # Errors
    /// The least-change assembly's failure, when the usual assembly fails too.
    pub(crate) fn prepare_held(
        &self,
        ws: &mut Workspace,
        options: &KinematicOptions,
        metric: HoldMetric,
    ) -> Result<Option<HeldRun>, AnalysisError> {
        if self.num_extra() > 0 {
            return Err(AnalysisError::Options(
                "free_dof = \"hold\" does not take curve elements yet (points on curves, cam pairs: their curve parameters have no least-change weight); drive every degree of freedom and leave free_dof at its default".into(),
            ));
        }
        let drawn = ws.pose.x.clone();
        let mut solver = LeastChange::new(self, metric.weights(self))
            .map_err(|e| self.map_solver_error(options.t0, e))?;
        solver.old.copy_from_slice(&drawn);
        let from_assembly = solver
            .solve(self, ws, options.t0, options.tolerance)
            .is_err();
        if from_assembly {
            // From the usual (minimum-norm) assembly's pose, when it assembles; its error,
            // which names what stays open and diagnoses an inconsistent model, when not.
            ws.pose.x.copy_from_slice(&drawn);
            ws.sync_poses();
            self.assemble(ws, &options.assembly())?;
        }
        self.accept_turns(&ws.pose.bodies, &mut ws.pose.turns);
        ws.invalidate();
        let report = self.dof(ws)?;
        if report.dof <= report.drivers {
            ws.pose.x.copy_from_slice(&drawn);
            ws.sync_poses();
            ws.invalidate();
            return Ok(None);
        }
        let held = report.dof - report.drivers;
        if from_assembly && options.drop_inconsistent {
            // The assembly dropped the rows that cannot hold with the others (an inconsistent
            // model run as OndselSolver runs it): the least change solves the rest.
            self.drop_dependent_rows(ws, &mut solver)?;
        }
        ws.kin.dof = Some(report);
        Ok(Some(HeldRun {
            solver,
            held,
            from_assembly,
        }))
    }

    /// The time grid of a held run (module docs), streamed to `sink` as
    /// [`Model::kinematics_into`] does.
    pub(crate) fn held_into(
        &self,
        ws: &mut Workspace,
        options: &KinematicOptions,
        sink: &mut impl FrameSink,
        run: HeldRun,
    ) -> Result<RunTotals, AnalysisError> {
        let HeldRun {
            mut solver,
            held,
            from_assembly,
        } = run;
        let mut frame = self.allocate_results(options, 1);
        let mut memory = JointMemory::new(self.joints.len());
        let mut frames = 0;
        let mut run = Ok(());
        for k in 0..=options.steps {
            let t = options.time(k);
            frame.clear_frames();
            if let Err(e) = self.held_step(ws, &mut solver, options, k, t, &mut frame, &mut memory)
            {
                frame.clear_frames();
                frame.held_dof = held;
                frame.held_from_assembly = from_assembly;
                run = Err(e.with_partial(frame.clone()));
                break;
            }
            frames += 1;
            if sink.frame(k, &frame).is_break() {
                break;
            }
        }
        run.map(|()| RunTotals {
            frames,
            subdivided_steps: 0,
            row_reselections: 0,
            dropped_rows: self.dropped_row_residuals(ws, options.tolerance),
            held_dof: held,
            held_from_assembly: from_assembly,
        })
    }

    /// Marks the joint rows dependent at the assembled pose as dropped, for the run's record
    /// and for `solver` (the rows the kinematic solver would drop: `analysis::dropped`).
    ///
    /// # Errors
    /// A solver error of the rank analysis.
    fn drop_dependent_rows(
        &self,
        ws: &mut Workspace,
        solver: &mut LeastChange,
    ) -> Result<(), AnalysisError> {
        let (_, dependent) = self.joint_rank(ws)?;
        let kept: Vec<usize> = (0..self.num_equations())
            .filter(|r| !dependent.contains(r))
            .collect();
        ws.set_kept_rows(&kept);
        solver.keep_rows(&ws.dropped.kept);
        Ok(())
    }

    /// One output time of a held run: the least change from the last pose (at k = 0 the
    /// assembled pose itself), the stops checked there, the rates as asked, stored.
    #[allow(clippy::too_many_arguments)]
    fn held_step(
        &self,
        ws: &mut Workspace,
        solver: &mut LeastChange,
        options: &KinematicOptions,
        k: usize,
        t: f64,
        results: &mut Results,
        memory: &mut JointMemory,
    ) -> Result<(), AnalysisError> {
        let out = options.outputs;
        solver.old.copy_from_slice(&ws.pose.x);
        let rep: LeastChangeReport = solver.solve(self, ws, t, options.tolerance)?;
        self.accept_turns(&ws.pose.bodies, &mut ws.pose.turns);
        if ws.dropped.kept.iter().any(|&k| !k) {
            // Φ at the solution, from the solve (not evaluated again).
            ws.rows.phi.copy_from_slice(solver.residuals());
            self.record_dropped_rows(ws, t);
        }
        self.check_stops(ws, t, true)?;
        if out.needs_velocity() {
            self.nu_into(&ws.pose.bodies, ws.pose.u(), t, &mut ws.rows.rhs);
            ws.counters.evaluations.nu += 1;
            solver.rates(self, ws, &ws.rows.rhs)?;
            ws.motion.v.copy_from_slice(solver.solution());
            ws.sync_poses();
            ws.motion.velocity_valid = true;
        }
        if out.acceleration {
            self.gamma_into(
                &ws.pose.bodies,
                (ws.pose.u(), self.extra_rates_of(&ws.motion.v)),
                t,
                &mut ws.rows.rhs,
            );
            ws.counters.evaluations.gamma += 1;
            solver.rates(self, ws, &ws.rows.rhs)?;
            ws.motion.vdot.copy_from_slice(solver.solution());
            ws.motion.acceleration_valid = true;
        }
        self.record(ws, out, k, rep.residual, rep.iterations, results, memory);
        Ok(())
    }
}
