//! The empty histories a recorder fills: one per body, named point, joint, driver, coupler and
//! work channel, with room reserved for the times to come, and the names of the points
//! reactions are taken about.

use crate::results::{
    CamForces, CouplerEfforts, DriverEfforts, DynamicResults, EnergyHistory, IntegrationStats,
    JointReactions,
};
use crate::system::Dynamics;
use cardan_constraints::Driver;
use cardan_mechanism::{
    BodyId, BodyResults, CouplerInfo, DriverInfo, JointResults, Model, Outputs, PointResults,
    Results,
};
use nalgebra::Vector3;

/// A named point of a moving body: the body's index and the point in its frame.
#[derive(Debug, Clone, Copy)]
pub(super) struct BodyPoint {
    pub body: usize,
    pub local: Vector3<f64>,
}

/// Results with no time yet and room for `capacity` (the histories `outputs` asks for), and
/// the named points of the moving bodies in the order of their histories.
pub(super) fn empty_results(
    d: &Dynamics,
    capacity: usize,
    outputs: Outputs,
) -> (DynamicResults, Vec<BodyPoint>) {
    let model = d.model;
    let (kinematics, points) = kinematic_histories(model, capacity, outputs);
    let e = || Vec::with_capacity(capacity);
    let res = DynamicResults {
        couplers: coupler_histories(model, capacity),
        kinematics,
        lambda: Vec::with_capacity(capacity),
        reactions: joint_reactions(model, capacity),
        drivers: driver_histories(model, capacity),
        cams: (model.curves().iter())
            .filter(|c| matches!(c.element, cardan_mechanism::CurveElement::Cam(_)))
            .map(|c| CamForces {
                name: c.name.clone(),
                force: Vec::with_capacity(capacity),
                normal_force: Vec::with_capacity(capacity),
            })
            .collect(),
        contacts: crate::results::ContactHistory {
            shapes: model.shapes().iter().map(|s| s.name.clone()).collect(),
            points: Vec::new(),
        },
        energy: EnergyHistory {
            kinetic: e(),
            gravity: e(),
            spring: e(),
            total: e(),
            elements: d.work_channels(capacity),
            work: e(),
            constraint_power: e(),
        },
        joint_space: (d.joint_space.as_ref())
            .map(|w| w.names.empty_like(capacity))
            .unwrap_or_default(),
        position_drift: e(),
        velocity_drift: e(),
        redundant: d.redundant.clone(),
        stats: IntegrationStats::default(),
    };
    (res, points)
}

/// The mechanism's results: bodies, named points of moving bodies (when asked) and joint
/// coordinates (when asked).
fn kinematic_histories(
    model: &Model,
    capacity: usize,
    outputs: Outputs,
) -> (Results, Vec<BodyPoint>) {
    let mut kin = Results {
        outputs: Some(outputs),
        times: Vec::with_capacity(capacity),
        residual: Vec::with_capacity(capacity),
        iterations: Vec::with_capacity(capacity),
        ..Results::default()
    };
    let cap = |on: bool| if on { capacity } else { 0 };
    let vel = outputs.needs_velocity();
    let acc = outputs.acceleration;
    for b in model.bodies() {
        kin.bodies.push(BodyResults {
            name: b.name.clone(),
            r: Vec::with_capacity(capacity),
            p: Vec::with_capacity(capacity),
            r_dot: Vec::with_capacity(cap(vel)),
            p_dot: Vec::with_capacity(cap(vel)),
            omega: Vec::with_capacity(cap(vel)),
            omega_local: Vec::with_capacity(cap(vel)),
            r_ddot: Vec::with_capacity(cap(acc)),
            p_ddot: Vec::with_capacity(cap(acc)),
            omega_dot: Vec::with_capacity(cap(acc)),
            omega_dot_local: Vec::with_capacity(cap(acc)),
        });
    }
    let mut points = Vec::new();
    if outputs.points {
        for p in model.points() {
            if let BodyId::Moving(k) = p.body {
                points.push(BodyPoint {
                    body: k,
                    local: p.local,
                });
                kin.points.push(PointResults {
                    body: p.body_name.clone(),
                    name: p.name.clone(),
                    position: Vec::with_capacity(capacity),
                    velocity: Vec::with_capacity(cap(vel)),
                    acceleration: Vec::with_capacity(cap(acc)),
                });
            }
        }
    }
    if outputs.joints {
        for j in model.joints() {
            kin.joints.push(JointResults {
                name: j.name.clone(),
                kind: j.joint.kind(),
                coordinates: j.joint.kind().info().coordinates,
                values: Vec::with_capacity(capacity),
                rates: Vec::new(),
                accelerations: Vec::new(),
            });
        }
    }
    kin.curves = model.curve_histories(capacity, (vel, acc));
    (kin, points)
}

