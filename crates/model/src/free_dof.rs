//! Which joint coordinates a mechanism leaves free: for the message of a kinematic or inverse
//! dynamics run with fewer drivers than degrees of freedom ("the joints leave 1 DOF: joint
//! \"bearing\" angle is free").
//!
//! At the pose assembled with the joints and the drivers there are, the free motions are the
//! null space of the scaled Φ_v (a dense eigen-decomposition of Φ_vᵀΦ_v; error path only, and only for models up to
//! [`MAX_UNKNOWNS`] unknowns). Each null vector v moves every joint coordinate at the rate
//! ċ = C v ([`cardan_constraints::Joint::coordinate_rates`]); the d coordinates named are chosen
//! greedily from the rows of R = C N (N the null basis, angles weighted by the characteristic
//! length L): each time the row of largest norm, then the rows are made orthogonal to it
//! (Gram–Schmidt with pivoting), so together they span every free motion. Driving those
//! coordinates makes the mechanism fully driven.

use cardan_constraints::joints::CoordinateQuantity;
use cardan_constraints::BodyPair;
use cardan_mechanism::{AssemblyOptions, Model};
use nalgebra::{DMatrix, DVector, Vector3};

/// Models with more unknowns are not diagnosed (the dense SVD would cost more than it tells).
pub const MAX_UNKNOWNS: usize = 600;

/// " (joint \"bearing\" angle, …)" naming the free coordinates of [`free_coordinates`] for a
/// message, or "" when they cannot be told.
pub fn named(model: &Model, t: f64) -> String {
    free_coordinates(model, t).map_or(String::new(), |n| format!(" ({})", n.join(", ")))
}

/// The joint coordinates left free at `t` (`joint "bearing" angle`), one per free degree of
/// freedom, or `None` when they cannot be told (a large model, a pose that does not assemble,
/// a free motion no joint coordinate measures, such as a body without joints).
pub fn free_coordinates(model: &Model, t: f64) -> Option<Vec<String>> {
    let n = model.num_unknowns();
    if n > MAX_UNKNOWNS || n == 0 {
        return None;
    }
    let mut ws = model.workspace();
    model.assemble(&mut ws, &AssemblyOptions::at(t)).ok()?;
    let m = model.num_equations();
    let mut slots = vec![0.0; model.pattern().num_slots()];
    model.eval_jacobian(&ws, t, &mut slots);
    let mut j = DMatrix::<f64>::zeros(m.max(1), n);
    for (s, v) in model.pattern().entries().zip(&slots) {
        j[s] = *v;
    }
    let scales = model.unknown_scales();
    for c in 0..n {
        let sc = scales.get(c).copied().unwrap_or(1.0);
        j.column_mut(c).scale_mut(sc);
    }
    for r in 0..j.nrows() {
        let norm = j.row(r).norm();
        if norm > 0.0 {
            j.row_mut(r).unscale_mut(norm);
        }
    }
    // The null space: the eigenvectors of JᵀJ (n × n, symmetric) with eigenvalue σ² ≈ 0.
    let svd = (j.transpose() * &j).symmetric_eigen();
    let largest = svd.eigenvalues.amax().max(1.0);
    let null: Vec<DVector<f64>> = (0..n)
        .filter(|&k| svd.eigenvalues[k].abs() <= 1e-16 * largest * n as f64)
        .map(|k| {
            let mut v = svd.eigenvectors.column(k).into_owned();
            for c in 0..n {
                v[c] *= scales.get(c).copied().unwrap_or(1.0);
            }
            v
        })
        .collect();
    if null.is_empty() {
        return None;
    }
    let (names, rows) = coordinate_rates(model, &mut ws, &null);
    choose(&names, rows, null.len())
}

/// The rate of every joint coordinate along each null vector: the names and the matrix R
/// (coordinates × null vectors), angles weighted by L.
fn coordinate_rates(
    model: &Model,
    ws: &mut cardan_mechanism::Workspace,
    null: &[DVector<f64>],
) -> (Vec<String>, DMatrix<f64>) {
    let l = model.characteristic_length();
    let coords: Vec<(usize, usize, String)> = model
        .joints()
        .iter()
        .enumerate()
        .flat_map(|(ji, j)| {
            let info = j.joint.kind().info();
            info.coordinates
                .iter()
                .enumerate()
                .map(move |(q, c)| (ji, q, format!("joint \"{}\" {}", j.name, c.name)))
        })
        .collect();
    let mut rows = DMatrix::<f64>::zeros(coords.len(), null.len());
    let zero = Default::default();
    for (k, v) in null.iter().enumerate() {
        for b in 0..model.num_bodies() {
            let r_dot = Vector3::new(v[6 * b], v[6 * b + 1], v[6 * b + 2]);
            let w = Vector3::new(v[6 * b + 3], v[6 * b + 4], v[6 * b + 5]);
            ws.set_velocity(b, r_dot, w);
        }
        for (row, (ji, q, _)) in coords.iter().enumerate() {
            let j = &model.joints()[*ji];
            let (si, sj) = (ws.state_of(j.body_i), ws.state_of(j.body_j));
            let rates = j
                .joint
                .coordinate_rates(&BodyPair::new(&si, &sj), &zero, &zero);
            let info = j.joint.kind().info();
            let weight = match info.coordinates[*q].measure.quantity() {
                CoordinateQuantity::Angle => l,
                _ => 1.0,
            };
            rows[(row, k)] = rates.rates[*q] * weight;
        }
    }
    (coords.into_iter().map(|c| c.2).collect(), rows)
}

/// `d` coordinates whose rows of `rows` span its column space: Gram–Schmidt with the largest
/// remaining row as pivot each time. `None` when the free motion is not measured by `d`
/// independent joint coordinates.
fn choose(names: &[String], mut rows: DMatrix<f64>, d: usize) -> Option<Vec<String>> {
    let scale = rows.amax();
    if scale == 0.0 {
        return None;
    }
    let mut chosen = Vec::new();
    for _ in 0..d {
        let (best, norm) = (0..rows.nrows())
            .map(|r| (r, rows.row(r).norm()))
            .max_by(|a, b| a.1.total_cmp(&b.1))?;
        if norm <= 1e-8 * scale {
            return None;
        }
        let u = rows.row(best).into_owned() / norm;
        for r in 0..rows.nrows() {
            let along = rows.row(r).dot(&u);
            let new = rows.row(r) - &u * along;
            rows.row_mut(r).copy_from(&new);
        }
        chosen.push(names[best].clone());
    }
    Some(chosen)
}
