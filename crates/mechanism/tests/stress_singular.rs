//! Stress: near-singular configurations. Each test states the expected behaviour in its doc
//! comment and asserts it: either the run converges (with the residual as diagnostic), or it
//! stops with a typed error (`Singular` / `NotConverged`) at the right time, keeping the
//! results up to there.

mod common;
mod stress_common;

use cardan_mechanism::{
    AnalysisError, Body, DriverSpec, JointKind, JointSpec, KinematicOptions, MechanismBuilder,
    Orientation, TimeFunction, GROUND,
};
use nalgebra::{Rotation3, Unit, Vector3};
use std::f64::consts::{FRAC_PI_2, PI};
use stress_common::results_finite;

/// The time at which a run stopped, and the results it kept.
fn stop_time(e: &AnalysisError) -> Option<f64> {
    match e {
        AnalysisError::Singular { time, .. }
        | AnalysisError::NotConverged { time, .. }
        | AnalysisError::Solver { time, .. } => Some(*time),
        _ => None,
    }
}

/// A crank on a revolute joint whose axis is the coordinate axis `k` tilted by `eps` rad, driven
/// through one turn.
fn tilted_crank(k: usize, eps: f64, kind: JointKind) -> MechanismBuilder {
    let e = Vector3::ith(k, 1.0);
    let tilt =
        Rotation3::from_axis_angle(&Unit::new_normalize(Vector3::ith((k + 1) % 3, 1.0)), eps);
    let axis = tilt * e;
    let x = tilt * Vector3::ith((k + 2) % 3, 1.0);
    let mut b = MechanismBuilder::new();
    b.body(
        Body::new("crank")
            .mass(1.0)
            .inertia_diagonal(0.1, 0.1, 0.1)
            .position(0.5 * x)
            .orientation(Orientation::Axes {
                z: axis,
                x: Some(x),
            }),
    );
    b.point(GROUND, "O", Vector3::zeros())
        .vector(GROUND, "a", axis)
        .vector(GROUND, "x", x);
    b.point("crank", "O", Vector3::new(-0.5, 0.0, 0.0))
        .point("crank", "tip", Vector3::new(0.5, 0.0, 0.0))
        .vector("crank", "z", Vector3::z())
        .vector("crank", "x", Vector3::x());
    b.joint(
        JointSpec::new("pivot", kind, (GROUND, "O"), ("crank", "O"))
            .axes("a", "z")
            .x_axes("x", "x"),
    );
    b.driver(DriverSpec::rotation(
        "motor",
        "pivot",
        TimeFunction::Polynomial(vec![0.0, 2.0 * PI]),
    ));
    if kind == JointKind::Cylindrical {
        b.driver(DriverSpec::translation(
            "lift",
            "pivot",
            TimeFunction::Polynomial(vec![0.0, 0.1]),
        ));
    }
    b
}

/// Parallel constraints (p1/p2 inside revolute and cylindrical joints) with the axis s_i along
/// each coordinate axis and 1e-14 … 1e-4 rad off it: the joints use two body-fixed
/// perpendiculars of s_i, so nothing changes rank; a full driven turn converges with residual
/// < 1e-12 and the tip on its circle.
#[test]
fn parallel_constraints_near_each_coordinate_axis() {
    for kind in [JointKind::Revolute, JointKind::Cylindrical] {
        for k in 0..3 {
            for eps in [0.0, 1e-14, 1e-10, 1e-7, 1e-4] {
                let model = tilted_crank(k, eps, kind).build().unwrap();
                let r = model
                    .run_kinematics(&KinematicOptions::new(0.0, 1.0, 64))
                    .unwrap_or_else(|e| panic!("{kind:?} axis {k} tilt {eps}: {e}"));
                assert!(results_finite(&r));
                let worst = r.residual.iter().fold(0.0f64, |a, &b| a.max(b));
                assert!(
                    worst < 1e-12,
                    "{kind:?} axis {k} tilt {eps}: residual {worst:e}"
                );
                let tip = &r.point("crank", "tip").unwrap().position;
                let lift = if kind == JointKind::Cylindrical {
                    0.1
                } else {
                    0.0
                };
                for (i, p) in tip.iter().enumerate() {
                    let t = r.times[i];
                    let axial = lift * t;
                    let radial = (p.norm_squared() - axial * axial).sqrt();
                    assert!((radial - 1.0).abs() < 1e-10, "radius {radial}");
                }
                let angle = r.joint("pivot").unwrap().values[64][0];
                assert!((angle - 2.0 * PI).abs() < 1e-9, "angle {angle}");
            }
        }
    }
}

