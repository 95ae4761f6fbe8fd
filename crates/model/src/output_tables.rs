//! Output shared by the subcommands: the aligned text tables of `cardan check` and
//! `cardan eval` with their compact number format, the error of a failed write to standard
//! output (also for the summary line of `cardan run`), and what the analyses of `cardan run`
//! share for their output groups: the outputs to write (`requested`), the unit of a joint
//! coordinate, and the driver efforts and joint reactions of the dynamic and inverse dynamics
//! runs (their tables and peak values).

use crate::build::Outputs as Requested;
use crate::diag::Error;
use crate::prepare::Prepared;
use crate::table::Table;
use cardan_dynamics::DynamicResults;
use std::io::Write;

/// Writes an aligned text table.
pub fn write_table(
    out: &mut dyn Write,
    headers: &[&str],
    rows: &[Vec<String>],
) -> std::io::Result<()> {
    let n = headers.len();
    let mut w: Vec<usize> = headers.iter().map(|h| h.chars().count()).collect();
    for r in rows {
        for (k, c) in r.iter().enumerate().take(n) {
            w[k] = w[k].max(c.chars().count());
        }
    }
    let line = |cells: Vec<&str>| {
        let mut s = String::from("  ");
        for (k, c) in cells.iter().enumerate() {
            s.push_str(c);
            if k + 1 < cells.len() {
                s.push_str(&" ".repeat(w[k] - c.chars().count() + 2));
            }
        }
        s
    };
    writeln!(out, "{}", line(headers.to_vec()))?;
    for r in rows {
        writeln!(out, "{}", line(r.iter().map(String::as_str).collect()))?;
    }
    Ok(())
}

/// An error writing a report to standard output (a closed pipe is not an error of the run).
pub fn io(e: std::io::Error) -> Error {
    if e.kind() == std::io::ErrorKind::BrokenPipe {
        // The reader went away (`cardan eval m.toml | head`): not an error worth a message.
        return Error {
            kind: crate::diag::ErrorKind::BrokenPipe,
            location: None,
            message: String::new(),
        };
    }
    Error::output(format!("cannot write to standard output: {e}"))
}

/// Formats a number compactly.
pub fn g(v: f64) -> String {
    if v == 0.0 {
        "0".into()
    } else if (1e-3..1e5).contains(&v.abs()) {
        let s = format!("{v:.6}");
        let s = s.trim_end_matches('0').trim_end_matches('.');
        s.to_string()
    } else {
        format!("{v:.4e}")
    }
}

/// Per driver: name, largest |effort| over the run, unit.
pub(super) fn peak_efforts(
    p: &Prepared,
    r: &cardan_dynamics::DynamicResults,
) -> Vec<(String, f64, &'static str)> {
    let mut peaks = vec![0.0; r.drivers.len()];
    fold_peak_efforts(r, &mut peaks);
    peak_efforts_of(p, r, &peaks)
}

/// Takes the largest |effort| of each driver over the times of `r` into `peaks`.
pub(super) fn fold_peak_efforts(r: &DynamicResults, peaks: &mut [f64]) {
    for (peak, d) in peaks.iter_mut().zip(&r.drivers) {
        *peak = d.effort.iter().fold(*peak, |a, e| a.max(e.abs()));
    }
}

/// Per driver of `r`: name, its peak |effort| from `peaks` ([`fold_peak_efforts`] over every
/// time of the run), unit.
pub(super) fn peak_efforts_of(
    p: &Prepared,
    r: &DynamicResults,
    peaks: &[f64],
) -> Vec<(String, f64, &'static str)> {
    (r.drivers.iter())
        .zip(peaks)
        .map(|(d, &peak)| (d.name.clone(), peak, effort_kind(p, &d.name).1))
        .collect()
}

