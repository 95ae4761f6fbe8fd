//! [`Primitive`]: the closed set of primitive equations (static dispatch, no `dyn` in hot loops).

use crate::{
    Distance, Homokinetic, Normalization, P1Perp, P1Select, P2Perp, P2Select, RadialDistance,
    Spherical, N1, N2, P1, P2,
};

/// One primitive constraint. Adding a primitive: a file with its struct and `Constraint` impl,
/// a variant here, and one entry in the `dispatch!` list below (the compiler finds the rest).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Primitive {
    /// s_iᵀ s_j (1 row).
    N1(N1),
    /// s_iᵀ d (1 row).
    N2(N2),
    /// s_i × s_j (3 rows, rank 2).
    P1(P1),
    /// Two body-frame-selected rows of s_i × s_j.
    P1Select(P1Select),
    /// [f_iᵀ s_j; g_iᵀ s_j].
    P1Perp(P1Perp),
    /// s_i × d (3 rows, rank 2).
    P2(P2),
    /// Two body-frame-selected rows of s_i × d.
    P2Select(P2Select),
    /// [f_iᵀ d; g_iᵀ d].
    P2Perp(P2Perp),
    /// r^P_i − r^P_j (3 rows).
    Spherical(Spherical),
    /// dᵀd − ℓ² (1 row).
    Distance(Distance),
    /// p_iᵀ p_i − 1 (1 row).
    Normalization(Normalization),
    /// (f_iᵀ d)² + (g_iᵀ d)² − ℓ² (1 row).
    RadialDistance(RadialDistance),
    /// x_iᵀ y_j − y_iᵀ x_j (1 row).
    Homokinetic(Homokinetic),
}

macro_rules! dispatch {
    ($self:ident, $c:ident => $e:expr) => {
        match $self {
            Primitive::N1($c) => $e,
            Primitive::N2($c) => $e,
            Primitive::P1($c) => $e,
            Primitive::P1Select($c) => $e,
            Primitive::P1Perp($c) => $e,
            Primitive::P2($c) => $e,
            Primitive::P2Select($c) => $e,
            Primitive::P2Perp($c) => $e,
            Primitive::Spherical($c) => $e,
            Primitive::Distance($c) => $e,
            Primitive::Normalization($c) => $e,
            Primitive::RadialDistance($c) => $e,
            Primitive::Homokinetic($c) => $e,
        }
    };
}

forward_constraint_by_match!(Primitive, dispatch);

macro_rules! from_variant {
    ($($v:ident),*) => {$(
        impl From<$v> for Primitive {
            fn from(c: $v) -> Self {
                Primitive::$v(c)
            }
        }
    )*};
}
from_variant!(
    N1,
    N2,
    P1,
    P1Select,
    P1Perp,
    P2,
    P2Select,
    P2Perp,
    Spherical,
    Distance,
    Normalization,
    RadialDistance,
    Homokinetic
);
