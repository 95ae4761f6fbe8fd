//! `cardan check MODEL.toml`: validate and describe a model.

use crate::diag::Error;
use crate::output_tables::{g, io, write_table};
use crate::prepare::{analysis_error, prepare_with, Prepared};
use cardan_mechanism::{AnalysisError, AssemblyOptions, DofReport, Model, Workspace};
use std::io::Write;
use std::path::Path;

/// Validates the model and prints bodies, joints with equation counts, DOF and redundancy.
///
/// # Errors
/// Any input error; an assembly that cannot close; a driver count that does not match the DOF
/// of a kinematic analysis (after printing the description).
pub fn check(path: &Path, out: &mut dyn Write) -> Result<(), Error> {
    check_with(path, super::asmt::AsmtOptions::default(), out)
}

/// [`check`] reading an ASMT file as `options` say; the import's warnings follow the
/// description (`warning: <file>:<line>: …`, as in a run's summary).
///
/// # Errors
/// As [`check`].
pub fn check_with(
    path: &Path,
    options: super::asmt::AsmtOptions,
    out: &mut dyn Write,
) -> Result<(), Error> {
    let p = prepare_with(path, options)?;
    describe(&p, path, out)?;
    for w in &p.warnings {
        writeln!(out, "warning: {w}").map_err(io)?;
    }
    Ok(())
}

/// The description `check` prints, and its refusals.
fn describe(p: &Prepared, path: &Path, out: &mut dyn Write) -> Result<(), Error> {
    // The animation's geometry (mesh files included), as `cardan run` checks it.
    p.geometry.readable()?;
    let model = &p.model;
    let t0 = p.loaded.analysis.as_ref().map_or(0.0, |a| a.t_start);
    let mut ws = model.workspace();
    let opts = AssemblyOptions {
        include_drivers: false,
        ..AssemblyOptions::at(t0)
    };
    model
        .assemble(&mut ws, &opts)
        .map_err(|e| analysis_error(p, &e))?;
    let dof = model.dof(&ws).map_err(|e| analysis_error(p, &e))?;

    writeln!(
        out,
        "model \"{}\" ({}): {}",
        p.loaded.name,
        path.display(),
        p.units.describe()
    )
    .map_err(io)?;
    write_parameters(p, out)?;
    write_bodies(p, &ws, out)?;
    write_joints(model, out)?;
    write_curves(model, out)?;
    write_couplers(model, out)?;
    write_limits(p, &ws, out)?;
    write_frictions(p, out)?;
    write_shapes(p, out)?;
    write_drivers(p, out)?;
    write_counts(model, &dof, out)?;
    analysis_line(p, &mut ws, &dof, out)
}

/// The parameters: each one's value (SI, with its unit), the number the model uses (in its
/// units), how it is written and where; a value given with `--set` says so.
fn write_parameters(p: &Prepared, out: &mut dyn Write) -> Result<(), Error> {
    let params = &p.loaded.parameters;
    if params.list.is_empty() {
        return Ok(());
    }
    writeln!(out, "\nparameters ({})", params.list.len()).map_err(io)?;
    let rows: Vec<Vec<String>> = (params.list.iter())
        .map(|q| {
            let written = match &q.set {
                Some(text) => format!("--set {}={text} (the file: {})", q.name, q.written),
                None => q.written.clone(),
            };
            vec![
                q.name.clone(),
                q.value.describe(),
                g(q.value.in_model_units(params.ell)),
                written,
                q.line.to_string(),
            ]
        })
        .collect();
    let used = match p.units {
        crate::units::UnitSystem::Si => "in the model (SI)",
        crate::units::UnitSystem::Mm => "in the model (mm units)",
    };
    write_table(out, &["name", "value", used, "written", "line"], &rows).map_err(io)
}

