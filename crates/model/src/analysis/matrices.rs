//! The linearized model as MatrixMarket files, as a modal run and the linearization of a
//! dynamic run write them: the full matrices in the body increments ([`full_matrix_files`],
//! `lin_*_full.mtx`, `lin_Phi_v.mtx`), the reduced ones with the state-space model and its
//! signal list ([`matrix_files`]: `lin_M` … `lin_N` (`lin_G`), `ss_A` … `ss_D`,
//! `state_space.txt`), and the sparse path's choice between them ([`sparse_matrix_files`]).

use crate::build::Outputs as Requested;
use crate::prepare::Prepared;
use cardan_dynamics::{
    matrix_market, matrix_market_sparse, Dynamics, DynamicsError, Equilibrium, Force, Frame, Input,
    Linearization, Output, PointRef, SparseMatrix, SparseModalResults, State,
    SPARSE_LINEARIZATION_MAX_DOF, SPARSE_LINEARIZATION_MAX_UNKNOWNS,
};
use cardan_mechanism::BodyId;

/// The full linearized matrices about the equilibrium `state` (MatrixMarket, sparse):
/// `lin_M_full.mtx` (M), `lin_C_full.mtx` (C_t), `lin_K_full.mtx` (K_t), n × n in the body
/// increments δ, and `lin_Phi_v.mtx` (Φ_v, the independent constraint rows × n).
pub(super) fn full_matrix_files(
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
pub(super) fn sparse_matrix_files(
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
