//! When the LU members call a matrix singular, and what they say then: a pivot of the
//! equilibrated matrix at or below [`DEFAULT_PIVOT_TOLERANCE`] (or the solver's own tolerance)
//! fails the factorization, and the error names the dependent equations by a dense rank
//! analysis ([`crate::RankAnalysis`]) when the matrix is small enough, else the rows whose
//! pivots vanished.

use crate::error::SolverError;
use crate::pattern::SparsityPattern;
use crate::rank::{RankAnalysis, RankOptions};

/// Pivot tolerance of the LU members: a pivot `|u_jj| ≤ tol` of the equilibrated matrix (largest
/// entry of every row and column about 1) means singular.
pub const DEFAULT_PIVOT_TOLERANCE: f64 = 1e-12;

/// Largest `m · n` for which a failed LU runs a dense rank analysis to name the dependent
/// equations (beyond it the error lists the rows whose pivots vanished).
pub(crate) const DIAGNOSE_MAX_ENTRIES: usize = 1_000_000;

/// Builds the `Singular` error for an LU failure: a dense rank analysis when the matrix is
/// small enough, else the given pivot rows. Runs only on the error path (it allocates).
pub(crate) fn singular_error(
    pattern: &SparsityPattern,
    slots: &[f64],
    pivot_rows: &[usize],
) -> SolverError {
    if pattern.nrows().saturating_mul(pattern.ncols()) <= DIAGNOSE_MAX_ENTRIES {
        if let Ok(analysis) = RankAnalysis::compute(pattern, slots, RankOptions::default()) {
            if !analysis.dependent_rows().is_empty() {
                return SolverError::Singular {
                    dependent_equations: analysis.dependent_rows().to_vec(),
                };
            }
        }
    }
    let mut rows = pivot_rows.to_vec();
    rows.sort_unstable();
    SolverError::Singular {
        dependent_equations: rows,
    }
}
