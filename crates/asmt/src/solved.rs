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
//! The `Input` column is the pose as read.
//!
//! Joint and motion series are written when the run computed reactions (inverse dynamics or
//! dynamics: [`add_reactions`]), in OndselSolver's conventions: `FXonI FYonI FZonI` the force the
//! joint (or motion) exerts on the part that carries MarkerI, `TXonI TYonI TZonI` the torque on
//! that part about MarkerI's origin, global components. cardan's reaction on body i of a joint
//! (body i = MarkerI's part, [`fn@crate::import`]) is taken about the joint's point P_i; when
//! P_i is not MarkerI's origin m, the torque is moved there: T_m = T_P + (r_P − r_m) × F. Couplers
//! (gear, rack and pinion, screw) get no series: cardan writes their law in joint coordinates, so
//! the wrench of their equation is split between the coupled joints differently from OndselSolver's
//! (only the efforts about the axes are physical; the gears' joint series carry the rest).

use crate::document::Document;
use crate::import::Import;
use crate::series::REACTION_ROWS;
use crate::series::{Item, Row, TimeSeries, PART_ROWS};
use cardan_dynamics::{DynamicResults, JointReactions};
use cardan_mechanism::{Results, GROUND};
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

/// Scales the rows of `series` that carry one length (X Y Z, VX VY VZ, AX AY AZ of every part and
/// of the assembly, and the reaction torques TXonI TYonI TZonI; angles, angular rates and forces
/// carry none) by `factor`: e.g. 1000 to write a series
/// computed in SI into a file in millimetres.
pub fn scale_lengths(series: &mut TimeSeries, factor: f64) {
    const LENGTHS: [&str; 12] = [
        "X", "Y", "Z", "VX", "VY", "VZ", "AX", "AY", "AZ", "TXonI", "TYonI", "TZonI",
    ];
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

/// Appends to `series` the reaction series of every joint and motion of `doc` (file order:
/// joints, then motions) computed by a dynamic or inverse dynamics run (`dynamics`, on the
/// same output times as `series`). Elements without reactions (couplers, elements cardan does not
/// have) are left out.
pub fn add_reactions(
    series: &mut TimeSeries,
    doc: &Document,
    import: &Import,
    dynamics: &DynamicResults,
) {
    let path = |name: &str| format!("/{}/{name}", doc.name);
    for j in &doc.joints {
        let p = path(&j.name);
        let Some(el) = import.joints.iter().find(|e| e.path == p) else {
            continue;
        };
        let Some(r) = dynamics.reactions.iter().find(|r| r.name == el.spec.name) else {
            continue;
        };
        series.items.push(reaction_item(
            format!("{}Series", j.kind),
            p,
            import,
            dynamics,
            r,
            &el.spec.point_i,
        ));
    }
    for m in &doc.motions {
        let p = path(&m.name);
        let Some(el) = import.drivers.iter().find(|e| e.path == p) else {
            continue;
        };
        // A general motion is six driver rows (`<name>.x`, …): their wrenches add up.
        let name = &el.spec.name;
        let prefix = format!("{name}.");
        let mut rows = dynamics
            .drivers
            .iter()
            .filter(|d| &d.name == name || d.name.starts_with(&prefix))
            .map(|d| &d.reactions);
        let Some(first) = rows.next() else {
            continue;
        };
        let mut total = first.clone();
        for r in rows {
            for (sum, w) in total.on_i.iter_mut().zip(&r.on_i) {
                sum.force += w.force;
                sum.torque += w.torque;
            }
        }
        // MarkerI of a motion is its joint's MarkerI (checked by the import), or the pose
        // driver's point i.
        let point_i = match &el.spec.target {
            cardan_mechanism::DriverTarget::JointRotation { joint }
            | cardan_mechanism::DriverTarget::JointTranslation { joint } => import
                .joints
                .iter()
                .find(|j| &j.spec.name == joint)
                .map(|j| j.spec.point_i.clone()),
            cardan_mechanism::DriverTarget::Pose(t) => Some(t.point_i.clone()),
            _ => None,
        };
        let Some(point_i) = point_i else {
            continue;
        };
        let kind = match m.kind {
            crate::document::MotionKind::Rotational => "RotationalMotionSeries",
            crate::document::MotionKind::Translational => "TranslationalMotionSeries",
            crate::document::MotionKind::General => "GeneralMotionSeries",
        };
        series.items.push(reaction_item(
            kind.into(),
            p,
            import,
            dynamics,
            &total,
            &point_i,
        ));
    }
}

/// The local coordinates of point `name` of `body`: a named point, `origin` (the body frame's
/// origin) or `P(x;y;z)` (cardan-dynamics' name of an unnamed point).
fn local_point(import: &Import, body: &str, name: &str) -> Vector3<f64> {
    if let Some(p) = import
        .points
        .iter()
        .find(|p| p.body == body && p.name == name)
    {
        return p.value;
    }
    let xyz: Vec<f64> = name
        .strip_prefix("P(")
        .and_then(|s| s.strip_suffix(')'))
        .map(|s| s.split(';').filter_map(|c| c.parse().ok()).collect())
        .unwrap_or_default();
    match xyz[..] {
        [x, y, z] => Vector3::new(x, y, z),
        _ => Vector3::zeros(),
    }
}

/// The 6 rows of one joint or motion: the wrench on body i about its point `marker_i`.
fn reaction_item(
    kind: String,
    path: String,
    import: &Import,
    dynamics: &DynamicResults,
    r: &JointReactions,
    marker_i: &str,
) -> Item {
    let n = r.on_i.len();
    let mut rows: Vec<Row> = REACTION_ROWS
        .iter()
        .map(|l| Row {
            label: (*l).into(),
            input: 0.0,
            values: Vec::with_capacity(n),
        })
        .collect();
    // r_P − r_m in body i's frame (zero when the torque is already about MarkerI's origin).
    let offset = if r.point_i == marker_i {
        Vector3::zeros()
    } else {
        local_point(import, &r.body_i, &r.point_i) - local_point(import, &r.body_i, marker_i)
    };
    let body = (r.body_i != GROUND)
        .then(|| dynamics.kinematics.body(&r.body_i))
        .flatten();
    for (k, w) in r.on_i.iter().enumerate() {
        let a = body.map_or_else(Matrix3::identity, |b| cardan_eulerparam::a(&b.p[k]));
        let torque = w.torque + (a * offset).cross(&w.force);
        let values = [
            w.force.x, w.force.y, w.force.z, torque.x, torque.y, torque.z,
        ];
        for (row, x) in rows.iter_mut().zip(values) {
            row.values.push(x);
        }
    }
    Item {
        kind,
        path,
        line: 0,
        rows,
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
