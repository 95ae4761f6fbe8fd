//! The kinematic output groups as a layout: each table's name, title, columns and, for every
//! column, where its value is in a [`Results`] ([`Source`]). Built once per run, it fills a row
//! for any stored time, so the whole-run tables ([`Layout::tables`]) and the rows a streamed run
//! writes frame by frame ([`Layout::row`]) come from one code path and hold the same numbers.

use crate::build::Outputs as Requested;
use crate::table::Table;
use cardan_mechanism::{JointResults, PointResults, Results};
use nalgebra::Vector3;
use std::collections::HashMap;

/// A body history holding 3-vectors.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum BodyVec {
    R,
    RDot,
    Omega,
    RDdot,
    OmegaDot,
}

/// Where a column's value is, for the frame at index k.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Source {
    /// `points[i]`: position (0), velocity (1) or acceleration (2), component c.
    Point { i: usize, which: u8, c: usize },
    /// `joints[i]`: values (0), rates (1) or accelerations (2), coordinate q.
    Joint { i: usize, which: u8, q: usize },
    /// `curves[i]`: the curve parameter u (0), u̇ (1) or ü (2).
    Curve { i: usize, which: u8 },
    /// `curves[i]` of a cam pair: its contact point's component c (0–2), or the pressure angle
    /// (c = 3).
    Cam { i: usize, c: usize },
    /// `bodies[i]`, a 3-vector history, component c.
    Body { i: usize, vec: BodyVec, c: usize },
    /// `bodies[i].p`, component c.
    Euler { i: usize, c: usize },
    /// The position residual.
    Residual,
    /// The Newton iterations.
    Iterations,
}

fn component(v: &[Vector3<f64>], k: usize, c: usize) -> f64 {
    v.get(k).map_or(f64::NAN, |x| x[c])
}

impl Source {
    /// The value at frame k of `r` (NaN where the history has no such frame).
    fn value(self, r: &Results, k: usize) -> f64 {
        match self {
            Source::Point { i, which, c } => {
                let p = &r.points[i];
                let v = match which {
                    0 => &p.position,
                    1 => &p.velocity,
                    _ => &p.acceleration,
                };
                component(v, k, c)
            }
            Source::Joint { i, which, q } => {
                let j = &r.joints[i];
                let v = match which {
                    0 => &j.values,
                    1 => &j.rates,
                    _ => &j.accelerations,
                };
                v.get(k).map_or(f64::NAN, |v| v[q])
            }
            Source::Curve { i, which } => {
                let c = &r.curves[i];
                let v = match which {
                    0 => &c.u,
                    1 => &c.u_dot,
                    _ => &c.u_ddot,
                };
                v.get(k).copied().unwrap_or(f64::NAN)
            }
            Source::Cam { i, c: 3 } => {
                (r.curves[i].pressure_angle.get(k).copied()).unwrap_or(f64::NAN)
            }
            Source::Cam { i, c } => component(&r.curves[i].contact, k, c),
            Source::Body { i, vec, c } => {
                let b = &r.bodies[i];
                let v = match vec {
                    BodyVec::R => &b.r,
                    BodyVec::RDot => &b.r_dot,
                    BodyVec::Omega => &b.omega,
                    BodyVec::RDdot => &b.r_ddot,
                    BodyVec::OmegaDot => &b.omega_dot,
                };
                component(v, k, c)
            }
            Source::Euler { i, c } => r.bodies[i].p.get(k).map_or(f64::NAN, |v| v[c]),
            Source::Residual => r.residual.get(k).copied().unwrap_or(f64::NAN),
            Source::Iterations => r.iterations.get(k).map_or(f64::NAN, |&i| i as f64),
        }
    }
}

/// One output group: its empty table (name, title, columns) and its columns' sources.
#[derive(Debug, Clone)]
struct Group {
    table: Table,
    sources: Vec<Source>,
}

impl Group {
    fn new(name: &str, title: &str) -> Self {
        Self {
            table: Table::new(name, title, Vec::new()),
            sources: Vec::new(),
        }
    }

    fn column(&mut self, header: String, source: Source) {
        self.table.columns.push(header);
        self.sources.push(source);
    }
}

