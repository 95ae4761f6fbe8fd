//! Curve elements in the equations of motion (their parameters eliminated, `kkt::curves`):
//!
//! - a bead on a circular wire of radius 1 m in a vertical plane, released at the wire's
//!   height, swings as the A01 pendulum does (`shared/benchmarks`' exact solution): the bead's
//!   rotation is free and untouched (the wire's force passes through its centre of mass);
//! - a bead on a straight wire inclined at α slides with s̈ = g sin α, and the wire's force is
//!   m g cos α;
//! - a harmonic cam (an eccentric disc, radius R, eccentricity e) turning at ω and a flat-faced
//!   tappet (mass m) held on it by a spring (stiffness k, preload F₀): by inverse dynamics, the
//!   camshaft torque against the power balance T ω = d/dt(½ m ṡ² + ½ k s² + F₀ s).
//! - statics and modal analysis: a bead held on a circle by gravity and a push; the valve train
//!   held at an angle (contact force and motor torque); the free camshaft's oscillation about
//!   its lowest lift at √(F₀ e / J);
//! - a ball on a sphere (a spherical pendulum) moves as the same ball on a distance joint, and a
//!   bead sent along a torus' outer equator without gravity stays on it at constant speed, the
//!   torus pushing with m v² / (R + r);
//! - path drivers in the equations of motion are refused by name.

mod common;
use cardan_constraints::{Circle, JointKind, Line, Marker, TimeFunction};
use cardan_dynamics::{
    Dopri5Options, Dynamics, DynamicsError, Force, GeneralizedAlphaOptions, Integrator,
    SimulationOptions, StaticOptions,
};
use cardan_mechanism::{
    Body, CamSpec, CurveSpec, DriverSpec, JointSpec, KinematicOptions, MechanismBuilder, PathSpec,
    GROUND,
};
use common::{A01, G};
use nalgebra::Vector3;
use std::f64::consts::PI;

/// A bead (its centre of mass at its point P) on `wire`, a curve of the ground, drawn at `at`.
fn bead_on(wire: cardan_constraints::Curve, at: Vector3<f64>) -> MechanismBuilder {
    let mut b = bead("bead", 1.0, at);
    b.curve(CurveSpec::new("wire", GROUND, wire, "bead", "P"));
    b
}

/// A model of one body `name` of mass `m` (inertia diag(1, 2, 3) · 1e-2) drawn at `at`, its
/// centre of mass its point P.
fn bead(name: &str, m: f64, at: Vector3<f64>) -> MechanismBuilder {
    let mut b = MechanismBuilder::new();
    b.body(
        Body::new(name)
            .mass(m)
            .inertia_diagonal(1e-2, 2e-2, 3e-2)
            .position(at),
    );
    b.point(name, "P", Vector3::zeros());
    b
}

fn circle_wire() -> cardan_constraints::Curve {
    let m = Marker::from_axes(Vector3::zeros(), Vector3::z(), Vector3::x()).unwrap();
    Circle::new(&m, 1.0).unwrap().into()
}

/// The bead on the circle by `integrator`: (max position error against A01, max spin, energy
/// drift).
fn bead_swing(integrator: Integrator) -> (f64, f64, f64) {
    let model = bead_on(circle_wire(), Vector3::new(1.0, 0.0, 0.0))
        .build()
        .unwrap();
    let mut d = Dynamics::new(&model).unwrap();
    d.add_force(Force::gravity(Vector3::new(0.0, -G, 0.0)))
        .unwrap();
    let times: Vec<f64> = A01.iter().map(|r| r.0).collect();
    let opts = SimulationOptions::new(20.0, 1)
        .output_times(std::iter::once(0.0).chain(times.iter().copied()).collect())
        .integrator(integrator);
    let res = d.simulate(&d.initial_guess(), &opts).unwrap();
    let body = res.body("bead").unwrap();
    let mut err: f64 = 0.0;
    for (k, (_, x, y)) in A01.iter().enumerate() {
        let r = body.r[k + 1];
        err = err.max((r.x - x).abs()).max((r.y - y).abs());
    }
    let spin = (0..res.len())
        .map(|k| body.omega[k].norm())
        .fold(0.0f64, f64::max);
    (err, spin, res.energy.max_drift())
}

