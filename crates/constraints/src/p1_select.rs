//! p1 with the seed's row selection: two of the three rows of s̃_i s_j, chosen so that the choice
//! never changes during a simulation and never loses rank.
//!
//! The seed (Nikravesh 1988 §7.2) keeps the two rows of s̃_i s_j that contain the largest
//! components of s_i. Done on the *global* components, the choice must change as body i turns,
//! and switching rows from step to step (chatter) disturbs Newton and the integrator. cardan
//! applies the rule to the **body-frame** components instead: the equations are the rows of
//!
//! ```text
//! A_iᵀ (s̃_i s_j) = s̃'_i (A_iᵀ s_j)
//! ```
//!
//! (the same three equations, expressed in body i's frame), and the row k = argmax |s'_i\[k\]| is
//! dropped. Since s'_i is constant, the choice is fixed once at construction. Row k of s̃'_i y is
//! yᵀ (e_k × s'_i), so each kept row is an n1 with the body-fixed vector u'_k = e_k × s'_i:
//!
//! ```text
//! Φ = [u_aᵀ s_j; u_bᵀ s_j],   u_k = A_i (e_k × s'_i),   {a, b} = {0, 1, 2} \ {argmax_k |s'_i[k]|}
//! ```
//!
//! u'_a, u'_b are perpendicular to s'_i and independent of each other (their cross product is
//! s'_i\[k\] s'_i, nonzero), so the two rows have rank 2 whenever s_j ∥ s_i, in every orientation
//! of both bodies. Evaluation is that of [`crate::P1Perp`] with f' = u'_a, g' = u'_b.

use crate::p1_perp::P1Perp;
use nalgebra::Vector3;

/// The kept rows {a, b} (increasing) and their body-fixed vectors e_a × s', e_b × s'.
/// The dropped row is the first index of the largest |s'\[k\]|.
pub fn select_rows(s_local: &Vector3<f64>) -> ([usize; 2], [Vector3<f64>; 2]) {
    let k = s_local.iamax();
    let kept = match k {
        0 => [1, 2],
        1 => [0, 2],
        _ => [0, 1],
    };
    let u = kept.map(|r| {
        let mut e = Vector3::zeros();
        e[r] = 1.0;
        e.cross(s_local)
    });
    (kept, u)
}

/// Two selected rows of s̃'_i A_iᵀ s_j = 0.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct P1Select {
    /// s'_i, body-i components.
    pub s_i: Vector3<f64>,
    /// s'_j, body-j components.
    pub s_j: Vector3<f64>,
    /// The kept rows of s̃'_i (A_iᵀ s_j), increasing.
    pub kept: [usize; 2],
    inner: P1Perp,
}

impl P1Select {
    /// p1 between s'_i and s'_j with the body-frame row selection.
    pub fn new(s_i: Vector3<f64>, s_j: Vector3<f64>) -> Self {
        let (kept, [u, w]) = select_rows(&s_i);
        Self {
            s_i,
            s_j,
            kept,
            inner: P1Perp::new(u, w, s_j),
        }
    }
}

forward_constraint_to_field!(P1Select, inner, "p1_select");