/// The outputs to write: as requested, or every point, joint and body when `[analysis.outputs]`
/// lists none of the three groups (an empty list is a choice: `bodies = []` alone writes the
/// efforts of an inverse dynamics run and no pose table).
pub(super) fn requested(p: &Prepared, req: &Requested) -> Requested {
    if req.listed || !req.points.is_empty() || !req.joints.is_empty() || !req.bodies.is_empty() {
        return req.clone();
    }
    let m = &p.model;
    Requested {
        points: m
            .points()
            .iter()
            .filter(|f| f.body_name != cardan_mechanism::GROUND)
            .map(|f| (f.body_name.clone(), f.name.clone()))
            .collect(),
        joints: m.joints().iter().map(|j| j.name.clone()).collect(),
        bodies: m.bodies().iter().map(|b| b.name.clone()).collect(),
        listed: true,
        reactions: req.reactions.clone(),
        energy: req.energy,
        joint_space: req.joint_space,
        jacobians: req.jacobians.clone(),
    }
}

/// What the analysis computes at each output time for the outputs `req` (as [`requested`]
/// gives them): the point and joint histories only when a point or a joint is written (a run
/// asking for bodies and efforts alone computes neither).
pub(super) fn computed(req: &Requested) -> cardan_mechanism::Outputs {
    cardan_mechanism::Outputs {
        points: !req.points.is_empty(),
        joints: !req.joints.is_empty(),
        ..cardan_mechanism::Outputs::default()
    }
}

/// What a driver exerts and its unit: a torque (N m) for a rotation driver and a general
/// motion's angle rows (the torque on body j about P_j, frame-i components), else a force (N).
pub fn effort_kind(p: &Prepared, driver: &str) -> (&'static str, &'static str) {
    use cardan_constraints::Driver;
    match p
        .model
        .drivers()
        .iter()
        .find(|d| d.name == driver)
        .map(|d| &d.driver)
    {
        Some(Driver::Rotation(_)) => ("torque", "N m"),
        Some(Driver::Pose(pose)) if pose.row >= 3 => ("torque", "N m"),
        _ => ("force", "N"),
    }
}

/// `driver_efforts`: per driver, the generalized force it applies along its driven coordinate
/// (−λ ∂Φ/∂c; positive in the sense of increasing coordinate): `motor.torque [N m]` for a rotation
/// driver (about the joint axis, on body j), `name.force [N]` for the others. `None` without
/// drivers.
pub fn driver_efforts_table(p: &Prepared, r: &DynamicResults) -> Option<Table> {
    if r.drivers.is_empty() {
        return None;
    }
    let cols = r
        .drivers
        .iter()
        .map(|d| {
            let (what, unit) = effort_kind(p, &d.name);
            format!("{}.{what} [{unit}]", d.name)
        })
        .collect();
    let mut t = Table::new(
        "driver_efforts",
        "driver efforts (positive along the driven coordinate)",
        cols,
    );
    for (k, time) in r.times().iter().enumerate() {
        let mut row = vec![*time];
        driver_efforts_row(r, k, &mut row);
        t.rows.push(row);
    }
    Some(t)
}

/// Appends the driver efforts at time k to `row`.
pub(super) fn driver_efforts_row(r: &DynamicResults, k: usize, row: &mut Vec<f64>) {
    row.extend(
        r.drivers
            .iter()
            .map(|d| d.effort.get(k).copied().unwrap_or(f64::NAN)),
    );
}

/// `coupler_efforts`: per coupler, the generalized force it applies along each coupled joint
/// coordinate, `mesh.j1.torque [N m]` on an angle, `teeth.slide.force [N]` on a slide (−λ a_k,
/// positive along the coordinate), then its tooth force `mesh.tooth_force [N]` (a gear given by
/// radii: tangential, at gear j's pitch circle; a rack: along the rack) or thread force
/// `thread.axial_force [N]` (a screw: along the slide). `None` without couplers.
pub fn coupler_efforts_table(p: &Prepared, r: &DynamicResults) -> Option<Table> {
    if r.couplers.is_empty() {
        return None;
    }
    let model = &p.model;
    let mut cols = Vec::new();
    for (c, info) in r.couplers.iter().zip(model.couplers()) {
        for q in info.coordinates {
            let joint = &model.joints()[q.joint].name;
            let (what, unit) = if q.slide {
                ("force", "N")
            } else {
                ("torque", "N m")
            };
            cols.push(format!("{}.{joint}.{what} [{unit}]", c.name));
        }
        if c.force.is_some() {
            let what = if info.kind() == "screw" {
                "axial_force"
            } else {
                "tooth_force"
            };
            cols.push(format!("{}.{what} [N]", c.name));
        }
    }
    let mut t = Table::new(
        "coupler_efforts",
        "coupler efforts (positive along the coupled coordinates) and tooth or thread forces",
        cols,
    );
    for (k, time) in r.times().iter().enumerate() {
        let mut row = vec![*time];
        coupler_efforts_row(r, k, &mut row);
        t.rows.push(row);
    }
    Some(t)
}

