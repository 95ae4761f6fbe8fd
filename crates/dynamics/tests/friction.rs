//! Joint friction (issue 48) against closed forms: a block on an incline (prismatic joint with
//! Coulomb friction) slides with a = g (sin α − μ cos α) exactly when tan α > μ and sticks
//! (creeps at the regularization's rate) otherwise; a crank with pin friction driven at
//! constant speed needs the hand-derived friction-circle torque in inverse dynamics.

use cardan_constraints::JointKind;
use cardan_dynamics::{Dopri5Options, Dynamics, Force, Integrator, SimulationOptions};
use cardan_mechanism::{
    Body, DriverSpec, FrictionSpec, JointSpec, KinematicOptions, MechanismBuilder, ModelError,
    TimeFunction, GROUND,
};
use nalgebra::Vector3;

const G: f64 = 9.81;

/// A 2 kg block on a prismatic joint down an incline of angle `alpha` (axis (cos α, −sin α,
/// 0)), with friction μ.
fn incline(alpha: f64, mu: f64, vs: f64) -> MechanismBuilder {
    let axis = Vector3::new(alpha.cos(), -alpha.sin(), 0.0);
    let mut b = MechanismBuilder::new();
    b.body(Body::new("block").mass(2.0).inertia_diagonal(0.1, 0.1, 0.1));
    b.point(GROUND, "O", Vector3::zeros())
        .vector(GROUND, "d", axis)
        .vector(GROUND, "z", Vector3::z());
    b.point("block", "C", Vector3::zeros())
        .vector("block", "d", axis)
        .vector("block", "z", Vector3::z());
    b.joint(
        JointSpec::new("rail", JointKind::Prismatic, (GROUND, "O"), ("block", "C"))
            .axes("d", "d")
            .x_axes("z", "z"),
    );
    b.friction(FrictionSpec::new("dry", "rail", mu).stiction_velocity(vs));
    b
}

fn run_incline(alpha: f64, mu: f64, vs: f64, t_end: f64) -> (f64, f64, f64) {
    let model = incline(alpha, mu, vs).build().unwrap();
    let mut d = Dynamics::new(&model).unwrap();
    d.add_force(Force::gravity(Vector3::new(0.0, -G, 0.0)))
        .unwrap();
    let o = SimulationOptions::new(t_end, 10)
        .integrator(Integrator::Dopri5(Dopri5Options::tolerances(1e-10, 1e-12)));
    let r = d.simulate(&d.initial_guess(), &o).unwrap();
    let axis = Vector3::new(alpha.cos(), -alpha.sin(), 0.0);
    let b = r.body("block").unwrap();
    let s = b.r.last().unwrap().dot(&axis);
    let v = b.r_dot.last().unwrap().dot(&axis);
    let balance = r
        .energy
        .balance()
        .iter()
        .fold(0.0f64, |a, x| a.max(x.abs()));
    (s, v, balance)
}

#[test]
fn a_block_slides_down_an_incline_with_a_equal_g_sin_minus_mu_cos() {
    let (alpha, mu) = (30f64.to_radians(), 0.3);
    let a = G * (alpha.sin() - mu * alpha.cos());
    let (s, v, balance) = run_incline(alpha, mu, 1e-6, 1.0);
    eprintln!(
        "a = {a}: v(1) error {:.2e}, s(1) error {:.2e}, energy balance {balance:.2e}",
        v - a,
        s - 0.5 * a
    );
    assert!((v - a).abs() < 1e-6 * a);
    assert!((s - 0.5 * a).abs() < 1e-6 * a);
    // The friction's work closes the energy balance.
    assert!(balance < 1e-6, "{balance:e}");
}

#[test]
fn a_block_sticks_when_tan_alpha_is_at_most_mu() {
    // tan 20° = 0.364 < μ = 0.5: held, creeping at v_s ρ/√(1 − ρ²), ρ = tan α / μ.
    let (alpha, mu, vs) = (20f64.to_radians(), 0.5, 1e-4);
    let rho = alpha.tan() / mu;
    let creep = vs * rho / (1.0 - rho * rho).sqrt();
    let (s, v, balance) = run_incline(alpha, mu, vs, 0.5);
    eprintln!("creep {creep:.6e}: v {v:.6e}, s {s:.3e}, balance {balance:.2e}");
    assert!((v - creep).abs() < 1e-6 * creep, "{v} {creep}");
    assert!(s.abs() <= creep * 0.5 * 1.000_001);
    // Just past tan α = μ it slides.
    let (_, v, _) = run_incline(mu.atan() + 0.01, mu, vs, 0.5);
    assert!(v > 100.0 * creep, "{v}");
}

