//! Where each value of the KKT matrix goes, decided once per model and active row set.
//!
//! The matrix K = [A Φ_vᵀ; Φ_v 0] (A the top-left: the mass matrix or the iteration matrix) is
//! kept as a list of slots, one per structural nonzero, in this order: the 36 nb entries of the
//! diagonal 6×6 blocks of A (body, row, column), the two 6×6 blocks of each pair of bodies
//! joined by a force element, then the Φ_v and Φ_vᵀ entries, six per active row and moving
//! body of its element (a *group*). Φ_v itself is held apart as six values per group, in the
//! evaluation order of [`super::elements`], and the mass blocks as 36 values per body; the
//! layout maps both to their slots for the LU of the full matrix.

use super::elements::Element;
use cardan_mechanism::{BodyId, Model};

/// Six Φ_v entries: active row `row`, the six columns `col..col + 6` of one moving body
/// (values `jac[6 g..6 g + 6]` for group g).
#[derive(Debug, Clone, Copy)]
pub(crate) struct Group {
    pub row: usize,
    pub col: usize,
}

/// The fixed slot layout of the KKT matrix.
#[derive(Debug)]
pub(crate) struct Layout {
    /// Φ_v by groups of six entries, in evaluation order.
    pub groups: Vec<Group>,
    /// KKT slots (Φ_v, Φ_vᵀ) of each Φ_v value.
    pub jac_slots: Vec<(usize, usize)>,
    /// Top-left slots: (row, col, slot); the 36 nb diagonal-block entries first (body, row,
    /// column order), then the coupling blocks.
    pub top: Vec<(usize, usize, usize)>,
    /// Slot of each entry of the column-major 6×6 diagonal blocks (36 nb).
    pub block_slots: Vec<usize>,
    /// Coupling blocks were laid out (a force element joins two moving bodies).
    pub coupled: bool,
}

impl Layout {
    /// The layout for `elements` restricted to the active rows (`active_of[r]`: position of
    /// model row r among them, `usize::MAX` if dropped), with coupling blocks for the body
    /// `pairs` joined by force elements; also the (row, column) of every slot, in slot order.
    pub fn new(
        model: &Model,
        elements: &[Element],
        active_of: &[usize],
        pairs: &[(usize, usize)],
    ) -> (Self, Vec<(usize, usize)>) {
        let nb = model.num_bodies();
        let n = 6 * nb;
        let mut pos: Vec<(usize, usize)> = Vec::new();
        let mut top = Vec::new();
        let mut block = |bi: usize, bj: usize, pos: &mut Vec<(usize, usize)>| {
            for r in 0..6 {
                for c in 0..6 {
                    top.push((6 * bi + r, 6 * bj + c, pos.len()));
                    pos.push((6 * bi + r, 6 * bj + c));
                }
            }
        };
        for k in 0..nb {
            block(k, k, &mut pos);
        }
        let mut seen: Vec<(usize, usize)> = Vec::new();
        for &(i, j) in pairs {
            let key = (i.min(j), i.max(j));
            if i != j && !seen.contains(&key) {
                seen.push(key);
                block(i, j, &mut pos);
                block(j, i, &mut pos);
            }
        }
        let mut groups = Vec::new();
        let mut jac_slots = Vec::new();
        for e in elements {
            for r in e.rows.clone() {
                let a = active_of[r];
                if a == usize::MAX {
                    continue;
                }
                for id in [e.bi, e.bj] {
                    if let BodyId::Moving(k) = id {
                        groups.push(Group { row: a, col: 6 * k });
                        for c in 0..6 {
                            let col = 6 * k + c;
                            jac_slots.push((pos.len(), pos.len() + 1));
                            pos.push((n + a, col));
                            pos.push((col, n + a));
                        }
                    }
                }
            }
        }
        let coupled = top.len() > 36 * nb;
        // The blocks are column-major per body; `top` lists the diagonal blocks row by row.
        let mut block_slots = vec![0; 36 * nb];
        for &(r, c, s) in &top[..36 * nb] {
            block_slots[36 * (r / 6) + 6 * (c % 6) + r % 6] = s;
        }
        let layout = Self {
            groups,
            jac_slots,
            top,
            block_slots,
            coupled,
        };
        (layout, pos)
    }

    /// The Φ_v entries (row, column) in value order: the pattern of the Schur solver's Φ_v.
    pub fn phi_v_entries(&self) -> Vec<(usize, usize)> {
        self.groups
            .iter()
            .flat_map(|g| (0..6).map(move |c| (g.row, g.col + c)))
            .collect()
    }
}