#[test]
fn a_bead_on_a_circular_wire_swings_as_the_a01_pendulum() {
    let (err, spin, drift) =
        bead_swing(Integrator::Dopri5(Dopri5Options::tolerances(1e-10, 1e-12)));
    eprintln!("bead on a circle, DOPRI5: position error {err:.2e}, spin {spin:.1e} rad/s, energy drift {drift:.2e}");
    assert!(err < 1e-7, "position error {err}");
    assert!(spin < 1e-9, "the bead turned: {spin}");
    assert!(drift < 1e-7, "energy drift {drift}");
    let (err, spin, drift) = bead_swing(Integrator::GeneralizedAlpha(GeneralizedAlphaOptions {
        rho_inf: 1.0,
        ..GeneralizedAlphaOptions::with_step(1e-3)
    }));
    eprintln!("bead on a circle, generalized-α h = 1 ms: position error {err:.2e}, spin {spin:.1e} rad/s, energy drift {drift:.2e}");
    assert!(err < 1e-3, "position error {err}");
    assert!(spin < 1e-9, "the bead turned: {spin}");
    assert!(drift < 1e-3, "energy drift {drift}");
}

#[test]
fn a_bead_on_an_inclined_straight_wire_slides_at_g_sin_alpha() {
    let alpha: f64 = 0.3;
    let dir = Vector3::new(alpha.cos(), -alpha.sin(), 0.0);
    let m = Marker::from_axis(Vector3::zeros(), dir).unwrap();
    let model = bead_on(Line::new(&m).into(), Vector3::zeros())
        .build()
        .unwrap();
    let mut d = Dynamics::new(&model).unwrap();
    d.add_force(Force::gravity(Vector3::new(0.0, -G, 0.0)))
        .unwrap();
    let opts = SimulationOptions::new(1.0, 10)
        .integrator(Integrator::Dopri5(Dopri5Options::tolerances(1e-11, 1e-13)));
    let res = d.simulate(&d.initial_guess(), &opts).unwrap();
    let body = res.body("bead").unwrap();
    let mut err: f64 = 0.0;
    for k in 0..res.len() {
        let t = res.times()[k];
        let s = 0.5 * G * alpha.sin() * t * t;
        err = err.max((body.r[k] - s * dir).norm());
    }
    eprintln!("bead on an incline: position error {err:.2e}");
    assert!(err < 1e-9, "position error {err}");
}

#[test]
fn a_bead_sliding_off_the_end_of_an_open_spline_wire_stops_the_run_there() {
    // A straight spline wire inclined at α, 0.5 m long: the bead reaches its end at
    // t = √(2 L / (g sin α)).
    let (alpha, length): (f64, f64) = (0.3, 0.5);
    let dir = Vector3::new(alpha.cos(), -alpha.sin(), 0.0);
    let pts = (0..5).map(|k| dir * (length * k as f64 / 4.0)).collect();
    let wire = cardan_constraints::CubicCurve::new(pts, false).unwrap();
    let model = bead_on(wire.into(), Vector3::zeros()).build().unwrap();
    let mut d = Dynamics::new(&model).unwrap();
    d.add_force(Force::gravity(Vector3::new(0.0, -G, 0.0)))
        .unwrap();
    let opts = SimulationOptions::new(1.0, 100)
        .integrator(Integrator::Dopri5(Dopri5Options::tolerances(1e-10, 1e-12)));
    let err = d.simulate(&d.initial_guess(), &opts).unwrap_err();
    let end = (2.0 * length / (G * alpha.sin())).sqrt();
    eprintln!("{err}");
    let DynamicsError::MidRun { source, .. } = &err else {
        panic!("not a mid-run stop: {err}");
    };
    let DynamicsError::CurveEnd { time, element, .. } = source.as_ref() else {
        panic!("not a curve end: {source}");
    };
    assert_eq!(element, "wire");
    // Within the step that crossed the end.
    assert!(
        (*time - end).abs() < 1e-2,
        "stopped at {time}, end at {end}"
    );
}

