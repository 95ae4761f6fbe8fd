//! `kind = "static"`, `"quasi_static"` and `"modal"`: static equilibria under the file's forces
//! ([`cardan_dynamics::Dynamics::statics`], [`cardan_dynamics::Dynamics::quasi_statics`]) and
//! the vibration modes about one ([`cardan_dynamics::Dynamics::modal`]). Their output groups are
//! the pose groups of a kinematic run (no velocities or accelerations: a static analysis has
//! none), the driver efforts (holding forces and torques), the reactions and `stability.csv`;
//! a modal run adds `modes.csv` and `mode_shapes.csv`.

use super::located::located_as;
use super::matrices::{full_matrix_files, matrix_files, sparse_matrix_files};
use super::modes::mode_tables;
use super::setup::dynamics_as;
use super::summary::{Analysed, Summary};
use super::tables::inverse_tables;
use super::warnings::dropped_row_warnings;
use crate::build::Outputs as Requested;
use crate::build::{Analysis, StaticKind, DEFAULT_SPARSE_MODES};
use crate::diag::Error;
use crate::output_tables::{peak_efforts, requested};
use crate::prepare::{analysis_error, Prepared};
use crate::table::Table;
use cardan_dynamics::{
    DynamicResults, Dynamics, DynamicsError, ModalOptions, ModalResults, SparseModalResults,
    Stability, StaticOptions, StaticResults,
};
use cardan_mechanism::Outputs;
use nalgebra::Vector4;
use std::path::PathBuf;
use std::time::{Duration, Instant};

/// Output tables and named files (name, text).
type Written = (Vec<Table>, Vec<(String, String)>);

/// The groups a static analysis does not write (it has no velocities or accelerations).
const MOTION_GROUPS: [&str; 6] = [
    "point_velocities",
    "point_accelerations",
    "joint_velocities",
    "joint_accelerations",
    "body_velocities",
    "body_accelerations",
];

/// Runs a static kind: the equilibria (and modes), the tables, the summary. A quasi-static
/// failure after the first time keeps the equilibria found before it. (A quasi-static run
/// through stops goes to `quasi_stops` instead: the caller, `analysis::analyse`, decides.)
pub(super) fn run_statics(
    p: &Prepared,
    analysis: &Analysis,
    kind: StaticKind,
) -> Result<Analysed, Error> {
    let start = Instant::now();
    // The stops the equilibrium rests on, held (`resting`): the model to analyse.
    let equilibrium = |q: &Prepared, o: &StaticOptions| {
        let mut d = dynamics_as(q, what(kind))?;
        d.statics(o).map_err(|e| error(q, &e, what(kind)))
    };
    let held = super::resting::resting(p, &static_options(analysis), equilibrium)?;
    let p = held.as_ref().unwrap_or(p);
    let mut d = dynamics_as(p, what(kind))?;
    let solved = solve(p, &mut d, analysis, kind)?;
    let wall = start.elapsed();
    if kind == StaticKind::Modal && nothing_vibrates(p, analysis, &solved) {
        return Err(no_modes(p));
    }
    let statics = &solved.statics;
    let r = &statics.results;
    let req = requested(p, &analysis.outputs);
    let mut tables = equilibrium_tables(p, statics, &req);
    let mut warnings = equilibrium_warnings(p, statics);
    let mut files = Vec::new();
    if let Some(s) = &solved.sparse {
        let (t, f) = sparse_outputs(p, &mut d, analysis, &req, s, r, &mut warnings)?;
        tables.extend(t);
        files = f;
    }
    if let Some(m) = &solved.modal {
        let (t, f) = dense_outputs(p, &mut d, analysis, &req, m, r)?;
        tables.extend(t);
        files = f;
    }
    let summary = equilibria_summary(
        p,
        &r.kinematics,
        Work {
            iterations: statics.equilibria.iter().map(|e| e.iterations).sum(),
            row_reselections: r.stats.row_reselections,
            wall,
        },
        peak_efforts(p, r),
        warnings,
    );
    Ok(Analysed {
        tables,
        summary,
        results: r.kinematics.clone(),
        dynamic: Some(r.clone()),
        failure: solved.failure,
        strict_failure: None,
        files,
        modes: match (solved.sparse, solved.modal) {
            (Some(s), _) => s.modes,
            (None, Some(m)) => m.modes,
            (None, None) => Vec::new(),
        },
        events: Vec::new(),
        streamed: None,
    })
}

