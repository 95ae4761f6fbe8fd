//! `kind = "static"`, `"quasi_static"` and `"modal"`: static equilibria under the file's forces
//! ([`cardan_dynamics::Dynamics::statics`], [`cardan_dynamics::Dynamics::quasi_statics`]) and
//! the vibration modes about one ([`cardan_dynamics::Dynamics::modal`]). Their output groups are
//! the pose groups of a kinematic run (no velocities or accelerations: a static analysis has
//! none), the driver efforts (holding forces and torques), the reactions and `stability.csv`;
//! a modal run adds `modes.csv` and `mode_shapes.csv`.

use super::located::located_as;
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
    matrix_market, matrix_market_sparse, Dynamics, DynamicsError, Equilibrium, Force, Frame, Input,
    Linearization, ModalOptions, Mode, ModeKind, Output, PointRef, SparseMatrix,
    SparseModalResults, Stability, State, StaticOptions, StaticResults,
    SPARSE_LINEARIZATION_MAX_DOF, SPARSE_LINEARIZATION_MAX_UNKNOWNS,
};
use cardan_mechanism::{BodyId, Outputs};
use nalgebra::{Vector3, Vector4};
use std::path::PathBuf;
use std::time::Instant;

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
/// failure after the first time keeps the equilibria found before it.
pub(super) fn run_statics(
    p: &Prepared,
    analysis: &Analysis,
    kind: StaticKind,
) -> Result<Analysed, Error> {
    let what = match kind {
        StaticKind::Static => "static analysis",
        StaticKind::QuasiStatic => "quasi-static analysis",
        StaticKind::Modal => "modal analysis",
    };
    let start = Instant::now();
    let mut d = dynamics_as(p, what)?;
    let options = StaticOptions {
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
    };
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
    let wall = start.elapsed();
    // No free motion and no driver released as a state-space input: nothing can vibrate.
    let released = analysis
        .inputs
        .iter()
        .any(|i| p.loaded.drivers.iter().any(|(n, _)| n == i));
    let no_modes_found = match (&sparse, &modal) {
        (Some(s), _) => s.modes.is_empty(),
        (None, Some(m)) => m.modes.is_empty(),
        (None, None) => false,
    };
    let held = statics.equilibria.iter().all(|e| e.eigenvalues.is_empty());
    if kind == StaticKind::Modal && no_modes_found && held && !released {
        return Err(no_modes(p));
    }
    let r = &statics.results;
    let req = requested(p, &analysis.outputs);
    let mut tables: Vec<Table> = inverse_tables(p, r, &req)
        .into_iter()
        .filter(|t| !MOTION_GROUPS.contains(&t.name.as_str()))
        .collect();
    tables.push(stability_table(&statics));
    let mut warnings = stability_warnings(&statics);
    warnings.extend(dropped_row_warnings(p, &r.kinematics.dropped_rows));
    let mut files = Vec::new();
    let bodies: Vec<&str> = r
        .kinematics
        .bodies
        .iter()
        .map(|b| b.name.as_str())
        .collect();
    // The Euler parameters at the (first) equilibrium, about which the modes are; a failed
    // quasi-static run may have none, and no modes either.
    let rest: Vec<Vector4<f64>> = r
        .kinematics
        .bodies
        .iter()
        .map(|b| b.p.first().copied().unwrap_or_else(Vector4::x))
        .collect();
    if let Some(s) = &sparse {
        let t = s.equilibrium.equilibria.first().map_or(0.0, |e| e.state.t);
        tables.extend(mode_tables(t, &bodies, &rest, &s.modes));
        if !s.converged {
            warnings.push(format!(
                "the {} lowest modes did not all converge in {} Lanczos steps: their \
                 frequencies are doubtful",
                s.modes.len(),
                s.lanczos_steps
            ));
        }
        if let Some(eq) = s.equilibrium.equilibria.first() {
            files = sparse_matrix_files(p, &mut d, eq, s, &req, &analysis.inputs, &mut warnings)
                .map_err(|e| error(p, &e, what))?;
        }
    }
    if let Some(m) = &modal {
        if let Some(eq) = m.equilibrium.equilibria.first() {
            tables.extend(mode_tables(eq.state.t, &bodies, &rest, &m.modes));
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
                d.linearize_released(eq, &released)
                    .map_err(|e| error(p, &e, what))?
            };
            files = full_matrix_files(
                &mut d,
                &eq.state,
                &m.linearization.full_stiffness,
                &m.linearization.full_damping,
            )
            .map_err(|e| error(p, &e, what))?;
            files.extend(
                matrix_files(
                    p,
                    &mut d,
                    &eq.state,
                    &lin,
                    &req,
                    &analysis.inputs,
                    &about,
                    false,
                )
                .map_err(|e| error(p, &e, what))?,
            );
        }
    }
    let k = &r.kinematics;
    let summary = Summary {
        name: p.loaded.name.clone(),
        steps: k.len(),
        noun: ["equilibrium", "equilibria"],
        iterations: statics.equilibria.iter().map(|e| e.iterations).sum(),
        max_residual: k.residual.iter().fold(0.0, |a: f64, &b| a.max(b)),
        wall,
        dir: PathBuf::new(),
        files: Vec::new(),
        dynamic: None,
        energy_balance: None,
        peak_efforts: peak_efforts(p, r),
        warnings,
        subdivided_steps: None,
        row_reselections: r.stats.row_reselections,
    };
    Ok(Analysed {
        tables,
        summary,
        results: r.kinematics.clone(),
        dynamic: Some(r.clone()),
        failure,
        strict_failure: None,
        files,
        modes: match (sparse, modal) {
            (Some(s), _) => s.modes,
            (None, Some(m)) => m.modes,
            (None, None) => Vec::new(),
        },
        streamed: None,
    })
}

