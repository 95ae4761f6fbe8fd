//! Force elements against closed forms: body-frame point force, actuator, rotational
//! spring-damper (damped oscillator), user callback (same motion as built-in gravity), and
//! energy conservation with translational and rotational springs.

mod common;
use cardan_constraints::TimeFunction;
use cardan_dynamics::{
    Dopri5Options, Dynamics, DynamicsError, Force, Frame, Integrator, SimulationOptions,
};
use cardan_mechanism::{BodyId, GROUND};
use common::*;
use nalgebra::Vector3;

fn tight() -> Integrator {
    Integrator::Dopri5(Dopri5Options::tolerances(1e-11, 1e-13))
}

#[test]
fn body_frame_point_force_spins_at_a_constant_rate() {
    let (m, i3, f, arm) = (2.0, 0.3, 1.5, 0.1);
    let model = free_body(m, [0.2, 0.25, i3]);
    let mut d = Dynamics::new(&model).unwrap();
    d.add_force(Force::point_force(
        "push",
        "body",
        Vector3::new(arm, 0.0, 0.0),
        Vector3::new(0.0, f, 0.0),
        Frame::Body,
    ))
    .unwrap();
    let res = d
        .simulate(
            &d.initial_guess(),
            &SimulationOptions::new(1.0, 10).integrator(tight()),
        )
        .unwrap();
    let b = res.body("body").unwrap();
    let mut err: f64 = 0.0;
    for (k, &t) in res.times().iter().enumerate() {
        // ω'_z = f·arm/I3 · t, and the force turns with the body: ṙ = (f/m) ∫ (−sin φ, cos φ).
        let alpha = f * arm / i3;
        let phi = 0.5 * alpha * t * t;
        err = err.max((b.omega_local[k] - Vector3::new(0.0, 0.0, alpha * t)).norm());
        let a = (f / m) * Vector3::new(-phi.sin(), phi.cos(), 0.0);
        err = err.max((b.r_ddot[k] - a).norm());
    }
    eprintln!("body-frame force: error {err:.2e}");
    assert!(err < 1e-8, "{err}");
}

#[test]
fn actuator_pulls_with_its_prescribed_tension() {
    let m = 2.0;
    let model = free_body(m, [0.1, 0.1, 0.1]); // at (0, 0, 1)
    let mut d = Dynamics::new(&model).unwrap();
    d.add_force(Force::SpringDamperActuator {
        name: "cable".into(),
        body_i: GROUND.into(),
        point_i: Vector3::zeros().into(),
        body_j: "body".into(),
        point_j: "c".into(),
        stiffness: 0.0,
        damping: 0.0,
        free_length: None,
        actuator: Some(TimeFunction::Polynomial(vec![5.0, 2.0])), // 5 + 2t N
    })
    .unwrap();
    let res = d
        .simulate(
            &d.initial_guess(),
            &SimulationOptions::new(0.4, 4).integrator(tight()),
        )
        .unwrap();
    let b = res.body("body").unwrap();
    let mut err: f64 = 0.0;
    for (k, &t) in res.times().iter().enumerate() {
        // z'' = −(5 + 2t)/m → z = 1 − (2.5 t² + t³/3)/m.
        let z = 1.0 - (2.5 * t * t + t * t * t / 3.0) / m;
        err = err.max((b.r[k] - Vector3::new(0.0, 0.0, z)).norm());
    }
    eprintln!("actuator: error {err:.2e}");
    assert!(err < 1e-9, "{err}");
}

