//! Points on surfaces (u and v extra coordinates) in kinematic runs, against closed forms: an
//! arm on a cylindrical joint along global z, turned at θ = ω t, whose tip T at radius ρ from the
//! axis is held on a surface; the surface fixes the arm's height z(θ):
//!
//! - an inclined plane through the origin with normal (sin α, 0, cos α) (a swash plate):
//!   z = −ρ tan α cos θ; the same plane as a flat bicubic patch gives the same z;
//! - a sphere of radius R about (a, 0, 0): z = √(R² − (ρ cos θ − a)² − ρ² sin² θ);
//! - a torus about the x axis (centre circle of radius R in the y–z plane, tube r), outer
//!   branch: z = √((R + √(r² − ρ² cos² θ))² − ρ² sin² θ);
//! - a cylinder of radius R about the y axis: z = √(R² − ρ² cos² θ).
//!
//! A tip driven off a patch's edge stops the run with the time, naming the patch.

use cardan_constraints::{
    BicubicPatch, Cylinder, JointKind, Marker, Plane, Sphere, Surface, TimeFunction, Torus,
};
use cardan_mechanism::{
    AnalysisError, Body, DriverSpec, JointSpec, KinematicOptions, MechanismBuilder, Outputs,
    Results, SurfaceSpec, GROUND,
};
use nalgebra::{Matrix3, Vector3};
use std::f64::consts::PI;

const RHO: f64 = 0.3;
const OMEGA: f64 = 2.0 * PI;

/// The arm at height `z0` on its cylindrical joint, its tip on `surface` (of the ground).
fn arm_on(surface: Surface, z0: f64) -> MechanismBuilder {
    let mut b = MechanismBuilder::new();
    b.body(
        Body::new("arm")
            .mass(1.0)
            .inertia_diagonal(1e-2, 1e-2, 1e-2)
            .position(Vector3::new(0.0, 0.0, z0)),
    );
    b.point(GROUND, "O", Vector3::zeros())
        .vector(GROUND, "z", Vector3::z())
        .vector(GROUND, "x", Vector3::x());
    b.point("arm", "O", Vector3::zeros())
        .point("arm", "T", Vector3::new(RHO, 0.0, 0.0))
        .vector("arm", "z", Vector3::z())
        .vector("arm", "x", Vector3::x());
    b.joint(
        JointSpec::new("shaft", JointKind::Cylindrical, (GROUND, "O"), ("arm", "O"))
            .axes("z", "z")
            .x_axes("x", "x"),
    );
    b.driver(DriverSpec::rotation(
        "motor",
        "shaft",
        TimeFunction::Polynomial(vec![0.0, OMEGA]),
    ));
    b.surface(SurfaceSpec::new("track", GROUND, surface, "arm", "T"));
    b
}

fn run(b: &MechanismBuilder, t_end: f64) -> Result<Results, AnalysisError> {
    let model = b.build().unwrap();
    let mut opts = KinematicOptions::new(0.0, t_end, 100);
    opts.outputs = Outputs {
        acceleration: true,
        ..Outputs::with_velocity()
    };
    model.run_kinematics(&opts)
}

/// max |z − z(θ)|, |ż − ż(θ)|, |z̈ − z̈(θ)| over the run (the closed form's rates by central
/// differences in θ, step 1e-4: their error is of order 1e-8 z).
fn against(r: &Results, z: impl Fn(f64) -> f64) -> [f64; 3] {
    let arm = r.body("arm").unwrap();
    let h = 1e-4;
    let mut worst = [0.0f64; 3];
    for (k, &t) in r.times.iter().enumerate() {
        let th = OMEGA * t;
        let dz = (z(th + h) - z(th - h)) / (2.0 * h) * OMEGA;
        let ddz = (z(th + h) - 2.0 * z(th) + z(th - h)) / (h * h) * OMEGA * OMEGA;
        worst[0] = worst[0].max((arm.r[k].z - z(th)).abs());
        worst[1] = worst[1].max((arm.r_dot[k].z - dz).abs());
        worst[2] = worst[2].max((arm.r_ddot[k].z - ddz).abs());
    }
    worst
}

fn marker(origin: Vector3<f64>, x: Vector3<f64>, y: Vector3<f64>) -> Marker {
    Marker::new(origin, Matrix3::from_columns(&[x, y, x.cross(&y)])).unwrap()
}

