//! Cam pairs (a follower's curve in tangent contact with a cam's profile, both curve parameters
//! extra coordinates) in kinematic runs, against the closed forms of the eccentric circular cam
//! (a disc of radius R whose centre is e from the camshaft axis, turning at ω):
//!
//! - a translating flat-faced follower, its face perpendicular to its motion through the
//!   camshaft axis: lift s(θ) − s(0) = e (1 − cos θ), ṡ = e ω sin θ, s̈ = e ω² cos θ; the contact
//!   point is on the face at w = e sin θ (the face's point above the disc's centre) and on the
//!   disc at u = R (π/2 − θ);
//! - a translating roller follower (radius r) in line with the camshaft axis: the roller centre
//!   at s(θ) = e cos θ + √((R + r)² − e² sin² θ), with its two derivatives.

use cardan_constraints::{Circle, JointKind, Line, Marker, TimeFunction};
use cardan_mechanism::{
    Body, CamSpec, DriverSpec, JointSpec, KinematicOptions, MechanismBuilder, Model, GROUND,
};
use nalgebra::Vector3;
use std::f64::consts::PI;

const OMEGA: f64 = 2.0 * PI;
const R: f64 = 0.04;
const E: f64 = 0.01;

/// The camshaft: a revolute about global z at the origin driven at θ = ω t, and the follower's
/// guide: a prismatic joint along `guide` (global) for body "follower" drawn at `at`.
fn cam_and_follower(guide: Vector3<f64>, at: Vector3<f64>) -> MechanismBuilder {
    let mut b = MechanismBuilder::new();
    b.body(
        Body::new("cam")
            .mass(1.0)
            .inertia_diagonal(1e-3, 1e-3, 1e-3),
    );
    b.body(
        Body::new("follower")
            .mass(0.2)
            .inertia_diagonal(1e-4, 1e-4, 1e-4)
            .position(at),
    );
    b.point(GROUND, "O", Vector3::zeros())
        .vector(GROUND, "z", Vector3::z())
        .vector(GROUND, "x", Vector3::x())
        .vector(GROUND, "guide", guide);
    b.point("cam", "O", Vector3::zeros())
        .vector("cam", "z", Vector3::z())
        .vector("cam", "x", Vector3::x());
    b.point("follower", "F", Vector3::zeros())
        .vector("follower", "guide", guide);
    b.joint(
        JointSpec::new("shaft", JointKind::Revolute, (GROUND, "O"), ("cam", "O"))
            .axes("z", "z")
            .x_axes("x", "x"),
    );
    b.joint(
        JointSpec::new(
            "guide",
            JointKind::Prismatic,
            (GROUND, "O"),
            ("follower", "F"),
        )
        .axes("guide", "guide"),
    );
    b.driver(DriverSpec::rotation(
        "motor",
        "shaft",
        TimeFunction::Polynomial(vec![0.0, OMEGA]),
    ));
    b
}

/// The disc: a circle of radius R about the cam's z, centred at `centre` (cam coordinates),
/// u = 0 along the cam's x from the centre.
fn disc(centre: Vector3<f64>, radius: f64) -> Circle {
    Circle::new(
        &Marker::from_axes(centre, Vector3::z(), Vector3::x()).unwrap(),
        radius,
    )
    .unwrap()
}

fn flat_faced() -> Model {
    // Disc centre at (0, −e) at θ = 0: the top of the disc at y = R − e, lowest lift.
    let mut b = cam_and_follower(Vector3::y(), Vector3::new(0.0, R - E, 0.0));
    let face = Line::new(&Marker::from_axis(Vector3::zeros(), Vector3::x()).unwrap());
    b.cam(CamSpec::new(
        "cam_face",
        ("cam", disc(Vector3::new(0.0, -E, 0.0), R), Vector3::z()),
        ("follower", face),
    ));
    b.build().unwrap()
}

