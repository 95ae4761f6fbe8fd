//! What the last successful factorization holds: which path made it, the Φ_v values it was
//! made with (for the Schur refinement, whose residual must use the factored matrix), and
//! whether its top-left was the mass matrix unchanged since.
//!
//! A mass-only matrix equal to the one factored last is not factored again: DOPRI5's velocity
//! projection of a step end whose positions did not move, the evaluation of the equations of
//! motion there and the recording of an output time all share one factorization.

/// The factorization held for [`Kkt::solve`](super::Kkt::solve).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Factored {
    Schur,
    Lu,
}

/// The record of the last factorization.
#[derive(Debug)]
pub(crate) struct LastFactorization {
    kind: Option<Factored>,
    /// Φ_v values of the last factorization.
    jac: Vec<f64>,
    /// Its top-left was the mass matrix, and the mass blocks have not changed since.
    mass_only: bool,
}

impl LastFactorization {
    /// For `ne` values of Φ_v; nothing factored.
    pub fn new(ne: usize) -> Self {
        Self {
            kind: None,
            jac: vec![0.0; ne],
            mass_only: false,
        }
    }

    pub fn kind(&self) -> Option<Factored> {
        self.kind
    }

    /// Φ_v as factored.
    pub fn jac(&self) -> &[f64] {
        &self.jac
    }

    /// Nothing usable is held (a factorization starts, or the path was forced).
    pub fn clear(&mut self) {
        self.kind = None;
    }

    /// The mass blocks changed: the held factorization is not of the current mass matrix.
    pub fn mass_changed(&mut self) {
        self.mass_only = false;
    }

    /// The held factorization is of this mass-only matrix (`tangent`: the top-left has
    /// tangent terms).
    pub fn unchanged(&self, jac: &[f64], tangent: bool) -> bool {
        self.kind.is_some() && self.mass_only && !tangent && jac == self.jac
    }

    /// Records a successful factorization.
    pub fn remember(&mut self, kind: Factored, jac: &[f64], tangent: bool) {
        self.kind = Some(kind);
        self.jac.copy_from_slice(jac);
        self.mass_only = !tangent;
    }
}
