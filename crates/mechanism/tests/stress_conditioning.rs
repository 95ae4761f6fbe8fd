//! Stress: conditioning. The same slider-crank in metres and in millimetres gives the same
//! motion (positions scaled by 1000, angles equal) to 1e-12 relative; Euler parameters of a body
//! turning many times pass through e0 = 0 and change sign continuously (p → −p after one turn,
//! no silent flip), with joint angles unwrapped.

mod stress_common;

use cardan_mechanism::{
    Body, DriverSpec, JointKind, JointSpec, KinematicOptions, MechanismBuilder, Orientation,
    TimeFunction, GROUND,
};
use nalgebra::{Matrix3, Vector3, Vector4};
use std::f64::consts::PI;
use stress_common::results_finite;

/// Haug's spatial slider-crank (as in tests/common) with every length multiplied by `s`.
fn slider_crank(s: f64) -> MechanismBuilder {
    let mut b = MechanismBuilder::new();
    let x_rod = Vector3::new(2.0, -1.0, -2.0) / 3.0;
    let y_rod = Vector3::new(0.0, 2.0, -1.0) / 5f64.sqrt();
    let v = |x: f64, y: f64, z: f64| Vector3::new(x, y, z) * s;
    b.body(
        Body::new("crank")
            .mass(0.12)
            .inertia_diagonal(1e-4 * s * s, 1e-4 * s * s, 1e-5 * s * s)
            .position(v(0.0, 0.1, 0.16)),
    );
    b.body(
        Body::new("conrod")
            .mass(0.5)
            .inertia_diagonal(4e-4 * s * s, 4e-3 * s * s, 4e-3 * s * s)
            .position(v(0.1, 0.05, 0.1))
            .orientation(Orientation::Axes {
                z: x_rod.cross(&y_rod),
                x: Some(x_rod),
            }),
    );
    b.body(
        Body::new("slider")
            .mass(2.0)
            .inertia(Matrix3::identity() * 1e-4 * s * s)
            .position(v(0.2, 0.0, 0.0)),
    );
    b.point(GROUND, "A", v(0.0, 0.1, 0.12))
        .point(GROUND, "O", Vector3::zeros())
        .vector(GROUND, "x", Vector3::x())
        .vector(GROUND, "z", Vector3::z());
    b.point("crank", "A", v(0.0, 0.0, -0.04))
        .point("crank", "B", v(0.0, 0.0, 0.04))
        .vector("crank", "x", Vector3::x())
        .vector("crank", "z", Vector3::z());
    b.point("conrod", "B", v(-0.15, 0.0, 0.0))
        .point("conrod", "C", v(0.15, 0.0, 0.0))
        .vector("conrod", "y", Vector3::y());
    b.point("slider", "C", Vector3::zeros())
        .vector("slider", "x", Vector3::x())
        .vector("slider", "z", Vector3::z());
    b.joint(
        JointSpec::new("A", JointKind::Revolute, (GROUND, "A"), ("crank", "A"))
            .axes("x", "x")
            .x_axes("z", "z"),
    );
    b.joint(JointSpec::new(
        "B",
        JointKind::Spherical,
        ("crank", "B"),
        ("conrod", "B"),
    ));
    b.joint(
        JointSpec::new("C", JointKind::Universal, ("slider", "C"), ("conrod", "C")).axes("x", "y"),
    );
    b.joint(
        JointSpec::new(
            "slide",
            JointKind::Prismatic,
            (GROUND, "O"),
            ("slider", "C"),
        )
        .axes("x", "x")
        .x_axes("z", "z"),
    );
    b.driver(DriverSpec::rotation(
        "motor",
        "A",
        TimeFunction::Polynomial(vec![0.0, 2.0 * PI]),
    ));
    b
}

