//! Stress: random mechanisms (proptest). Chains (body k joined to k − 1 by a random joint type)
//! and closed loops (ground–crank–coupler–rocker–ground with random joint types), with
//! dimensions from 1e-3 to 1e3 m, masses from 1e-3 to 1e3 kg and random orientations.
//!
//! Every mechanism is consistent by construction: the configuration (body poses, joint points
//! and axes in global coordinates) is drawn first, then each joint's local points and axes are
//! computed from it, so the initial pose is assembled. The poses are then perturbed and the
//! mechanism reassembled. Checked:
//! - `build` succeeds; assembly converges (scaled residual < 1e-9) or returns a typed error;
//! - the sparse rank analysis reports the dense one's redundant equations;
//! - the DOF is the one expected (chains: the sum of the joints' relative DOF; single loops in
//!   the sum of the joints' freedoms minus the rank of their twists, computed independently
//!   from the constructed configuration);
//! - when drivers = DOF, a short kinematic run succeeds (chains) or stops with a typed error
//!   (loops may reach a limit position); no NaN anywhere in the results;
//! - bounded time per case (iteration caps; asserted < 20 s).
//!
//! Case count: `CARDAN_STRESS_CASES` (default 12 per property, the CI subset;
//! `cargo xtask stress` runs 1000).

mod stress_common;

use cardan_constraints::joints::Block;
use cardan_constraints::{KindInfo, KINDS};
use cardan_mechanism::{
    AnalysisError, AssemblyOptions, Body, DriverSpec, JointKind, JointSpec, KinematicOptions,
    MechanismBuilder, Model, Orientation, Results, TimeFunction, GROUND,
};
use cardan_solver::{RankAnalysis, RankOptions};
use nalgebra::{Matrix3, UnitQuaternion, Vector3, Vector4};
use proptest::prelude::*;
use std::sync::LazyLock;
use std::time::{Duration, Instant};
use stress_common::{cases, results_finite};

/// One body's pose: position (in units of L) and a rotation.
#[derive(Debug, Clone)]
struct Pose {
    r: Vector3<f64>,
    q: UnitQuaternion<f64>,
}

fn unit(v: [f64; 3], fallback: Vector3<f64>) -> Vector3<f64> {
    let v = Vector3::from(v);
    if v.norm() < 1e-3 {
        fallback
    } else {
        v.normalize()
    }
}

fn pose() -> impl Strategy<Value = Pose> {
    (
        prop::array::uniform3(-1.0f64..1.0),
        prop::array::uniform4(-1.0f64..1.0),
    )
        .prop_map(|(r, q)| {
            let q = Vector4::from(q);
            let q = if q.norm() < 1e-2 {
                Vector4::new(1.0, 0.0, 0.0, 0.0)
            } else {
                q.normalize()
            };
            Pose {
                r: Vector3::from(r),
                q: UnitQuaternion::from_quaternion(nalgebra::Quaternion::new(
                    q[0], q[1], q[2], q[3],
                )),
            }
        })
}

/// One joint of the configuration: kind, point offset, axis and reference direction (global).
#[derive(Debug, Clone)]
struct JointDraw {
    kind: usize,
    offset: [f64; 3],
    axis: [f64; 3],
    other: [f64; 3],
    driven_rate: f64,
}

fn joint_draw(kinds: &'static [usize]) -> impl Strategy<Value = JointDraw> {
    (
        prop::sample::select(kinds),
        prop::array::uniform3(-1.0f64..1.0),
        prop::array::uniform3(-1.0f64..1.0),
        prop::array::uniform3(-1.0f64..1.0),
        -1.0f64..1.0,
    )
        .prop_map(|(kind, offset, axis, other, driven_rate)| JointDraw {
            kind,
            offset,
            axis,
            other,
            driven_rate,
        })
}

/// A mechanism drawn at random, with what to expect of it.
#[derive(Debug)]
struct Drawn {
    builder: MechanismBuilder,
    length: f64,
    expected_dof: usize,
    drivers: usize,
}

/// Adds body `name` with pose `pose` (positions scaled by `l`), mass `m`.
fn add_body(b: &mut MechanismBuilder, name: &str, pose: &Pose, l: f64, m: f64) {
    let p = pose.q.quaternion();
    let j = m * l * l / 12.0;
    b.body(
        Body::new(name)
            .mass(m)
            .inertia(Matrix3::from_diagonal(&Vector3::new(j, 1.5 * j, 2.0 * j)))
            .position(pose.r * l)
            .orientation(Orientation::EulerParams([p.w, p.i, p.j, p.k])),
    );
}

