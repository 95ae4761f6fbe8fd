//! `cardan eval MODEL.toml [--t T] [--format text|json|csv]`: Φ, Φ_v (pattern and values), ν
//! and γ# at the assembled state, the tool for debugging a model. As text for reading (7
//! significant digits), or for programs as JSON or CSV: every number at full precision (the
//! shortest decimal that reads back to the same f64), with the map from each row to its element
//! and primitive and from each column to its body and coordinate.
//!
//! The form is the 6-coordinate one (`shared/notation.md`): per moving body the unknowns are
//! Δr (global, m) and Δπ' (body frame, rad), so Φ_v multiplies v = [ṙ; ω'] and
//! Φ_v v̇ = γ#, with ν = −Φ_t and γ# = −(Φ_v v)_q q̇ − 2 Φ_vt v − Φ_tt at the bodies' velocities.

use crate::diag::Error;
use crate::output_tables::{g, io, write_table};
use crate::prepare::{analysis_error, prepare, Prepared};
use cardan_mechanism::AssemblyOptions;
use serde::Serialize;
use std::io::Write;
use std::path::Path;

/// Largest number of Jacobian columns drawn as a character grid.
const GRID_MAX_COLUMNS: usize = 120;

fn e(v: f64) -> String {
    format!("{v:+.6e}")
}

/// The output format of `cardan eval`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
#[cfg_attr(feature = "clap", derive(clap::ValueEnum))]
pub enum Format {
    /// Tables to read (7 significant digits).
    #[default]
    Text,
    /// One JSON object at full precision (see [`Evaluation`]).
    Json,
    /// One CSV table at full precision: a line per equation with its element, kind,
    /// primitive, Φ, ν, γ# and its row of Φ_v (a column per unknown, `body.r.x` ...).
    Csv,
}

/// Most unknowns written as dense Jacobian columns by `--format csv` (JSON is sparse).
pub const CSV_MAX_UNKNOWNS: usize = 3000;

/// The unknowns of one moving body, in column order (6-coordinate form).
pub const COORDINATES: [&str; 6] = ["r.x", "r.y", "r.z", "ω'.x", "ω'.y", "ω'.z"];

/// What `cardan eval --format json` writes: the assembled state and the constraint quantities
/// there, every number as the shortest decimal that reads back to the same f64.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Evaluation {
    /// The model name.
    pub model: String,
    /// The time (s).
    pub t: f64,
    /// Newton iterations of the assembly.
    pub assembly_iterations: usize,
    /// Largest scaled residual after the assembly.
    pub assembly_residual: f64,
    /// Where the velocities come from (the velocity analysis, or rest).
    pub velocities: String,
    /// The form of the quantities (see the module docs).
    pub form: &'static str,
    /// Each moving body's state: r (m), p, ṙ (m/s), ω (global, rad/s).
    pub bodies: Vec<BodyState>,
    /// What each row is: element, kind, primitive and row within it.
    pub rows: Vec<RowInfo>,
    /// What each column is: body and coordinate.
    pub columns: Vec<ColumnInfo>,
    /// Φ per row.
    pub phi: Vec<f64>,
    /// ν = −Φ_t per row.
    pub nu: Vec<f64>,
    /// γ# per row.
    pub gamma: Vec<f64>,
    /// The structural nonzeros of Φ_v: row, column, value.
    pub jacobian: Vec<(usize, usize, f64)>,
}

/// A body's state in an [`Evaluation`].
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct BodyState {
    /// Its name.
    pub name: String,
    /// Position of the body frame origin (m).
    pub r: [f64; 3],
    /// Euler parameters [e0, e1, e2, e3].
    pub p: [f64; 4],
    /// Velocity (m/s).
    pub r_dot: [f64; 3],
    /// Angular velocity, global (rad/s).
    pub omega: [f64; 3],
}

/// One row of an [`Evaluation`].
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct RowInfo {
    /// The joint or driver.
    pub element: String,
    /// Its kind.
    pub kind: String,
    /// The primitive the row belongs to.
    pub primitive: String,
    /// The row within the element.
    pub local_row: usize,
}

/// One column of an [`Evaluation`].
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ColumnInfo {
    /// The moving body (for a curve parameter: the curve element).
    pub body: String,
    /// The coordinate ([`COORDINATES`], or `u`, `w` for a curve parameter).
    pub coordinate: &'static str,
}