/// Metres vs millimetres over two crank turns: every point position (divided by 1000), body
/// position, Euler parameters, joint angle and slide agree to 1e-12 relative to the size of the
/// mechanism; velocities and accelerations scale the same way.
#[test]
fn slider_crank_in_millimetres_moves_like_in_metres() {
    let opts = KinematicOptions::new(0.0, 2.0, 400);
    let m = slider_crank(1.0)
        .build()
        .unwrap()
        .run_kinematics(&opts)
        .unwrap();
    let mm = slider_crank(1000.0)
        .build()
        .unwrap()
        .run_kinematics(&opts)
        .unwrap();
    assert!(results_finite(&m) && results_finite(&mm));
    let size = 0.3; // the conrod length, m
    let mut worst = 0.0f64;
    for (pm, pmm) in m.points.iter().zip(&mm.points) {
        for k in 0..m.len() {
            worst = worst.max((pmm.position[k] / 1000.0 - pm.position[k]).norm() / size);
            worst =
                worst.max((pmm.velocity[k] / 1000.0 - pm.velocity[k]).norm() / (size * 2.0 * PI));
            worst = worst.max(
                (pmm.acceleration[k] / 1000.0 - pm.acceleration[k]).norm() / (size * 4.0 * PI * PI),
            );
        }
    }
    for (bm, bmm) in m.bodies.iter().zip(&mm.bodies) {
        for k in 0..m.len() {
            worst = worst.max((bmm.r[k] / 1000.0 - bm.r[k]).norm() / size);
            worst = worst.max((bmm.p[k] - bm.p[k]).norm());
            worst = worst.max((bmm.omega[k] - bm.omega[k]).norm() / (2.0 * PI));
        }
    }
    let (am, amm) = (m.joint("A").unwrap(), mm.joint("A").unwrap());
    let (sm, smm) = (m.joint("slide").unwrap(), mm.joint("slide").unwrap());
    for k in 0..m.len() {
        worst = worst.max((amm.values[k][0] - am.values[k][0]).abs());
        worst = worst.max((smm.values[k][0] / 1000.0 - sm.values[k][0]).abs() / size);
    }
    println!("m vs mm: worst relative difference {worst:e}");
    assert!(worst < 1e-12, "worst relative difference {worst:e}");
}

/// A body on a revolute joint about a tilted axis u, turned through 5 turns (θ = 2π t, the grid
/// lands on θ = kπ, where e0 = 0 exactly). Expected: p(θ) = [cos(θ/2), sin(θ/2) u] with p0 = I:
/// e0 passes through zero and p changes sign each turn (p = −p0 after one turn, p0 after two),
/// continuously (no silent sign flip: |p_{k+1} − p_k| ≤ 2 sin(Δθ/4) + 1e-12), normalization
/// kept to 1e-14, and the joint angle unwrapped to 10π.
#[test]
fn euler_parameters_pass_through_e0_zero_and_change_sign() {
    let u = Vector3::new(1.0, 2.0, 2.0) / 3.0;
    let x = Vector3::new(2.0, -2.0, 1.0) / 3.0; // ⟂ u
    let mut b = MechanismBuilder::new();
    b.body(
        Body::new("rotor")
            .mass(1.0)
            .inertia_diagonal(1.0, 1.0, 1.0)
            .position(Vector3::zeros()),
    );
    b.point(GROUND, "O", Vector3::zeros())
        .vector(GROUND, "u", u)
        .vector(GROUND, "x", x);
    b.point("rotor", "O", Vector3::zeros())
        .point("rotor", "tip", x)
        .vector("rotor", "u", u)
        .vector("rotor", "x", x);
    b.joint(
        JointSpec::new("axle", JointKind::Revolute, (GROUND, "O"), ("rotor", "O"))
            .axes("u", "u")
            .x_axes("x", "x"),
    );
    b.driver(DriverSpec::rotation(
        "motor",
        "axle",
        TimeFunction::Polynomial(vec![0.0, 2.0 * PI]),
    ));
    let model = b.build().unwrap();
    let steps = 5 * 64;
    let r = model
        .run_kinematics(&KinematicOptions::new(0.0, 5.0, steps))
        .unwrap();
    assert!(results_finite(&r));
    let p = &r.body("rotor").unwrap().p;
    let angle = &r.joint("axle").unwrap().values;
    let dtheta = 2.0 * PI * 5.0 / steps as f64;
    let mut zero_crossings = 0;
    for k in 0..r.len() {
        let th = 2.0 * PI * r.times[k];
        let want = Vector4::new(
            (th / 2.0).cos(),
            (th / 2.0).sin() * u.x,
            (th / 2.0).sin() * u.y,
            (th / 2.0).sin() * u.z,
        );
        assert!(
            (p[k] - want).norm() < 1e-12,
            "t = {}: p = {:?}, want {:?}",
            r.times[k],
            p[k],
            want
        );
        assert!((p[k].norm() - 1.0).abs() < 1e-14);
        assert!(
            (angle[k][0] - th).abs() < 1e-9,
            "angle {} vs {th}",
            angle[k][0]
        );
        if k > 0 {
            assert!((p[k] - p[k - 1]).norm() <= 2.0 * (dtheta / 4.0).sin() + 1e-12);
            if p[k][0].abs() < 1e-12 || p[k][0].signum() != p[k - 1][0].signum() {
                zero_crossings += 1;
            }
        }
    }
    // e0 = 0 at θ = π, 3π, 5π, 7π, 9π.
    assert!(zero_crossings >= 5, "{zero_crossings}");
    // One turn: p = −p0; two turns: p0.
    assert!((p[64] + Vector4::new(1.0, 0.0, 0.0, 0.0)).norm() < 1e-12);
    assert!((p[128] - Vector4::new(1.0, 0.0, 0.0, 0.0)).norm() < 1e-12);
}