/// How the errors of a static kind start.
fn what(kind: StaticKind) -> &'static str {
    match kind {
        StaticKind::Static => "static analysis",
        StaticKind::QuasiStatic => "quasi-static analysis",
        StaticKind::Modal => "modal analysis",
    }
}

/// What a static kind solved: the equilibria and, for a modal run, its modes (on the dense
/// path, or on the sparse path of a large model).
struct Solved {
    statics: StaticResults,
    /// A modal run on the dense path.
    modal: Option<ModalResults>,
    /// A modal run on the sparse path: a few lowest modes.
    sparse: Option<SparseModalResults>,
    /// The failure that stopped a quasi-static run after its first time.
    failure: Option<Error>,
}

/// The file's options of a static solution: poses only (points and joints, no velocities or
/// accelerations).
pub(super) fn static_options(analysis: &Analysis) -> StaticOptions {
    StaticOptions {
        time: analysis.t_start,
        tolerance: analysis.tolerance,
        load_steps: analysis.load_steps,
        outputs: Outputs {
            velocity: false,
            acceleration: false,
            points: true,
            joints: true,
        },
        ..StaticOptions::default()
    }
}

/// Solves the equilibria of `kind` (and the modes of a modal run). A quasi-static run that
/// fails after its first time keeps the results so far, with the failure.
///
/// # Errors
/// A failed equilibrium or eigen-analysis, located in the file.
fn solve(
    p: &Prepared,
    d: &mut Dynamics,
    analysis: &Analysis,
    kind: StaticKind,
) -> Result<Solved, Error> {
    let what = what(kind);
    let options = static_options(analysis);
    let mut failure = None;
    let mut sparse: Option<SparseModalResults> = None;
    let (statics, modal) = match kind {
        StaticKind::Static => (d.statics(&options).map_err(|e| error(p, &e, what))?, None),
        StaticKind::QuasiStatic => match d.quasi_statics(&analysis.times(), &options) {
            Ok(r) => (r, None),
            Err(e) => match &e {
                DynamicsError::MidRun {
                    partial, source, ..
                } => {
                    failure = Some(error(p, source, what));
                    let r = StaticResults {
                        results: (**partial).clone(),
                        equilibria: Vec::new(),
                    };
                    (r, None)
                }
                _ => return Err(error(p, &e, what)),
            },
        },
        // Large models: the sparse path, a few lowest modes (docs/model-format.md).
        StaticKind::Modal if d.sparse_path() => {
            let count = analysis.modes.unwrap_or(DEFAULT_SPARSE_MODES);
            let m = d
                .modal_sparse(&options, count)
                .map_err(|e| error(p, &e, what))?;
            let eq = m.equilibrium.clone();
            sparse = Some(m);
            (eq, None)
        }
        StaticKind::Modal => {
            let mut m = d
                .modal(&ModalOptions { statics: options })
                .map_err(|e| error(p, &e, what))?;
            if let Some(count) = analysis.modes {
                m.modes.truncate(count);
            }
            (m.equilibrium.clone(), Some(m))
        }
    };
    Ok(Solved {
        statics,
        modal,
        sparse,
        failure,
    })
}

/// Whether a modal run found nothing that can vibrate: no modes, no free motion at any
/// equilibrium, and no driver released as a state-space input.
fn nothing_vibrates(p: &Prepared, analysis: &Analysis, solved: &Solved) -> bool {
    let released = analysis
        .inputs
        .iter()
        .any(|i| p.loaded.drivers.iter().any(|(n, _)| n == i));
    let no_modes_found = match (&solved.sparse, &solved.modal) {
        (Some(s), _) => s.modes.is_empty(),
        (None, Some(m)) => m.modes.is_empty(),
        (None, None) => false,
    };
    let held = (solved.statics.equilibria.iter()).all(|e| e.eigenvalues.is_empty());
    no_modes_found && held && !released
}