/// The valve train of `examples/valve_train.toml` with a tappet spring: a disc of radius R whose
/// centre is e below the camshaft axis at θ = 0, a flat-faced tappet of mass m sliding along y,
/// a spring k between ground and tappet with its free length `free` (so the force at the lowest
/// lift is F₀ = k (free − y₀)), the camshaft turning at ω.
struct ValveTrain {
    m: f64,
    k: f64,
    preload: f64,
    omega: f64,
}

const R: f64 = 0.02;
const E: f64 = 0.005;

impl ValveTrain {
    fn build(&self) -> cardan_mechanism::Model {
        self.builder(true).build().unwrap()
    }

    /// Without the motor: the camshaft turns freely.
    fn build_free(&self) -> cardan_mechanism::Model {
        self.builder(false).build().unwrap()
    }

    fn builder(&self, driven: bool) -> MechanismBuilder {
        let y0 = R - E;
        let mut b = MechanismBuilder::new();
        b.body(
            Body::new("camshaft")
                .mass(0.5)
                .inertia_diagonal(1e-4, 1e-4, 1e-4),
        );
        b.body(
            Body::new("tappet")
                .mass(self.m)
                .inertia_diagonal(1e-5, 1e-5, 1e-5)
                .position(Vector3::new(0.0, y0, 0.0)),
        );
        b.point(GROUND, "O", Vector3::zeros())
            .point(GROUND, "S", Vector3::new(0.0, 0.2, 0.0))
            .vector(GROUND, "x", Vector3::x())
            .vector(GROUND, "y", Vector3::y())
            .vector(GROUND, "z", Vector3::z());
        b.point("camshaft", "O", Vector3::zeros())
            .vector("camshaft", "x", Vector3::x())
            .vector("camshaft", "z", Vector3::z());
        b.point("tappet", "F", Vector3::zeros())
            .vector("tappet", "y", Vector3::y());
        b.joint(
            JointSpec::new(
                "bearing",
                JointKind::Revolute,
                (GROUND, "O"),
                ("camshaft", "O"),
            )
            .axes("z", "z")
            .x_axes("x", "x"),
        );
        b.joint(
            JointSpec::new(
                "guide",
                JointKind::Prismatic,
                (GROUND, "O"),
                ("tappet", "F"),
            )
            .axes("y", "y"),
        );
        let disc = Marker::from_axes(Vector3::new(0.0, -E, 0.0), Vector3::z(), Vector3::x());
        let face = Marker::from_axis(Vector3::zeros(), Vector3::x()).unwrap();
        b.cam(CamSpec::new(
            "lobe",
            (
                "camshaft",
                Circle::new(&disc.unwrap(), R).unwrap(),
                Vector3::z(),
            ),
            ("tappet", Line::new(&face)),
        ));
        if driven {
            b.driver(DriverSpec::rotation(
                "motor",
                "bearing",
                TimeFunction::Polynomial(vec![0.0, self.omega]),
            ));
        }
        b
    }

    /// The dynamics of `model` with the valve spring: it pushes the tappet down onto the cam,
    /// anchored above it at S and compressed by F₀ / k at the lowest lift.
    fn dynamics<'m>(&self, model: &'m cardan_mechanism::Model) -> Dynamics<'m> {
        let free = 0.2 - (R - E) + self.preload / self.k;
        let mut d = Dynamics::new(model).unwrap();
        let spring = Force::spring_damper(
            "valve_spring",
            (GROUND, "S"),
            ("tappet", "F"),
            self.k,
            0.0,
            Some(free),
        );
        d.add_force(spring).unwrap();
        d
    }
}