/// Appends the coupler efforts (and tooth or thread forces) at time k to `row`.
pub(super) fn coupler_efforts_row(r: &DynamicResults, k: usize, row: &mut Vec<f64>) {
    for c in &r.couplers {
        let q = c.efforts.get(k).copied().unwrap_or([f64::NAN; 2]);
        row.extend(q);
        if let Some(f) = &c.force {
            row.push(f.get(k).copied().unwrap_or(f64::NAN));
        }
    }
}

/// The cam pairs' contact forces on their followers (global components, and the component
/// along the direction a pressing contact pushes: negative where the follower would lift off);
/// `None` without cam pairs.
pub fn cam_forces_table(r: &DynamicResults) -> Option<Table> {
    if r.cams.is_empty() {
        return None;
    }
    let mut cols = Vec::new();
    for c in &r.cams {
        for ax in ["x", "y", "z"] {
            cols.push(format!("{}.force.{ax} [N]", c.name));
        }
        cols.push(format!("{}.normal_force [N]", c.name));
    }
    let mut t = Table::new(
        "cam_forces",
        "cam contact forces on the followers (normal_force < 0: the contact pulls, the follower would lift off)",
        cols,
    );
    for (k, time) in r.times().iter().enumerate() {
        let mut row = vec![*time];
        cam_forces_row(r, k, &mut row);
        t.rows.push(row);
    }
    Some(t)
}

/// Appends the cam contact forces at time k to `row`.
pub(super) fn cam_forces_row(r: &DynamicResults, k: usize, row: &mut Vec<f64>) {
    for c in &r.cams {
        let f = c.force.get(k).map_or([f64::NAN; 3], |f| [f.x, f.y, f.z]);
        row.extend(f);
        row.push(c.normal_force.get(k).copied().unwrap_or(f64::NAN));
    }
}

/// A reaction history of a [`DynamicResults`]: a joint's or a coupler's.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum ReactionRef {
    /// `reactions[i]`.
    Joint(usize),
    /// `couplers[i].reactions`.
    Coupler(usize),
}

impl ReactionRef {
    fn of(self, r: &DynamicResults) -> &cardan_dynamics::JointReactions {
        match self {
            ReactionRef::Joint(i) => &r.reactions[i],
            ReactionRef::Coupler(i) => &r.couplers[i].reactions,
        }
    }
}

/// The reaction histories the reaction tables hold: the requested joints or couplers (default
/// all joints, then all couplers).
pub(super) fn reaction_selection(r: &DynamicResults, req: &Requested) -> Vec<ReactionRef> {
    match &req.reactions {
        Some(list) => list
            .iter()
            .filter_map(|j| {
                (r.reactions.iter().position(|x| x.name == *j))
                    .map(ReactionRef::Joint)
                    .or_else(|| {
                        (r.couplers.iter().position(|c| c.name == *j)).map(ReactionRef::Coupler)
                    })
            })
            .collect(),
        None => (0..r.reactions.len())
            .map(ReactionRef::Joint)
            .chain((0..r.couplers.len()).map(ReactionRef::Coupler))
            .collect(),
    }
}

/// Appends the reactions of the `selected` histories at time k to `row` (body components if
/// `local`).
pub(super) fn reactions_row(
    r: &DynamicResults,
    selected: &[ReactionRef],
    local: bool,
    k: usize,
    row: &mut Vec<f64>,
) {
    for j in selected {
        let j = j.of(r);
        for side in [&j.on_i, &j.on_j] {
            let rc = side.get(k).copied().unwrap_or_default();
            let (f, m) = if local {
                (rc.force_local, rc.torque_local)
            } else {
                (rc.force, rc.torque)
            };
            row.extend(f.iter().copied());
            row.extend(m.iter().copied());
        }
    }
}