/// Two shafts through a universal joint at bend β, input driven through one turn
/// (tan φ2 = tan φ1 / cos β). Output speed ratio between cos β and 1/cos β: the position
/// Jacobian degrades as 1/cos β near φ1 = π/2 (mod π).
fn universal_drive(beta: f64) -> MechanismBuilder {
    let a2 = Vector3::new(beta.cos(), beta.sin(), 0.0);
    let mut b = MechanismBuilder::new();
    b.point(GROUND, "B1", Vector3::new(-0.4, 0.0, 0.0))
        .point(GROUND, "B2", 0.4 * a2)
        .vector(GROUND, "a1", Vector3::x())
        .vector(GROUND, "a2", a2)
        .vector(GROUND, "y", Vector3::y())
        .vector(GROUND, "z", Vector3::z());
    b.body(
        Body::new("shaft1")
            .mass(1.0)
            .inertia_diagonal(1e-3, 1.4e-2, 1.4e-2)
            .position(Vector3::new(-0.2, 0.0, 0.0)),
    );
    b.body(
        Body::new("shaft2")
            .mass(1.0)
            .inertia_diagonal(1e-3, 1.4e-2, 1.4e-2)
            .position(0.2 * a2)
            .orientation(Orientation::AxisAngle {
                axis: Vector3::z(),
                angle: beta,
            }),
    );
    for (s, sign) in [("shaft1", 1.0), ("shaft2", -1.0)] {
        b.point(s, "B", Vector3::new(-0.2 * sign, 0.0, 0.0))
            .point(s, "U", Vector3::new(0.2 * sign, 0.0, 0.0))
            .vector(s, "axis", Vector3::x())
            .vector(s, "y", Vector3::y())
            .vector(s, "z", Vector3::z());
    }
    b.joint(
        JointSpec::new(
            "bearing1",
            JointKind::Revolute,
            (GROUND, "B1"),
            ("shaft1", "B"),
        )
        .axes("a1", "axis")
        .x_axes("y", "y"),
    );
    b.joint(
        JointSpec::new(
            "bearing2",
            JointKind::Revolute,
            (GROUND, "B2"),
            ("shaft2", "B"),
        )
        .axes("a2", "axis")
        .x_axes("z", "z"),
    );
    b.joint(
        JointSpec::new(
            "cross",
            JointKind::Universal,
            ("shaft1", "U"),
            ("shaft2", "U"),
        )
        .axes("y", "z"),
    );
    b.driver(DriverSpec::rotation(
        "motor",
        "bearing1",
        TimeFunction::Polynomial(vec![0.0, 2.0 * PI]),
    ));
    b
}

/// Universal joint near a 90° bend. Expected (measured): up to β = 89.9° a full turn at 400
/// steps converges and follows tan φ2 = tan φ1 / cos β (speed ratio up to 1/cos β ≈ 573); at
/// exactly β = 90° the equations bifurcate at the start (φ1 = 0) and the run follows the branch
/// with the output locked at φ2 = ±π/2, converged to round-off — not an error.
#[test]
fn universal_joint_near_90_degree_bend() {
    for deg in [30.0f64, 60.0, 80.0] {
        let model = universal_drive(deg.to_radians()).build().unwrap();
        let r = model
            .run_kinematics(&KinematicOptions::new(0.0, 1.0, 400))
            .unwrap_or_else(|e| panic!("β = {deg}°: {e}"));
        assert!(results_finite(&r));
        let (j1, j2) = (r.joint("bearing1").unwrap(), r.joint("bearing2").unwrap());
        let c = deg.to_radians().cos();
        for k in 0..r.len() {
            let (p1, p2) = (j1.values[k][0], j2.values[k][0]);
            // tan φ2 cos β = tan φ1, written without tangents.
            let lhs = p2.sin() * c * p1.cos();
            let rhs = p1.sin() * p2.cos();
            assert!(
                (lhs - rhs).abs() < 1e-8,
                "β = {deg}°, t = {}: {lhs} vs {rhs}",
                r.times[k]
            );
        }
    }
    // 89° and 89.9°: output speed ratio up to 1/cos β ≈ 57 and 573; still converges in ≤ 4
    // iterations per step and follows the law.
    for deg in [89.0f64, 89.9] {
        let model = universal_drive(deg.to_radians()).build().unwrap();
        let r = model
            .run_kinematics(&KinematicOptions::new(0.0, 1.0, 400))
            .unwrap_or_else(|e| panic!("β = {deg}°: {e}"));
        let (j1, j2) = (r.joint("bearing1").unwrap(), r.joint("bearing2").unwrap());
        let c = deg.to_radians().cos();
        for k in 0..r.len() {
            let (p1, p2) = (j1.values[k][0], j2.values[k][0]);
            assert!((p2.sin() * c * p1.cos() - p1.sin() * p2.cos()).abs() < 1e-8);
        }
    }
    // 90°: sin φ1 cos φ2 = 0 has two branches crossing at φ1 = 0 (the start): the run takes
    // the branch where the output is locked at φ2 = ±π/2 and the input turns freely — a valid
    // solution of the equations, converged to round-off.
    let model = universal_drive(FRAC_PI_2).build().unwrap();
    let r = model
        .run_kinematics(&KinematicOptions::new(0.0, 1.0, 400))
        .unwrap();
    assert!(results_finite(&r));
    let j2 = r.joint("bearing2").unwrap();
    assert!(j2.values.iter().skip(1).all(|v| v[0].cos().abs() < 1e-9));
    assert!(r.residual.iter().all(|&x| x < 1e-12));
}

