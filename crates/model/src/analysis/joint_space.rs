//! An inverse dynamics run's joint space as output groups (`[analysis.outputs] joint_space`,
//! `jacobians`): `mass_matrix` (M(θ) row by row, `M.d_i.d_j`), `bias_forces` (h(θ, θ̇), one
//! column per driver) and `jacobians` (per point and per driven coordinate, the point's velocity
//! and its body's angular velocity, global axes). The coordinates are the drivers', in model
//! order; the theory is [`cardan_dynamics::joint_space`]'s.
//!
//! Units follow each pair of coordinates: M_ij is effort_i per unit acceleration of θ_j (kg m²
//! for two angles, kg m for an angle and a slide, kg for two slides), a Jacobian column is per
//! unit rate of θ_j (m and − for a point's velocity per rad/s and per m/s, − and rad/m for the
//! angular velocity).

use crate::build::Outputs as Requested;
use crate::diag::Error;
use crate::output_tables::effort_kind;
use crate::prepare::Prepared;
use crate::table::Table;
use cardan_constraints::Driver;
use cardan_dynamics::{DynamicResults, Dynamics, JointSpacePoint};

/// Asks `d` for the joint space when `req` does (`joint_space = true` or `jacobians`).
///
/// # Errors
/// The model's drivers do not make a joint space (none, or a general motion from a moving
/// body).
pub(super) fn request(p: &Prepared, d: &mut Dynamics, req: &Requested) -> Result<(), Error> {
    if !req.joint_space && req.jacobians.is_empty() {
        return Ok(());
    }
    let points = (req.jacobians.iter())
        .filter_map(|(body, point)| {
            let f = (p.model.points().iter()).find(|f| &f.body_name == body && &f.name == point)?;
            Some(JointSpacePoint {
                name: format!("{body}.{point}"),
                body: f.body,
                local: f.local,
            })
        })
        .collect();
    d.request_joint_space(points)
        .map(|_| ())
        .map_err(|e| p.source.error(format!("[analysis.outputs]: {e}")))
}

/// Whether driver i's coordinate is an angle.
fn is_angle(p: &Prepared, name: &str) -> bool {
    (p.model.drivers().iter())
        .find(|d| d.name == name)
        .is_some_and(|d| matches!(d.driver, Driver::Rotation(_)))
}

/// The tables of the joint space, when the run recorded it.
pub fn joint_space_tables(p: &Prepared, r: &DynamicResults) -> Vec<Table> {
    let js = &r.joint_space;
    if !js.is_requested() {
        return Vec::new();
    }
    let names = &js.coordinates;
    let angle: Vec<bool> = names.iter().map(|n| is_angle(p, n)).collect();
    let mut mass = Vec::new();
    for (i, a) in names.iter().enumerate() {
        for (j, b) in names.iter().enumerate() {
            let unit = match (angle[i], angle[j]) {
                (true, true) => "kg m²",
                (false, false) => "kg",
                _ => "kg m",
            };
            mass.push(format!("M.{a}.{b} [{unit}]"));
        }
    }
    let bias = (names.iter())
        .map(|n| {
            let (what, unit) = effort_kind(p, n);
            format!("{n}.{what} [{unit}]")
        })
        .collect();
    let mut jac = Vec::new();
    for point in &js.points {
        for (row, linear) in ROWS {
            for (j, n) in names.iter().enumerate() {
                let unit = match (linear, angle[j]) {
                    (true, true) => "m",
                    (false, false) => "rad/m",
                    _ => "-",
                };
                jac.push(format!("{}.{row}.{n} [{unit}]", point.name));
            }
        }
    }
    let mut out = vec![
        Table::new(
            "mass_matrix",
            "mass matrix M(θ) in the driven coordinates",
            mass,
        ),
        Table::new(
            "bias_forces",
            "bias forces h(θ, θ̇) (efforts at θ̈ = 0)",
            bias,
        ),
    ];
    if !js.points.is_empty() {
        out.push(Table::new("jacobians", "point Jacobians, global axes", jac));
    }
    for (g, t) in out.iter_mut().enumerate() {
        for (k, time) in r.times().iter().enumerate() {
            let mut row = vec![*time];
            joint_space_row(r, g, k, &mut row);
            t.rows.push(row);
        }
    }
    out
}

/// The Jacobian's rows: name and whether it is a linear velocity.
const ROWS: [(&str, bool); 6] = [
    ("vx", true),
    ("vy", true),
    ("vz", true),
    ("wx", false),
    ("wy", false),
    ("wz", false),
];

/// Appends group g (0 mass matrix, 1 bias forces, 2 Jacobians) at time k to `row`.
pub(super) fn joint_space_row(r: &DynamicResults, g: usize, k: usize, row: &mut Vec<f64>) {
    let js = &r.joint_space;
    match g {
        0 => row.extend_from_slice(js.mass_at(k)),
        1 => row.extend_from_slice(js.bias_at(k)),
        _ => (0..js.points.len()).for_each(|p| row.extend_from_slice(js.jacobian_at(k, p))),
    }
}