#[test]
fn the_camshaft_torque_balances_the_power_of_the_valve_train() {
    let v = ValveTrain {
        m: 0.1,
        k: 2.0e4,
        preload: 150.0,
        omega: 2.0 * PI * 50.0,
    };
    let model = v.build();
    let mut d = v.dynamics(&model);
    let period = 2.0 * PI / v.omega;
    let steps = 72;
    let res = d
        .inverse_dynamics(&KinematicOptions::new(0.0, period, steps))
        .unwrap();
    let torque = &res.driver("motor").unwrap().effort;
    let mut err: f64 = 0.0;
    let mut scale: f64 = 0.0;
    for (k, &t) in res.times().iter().enumerate() {
        let th = v.omega * t;
        // s = e (1 − cos θ), ṡ = e ω sin θ, s̈ = e ω² cos θ; the spring's force k s + F₀.
        let (s, sd, sdd) = (
            E * (1.0 - th.cos()),
            E * v.omega * th.sin(),
            E * v.omega * v.omega * th.cos(),
        );
        let power = (v.m * sdd + v.k * s + v.preload) * sd;
        let expected = power / v.omega;
        err = err.max((torque[k] - expected).abs());
        scale = scale.max(expected.abs());
    }
    eprintln!("camshaft torque against the power balance: {err:.2e} N·m of {scale:.2e}");
    assert!(err < 1e-9 * scale, "torque error {err} of {scale}");
}

#[test]
fn path_drivers_are_refused_by_name() {
    let mut b = bead_on(circle_wire(), Vector3::new(1.0, 0.0, 0.0));
    b.path(PathSpec::new(
        "along",
        "wire",
        TimeFunction::Polynomial(vec![0.0, 0.1]),
    ));
    let model = b.build().unwrap();
    let Err(err) = Dynamics::new(&model) else {
        panic!("a path driver was accepted");
    };
    assert!(
        matches!(&err, DynamicsError::PathDriver { driver } if driver == "along"),
        "{err}"
    );
    assert!(err.to_string().contains("kind = \"kinematic\""), "{err}");
}

/// A bead on a vertical circular wire of radius 1 m under gravity and a constant horizontal
/// force F rests where tan φ = F / (m g) from the bottom, the wire pushing back with
/// √((m g)² + F²).
#[test]
fn a_bead_on_a_circular_wire_rests_where_gravity_and_a_push_balance() {
    let model = bead_on(circle_wire(), Vector3::new(0.0, -1.0, 0.0))
        .build()
        .unwrap();
    let mut d = Dynamics::new(&model).unwrap();
    let push = 4.0;
    d.add_force(Force::gravity(Vector3::new(0.0, -G, 0.0)))
        .unwrap();
    d.add_force(Force::point_force(
        "push",
        "bead",
        "P",
        Vector3::new(push, 0.0, 0.0),
        cardan_dynamics::Frame::Global,
    ))
    .unwrap();
    let r = d.statics(&StaticOptions::default()).unwrap();
    let eq = &r.equilibria[0];
    let p = eq.state.r(0);
    let phi = push.atan2(G);
    let err = (p - Vector3::new(phi.sin(), -phi.cos(), 0.0)).norm();
    let wire = r.results.cam("wire");
    eprintln!(
        "bead at rest: position error {err:.2e} m, {:?}",
        eq.stability
    );
    assert!(err < 1e-10, "position error {err}");
    assert!(wire.is_none(), "a point on a curve is not a cam pair");
}

/// The valve train held still at camshaft angle θ (statics at t = θ/ω): the contact force is
/// the spring's, F₀ + k e (1 − cos θ), and the motor holds the camshaft with T = N e sin θ.
#[test]
fn the_valve_train_held_at_an_angle_needs_the_spring_torque() {
    let model = VALVE.build();
    let mut d = VALVE.dynamics(&model);
    let th: f64 = 1.1;
    let r = d
        .statics(&StaticOptions {
            time: th / VALVE.omega,
            ..StaticOptions::default()
        })
        .unwrap();
    let n = VALVE.preload + VALVE.k * E * (1.0 - th.cos());
    let cam = r.results.cam("lobe").unwrap();
    let torque = r.results.driver("motor").unwrap().effort[0];
    let (nerr, terr) = (
        (cam.normal_force[0] - n).abs(),
        (torque - n * E * th.sin()).abs(),
    );
    eprintln!("held valve train: contact force error {nerr:.2e} N, torque error {terr:.2e} N m");
    assert!(nerr < 1e-9 * n && terr < 1e-9 * n * E, "{nerr} {terr}");
}

