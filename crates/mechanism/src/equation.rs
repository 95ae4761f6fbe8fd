//! [`EquationName`]: which element, kind and primitive a global equation (row) belongs to, the
//! name that reports of redundancy, singularity and dropped rows give a row. Made by
//! [`Model::equation`](crate::Model::equation).

/// A named equation of the mechanism (for redundancy and singularity reports).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct EquationName {
    /// Global row index.
    pub row: usize,
    /// Joint or driver name.
    pub element: String,
    /// Joint kind name or driver kind ("revolute", "rotation_driver", ...).
    pub kind: &'static str,
    /// Primitive the row belongs to ("spherical", "n1", ...; the driver kind for drivers).
    pub primitive: &'static str,
    /// Row within the element.
    pub local_row: usize,
}

impl std::fmt::Display for EquationName {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "{} \"{}\" row {} ({})",
            self.kind, self.element, self.local_row, self.primitive
        )
    }
}