/// Places joint `name` of `draw` between `(bi, pose_i)` and `(bj, pose_j)` (None = ground) at the
/// global point `at`, declaring the local points and vectors so that it is assembled. Returns
/// the joint kind.
#[allow(clippy::too_many_arguments)]
fn add_joint(
    b: &mut MechanismBuilder,
    name: &str,
    draw: &JointDraw,
    (bi, pose_i): (&str, Option<&Pose>),
    (bj, pose_j): (&str, Option<&Pose>),
    at: Vector3<f64>,
    l: f64,
    drive: bool,
) -> (JointKind, usize, Vec<[f64; 6]>) {
    let kind = KINDS[draw.kind].kind;
    let info = kind.info();
    let u = unit(draw.axis, Vector3::z());
    let w = Vector3::from(draw.other);
    let mut v = w - u * u.dot(&w);
    if v.norm() < 1e-2 {
        v = u.cross(&Vector3::x());
        if v.norm() < 1e-2 {
            v = u.cross(&Vector3::y());
        }
    }
    let v = v.normalize();
    let local = |pose: Option<&Pose>, g: Vector3<f64>, point: bool| -> Vector3<f64> {
        match pose {
            None => g,
            Some(p) => {
                let g = if point { g - p.r * l } else { g };
                p.q.inverse_transform_vector(&g)
            }
        }
    };
    // A length block needs P_j away from P_i: along the axis for a point distance, across it
    // for a distance from the axis line.
    let at_j = match (info.length, info.blocks.contains(&Block::RadialDistance)) {
        (true, true) => at + 0.5 * l * v,
        (true, false) => at + 0.5 * l * u,
        _ => at,
    };
    let (pi, pj) = (format!("{name}_Pi"), format!("{name}_Pj"));
    let (ui, uj, xi, xj) = (
        format!("{name}_ui"),
        format!("{name}_uj"),
        format!("{name}_xi"),
        format!("{name}_xj"),
    );
    b.point(bi, &pi, local(pose_i, at, true));
    b.point(bj, &pj, local(pose_j, at_j, true));
    // Universal and perpendicular: the axes are perpendicular (u on i, v on j).
    let (arm_j, x_j) = if matches!(
        kind,
        JointKind::Universal | JointKind::Perpendicular | JointKind::LineInPlane
    ) {
        (v, u)
    } else if kind == JointKind::Cone {
        // A cone is refused at α = 0: z_j drawn 45° from z_i, in the plane of u and v.
        ((u + v).normalize(), u.cross(&v))
    } else {
        (u, v)
    };
    b.vector(bi, &ui, local(pose_i, u, false));
    b.vector(bj, &uj, local(pose_j, arm_j, false));
    b.vector(bi, &xi, local(pose_i, v, false));
    b.vector(bj, &xj, local(pose_j, x_j, false));
    let mut js = JointSpec::new(name, kind, (bi, &pi), (bj, &pj));
    if info.axes.on_j() {
        js = js.axes(&ui, &uj);
        if info.x_axes && kind != JointKind::Universal {
            js = js.x_axes(&xi, &xj);
        }
    } else if info.axes.accepted() {
        js = js.axis_i(&ui);
        if info.x_axes {
            js = js.x_axis_i(&xi);
        }
    }
    b.joint(js);
    let mut drivers = 0;
    if drive {
        let rate = draw.driven_rate;
        if info.rotation.is_some() {
            b.driver(DriverSpec::rotation(
                format!("{name}_rot"),
                name,
                TimeFunction::Polynomial(vec![0.0, rate]),
            ));
            drivers += 1;
        }
        if info.translation.is_some() {
            b.driver(DriverSpec::translation(
                format!("{name}_slide"),
                name,
                TimeFunction::Polynomial(vec![0.0, 0.1 * l * rate]),
            ));
            drivers += 1;
        }
    }
    // The relative twists (ω; v_O) of body j with respect to body i the joint allows, at the
    // constructed configuration: an independent description of the joint's freedom (so this
    // match is exhaustive: a new kind states its freedom here).
    let rot = |axis: Vector3<f64>, p: Vector3<f64>| {
        let v = p.cross(&axis);
        [axis.x, axis.y, axis.z, v.x, v.y, v.z]
    };
    let tra = |a: Vector3<f64>| [0.0, 0.0, 0.0, a.x, a.y, a.z];
    let (e1, e2, e3) = (Vector3::x(), Vector3::y(), Vector3::z());
    let w = u.cross(&v);
    let twists = match kind {
        JointKind::Spherical => vec![rot(e1, at), rot(e2, at), rot(e3, at)],
        JointKind::Universal => vec![rot(u, at), rot(v, at)],
        JointKind::Revolute => vec![rot(u, at)],
        JointKind::Cylindrical => vec![rot(u, at), tra(u)],
        JointKind::Prismatic => vec![tra(u)],
        JointKind::Fixed => vec![],
        // Rotations about P_j, plus the rotations about P_i that move P_j across d (d ∥ u).
        JointKind::SphericalSpherical => vec![
            rot(e1, at_j),
            rot(e2, at_j),
            rot(e3, at_j),
            rot(v, at),
            rot(w, at),
        ],
        JointKind::Planar => vec![rot(u, at), tra(v), tra(w)],
        // z_j ⟂ z_i (u on i, v on j, as for the universal arms): every translation, the rotations
        // about the two axes.
        JointKind::Perpendicular => vec![tra(e1), tra(e2), tra(e3), rot(u, at), rot(v, at)],
        JointKind::PointInLine => vec![rot(e1, at), rot(e2, at), rot(e3, at), tra(u)],
        JointKind::PointInPlane => vec![rot(e1, at), rot(e2, at), rot(e3, at), tra(v), tra(w)],
        // Plane normal u on i, line v on j: slide in the plane, turn about the normal and the line.
        JointKind::LineInPlane => vec![tra(v), tra(w), rot(u, at), rot(v, at)],
        JointKind::ParallelAxes => vec![tra(e1), tra(e2), tra(e3), rot(u, at)],
        // Drawn at angle 0 about x_i = v (z_j = z_i = u): z_j may turn in the plane of u and v
        // (about w) and about itself (u).
        JointKind::Angle => vec![tra(e1), tra(e2), tra(e3), rot(u, at), rot(w, at)],
        // z_j 45° from z_i = u in the plane of u and v: every translation, the rotations that
        // keep z_iᵀz_j (ω ⟂ z_j × z_i ∥ w).
        JointKind::Cone => vec![tra(e1), tra(e2), tra(e3), rot(u, at), rot(v, at)],
        JointKind::NoRotation => vec![tra(e1), tra(e2), tra(e3)],
        // Straight shafts along u: bends about the two cross directions, no twist.
        JointKind::ConstantVelocity => vec![rot(v, at), rot(w, at)],
        // P_j across the axis at distance ℓ: j turns about its own axis, orbits i's, slides.
        JointKind::RevCyl => vec![rot(u, at_j), rot(u, at), tra(u)],
        JointKind::CylSph => vec![
            rot(e1, at_j),
            rot(e2, at_j),
            rot(e3, at_j),
            rot(u, at),
            tra(u),
        ],
        JointKind::RevRev => vec![rot(u, at_j), rot(u, at)],
    };
    (kind, drivers, twists)
}

