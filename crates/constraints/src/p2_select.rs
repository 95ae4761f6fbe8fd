//! p2 with the seed's row selection, applied in body i's frame (see [`crate::p1_select`]):
//!
//! ```text
//! Φ = two rows of s̃'_i (A_iᵀ d) = [u_aᵀ d; u_bᵀ d],   u_k = A_i (e_k × s'_i)
//! ```
//! with the row k = argmax |s'_i\[k\]| dropped, fixed at construction (no chatter, always rank 2).
//! Evaluation is that of [`crate::P2Perp`] with f' = u'_a, g' = u'_b.

use crate::p1_select::select_rows;
use crate::p2_perp::P2Perp;
use nalgebra::Vector3;

/// Two selected rows of s̃'_i A_iᵀ d = 0.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct P2Select {
    /// s'_i, body-i components.
    pub s_i: Vector3<f64>,
    /// s'^P_i.
    pub sp_i: Vector3<f64>,
    /// s'^P_j.
    pub sp_j: Vector3<f64>,
    /// The kept rows of s̃'_i (A_iᵀ d), increasing.
    pub kept: [usize; 2],
    inner: P2Perp,
}

impl P2Select {
    /// p2 with direction s'_i, points s'^P_i, s'^P_j and the body-frame row selection.
    pub fn new(s_i: Vector3<f64>, sp_i: Vector3<f64>, sp_j: Vector3<f64>) -> Self {
        let (kept, [u, w]) = select_rows(&s_i);
        Self {
            s_i,
            sp_i,
            sp_j,
            kept,
            inner: P2Perp::new(u, w, sp_i, sp_j),
        }
    }
}

forward_constraint_to_field!(P2Select, inner, "p2_select");