/// The moving bodies: name, mass, assembled position (in the model's units) and columns.
fn write_bodies(p: &Prepared, ws: &Workspace, out: &mut dyn Write) -> Result<(), Error> {
    let model = &p.model;
    writeln!(out, "\nbodies ({} moving, plus ground)", model.num_bodies()).map_err(io)?;
    let (unit, length) = p.units.unit("m");
    let position = format!("assembled position [{unit}]");
    let rows: Vec<Vec<String>> = model
        .bodies()
        .iter()
        .enumerate()
        .map(|(k, b)| {
            let r = ws.r(k) * length;
            vec![
                b.name.clone(),
                b.mass.map_or("-".into(), g),
                format!("({}, {}, {})", g(r.x), g(r.y), g(r.z)),
                format!("{}..{}", 6 * k, 6 * k + 6),
            ]
        })
        .collect();
    write_table(
        out,
        &["name", "mass [kg]", position.as_str(), "columns"],
        &rows,
    )
    .map_err(io)
}

/// The joints: name, type, bodies, equation count and rows.
fn write_joints(model: &Model, out: &mut dyn Write) -> Result<(), Error> {
    writeln!(out, "\njoints ({})", model.joints().len()).map_err(io)?;
    let rows: Vec<Vec<String>> = model
        .joints()
        .iter()
        .map(|j| {
            vec![
                j.name.clone(),
                j.joint.kind().name().to_string(),
                format!(
                    "{} – {}",
                    model.body_name(j.body_i),
                    model.body_name(j.body_j)
                ),
                j.rows.len().to_string(),
                format!("{}..{}", j.rows.start, j.rows.end),
            ]
        })
        .collect();
    write_table(out, &["name", "type", "bodies", "equations", "rows"], &rows).map_err(io)
}

/// The curve elements (points on curves, cam pairs), when the model has any: name, curve kinds,
/// bodies, the columns of the curve parameters, equation count and rows.
fn write_curves(model: &Model, out: &mut dyn Write) -> Result<(), Error> {
    if model.curves().is_empty() {
        return Ok(());
    }
    writeln!(
        out,
        "\ncurves, cams and surfaces ({})",
        model.curves().len()
    )
    .map_err(io)?;
    let nb6 = 6 * model.bodies().len();
    let rows: Vec<Vec<String>> = (model.curves().iter())
        .map(|c| {
            vec![
                c.name.clone(),
                match &c.element {
                    cardan_mechanism::CurveElement::Surface(s) => s.surface.kind().to_string(),
                    e => (e.curves().into_iter().flatten())
                        .map(|curve| match curve.kind() {
                            "cubic" => "spline",
                            "cubic_closed" => "closed spline",
                            kind => kind,
                        })
                        .collect::<Vec<_>>()
                        .join(" on "),
                },
                format!(
                    "{} – {}",
                    model.body_name(c.body_i),
                    model.body_name(c.body_j)
                ),
                (c.element.parameters().iter().zip(c.extras()))
                    .map(|(p, k)| format!("{p}: {}", nb6 + k))
                    .collect::<Vec<_>>()
                    .join(", "),
                c.rows.len().to_string(),
                format!("{}..{}", c.rows.start, c.rows.end),
            ]
        })
        .collect();
    let header = ["name", "curve", "bodies", "column", "equations", "rows"];
    write_table(out, &header, &rows).map_err(io)
}