/// The free camshaft resting at its lowest lift is held there by the spring through the cam:
/// the potential F₀ e (1 − cos θ) + ½ k e² (1 − cos θ)² has stiffness F₀ e at θ = 0, and the
/// tappet does not move to first order (ṡ = e θ̇ sin θ), so the camshaft oscillates at
/// ω = √(F₀ e / J).
#[test]
fn the_free_camshaft_oscillates_at_the_closed_form_frequency() {
    let model = VALVE.build_free();
    let mut d = VALVE.dynamics(&model);
    let r = d.modal(&cardan_dynamics::ModalOptions::default()).unwrap();
    // In Hz.
    let expected = (VALVE.preload * E / 1e-4).sqrt() / (2.0 * PI);
    let f = r.modes[0].frequency;
    eprintln!("free camshaft: {f:.9} Hz (closed form {expected:.9})");
    assert!(r.modes.len() == 1, "{} modes", r.modes.len());
    assert!(
        (f - expected).abs() < 1e-7 * expected,
        "{f} against {expected}"
    );
}

impl ValveTrain {
    /// The contact force N(θ) = F₀ + k s + m s̈ = F₀ + k e (1 − cos θ) + m e ω² cos θ.
    fn contact_force(&self, th: f64) -> f64 {
        self.preload + self.k * E * (1.0 - th.cos()) + self.m * E * self.omega.powi(2) * th.cos()
    }

    /// The camshaft speed at which N first reaches 0 (at θ = π): F₀ + 2 k e = m e ω².
    fn lift_off_speed(&self) -> f64 {
        ((self.preload + 2.0 * self.k * E) / (self.m * E)).sqrt()
    }

    /// Inverse dynamics over one revolution in `steps` steps.
    fn revolution(&self, steps: usize) -> cardan_dynamics::DynamicResults {
        let model = self.build();
        let mut d = self.dynamics(&model);
        let period = 2.0 * PI / self.omega;
        d.inverse_dynamics(&KinematicOptions::new(0.0, period, steps))
            .unwrap()
    }
}

const VALVE: ValveTrain = ValveTrain {
    m: 0.1,
    k: 2.0e4,
    preload: 150.0,
    omega: 2.0 * PI * 50.0,
};

#[test]
fn the_cam_contact_force_is_the_closed_form_of_the_harmonic_cam() {
    let res = VALVE.revolution(72);
    let cam = res.cam("lobe").unwrap();
    let mut err: f64 = 0.0;
    let mut side: f64 = 0.0;
    for (k, &t) in res.times().iter().enumerate() {
        let th = VALVE.omega * t;
        err = err.max((cam.normal_force[k] - VALVE.contact_force(th)).abs());
        // Frictionless: along the tappet's axis (the face's normal), nothing across it.
        side = side.max(cam.force[k].x.abs()).max(cam.force[k].z.abs());
    }
    let scale = VALVE.contact_force(0.0);
    eprintln!("cam contact force against N(θ): {err:.2e} N of {scale:.1} N, across {side:.1e} N");
    assert!(err < 1e-9 * scale, "contact force error {err}");
    assert!(side < 1e-9 * scale, "a force across the face: {side}");
    assert!(cam.first_pull(res.times(), 1e-9).is_none());
    // The parameters' rates and accelerations: w = e sin θ on the face.
    let w = res.kinematics.curve_parameter("lobe", "w").unwrap();
    let mut werr: f64 = 0.0;
    for (k, &t) in res.times().iter().enumerate() {
        let th = VALVE.omega * t;
        let o = VALVE.omega;
        werr = werr
            .max((w.u[k] - E * th.sin()).abs())
            .max((w.u_dot[k] - E * o * th.cos()).abs() / o)
            .max((w.u_ddot[k] + E * o * o * th.sin()).abs() / (o * o));
    }
    eprintln!("face parameter w = e sin θ and its rates: {werr:.2e} m");
    assert!(werr < 1e-12, "w error {werr}");
}