/// Slider-crank at dead centre. Expected: crank-driven, it passes both dead centres (the
/// driver is the crank; the slider velocity is zero there, nothing is singular), over two
/// turns, following the closed form. Slider-driven (x(t) = x0 + v t), the run reaches the dead
/// centre x_max at t* = (x_max − x0)/v: it stops with a typed error (`NotConverged`, measured)
/// at the first time step past t* (no solution exists beyond it), after converging at every
/// step before it.
#[test]
fn slider_crank_at_dead_centre() {
    let model = common::slider_crank_builder(2.0 * PI).build().unwrap();
    let r = model
        .run_kinematics(&KinematicOptions::new(0.0, 2.0, 720))
        .unwrap();
    let c = &r.point("slider", "C").unwrap().position;
    for k in 0..r.len() {
        let theta = 2.0 * PI * r.times[k];
        assert!((c[k].x - common::slider_x(theta).0).abs() < 1e-10);
    }
    // x_max: maximize the closed form over θ.
    let (mut x_max, mut th_max) = (0.0, 0.0);
    for i in 0..200_000 {
        let th = 2.0 * PI * i as f64 / 200_000.0;
        let x = common::slider_x(th).0;
        if x > x_max {
            (x_max, th_max) = (x, th);
        }
    }
    let x0 = common::slider_x(0.0).0;
    let v = 0.01; // m/s
    let t_star = (x_max - x0) / v;
    let mut b = common::slider_crank_undriven();
    b.driver(DriverSpec::translation(
        "push",
        "slide",
        TimeFunction::Polynomial(vec![x0, v]),
    ));
    let model = b.build().unwrap();
    let steps = 200;
    let t_end = 2.0 * t_star;
    let h = t_end / steps as f64;
    let e = model
        .run_kinematics(&KinematicOptions::new(0.0, t_end, steps))
        .map(|_| ())
        .expect_err("beyond the dead centre there is no solution");
    let t = stop_time(&e).unwrap_or_else(|| panic!("typed run error expected: {e}"));
    println!("slider-driven: x_max = {x_max} at θ = {th_max}, t* = {t_star}, stopped: {e}");
    assert!(
        t > t_star - h && t <= t_star + h + 1e-12,
        "t = {t}, t* = {t_star}"
    );
    let p = e.partial_results().expect("results up to the dead centre");
    assert!(results_finite(p));
    assert!(*p.times.last().unwrap() >= t_star - 2.0 * h);
}

