//! The [`Constraint`] trait: what every primitive, joint and driver provides.

use crate::jet::{Form, Q7, V6};
use crate::state::{BodyPair, Footprint};

/// The most extra coordinates one element owns (a curve on a curve: one parameter each).
pub const MAX_EXTRA: usize = 2;

/// A block of constraint equations Φ(q_i, q_j, t) = 0 between bodies i and j.
///
/// Implemented by every primitive, by [`crate::Joint`] (a list of primitives) and by
/// [`crate::Driver`]. Evaluation never fails and never allocates: output slices have exactly
/// [`Constraint::rows`] entries (rows), and the Jacobian blocks of a ground body may be written
/// but are not used by a mechanism.
///
/// The two coordinate forms are selected by the [`Form`] type parameter:
/// [`Q7`] (q_k = [r_k; p_k], 7 columns per body, Φ_q) or [`V6`] (v_k = [ṙ_k; ω'_k], 6 columns per
/// body, Φ_v). The provided methods [`Constraint::phi_q`], [`Constraint::phi_v`],
/// [`Constraint::gamma_sharp_q`] and [`Constraint::gamma_sharp_v`] name the four combinations.
///
/// Sign conventions (`shared/notation.md`): Φ_q q̇ = ν with ν = −Φ_t, and Φ_q q̈ = γ# where
/// γ# = −(Φ_q q̇)_q q̇ − 2 Φ_qt q̇ − Φ_tt, i.e. minus everything in Φ̈ that is not Φ_q q̈.
pub trait Constraint {
    /// The element's name, as in the oracle data ("n1", "revolute", "rotation_driver", ...).
    fn name(&self) -> &'static str;

    /// Number of equations (rows).
    fn rows(&self) -> usize;

    /// The physical dimension of row `row`'s value (1, length or area), which fixes the row's
    /// scale in convergence tests and rank decisions. Every element states it: a new
    /// dimensionless element cannot silently get a length scale.
    fn dimension(&self, row: usize) -> Dimension;

    /// Which coordinate blocks the rows depend on; fixed by the definition.
    fn footprint(&self) -> Footprint;

    /// Φ (length `rows`).
    fn phi(&self, x: &BodyPair, t: f64, out: &mut [f64]);

    /// The Jacobian blocks for body i and body j in form `F` (each `rows` × N).
    fn jacobian<const N: usize, F: Form<N>>(
        &self,
        x: &BodyPair,
        t: f64,
        out_i: &mut [[f64; N]],
        out_j: &mut [[f64; N]],
    );

    /// The number of extra coordinates u the element owns (the curve parameters of a higher
    /// pair, read from [`BodyPair::u`]): 0 for every other element, at most [`MAX_EXTRA`].
    fn extra(&self) -> usize {
        0
    }

    /// ∂Φ/∂u: `rows` rows of [`Constraint::extra`] columns (the same in both forms: u is a
    /// plain coordinate). Elements without extra coordinates write nothing.
    fn jacobian_extra(&self, x: &BodyPair, t: f64, out: &mut [[f64; MAX_EXTRA]]) {
        let _ = (x, t, out);
    }

    /// ν = −Φ_t (length `rows`). Zero for elements that do not depend on time.
    fn nu(&self, x: &BodyPair, t: f64, out: &mut [f64]) {
        let _ = (x, t);
        out.fill(0.0);
    }

    /// γ# in form `F` (length `rows`), from the velocities held in the [`BodyPair`]
    /// (ṗ for [`Q7`], ω' for [`V6`]; u̇ of an element with extra coordinates).
    fn gamma_sharp<const N: usize, F: Form<N>>(&self, x: &BodyPair, t: f64, out: &mut [f64]);

    /// Φ_q: blocks [Φ_ri Φ_pi] and [Φ_rj Φ_pj].
    fn phi_q(&self, x: &BodyPair, t: f64, out_i: &mut [[f64; 7]], out_j: &mut [[f64; 7]]) {
        self.jacobian::<7, Q7>(x, t, out_i, out_j)
    }