/// The error of a modal analysis whose drivers hold every degree of freedom: a mechanism
/// without free motion has no modes (an input error, at the analysis).
fn no_modes(p: &Prepared) -> Error {
    let drivers = p.loaded.drivers.len();
    let message = format!(
        "modal analysis: the drivers hold every degree of freedom of the mechanism ({drivers} \
         driver{}), so it has no free motion and no modes; remove the driver of each coordinate \
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

/// `modes.csv` (one row per mode: its number, kind, frequencies, damping ratio, eigenvalue of
/// the first-order form) and `mode_shapes.csv` (one row per mode: each body's δr, δθ and the
/// increment δp = ½ Gᵀ(p₀) δθ of its Euler parameters p₀ in `rest`), at time `t` with the
/// moving `bodies` in file order.
pub(super) fn mode_tables(
    t: f64,
    bodies: &[&str],
    rest: &[Vector4<f64>],
    list: &[Mode],
) -> Vec<Table> {
    let mut modes = Table::new(
        "modes",
        "vibration modes",
        vec![
            "mode [-]".into(),
            "kind [-]".into(),
            "frequency [Hz]".into(),
            "damped_frequency [Hz]".into(),
            "damping_ratio [-]".into(),
            "eigenvalue.re [1/s]".into(),
            "eigenvalue.im [1/s]".into(),
        ],
    );
    let mut cols = vec!["mode [-]".to_string()];
    for b in bodies {
        for ax in ["x", "y", "z"] {
            cols.push(format!("{b}.dr.{ax} [m]"));
        }
        for ax in ["x", "y", "z"] {
            cols.push(format!("{b}.dtheta.{ax} [rad]"));
        }
        for e in ["e0", "e1", "e2", "e3"] {
            cols.push(format!("{b}.dp.{e} [-]"));
        }
    }
    let mut shapes = Table::new("mode_shapes", "mode shapes", cols);
    for (i, mode) in list.iter().enumerate() {
        let kind = match mode.kind {
            ModeKind::Elastic => 0.0,
            ModeKind::Rigid => 1.0,
            ModeKind::Unstable => 2.0,
            ModeKind::Overdamped => 3.0,
        };
        modes.rows.push(vec![
            t,
            (i + 1) as f64,
            kind,
            mode.frequency,
            mode.damped_frequency,
            mode.damping_ratio,
            mode.eigenvalue[0],
            mode.eigenvalue[1],
        ]);
        let mut row = vec![t, (i + 1) as f64];
        for (s, p0) in mode.shape.iter().zip(rest) {
            row.extend(s.translation.iter());
            row.extend(s.rotation.iter());
            row.extend(euler_increment(p0, &s.rotation).iter());
        }
        shapes.rows.push(row);
    }
    vec![modes, shapes]
}

/// δp = ½ Gᵀ(p₀) δθ: the increment of unit Euler parameters p₀ (normalized here) for a small
/// rotation δθ in global components (Nikravesh 1988 ch. 6, ṗ = ½ Gᵀ ω); p₀ᵀδp = 0.
pub(crate) fn euler_increment(p0: &Vector4<f64>, dtheta: &Vector3<f64>) -> Vector4<f64> {
    cardan_eulerparam::velocity::p_dot_from_global(&(p0 / p0.norm()), dtheta)
}

/// The full linearized matrices about the equilibrium `state` (MatrixMarket, sparse):
/// `lin_M_full.mtx` (M), `lin_C_full.mtx` (C_t), `lin_K_full.mtx` (K_t), n × n in the body
/// increments δ, and `lin_Phi_v.mtx` (Φ_v, the independent constraint rows × n).
fn full_matrix_files(
    d: &mut Dynamics,
    state: &State,
    stiffness: &nalgebra::DMatrix<f64>,
    damping: &nalgebra::DMatrix<f64>,
) -> Result<Vec<(String, String)>, DynamicsError> {
    let full = d.linearization_matrices(state)?;
    let sparse = |m: &SparseMatrix| matrix_market_sparse(m.n, m.n, &m.entries);
    Ok(vec![
        ("lin_M_full.mtx".into(), sparse(&full.mass)),
        ("lin_C_full.mtx".into(), matrix_market(damping)),
        ("lin_K_full.mtx".into(), matrix_market(stiffness)),
        (
            "lin_Phi_v.mtx".into(),
            matrix_market_sparse(
                full.jacobian.rows,
                full.jacobian.cols,
                &full.jacobian.entries,
            ),
        ),
    ])
}

/// The matrix files of the sparse path: the full matrices (as [`full_matrix_files`], from the
/// sparse tangents), and, when the model is of moderate size and no driver is an input, the
/// reduced matrices and the state-space model of [`matrix_files`] (a basis from the sparse
/// factorization, [`Dynamics::linearize_sparse`]); otherwise a warning saying why not.
fn sparse_matrix_files(
    p: &Prepared,
    d: &mut Dynamics,
    eq: &Equilibrium,
    s: &SparseModalResults,
    req: &Requested,
    input_names: &[String],
    warnings: &mut Vec<String>,
) -> Result<Vec<(String, String)>, DynamicsError> {
    let full = d.linearization_matrices(&eq.state)?;
    let sparse = |m: &SparseMatrix| matrix_market_sparse(m.n, m.n, &m.entries);
    let n = full.mass.n;
    let dof = n.saturating_sub(full.jacobian.rows);
    let mut files = vec![
        ("lin_M_full.mtx".into(), sparse(&full.mass)),
        ("lin_C_full.mtx".into(), sparse(&s.damping)),
        ("lin_K_full.mtx".into(), sparse(&s.stiffness)),
        (
            "lin_Phi_v.mtx".into(),
            matrix_market_sparse(
                full.jacobian.rows,
                full.jacobian.cols,
                &full.jacobian.entries,
            ),
        ),
    ];
    let skipped = "the reduced matrices and the state-space model (lin_M, lin_C, lin_K, lin_N, \
                   ss_A … ss_D .mtx, state_space.txt) were not written";
    let drivers: Vec<&String> = input_names
        .iter()
        .filter(|n| p.model.drivers().iter().any(|d| &d.name == *n))
        .collect();
    if !drivers.is_empty() {
        warnings.push(format!(
            "{skipped}: driver efforts as inputs ({}) need the dense path (fewer than {} \
             moving bodies); lin_M_full, lin_C_full, lin_K_full and lin_Phi_v .mtx hold the \
             linearized model",
            drivers
                .iter()
                .map(|s| format!("\"{s}\""))
                .collect::<Vec<_>>()
                .join(", "),
            cardan_dynamics::SPARSE_MIN_BODIES
        ));
        return Ok(files);
    }
    if dof > SPARSE_LINEARIZATION_MAX_DOF || n > SPARSE_LINEARIZATION_MAX_UNKNOWNS {
        warnings.push(format!(
            "{skipped}: they are dense, and this model has {dof} independent coordinates and \
             {n} unknowns, beyond the sparse path's {SPARSE_LINEARIZATION_MAX_DOF} and \
             {SPARSE_LINEARIZATION_MAX_UNKNOWNS}; lin_M_full, lin_C_full, lin_K_full and \
             lin_Phi_v .mtx (sparse) hold the linearized model"
        ));
        return Ok(files);
    }
    let lin = d.linearize_sparse(eq, &s.stiffness, &s.damping)?;
    let about = format!("the equilibrium at t = {} s", eq.state.t);
    files.extend(matrix_files(
        p,
        d,
        &eq.state,
        &lin,
        req,
        input_names,
        &about,
        false,
    )?);
    Ok(files)
}

/// The linearization's matrices in MatrixMarket form: `lin_M.mtx`, `lin_C.mtx`, `lin_K.mtx`,
/// the basis `lin_N.mtx` (and `lin_G.mtx` about a moving state) and the state-space model
/// (`ss_A.mtx` … `ss_D.mtx`) with inputs = the named force elements (a unit force or torque
/// along the element's direction at `state`) and outputs = the requested points' x, y, z and
/// joint coordinates, listed in `state_space.txt`. `about` names the linearization point;
/// `moving`: about a state of a dynamic run (`lin_G.mtx` written).
#[allow(clippy::too_many_arguments)]
pub(super) fn matrix_files(
    p: &Prepared,
    d: &mut Dynamics,
    state: &State,
    lin: &Linearization,
    req: &Requested,
    input_names: &[String],
    about: &str,
    moving: bool,
) -> Result<Vec<(String, String)>, DynamicsError> {
    let model = &p.model;
    let local = |body: &str, pt: &PointRef| match pt {
        PointRef::Local(v) => *v,
        PointRef::Named(n) => model
            .point_index(body, n)
            .map_or(nalgebra::Vector3::zeros(), |i| model.points()[i].local),
    };
    let global =
        |body: &str, v: nalgebra::Vector3<f64>, frame: Frame| match (frame, model.body_id(body)) {
            (Frame::Body, Some(BodyId::Moving(k))) => state.body_state(k).a * v,
            _ => v,
        };
    let mut inputs = Vec::new();
    let mut names = Vec::new();
    for name in input_names {
        if let Some(dr) = model.drivers().iter().find(|d| &d.name == name) {
            inputs.push(Input::Driver {
                driver: name.clone(),
            });
            let unit = match dr.driver {
                cardan_constraints::Driver::Rotation(_) => "N m",
                _ => "N",
            };
            names.push(format!(
                "{name} [{unit}] (driver effort, the driver released)"
            ));
            continue;
        }
        match p.loaded.forces.iter().find(|f| f.name() == name.as_str()) {
            Some(Force::PointForce {
                body,
                point,
                value,
                frame,
                ..
            }) => {
                inputs.push(Input::Force {
                    body: body.clone(),
                    point: local(body, point),
                    direction: global(body, value.eval(state.t), *frame),
                });
                names.push(format!("{name} [N]"));
            }
            Some(Force::PointTorque {
                body, value, frame, ..
            }) => {
                inputs.push(Input::Torque {
                    body: body.clone(),
                    axis: global(body, value.eval(state.t), *frame),
                });
                names.push(format!("{name} [N m]"));
            }
            _ => {}
        }
    }
    let mut outputs = Vec::new();
    let mut out_names = Vec::new();
    for (b, pt) in &req.points {
        if !matches!(model.body_id(b), Some(BodyId::Moving(_))) {
            continue;
        }
        let s = local(b, &PointRef::Named(pt.clone()));
        for (ax, dir) in ["x", "y", "z"].iter().zip([
            nalgebra::Vector3::x(),
            nalgebra::Vector3::y(),
            nalgebra::Vector3::z(),
        ]) {
            outputs.push(Output::Point {
                body: b.clone(),
                point: s,
                direction: dir,
            });
            out_names.push(format!("{b}.{pt}.{ax} [m]"));
        }
    }
    for j in &req.joints {
        if let Some(ji) = model.joint_index(j) {
            for (i, c) in model.joints()[ji]
                .joint
                .kind()
                .info()
                .coordinates
                .iter()
                .enumerate()
            {
                outputs.push(Output::Joint {
                    joint: j.clone(),
                    index: i,
                });
                out_names.push(format!("{j}.{} [{}]", c.name, c.measure.quantity().unit()));
            }
        }
    }
    let ss = d.state_space(state, lin, &inputs, &outputs)?;
    let dof = lin.dof();
    let mut signals = format!(
        "# State-space model about {about} (MatrixMarket files, 1-based):\n\
         # x' = A x + B u, y = C x + D u; x = [z; dz/dt] with {dof} independent coordinates z,\n\
         # the body increments delta = N z (lin_N.mtx: 6 rows per moving body in file order,\n\
         # dr.x dr.y dr.z [m] of the centre of mass, then the rotation dpi'.x .y .z [rad] in\n\
         # body components); M_r z'' + C_r z' + K_r z = Q_u u (lin_M, lin_C, lin_K).\n"
    );
    if moving {
        signals.push_str(
            "# About a moving state: z' = w - G z with w = P dv the independent velocities\n\
             # (lin_G.mtx); the matrices are frozen at this time (docs/model-format.md).\n",
        );
    }
    for (i, n) in names.iter().enumerate() {
        signals.push_str(&format!("input {}: {n}\n", i + 1));
    }
    for (i, n) in out_names.iter().enumerate() {
        signals.push_str(&format!("output {}: {n}\n", i + 1));
    }
    let mut files = vec![
        ("lin_M.mtx".into(), matrix_market(&lin.mass)),
        ("lin_C.mtx".into(), matrix_market(&lin.damping)),
        ("lin_K.mtx".into(), matrix_market(&lin.stiffness)),
        ("lin_N.mtx".into(), matrix_market(&lin.basis)),
        ("ss_A.mtx".into(), matrix_market(&ss.a)),
        ("ss_B.mtx".into(), matrix_market(&ss.b)),
        ("ss_C.mtx".into(), matrix_market(&ss.c)),
        ("ss_D.mtx".into(), matrix_market(&ss.d)),
        ("state_space.txt".into(), signals),
    ];
    if moving {
        files.push(("lin_G.mtx".into(), matrix_market(&lin.transport)));
    }
    Ok(files)
}
