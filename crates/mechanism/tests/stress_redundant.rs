//! Stress: redundant constraints — overconstrained mechanisms whose Grübler count is wrong.
//! Bennett's linkage (4 revolutes, 20 equations of rank 17: three redundant, DOF 1), Bricard's
//! linkage (30 equations of rank 29, DOF 1) and the planar four-bar of four spatial revolutes
//! (three redundant): the DOF, the number of redundant equations and the motion are checked.

mod common;
mod stress_common;

use cardan_mechanism::{
    AssemblyOptions, Body, DriverSpec, JointKind, JointSpec, KinematicOptions, MechanismBuilder,
    Orientation, TimeFunction, GROUND,
};
use nalgebra::{Isometry3, Translation3, UnitQuaternion, Vector3};
use std::f64::consts::PI;
use stress_common::results_finite;

fn rz(t: f64) -> Isometry3<f64> {
    Isometry3::from_parts(
        Translation3::identity(),
        UnitQuaternion::from_axis_angle(&Vector3::z_axis(), t),
    )
}

/// One Denavit–Hartenberg link step: along x by a, twist about x by α.
fn link(a: f64, alpha: f64) -> Isometry3<f64> {
    Isometry3::from_parts(
        Translation3::new(a, 0.0, 0.0),
        UnitQuaternion::from_axis_angle(&Vector3::x_axis(), alpha),
    )
}

/// Bennett's linkage: links (a, α), (b, β), (a, α), (b, β) with a / sin α = b / sin β, joint
/// angles θ0..θ3 closing the loop. Returns the builder (ground = link 0) and the angles.
fn bennett(theta0: f64) -> (MechanismBuilder, [f64; 4]) {
    let (a, alpha) = (1.0, 0.6f64);
    let beta = 1.1f64;
    let b = a * beta.sin() / alpha.sin();
    let k = ((beta + alpha) / 2.0).sin() / ((beta - alpha) / 2.0).sin();
    let links = [(a, alpha), (b, beta), (a, alpha), (b, beta)];
    // θ1 from the Bennett relation tan(θ0/2) tan(θ1/2) = ±K, θ2 = ±θ0, θ3 = ±θ1: pick the
    // combination that closes the loop.
    let mut best = (f64::MAX, [0.0; 4]);
    for s1 in [1.0, -1.0] {
        let t1 = 2.0 * (s1 * k / (theta0 / 2.0).tan()).atan();
        for t2 in [theta0, -theta0, 2.0 * PI - theta0] {
            for t3 in [t1, -t1, 2.0 * PI - t1] {
                let th = [theta0, t1, t2, t3];
                let mut f = Isometry3::identity();
                for i in 0..4 {
                    f = f * rz(th[i]) * link(links[i].0, links[i].1);
                }
                let err = f.translation.vector.norm() + f.rotation.angle();
                if err < best.0 {
                    best = (err, th);
                }
            }
        }
    }
    assert!(best.0 < 1e-12, "no closing combination: {}", best.0);
    let th = best.1;
    // Body frame of link i: F_i Rz(θ_i), with F_0 = I; joint i at F_i's origin about its z.
    let mut frames = Vec::new();
    let mut joint_frames = Vec::new();
    let mut f = Isometry3::identity();
    for i in 0..4 {
        joint_frames.push(f);
        let body = f * rz(th[i]);
        frames.push(body);
        f = body * link(links[i].0, links[i].1);
    }
    let mut bld = MechanismBuilder::new();
    let names = [GROUND, "l1", "l2", "l3"];
    // Ground is link 0 with its body frame = Rz(θ0) ≠ I: declare its features globally.
    for i in 1..4 {
        let q = frames[i].rotation.quaternion();
        bld.body(
            Body::new(names[i])
                .mass(1.0)
                .inertia_diagonal(0.1, 0.1, 0.1)
                .position(frames[i].translation.vector)
                .orientation(Orientation::EulerParams([q.w, q.i, q.j, q.k])),
        );
    }
    for j in 0..4 {
        let (bi, bj) = (names[(j + 3) % 4], names[j]);
        let (ii, jj) = ((j + 3) % 4, j);
        let g = joint_frames[j];
        let p = g.translation.vector;
        let z = g.rotation * Vector3::z();
        let x = g.rotation * Vector3::x();
        for (idx, body) in [(ii, bi), (jj, bj)] {
            let (pl, zl, xl) = if idx == 0 {
                (p, z, x)
            } else {
                let inv = frames[idx].inverse();
                (
                    inv.transform_point(&p.into()).coords,
                    inv.transform_vector(&z),
                    inv.transform_vector(&x),
                )
            };
            bld.point(body, &format!("P{j}"), pl)
                .vector(body, &format!("z{j}"), zl);
            // The angle reference: x of F_j on body i; x of the body frame on body j.
            if idx == ii {
                bld.vector(body, &format!("x{j}"), xl);
            } else {
                let xb = frames[jj].rotation * Vector3::x();
                let xb = if jj == 0 {
                    xb
                } else {
                    frames[jj].inverse_transform_vector(&xb)
                };
                bld.vector(body, &format!("xb{j}"), xb);
            }
        }
        bld.joint(
            JointSpec::new(
                format!("J{j}"),
                JointKind::Revolute,
                (bi, &format!("P{j}")),
                (bj, &format!("P{j}")),
            )
            .axes(&format!("z{j}"), &format!("z{j}"))
            .x_axes(&format!("x{j}"), &format!("xb{j}")),
        );
    }
    (bld, th)
}