    /// Φ_v: blocks [Φ_ṙi Φ_ω'i] and [Φ_ṙj Φ_ω'j].
    fn phi_v(&self, x: &BodyPair, t: f64, out_i: &mut [[f64; 6]], out_j: &mut [[f64; 6]]) {
        self.jacobian::<6, V6>(x, t, out_i, out_j)
    }

    /// γ# of the 7-coordinate form (uses ṗ).
    fn gamma_sharp_q(&self, x: &BodyPair, t: f64, out: &mut [f64]) {
        self.gamma_sharp::<7, Q7>(x, t, out)
    }

    /// γ# of the 6-coordinate form (uses ω').
    fn gamma_sharp_v(&self, x: &BodyPair, t: f64, out: &mut [f64]) {
        self.gamma_sharp::<6, V6>(x, t, out)
    }
}

/// The physical dimension of an equation's value, which fixes its scale for convergence tests
/// and rank decisions: 1, L or L² for a model length L.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Dimension {
    /// A cosine or a sine (n1 and p1 rows, angle drivers), or Euler parameters.
    Dimensionless,
    /// A distance (point coincidence, n2 and p2 rows, slides, coordinates).
    Length,
    /// A squared distance (dᵀd − ℓ²).
    Area,
}

impl Dimension {
    /// The scale of a value of this dimension in a model of length scale `length`.
    pub fn scale(self, length: f64) -> f64 {
        match self {
            Dimension::Dimensionless => 1.0,
            Dimension::Length => length,
            Dimension::Area => length * length,
        }
    }
}

/// Implements [`Constraint`] for an enum whose every variant holds one element, by delegating
/// each method to the variant's element (a closed family of elements stored in one list and
/// evaluated by static dispatch):
///
/// ```
/// use cardan_constraints::{delegate_constraint, CurveOnCurve, PointOnCurve};
/// enum HigherPair {
///     Point(PointOnCurve),
///     Cam(CurveOnCurve),
/// }
/// delegate_constraint!(HigherPair { HigherPair::Point, HigherPair::Cam });
/// ```
#[macro_export]
macro_rules! delegate_constraint {
    ($ty:ty { $($variant:path),+ $(,)? }) => {
        impl $crate::Constraint for $ty {
            fn name(&self) -> &'static str {
                match self { $($variant(c) => $crate::Constraint::name(c),)+ }
            }
            fn rows(&self) -> usize {
                match self { $($variant(c) => $crate::Constraint::rows(c),)+ }
            }
            fn dimension(&self, row: usize) -> $crate::Dimension {
                match self { $($variant(c) => $crate::Constraint::dimension(c, row),)+ }
            }
            fn footprint(&self) -> $crate::Footprint {
                match self { $($variant(c) => $crate::Constraint::footprint(c),)+ }
            }
            fn phi(&self, x: &$crate::BodyPair, t: f64, out: &mut [f64]) {
                match self { $($variant(c) => $crate::Constraint::phi(c, x, t, out),)+ }
            }
            fn jacobian<const N: usize, F: $crate::Form<N>>(
                &self,
                x: &$crate::BodyPair,
                t: f64,
                out_i: &mut [[f64; N]],
                out_j: &mut [[f64; N]],
            ) {
                match self {
                    $($variant(c) => $crate::Constraint::jacobian::<N, F>(c, x, t, out_i, out_j),)+
                }
            }
            fn extra(&self) -> usize {
                match self { $($variant(c) => $crate::Constraint::extra(c),)+ }
            }
            fn jacobian_extra(
                &self,
                x: &$crate::BodyPair,
                t: f64,
                out: &mut [[f64; $crate::MAX_EXTRA]],
            ) {
                match self { $($variant(c) => $crate::Constraint::jacobian_extra(c, x, t, out),)+ }
            }
            fn nu(&self, x: &$crate::BodyPair, t: f64, out: &mut [f64]) {
                match self { $($variant(c) => $crate::Constraint::nu(c, x, t, out),)+ }
            }
            fn gamma_sharp<const N: usize, F: $crate::Form<N>>(
                &self,
                x: &$crate::BodyPair,
                t: f64,
                out: &mut [f64],
            ) {
                match self {
                    $($variant(c) => $crate::Constraint::gamma_sharp::<N, F>(c, x, t, out),)+
                }
            }
        }
    };
}