#[test]
fn hostile_friction_specs_are_builder_errors() {
    let bad = |f: FrictionSpec, key: &str| {
        let mut b = incline(0.3, 0.3, 1e-4);
        b.friction(f);
        let e = b.build().expect_err("refused");
        assert_eq!(e.limit_site().map(|s| s.1), Some(key), "{e}");
        e
    };
    let e = bad(FrictionSpec::new("f", "rail", -0.1), "coefficient");
    assert!(matches!(e, ModelError::BadFriction { .. }));
    bad(FrictionSpec::new("f", "rail", 0.1).radius(0.01), "radius");
    bad(FrictionSpec::new("f", "rail", 0.1).preload(-1.0), "preload");
    bad(
        FrictionSpec::new("f", "rail", 0.1).stiction_velocity(0.0),
        "stiction_velocity",
    );
    bad(FrictionSpec::new("f", "rial", 0.1), "joint");
}

#[test]
fn crank_with_pin_friction_needs_the_friction_circle_torque() {
    // A 1.5 kg crank of length L = 0.4 m pinned at its end, turned at ω = 3 rad/s in the
    // vertical x–y plane. The pin force is F = m (−ω² L/2 e_r + g ŷ) and the friction circle
    // adds μ r |F| to the gravity torque m g (L/2) cos θ.
    let (m, l, w, mu, r) = (1.5, 0.4, 3.0, 0.2, 0.01);
    let mut b = MechanismBuilder::new();
    b.body(
        Body::new("crank")
            .mass(m)
            .inertia_diagonal(1e-4, m * l * l / 12.0, m * l * l / 12.0)
            .position(Vector3::new(l / 2.0, 0.0, 0.0)),
    );
    b.point(GROUND, "O", Vector3::zeros())
        .vector(GROUND, "z", Vector3::z())
        .vector(GROUND, "x", Vector3::x());
    b.point("crank", "O", Vector3::new(-l / 2.0, 0.0, 0.0))
        .vector("crank", "z", Vector3::z())
        .vector("crank", "x", Vector3::x());
    b.joint(
        JointSpec::new("pin", JointKind::Revolute, (GROUND, "O"), ("crank", "O"))
            .axes("z", "z")
            .x_axes("x", "x"),
    );
    b.driver(DriverSpec::rotation(
        "motor",
        "pin",
        TimeFunction::Polynomial(vec![0.0, w]),
    ));
    b.friction(
        FrictionSpec::new("bearing", "pin", mu)
            .radius(r)
            .stiction_velocity(1e-6),
    );
    let model = b.build().unwrap();
    let mut d = Dynamics::new(&model).unwrap();
    d.add_force(Force::gravity(Vector3::new(0.0, -G, 0.0)))
        .unwrap();
    let res = d
        .inverse_dynamics(&KinematicOptions::new(0.0, 2.0, 40))
        .unwrap();
    let effort = &res.drivers[0].effort;
    let mut worst = 0.0f64;
    for (k, &t) in res.times().iter().enumerate() {
        let th = w * t;
        let er = Vector3::new(th.cos(), th.sin(), 0.0);
        let f = m * (-w * w * l / 2.0 * er + Vector3::new(0.0, G, 0.0));
        let want = m * G * l / 2.0 * th.cos() + mu * r * f.norm();
        worst = worst.max(
            (effort[k].abs() - want.abs())
                .abs()
                .min((effort[k] - want).abs()),
        );
        assert!(
            (effort[k] - want).abs() < 1e-8 || (effort[k] + want).abs() < 1e-8,
            "t = {t}: effort {} want {want}",
            effort[k]
        );
    }
    eprintln!("driver torque against the friction circle: worst error {worst:.2e} N m");
}
