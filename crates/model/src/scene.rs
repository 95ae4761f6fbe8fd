//! The animation's [`Scene`] from a model and its results: per body its poses at the output
//! times, its named points, its colour (the plots' palette by body index) and its geometry:
//! the model file's `geometry` items ([`crate::geometry`]) or, for a body without them, a
//! picture derived from the model:
//!
//! - a rod (thin cylinder) from the body origin (its centre of mass) to each of its points, and
//!   a small sphere at the origin;
//! - at each joint, on body i (on body j when i is the ground): a sphere for a spherical joint
//!   (and the other kinds without an axis), a short cylinder along the axis of a revolute,
//!   cylindrical, universal or other axis joint, a block along the axis of a prismatic joint;
//! - a small cube at each ground point;
//! - on every body, the curves of its curve elements: slots, tracks, paths, cam profiles and
//!   followers' faces and rollers, as chains of thin rods ([`crate::scene_curves`]).
//!
//! Sizes are fractions of the mechanism's extent L (the diagonal of the box around every body
//! origin and point over the run): rods of radius L/100, joint parts of L/30, markers of L/60.
//!
//! A dynamic run's end stops ([`stop_markers`]): per stop of `[[limit]]`, the joint it limits,
//! placed where that joint's part is drawn, and per frame of the scene whether the stop was
//! active (held closed or pressed at an output time since the frame before, or struck in
//! between: the `stops` table and the run's impacts) and its force; the impacts and releases as
//! events.

use crate::geometry::Declared;
use crate::table::Table;
use cardan_constraints::joints::Axes;
use cardan_constraints::JointKind;
use cardan_mechanism::{BodyId, Model, Results};
use cardan_report::{
    Body, BodyIncrement, Geometry, JointAxis, ModeShape, NamedPoint, Scene, Shape, StopEvent,
    StopEventKind, StopMarker,
};
use nalgebra::{Matrix3, Vector3, Vector4};

/// The scene of a run of `model` with `results`.
pub fn scene(name: &str, model: &Model, results: &Results, declared: &Declared) -> Scene {
    let extent = extent(model, results);
    let mut points = points_by_body(model);
    let histories: std::collections::HashMap<&str, &cardan_mechanism::BodyResults> = results
        .bodies
        .iter()
        .map(|b| (b.name.as_str(), b))
        .collect();
    let mut bodies: Vec<Body> = model
        .bodies()
        .iter()
        .enumerate()
        .map(|(k, info)| {
            let (positions, rotations) = match histories.get(info.name.as_str()) {
                Some(h) => (
                    h.r.iter().map(|r| [r.x, r.y, r.z]).collect(),
                    h.p.iter().map(|p| [p[0], p[1], p[2], p[3]]).collect(),
                ),
                None => (vec![], vec![]),
            };
            Body {
                name: info.name.clone(),
                colour: cardan_report::palette_colour(k),
                geometry: Vec::new(),
                points: std::mem::take(&mut points[k]),
                positions,
                rotations,
            }
        })
        .collect();
    let ground = bodies.len();
    bodies.push(Body {
        name: cardan_mechanism::GROUND.into(),
        colour: [0.35, 0.35, 0.37],
        geometry: Vec::new(),
        points: points.pop().unwrap_or_default(),
        positions: vec![],
        rotations: vec![],
    });
    let index = |id: BodyId| match id {
        BodyId::Ground => ground,
        BodyId::Moving(k) => k,
    };
    let derive: Vec<bool> = bodies
        .iter()
        .map(|b| !declared.bodies.contains_key(&b.name))
        .collect();
    for (k, b) in bodies.iter_mut().enumerate() {
        match declared.bodies.get(&b.name) {
            Some(items) => b.geometry = items.clone(),
            None if k == ground => {
                let cube = Shape::Box {
                    size: [extent / 60.0; 3],
                };
                b.geometry = b
                    .points
                    .iter()
                    .map(|p| Geometry::at(cube.clone(), p.local))
                    .collect();
            }
            None => b.geometry = rods(&b.points, extent),
        }
    }
    // A body with collision shapes is drawn as its shapes, not as rods between its points.
    let shapes = crate::scene_shapes::shape_geometry(model, extent);
    let mut shaped = vec![false; bodies.len()];
    for (on, _) in &shapes {
        shaped[index(*on)] = true;
    }
    for (k, b) in bodies.iter_mut().enumerate() {
        if derive[k] && shaped[k] && k != ground {
            b.geometry.clear();
        }
    }
    for (on, g) in shapes {
        bodies[index(on)].geometry.push(g);
    }
    let mut axes = Vec::new();
    for j in model.joints() {
        let kind = j.joint.kind();
        let (on, marker) = if j.body_i == BodyId::Ground {
            (index(j.body_j), j.joint.marker_j())
        } else {
            (index(j.body_i), j.joint.marker_i())
        };
        if derive[on] {
            bodies[on]
                .geometry
                .push(joint_part(kind, &marker.point, &marker.frame, extent));
        }
        if kind.info().axes != Axes::Unused {
            for (id, m, side) in [
                (j.body_i, j.joint.marker_i(), "i"),
                (j.body_j, j.joint.marker_j(), "j"),
            ] {
                let z = m.frame.column(2);
                axes.push(JointAxis {
                    name: format!("{}.{side}", j.name),
                    body: index(id),
                    point: [m.point.x, m.point.y, m.point.z],
                    direction: [z[0], z[1], z[2]],
                });
            }
        }
    }
    // The curves of the curve elements (slots, tracks, paths, cam profiles), on every body.
    for (on, rods) in crate::scene_curves::curve_rods(model, results, extent) {
        bodies[index(on)].geometry.extend(rods);
    }
    Scene {
        name: name.to_string(),
        times: results.times.clone(),
        bodies,
        axes,
        extent,
    }
}