/// Degrees of freedom of a single loop from its joints' twists: Σ f − rank [ξ].
fn loop_dof(twists: &[[f64; 6]]) -> usize {
    if twists.is_empty() {
        return 0;
    }
    let m = nalgebra::DMatrix::from_fn(6, twists.len(), |r, c| twists[c][r]);
    let sv = m.svd(false, false).singular_values;
    let tol = 1e-8 * sv.max().max(1.0);
    twists.len() - sv.iter().filter(|&&x| x > tol).count()
}

/// Indices into the kind table of the kinds that pass `pick`.
fn kinds_where(pick: fn(&KindInfo) -> bool) -> Vec<usize> {
    (0..KINDS.len()).filter(|&k| pick(&KINDS[k])).collect()
}

/// All joint kinds.
static ALL: LazyLock<Vec<usize>> = LazyLock::new(|| kinds_where(|_| true));
/// The drivable ones: every relative freedom has a driver (revolute, cylindrical, prismatic,
/// fixed).
static DRIVABLE: LazyLock<Vec<usize>> = LazyLock::new(|| {
    kinds_where(|k| {
        let driven = usize::from(k.rotation.is_some()) + usize::from(k.translation.is_some());
        k.relative_dof() == driven
    })
});
/// Loop joints (a rigid joint is left out: it merges two bodies of a four-body loop).
static LOOP: LazyLock<Vec<usize>> = LazyLock::new(|| kinds_where(|k| k.relative_dof() > 0));