/// The moving bodies' names and their Euler parameters at the (first) equilibrium, about which
/// the modes are; a failed quasi-static run may have none, and no modes either.
fn rest_pose(r: &DynamicResults) -> (Vec<&str>, Vec<Vector4<f64>>) {
    let bodies = &r.kinematics.bodies;
    let names = bodies.iter().map(|b| b.name.as_str()).collect();
    let rest = bodies
        .iter()
        .map(|b| b.p.first().copied().unwrap_or_else(Vector4::x))
        .collect();
    (names, rest)
}

/// The mode tables and matrix files of a modal run on the sparse path (a warning when its
/// Lanczos iteration did not converge, and when the reduced matrices are not written).
///
/// # Errors
/// A failed linearization, located in the file.
fn sparse_outputs(
    p: &Prepared,
    d: &mut Dynamics,
    analysis: &Analysis,
    req: &Requested,
    s: &SparseModalResults,
    r: &DynamicResults,
    warnings: &mut Vec<String>,
) -> Result<Written, Error> {
    let (bodies, rest) = rest_pose(r);
    let t = s.equilibrium.equilibria.first().map_or(0.0, |e| e.state.t);
    let tables = mode_tables(t, &bodies, &rest, &s.modes);
    if !s.converged {
        warnings.push(format!(
            "the {} lowest modes did not all converge in {} Lanczos steps: their \
             frequencies are doubtful",
            s.modes.len(),
            s.lanczos_steps
        ));
    }
    let mut files = Vec::new();
    if let Some(eq) = s.equilibrium.equilibria.first() {
        files = sparse_matrix_files(p, d, eq, s, req, &analysis.inputs, warnings)
            .map_err(|e| error(p, &e, what(StaticKind::Modal)))?;
    }
    Ok((tables, files))
}

/// The mode tables and matrix files of a modal run on the dense path: the full matrices, and
/// the reduced ones with the state-space model (linearized again with the drivers that are
/// inputs released).
///
/// # Errors
/// A failed linearization, located in the file.
fn dense_outputs(
    p: &Prepared,
    d: &mut Dynamics,
    analysis: &Analysis,
    req: &Requested,
    m: &ModalResults,
    r: &DynamicResults,
) -> Result<Written, Error> {
    let Some(eq) = m.equilibrium.equilibria.first() else {
        return Ok((Vec::new(), Vec::new()));
    };
    let fail = |e: DynamicsError| error(p, &e, what(StaticKind::Modal));
    let (bodies, rest) = rest_pose(r);
    let tables = mode_tables(eq.state.t, &bodies, &rest, &m.modes);
    let about = format!("the equilibrium at t = {} s", eq.state.t);
    let released: Vec<String> = analysis
        .inputs
        .iter()
        .filter(|n| p.model.drivers().iter().any(|d| &d.name == *n))
        .cloned()
        .collect();
    let lin = if released.is_empty() {
        m.linearization.clone()
    } else {
        d.linearize_released(eq, &released).map_err(fail)?
    };
    let full = &m.linearization;
    let mut files =
        full_matrix_files(d, &eq.state, &full.full_stiffness, &full.full_damping).map_err(fail)?;
    let reduced = matrix_files(p, d, &eq.state, &lin, req, &analysis.inputs, &about, false);
    files.extend(reduced.map_err(fail)?);
    Ok((tables, files))
}

/// What solving the equilibria took (for the summary).
pub(super) struct Work {
    pub iterations: usize,
    pub row_reselections: usize,
    pub wall: Duration,
}