/// A modal run's `modes` as the report animates them: per body of the scene (the moving
/// bodies in file order, then the ground, which does not move) the increment [δr; δp] of its
/// body coordinates, δp = ½ Gᵀ(p₀) δθ at the equilibrium's Euler parameters p₀ (the first time
/// of `results`).
pub fn mode_shapes(
    model: &Model,
    results: &Results,
    modes: &[cardan_dynamics::Mode],
) -> Vec<ModeShape> {
    if modes.is_empty() {
        return Vec::new();
    }
    // By name through a map: a search of the result list per body was O(n²), 80 s of a
    // 100,000-body run that has no modes at all.
    let by_name: std::collections::HashMap<&str, &cardan_mechanism::BodyResults> = (results.bodies)
        .iter()
        .map(|b| (b.name.as_str(), b))
        .collect();
    let rest: Vec<Option<Vector4<f64>>> = (model.bodies().iter())
        .map(|info| (by_name.get(info.name.as_str())).and_then(|b| b.p.first().copied()))
        .collect();
    modes
        .iter()
        .enumerate()
        .map(|(i, m)| {
            let mut bodies: Vec<BodyIncrement> = rest
                .iter()
                .zip(&m.shape)
                .map(|(p0, s)| match p0 {
                    Some(p0) => BodyIncrement {
                        dr: s.translation.into(),
                        dp: crate::analysis::modes::euler_increment(p0, &s.rotation).into(),
                    },
                    None => BodyIncrement::default(),
                })
                .collect();
            bodies.resize(rest.len() + 1, BodyIncrement::default());
            ModeShape {
                number: i + 1,
                kind: m.kind.name().to_string(),
                frequency: m.frequency,
                damping_ratio: m.damping_ratio,
                bodies,
            }
        })
        .collect()
}

