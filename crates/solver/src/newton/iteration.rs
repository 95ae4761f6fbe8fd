//! The iteration loop of [`Newton::solve`]: test, (re)factor, step, search, accept.
//!
//! Each iteration `k`:
//!
//! 1. **Test** convergence on the current iterate (the scaled tests of
//!    [`convergence`](crate::convergence)).
//! 2. **Factor** `Φ_q` at the iterate if the refactor policy (`policy.rs`) asks for it.
//! 3. **Step**: solve `Φ_q Δ = −Φ` with the current factors.
//! 4. **Search** along `Δ` (`line_search.rs`): a chord direction that fails its trial asks for
//!    new factors and the iteration is retried; no decrease at all ends the solve.
//! 5. **Accept** the trial: estimate the error the step left (Newton step: about `‖Δ‖²`; chord
//!    step: `θ/(1−θ) ‖Δ‖`, `rate.rs`) and let the policy judge the factors.

use super::line_search::{Direction, Outcome};
use super::JacobianUpdate;
use super::{eval_residual, Newton, NewtonOptions, NewtonReport, NonlinearSystem};
use crate::convergence::{weighted_inf_norm, weighted_sum_squares, worst_entries};
use crate::error::SolverError;
use crate::linear::LinearSolver;

/// Where the iteration stands.
#[derive(Debug, Clone, Copy)]
struct Iterate {
    /// Iterations made.
    k: usize,
    /// Scaled residual norm `max_i |Φ_i| / e_i`.
    rn: f64,
    /// Merit `Σ (Φ_i / e_i)²` of the line search.
    merit: f64,
    /// Scaled length of the last step.
    last_step: f64,
    /// Estimated (scaled) error left by the last step, compared with `τ_step²`.
    last_error: f64,
}

impl<S: LinearSolver> Newton<S> {
    /// Solves `Φ(x) = 0` starting from `x` (overwritten with the solution, or with the last
    /// iterate on failure). Does not allocate after the first call (on success).
    ///
    /// # Errors
    /// [`SolverError::NotConverged`] (residual history and worst equations),
    /// [`SolverError::Singular`] (dependent equations), [`SolverError::NonFinite`], size
    /// mismatches.
    pub fn solve<N: NonlinearSystem + ?Sized>(
        &mut self,
        system: &mut N,
        x: &mut [f64],
    ) -> Result<NewtonReport, SolverError> {
        self.check_system(system, x)?;
        if self.x_last.as_slice() != x {
            // Moved since the last solve without `state_moved`: distance unknown.
            self.fact.drift = f64::INFINITY;
        }
        // The state changes from here on: an old factorization is no longer "current".
        self.fact.at_current = false;
        self.fact.slots_at_last = false;
        // Age and step ratios count within one solve.
        self.policy.reset();
        self.rate.reset();
        let opts = self.options;
        self.update_weights(system);
        if let JacobianUpdate::EveryIteration = opts.jacobian_update {
            self.fact.factored = false;
        }
        self.history.clear();
        let mut report = NewtonReport::empty();
        let mut residual = std::mem::take(&mut self.residual);
        let result = self.iterate(system, x, &mut residual, &mut report, &opts);
        self.residual = residual;
        self.x_last.copy_from_slice(x);
        // A factorization at the solution holds its Jacobian.
        self.fact.slots_at_last = self.fact.is_current();
        result.map(|()| {
            report.rank = self.fact.solver.rank();
            report.redundant_equations = self.fact.redundancy();
            report
        })
    }