const FORM: &str = "6-coordinate: per moving body the columns are r.x r.y r.z (global, m) and \
                    ω'.x ω'.y ω'.z (body frame, rad), then one column u (m) per curve parameter; Φ_v v = ν with ν = −Φ_t, Φ_v v̇ = γ#";

/// Assembles at time t (default: the analysis start) and writes Φ, the Jacobian, ν and γ#, as
/// text or as JSON.
///
/// # Errors
/// Input errors; an assembly that cannot close.
pub fn eval(path: &Path, t: Option<f64>, format: Format, out: &mut dyn Write) -> Result<(), Error> {
    eval_with(path, t, &[], format, out)
}

/// [`eval`] with `--set` values for the model's `[parameters]`.
///
/// # Errors
/// As [`eval`]; a `--set` of a parameter the file does not define, or of a wrong unit.
pub fn eval_with(
    path: &Path,
    t: Option<f64>,
    set: &[(String, String)],
    format: Format,
    out: &mut dyn Write,
) -> Result<(), Error> {
    let options = crate::asmt::AsmtOptions {
        set: set.to_vec(),
        ..Default::default()
    };
    let (p, ev) = evaluate_prepared(crate::prepare::prepare_with(path, options)?, t)?;
    match format {
        Format::Text => write_text(&p, &ev, out),
        Format::Json => {
            let text = serde_json::to_string_pretty(&ev)
                .map_err(|e| Error::output(format!("cannot write the JSON: {e}")))?;
            writeln!(out, "{text}").map_err(io)
        }
        Format::Csv => write_csv(&ev, out),
    }
}

/// The CSV of `--format csv`: numbers as the shortest decimal that reads back to the same f64
/// (`1.5e-3`), structural zeros of Φ_v written as 0.
fn write_csv(ev: &Evaluation, out: &mut dyn Write) -> Result<(), Error> {
    let n = ev.columns.len();
    if n > CSV_MAX_UNKNOWNS {
        return Err(Error::usage(format!(
            "cardan eval --format csv writes the Jacobian densely and the model has {n} unknowns \
             (at most {CSV_MAX_UNKNOWNS}): use --format json, which lists its nonzeros"
        )));
    }
    let mut header: Vec<String> = [
        "row",
        "element",
        "kind",
        "primitive",
        "local_row",
        "phi",
        "nu",
        "gamma",
    ]
    .map(String::from)
    .to_vec();
    header.extend(
        ev.columns
            .iter()
            .map(|c| format!("{}.{}", c.body, c.coordinate)),
    );
    let line = |fields: Vec<String>| -> String {
        let f: Vec<String> = fields
            .iter()
            .map(|s| crate::table::csv_field(s).into_owned())
            .collect();
        f.join(",")
    };
    writeln!(out, "{}", line(header)).map_err(io)?;
    let mut by_row = vec![Vec::new(); ev.rows.len()];
    for &(r, c, v) in &ev.jacobian {
        by_row[r].push((c, v));
    }
    let mut dense = vec![0.0; n];
    for (k, r) in ev.rows.iter().enumerate() {
        dense.fill(0.0);
        for &(c, v) in &by_row[k] {
            dense[c] += v;
        }
        let mut fields = vec![
            k.to_string(),
            r.element.clone(),
            r.kind.clone(),
            r.primitive.clone(),
            r.local_row.to_string(),
        ];
        fields.extend(
            [ev.phi[k], ev.nu[k], ev.gamma[k]]
                .iter()
                .map(|v| format!("{v:e}")),
        );
        fields.extend(dense.iter().map(|v| format!("{v:e}")));
        writeln!(out, "{}", line(fields)).map_err(io)?;
    }
    Ok(())
}

/// Assembles at time t (default: the analysis start) and evaluates Φ, ν, γ# and Φ_v there.
///
/// # Errors
/// Input errors; an assembly that cannot close.
pub fn evaluate(path: &Path, t: Option<f64>) -> Result<(Prepared, Evaluation), Error> {
    evaluate_prepared(prepare(path)?, t)
}

