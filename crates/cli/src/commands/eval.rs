//! `cardan eval MODEL.toml [--t T]`: Φ, Φ_v (pattern and values), ν and γ# at the assembled
//! state, the tool for debugging a model.

use super::output_tables::{g, io, write_table};
use super::{analysis_error, prepare};
use crate::diag::Error;
use cardan_mechanism::AssemblyOptions;
use std::io::Write;
use std::path::Path;

/// Largest number of Jacobian columns drawn as a character grid.
const GRID_MAX_COLUMNS: usize = 120;

fn e(v: f64) -> String {
    format!("{v:+.6e}")
}

/// Assembles at time t (default: the analysis start) and prints Φ, the Jacobian, ν and γ#.
///
/// # Errors
/// Input errors; an assembly that cannot close.
pub fn eval(path: &Path, t: Option<f64>, out: &mut dyn Write) -> Result<(), Error> {
    let p = prepare(path)?;
    let model = &p.model;
    let t = t.unwrap_or_else(|| p.loaded.analysis.as_ref().map_or(0.0, |a| a.t_start));
    if !t.is_finite() {
        return Err(Error::input(format!("--t must be a finite time, got {t}")));
    }
    super::check_driver_values(&p.source, &p.loaded, &[t])?;
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

    writeln!(
        out,
        "model \"{}\" at t = {t} s: assembled in {} iterations (scaled residual {:.2e}); {velocity_note}",
        p.loaded.name, rep.iterations, rep.residual
    )
    .map_err(io)?;
    writeln!(
        out,
        "{m} equations, {n} unknowns (per moving body: Δr x y z, Δπ' x y z in the body frame; 6-coordinate form)"
    )
    .map_err(io)?;

    writeln!(out, "\nbody states").map_err(io)?;
    let rows: Vec<Vec<String>> = model
        .bodies()
        .iter()
        .enumerate()
        .map(|(k, b)| {
            let (r, q, rd, w) = (ws.r(k), ws.p(k), ws.r_dot(k), ws.omega(k));
            vec![
                b.name.clone(),
                format!("({}, {}, {})", g(r.x), g(r.y), g(r.z)),
                format!("({}, {}, {}, {})", g(q[0]), g(q[1]), g(q[2]), g(q[3])),
                format!("({}, {}, {})", g(rd.x), g(rd.y), g(rd.z)),
                format!("({}, {}, {})", g(w.x), g(w.y), g(w.z)),
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
    let coord = ["r.x", "r.y", "r.z", "ω'.x", "ω'.y", "ω'.z"];
    let rows: Vec<Vec<String>> = pattern
        .entries()
        .zip(&slots)
        .map(|((r, c), v)| {
            vec![
                r.to_string(),
                c.to_string(),
                format!("{}.{}", model.bodies()[c / 6].name, coord[c % 6]),
                e(*v),
            ]
        })
        .collect();
    write_table(out, &["row", "col", "unknown", "value"], &rows).map_err(io)?;
    Ok(())
}