#[test]
fn the_tappet_lifts_off_above_the_closed_form_speed_where_the_contact_first_pulls() {
    let lift_off = VALVE.lift_off_speed();
    let below = ValveTrain {
        omega: 0.99 * lift_off,
        ..VALVE
    };
    let res = below.revolution(720);
    let cam = res.cam("lobe").unwrap();
    let least = cam
        .normal_force
        .iter()
        .copied()
        .fold(f64::INFINITY, f64::min);
    let expected = below.preload + 2.0 * below.k * E - below.m * E * below.omega.powi(2);
    eprintln!("at 0.99 ω_lo: least contact force {least:.4} N (closed form {expected:.4} N)");
    assert!((least - expected).abs() < 1e-9 * below.preload);
    assert!(cam.first_pull(res.times(), 1e-9).is_none());

    let above = ValveTrain {
        omega: 1.05 * lift_off,
        ..VALVE
    };
    let steps = 3600;
    let res = above.revolution(steps);
    let (t, force) = res
        .cam("lobe")
        .unwrap()
        .first_pull(res.times(), 1e-9)
        .expect("the contact pulls above the lift-off speed");
    // N(θ*) = 0: cos θ* = −(F₀ + k e) / (m e ω² − k e).
    let (ke, me) = (above.k * E, above.m * E * above.omega.powi(2));
    let theta = (-(above.preload + ke) / (me - ke)).acos();
    let h = 2.0 * PI / above.omega / steps as f64;
    eprintln!(
        "at 1.05 ω_lo = {:.1} rad/s: first pull at t = {t:.6} s ({force:.3} N), closed form θ*/ω = {:.6} s",
        above.omega,
        theta / above.omega
    );
    assert!(t >= theta / above.omega && t < theta / above.omega + h);
}

#[test]
fn a_free_camshaft_and_a_sprung_tappet_keep_their_energy() {
    // The camshaft spins freely (no motor) and drives the tappet against its spring: the cam
    // pair's force does no net work, so kinetic + spring energy stays put.
    let model = VALVE.build_free();
    let mut d = VALVE.dynamics(&model);
    let mut guess = d.initial_guess();
    let cardan_mechanism::BodyId::Moving(shaft) = model.body_id("camshaft").unwrap() else {
        unreachable!()
    };
    guess.set_velocity(shaft, Vector3::zeros(), Vector3::new(0.0, 0.0, 300.0));
    let state = d.consistent_state(&guess).unwrap();
    let opts = SimulationOptions::new(0.2, 200)
        .integrator(Integrator::Dopri5(Dopri5Options::tolerances(1e-10, 1e-12)));
    let res = d.simulate(&state, &opts).unwrap();
    let drift = res.energy.max_drift();
    let e0 = res.energy.total[0];
    let lift = res.body("tappet").unwrap();
    let top = lift.r.iter().map(|r| r.y).fold(f64::MIN, f64::max) - (R - E);
    eprintln!("free camshaft: energy {e0:.4} J, drift {drift:.2e} J; highest lift {top:.2e} m");
    assert!(top > 1.9 * E, "the tappet did not go over the top: {top}");
    assert!(drift < 1e-8 * e0, "energy drift {drift} of {e0}");
}