/// The reaction history of element `name` between two bodies, each at a point of its frame.
fn reaction_history(
    model: &Model,
    capacity: usize,
    name: &str,
    (bi, pi): (BodyId, Vector3<f64>),
    (bj, pj): (BodyId, Vector3<f64>),
) -> JointReactions {
    JointReactions {
        name: name.to_string(),
        body_i: model.body_name(bi).to_string(),
        body_j: model.body_name(bj).to_string(),
        point_i: point_name(model, bi, &pi),
        point_j: point_name(model, bj, &pj),
        on_i: Vec::with_capacity(capacity),
        on_j: Vec::with_capacity(capacity),
    }
}

/// Every joint's reactions, about its marker points.
fn joint_reactions(model: &Model, capacity: usize) -> Vec<JointReactions> {
    model
        .joints()
        .iter()
        .map(|j| {
            let (pi, pj) = (j.joint.marker_i().point, j.joint.marker_j().point);
            reaction_history(model, capacity, &j.name, (j.body_i, pi), (j.body_j, pj))
        })
        .collect()
}

/// Every driver's multiplier, effort, power and reactions.
fn driver_histories(model: &Model, capacity: usize) -> Vec<DriverEfforts> {
    model
        .drivers()
        .iter()
        .map(|dr| DriverEfforts {
            name: dr.name.clone(),
            lambda: Vec::with_capacity(capacity),
            effort: Vec::with_capacity(capacity),
            power: Vec::with_capacity(capacity),
            reactions: {
                let (pi, pj) = driver_points(model, dr);
                reaction_history(model, capacity, &dr.name, (dr.body_i, pi), (dr.body_j, pj))
            },
        })
        .collect()
}

/// Every coupler's multiplier, efforts, tooth or thread force and reactions.
fn coupler_histories(model: &Model, capacity: usize) -> Vec<CouplerEfforts> {
    model
        .couplers()
        .iter()
        .map(|c| CouplerEfforts {
            name: c.name.clone(),
            lambda: Vec::with_capacity(capacity),
            efforts: Vec::with_capacity(capacity),
            force: has_force(c).then(|| Vec::with_capacity(capacity)),
            reactions: {
                let (pi, pj) = c.coupler.points();
                reaction_history(model, capacity, &c.name, (c.body_i, pi), (c.body_j, pj))
            },
        })
        .collect()
}

/// Whether a coupler has a tooth or thread force: every rack and screw, and a gear given by
/// radii.
fn has_force(c: &CouplerInfo) -> bool {
    c.kind() != "gear" || c.gear_radius_j.is_some()
}

/// The points a driver's reaction torques are taken about (body frames): its joint's points,
/// a general motion's frame origins, else the body frame origins.
pub(super) fn driver_points(model: &Model, dr: &DriverInfo) -> (Vector3<f64>, Vector3<f64>) {
    match (dr.joint, &dr.driver) {
        (Some(j), _) => (
            model.joints()[j].joint.marker_i().point,
            model.joints()[j].joint.marker_j().point,
        ),
        (None, Driver::Pose(p)) => (p.marker_i.point, p.marker_j.point),
        (None, _) => (Vector3::zeros(), Vector3::zeros()),
    }
}

/// The name of `body`'s point at `local` (body frame), or `origin` for the body frame origin,
/// else `P(x;y;z)` (body-frame components, m).
fn point_name(model: &Model, body: BodyId, local: &Vector3<f64>) -> String {
    match model
        .points()
        .iter()
        .find(|p| p.body == body && p.local == *local)
    {
        Some(p) => p.name.clone(),
        None if *local == Vector3::zeros() => "origin".into(),
        None => format!("P({};{};{})", local.x, local.y, local.z),
    }
}