/// The collision shapes and their materials, when the model has any: name, type, body, size
/// (in the model's units), material and its law; then the number of shape pairs that may touch.
fn write_shapes(p: &Prepared, out: &mut dyn Write) -> Result<(), Error> {
    use cardan_mechanism::{Geometry, Stiffness};
    let model = &p.model;
    if model.shapes().is_empty() {
        return Ok(());
    }
    let (unit, length) = p.units.unit("m");
    let l = |x: f64| g(x * length);
    writeln!(
        out,
        "
shapes ({})",
        model.shapes().len()
    )
    .map_err(io)?;
    let rows: Vec<Vec<String>> = (model.shapes().iter())
        .map(|s| {
            let size = match &s.geometry {
                Geometry::Sphere { radius } => format!("r {}", l(*radius)),
                Geometry::Capsule { radius, length } | Geometry::Cylinder { radius, length } => {
                    format!("r {}, ℓ {}", l(*radius), l(*length))
                }
                Geometry::Box { size } => format!("{} × {} × {}", l(size.x), l(size.y), l(size.z)),
                Geometry::Plane => "-".into(),
                Geometry::ConvexMesh { points } => format!("hull of {} points", points.len()),
                Geometry::TriangleMesh { triangles, .. } => {
                    format!("{} triangles", triangles.len())
                }
            };
            let m = &model.materials()[s.material];
            let law = match m.stiffness {
                Stiffness::Direct { k, exponent } => format!("K {} N/m^{exponent}", g(k)),
                Stiffness::Elastic {
                    youngs_modulus,
                    poisson_ratio,
                } => format!("E {} Pa, ν {}", g(youngs_modulus), g(poisson_ratio)),
            };
            vec![
                s.name.clone(),
                s.geometry.kind().to_string(),
                model.body_name(s.body).to_string(),
                size,
                format!(
                    "{} ({law}, e {}, μ {})",
                    m.name,
                    g(m.restitution),
                    g(m.friction_dynamic)
                ),
            ]
        })
        .collect();
    let size = format!("size [{unit}]");
    write_table(out, &["name", "type", "body", &size, "material"], &rows).map_err(io)?;
    let n = model.shapes().len();
    if n > 1000 {
        return writeln!(
            out,
            "(the pairs that may touch are not counted beyond 1000 shapes)"
        )
        .map_err(io);
    }
    let pairs = (0..n)
        .flat_map(|a| (a + 1..n).map(move |b| (a, b)))
        .filter(|&(a, b)| model.shapes_may_touch(a, b))
        .count();
    writeln!(
        out,
        "{pairs} pair{} of shapes may touch (bodies joined by a joint and filtered groups do not)",
        if pairs == 1 { "" } else { "s" }
    )
    .map_err(io)
}

/// The couplers (gears, racks, screws), when the model has any: name, type, joints and rows.
fn write_couplers(model: &Model, out: &mut dyn Write) -> Result<(), Error> {
    if model.couplers().is_empty() {
        return Ok(());
    }
    writeln!(out, "\ncouplers ({})", model.couplers().len()).map_err(io)?;
    let rows: Vec<Vec<String>> = model
        .couplers()
        .iter()
        .map(|c| {
            let joints: Vec<&str> = c
                .coordinates
                .iter()
                .map(|q| model.joints()[q.joint].name.as_str())
                .collect();
            vec![
                c.name.clone(),
                c.kind().to_string(),
                joints.join(" – "),
                format!("{}..{}", c.rows.start, c.rows.end),
            ]
        })
        .collect();
    write_table(out, &["name", "type", "joints", "rows"], &rows).map_err(io)
}

/// The limits, when the model has any: name, joint and coordinate, range, law, the coordinate
/// at the assembled pose and whether it respects the limit (the builder refuses a drawn pose
/// beyond one).
fn write_limits(p: &Prepared, ws: &Workspace, out: &mut dyn Write) -> Result<(), Error> {
    let model = &p.model;
    if model.limits().is_empty() {
        return Ok(());
    }
    writeln!(out, "\nlimits ({})", model.limits().len()).map_err(io)?;
    let status = model.stop_status(ws);
    let rows: Vec<Vec<String>> = model
        .limits()
        .iter()
        .enumerate()
        .map(|(k, l)| {
            let si = crate::units::coordinate_units(l.measure.quantity()).coordinate;
            let (unit, f) = p.units.unit(si);
            let bound = |b: Option<f64>| b.map_or("-".to_string(), |v| g(v * f));
            let stops: Vec<usize> = (0..model.stops().len())
                .filter(|&s| model.stops()[s].limit == k)
                .collect();
            let value = stops.first().map_or(f64::NAN, |&s| status[s].0);
            let closed = stops.iter().any(|&s| status[s].1 <= 0.0);
            let law = match &l.compliance {
                Some(c) => format!(
                    "compliant (k {}, c {}, n {})",
                    g(c.stiffness),
                    g(c.damping),
                    g(c.exponent)
                ),
                None => format!("impact (e {})", g(l.restitution)),
            };
            vec![
                l.name.clone(),
                format!("{} of {}", l.coordinate, model.joints()[l.joint].name),
                format!("[{}, {}] {unit}", bound(l.lower), bound(l.upper)),
                law,
                format!("{} {unit}", g(value * f)),
                if closed { "on a stop" } else { "inside" }.to_string(),
            ]
        })
        .collect();
    write_table(
        out,
        &["name", "coordinate", "range", "law", "assembled", "pose"],
        &rows,
    )
    .map_err(io)
}