/// A planar four-bar of four revolutes about z (3 redundant equations): ground d, crank a,
/// coupler b, rocker c; crank driven θ = θ0 + ω t. The initial configuration is the closed-form
/// upper branch.
fn four_bar(
    d: f64,
    a: f64,
    bl: f64,
    c: f64,
    theta0: f64,
    omega: f64,
    upper: bool,
) -> MechanismBuilder {
    let pa = Vector3::new(a * theta0.cos(), a * theta0.sin(), 0.0);
    let o4 = Vector3::new(d, 0.0, 0.0);
    let dd = o4 - pa;
    let delta = dd.norm();
    let u = dd / delta;
    let l = (bl * bl - c * c + delta * delta) / (2.0 * delta);
    let h = (bl * bl - l * l).max(0.0).sqrt() * if upper { 1.0 } else { -1.0 };
    let pb = pa + l * u + h * Vector3::new(-u.y, u.x, 0.0);
    let mut b = MechanismBuilder::new();
    let mut link = |name: &str, p: Vector3<f64>, q: Vector3<f64>| {
        let mid = (p + q) / 2.0;
        b.body(
            Body::new(name)
                .mass(1.0)
                .inertia_diagonal(0.1, 0.1, 0.1)
                .position(mid),
        );
        b.point(name, "P", p - mid)
            .point(name, "Q", q - mid)
            .vector(name, "z", Vector3::z())
            .vector(name, "x", Vector3::x());
    };
    link("crank", Vector3::zeros(), pa);
    link("coupler", pa, pb);
    link("rocker", o4, pb);
    b.point(GROUND, "O2", Vector3::zeros())
        .point(GROUND, "O4", o4)
        .vector(GROUND, "z", Vector3::z())
        .vector(GROUND, "x", Vector3::x());
    let rev = |n: &str, i: (&str, &str), j: (&str, &str)| {
        JointSpec::new(n, JointKind::Revolute, i, j)
            .axes("z", "z")
            .x_axes("x", "x")
    };
    b.joint(rev("O2", (GROUND, "O2"), ("crank", "P")));
    b.joint(rev("A", ("crank", "Q"), ("coupler", "P")));
    b.joint(rev("B", ("coupler", "Q"), ("rocker", "Q")));
    b.joint(rev("O4", (GROUND, "O4"), ("rocker", "P")));
    // The joint angle is measured from the initial pose (markers along global x on both
    // bodies), so the crank angle is θ0 + ω t.
    b.driver(DriverSpec::rotation(
        "motor",
        "O2",
        TimeFunction::Polynomial(vec![0.0, omega]),
    ));
    b
}

/// The double (parallelogram) four-bar, d = b = 1, a = c = 0.4, driven through its horizontal
/// change points θ = π and 2π (all four links collinear, where the parallelogram and the
/// anti-parallelogram branches meet and the joint Jacobian loses one more rank: an
/// instantaneous second DOF that the crank driver does not control). The crank angle is
/// θ = 0.5 + ω t (the joint angle is measured from the initial pose, so the driver is ω t).
/// Expected (measured): with steps that do not land on a change point (97), the run passes both
/// on the parallelogram branch (rocker angle = crank angle to 1e-6, ≤ 10 Newton iterations per
/// step); a step landing exactly on θ = π (100 steps, t = 0.5) stops with a typed `Singular`
/// error at that time, naming a dependent equation, with the results up to it kept.
#[test]
fn double_four_bar_through_its_change_point() {
    let theta0 = 0.5;
    let omega = 2.0 * (PI - theta0); // θ(0.5) = π, θ(1) = 2π − 0.5; θ = 2π at t ≈ 1.086
    let model = four_bar(1.0, 0.4, 1.0, 0.4, theta0, omega, true)
        .build()
        .unwrap();
    let r = model
        .run_kinematics(&KinematicOptions::new(0.0, 1.2, 97))
        .unwrap_or_else(|e| panic!("97 steps: {e}"));
    assert!(results_finite(&r));
    let (crank, rocker) = (r.joint("O2").unwrap(), r.joint("O4").unwrap());
    for k in 0..r.len() {
        let gap = (crank.values[k][0] - rocker.values[k][0]).abs();
        assert!(
            gap < 1e-6,
            "t = {}: left the parallelogram branch",
            r.times[k]
        );
    }
    assert!(r.iterations.iter().all(|&n| n <= 10));
    // Both change points passed: the crank angle θ0 + ω t went beyond 2π.
    assert!(theta0 + crank.values.last().unwrap()[0] > 2.0 * PI);

    let e = model
        .run_kinematics(&KinematicOptions::new(0.0, 1.0, 100))
        .map(|_| ())
        .expect_err("a step lands exactly on the change point");
    match &e {
        AnalysisError::Singular {
            time, dependent, ..
        } => {
            assert!((time - 0.5).abs() < 1e-12, "{e}");
            assert!(!dependent.is_empty());
        }
        other => panic!("Singular expected: {other}"),
    }
    let p = e.partial_results().unwrap();
    assert_eq!(p.len(), 50);
    assert!(results_finite(p));
}