/// The kinematic output groups of a run (module docs).
#[derive(Debug, Clone)]
pub struct Layout {
    groups: Vec<Group>,
}

const XYZ: [&str; 3] = ["x", "y", "z"];

/// The header `a.b.c [unit]` of a column: its dotted `parts`, then the pieces of its unit. Built
/// directly rather than through `format!`: a large model's tables have 10⁵ columns.
fn header(parts: &[&str], unit: &[&str]) -> String {
    let len: usize = parts.iter().chain(unit).map(|p| p.len() + 1).sum();
    let mut s = String::with_capacity(len + 2);
    for (k, p) in parts.iter().enumerate() {
        if k > 0 {
            s.push('.');
        }
        s.push_str(p);
    }
    s.push_str(" [");
    unit.iter().for_each(|u| s.push_str(u));
    s.push(']');
    s
}

impl Layout {
    /// The groups `req` asks for, with the histories of `r` (any number of frames: only the
    /// names are read).
    pub fn new(r: &Results, req: &Requested) -> Self {
        let mut groups = Vec::new();
        if !req.points.is_empty() {
            point_groups(r, req, &mut groups);
        }
        if !req.joints.is_empty() {
            joint_groups(r, req, &mut groups);
            cam_group(r, req, &mut groups);
        }
        if !req.bodies.is_empty() {
            body_groups(r, req, &mut groups);
        }
        let mut g = Group::new("residual", "constraint residual");
        g.column("max |Φ| [m or -]".into(), Source::Residual);
        g.column("newton_iterations [-]".into(), Source::Iterations);
        groups.push(g);
        Self { groups }
    }

    /// The number of groups.
    pub fn groups(&self) -> usize {
        self.groups.len()
    }

    /// Group `g`'s table without rows.
    pub fn empty_table(&self, g: usize) -> &Table {
        &self.groups[g].table
    }

    /// The tables without rows, in output order.
    pub fn into_empty_tables(self) -> Vec<Table> {
        self.groups.into_iter().map(|g| g.table).collect()
    }

    /// Fills `row` with the row of group `g` at frame k of `r`: the time, then each column.
    pub fn row(&self, g: usize, r: &Results, k: usize, row: &mut Vec<f64>) {
        row.clear();
        row.push(r.times[k]);
        row.extend(self.groups[g].sources.iter().map(|s| s.value(r, k)));
    }
}

/// Point positions, velocities and accelerations of the requested points.
fn point_groups(r: &Results, req: &Requested, groups: &mut Vec<Group>) {
    // Histories by name, looked up once per requested element (models of 10⁴ bodies).
    let index: HashMap<(&str, &str), usize> = (r.points.iter().enumerate())
        .map(|(i, p): (usize, &PointResults)| ((p.body.as_str(), p.name.as_str()), i))
        .collect();
    let kinds = [
        ("points", "point positions", "m"),
        ("point_velocities", "point velocities", "m/s"),
        ("point_accelerations", "point accelerations", "m/s²"),
    ];
    for (which, (name, title, unit)) in kinds.into_iter().enumerate() {
        let mut g = Group::new(name, title);
        for (b, pt) in &req.points {
            if let Some(&i) = index.get(&(b.as_str(), pt.as_str())) {
                for (c, ax) in XYZ.iter().enumerate() {
                    let which = which as u8;
                    g.column(header(&[b, pt, ax], &[unit]), Source::Point { i, which, c });
                }
            }
        }
        groups.push(g);
    }
}