/// `reactions` and `reactions_local`: per requested joint or coupler (default all joints, then
/// all couplers) and per body, the reaction force and its torque about the joint point (a
/// coupler's marker point on each body).
pub fn reaction_tables(r: &DynamicResults, req: &Requested) -> Vec<Table> {
    let mut out = Vec::new();
    let times = r.times();
    let n = times.len();
    let selected = reaction_selection(r, req);
    let joints: Vec<&cardan_dynamics::JointReactions> = selected.iter().map(|j| j.of(r)).collect();
    let xyz = ["x", "y", "z"];
    for (name, title, local) in [
        ("reactions", "joint reactions (global components)", false),
        ("reactions_local", "joint reactions (body components)", true),
    ] {
        if joints.is_empty() {
            break;
        }
        let mut cols = Vec::new();
        // The torque's reference point is in its header: `joint.body.T@point.x`.
        for j in &joints {
            for (body, point) in [(&j.body_i, &j.point_i), (&j.body_j, &j.point_j)] {
                for (q, u) in [("F".to_string(), "N"), (format!("T@{point}"), "N m")] {
                    for ax in xyz {
                        cols.push(format!("{}.{body}.{q}.{ax} [{u}]", j.name));
                    }
                }
            }
        }
        let mut t = Table::new(name, title, cols);
        for k in 0..n {
            let mut row = vec![times[k]];
            reactions_row(r, &selected, local, k, &mut row);
            t.rows.push(row);
        }
        out.push(t);
    }
    out
}

/// `energy`: kinetic and potential energy, their sum and its drift E − E(t₀); then, per driver
/// and non-conservative force element (damper, actuator, point force or torque), its power
/// `name.P [W]` (positive into the mechanism) and work `name.W [J]`; their sum `W_nc [J]`; the
/// balance E − E(t₀) − W_nc `balance [J]` (the integration error, [`cardan_dynamics::work`]); and
/// the power of the joints' reactions `P_joints [W]` (0 up to the velocity drift: a check).
pub fn energy_table(r: &DynamicResults) -> Table {
    let e = &r.energy;
    let mut cols: Vec<String> = [
        "kinetic [J]",
        "potential_gravity [J]",
        "potential_spring [J]",
        "total [J]",
        "drift [J]",
    ]
    .map(String::from)
    .to_vec();
    for w in &e.elements {
        cols.push(format!("{}.P [W]", w.name));
        cols.push(format!("{}.W [J]", w.name));
    }
    cols.extend(["W_nc [J]", "balance [J]", "P_joints [W]"].map(String::from));
    let mut t = Table::new("energy", "energy", cols);
    let e0 = e.total.first().copied().unwrap_or(0.0);
    for (k, time) in r.times().iter().enumerate() {
        let mut row = vec![*time];
        energy_row(e, e0, k, &mut row);
        t.rows.push(row);
    }
    t
}

/// Appends the energy row at time k to `row`, `e0` the total energy at the run's first time
/// (the drift E − E(t₀) and the balance E − E(t₀) − W_nc of
/// [`cardan_dynamics::EnergyHistory::drift`] and [`balance`](cardan_dynamics::EnergyHistory::balance)).
pub(super) fn energy_row(
    e: &cardan_dynamics::EnergyHistory,
    e0: f64,
    k: usize,
    row: &mut Vec<f64>,
) {
    let g = |v: &[f64]| v.get(k).copied().unwrap_or(f64::NAN);
    // As EnergyHistory::drift and ::balance: the same operations, the same numbers.
    let (drift, balance) = match (e.total.get(k), e.work.get(k)) {
        (Some(&t), Some(&w)) => (t - e0, t - e0 - w),
        (Some(&t), None) => (t - e0, f64::NAN),
        _ => (f64::NAN, f64::NAN),
    };
    row.extend([
        g(&e.kinetic),
        g(&e.gravity),
        g(&e.spring),
        g(&e.total),
        drift,
    ]);
    for w in &e.elements {
        row.push(g(&w.power));
        row.push(g(&w.work));
    }
    row.extend([g(&e.work), balance, g(&e.constraint_power)]);
}
