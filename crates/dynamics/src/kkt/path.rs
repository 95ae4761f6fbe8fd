//! Which factorization [`Kkt::factor`](super::Kkt::factor) tries first: the Schur complement or
//! the LU of the full matrix, and the back-off from the Schur path after it was refused.
//!
//! The Schur complement S = Φ_v A⁻¹ Φ_vᵀ squares the conditioning of Φ_v, so near a singular
//! configuration its Cholesky refuses S (small relative pivot) and the LU takes that
//! factorization. A model whose S is refused again and again (a mechanism held near such a
//! configuration) should not pay for the attempt at every factorization: after
//! [`SCHUR_BACKOFF`]`.0` consecutive refusals the Schur path is skipped for the next
//! [`SCHUR_BACKOFF`]`.1` factorizations. A mass block the Schur solver refuses (condition beyond
//! 1e8: a point mass with a negligible inertia) is constant, so every later mass-only
//! factorization goes to the LU directly.

/// After this many consecutive refusals of S (`.0`), the Schur complement is skipped for the
/// next `.1` factorizations: a model whose S is always refused (a mechanism held in a
/// near-singular configuration) pays for the attempt once in 16 factorizations instead of at
/// each, and a singular passage returns to the Schur path at most 15 factorizations after it.
pub(crate) const SCHUR_BACKOFF: (usize, usize) = (3, 15);

/// Which factorization [`Kkt::factor`](super::Kkt::factor) uses.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub(crate) enum KktSolve {
    /// Schur complement when the top-left is block diagonal, with the LU as fallback; LU
    /// otherwise.
    #[default]
    Auto,
    /// Always the LU of the full matrix.
    #[allow(dead_code)]
    Lu,
    /// The Schur complement whenever the top-left is block diagonal, and no fallback (its error
    /// is returned); LU otherwise.
    #[allow(dead_code)]
    Schur,
}

/// The path policy: the forced mode and the back-off state of the Schur path (`Default`: the
/// automatic choice, nothing refused yet).
#[derive(Debug, Clone, Default)]
pub(crate) struct SolvePath {
    mode: KktSolve,
    /// The Schur solver refused the mass blocks (see the module docs).
    mass_refused: bool,
    /// Consecutive factorizations whose S was refused.
    refusals: usize,
    /// Factorizations left before the Schur path is tried again.
    skip_left: usize,
}

impl SolvePath {
    pub fn set_mode(&mut self, mode: KktSolve) {
        self.mode = mode;
    }

    /// A Schur failure is returned instead of falling back to the LU.
    pub fn strict(&self) -> bool {
        self.mode == KktSolve::Schur
    }

    /// Whether this factorization (`tangent`: the top-left has tangent terms) tries the Schur
    /// path first; counts down the back-off.
    pub fn try_schur(&mut self, tangent: bool) -> bool {
        let auto = self.mode == KktSolve::Auto;
        let skip = self.mode == KktSolve::Lu
            || (auto && self.mass_refused && !tangent)
            || (auto && self.skip_left > 0);
        self.skip_left = self.skip_left.saturating_sub(1);
        !skip
    }

    /// The Schur factorization succeeded.
    pub fn accepted(&mut self) {
        self.refusals = 0;
    }

    /// The Schur factorization failed and the LU takes over: `mass_block` when a mass block
    /// was refused (a failure that lists no equations) of a mass-only matrix, else S.
    pub fn refused(&mut self, mass_block: bool) {
        if mass_block {
            self.mass_refused = true;
        } else {
            self.refusals += 1;
            if self.refusals >= SCHUR_BACKOFF.0 {
                self.skip_left = SCHUR_BACKOFF.1;
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn three_refusals_skip_the_schur_path_for_fifteen_factorizations() {
        let mut p = SolvePath::default();
        for _ in 0..SCHUR_BACKOFF.0 {
            assert!(p.try_schur(false));
            p.refused(false);
        }
        let skipped = (0..100).take_while(|_| !p.try_schur(false)).count();
        assert_eq!(skipped, SCHUR_BACKOFF.1);
        // An accepted S resets the count: two more refusals do not back off.
        p.accepted();
        for _ in 0..SCHUR_BACKOFF.0 - 1 {
            p.refused(false);
            assert!(p.try_schur(false));
        }
    }

    #[test]
    fn a_refused_mass_block_sends_mass_only_matrices_to_the_lu() {
        let mut p = SolvePath::default();
        p.refused(true);
        assert!(!p.try_schur(false));
        assert!(p.try_schur(true), "a tangent matrix has other blocks");
        p.set_mode(KktSolve::Lu);
        assert!(!p.try_schur(true));
        p.set_mode(KktSolve::Schur);
        assert!(p.strict());
    }
}