/// The joint frictions, when the model has any: name, joint, μ, radius, preload, the constant
/// friction (a slide's force, a pin's torque).
fn write_frictions(p: &Prepared, out: &mut dyn Write) -> Result<(), Error> {
    let model = &p.model;
    if model.frictions().is_empty() {
        return Ok(());
    }
    writeln!(out, "\njoint friction ({})", model.frictions().len()).map_err(io)?;
    let (unit, f) = p.units.unit("m");
    let (torque_unit, tf) = p.units.unit("N m");
    let rows: Vec<Vec<String>> = model
        .frictions()
        .iter()
        .map(|fr| {
            vec![
                fr.name.clone(),
                model.joints()[fr.joint].name.clone(),
                g(fr.coefficient),
                if fr.radius > 0.0 {
                    format!("{} {unit}", g(fr.radius * f))
                } else {
                    "-".into()
                },
                format!("{} N", g(fr.preload)),
                match (fr.force > 0.0, fr.torque > 0.0) {
                    (true, true) => {
                        format!("{} N, {} {torque_unit}", g(fr.force), g(fr.torque * tf))
                    }
                    (true, false) => format!("{} N", g(fr.force)),
                    (false, true) => format!("{} {torque_unit}", g(fr.torque * tf)),
                    (false, false) => "-".into(),
                },
            ]
        })
        .collect();
    let head = ["name", "joint", "μ", "radius", "preload", "constant"];
    write_table(out, &head, &rows).map_err(io)
}

/// The drivers: name, what each drives, equation count and rows.
fn write_drivers(p: &Prepared, out: &mut dyn Write) -> Result<(), Error> {
    let model = &p.model;
    let drivers = (model.drivers().iter()).map(|d| (&d.name, &d.rows));
    let paths = (model.paths().iter()).map(|d| (&d.name, &d.rows));
    let all: Vec<_> = drivers.chain(paths).collect();
    writeln!(out, "\ndrivers ({})", all.len()).map_err(io)?;
    let what = |name: &str| {
        (p.loaded.drivers.iter())
            .find(|(n, _)| n == name)
            .map_or(String::new(), |(_, w)| w.clone())
    };
    let rows: Vec<Vec<String>> = (all.into_iter())
        .map(|(name, rows)| {
            vec![
                name.clone(),
                what(name),
                rows.len().to_string(),
                format!("{}..{}", rows.start, rows.end),
            ]
        })
        .collect();
    write_table(out, &["name", "drives", "equations", "rows"], &rows).map_err(io)
}

/// The counts: unknowns and equations, the joint Jacobian's rank and the degrees of freedom
/// (with Grübler's count beside), and the redundant equations.
fn write_counts(model: &Model, dof: &DofReport, out: &mut dyn Write) -> Result<(), Error> {
    writeln!(
        out,
        "\nunknowns: {} (6 per moving body{}); equations: {} joint + {} driver = {}",
        model.num_unknowns(),
        match model.num_extra() {
            0 => String::new(),
            n => format!(", and {n} curve parameter{}", if n == 1 { "" } else { "s" }),
        },
        model.num_joint_equations(),
        model.num_equations() - model.num_joint_equations(),
        model.num_equations()
    )
    .map_err(io)?;
    writeln!(
        out,
        "joint Jacobian rank {} → degrees of freedom: {} (Grübler count: {})",
        dof.rank,
        dof.dof,
        model.num_unknowns() as i64 - model.num_joint_equations() as i64
    )
    .map_err(io)?;
    if dof.redundant.is_empty() {
        writeln!(out, "redundant equations: none").map_err(io)?;
    } else {
        writeln!(out, "redundant equations ({}):", dof.redundant.len()).map_err(io)?;
        for e in &dof.redundant {
            writeln!(out, "  row {}: {e}", e.row).map_err(io)?;
        }
    }
    Ok(())
}