#[test]
fn a_tip_on_an_inclined_plane_rides_the_swash_plate() {
    let alpha: f64 = 0.4;
    let n = Vector3::new(alpha.sin(), 0.0, alpha.cos());
    let x = Vector3::y().cross(&n);
    let plane = Plane::new(&marker(Vector3::zeros(), x, Vector3::y()));
    let z = |th: f64| -RHO * alpha.tan() * th.cos();
    let r = run(&arm_on(plane.into(), z(0.0)), 1.0).unwrap();
    let e = against(&r, z);
    eprintln!("plane: {e:?}");
    assert!(e[0] < 1e-12 && e[1] < 1e-6 && e[2] < 1e-4, "{e:?}");
    // The same plane as a flat patch of side 2 centred on the axis.
    let mut pts = [[Vector3::zeros(); 4]; 4];
    for (i, row) in pts.iter_mut().enumerate() {
        for (j, p) in row.iter_mut().enumerate() {
            let (a, b) = (-1.0 + 2.0 * i as f64 / 3.0, -1.0 + 2.0 * j as f64 / 3.0);
            *p = x * a + Vector3::y() * b;
        }
    }
    let patch = BicubicPatch::new(pts).unwrap();
    let r = run(&arm_on(patch.into(), z(0.0)), 1.0).unwrap();
    let e = against(&r, z);
    eprintln!("flat patch: {e:?}");
    assert!(e[0] < 1e-12 && e[1] < 1e-6 && e[2] < 1e-4, "{e:?}");
    // (u, v) = ((s + 1)/2, (y + 1)/2) on the patch, s the tip's coordinate along x.
    let u = r.curve_parameter("track", "u").unwrap();
    let v = r.curve_parameter("track", "v").unwrap();
    for (k, &t) in r.times.iter().enumerate() {
        let th = OMEGA * t;
        let s = RHO * th.cos() / alpha.cos();
        assert!((u.u[k] - (s + 1.0) / 2.0).abs() < 1e-12);
        assert!((v.u[k] - (RHO * th.sin() + 1.0) / 2.0).abs() < 1e-12);
    }
}

#[test]
fn a_tip_on_a_sphere_a_torus_and_a_cylinder_follows_the_closed_forms() {
    let frame = marker(Vector3::new(0.1, 0.0, 0.0), Vector3::x(), Vector3::y());
    let sphere = Sphere::new(&frame, 0.8).unwrap();
    let z_sphere = |th: f64| {
        let (x, y) = (RHO * th.cos() - 0.1, RHO * th.sin());
        (0.64 - x * x - y * y).sqrt()
    };
    // Torus about x: its marker's z is global x.
    let about_x = marker(Vector3::zeros(), Vector3::y(), Vector3::z());
    let torus = Torus::new(&about_x, 1.0, 0.4).unwrap();
    let z_torus = |th: f64| {
        let (x, y) = (RHO * th.cos(), RHO * th.sin());
        let s = (0.16 - x * x).sqrt();
        ((1.0 + s).powi(2) - y * y).sqrt()
    };
    // Cylinder about y: its marker's z is global y.
    let about_y = marker(Vector3::zeros(), Vector3::z(), Vector3::x());
    let cylinder = Cylinder::new(&about_y, 0.5).unwrap();
    let z_cylinder = |th: f64| (0.25 - (RHO * th.cos()).powi(2)).sqrt();
    type Case<'a> = (&'a str, Surface, &'a dyn Fn(f64) -> f64);
    let cases: [Case; 3] = [
        ("sphere", sphere.into(), &z_sphere),
        ("torus", torus.into(), &z_torus),
        ("cylinder", cylinder.into(), &z_cylinder),
    ];
    for (name, surface, z) in cases {
        let r = run(&arm_on(surface, z(0.0)), 2.0).unwrap();
        let e = against(&r, z);
        eprintln!("{name}: {e:?}");
        assert!(e[0] < 1e-12 && e[1] < 1e-6 && e[2] < 1e-4, "{name}: {e:?}");
    }
}

#[test]
fn a_tip_driven_off_its_patch_stops_the_run_at_the_edge() {
    // A flat patch on z = 0 spanning x ∈ [−0.2, 0.4]: the tip (radius 0.3) leaves it where
    // 0.3 cos θ = −0.2, at θ = acos(−2/3).
    let mut pts = [[Vector3::zeros(); 4]; 4];
    for (i, row) in pts.iter_mut().enumerate() {
        for (j, p) in row.iter_mut().enumerate() {
            *p = Vector3::new(-0.2 + 0.2 * i as f64, -0.5 + j as f64 / 3.0, 0.0);
        }
    }
    let patch = BicubicPatch::new(pts).unwrap();
    let err = run(&arm_on(patch.into(), 0.0), 1.0).unwrap_err();
    eprintln!("{err}");
    let AnalysisError::CurveEnd {
        time, parameter, ..
    } = &err
    else {
        panic!("{err}");
    };
    let edge = (-2.0f64 / 3.0).acos() / OMEGA;
    assert_eq!(*parameter, "u");
    assert!(
        *time >= edge && *time < edge + 0.01,
        "{time} against {edge}"
    );
    assert!(err.to_string().contains("patch"), "{err}");
}