/// A uniform rod (1 kg, 1 m) on a pin with a rotational spring-damper (k = 20 N m/rad,
/// c = 0.4 N m s/rad), started at the rest angle with rate `w0`, over 3 s with `outputs`
/// output steps: the largest error of the joint angle in the results against the damped
/// oscillator θ(t) = w0/ω_d e^(−ζω t) sin(ω_d t).
fn swinging_rod_angle_error(w0: f64, outputs: usize) -> f64 {
    let (m, l, k, c) = (1.0, 1.0, 20.0, 0.4);
    let model = crank(m, l, None);
    let mut d = Dynamics::new(&model).unwrap();
    d.add_force(Force::rotational_spring_damper("coil", "pin", k, c, 0.0))
        .unwrap();
    let mut s = d.initial_guess();
    s.set_velocity(
        0,
        Vector3::new(0.0, w0 * l / 2.0, 0.0),
        Vector3::new(0.0, 0.0, w0),
    );
    let res = d
        .simulate(
            &s,
            &SimulationOptions::new(3.0, outputs).integrator(tight()),
        )
        .unwrap();
    let j = m * l * l / 3.0;
    let (zeta_w, wd) = (c / (2.0 * j), (k / j - (c / (2.0 * j)).powi(2)).sqrt());
    let angle = &res.kinematics.joint("pin").unwrap().values;
    let mut err: f64 = 0.0;
    for (i, &t) in res.times().iter().enumerate() {
        let th = w0 / wd * (-zeta_w * t).exp() * (wd * t).sin();
        err = err.max((angle[i][0] - th).abs());
    }
    err
}

#[test]
fn rotational_spring_damper_is_a_damped_oscillator() {
    let err = swinging_rod_angle_error(2.0, 30);
    eprintln!("rotational spring-damper: angle error {err:.2e}");
    assert!(err < 1e-8, "{err}");
}

/// The same oscillator swinging through several turns (amplitude w0/ω_d = 5.2 rad) with outputs
/// 0.3 s apart, where it turns by up to 10 rad: the joint angle in the results is continued
/// along the integrator's steps, not guessed from the rates at the output times (that guess
/// took the wrong turn: the angle was off by multiples of 2π).
#[test]
fn joint_angles_are_continued_over_turns_between_output_times() {
    let err = swinging_rod_angle_error(40.0, 10);
    eprintln!("many turns between outputs: angle error {err:.2e}");
    assert!(err < 1e-7, "{err}");
}

/// A block on a horizontal prismatic rail (gravity across it) with a translational
/// spring-damper on the rail, started at speed v0 from the spring's rest position: the damped
/// oscillator s(t) = v0/ω_d e^(−ζω t) sin(ω_d t) (closed form, to 1e-9 m); the damper's work
/// closes the energy balance.
#[test]
fn translational_spring_damper_is_a_damped_oscillator() {
    let (m, k, c, v0) = (2.0, 50.0, 0.8, 0.3);
    let mut b = cardan_mechanism::MechanismBuilder::new();
    b.body(
        cardan_mechanism::Body::new("block")
            .mass(m)
            .inertia_diagonal(0.1, 0.1, 0.1),
    );
    b.point(GROUND, "O", Vector3::zeros())
        .vector(GROUND, "x", Vector3::x())
        .vector(GROUND, "z", Vector3::z());
    b.point("block", "C", Vector3::zeros())
        .vector("block", "x", Vector3::x())
        .vector("block", "z", Vector3::z());
    b.joint(
        cardan_mechanism::JointSpec::new(
            "rail",
            cardan_constraints::JointKind::Prismatic,
            (GROUND, "O"),
            ("block", "C"),
        )
        .axes("x", "x")
        .x_axes("z", "z"),
    );
    let model = b.build().unwrap();
    let mut d = Dynamics::new(&model).unwrap();
    d.add_force(Force::gravity(Vector3::new(0.0, -9.81, 0.0)))
        .unwrap();
    d.add_force(Force::translational_spring_damper(
        "coil", "rail", k, c, 0.0,
    ))
    .unwrap();
    let mut s = d.initial_guess();
    s.set_velocity(0, Vector3::new(v0, 0.0, 0.0), Vector3::zeros());
    let res = d
        .simulate(&s, &SimulationOptions::new(3.0, 30).integrator(tight()))
        .unwrap();
    let (zeta_w, wd) = (c / (2.0 * m), (k / m - (c / (2.0 * m)).powi(2)).sqrt());
    let slide = &res.kinematics.joint("rail").unwrap().values;
    let mut err: f64 = 0.0;
    for (i, &t) in res.times().iter().enumerate() {
        let s = v0 / wd * (-zeta_w * t).exp() * (wd * t).sin();
        err = err.max((slide[i][0] - s).abs());
    }
    let balance = (res.energy.balance().iter()).fold(0.0f64, |a, x| a.max(x.abs()));
    eprintln!("translational spring-damper: slide error {err:.2e}, balance {balance:.2e}");
    assert!(err < 1e-9, "{err}");
    assert!(balance < 1e-8, "{balance:e}");
}