/// The line about the file's analysis: what a dynamic or static kind has to work with, or
/// whether a kinematic or inverse dynamics analysis has as many drivers as degrees of freedom
/// (and drivers that control the mechanism): its refusals are `run`'s.
fn analysis_line(
    p: &Prepared,
    ws: &mut Workspace,
    dof: &DofReport,
    out: &mut dyn Write,
) -> Result<(), Error> {
    let model = &p.model;
    if let Some(integrator) = p.loaded.analysis.as_ref().and_then(|a| a.integrator()) {
        let name = match integrator {
            cardan_dynamics::Integrator::Dopri5(_) => "DOPRI5",
            cardan_dynamics::Integrator::GeneralizedAlpha(_) => "generalized-α",
        };
        writeln!(
            out,
            "dynamic analysis ({name}): {} DOF left free by the joints and {} driver{}; {} force element{}",
            dof.dof.saturating_sub(dof.drivers),
            dof.drivers,
            if dof.drivers == 1 { "" } else { "s" },
            p.loaded.forces.len(),
            if p.loaded.forces.len() == 1 { "" } else { "s" },
        )
        .map_err(io)?;
    } else if let Some(k) = p.loaded.analysis.as_ref().and_then(|a| a.statics()) {
        // A static analysis needs no drivers: the free degrees of freedom settle under the loads.
        writeln!(
            out,
            "{} analysis: {} DOF left free by the joints and {} driver{}; {} force element{}",
            k.name(),
            dof.dof.saturating_sub(dof.drivers),
            dof.drivers,
            if dof.drivers == 1 { "" } else { "s" },
            p.loaded.forces.len(),
            if p.loaded.forces.len() == 1 { "" } else { "s" },
        )
        .map_err(io)?;
    } else if let Some(a) = &p.loaded.analysis {
        if a.kind == crate::build::AnalysisKind::InverseDynamics
            && (dof.dof != dof.drivers || dof.drivers == 0)
        {
            // A start resting on as many stops as drivers are missing: the run holds them.
            let Some(held) = crate::analysis::resting_motion(p, a.t_start)? else {
                return Err(crate::prepare::not_fully_driven(p, dof.dof, dof.drivers));
            };
            let names: Vec<&str> = (held.loaded.drivers.iter())
                .skip(p.loaded.drivers.len())
                .map(|(n, _)| n.as_str())
                .collect();
            writeln!(
                out,
                "inverse dynamics: {} driver{} and {} stop{} the start rests on ({}) for {} DOF: \
                 ok; {} force element{}",
                dof.drivers,
                if dof.drivers == 1 { "" } else { "s" },
                names.len(),
                if names.len() == 1 { "" } else { "s" },
                names.join(", "),
                dof.dof,
                p.loaded.forces.len(),
                if p.loaded.forces.len() == 1 { "" } else { "s" },
            )
            .map_err(io)?;
            return Ok(());
        }
        if dof.dof > dof.drivers && matches!(a.free_dof, cardan_mechanism::FreeDof::Hold(_)) {
            let free = dof.dof - dof.drivers;
            let names = crate::free_dof::named(model, a.t_start);
            writeln!(
                out,
                "kinematic analysis: {} driver{} for {} DOF: ok, {free} free DOF{names} held by \
                 least change (free_dof = \"hold\")",
                dof.drivers,
                if dof.drivers == 1 { "" } else { "s" },
                dof.dof,
            )
            .map_err(io)?;
            return Ok(());
        }
        if dof.dof == dof.drivers {
            // What `run` refuses next: drivers that depend on the joints or on each other.
            model
                .prepare_kinematics(ws)
                .map_err(|e| analysis_error(p, &e))?;
            writeln!(
                out,
                "{}: {} driver{} for {} DOF: ok{}",
                if a.kind == crate::build::AnalysisKind::InverseDynamics {
                    "inverse dynamics"
                } else {
                    "kinematic analysis"
                },
                dof.drivers,
                if dof.drivers == 1 { "" } else { "s" },
                dof.dof,
                if a.kind == crate::build::AnalysisKind::InverseDynamics {
                    format!(
                        "; {} force element{}",
                        p.loaded.forces.len(),
                        if p.loaded.forces.len() == 1 { "" } else { "s" }
                    )
                } else {
                    String::new()
                }
            )
            .map_err(io)?;
        } else {
            return Err(analysis_error(
                p,
                &AnalysisError::DriverCount {
                    dof: dof.dof,
                    drivers: dof.drivers,
                },
            ));
        }
    }
    Ok(())
}