/// [`evaluate`] of a model already read.
///
/// # Errors
/// As [`evaluate`].
pub fn evaluate_prepared(p: Prepared, t: Option<f64>) -> Result<(Prepared, Evaluation), Error> {
    let model = &p.model;
    let t = t.unwrap_or_else(|| p.loaded.analysis.as_ref().map_or(0.0, |a| a.t_start));
    if !t.is_finite() {
        return Err(Error::usage(format!("--t must be a finite time, got {t}")));
    }
    crate::prepare::check_driver_values(&p.source, &p.loaded, &[t])?;
    let mut ws = model.workspace();
    let rep = model
        .assemble(&mut ws, &AssemblyOptions::at(t))
        .map_err(|e| analysis_error(&p, &e))?;
    // Velocities for γ# need a square, controlled system; without one γ# is at rest.
    let velocity_note = match model
        .prepare_kinematics(&mut ws)
        .and_then(|_| model.position(&mut ws, t))
        .and_then(|_| model.velocity(&mut ws))
    {
        Ok(()) => "velocities from the velocity analysis".to_string(),
        Err(err) => {
            let msg = analysis_error(&p, &err).message;
            let mut ws2 = model.workspace();
            model
                .assemble(&mut ws2, &AssemblyOptions::at(t))
                .map_err(|e| analysis_error(&p, &e))?;
            ws = ws2;
            format!("bodies at rest (no velocity analysis: {msg})")
        }
    };

    let m = model.num_equations();
    let n = model.num_unknowns();
    let mut phi = vec![0.0; m];
    let mut nu = vec![0.0; m];
    let mut gamma = vec![0.0; m];
    let mut slots = vec![0.0; model.pattern().num_slots()];
    model.eval_phi(&ws, t, &mut phi);
    model.eval_nu(&ws, t, &mut nu);
    model.eval_gamma(&ws, t, &mut gamma);
    model.eval_jacobian(&ws, t, &mut slots);

    let bodies = model
        .bodies()
        .iter()
        .enumerate()
        .map(|(k, b)| BodyState {
            name: b.name.clone(),
            r: ws.r(k).into(),
            p: {
                let q = ws.p(k);
                [q[0], q[1], q[2], q[3]]
            },
            r_dot: ws.r_dot(k).into(),
            omega: ws.omega(k).into(),
        })
        .collect();
    let rows = (0..m)
        .map(|r| {
            let eq = model.equation(r);
            RowInfo {
                element: eq.as_ref().map_or("?".into(), |e| e.element.clone()),
                kind: eq.as_ref().map_or("?".into(), |e| e.kind.to_string()),
                primitive: eq.as_ref().map_or("?".into(), |e| e.primitive.to_string()),
                local_row: eq.as_ref().map_or(0, |e| e.local_row),
            }
        })
        .collect();
    // Six columns per moving body, then one per curve parameter (named by its element).
    let nb6 = 6 * model.bodies().len();
    let columns = (0..n)
        .map(|c| match c.checked_sub(nb6) {
            None => ColumnInfo {
                body: model.bodies()[c / 6].name.clone(),
                coordinate: COORDINATES[c % 6],
            },
            Some(k) => {
                let c = (model.curves().iter())
                    .find(|c| c.extras().contains(&k))
                    .expect("every extra coordinate belongs to a curve element");
                ColumnInfo {
                    body: c.name.clone(),
                    coordinate: c.element.parameters()[k - c.extra],
                }
            }
        })
        .collect();
    let jacobian = model
        .pattern()
        .entries()
        .zip(&slots)
        .map(|((r, c), v)| (r, c, *v))
        .collect();
    let ev = Evaluation {
        model: p.loaded.name.clone(),
        t,
        assembly_iterations: rep.iterations,
        assembly_residual: rep.residual,
        velocities: velocity_note,
        form: FORM,
        bodies,
        rows,
        columns,
        phi,
        nu,
        gamma,
        jacobian,
    };
    Ok((p, ev))
}

