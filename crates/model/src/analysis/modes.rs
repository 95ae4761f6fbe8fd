//! The vibration modes as output groups: `modes.csv` (number, kind, frequencies, damping ratio,
//! eigenvalue) and `mode_shapes.csv` (each body's δr, δθ and Euler-parameter increment δp), as a
//! modal run and the linearization of a dynamic run write them; the increment δp is also what
//! the report's animation of a mode moves ([`euler_increment`], `crate::scene`).

use crate::table::Table;
use cardan_dynamics::{Mode, ModeKind};
use nalgebra::{Vector3, Vector4};

/// `modes.csv` (one row per mode: its number, kind, frequencies, damping ratio, eigenvalue of
/// the first-order form) and `mode_shapes.csv` (one row per mode: each body's δr, δθ and the
/// increment δp = ½ Gᵀ(p₀) δθ of its Euler parameters p₀ in `rest`), at time `t` with the
/// moving `bodies` in file order.
pub fn mode_tables(t: f64, bodies: &[&str], rest: &[Vector4<f64>], list: &[Mode]) -> Vec<Table> {
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