#[test]
fn user_callback_reproduces_gravity() {
    let model = crank(1.5, 0.7, None);
    let g = Vector3::new(0.0, -G, 0.0);
    let mut a = Dynamics::new(&model).unwrap();
    a.add_force(Force::gravity(g)).unwrap();
    let ra = a
        .simulate(&a.initial_guess(), &SimulationOptions::new(1.0, 10))
        .unwrap();
    let mut b = Dynamics::new(&model).unwrap();
    let mass = b.mass(0);
    b.set_user_forces(move |_t, f| f.add_force(BodyId::Moving(0), &(g * mass)));
    let rb = b
        .simulate(&b.initial_guess(), &SimulationOptions::new(1.0, 10))
        .unwrap();
    let (pa, pb) = (&ra.body("crank").unwrap().r, &rb.body("crank").unwrap().r);
    let diff = pa
        .iter()
        .zip(pb)
        .map(|(x, y)| (x - y).norm())
        .fold(0.0, f64::max);
    assert!(diff < 1e-12, "{diff}");
}

#[test]
fn springs_and_gravity_conserve_energy() {
    let model = crank(1.0, 1.0, None);
    let mut d = Dynamics::new(&model).unwrap();
    d.add_force(Force::gravity(Vector3::new(0.0, -G, 0.0)))
        .unwrap();
    d.add_force(Force::spring_damper(
        "spring",
        (GROUND, Vector3::new(0.0, 1.0, 0.0)),
        ("crank", "tip"),
        50.0,
        0.0,
        Some(0.5),
    ))
    .unwrap();
    d.add_force(Force::rotational_spring_damper(
        "coil", "pin", 3.0, 0.0, 0.3,
    ))
    .unwrap();
    let res = d
        .simulate(
            &d.initial_guess(),
            &SimulationOptions::new(5.0, 50)
                .integrator(Integrator::Dopri5(Dopri5Options::tolerances(1e-12, 1e-14))),
        )
        .unwrap();
    let e = &res.energy;
    let swing = e.spring.iter().fold(0.0f64, |a, v| a.max(*v))
        - e.spring.iter().fold(f64::MAX, |a, v| a.min(*v));
    eprintln!(
        "springs + gravity: energy drift {:.2e} (spring energy varies by {swing:.2})",
        e.max_drift()
    );
    assert!(swing > 1.0);
    assert!(e.max_drift() < 1e-7, "{}", e.max_drift());
}

#[test]
fn bad_force_elements_are_named() {
    let model = crank(1.0, 1.0, None);
    let mut d = Dynamics::new(&model).unwrap();
    let e = d
        .add_force(Force::point_force(
            "f",
            "crank",
            "nowhere",
            Vector3::x(),
            Frame::Global,
        ))
        .unwrap_err();
    assert!(
        matches!(&e, DynamicsError::BadForce { force, .. } if force == "f"),
        "{e}"
    );
    let e = d
        .add_force(Force::rotational_spring_damper(
            "coil", "nope", 1.0, 0.0, 0.0,
        ))
        .unwrap_err();
    assert!(e.to_string().contains("unknown joint"), "{e}");
    // A translational spring on a joint that does not slide, or one that does nothing.
    let e = d
        .add_force(Force::translational_spring_damper(
            "coil", "pin", 1.0, 0.0, 0.0,
        ))
        .unwrap_err();
    assert!(e.to_string().contains("acts on the slide of"), "{e}");

    let e = d
        .add_force(Force::spring_damper(
            "s",
            (GROUND, "O"),
            ("crank", "tip"),
            -1.0,
            0.0,
            None,
        ))
        .unwrap_err();
    assert!(e.to_string().contains("stiffness"), "{e}");
}
