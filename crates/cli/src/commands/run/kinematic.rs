//! `kind = "kinematic"`: the position, velocity and acceleration analysis over the file's time
//! grid ([`cardan_mechanism::Model::kinematics_with_control`]) and its output groups: points,
//! joint coordinates, body poses, velocities and accelerations, and the residual of the
//! position analysis. The dynamic and inverse dynamics runs write the same kinematic groups.

use super::summary::{Analysed, Summary};
use crate::build::Outputs as Requested;
use crate::commands::output_tables::requested;
use crate::commands::{analysis_error, Prepared};
use crate::diag::Error;
use crate::table::Table;
use cardan_constraints::joints::MAX_COORDINATES;
use cardan_constraints::Dimension;
use cardan_mechanism::{DroppedRowResidual, KinematicOptions, Results};
use std::collections::HashMap;
use std::path::PathBuf;
use std::time::Instant;

/// `kind = "kinematic"`: the kinematics over the file's grid and its tables.
pub(super) fn run_kinematic(
    p: &Prepared,
    analysis: &crate::build::Analysis,
    progress: bool,
) -> Result<Analysed, Error> {
    let opts = KinematicOptions::new(analysis.t_start, analysis.t_end, analysis.steps)
        .tolerance(analysis.tolerance);
    let start = Instant::now();
    let mut bar = crate::progress::Progress::new(progress, opts.steps as u64 + 1);
    let mut ws = p.model.workspace();
    let run = p
        .model
        .kinematics_with_control(&mut ws, &opts, |k, t| bar.tick(k as u64 + 1, t));
    let wall = start.elapsed();
    let (results, failure) = match run {
        Ok(r) if bar.stopped() => {
            let e = crate::progress::interrupted(&r.times);
            (r, Some(e))
        }
        Ok(r) => (r, None),
        Err(e) => match e.partial_results() {
            Some(r) => (r.clone(), Some(analysis_error(p, &e))),
            None => return Err(analysis_error(p, &e)),
        },
    };
    drop(bar);
    let req = requested(p, &analysis.outputs);
    let tables = tables(&results, &req);
    let summary = Summary {
        name: p.loaded.name.clone(),
        steps: results.len(),
        noun: ["step", "steps"],
        iterations: results.iterations.iter().sum(),
        max_residual: results.residual.iter().fold(0.0, |a: f64, &b| a.max(b)),
        wall,
        dir: PathBuf::new(),
        files: Vec::new(),
        dynamic: None,
        energy_balance: None,
        peak_efforts: Vec::new(),
        warnings: dropped_row_warnings(p, &results.dropped_rows),
        subdivided_steps: Some(results.subdivided_steps),
        row_reselections: results.row_reselections,
    };
    Ok(Analysed {
        tables,
        summary,
        results,
        dynamic: None,
        failure,
        strict_failure: None,
        files: Vec::new(),
        modes: Vec::new(),
    })
}

/// One warning per joint whose equation was dropped as redundant but not satisfied at the
/// solution (its worst residual in the model's units, relative to the model's size, and when;
/// `cardan_mechanism::analysis::dropped`).
pub(super) fn dropped_row_warnings(p: &Prepared, rows: &[DroppedRowResidual]) -> Vec<String> {
    rows.iter()
        .map(|d| {
            let (unit, factor) = p.units.unit("m");
            let value = match d.dimension {
                Dimension::Dimensionless => format!("{:.2e}", d.value.abs()),
                Dimension::Length => format!("{:.2e} {unit}", d.value.abs() * factor),
                Dimension::Area => format!("{:.2e} {unit}²", d.value.abs() * factor * factor),
            };
            format!(
                "{} was dropped as redundant but is not satisfied: |Φ| = {value} ({:.2e} \
                 relative to the model's size) at worst, at t = {} s; the model's redundant \
                 joints disagree slightly, so the results satisfy the other equations exactly \
                 and this one only approximately (make the joints' geometry consistent, or use \
                 a joint with fewer equations to remove the redundancy)",
                d.equation, d.residual, d.time
            )
        })
        .collect()
}