/// The ball of a spherical pendulum (length 1 m, released at the height of the pivot with a
/// sideways speed): held on a sphere of radius 1 (u, v eliminated) or by a distance joint of
/// length 1 to the pivot, it moves alike.
#[test]
fn a_ball_on_a_sphere_moves_as_the_spherical_pendulum() {
    let axes = Marker::from_axes(Vector3::zeros(), Vector3::z(), Vector3::x()).unwrap();
    let on_sphere = {
        let mut b = bead("ball", 1.0, Vector3::x());
        let sphere = cardan_constraints::Sphere::new(&axes, 1.0).unwrap();
        b.surface(cardan_mechanism::SurfaceSpec::new(
            "shell", GROUND, sphere, "ball", "P",
        ));
        b.build().unwrap()
    };
    let on_rod = {
        let mut b = bead("ball", 1.0, Vector3::x());
        b.point(GROUND, "O", Vector3::zeros());
        b.joint(
            JointSpec::new(
                "rod",
                JointKind::SphericalSpherical,
                (GROUND, "O"),
                ("ball", "P"),
            )
            .length(1.0),
        );
        b.build().unwrap()
    };
    let swing = |model: &cardan_mechanism::Model| {
        let mut d = Dynamics::new(model).unwrap();
        d.add_force(Force::gravity(Vector3::new(0.0, -G, 0.0)))
            .unwrap();
        let mut guess = d.initial_guess();
        guess.set_velocity(0, Vector3::new(0.0, 0.0, 1.5), Vector3::zeros());
        let state = d.consistent_state(&guess).unwrap();
        let opts = SimulationOptions::new(3.0, 30)
            .integrator(Integrator::Dopri5(Dopri5Options::tolerances(1e-11, 1e-13)));
        d.simulate(&state, &opts).unwrap()
    };
    let (a, b) = (swing(&on_sphere), swing(&on_rod));
    let (ra, rb) = (&a.body("ball").unwrap().r, &b.body("ball").unwrap().r);
    let err = ra
        .iter()
        .zip(rb)
        .map(|(p, q)| (p - q).norm())
        .fold(0.0, f64::max);
    let v = a.kinematics.curve_parameter("shell", "v").unwrap();
    let reach = v.u.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    eprintln!(
        "spherical pendulum, sphere against distance joint: {err:.2e} m; |v| up to {reach:.2} m, energy drift {:.1e}",
        a.energy.max_drift()
    );
    assert!(err < 1e-8, "{err}");
    assert!(reach > 0.3, "the ball did not leave the equator: {reach}");
}

/// A bead sent along a torus' outer equator (radius R + r) without gravity stays on it at its
/// speed v, and the torus pushes it inward with m v² / (R + r).
#[test]
fn a_bead_along_a_torus_equator_keeps_its_circle_and_speed() {
    let (big, tube, speed) = (1.0, 0.3, 2.0);
    let axes = Marker::from_axes(Vector3::zeros(), Vector3::z(), Vector3::x()).unwrap();
    let torus = cardan_constraints::Torus::new(&axes, big, tube).unwrap();
    let mut b = bead("bead", 0.5, Vector3::new(big + tube, 0.0, 0.0));
    b.surface(cardan_mechanism::SurfaceSpec::new(
        "ring", GROUND, torus, "bead", "P",
    ));
    let model = b.build().unwrap();
    let mut d = Dynamics::new(&model).unwrap();
    let mut guess = d.initial_guess();
    guess.set_velocity(0, Vector3::new(0.0, speed, 0.0), Vector3::zeros());
    let state = d.consistent_state(&guess).unwrap();
    let opts = SimulationOptions::new(2.0, 40)
        .integrator(Integrator::Dopri5(Dopri5Options::tolerances(1e-11, 1e-13)));
    let res = d.simulate(&state, &opts).unwrap();
    let body = res.body("bead").unwrap();
    let radius = big + tube;
    let mut worst = [0.0f64; 3];
    for k in 0..res.len() {
        let (r, v) = (body.r[k], body.r_dot[k]);
        worst[0] = worst[0].max((r.xy().norm() - radius).abs()).max(r.z.abs());
        worst[1] = worst[1].max((v.norm() - speed).abs());
        // The torus' force is the only one: m r̈.
        let f = body.r_ddot[k] * 0.5;
        worst[2] = worst[2].max((f.norm() - 0.5 * speed * speed / radius).abs());
    }
    eprintln!(
        "bead on a torus' equator: off the circle {:.1e} m, speed {:.1e} m/s, force {:.1e} N",
        worst[0], worst[1], worst[2]
    );
    assert!(
        worst[0] < 1e-9 && worst[1] < 1e-9 && worst[2] < 1e-8,
        "{worst:?}"
    );
}
