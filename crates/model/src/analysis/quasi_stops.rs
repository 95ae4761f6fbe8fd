//! `kind = "quasi_static"` of a model with end stops (`[[limit]]`): the path in segments, each
//! with the stops its first equilibrium rests on held ([`super::resting::resting`]: the
//! active-set iteration of a static analysis at that time). Where an equilibrium of a segment
//! passes an open stop or a held stop would pull ([`super::resting::set_change`]), the segment
//! ends before it and the next one starts there with the set found again. The segments' tables
//! are joined column by column: a stop's reaction column (`<limit>.<end>.torque` or `.force`
//! in `driver_efforts.csv`) holds 0 where the stop is open, which is its reaction there.

use super::located::located_as;
use super::setup::dynamics_as;
use super::statics::{
    equilibria_summary, equilibrium_tables, equilibrium_warnings, static_options, Work,
};
use super::summary::Analysed;
use crate::build::{Analysis, StaticKind};
use crate::diag::Error;
use crate::output_tables::{peak_efforts, requested};
use crate::prepare::Prepared;
use crate::table::Table;
use cardan_dynamics::{DynamicsError, StaticOptions, StaticResults};
use std::time::Instant;

const WHAT: &str = "quasi-static analysis";

/// More segments than this (the set changing at nearly every time: a path along a stop's
/// bound, or an equilibrium that alternates) end the path with a warning.
const MAX_SEGMENTS: usize = 64;

/// The path: its segments, notes about it (warnings), and a failure after the first segment.
struct Path {
    segments: Vec<Segment>,
    notes: Vec<String>,
    failure: Option<Error>,
}

/// One segment: the model with its held stops (`None`: the file's, nothing held) and its
/// equilibria.
struct Segment {
    held: Option<Prepared>,
    statics: StaticResults,
}

/// Runs the quasi-static analysis of a model with limits, in segments (module docs).
///
/// # Errors
/// The first equilibrium's errors; a later failure ends the path with the equilibria so far.
pub(super) fn run(p: &Prepared, analysis: &Analysis) -> Result<Analysed, Error> {
    let start = Instant::now();
    let times = analysis.times();
    let Path {
        segments,
        notes: changes,
        failure,
    } = segments(p, analysis, &times)?;
    let wall = start.elapsed();
    let req = requested(p, &analysis.outputs);
    let mut tables: Vec<Table> = Vec::new();
    let mut warnings = Vec::new();
    let mut kinematics: Option<cardan_mechanism::Results> = None;
    let mut work = Work {
        iterations: 0,
        row_reselections: 0,
        wall,
    };
    let mut peaks = Vec::new();
    for seg in &segments {
        let q = seg.held.as_ref().unwrap_or(p);
        let r = &seg.statics.results;
        join(&mut tables, equilibrium_tables(q, &seg.statics, &req));
        warnings.extend(equilibrium_warnings(q, &seg.statics));
        match &mut kinematics {
            Some(k) => k.extend_from(&r.kinematics),
            None => kinematics = Some(r.kinematics.clone()),
        }
        work.iterations += (seg.statics.equilibria.iter())
            .map(|e| e.iterations)
            .sum::<usize>();
        work.row_reselections += r.stats.row_reselections;
        take_peaks(&mut peaks, peak_efforts(q, r));
    }
    warnings.extend(changes);
    let k = kinematics.unwrap_or_default();
    let summary = equilibria_summary(p, &k, work, peaks, warnings);
    Ok(Analysed {
        tables,
        summary,
        results: k,
        // The segments' results have different drivers (each holds its own stops): no one
        // set of dynamic results stands for the path; its tables and kinematics are joined.
        dynamic: None,
        failure,
        strict_failure: None,
        files: Vec::new(),
        modes: Vec::new(),
        events: Vec::new(),
        streamed: None,
    })
}

