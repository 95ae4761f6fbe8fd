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
//! dynamics: `add_reactions`), in OndselSolver's conventions: `FXonI FYonI FZonI` the force the
//! joint (or motion) exerts on the part that carries MarkerI, `TXonI TYonI TZonI` the torque on
//! that part about MarkerI's origin, global components. cardan's reaction on body i of a joint
//! (body i = MarkerI's part, [`fn@crate::import`]) is taken about the joint's point P_i; when
//! P_i is not MarkerI's origin m, the torque is moved there: T_m = T_P + (r_P − r_m) × F. Couplers
//! (gear, rack and pinion, screw) get no series: cardan writes their law in joint coordinates, so
//! the wrench of their equation is split between the coupled joints differently from OndselSolver's
//! (only the efforts about the axes are physical; the gears' joint series carry the rest).

use crate::document::Document;
use crate::import::{BodyMap, Import};
use crate::series::REACTION_ROWS;
use crate::series::{Item, Row, TimeSeries, PART_ROWS};
use cardan_dynamics::{DynamicResults, JointReactions};
use cardan_mechanism::{BodyResults, Results, GROUND};
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

/// The rows that carry one length (X Y Z, VX VY VZ, AX AY AZ of every part and of the
/// assembly, and the reaction torques TXonI TYonI TZonI; angles, angular rates and forces carry
/// none): [`SeriesPlan::new`]'s `length_factor` scales them, e.g. 1000 to write a series
/// computed in SI into a file in millimetres.
const LENGTHS: [&str; 12] = [
    "X", "Y", "Z", "VX", "VY", "VZ", "AX", "AY", "AZ", "TXonI", "TYonI", "TZonI",
];

/// Where an item's values come from.
enum Source {
    /// The assembly: zeros.
    Ground,
    /// A part: body `body` of the results, through the part frame of `map`.
    Part { body: usize, map: Box<BodyMap> },
    /// A joint or motion.
    Wrench(Wrench),
}

/// The reaction of a joint or motion: the sum of the wrenches on body i of the reactions
/// `joints` and the driver rows `drivers`, the torque moved to MarkerI's origin:
/// T_m = T_P + (A_i o) × F, o = r_P − r_m in body i's frame; `body`: body i in the results
/// (`None`: ground).
struct Wrench {
    joints: Vec<usize>,
    drivers: Vec<usize>,
    body: Option<usize>,
    offset: Vector3<f64>,
}

/// A solved `TimeSeries` before its values: the items (kinds, paths, row labels and inputs;
/// the rows' values empty) and how to compute every row at any time of a run's results, so
/// that the series can be built whole ([`SeriesPlan::series`]) or frame by frame as a run
/// streams ([`SeriesPlan::frame`]).
pub struct SeriesPlan {
    items: Vec<Item>,
    sources: Vec<Source>,
    /// Per data row: the factor of its values and input (`length_factor` or 1).
    factors: Vec<f64>,
}

