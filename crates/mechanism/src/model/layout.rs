//! The row layout of the global system: each joint's and driver's row range, the sparsity
//! pattern of Φ_v (the declared r and p blocks of each moving body of each element), the scatter
//! maps from element blocks to pattern slots, and the scales of equations (by their dimension:
//! 1, L or L²) and unknowns (L for Δr, 1 for Δπ'), with L the characteristic length.

use super::elements::{
    BodyId, BodyInfo, CouplerInfo, CurveInfo, DriverInfo, FeatureInfo, JointInfo, PathInfo,
    ScatterMap, NO_SLOT,
};
use crate::builder::MechanismBuilder;
use cardan_constraints::{Constraint, Footprint};
use cardan_solver::SparsityPattern;
use std::ops::Range;

/// The rows, pattern and scales of a model.
pub(super) struct Layout {
    pub pattern: SparsityPattern,
    pub equation_scales: Vec<f64>,
    pub unknown_scales: Vec<f64>,
    pub num_rows: usize,
    pub joint_rows: usize,
}

/// The characteristic length L: the largest body position, point offset or joint length (1 when
/// all are zero).
pub(super) fn characteristic_length(
    b: &MechanismBuilder,
    bodies: &[BodyInfo],
    points: &[FeatureInfo],
) -> f64 {
    let mut length: f64 = 0.0;
    for bd in bodies {
        length = length.max(bd.initial_r.norm());
    }
    for p in points {
        length = length.max(p.local.norm());
    }
    for j in &b.joints {
        for l in [j.length, j.offset].into_iter().flatten() {
            if l.is_finite() {
                length = length.max(l.abs());
            }
        }
    }
    if !(length > 0.0 && length.is_finite()) {
        length = 1.0;
    }
    length
}

/// Lays out the rows of `joints`, `curves` (point-on-curve elements), `couplers`, `drivers`,
/// then `paths` (setting their row ranges and
/// scatter maps) for `nb` moving bodies. Joints and couplers are the constraints that fix the
/// degrees of freedom (the "joint rows"); drivers come last.
pub(super) fn rows(
    joints: &mut [JointInfo],
    curves: &mut [CurveInfo],
    couplers: &mut [CouplerInfo],
    drivers: &mut [DriverInfo],
    paths: &mut [PathInfo],
    nb: usize,
    length: f64,
) -> Layout {
    let mut entries: Vec<(usize, usize)> = Vec::new();
    let mut equation_scales = Vec::new();
    let mut row = 0;
    for j in joints.iter_mut() {
        let (rows, map) = layout(
            &mut row,
            &mut entries,
            j.joint.rows(),
            j.joint.footprint(),
            j.body_i,
            j.body_j,
        );
        j.rows = rows;
        j.map = map;
        // Each row's scale from its dimension: 1, L or L².
        for r in 0..j.joint.rows() {
            equation_scales.push(j.joint.dimension(r).scale(length));
        }
    }
    // Point-on-curve elements: joint rows too, with their curve parameter's column after the
    // bodies' (6 nb + extra).
    for c in curves.iter_mut() {
        let n = c.element.rows();
        let (rows, map) = layout(
            &mut row,
            &mut entries,
            n,
            c.element.footprint(),
            c.body_i,
            c.body_j,
        );
        c.extra_slots = (rows.clone())
            .flat_map(|r| c.extras().map(move |e| (r, 6 * nb + e)))
            .map(|entry| {
                entries.push(entry);
                entries.len() - 1
            })
            .collect();
        c.rows = rows;
        c.map = map;
        for r in 0..n {
            equation_scales.push(c.element.dimension(r).scale(length));
        }
    }
    for c in couplers.iter_mut() {
        let (rows, map) = layout(
            &mut row,
            &mut entries,
            1,
            c.coupler.footprint(),
            c.body_i,
            c.body_j,
        );
        c.rows = rows;
        c.map = map;
        equation_scales.push(c.coupler.dimension(0).scale(length));
    }
    let joint_rows = row;
    for d in drivers.iter_mut() {
        let (rows, map) = layout(
            &mut row,
            &mut entries,
            1,
            d.driver.footprint(),
            d.body_i,
            d.body_j,
        );
        d.rows = rows;
        d.map = map;
        equation_scales.push(d.driver.dimension(0).scale(length));
    }
    // Path drivers: one row on their curve parameter's column alone.
    for p in paths.iter_mut() {
        p.rows = row..row + 1;
        p.slot = entries.len();
        entries.push((row, 6 * nb + p.extra));
        equation_scales.push(p.driver.dimension(0).scale(length));
        row += 1;
    }
    let num_rows = row;
    let n = 6 * nb + curves.last().map_or(0, |c| c.extras().end);
    let pattern = SparsityPattern::new(num_rows, n, &entries)
        .expect("entries are inside the matrix by construction");
    // Δr and a curve parameter (a length: chord length or arc length) scale with L, Δπ' not.
    let unknown_scales = (0..n)
        .map(|c| {
            if c >= 6 * nb || c % 6 < 3 {
                length
            } else {
                1.0
            }
        })
        .collect();
    Layout {
        pattern,
        equation_scales,
        unknown_scales,
        num_rows,
        joint_rows,
    }
}

/// Appends the pattern entries of an element with `rows` rows starting at `*row`.
fn layout(
    row: &mut usize,
    entries: &mut Vec<(usize, usize)>,
    rows: usize,
    fp: Footprint,
    bi: BodyId,
    bj: BodyId,
) -> (Range<usize>, ScatterMap) {
    let start = *row;
    let mut slots = vec![NO_SLOT; rows * 12];
    for r in 0..rows {
        for (side, id, use_) in [(0, bi, fp.i), (1, bj, fp.j)] {
            let BodyId::Moving(k) = id else { continue };
            for c in 0..6 {
                let used = if c < 3 { use_.r } else { use_.p };
                if used {
                    slots[r * 12 + side * 6 + c] = entries.len();
                    entries.push((start + r, 6 * k + c));
                }
            }
        }
    }
    *row += rows;
    (start..*row, ScatterMap { slots })
}
