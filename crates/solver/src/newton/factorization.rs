//! The factored Jacobian and where it was made.
//!
//! A [`Factorization`] evaluates `Φ_q(x)`, maps it to the linear solver's matrix ([`SlotMap`]),
//! factors it and solves with it. It also knows how far the state has moved since: at the point
//! (`at_current`), a known scaled distance away (`drift`, the sum of the step lengths since), or
//! an unknown distance (infinite drift). The refactor policy, the convergence test and the
//! refinement of [`Newton::solve_linear_at`](super::Newton::solve_linear_at) read those.

use super::slot_map::SlotMap;
use super::weights::Weights;
use super::{with_iteration, NonlinearSystem};
use crate::error::SolverError;
use crate::linear::LinearSolver;
use crate::pattern::{RowSelection, SparsityPattern};

/// A linear solver with its matrix: the Jacobian on its pattern, reduced and scaled.
#[derive(Debug)]
pub(super) struct Factorization<S> {
    pub(super) pattern: SparsityPattern,
    pub(super) selection: Option<RowSelection>,
    pub(super) solver: S,
    pub(super) map: SlotMap,
    /// The Jacobian values of the last evaluation, in full pattern order.
    pub(super) full_slots: Vec<f64>,
    /// Values handed to the linear solver (reduced and scaled).
    solve_slots: Vec<f64>,
    /// Right-hand side handed to the linear solver.
    rhs: Vec<f64>,
    /// A factorization exists.
    pub(super) factored: bool,
    /// It was made at the current state.
    pub(super) at_current: bool,
    /// `full_slots` hold the Jacobian at the state last returned or passed in.
    pub(super) slots_at_last: bool,
    /// Scaled distance (sum of step lengths) from the point of the factorization to the last
    /// iterate (infinite: unknown).
    pub(super) drift: f64,
    /// Factorizations attempted (successful or not).
    pub(super) count: u64,
}

impl<S: LinearSolver> Factorization<S> {
    /// An unfactored `solver` (already analyzed) for `pattern` and an optional selection.
    pub(super) fn new(
        pattern: &SparsityPattern,
        selection: Option<RowSelection>,
        solver: S,
    ) -> Self {
        let map = SlotMap::new(pattern, selection.as_ref());
        Self {
            pattern: pattern.clone(),
            solve_slots: vec![0.0; map.num_slots()],
            rhs: vec![0.0; map.solve_rows.len()],
            selection,
            solver,
            map,
            full_slots: vec![0.0; pattern.num_slots()],
            factored: false,
            at_current: false,
            slots_at_last: false,
            drift: f64::INFINITY,
            count: 0,
        }
    }

    /// A factorization made at the current state.
    pub(super) fn is_current(&self) -> bool {
        self.factored && self.at_current
    }

    /// The state moved by an unknown amount: the factors stay usable, but are not current.
    pub(super) fn state_moved(&mut self) {
        self.at_current = false;
        self.slots_at_last = false;
        self.drift = f64::INFINITY;
    }

    /// Forgets the factors.
    pub(super) fn invalidate(&mut self) {
        self.factored = false;
        self.state_moved();
    }

    /// Evaluates `Φ_q(x)` and factors it (scaled if `scaled`). Errors name the Newton
    /// iteration, and with a row selection the full equation indices.
    pub(super) fn refactor<N: NonlinearSystem + ?Sized>(
        &mut self,
        system: &mut N,
        x: &[f64],
        iteration: Option<usize>,
        scaled: bool,
    ) -> Result<(), SolverError> {
        self.factored = false;
        self.at_current = false;
        self.count += 1;
        system.jacobian(x, &mut self.full_slots);
        let finite = self
            .map
            .gather(&self.full_slots, &mut self.solve_slots, scaled);
        if !finite || self.selection.is_some() {
            // Name the slot (with a row selection, the dropped rows are checked too).
            self.pattern
                .check_finite(&self.full_slots)
                .map_err(|e| with_iteration(e, iteration))?;
        }
        self.solver
            .factor(&self.solve_slots)
            .map_err(|e| self.map_rows(with_iteration(e, iteration)))?;
        self.factored = true;
        self.at_current = true;
        self.drift = 0.0;
        Ok(())
    }

    /// Solves `Φ_q out = sign · rhs` with the current factors (`rhs` over all equations, the
    /// dropped rows ignored). No allocation.
    pub(super) fn solve(
        &mut self,
        rhs: &[f64],
        sign: f64,
        out: &mut [f64],
        weights: &Weights,
        scaled: bool,
    ) -> Result<(), SolverError> {
        self.map
            .gather_rhs(rhs, sign, weights, scaled, &mut self.rhs);
        self.solver.solve(&self.rhs, out)?;
        if scaled {
            // Back from the scaled unknowns: Δq_j = y_j / v_j.
            for (o, w) in out.iter_mut().zip(&weights.unknown) {
                *o /= w;
            }
        }
        Ok(())
    }

    /// Redundant equations: rows the selection drops plus rows the solver found dependent.
    pub(super) fn redundancy(&self) -> usize {
        self.map.dropped_rows.len() + self.solver.rank().map_or(0, |r| self.solver.nrows() - r)
    }

    /// Maps equation indices of the reduced system back to the full system in errors.
    fn map_rows(&self, e: SolverError) -> SolverError {
        match (e, &self.selection) {
            (
                SolverError::Singular {
                    dependent_equations,
                },
                Some(sel),
            ) => {
                let mut rows: Vec<usize> = dependent_equations
                    .iter()
                    .filter_map(|&i| sel.rows().get(i).copied())
                    .collect();
                rows.sort_unstable();
                SolverError::Singular {
                    dependent_equations: rows,
                }
            }
            (e, _) => e,
        }
    }
}
