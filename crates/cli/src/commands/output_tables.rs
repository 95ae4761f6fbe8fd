//! Output shared by the subcommands: the aligned text tables of `cardan check` and
//! `cardan eval` with their compact number format, the error of a failed write to standard
//! output (also for the summary line of `cardan run`), and what the analyses of `cardan run`
//! share for their output groups: the outputs to write ([`requested`]), the unit of a joint
//! coordinate, the peak driver efforts.

use super::Prepared;
use crate::build::Outputs as Requested;
use crate::diag::Error;
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

pub(crate) fn io(e: std::io::Error) -> Error {
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
    r.drivers
        .iter()
        .map(|d| {
            let peak = d.effort.iter().fold(0.0f64, |a, e| a.max(e.abs()));
            (
                d.name.clone(),
                peak,
                crate::dynamic::effort_kind(p, &d.name).1,
            )
        })
        .collect()
}

/// The outputs to write: as requested, or everything when the file has no `[analysis.outputs]`.
pub(super) fn requested(p: &Prepared, req: &Requested) -> Requested {
    if !req.points.is_empty() || !req.joints.is_empty() || !req.bodies.is_empty() {
        return req.clone();
    }
    let _ = &req.reactions;
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
        reactions: req.reactions.clone(),
        energy: req.energy,
    }
}

/// The unit of a joint coordinate, from its name.
pub(super) fn joint_unit(name: &str) -> &'static str {
    if name.starts_with("angle") {
        "rad"
    } else {
        "m"
    }
}