/// The end stops of a run of `model` drawn in `scene` (its frames at `scene.times`), from the
/// run's `stops` table (rows: the time, then per stop of [`Model::stops`] held 0/1 and its force
/// in the unit of the column's header) and its impacts and releases. Frame k stands for
/// (t_{k−1}, t_k] (frame 0: up to t_0), so that the decimated frames of a long run miss no
/// contact: the stop is active in it if held or pressed (force ≠ 0) at an output time of that
/// interval, or struck in it. Nothing for a model without limits or a run without the table.
pub fn stop_markers(
    model: &Model,
    scene: &Scene,
    table: Option<&Table>,
    impacts: &[cardan_dynamics::ImpactEvent],
) -> (Vec<StopMarker>, Vec<StopEvent>) {
    let (Some(table), false) = (table, model.stops().is_empty()) else {
        return (Vec::new(), Vec::new());
    };
    let events = stop_events(model, impacts);
    let ground = scene.bodies.len() - 1;
    let index = |id: BodyId| match id {
        BodyId::Ground => ground,
        BodyId::Moving(k) => k,
    };
    let times = &scene.times;
    let markers = model
        .stops()
        .iter()
        .enumerate()
        .map(|(s, stop)| {
            let joint = &model.joints()[model.limits()[stop.limit].joint];
            let (body, marker) = if joint.body_i == BodyId::Ground {
                (index(joint.body_j), joint.joint.marker_j())
            } else {
                (index(joint.body_i), joint.joint.marker_i())
            };
            let z = marker.frame.column(2);
            let column = 1 + 2 * s;
            let unit = (table.columns.get(column))
                .and_then(|c| c.rsplit_once('[').map(|(_, u)| u.trim_end_matches(']')))
                .unwrap_or("")
                .to_string();
            let struck: Vec<f64> = (events.iter())
                .filter(|e| e.stop == s && e.kind != StopEventKind::Release)
                .map(|e| e.time)
                .collect();
            let (active, force) = frames(times, &table.rows, column, &struck);
            StopMarker {
                name: stop.name.clone(),
                joint: joint.name.clone(),
                body,
                point: [marker.point.x, marker.point.y, marker.point.z],
                direction: [z[0], z[1], z[2]],
                active,
                force,
                unit,
            }
        })
        .collect();
    (markers, events)
}

/// Per frame at `times`: whether the stop whose held flag is in `column` of `rows` (its force
/// in the next) was held or pressed at a row of the frame's interval (t_{k−1}, t_k], or struck
/// (`struck`, in time order) in it; and its force at the last row up to t_k.
fn frames(
    times: &[f64],
    rows: &[Vec<f64>],
    column: usize,
    struck: &[f64],
) -> (Vec<bool>, Vec<f64>) {
    let mut active = Vec::with_capacity(times.len());
    let mut force = Vec::with_capacity(times.len());
    let (mut row, mut hit) = (0, 0);
    let mut last = 0.0;
    for &t in times {
        let mut on = false;
        while row < rows.len() && rows[row][0] <= t {
            let (held, f) = (rows[row][column], rows[row][column + 1]);
            on |= held != 0.0 || f != 0.0;
            last = f;
            row += 1;
        }
        while hit < struck.len() && struck[hit] <= t {
            on = true;
            hit += 1;
        }
        active.push(on);
        force.push(last);
    }
    (active, force)
}

/// The run's impacts and releases by the stop's index in [`Model::stops`].
fn stop_events(model: &Model, impacts: &[cardan_dynamics::ImpactEvent]) -> Vec<StopEvent> {
    (impacts.iter())
        .filter_map(|e| {
            let stop = model.stops().iter().position(|s| s.name == e.stop)?;
            let kind = match (e.release, e.held) {
                (true, _) => StopEventKind::Release,
                (false, true) => StopEventKind::ImpactHeld,
                (false, false) => StopEventKind::Impact,
            };
            Some(StopEvent {
                time: e.time,
                stop,
                kind,
            })
        })
        .collect()
}

/// The named points of each moving body (by index), then of the ground (last), in body
/// coordinates.
fn points_by_body(model: &Model) -> Vec<Vec<NamedPoint>> {
    let n = model.bodies().len();
    let mut out = vec![Vec::new(); n + 1];
    for f in model.points() {
        let k = match f.body {
            BodyId::Ground => n,
            BodyId::Moving(k) => k,
        };
        out[k].push(NamedPoint {
            name: f.name.clone(),
            local: [f.local.x, f.local.y, f.local.z],
        });
    }
    out
}