    fn iterate<N: NonlinearSystem + ?Sized>(
        &mut self,
        system: &mut N,
        x: &mut [f64],
        residual: &mut [f64],
        report: &mut NewtonReport,
        opts: &NewtonOptions,
    ) -> Result<(), SolverError> {
        eval_residual(system, x, residual, 0)?;
        report.residual_evaluations += 1;
        let mut it = Iterate {
            k: 0,
            rn: weighted_inf_norm(residual, &self.weights.eq).0,
            merit: weighted_sum_squares(residual, &self.weights.eq),
            last_step: f64::INFINITY,
            last_error: f64::INFINITY,
        };
        self.history.push(it.rn);
        loop {
            report.residual_norm = it.rn;
            if opts.tolerances.converged(it.rn, it.k == 0, it.last_error) {
                let step = if it.k == 0 { 0.0 } else { it.last_step };
                return self.finish(system, x, it.k, step, report, opts);
            }
            if it.k >= opts.max_iterations {
                return Err(self.not_converged(it.k, residual, opts));
            }
            it.k += 1;
            let k = it.k;
            let update = opts.jacobian_update;
            if self.policy.take_decision(update, self.fact.factored) && !self.fact.is_current() {
                self.refactor(system, x, Some(k))?;
                report.refactorizations += 1;
            }
            let fresh = self.fact.at_current;
            let step = self.newton_step(residual, k)?;
            let alpha = match opts.max_step {
                Some(cap) if step > cap => cap / step,
                _ => 1.0,
            };
            let dir = Direction {
                x: &*x,
                dx: &self.dx,
                alpha,
                merit: it.merit,
                fresh,
                iteration: k,
            };
            let evaluations = &mut report.residual_evaluations;
            let eq = &self.weights.eq;
            match self
                .trial
                .search(system, &dir, opts.line_search, eq, evaluations)?
            {
                Outcome::StaleDirection => {
                    // A stale factorization gave a poor direction: refactor here and retry.
                    self.policy.force();
                    self.history.push(it.rn);
                }
                Outcome::NoDecrease if it.rn <= opts.tolerances.residual => {
                    // The residual test holds and no step reduces the residual further
                    // (rounding level): accept the point, reporting the step not taken.
                    return self.finish(system, x, k, step, report, opts);
                }
                Outcome::NoDecrease => return Err(self.not_converged(k, residual, opts)),
                Outcome::Accepted { alpha } => {
                    if alpha < 1.0 {
                        report.damped_steps += 1;
                    }
                    self.accept(x, residual, step * alpha, fresh, &mut it, opts);
                }
            }
        }
    }

    /// The Newton (or chord) step `Φ_q Δ = −Φ` into `self.dx`; returns its scaled length.
    fn newton_step(&mut self, residual: &[f64], k: usize) -> Result<f64, SolverError> {
        let scaled = self.options.scale_linear_system;
        self.fact
            .solve(residual, -1.0, &mut self.dx, &self.weights, scaled)
            .map_err(|e| super::with_iteration(e, Some(k)))?;
        self.policy.stepped();
        Ok(weighted_inf_norm(&self.dx, &self.weights.unknown).0)
    }

    /// Takes the line search's trial (a step of scaled length `step`) as the new iterate: its
    /// error estimate, the policy's checks, the drift of the factors.
    fn accept(
        &mut self,
        x: &mut [f64],
        residual: &mut [f64],
        step: f64,
        fresh: bool,
        it: &mut Iterate,
        opts: &NewtonOptions,
    ) {
        x.copy_from_slice(&self.trial.x);
        self.fact.at_current = false;
        residual.copy_from_slice(&self.trial.residual);
        let new_rn = weighted_inf_norm(residual, &self.weights.eq).0;
        it.merit = weighted_sum_squares(residual, &self.weights.eq);
        let update = opts.jacobian_update;
        let modified = matches!(update, JacobianUpdate::Modified { .. });
        let theta = (modified && !fresh).then(|| self.rate.observe_chord(step, it.rn, new_rn));
        let tau2 = opts.tolerances.step * opts.tolerances.step;
        let chord_error = self
            .policy
            .after_step(update, (it.rn, new_rn), step, theta, tau2);
        it.last_error = if fresh {
            // Newton step: quadratic convergence, the error left is about ‖Δ‖².
            opts.tolerances.newton_step_error(step)
        } else {
            chord_error
        };
        self.rate.record(step);
        self.fact.drift += step;
        it.rn = new_rn;
        it.last_step = step;
        self.history.push(it.rn);
    }

    /// Converged after `k` iterations, the last step of scaled length `step`: refactors at the
    /// solution if asked to.
    fn finish<N: NonlinearSystem + ?Sized>(
        &mut self,
        system: &mut N,
        x: &[f64],
        k: usize,
        step: f64,
        report: &mut NewtonReport,
        opts: &NewtonOptions,
    ) -> Result<(), SolverError> {
        report.iterations = k;
        report.step_norm = step;
        if opts.factor_at_solution && !self.fact.is_current() {
            self.refactor(system, x, Some(k))?;
            report.refactorizations += 1;
        }
        Ok(())
    }

    fn not_converged(
        &self,
        iterations: usize,
        residual: &[f64],
        opts: &NewtonOptions,
    ) -> SolverError {
        SolverError::NotConverged {
            iterations,
            residual_history: self.history.clone(),
            worst_equations: worst_entries(residual, &self.weights.eq, opts.report_worst),
        }
    }
}
