//! Minimum-norm solutions of large under-determined or redundant systems.
//!
//! [`MinNormQr`](crate::MinNormQr) is dense (`m n` memory: 24 GB for a 10,000-body chain). For
//! large models the same step is found sparsely: at each factorization the independent rows are
//! chosen by the sparse rank analysis ([`crate::sparse_rank`]), and the minimum-norm solution of
//! the kept rows `J_s x = b_s` is the first block of the saddle-point system (the optimality
//! conditions of `min ½ ‖x‖²` subject to `J_s x = b_s`; Björck, *Numerical Methods for Least
//! Squares Problems*, 1996, §1.1.2 and §7.7)
//!
//! ```text
//!   [ I   J_sᵀ ] [ x ]   [ 0   ]
//!   [ J_s  0   ] [ λ ] = [ b_s ],
//! ```
//!
//! nonsingular because `J_s` has full row rank, and factored with the sparse LU
//! ([`SparseLu`], which equilibrates rows and columns and pivots for stability; the augmented
//! form keeps the condition number of `J_s`, where the normal equations `J_s J_sᵀ` would square
//! it). Dropped rows are the dependent ones: on a consistent redundant system the step satisfies
//! them too. Unlike the dense solver, this one is not a Gauss-Newton step for an inconsistent
//! redundant system (it ignores the dropped rows), which only slows an assembly iterate far off
//! the manifold; the convergence test still covers every equation.
//!
//! `factor` allocates (the rank analysis, and a new symbolic LU when the kept rows change): the
//! solver is meant for assembly, a setup step, not for the per-step solves of a run.

use crate::error::SolverError;
use crate::linear::LinearSolver;
use crate::pattern::{check_len, SparsityPattern};
use crate::rank::{RankAnalysis, RankOptions};
use crate::sparse::SparseLu;

/// Sparse minimum-norm solver for any shape (see the module docs).
#[derive(Debug, Default)]
pub struct SparseMinNorm {
    pattern: Option<SparsityPattern>,
    options: RankOptions,
    /// Rows kept by the last rank analysis, and the LU of the augmented system on them.
    kept: Vec<usize>,
    dependent: Vec<usize>,
    lu: Option<SparseLu>,
    /// For each slot of the augmented pattern after the identity: the slot of `J` it copies.
    source: Vec<usize>,
    values: Vec<f64>,
    rhs: Vec<f64>,
    sol: Vec<f64>,
    factored: bool,
}

impl SparseMinNorm {
    /// A solver with the default rank options.
    pub fn new() -> Self {
        Self::default()
    }

    /// Builds the augmented pattern on the kept rows and analyzes its LU.
    fn lay_out(&mut self, pattern: &SparsityPattern) -> Result<(), SolverError> {
        let n = pattern.ncols();
        let mut position = vec![usize::MAX; pattern.nrows()];
        for (i, &r) in self.kept.iter().enumerate() {
            position[r] = i;
        }
        let mut entries: Vec<(usize, usize)> = (0..n).map(|k| (k, k)).collect();
        self.source.clear();
        for (s, (r, c)) in pattern.entries().enumerate() {
            let i = position[r];
            if i != usize::MAX {
                entries.push((n + i, c));
                entries.push((c, n + i));
                self.source.push(s);
            }
        }
        let size = n + self.kept.len();
        let aug = SparsityPattern::new(size, size, &entries)?;
        let mut lu = SparseLu::new();
        lu.analyze(&aug)?;
        self.lu = Some(lu);
        self.values = vec![0.0; entries.len()];
        self.values[..n].fill(1.0);
        self.rhs = vec![0.0; size];
        self.sol = vec![0.0; size];
        Ok(())
    }
}

impl LinearSolver for SparseMinNorm {
    fn analyze(&mut self, pattern: &SparsityPattern) -> Result<(), SolverError> {
        self.pattern = Some(pattern.clone());
        self.kept.clear();
        self.lu = None;
        self.factored = false;
        Ok(())
    }

    fn factor(&mut self, slots: &[f64]) -> Result<(), SolverError> {
        self.factored = false;
        let pattern = self
            .pattern
            .take()
            .ok_or(SolverError::NotReady { missing: "analyze" })?;
        let result = self.factor_with(&pattern, slots);
        self.pattern = Some(pattern);
        result
    }

    fn solve(&mut self, b: &[f64], x: &mut [f64]) -> Result<(), SolverError> {
        let (Some(lu), true) = (self.lu.as_mut(), self.factored) else {
            return Err(SolverError::NotReady { missing: "factor" });
        };
        let n = x.len();
        check_len(
            "right-hand side",
            self.dependent.len() + self.kept.len(),
            b.len(),
        )?;
        check_len("solution", self.rhs.len() - self.kept.len(), n)?;
        self.rhs[..n].fill(0.0);
        for (i, &r) in self.kept.iter().enumerate() {
            self.rhs[n + i] = b[r];
        }
        lu.solve(&self.rhs, &mut self.sol)?;
        x.copy_from_slice(&self.sol[..n]);
        Ok(())
    }

    fn nrows(&self) -> usize {
        self.pattern.as_ref().map_or(0, SparsityPattern::nrows)
    }

    fn ncols(&self) -> usize {
        self.pattern.as_ref().map_or(0, SparsityPattern::ncols)
    }

    fn rank(&self) -> Option<usize> {
        self.factored.then_some(self.kept.len())
    }

    fn dependent_equations(&self) -> &[usize] {
        if self.factored {
            &self.dependent
        } else {
            &[]
        }
    }

    fn name(&self) -> &'static str {
        "sparse-min-norm"
    }
}

impl SparseMinNorm {
    fn factor_with(&mut self, pattern: &SparsityPattern, slots: &[f64]) -> Result<(), SolverError> {
        let ra = RankAnalysis::compute_sparse(pattern, slots, self.options)?;
        if self.lu.is_none() || ra.independent_rows() != self.kept.as_slice() {
            self.kept = ra.independent_rows().to_vec();
            self.lay_out(pattern)?;
        }
        self.dependent = ra.dependent_rows().to_vec();
        let n = pattern.ncols();
        for (v, &s) in self.values[n..].chunks_exact_mut(2).zip(&self.source) {
            v[0] = slots[s];
            v[1] = slots[s];
        }
        let lu = self.lu.as_mut().expect("laid out above");
        lu.factor(&self.values)?;
        self.factored = true;
        Ok(())
    }
}
