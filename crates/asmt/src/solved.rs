//! cardan results → an OndselSolver `TimeSeries` (notes §1.8), and the `<name>.solved.asmt` text.
//!
//! Per part, in global components: the part-frame origin P (not the CM)
//!
//! ```text
//! A_P = A_cm A_Pcmᵀ,   s = r_P − r_cm = −A_P r_Pcm,   r_P = r_cm + s
//! v_P = ṙ_cm + ω × s,  a_P = r̈_cm + α × s + ω × (ω × s)
//! ```
//!
//! and the Bryant angles of A_P = R_x(b_x) R_y(b_y) R_z(b_z):
//! b_x = atan2(−A₁₂, A₂₂), b_y = atan2(A₀₂, √(A₀₀² + A₀₁²)), b_z = atan2(−A₀₁, A₀₀), exact at
//! every attitude (OndselSolver's writer clamps b_y to ±π/2 when |A₀₂| > 0.9999; this one does not).
//! The `Input` column is the pose as read. Joint and motion series (reactions) are written only
//! when reactions were computed; a kinematic run writes parts only.

use crate::document::Document;
use crate::import::Import;
use crate::series::{Item, Row, TimeSeries, PART_ROWS};
use cardan_mechanism::Results;
use nalgebra::{Matrix3, Vector3};

/// Bryant angles (x-y-z) of a rotation matrix, exact (no clamping near b_y = ±π/2):
/// b_x = atan2(−A₁₂, A₂₂), then M = R_x(b_x)ᵀ A = R_y(b_y) R_z(b_z) gives
/// b_y = atan2(M₀₂, M₂₂) and b_z = atan2(M₁₀, M₁₁), so the three reproduce A to rounding at
/// every attitude (near gimbal lock b_x absorbs the ill-conditioned split).
pub fn bryant_angles(a: &Matrix3<f64>) -> [f64; 3] {
    let bx = (-a[(1, 2)]).atan2(a[(2, 2)]);
    let (s, c) = bx.sin_cos();
    // Rows 1 and 2 of Rx(bx)ᵀ A; row 0 is A's.
    let m1 = a.row(1) * c + a.row(2) * s;
    let m2 = -a.row(1) * s + a.row(2) * c;
    [bx, a[(0, 2)].atan2(m2[2]), m1[0].atan2(m1[1])]
}

/// The 18 values of a part row set at one time.
fn part_values(
    r: Vector3<f64>,
    a: &Matrix3<f64>,
    v: Vector3<f64>,
    w: Vector3<f64>,
    acc: Vector3<f64>,
    alpha: Vector3<f64>,
) -> [f64; 18] {
    let b = bryant_angles(a);
    [
        r.x, r.y, r.z, b[0], b[1], b[2], v.x, v.y, v.z, w.x, w.y, w.z, acc.x, acc.y, acc.z,
        alpha.x, alpha.y, alpha.z,
    ]
}

/// The TimeSeries of a kinematic run: the assembly (zeros) and every part.
pub fn time_series(doc: &Document, import: &Import, results: &Results) -> TimeSeries {
    let n = results.times.len();
    let mut items = vec![Item {
        kind: "AssemblySeries".into(),
        path: format!("/{}", doc.name),
        line: 0,
        rows: PART_ROWS
            .iter()
            .map(|l| Row {
                label: (*l).into(),
                input: 0.0,
                values: vec![0.0; n],
            })
            .collect(),
    }];
    for (part, map) in doc.parts.iter().zip(&import.bodies) {
        let Some(body) = results.body(&map.body.name) else {
            continue;
        };
        let input_frame = doc.frame.then(&part.frame);
        let input = part_values(
            input_frame.position,
            &input_frame.rotation,
            part.velocity,
            part.omega,
            Vector3::zeros(),
            Vector3::zeros(),
        );
        let mut rows: Vec<Row> = PART_ROWS
            .iter()
            .zip(input)
            .map(|(l, i)| Row {
                label: (*l).into(),
                input: i,
                values: Vec::with_capacity(n),
            })
            .collect();
        for k in 0..n {
            let a_cm = cardan_eulerparam::a(&body.p[k]);
            let f = map.part_frame(&body.r[k], &a_cm);
            let s = f.position - body.r[k];
            let pick = |v: &Vec<Vector3<f64>>| v.get(k).copied().unwrap_or_else(Vector3::zeros);
            let (w, al) = (pick(&body.omega), pick(&body.omega_dot));
            let vel = pick(&body.r_dot) + w.cross(&s);
            let acc = pick(&body.r_ddot) + al.cross(&s) + w.cross(&w.cross(&s));
            for (row, x) in
                rows.iter_mut()
                    .zip(part_values(f.position, &f.rotation, vel, w, acc, al))
            {
                row.values.push(x);
            }
        }
        items.push(Item {
            kind: "PartSeries".into(),
            path: map.path.clone(),
            line: 0,
            rows,
        });
    }
    TimeSeries {
        times: results.times.clone(),
        items,
    }
}

/// Scales the length rows of `series` (X Y Z, VX VY VZ, AX AY AZ of every part and of the
/// assembly; angles and angular rates are unit-free) by `factor`: e.g. 1000 to write a series
/// computed in SI into a file in millimetres.
pub fn scale_lengths(series: &mut TimeSeries, factor: f64) {
    const LENGTHS: [&str; 9] = ["X", "Y", "Z", "VX", "VY", "VZ", "AX", "AY", "AZ"];
    for row in series
        .items
        .iter_mut()
        .flat_map(|i| i.rows.iter_mut())
        .filter(|r| LENGTHS.contains(&r.label.as_str()))
    {
        row.input *= factor;
        row.values.iter_mut().for_each(|v| *v *= factor);
    }
}

/// The input text with its `TimeSeries` (if any) replaced by `series`.
pub fn solved_text(input: &str, series: &TimeSeries) -> String {
    let mut out = String::with_capacity(input.len() * 2);
    for line in input.lines() {
        if line.trim_end() == "TimeSeries" {
            break;
        }
        out.push_str(line);
        out.push('\n');
    }
    series.write(&mut out);
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use cardan_eulerparam::p_from_euler_123;

    #[test]
    fn bryant_angles_invert_the_123_matrix_also_at_gimbal_lock() {
        for b in [
            [0.3, -0.2, 1.1],
            [-2.0, 1.2, 3.0],
            [0.4, std::f64::consts::FRAC_PI_2 - 1e-7, 0.2],
        ] {
            let a = p_from_euler_123(b[0], b[1], b[2]).unwrap().a();
            let back = bryant_angles(&a);
            let a2 = p_from_euler_123(back[0], back[1], back[2]).unwrap().a();
            assert!((a - a2).abs().max() < 1e-12, "{b:?} -> {back:?}");
        }
    }
}