/// Builds the output groups from the results.
pub fn tables(r: &Results, req: &Requested) -> Vec<Table> {
    let n = r.len();
    let xyz = ["x", "y", "z"];
    let mut out = Vec::new();
    // Histories by name, looked up once per requested element (models of 10⁴ bodies).
    let points: HashMap<(&str, &str), &cardan_mechanism::PointResults> = r
        .points
        .iter()
        .map(|p| ((p.body.as_str(), p.name.as_str()), p))
        .collect();
    let joint_of: HashMap<&str, _> = r.joints.iter().map(|j| (j.name.as_str(), j)).collect();
    let body_of: HashMap<&str, _> = r.bodies.iter().map(|b| (b.name.as_str(), b)).collect();
    let vec_table =
        |name: &str,
         title: &str,
         unit: &str,
         pick: &dyn Fn(&cardan_mechanism::PointResults) -> &Vec<nalgebra::Vector3<f64>>| {
            let mut cols = Vec::new();
            let mut series = Vec::new();
            for (b, pt) in &req.points {
                if let Some(h) = points.get(&(b.as_str(), pt.as_str())) {
                    for (c, ax) in xyz.iter().enumerate() {
                        cols.push(format!("{b}.{pt}.{ax} [{unit}]"));
                        series.push((pick(h), c));
                    }
                }
            }
            let mut t = Table::new(name, title, cols);
            for k in 0..n {
                let mut row = vec![r.times[k]];
                row.extend(
                    series
                        .iter()
                        .map(|(v, c)| v.get(k).map_or(f64::NAN, |x| x[*c])),
                );
                t.rows.push(row);
            }
            t
        };
    if !req.points.is_empty() {
        out.push(vec_table("points", "point positions", "m", &|h| {
            &h.position
        }));
        out.push(vec_table(
            "point_velocities",
            "point velocities",
            "m/s",
            &|h| &h.velocity,
        ));
        out.push(vec_table(
            "point_accelerations",
            "point accelerations",
            "m/s²",
            &|h| &h.acceleration,
        ));
    }
    if !req.joints.is_empty() {
        let joints: Vec<_> = req
            .joints
            .iter()
            .filter_map(|j| joint_of.get(j.as_str()))
            .collect();
        type Pick = fn(&cardan_mechanism::JointResults) -> &Vec<[f64; MAX_COORDINATES]>;
        let groups: [(&str, &str, &str, Pick); 3] = [
            ("joints", "joint coordinates", "", |h| &h.values),
            ("joint_velocities", "joint coordinate rates", "/s", |h| {
                &h.rates
            }),
            (
                "joint_accelerations",
                "joint coordinate accelerations",
                "/s²",
                |h| &h.accelerations,
            ),
        ];
        for (name, title, per, pick) in groups {
            let mut cols = Vec::new();
            let mut src = Vec::new();
            for h in &joints {
                for (q, c) in h.coordinates.iter().enumerate() {
                    let unit = c.measure.quantity().unit();
                    cols.push(format!("{}.{} [{unit}{per}]", h.name, c.name));
                    src.push((pick(h), q));
                }
            }
            let mut t = Table::new(name, title, cols);
            for k in 0..n {
                let mut row = vec![r.times[k]];
                row.extend(
                    src.iter()
                        .map(|(v, q)| v.get(k).map_or(f64::NAN, |v| v[*q])),
                );
                t.rows.push(row);
            }
            out.push(t);
        }
    }
    if !req.bodies.is_empty() {
        let bodies: Vec<_> = req
            .bodies
            .iter()
            .filter_map(|b| body_of.get(b.as_str()))
            .collect();
        let mut cols = Vec::new();
        for b in &bodies {
            for ax in xyz {
                cols.push(format!("{}.r.{ax} [m]", b.name));
            }
            for e in ["e0", "e1", "e2", "e3"] {
                cols.push(format!("{}.p.{e} [-]", b.name));
            }
        }
        let mut t = Table::new("bodies", "body poses (r, Euler parameters p)", cols);
        for k in 0..n {
            let mut row = vec![r.times[k]];
            for b in &bodies {
                row.extend((0..3).map(|c| b.r.get(k).map_or(f64::NAN, |v| v[c])));
                row.extend((0..4).map(|c| b.p.get(k).map_or(f64::NAN, |v| v[c])));
            }
            t.rows.push(row);
        }
        out.push(t);
        for (name, title, u1, u2, first, second) in [
            (
                "body_velocities",
                "body velocities (ṙ, ω global)",
                "m/s",
                "rad/s",
                "r_dot",
                "omega",
            ),
            (
                "body_accelerations",
                "body accelerations (r̈, ω̇ global)",
                "m/s²",
                "rad/s²",
                "r_ddot",
                "omega_dot",
            ),
        ] {
            let mut cols = Vec::new();
            for b in &bodies {
                for ax in xyz {
                    cols.push(format!("{}.{first}.{ax} [{u1}]", b.name));
                }
                for ax in xyz {
                    cols.push(format!("{}.{second}.{ax} [{u2}]", b.name));
                }
            }
            let mut t = Table::new(name, title, cols);
            for k in 0..n {
                let mut row = vec![r.times[k]];
                for b in &bodies {
                    let (a, w) = if first == "r_dot" {
                        (&b.r_dot, &b.omega)
                    } else {
                        (&b.r_ddot, &b.omega_dot)
                    };
                    row.extend((0..3).map(|c| a.get(k).map_or(f64::NAN, |v| v[c])));
                    row.extend((0..3).map(|c| w.get(k).map_or(f64::NAN, |v| v[c])));
                }
                t.rows.push(row);
            }
            out.push(t);
        }
    }
    let mut t = Table::new(
        "residual",
        "constraint residual",
        vec!["max |Φ| [m or -]".into(), "newton_iterations [-]".into()],
    );
    for k in 0..n {
        t.rows.push(vec![
            r.times[k],
            r.residual.get(k).copied().unwrap_or(f64::NAN),
            r.iterations.get(k).map_or(f64::NAN, |&i| i as f64),
        ]);
    }
    out.push(t);
    out
}