/// Joint coordinates, rates and accelerations of the requested joints.
fn joint_groups(r: &Results, req: &Requested, groups: &mut Vec<Group>) {
    let index: HashMap<&str, usize> = (r.joints.iter().enumerate())
        .map(|(i, j): (usize, &JointResults)| (j.name.as_str(), i))
        .collect();
    // Each curve element's first parameter, u (a cam pair's w follows it).
    let curves: HashMap<&str, usize> = (r.curves.iter().enumerate())
        .filter(|(_, c)| c.parameter == "u")
        .map(|(i, c)| (c.name.as_str(), i))
        .collect();
    // A requested name is a joint (its coordinates) or a curve (its parameter u).
    let entries: Vec<Result<usize, usize>> = (req.joints.iter())
        .filter_map(|j| {
            let j = j.as_str();
            (index.get(j).copied().map(Ok)).or_else(|| curves.get(j).copied().map(Err))
        })
        .collect();
    let kinds = [
        ("joints", "joint coordinates", ""),
        ("joint_velocities", "joint coordinate rates", "/s"),
        (
            "joint_accelerations",
            "joint coordinate accelerations",
            "/s²",
        ),
    ];
    for (which, (name, title, per)) in kinds.into_iter().enumerate() {
        let mut g = Group::new(name, title);
        for &e in &entries {
            let i = match e {
                Ok(i) => i,
                Err(i) => {
                    // Every parameter of the curve element (u; u and w of a cam pair).
                    let name = r.curves[i].name.as_str();
                    let all = (i..r.curves.len()).take_while(|&k| r.curves[k].name == name);
                    for i in all {
                        let (which, p) = (which as u8, r.curves[i].parameter);
                        g.column(header(&[name, p], &["m", per]), Source::Curve { i, which });
                    }
                    continue;
                }
            };
            let h = &r.joints[i];
            for (q, c) in h.coordinates.iter().enumerate() {
                let unit = c.measure.quantity().unit();
                let which = which as u8;
                g.column(
                    header(&[&h.name, c.name], &[unit, per]),
                    Source::Joint { i, which, q },
                );
            }
        }
        groups.push(g);
    }
}

/// The requested cam pairs' contact points and, with velocities, pressure angles: the `cams`
/// group, written when `joints` lists a cam.
fn cam_group(r: &Results, req: &Requested, groups: &mut Vec<Group>) {
    let cams: Vec<usize> = (req.joints.iter())
        .filter_map(|j| (r.curves.iter()).position(|c| &c.name == j && c.cam))
        .collect();
    if cams.is_empty() {
        return;
    }
    let angle = r.outputs.is_none_or(|o| o.needs_velocity());
    let mut g = Group::new("cams", "cam contact points and pressure angles");
    for &i in &cams {
        let name = r.curves[i].name.as_str();
        for (c, ax) in XYZ.iter().enumerate() {
            g.column(header(&[name, "contact", ax], &["m"]), Source::Cam { i, c });
        }
        if angle {
            g.column(
                header(&[name, "pressure_angle"], &["rad"]),
                Source::Cam { i, c: 3 },
            );
        }
    }
    groups.push(g);
}

/// Body poses, velocities and accelerations of the requested bodies.
fn body_groups(r: &Results, req: &Requested, groups: &mut Vec<Group>) {
    let index: HashMap<&str, usize> = (r.bodies.iter().enumerate())
        .map(|(i, b)| (b.name.as_str(), i))
        .collect();
    let bodies: Vec<usize> = (req.bodies.iter())
        .filter_map(|b| index.get(b.as_str()).copied())
        .collect();
    let mut g = Group::new("bodies", "body poses (r, Euler parameters p)");
    for &i in &bodies {
        let name = &r.bodies[i].name;
        for (c, ax) in XYZ.iter().enumerate() {
            let vec = BodyVec::R;
            g.column(header(&[name, "r", ax], &["m"]), Source::Body { i, vec, c });
        }
        for (c, e) in ["e0", "e1", "e2", "e3"].iter().enumerate() {
            g.column(header(&[name, "p", e], &["-"]), Source::Euler { i, c });
        }
    }
    groups.push(g);
    let kinds = [
        (
            "body_velocities",
            "body velocities (ṙ, ω global)",
            ("r_dot", "m/s", BodyVec::RDot),
            ("omega", "rad/s", BodyVec::Omega),
        ),
        (
            "body_accelerations",
            "body accelerations (r̈, ω̇ global)",
            ("r_ddot", "m/s²", BodyVec::RDdot),
            ("omega_dot", "rad/s²", BodyVec::OmegaDot),
        ),
    ];
    for (name, title, first, second) in kinds {
        let mut g = Group::new(name, title);
        for &i in &bodies {
            let body = &r.bodies[i].name;
            for (label, unit, vec) in [first, second] {
                for (c, ax) in XYZ.iter().enumerate() {
                    g.column(
                        header(&[body, label, ax], &[unit]),
                        Source::Body { i, vec, c },
                    );
                }
            }
        }
        groups.push(g);
    }
}
