//! `kind = "dynamic"`: a model file's forces, initial velocities and integrator settings turned
//! into a [`cardan_dynamics`] simulation, and its results into output tables (reactions,
//! energy, constraint drift, besides the kinematic groups).
//!
//! The benchmark tests call [`simulate`] directly, so what is tested is the model file itself.

use crate::build::Outputs as Requested;
use crate::commands::Prepared;
use crate::diag::Error;
use crate::table::Table;
use cardan_dynamics::{DynamicResults, Dynamics, Integrator, SimulationOptions, State};

/// The [`Dynamics`] of a prepared model with the file's forces (gravity first).
///
/// # Errors
/// A body without mass or inertia, an invalid force element.
pub fn dynamics(p: &Prepared) -> Result<Dynamics<'_>, Error> {
    let mut d = Dynamics::new(&p.model).map_err(|e| located(p, &e))?;
    for f in &p.loaded.forces {
        d.add_force(f.clone()).map_err(|e| located(p, &e))?;
    }
    Ok(d)
}

/// The initial guess: the bodies' initial poses (assembled later) and the file's velocities, at
/// `t_start`.
pub fn initial_state(p: &Prepared) -> State {
    let t0 = p.loaded.analysis.as_ref().map_or(0.0, |a| a.t_start);
    let mut s = State::initial(&p.model, t0);
    for v in &p.loaded.velocities {
        if let Some(k) = p.model.bodies().iter().position(|b| b.name == v.body) {
            if v.omega_local {
                s.set_velocity(k, v.velocity, v.omega);
            } else {
                s.set_velocity_global(k, v.velocity, v.omega);
            }
        }
    }
    s
}

/// The file's simulation options; `integrator` overrides the file's integrator settings.
///
/// # Errors
/// The file has no `kind = "dynamic"` analysis.
pub fn options(p: &Prepared, integrator: Option<Integrator>) -> Result<SimulationOptions, Error> {
    let a = p
        .loaded
        .analysis
        .as_ref()
        .filter(|a| a.dynamic.is_some())
        .ok_or_else(|| {
            p.source
                .error("the model file has no [analysis] with kind = \"dynamic\"")
        })?;
    let integrator = integrator.or(a.dynamic).unwrap_or_default();
    Ok(SimulationOptions::new(a.t_end, a.steps).integrator(integrator))
}

/// Runs the file's dynamic analysis (or with another integrator).
///
/// # Errors
/// As [`dynamics`] and [`options`]; inconsistent initial conditions; integration failures
/// (located at the element concerned when the error names one).
pub fn simulate(p: &Prepared, integrator: Option<Integrator>) -> Result<DynamicResults, Error> {
    let opts = options(p, integrator)?;
    let mut d = dynamics(p)?;
    let s = initial_state(p);
    d.simulate(&s, &opts).map_err(|e| located(p, &e))
}

/// A dynamics error as a message, placed at the first element it names or at `[analysis]`.
pub fn located(p: &Prepared, e: &cardan_dynamics::DynamicsError) -> Error {
    use cardan_dynamics::DynamicsError as E;
    let spans = &p.loaded.spans;
    let span = match e.cause() {
        E::MissingInertia { body } => spans.element(body),
        E::BadForce { force, .. } => spans.element(force),
        E::InconsistentPositions { open } => open.first().and_then(|o| spans.element(&o.element)),
        E::InconsistentVelocities { equations, .. }
        | E::Singular {
            dependent: equations,
            ..
        } => equations.first().and_then(|o| spans.element(&o.element)),
        _ => None,
    }
    .unwrap_or_else(|| spans.analysis.clone());
    let mut err = Error::analysis(format!("dynamic analysis: {}", e.cause()));
    err.location = Some(p.source.location(span.start));
    err
}

/// The output groups of a dynamic run: the kinematic groups, then reactions (global and body
/// components), energy and constraint drift.
pub fn tables(p: &Prepared, r: &DynamicResults, req: &Requested) -> Vec<Table> {
    let mut out = crate::commands::run::tables(p, &r.kinematics, req);
    // The kinematic "residual" group is replaced by the drift group below.
    out.retain(|t| t.name != "residual");
    let times = r.times();
    let n = times.len();
    let joints: Vec<&cardan_dynamics::JointReactions> = match &req.reactions {
        Some(list) => list.iter().filter_map(|j| r.joint_reactions(j)).collect(),
        None => r.reactions.iter().collect(),
    };
    let xyz = ["x", "y", "z"];
    for (name, title, local) in [
        ("reactions", "joint reactions (global components)", false),
        ("reactions_local", "joint reactions (body components)", true),
    ] {
        if joints.is_empty() {
            break;
        }
        let mut cols = Vec::new();
        for j in &joints {
            for body in [&j.body_i, &j.body_j] {
                for (q, u) in [("F", "N"), ("T", "N m")] {
                    for ax in xyz {
                        cols.push(format!("{}.{body}.{q}.{ax} [{u}]", j.name));
                    }
                }
            }
        }
        let mut t = Table::new(name, title, cols);
        for k in 0..n {
            let mut row = vec![times[k]];
            for j in &joints {
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
            t.rows.push(row);
        }
        out.push(t);
    }
    if req.energy {
        let e = &r.energy;
        let drift = e.drift();
        let mut t = Table::new(
            "energy",
            "energy",
            vec![
                "kinetic [J]".into(),
                "potential_gravity [J]".into(),
                "potential_spring [J]".into(),
                "total [J]".into(),
                "drift [J]".into(),
            ],
        );
        for k in 0..n {
            let g = |v: &Vec<f64>| v.get(k).copied().unwrap_or(f64::NAN);
            t.rows.push(vec![
                times[k],
                g(&e.kinetic),
                g(&e.gravity),
                g(&e.spring),
                g(&e.total),
                g(&drift),
            ]);
        }
        out.push(t);
    }
    let mut t = Table::new(
        "constraint_drift",
        "constraint drift",
        vec![
            "max |Φ| [m or -]".into(),
            "max |Φ_v v − ν| [m/s or 1/s]".into(),
        ],
    );
    for k in 0..n {
        t.rows.push(vec![
            times[k],
            r.position_drift.get(k).copied().unwrap_or(f64::NAN),
            r.velocity_drift.get(k).copied().unwrap_or(f64::NAN),
        ]);
    }
    out.push(t);
    out
}