/// RSSR (crank about z at O, radius a; rocker about y at G, radius c; coupler a distance
/// constraint of length L) whose crank cannot turn fully: the crank is driven at constant speed
/// into its limit position θ*, found independently by scanning the closed-form distance range.
/// Expected: converges up to θ*, then a typed error (`NotConverged`: no real solution exists
/// past θ*; the Jacobian is singular only exactly at it) at the first step past θ*.
#[test]
fn rssr_near_its_limit_position() {
    let (a, c, len) = (0.1, 0.2, 0.2);
    let g = Vector3::new(0.3, 0.15, 0.1);
    // Distance range between P(θ) and the rocker circle Q(ψ) = G + c (cos ψ, 0, sin ψ).
    let reachable = |th: f64| {
        let p = Vector3::new(a * th.cos(), a * th.sin(), 0.0);
        let (mut lo, mut hi) = (f64::MAX, 0.0f64);
        for i in 0..2_000 {
            let psi = 2.0 * PI * i as f64 / 2_000.0;
            let q = g + c * Vector3::new(psi.cos(), 0.0, psi.sin());
            let d = (q - p).norm();
            lo = lo.min(d);
            hi = hi.max(d);
        }
        lo <= len && len <= hi
    };
    assert!(reachable(0.0));
    let mut th_star = 0.0;
    while reachable(th_star + 1e-3) {
        th_star += 1e-3;
        assert!(th_star < 2.0 * PI, "the crank turns fully; pick another L");
    }
    // Initial pose: ψ0 solving |Q(ψ) − P(0)| = L, on the branch with the larger ψ near π.
    let p0 = Vector3::new(a, 0.0, 0.0);
    let f = |psi: f64| (g + c * Vector3::new(psi.cos(), 0.0, psi.sin()) - p0).norm() - len;
    let (mut lo, mut hi) = (0.0, PI);
    if f(lo).signum() == f(hi).signum() {
        (lo, hi) = (PI, 2.0 * PI);
    }
    for _ in 0..100 {
        let mid = 0.5 * (lo + hi);
        if f(mid).signum() == f(lo).signum() {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    let psi0 = 0.5 * (lo + hi);
    let q0 = g + c * Vector3::new(psi0.cos(), 0.0, psi0.sin());
    let mut b = MechanismBuilder::new();
    b.point(GROUND, "O", Vector3::zeros())
        .point(GROUND, "G", g)
        .vector(GROUND, "z", Vector3::z())
        .vector(GROUND, "y", Vector3::y())
        .vector(GROUND, "x", Vector3::x());
    b.body(
        Body::new("crank")
            .mass(0.2)
            .inertia_diagonal(1e-5, 2e-4, 2e-4)
            .position(p0 / 2.0),
    );
    b.point("crank", "O", -p0 / 2.0)
        .point("crank", "P", p0 / 2.0)
        .vector("crank", "z", Vector3::z())
        .vector("crank", "x", Vector3::x());
    b.body(
        Body::new("rocker")
            .mass(0.3)
            .inertia_diagonal(1e-5, 1e-3, 1e-3)
            .position(g),
    );
    b.point("rocker", "G", Vector3::zeros())
        .point("rocker", "Q", q0 - g)
        .vector("rocker", "y", Vector3::y());
    b.joint(
        JointSpec::new(
            "crank_pivot",
            JointKind::Revolute,
            (GROUND, "O"),
            ("crank", "O"),
        )
        .axes("z", "z")
        .x_axes("x", "x"),
    );
    b.joint(
        JointSpec::new(
            "rocker_pivot",
            JointKind::Revolute,
            (GROUND, "G"),
            ("rocker", "G"),
        )
        .axes("y", "y"),
    );
    b.joint(
        JointSpec::new(
            "coupler",
            JointKind::SphericalSpherical,
            ("crank", "P"),
            ("rocker", "Q"),
        )
        .length(len),
    );
    let omega = 1.0;
    b.driver(DriverSpec::rotation(
        "motor",
        "crank_pivot",
        TimeFunction::Polynomial(vec![0.0, omega]),
    ));
    let model = b.build().unwrap();
    let t_star = th_star / omega;
    let steps = 300;
    let t_end = 1.5 * t_star;
    let h = t_end / steps as f64;
    let e = model
        .run_kinematics(&KinematicOptions::new(0.0, t_end, steps))
        .map(|_| ())
        .expect_err("the crank cannot pass its limit position");
    let t = stop_time(&e).unwrap_or_else(|| panic!("typed run error expected: {e}"));
    println!("RSSR: θ* = {th_star}, stopped at t = {t}: {e}");
    assert!(
        t > t_star - 2.0 * h && t <= t_star + h + 1e-4,
        "t = {t}, t* = {t_star}"
    );
    assert!(results_finite(e.partial_results().unwrap()));
}