fn chain() -> impl Strategy<Value = Drawn> {
    (any::<bool>(), 1usize..=4, -3.0f64..3.0, -3.0f64..3.0)
        .prop_flat_map(|(driven, n, log_l, log_m)| {
            let kinds: &'static [usize] = if driven {
                DRIVABLE.as_slice()
            } else {
                ALL.as_slice()
            };
            (
                Just(driven),
                Just(10f64.powf(log_l)),
                Just(10f64.powf(log_m)),
                prop::collection::vec(pose(), n),
                prop::collection::vec(joint_draw(kinds), n),
            )
        })
        .prop_map(|(driven, l, m, poses, joints)| {
            let mut b = MechanismBuilder::new();
            for (k, p) in poses.iter().enumerate() {
                add_body(&mut b, &format!("b{k}"), p, l, m);
            }
            let (mut dof, mut drivers) = (0, 0);
            for k in 0..poses.len() {
                let parent = if k == 0 {
                    (GROUND.to_string(), None, Vector3::zeros())
                } else {
                    (
                        format!("b{}", k - 1),
                        Some(&poses[k - 1]),
                        poses[k - 1].r * l,
                    )
                };
                let at =
                    (parent.2 + poses[k].r * l) / 2.0 + 0.3 * l * Vector3::from(joints[k].offset);
                let (kind, d, _) = add_joint(
                    &mut b,
                    &format!("J{k}"),
                    &joints[k],
                    (&parent.0, parent.1),
                    (&format!("b{k}"), Some(&poses[k])),
                    at,
                    l,
                    driven,
                );
                dof += kind.info().relative_dof();
                drivers += d;
            }
            Drawn {
                builder: b,
                length: l,
                expected_dof: dof,
                drivers,
            }
        })
}

/// Ground–crank–coupler–rocker–ground: four joints at O2, A, B, O4 of random kinds; the crank
/// joint is a driven revolute when `driven`.
fn closed_loop() -> impl Strategy<Value = Drawn> {
    (
        any::<bool>(),
        -3.0f64..3.0,
        -3.0f64..3.0,
        prop::collection::vec(pose(), 3),
        prop::collection::vec(prop::array::uniform3(-1.0f64..1.0), 4),
        prop::collection::vec(joint_draw(LOOP.as_slice()), 4),
    )
        .prop_map(|(driven, log_l, log_m, poses, points, mut joints)| {
            let (l, m) = (10f64.powf(log_l), 10f64.powf(log_m));
            if driven {
                joints[0].kind = 2;
            }
            let mut b = MechanismBuilder::new();
            let names = ["crank", "coupler", "rocker"];
            for k in 0..3 {
                add_body(&mut b, names[k], &poses[k], l, m);
            }
            // A skew quadrilateral in general position, randomly deformed (shrinking leads
            // back to it, not to the degenerate all-points-equal case).
            let base = [
                Vector3::new(0.0, 0.0, 0.0),
                Vector3::new(1.0, 0.2, 0.1),
                Vector3::new(1.3, 1.1, 0.7),
                Vector3::new(-0.2, 1.4, 0.3),
            ];
            let pts: Vec<Vector3<f64>> = points
                .iter()
                .zip(base)
                .map(|(p, b)| (b + 0.3 * Vector3::from(*p)) * l)
                .collect();
            // Axes in general position likewise.
            let axes = [
                [0.1, 0.3, 1.0],
                [0.8, -0.3, 0.5],
                [-0.2, 0.9, 0.4],
                [0.6, 0.5, -0.6],
            ];
            for (j, a) in joints.iter_mut().zip(axes) {
                for c in 0..3 {
                    j.axis[c] = a[c] + 0.3 * j.axis[c];
                    j.other[c] = a[(c + 1) % 3] - 0.5 * a[c] + 0.3 * j.other[c];
                }
            }
            let ends: [(&str, Option<&Pose>); 5] = [
                (GROUND, None),
                ("crank", Some(&poses[0])),
                ("coupler", Some(&poses[1])),
                ("rocker", Some(&poses[2])),
                (GROUND, None),
            ];
            let mut all_twists = Vec::new();
            let mut drivers = 0;
            for k in 0..4 {
                let (_, d, twists) = add_joint(
                    &mut b,
                    &format!("L{k}"),
                    &joints[k],
                    ends[k],
                    ends[k + 1],
                    pts[k],
                    l,
                    driven && k == 0,
                );
                all_twists.extend(twists);
                drivers += d;
            }
            Drawn {
                builder: b,
                length: l,
                // Lengths enter the twists; work in units of L.
                expected_dof: loop_dof(
                    &all_twists
                        .iter()
                        .map(|t| [t[0], t[1], t[2], t[3] / l, t[4] / l, t[5] / l])
                        .collect::<Vec<_>>(),
                ),
                drivers,
            }
        })
}