/// The text form of an [`Evaluation`].
fn write_text(p: &Prepared, ev: &Evaluation, out: &mut dyn Write) -> Result<(), Error> {
    let model = &p.model;
    let (t, m, n) = (ev.t, ev.phi.len(), ev.columns.len());
    let (phi, nu, gamma) = (&ev.phi, &ev.nu, &ev.gamma);
    let velocity_note = &ev.velocities;
    let slots: Vec<f64> = ev.jacobian.iter().map(|&(_, _, v)| v).collect();
    writeln!(
        out,
        "model \"{}\" at t = {t} s: assembled in {} iterations (scaled residual {:.2e}); {velocity_note}",
        p.loaded.name, ev.assembly_iterations, ev.assembly_residual
    )
    .map_err(io)?;
    writeln!(
        out,
        "{m} equations, {n} unknowns (per moving body: Δr x y z, Δπ' x y z in the body frame; 6-coordinate form; then Δu per curve)"
    )
    .map_err(io)?;

    writeln!(out, "\nbody states").map_err(io)?;
    let v3 = |v: &[f64; 3]| format!("({}, {}, {})", g(v[0]), g(v[1]), g(v[2]));
    let rows: Vec<Vec<String>> = ev
        .bodies
        .iter()
        .map(|b| {
            let q = &b.p;
            vec![
                b.name.clone(),
                v3(&b.r),
                format!("({}, {}, {}, {})", g(q[0]), g(q[1]), g(q[2]), g(q[3])),
                v3(&b.r_dot),
                v3(&b.omega),
            ]
        })
        .collect();
    write_table(out, &["body", "r [m]", "p", "ṙ [m/s]", "ω [rad/s]"], &rows).map_err(io)?;

    writeln!(out, "\nequations (Φ, ν = −Φ_t, γ#)").map_err(io)?;
    let rows: Vec<Vec<String>> = (0..m)
        .map(|r| {
            let eq = model.equation(r);
            vec![
                r.to_string(),
                eq.as_ref().map_or("?".into(), |e| e.element.clone()),
                eq.as_ref().map_or("?".into(), |e| e.kind.to_string()),
                eq.as_ref()
                    .map_or("?".into(), |e| format!("{} [{}]", e.primitive, e.local_row)),
                e(phi[r]),
                e(nu[r]),
                e(gamma[r]),
            ]
        })
        .collect();
    write_table(
        out,
        &["row", "element", "kind", "primitive [row]", "Φ", "ν", "γ#"],
        &rows,
    )
    .map_err(io)?;

    // Dense view of the values and the pattern.
    let pattern = model.pattern();
    let big = slots.iter().fold(0.0f64, |a, v| a.max(v.abs()));
    let mut dense = vec![None; m * n];
    for (k, v) in slots.iter().enumerate() {
        let (r, c) = pattern.entry(k);
        dense[r * n + c] = Some(*v);
    }
    writeln!(
        out,
        "\nJacobian Φ_v pattern: {} structural nonzeros of {} ('#' nonzero, '0' zero to round-off, '.' outside the pattern)",
        pattern.nnz(),
        m * n
    )
    .map_err(io)?;
    if n <= GRID_MAX_COLUMNS {
        let mut header = String::from("       ");
        for b in model.bodies() {
            let mut name: String = b.name.chars().take(6).collect();
            while name.chars().count() < 7 {
                name.push(' ');
            }
            header.push_str(&name);
        }
        writeln!(out, "{}", header.trim_end()).map_err(io)?;
        let mut sub = String::from("       ");
        for _ in model.bodies() {
            sub.push_str("rrrwww ");
        }
        writeln!(out, "{}", sub.trim_end()).map_err(io)?;
        for r in 0..m {
            let mut line = format!("  {r:>3}  ");
            for c in 0..n {
                line.push(match dense[r * n + c] {
                    None => '.',
                    Some(v) if v.abs() <= 1e-12 * big => '0',
                    Some(_) => '#',
                });
                if c % 6 == 5 {
                    line.push(' ');
                }
            }
            let name = model.equation(r).map_or(String::new(), |e| e.to_string());
            writeln!(out, "{line} {name}").map_err(io)?;
        }
    } else {
        writeln!(
            out,
            "  ({n} columns: too wide for a grid; see the values below)"
        )
        .map_err(io)?;
    }

    writeln!(
        out,
        "\nJacobian Φ_v values (row, column, body.coordinate, value)"
    )
    .map_err(io)?;
    let rows: Vec<Vec<String>> = pattern
        .entries()
        .zip(&slots)
        .map(|((r, c), v)| {
            vec![
                r.to_string(),
                c.to_string(),
                format!("{}.{}", ev.columns[c].body, ev.columns[c].coordinate),
                e(*v),
            ]
        })
        .collect();
    write_table(out, &["row", "col", "unknown", "value"], &rows).map_err(io)?;
    Ok(())
}