fn roller(r: f64) -> Model {
    // Disc centre at (e, 0) at θ = 0; the follower moves along x, its roller centred at F.
    let s0 = E + R + r;
    let mut b = cam_and_follower(Vector3::x(), Vector3::new(s0, 0.0, 0.0));
    b.cam(CamSpec::new(
        "cam_roller",
        ("cam", disc(Vector3::new(E, 0.0, 0.0), R), Vector3::z()),
        ("follower", disc(Vector3::zeros(), r)),
    ));
    b.build().unwrap()
}

#[test]
fn a_flat_faced_follower_on_an_eccentric_disc_lifts_e_one_minus_cos() {
    let model = flat_faced();
    let ws = model.workspace();
    let dof = model.dof(&ws).unwrap();
    assert_eq!(dof.dof, 1, "{dof}");
    // The out-of-plane coincidence row is implied by the planar joints.
    assert_eq!(dof.redundant.len(), 1, "{dof}");
    let res = model
        .run_kinematics(&KinematicOptions::new(0.0, 2.0, 200))
        .unwrap();
    let f = res.body("follower").unwrap();
    let (u, w) = (
        res.curve_parameter("cam_face", "u").unwrap(),
        res.curve_parameter("cam_face", "w").unwrap(),
    );
    let mut worst = [0.0f64; 5];
    for (k, &t) in res.times.iter().enumerate() {
        let th = OMEGA * t;
        let e = [
            (f.r[k].y - (R - E) - E * (1.0 - th.cos())).abs(),
            (f.r_dot[k].y - E * OMEGA * th.sin()).abs(),
            (f.r_ddot[k].y - E * OMEGA * OMEGA * th.cos()).abs(),
            (w.u[k] - E * th.sin()).abs() + (w.u_dot[k] - E * OMEGA * th.cos()).abs(),
            (u.u[k] - R * (PI / 2.0 - th)).abs() + (u.u_dot[k] + R * OMEGA).abs(),
        ];
        for (a, b) in worst.iter_mut().zip(e) {
            *a = a.max(b);
        }
    }
    eprintln!(
        "flat-faced follower: |s − s(θ)|, |ṡ − ṡ(θ)|, |s̈ − s̈(θ)|, w, u: {:?}",
        worst.map(|e| format!("{e:.1e}"))
    );
    assert!(worst.iter().all(|&e| e < 1e-10), "{worst:?}");
    // The flat face's normal is along the tappet's motion: pressure angle 0 throughout.
    let cam = res.curve("cam_face").unwrap();
    assert!(cam.pressure_angle.iter().all(|&a| a.abs() < 1e-12));
}

#[test]
fn a_roller_follower_on_an_eccentric_disc_follows_the_closed_form() {
    let r = 0.01;
    let model = roller(r);
    let ws = model.workspace();
    let dof = model.dof(&ws).unwrap();
    assert_eq!(dof.dof, 1, "{dof}");
    let res = model
        .run_kinematics(&KinematicOptions::new(0.0, 2.0, 200))
        .unwrap();
    let f = res.body("follower").unwrap();
    let l = R + r;
    let mut worst = [0.0f64; 3];
    for (k, &t) in res.times.iter().enumerate() {
        let th = OMEGA * t;
        let root = (l * l - E * E * th.sin().powi(2)).sqrt();
        let s = E * th.cos() + root;
        // ds/dθ and d²s/dθ².
        let d1 = -E * th.sin() - E * E * th.sin() * th.cos() / root;
        let d2 = -E * th.cos()
            - E * E * (th.cos().powi(2) - th.sin().powi(2)) / root
            - E.powi(4) * (th.sin() * th.cos()).powi(2) / root.powi(3);
        let e = [
            (f.r[k].x - s).abs(),
            (f.r_dot[k].x - d1 * OMEGA).abs(),
            (f.r_ddot[k].x - d2 * OMEGA * OMEGA).abs(),
        ];
        for (a, b) in worst.iter_mut().zip(e) {
            *a = a.max(b);
        }
    }
    eprintln!(
        "roller follower: |s − s(θ)|, |ṡ − ṡ(θ)|, |s̈ − s̈(θ)|: {:?}",
        worst.map(|e| format!("{e:.1e}"))
    );
    // The pressure angle: the common normal runs through the disc's centre C = e (cos θ,
    // sin θ) and the roller's centre (s, 0); the follower moves along x:
    // tan φ = e |sin θ| / (s − e cos θ). At θ = 0 and π the follower is at rest and the angle
    // comes from its acceleration (along x: 0).
    let cam = res.curve("cam_roller").unwrap();
    assert_eq!(cam.pressure_angle.len(), res.len());
    let mut pa = 0.0f64;
    for (k, &t) in res.times.iter().enumerate() {
        let th = OMEGA * t;
        let s = f.r[k].x;
        let want = (E * th.sin().abs()).atan2(s - E * th.cos());
        pa = pa.max((cam.pressure_angle[k] - want).abs());
        // The contact point on the line of centres, R from C.
        let c = Vector3::new(E * th.cos(), E * th.sin(), 0.0);
        let p = Vector3::new(s, 0.0, 0.0);
        pa = pa.max((cam.contact[k] - (c + (p - c).normalize() * R)).norm() / R);
    }
    eprintln!("roller follower: pressure angle and contact point (over R) {pa:.1e}");
    assert!(pa < 1e-12, "{pa}");
    assert!(worst.iter().all(|&e| e < 1e-10), "{worst:?}");
}

