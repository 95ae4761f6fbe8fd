//! The LU of the full KKT matrix ([`AutoSolver`]: dense LU for small systems, sparse LU for
//! large), with its slot values.
//!
//! Its analysis (a fill-reducing ordering and trial factorizations: 25 ms at 1,000 bodies,
//! more than ten steps) is made with the layout for systems up to [`LU_EAGER_MAX_SIZE`] or
//! with coupling blocks, where the LU is a usual path; otherwise it waits for the first LU
//! factorization (a fallback near a singular configuration), which then allocates, once.

use super::layout::Layout;
use cardan_solver::{AutoSolver, LinearSolver, SolverError, SparsityPattern};

/// Size n + m_a up to which the LU of the full matrix is analyzed with the layout (see the
/// module docs).
pub(crate) const LU_EAGER_MAX_SIZE: usize = 2000;

/// The LU of the full matrix, analyzed on first use.
#[derive(Debug)]
pub(crate) struct FullLu {
    /// `None` until analyzed.
    solver: Option<AutoSolver>,
    /// (row, column) of each slot, kept for a deferred analysis.
    entries: Vec<(usize, usize)>,
    size: usize,
    /// Values of the full matrix in slot order (written only when this path factors).
    pub slots: Vec<f64>,
}

impl FullLu {
    /// The LU of a `size` × `size` matrix with nonzeros at `entries` (slot order).
    pub fn new(entries: Vec<(usize, usize)>, size: usize) -> Self {
        Self {
            solver: None,
            slots: vec![0.0; entries.len()],
            entries,
            size,
        }
    }

    /// The analyzed solver (analyzing it now if it was not).
    pub fn solver(&mut self) -> Result<&mut AutoSolver, SolverError> {
        if self.solver.is_none() {
            let pattern = SparsityPattern::new(self.size, self.size, &self.entries)?;
            let mut solver = AutoSolver::default();
            solver.analyze(&pattern)?;
            self.solver = Some(solver);
            self.entries = Vec::new();
        }
        Ok(self.solver.as_mut().expect("analyzed"))
    }

    /// The analysis was made.
    #[cfg(test)]
    pub fn analyzed(&self) -> bool {
        self.solver.is_some()
    }

    /// Writes Φ_v and Φ_vᵀ into their slots.
    pub fn write_phi_v(&mut self, layout: &Layout, jac: &[f64]) {
        for (&(s, st), &v) in layout.jac_slots.iter().zip(jac) {
            self.slots[s] = v;
            self.slots[st] = v;
        }
    }

    /// Factors the slots' values.
    pub fn factor(&mut self) -> Result<(), SolverError> {
        let slots = std::mem::take(&mut self.slots);
        let r = self.solver().and_then(|lu| lu.factor(&slots));
        self.slots = slots;
        r
    }

    /// Solves with the last factorization.
    pub fn solve(&mut self, rhs: &[f64], sol: &mut [f64]) -> Result<(), SolverError> {
        match self.solver.as_mut() {
            Some(lu) => lu.solve(rhs, sol),
            None => Err(SolverError::NotReady { missing: "factor" }),
        }
    }
}