/// The segments of the path over `times`, the set changes as notes, and a failure after the
/// first segment.
fn segments(p: &Prepared, analysis: &Analysis, times: &[f64]) -> Result<Path, Error> {
    let equilibrium = |q: &Prepared, o: &StaticOptions| {
        let mut d = dynamics_as(q, WHAT)?;
        d.statics(o).map_err(|e| located_as(q, &e, WHAT))
    };
    let (mut segments, mut notes) = (Vec::new(), Vec::new());
    let mut k0 = 0;
    while k0 < times.len() {
        let options = StaticOptions {
            time: times[k0],
            ..static_options(analysis)
        };
        let outcome = super::resting::resting(p, &options, equilibrium).and_then(|held| {
            let q = held.as_ref().unwrap_or(p);
            let r = path(q, &times[k0..], &options)?;
            Ok((held, r))
        });
        let (held, statics) = match outcome {
            Ok(x) => x,
            Err(e) if segments.is_empty() => return Err(e),
            Err(e) => {
                return Ok(Path {
                    segments,
                    notes,
                    failure: Some(e),
                })
            }
        };
        let q = held.as_ref().unwrap_or(p);
        let change = super::resting::set_change(q, &statics.results);
        match change {
            Some((k, _)) if k > 0 && segments.len() < MAX_SEGMENTS => {
                // The segment up to the change, solved again over its own times.
                let statics = path(q, &times[k0..k0 + k], &options)?;
                segments.push(Segment { held, statics });
                k0 += k;
            }
            Some((_, what)) => {
                // The set changes at the segment's own start, or too often: the path ends
                // here, said.
                let t = times[k0];
                notes.push(format!(
                    "quasi-static analysis: from t = {t} s {what}, and the stops the \
                     equilibrium rests on do not settle along the path ({} segments); the \
                     equilibria from there keep the last set and are not the mechanism's",
                    segments.len() + 1
                ));
                segments.push(Segment { held, statics });
                break;
            }
            None => {
                segments.push(Segment { held, statics });
                break;
            }
        }
    }
    Ok(Path {
        segments,
        notes,
        failure: None,
    })
}

/// The equilibria of `q` over `times`; a failure after the first time ends the segment with
/// the equilibria before it (its error is the run's failure only when nothing was solved).
fn path(q: &Prepared, times: &[f64], options: &StaticOptions) -> Result<StaticResults, Error> {
    let mut d = dynamics_as(q, WHAT)?;
    match d.quasi_statics(times, options) {
        Ok(r) => Ok(r),
        Err(DynamicsError::MidRun { partial, .. }) => Ok(StaticResults {
            results: *partial,
            equilibria: Vec::new(),
        }),
        Err(e) => Err(located_as(q, &e, WHAT)),
    }
}

/// Appends the segment's tables `part` to `tables`, table by table (by name) and column by
/// column (by header): a column a segment lacks is 0 in its rows (a stop open there carries
/// nothing), a column new in a segment is 0 in the rows before.
fn join(tables: &mut Vec<Table>, part: Vec<Table>) {
    for t in part {
        let Some(into) = tables.iter_mut().find(|x| x.name == t.name) else {
            tables.push(t);
            continue;
        };
        for c in &t.columns {
            if !into.columns.contains(c) {
                into.columns.push(c.clone());
                for row in &mut into.rows {
                    row.push(0.0);
                }
            }
        }
        let at: Vec<Option<usize>> = (into.columns.iter())
            .map(|c| t.columns.iter().position(|x| x == c))
            .collect();
        for row in &t.rows {
            let mut joined = Vec::with_capacity(1 + at.len());
            joined.push(row[0]);
            joined.extend(at.iter().map(|i| i.map_or(0.0, |i| row[1 + i])));
            into.rows.push(joined);
        }
    }
}

/// Takes a segment's peak efforts (per driver: name, largest |effort|, unit) into `all`, the
/// largest per name (a held stop's holding driver appears in the segments that hold it).
fn take_peaks(all: &mut Vec<(String, f64, &'static str)>, part: Vec<(String, f64, &'static str)>) {
    for (name, peak, unit) in part {
        match all.iter_mut().find(|(n, ..)| *n == name) {
            Some(e) => e.1 = e.1.max(peak),
            None => all.push((name, peak, unit)),
        }
    }
}

/// Whether a static kind of `p` runs here: a quasi-static path of a model with limits.
pub(super) fn applies(p: &Prepared, kind: StaticKind) -> bool {
    kind == StaticKind::QuasiStatic && !p.model.stops().is_empty()
}