/// The direction a pressing contact pushes the follower: out of a closed profile whichever way
/// it runs about the cam's normal, and, on an open profile, into a closed follower curve (a
/// roller); none for two open curves.
#[test]
fn a_pressing_contact_pushes_out_of_the_profile_or_into_the_roller() {
    use cardan_constraints::{BodyState, CurveOnCurve};
    use cardan_mechanism::CurveElement;
    let ground = BodyState::ground();
    let up = Vector3::y();
    // A disc of radius R about the origin, counterclockwise (axis z) and clockwise (axis −z),
    // touched at its top.
    for axis in [Vector3::z(), -Vector3::z()] {
        let m = Marker::from_axes(Vector3::zeros(), axis, Vector3::x()).unwrap();
        let profile = Circle::new(&m, R).unwrap();
        let face = Line::new(&Marker::from_axis(Vector3::new(0.0, R, 0.0), Vector3::x()).unwrap());
        let cam = CurveElement::Cam(
            CurveOnCurve::new(profile.into(), Vector3::z(), face.into()).unwrap(),
        );
        // The top: θ = π/2 about z, −π/2 about −z (whose y axis is −y).
        let u = axis.z * R * std::f64::consts::FRAC_PI_2;
        let push = cam.push_direction(&ground, &ground, &[u, 0.0]).unwrap();
        assert!((push - up).norm() < 1e-12, "{push:?} for axis {axis:?}");
    }
    // A straight track along x under a roller of radius r centred at (0, r): pushed up, into
    // the roller, either way the roller's circle runs.
    let r = 0.01;
    for axis in [Vector3::z(), -Vector3::z()] {
        let track = Line::new(&Marker::from_axis(Vector3::zeros(), Vector3::x()).unwrap());
        let m = Marker::from_axes(Vector3::new(0.0, r, 0.0), axis, Vector3::x()).unwrap();
        let roller = Circle::new(&m, r).unwrap();
        let cam = CurveElement::Cam(
            CurveOnCurve::new(track.into(), Vector3::z(), roller.into()).unwrap(),
        );
        // The roller's bottom: θ = −π/2 about z (u = −r π/2), +π/2 about −z.
        let w = if axis.z > 0.0 { -r } else { r } * std::f64::consts::FRAC_PI_2;
        let push = cam.push_direction(&ground, &ground, &[0.0, w]).unwrap();
        assert!((push - up).norm() < 1e-12, "{push:?} for axis {axis:?}");
    }
    let two_lines = CurveElement::Cam(
        CurveOnCurve::new(
            Line::new(&Marker::from_axis(Vector3::zeros(), Vector3::x()).unwrap()).into(),
            Vector3::z(),
            Line::new(&Marker::from_axis(Vector3::zeros(), Vector3::x()).unwrap()).into(),
        )
        .unwrap(),
    );
    assert!(two_lines
        .push_direction(&ground, &ground, &[0.0, 0.0])
        .is_none());
}