impl SeriesPlan {
    /// The series of `doc` imported as `import` for results laid out as `results` (any frame
    /// of the run): the assembly and every part; with `dynamics` (a dynamic or inverse dynamics
    /// run), also the reactions of every joint and motion (`reaction_sources`). Lengths are
    /// multiplied by `length_factor` (`LENGTHS`).
    pub fn new(
        doc: &Document,
        import: &Import,
        results: &Results,
        dynamics: Option<&DynamicResults>,
        length_factor: f64,
    ) -> Self {
        let rows = |labels: &[&str], inputs: &[f64]| -> Vec<Row> {
            (labels.iter().zip(inputs))
                .map(|(l, &input)| Row {
                    label: (*l).into(),
                    input,
                    values: Vec::new(),
                })
                .collect()
        };
        let mut items = vec![Item {
            kind: "AssemblySeries".into(),
            path: format!("/{}", doc.name),
            line: 0,
            rows: rows(&PART_ROWS, &[0.0; 18]),
        }];
        let mut sources = vec![Source::Ground];
        for (part, map) in doc.parts.iter().zip(&import.bodies) {
            let Some(body) = body_index(results, &map.body.name) else {
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
            items.push(Item {
                kind: "PartSeries".into(),
                path: map.path.clone(),
                line: 0,
                rows: rows(&PART_ROWS, &input),
            });
            sources.push(Source::Part {
                body,
                map: Box::new(map.clone()),
            });
        }
        if let Some(d) = dynamics {
            for (kind, path, source) in reaction_sources(doc, import, d) {
                items.push(Item {
                    kind,
                    path,
                    line: 0,
                    rows: rows(&REACTION_ROWS, &[0.0; 6]),
                });
                sources.push(source);
            }
        }
        let factors: Vec<f64> = (items.iter().flat_map(|i| &i.rows))
            .map(|r| match LENGTHS.contains(&r.label.as_str()) {
                true => length_factor,
                false => 1.0,
            })
            .collect();
        let mut row = factors.iter();
        for r in items.iter_mut().flat_map(|i| i.rows.iter_mut()) {
            r.input *= row.next().copied().unwrap_or(1.0);
        }
        Self {
            items,
            sources,
            factors,
        }
    }

    /// The items: kinds, paths, row labels and inputs (no values).
    pub fn items(&self) -> &[Item] {
        &self.items
    }

    /// Data rows (all items').
    pub fn rows(&self) -> usize {
        self.factors.len()
    }

    /// Appends every row's value at frame `k` of `results` (with `dynamics`, its reactions;
    /// `results` is then `dynamics.kinematics`) to `out`, in item order.
    pub fn frame(
        &self,
        results: &Results,
        dynamics: Option<&DynamicResults>,
        k: usize,
        out: &mut Vec<f64>,
    ) {
        let first = out.len();
        for source in &self.sources {
            match source {
                Source::Ground => out.extend([0.0; 18]),
                Source::Part { body, map } => {
                    out.extend(part_at(&results.bodies[*body], map, k));
                }
                Source::Wrench(w) => out.extend(w.at(results, dynamics, k)),
            }
        }
        for (v, f) in out[first..].iter_mut().zip(&self.factors) {
            *v *= f;
        }
    }

    /// The whole series of a run's results (every frame).
    pub fn series(&self, results: &Results, dynamics: Option<&DynamicResults>) -> TimeSeries {
        let n = results.times.len();
        let mut items = self.items.clone();
        for r in items.iter_mut().flat_map(|i| i.rows.iter_mut()) {
            r.values.reserve_exact(n);
        }
        let mut values = Vec::with_capacity(self.rows());
        for k in 0..n {
            values.clear();
            self.frame(results, dynamics, k, &mut values);
            let rows = items.iter_mut().flat_map(|i| i.rows.iter_mut());
            for (row, &v) in rows.zip(&values) {
                row.values.push(v);
            }
        }
        TimeSeries {
            times: results.times.clone(),
            items,
        }
    }
}

/// The index of body `name` in the results.
fn body_index(results: &Results, name: &str) -> Option<usize> {
    results.bodies.iter().position(|b| b.name == name)
}

/// A part's 18 values at frame k: its part frame's origin P and Bryant angles, v_P, ω, a_P, α
/// (module docs).
fn part_at(body: &BodyResults, map: &BodyMap, k: usize) -> [f64; 18] {
    let a_cm = cardan_eulerparam::a(&body.p[k]);
    let f = map.part_frame(&body.r[k], &a_cm);
    let s = f.position - body.r[k];
    let pick = |v: &Vec<Vector3<f64>>| v.get(k).copied().unwrap_or_else(Vector3::zeros);
    let (w, al) = (pick(&body.omega), pick(&body.omega_dot));
    let vel = pick(&body.r_dot) + w.cross(&s);
    let acc = pick(&body.r_ddot) + al.cross(&s) + w.cross(&w.cross(&s));
    part_values(f.position, &f.rotation, vel, w, acc, al)
}

impl Wrench {
    /// The 6 values at frame k of `results` (zeros without `dynamics`).
    fn at(&self, results: &Results, dynamics: Option<&DynamicResults>, k: usize) -> [f64; 6] {
        let Some(d) = dynamics else {
            return [0.0; 6];
        };
        let mut on_i = (self.joints.iter().map(|&j| &d.reactions[j].on_i[k])).chain(
            self.drivers
                .iter()
                .map(|&i| &d.drivers[i].reactions.on_i[k]),
        );
        let Some(first) = on_i.next() else {
            return [0.0; 6];
        };
        let (mut force, mut torque) = (first.force, first.torque);
        for w in on_i {
            force += w.force;
            torque += w.torque;
        }
        let a = self.body.map_or_else(Matrix3::identity, |b| {
            cardan_eulerparam::a(&results.bodies[b].p[k])
        });
        let torque = torque + (a * self.offset).cross(&force);
        [force.x, force.y, force.z, torque.x, torque.y, torque.z]
    }
}

/// The series of a kinematic run: the assembly (zeros) and every part.
pub fn time_series(doc: &Document, import: &Import, results: &Results) -> TimeSeries {
    SeriesPlan::new(doc, import, results, None, 1.0).series(results, None)
}

/// The reaction items of every joint and motion of `doc` (file order: joints, then motions)
/// that `dynamics` has reactions of: kind, path and source. Elements without reactions
/// (couplers, elements cardan does not have) are left out.
fn reaction_sources(
    doc: &Document,
    import: &Import,
    dynamics: &DynamicResults,
) -> Vec<(String, String, Source)> {
    let path = |name: &str| format!("/{}/{name}", doc.name);
    let mut out = Vec::new();
    for j in &doc.joints {
        let p = path(&j.name);
        let Some(el) = import.joints.iter().find(|e| e.path == p) else {
            continue;
        };
        let Some(i) = (dynamics.reactions.iter()).position(|r| r.name == el.spec.name) else {
            continue;
        };
        let r = &dynamics.reactions[i];
        let source = wrench(import, dynamics, r, &el.spec.point_i, vec![i], Vec::new());
        out.push((format!("{}Series", j.kind), p, source));
    }
    for m in &doc.motions {
        let p = path(&m.name);
        let Some(el) = import.drivers.iter().find(|e| e.path == p) else {
            continue;
        };
        // A general motion is six driver rows (`<name>.x`, …): their wrenches add up.
        let name = &el.spec.name;
        let prefix = format!("{name}.");
        let rows: Vec<usize> = (dynamics.drivers.iter().enumerate())
            .filter(|(_, d)| &d.name == name || d.name.starts_with(&prefix))
            .map(|(i, _)| i)
            .collect();
        let Some(&first) = rows.first() else {
            continue;
        };
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
        let r = &dynamics.drivers[first].reactions;
        let source = wrench(import, dynamics, r, &point_i, Vec::new(), rows);
        out.push((kind.into(), p, source));
    }
    out
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

/// The source of a joint's or motion's 6 rows: the wrench of the reactions `joints` and driver
/// rows `drivers` on body i (`r`'s, about its point P_i) moved to MarkerI's origin `marker_i`.
fn wrench(
    import: &Import,
    dynamics: &DynamicResults,
    r: &JointReactions,
    marker_i: &str,
    joints: Vec<usize>,
    drivers: Vec<usize>,
) -> Source {
    // r_P − r_m in body i's frame (zero when the torque is already about MarkerI's origin).
    let offset = if r.point_i == marker_i {
        Vector3::zeros()
    } else {
        local_point(import, &r.body_i, &r.point_i) - local_point(import, &r.body_i, marker_i)
    };
    let body = (r.body_i != GROUND)
        .then(|| body_index(&dynamics.kinematics, &r.body_i))
        .flatten();
    Source::Wrench(Wrench {
        joints,
        drivers,
        body,
        offset,
    })
}

/// The input text's lines before its `TimeSeries` (all of them if it has none), each ended
/// by a newline: the start of a solved file.
pub fn before_time_series(input: &str) -> String {
    let mut out = String::with_capacity(input.len());
    for line in input.lines() {
        if line.trim_end() == "TimeSeries" {
            break;
        }
        out.push_str(line);
        out.push('\n');
    }
    out
}

/// The input text with its `TimeSeries` (if any) replaced by `series`.
pub fn solved_text(input: &str, series: &TimeSeries) -> String {
    let mut out = before_time_series(input);
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