/// The diagonal of the box around the ground points and every body origin and point over the
/// run (1 m if that box is a point).
fn extent(model: &Model, results: &Results) -> f64 {
    let mut lo = Vector3::repeat(f64::INFINITY);
    let mut hi = Vector3::repeat(f64::NEG_INFINITY);
    let mut add = |v: Vector3<f64>| {
        lo = lo.inf(&v);
        hi = hi.sup(&v);
    };
    for f in model.points() {
        if f.body == BodyId::Ground {
            add(f.local);
        }
    }
    let by_body = points_by_body(model);
    let histories: std::collections::HashMap<&str, &cardan_mechanism::BodyResults> = results
        .bodies
        .iter()
        .map(|b| (b.name.as_str(), b))
        .collect();
    for (k, info) in model.bodies().iter().enumerate() {
        let Some(h) = histories.get(info.name.as_str()) else {
            continue;
        };
        let pts: Vec<Vector3<f64>> = by_body[k].iter().map(|p| Vector3::from(p.local)).collect();
        for (r, p) in h.r.iter().zip(&h.p) {
            add(*r);
            if pts.is_empty() {
                continue;
            }
            let a = a_of(p);
            for s in &pts {
                add(r + a * s);
            }
        }
    }
    let d = (hi - lo).norm();
    if d.is_finite() && d > 0.0 {
        d
    } else {
        1.0
    }
}

/// A(p) of possibly not exactly normalized Euler parameters.
fn a_of(p: &Vector4<f64>) -> Matrix3<f64> {
    cardan_eulerparam::a(&(p / p.norm()))
}

/// A sphere at the origin and a rod from it to each point.
fn rods(points: &[NamedPoint], extent: f64) -> Vec<Geometry> {
    let radius = extent / 100.0;
    let mut out = vec![Geometry::at(
        Shape::Sphere {
            radius: 2.0 * radius,
        },
        [0.0; 3],
    )];
    for p in points {
        let s = Vector3::from(p.local);
        let length = s.norm();
        if length < radius {
            continue;
        }
        let mid = s / 2.0;
        out.push(Geometry {
            shape: Shape::Cylinder { radius, length },
            position: [mid.x, mid.y, mid.z],
            rotation: crate::scene_curves::along(&s),
        });
    }
    out
}

/// The part drawn at a joint: in the marker frame (columns x', y', z' in body coordinates) at
/// `point`.
fn joint_part(
    kind: JointKind,
    point: &Vector3<f64>,
    frame: &Matrix3<f64>,
    extent: f64,
) -> Geometry {
    let r = extent / 30.0;
    let shape = match kind {
        JointKind::Prismatic => Shape::Box {
            size: [1.6 * r, 1.6 * r, 4.0 * r],
        },
        _ if kind.info().axes == Axes::Unused || kind == JointKind::Spherical => {
            Shape::Sphere { radius: r }
        }
        _ => Shape::Cylinder {
            radius: r,
            length: 3.0 * r,
        },
    };
    let rotation = cardan_eulerparam::EulerParams::from_rotation_matrix(frame)
        .map(|p| [p.e0(), p.e().x, p.e().y, p.e().z])
        .unwrap_or([1.0, 0.0, 0.0, 0.0]);
    Geometry {
        shape,
        position: [point.x, point.y, point.z],
        rotation,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_frame_is_active_for_a_contact_or_an_impact_since_the_frame_before() {
        // Output rows (t, held, force) every 0.1 s; the scene keeps 0, 0.2, 0.4.
        let rows: Vec<Vec<f64>> = [
            [0.0, 0.0, 0.0],
            [0.1, 1.0, 2.0],
            [0.2, 0.0, 0.0],
            [0.3, 0.0, 0.0],
            [0.4, 0.0, 0.5],
        ]
        .iter()
        .map(|r| r.to_vec())
        .collect();
        let (active, force) = frames(&[0.0, 0.2, 0.4], &rows, 1, &[]);
        assert_eq!(active, [false, true, true]);
        assert_eq!(force, [0.0, 0.0, 0.5]);
        let (active, _) = frames(&[0.0, 0.2, 0.4], &rows[..4], 1, &[0.25]);
        assert_eq!(active, [false, true, true]);
    }
}