/// The summary of a static kind: the equilibria `k` solved, their Newton iterations, the
/// largest residual, the peak holding efforts.
pub(super) fn equilibria_summary(
    p: &Prepared,
    k: &cardan_mechanism::Results,
    work: Work,
    peak_efforts: Vec<(String, f64, &'static str)>,
    warnings: Vec<String>,
) -> Summary {
    Summary {
        name: p.loaded.name.clone(),
        steps: k.len(),
        noun: ["equilibrium", "equilibria"],
        iterations: work.iterations,
        max_residual: k.residual.iter().fold(0.0, |a: f64, &b| a.max(b)),
        wall: work.wall,
        dir: PathBuf::new(),
        files: Vec::new(),
        dynamic: None,
        energy_balance: None,
        peak_efforts,
        warnings,
        subdivided_steps: None,
        row_reselections: work.row_reselections,
    }
}

/// The tables of the equilibria of `statics`: the pose, efforts and reactions groups of an
/// inverse dynamics run without the motion groups, and `stability`.
pub(super) fn equilibrium_tables(
    p: &Prepared,
    statics: &StaticResults,
    req: &Requested,
) -> Vec<Table> {
    let mut tables: Vec<Table> = inverse_tables(p, &statics.results, req)
        .into_iter()
        .filter(|t| !MOTION_GROUPS.contains(&t.name.as_str()))
        .collect();
    tables.push(stability_table(statics));
    tables
}

/// The doubtful results of the equilibria of `statics`: unstable ones, dropped rows left open.
pub(super) fn equilibrium_warnings(p: &Prepared, statics: &StaticResults) -> Vec<String> {
    let mut warnings = stability_warnings(statics);
    warnings.extend(dropped_row_warnings(
        p,
        &statics.results.kinematics.dropped_rows,
    ));
    warnings
}

/// The error of a modal analysis whose drivers hold every degree of freedom: a mechanism
/// without free motion has no modes (an input error, at the analysis).
fn no_modes(p: &Prepared) -> Error {
    let drivers = p.loaded.drivers.len();
    let stops: Vec<&str> = p
        .model
        .stops()
        .iter()
        .filter(|st| p.loaded.drivers.iter().any(|(n, _)| *n == st.name))
        .map(|st| st.name.as_str())
        .collect();
    let resting = if stops.is_empty() {
        String::new()
    } else {
        format!(
            "; the stops the equilibrium rests on, {}, are held like drivers",
            stops.join(", ")
        )
    };
    let message = format!(
        "modal analysis: the drivers hold every degree of freedom of the mechanism ({drivers} \
         driver{}{resting}), so it has no free motion and no modes; remove the driver of each coordinate \
         that should vibrate (a modal analysis holds the remaining drivers at their values), \
         release it as a state-space input (inputs = [\"driver\"]), or use kind = \"static\" \
         for the holding efforts and reactions",
        if drivers == 1 { "" } else { "s" }
    );
    p.source.error_at(p.loaded.spans.analysis.clone(), message)
}

/// A dynamics error located in the file (a mechanism error as the kinematic runs say it).
fn error(p: &Prepared, e: &DynamicsError, what: &str) -> Error {
    match e.cause() {
        DynamicsError::Mechanism(ae) => analysis_error(p, ae),
        _ => located_as(p, e, what),
    }
}

/// `stability.csv`: per time, the stability (1 stable, 0 neutral, −1 unstable), the smallest
/// eigenvalue ω² of the reduced stiffness, the Newton iterations and load steps.
fn stability_table(s: &StaticResults) -> Table {
    let mut t = Table::new(
        "stability",
        "equilibrium stability",
        vec![
            "stability [-]".into(),
            "lowest_eigenvalue [1/s^2]".into(),
            "newton_iterations [-]".into(),
            "load_steps [-]".into(),
        ],
    );
    // A mechanism whose drivers hold every degree of freedom has no eigenvalue: the column is
    // left out rather than written as NaN (it is stable: nothing can move).
    let free = s.equilibria.iter().any(|e| !e.eigenvalues.is_empty());
    if !free {
        t.columns.remove(1);
    }
    for e in &s.equilibria {
        let code = match e.stability {
            Stability::Stable => 1.0,
            Stability::Neutral => 0.0,
            Stability::Unstable => -1.0,
        };
        let mut row = vec![e.state.t, code, e.iterations as f64, e.load_steps as f64];
        if free {
            row.insert(2, e.eigenvalues.first().copied().unwrap_or(f64::NAN));
        }
        t.rows.push(row);
    }
    t
}

/// Unstable equilibria, as warnings (named directions). A neutral equilibrium (a free
/// direction without stiffness: rigid-body modes) is not doubtful and not warned about;
/// `stability.csv` and `modes.csv` report it.
fn stability_warnings(s: &StaticResults) -> Vec<String> {
    let mut out = Vec::new();
    for e in &s.equilibria {
        match e.stability {
            Stability::Stable | Stability::Neutral => {}
            Stability::Unstable => out.push(format!(
                "t = {} s: the equilibrium is unstable (negative stiffness along {}): a small \
                 disturbance moves the mechanism away from it",
                e.state.t,
                e.soft_directions.join(", ")
            )),
        }
    }
    out
}