/// Bennett: 3 moving bodies, 4 revolutes, 20 equations of rank 17 → DOF 1 (Grübler: −2),
/// three redundant equations. Driven at J0 (between link 3 and ground), the motion keeps the
/// Bennett relation tan(θ0/2) tan(θ1/2) = const and θ2 = ±θ0.
#[test]
fn bennett_has_one_dof_three_redundant_and_moves_like_bennett() {
    let (mut b, th) = bennett(1.0);
    let model = b.build().unwrap();
    let mut ws = model.workspace();
    model
        .assemble(
            &mut ws,
            &AssemblyOptions {
                include_drivers: false,
                ..AssemblyOptions::default()
            },
        )
        .unwrap();
    let dof = model.dof(&ws).unwrap();
    assert_eq!(model.num_joint_equations(), 20);
    assert_eq!(dof.rank, 17, "{dof}");
    assert_eq!(dof.dof, 1, "{dof}");
    assert_eq!(dof.redundant.len(), 3, "{dof}");

    b.driver(DriverSpec::rotation(
        "motor",
        "J0",
        TimeFunction::Polynomial(vec![th[0], 0.8]),
    ));
    let model = b.build().unwrap();
    let r = model
        .run_kinematics(&KinematicOptions::new(0.0, 1.0, 50))
        .unwrap();
    assert!(results_finite(&r));
    let k0 = (th[0] / 2.0).tan() * (th[1] / 2.0).tan();
    let (j0, j1, j2) = (
        r.joint("J0").unwrap(),
        r.joint("J1").unwrap(),
        r.joint("J2").unwrap(),
    );
    let s2 = (th[2] / th[0]).signum();
    for k in 0..r.len() {
        let (a0, a1, a2) = (j0.values[k][0], j1.values[k][0], j2.values[k][0]);
        assert!((a0 - (th[0] + 0.8 * r.times[k])).abs() < 1e-9);
        let kk = (a0 / 2.0).tan() * (a1 / 2.0).tan();
        assert!(
            (kk - k0).abs() < 1e-8 * k0.abs().max(1.0),
            "t = {}: {kk} vs {k0}",
            r.times[k]
        );
        assert!(
            ((a2 - s2 * a0).rem_euclid(2.0 * PI)).min((s2 * a0 - a2).rem_euclid(2.0 * PI)) < 1e-8
        );
    }
    assert!(r.residual.iter().all(|&x| x < 1e-10));
}

/// Bricard's linkage: 30 equations of rank 29 → DOF 1 (Grübler: 0), one redundant equation.
/// Driven over 0.3 (1 − cos 2πt): the loop stays closed (all equations, the redundant one
/// included, to 1e-10).
#[test]
fn bricard_has_one_dof_one_redundant() {
    let mut b = common::bricard_builder();
    let model = b.build().unwrap();
    let ws = model.workspace();
    let dof = model.dof(&ws).unwrap();
    assert_eq!(
        (dof.rank, dof.dof, dof.redundant.len()),
        (29, 1, 1),
        "{dof}"
    );
    b.driver(DriverSpec::rotation(
        "motor",
        "A",
        TimeFunction::Harmonic {
            amplitude: -0.3,
            frequency: 2.0 * PI,
            phase: PI / 2.0,
            offset: 0.3,
        },
    ));
    let model = b.build().unwrap();
    let r = model
        .run_kinematics(&KinematicOptions::new(0.0, 1.0, 60))
        .unwrap();
    assert!(results_finite(&r));
    assert!(r.residual.iter().all(|&x| x < 1e-10));
}

/// The planar four-bar as four spatial revolutes: 20 equations of rank 17 → DOF 1 (Grübler:
/// −2), three redundant; over two crank turns the coupler pin follows the planar closed form.
#[test]
fn four_bar_of_spatial_revolutes_has_three_redundant_and_follows_the_closed_form() {
    let model = common::four_bar_builder(0.7, 2.0 * PI).build().unwrap();
    let ws = model.workspace();
    let dof = model.dof(&ws).unwrap();
    assert_eq!(
        (dof.rank, dof.dof, dof.redundant.len()),
        (17, 1, 3),
        "{dof}"
    );
    let r = model
        .run_kinematics(&KinematicOptions::new(0.0, 2.0, 200))
        .unwrap();
    assert!(results_finite(&r));
    let b = &r.point("coupler", "B").unwrap().position;
    for k in 0..r.len() {
        let theta = 0.7 + 2.0 * PI * r.times[k];
        assert!((b[k] - common::four_bar_b(theta)).norm() < 1e-9);
    }
}