/// Moves every body by up to `eps` L and rotates it by up to about `eps` rad.
fn perturb(model: &Model, ws: &mut cardan_mechanism::Workspace, d: &[f64], eps: f64, l: f64) {
    for k in 0..model.num_bodies() {
        let e = |i: usize| d[(6 * k + i) % d.len()];
        let dr = Vector3::new(e(0), e(1), e(2)) * eps * l;
        let dp = Vector4::new(0.0, e(3), e(4), e(5)) * eps;
        let (r, p) = (ws.r(k), ws.p(k));
        ws.set_pose(k, r + dr, p + dp);
    }
}

fn scaled_residual(model: &Model, ws: &cardan_mechanism::Workspace, t: f64) -> f64 {
    let mut phi = vec![0.0; model.num_equations()];
    model.eval_phi(ws, t, &mut phi);
    phi.iter()
        .zip(model.equation_scales())
        .map(|(v, s)| (v / s).abs())
        .fold(0.0, f64::max)
}

/// The whole check of one drawn mechanism. `must_run`: a kinematic run with drivers = DOF must
/// succeed (open chains cannot reach a singular configuration under joint drivers).
fn check(d: &Drawn, shake: &[f64], must_run: bool) -> Result<(), TestCaseError> {
    let start = Instant::now();
    let model = match d.builder.build() {
        Ok(m) => m,
        Err(e) => return Err(TestCaseError::fail(format!("build failed: {e}"))),
    };
    let mut ws = model.workspace();
    // The initial configuration is assembled by construction.
    let r0 = scaled_residual(&model, &ws, 0.0);
    prop_assert!(r0 < 1e-9, "constructed pose not assembled: {r0:e}");
    perturb(&model, &mut ws, shake, 1e-3, d.length);
    match model.assemble(&mut ws, &AssemblyOptions::default()) {
        Ok(rep) => {
            prop_assert!(rep.residual.is_finite());
            let r = scaled_residual(&model, &ws, 0.0);
            prop_assert!(r < 1e-9, "assembled residual {r:e}");
            prop_assert!(ws.state().iter().all(|x| x.is_finite()));
        }
        // A typed error is acceptable; make sure it is one and carries finite numbers.
        Err(e @ AnalysisError::AssemblyFailed { .. }) => {
            return Err(TestCaseError::fail(format!(
                "assembly from a 1e-3 perturbation failed: {e}"
            )))
        }
        Err(e) => return Err(TestCaseError::fail(format!("unexpected error: {e}"))),
    }
    let dof = model
        .dof(&ws)
        .map_err(|e| TestCaseError::fail(e.to_string()))?;
    prop_assert_eq!(dof.dof, d.expected_dof, "{}", dof);
    // The sparse rank analysis finds the dense one's redundant equations (joints and drivers).
    let mut slots = vec![0.0; model.pattern().num_slots()];
    model.eval_jacobian(&ws, 0.0, &mut slots);
    let dense = RankAnalysis::compute(model.pattern(), &slots, RankOptions::default()).unwrap();
    let sparse =
        RankAnalysis::compute_sparse(model.pattern(), &slots, RankOptions::default()).unwrap();
    prop_assert_eq!(dense.dependent_rows(), sparse.dependent_rows());
    if d.drivers == dof.dof && d.drivers > 0 {
        let run = model.run_kinematics(&KinematicOptions::new(0.0, 1.0, 20));
        let check_results = |r: &Results| -> Result<(), TestCaseError> {
            prop_assert!(results_finite(r), "non-finite results");
            Ok(())
        };
        match run {
            Ok(r) => {
                check_results(&r)?;
                prop_assert_eq!(r.len(), 21);
                let worst = r.residual.iter().fold(0.0f64, |a, &b| a.max(b));
                prop_assert!(
                    worst < 1e-8 * model.characteristic_length().max(1.0),
                    "residual {worst:e}"
                );
            }
            Err(e) if !must_run => {
                if let Some(p) = e.partial_results() {
                    check_results(p)?;
                }
            }
            Err(e) => return Err(TestCaseError::fail(format!("driven chain: {e}"))),
        }
    }
    prop_assert!(
        start.elapsed() < Duration::from_secs(20),
        "took {:?}",
        start.elapsed()
    );
    Ok(())
}

proptest! {
    #![proptest_config(ProptestConfig { cases: cases(12), ..ProptestConfig::default() })]

    #[test]
    fn random_chains_assemble_and_run(
        d in chain(),
        shake in prop::collection::vec(-1.0f64..1.0, 24),
    ) {
        check(&d, &shake, true)?;
    }

    #[test]
    fn random_closed_loops_assemble_and_run(
        d in closed_loop(),
        shake in prop::collection::vec(-1.0f64..1.0, 18),
    ) {
        check(&d, &shake, false)?;
    }
}
