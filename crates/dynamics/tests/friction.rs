//! Joint friction (issue 48) against closed forms: a block on an incline (prismatic joint with
//! Coulomb friction) slides with a = g (sin α − μ cos α) exactly when tan α > μ and sticks
//! (creeps at the regularization's rate) otherwise; a crank with pin friction driven at
//! constant speed needs the hand-derived friction-circle torque in inverse dynamics.

use cardan_constraints::JointKind;
use cardan_dynamics::{
    Dopri5Options, Dynamics, Force, GeneralizedAlphaOptions, Integrator, SimulationOptions,
};
use cardan_mechanism::{
    Body, DriverSpec, FrictionSpec, JointSpec, KinematicOptions, MechanismBuilder, ModelError,
    TimeFunction, GROUND,
};
use nalgebra::Vector3;

mod common;

const G: f64 = 9.81;

/// A 2 kg block on a prismatic joint down an incline of angle `alpha` (axis (cos α, −sin α,
/// 0)), with friction μ.
fn incline(alpha: f64, mu: f64, vs: f64) -> MechanismBuilder {
    incline_with(
        alpha,
        FrictionSpec::new("dry", "rail", mu).stiction_velocity(vs),
    )
}

/// The block of [`incline`] with the friction `friction` of joint "rail".
fn incline_with(alpha: f64, friction: FrictionSpec) -> MechanismBuilder {
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
    b.friction(friction);
    b
}

fn run_incline(alpha: f64, mu: f64, vs: f64, t_end: f64) -> (f64, f64, f64) {
    let tight = Integrator::Dopri5(Dopri5Options::tolerances(1e-10, 1e-12));
    run_incline_with(alpha, mu, vs, t_end, tight)
}

fn run_incline_with(
    alpha: f64,
    mu: f64,
    vs: f64,
    t_end: f64,
    integrator: Integrator,
) -> (f64, f64, f64) {
    run_incline_from(alpha, mu, vs, t_end, integrator, 0.0)
}

/// The block started at speed `v0` down the incline.
fn run_incline_from(
    alpha: f64,
    mu: f64,
    vs: f64,
    t_end: f64,
    integrator: Integrator,
    v0: f64,
) -> (f64, f64, f64) {
    let model = incline(alpha, mu, vs).build().unwrap();
    let mut d = Dynamics::new(&model).unwrap();
    d.add_force(Force::gravity(Vector3::new(0.0, -G, 0.0)))
        .unwrap();
    let o = SimulationOptions::new(t_end, 10).integrator(integrator);
    let axis = Vector3::new(alpha.cos(), -alpha.sin(), 0.0);
    let mut start = d.initial_guess();
    for c in 0..3 {
        start.v[c] = v0 * axis[c];
    }
    let r = d.simulate(&start, &o).unwrap();
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

/// Generalized-α solves the friction with the step's multipliers: the block sliding from
/// v₀ = 0.5 m/s has a constant acceleration, which the scheme integrates exactly, so s and v
/// match the closed form to the Newton tolerance; the stuck block creeps at the
/// regularization's rate; the friction's work closes the balance. Started from rest, the
/// friction jumps from 0 (the regularized sign at v = 0) to μN within v_s / a ≈ 4e-7 s, which
/// one step does not resolve: the velocity then carries the step's error h μ g cos α / 2
/// (1.27e-3 m/s at h = 1 ms, halving with h), which DOPRI5's step control resolves.
#[test]
fn generalized_alpha_slides_and_sticks_as_the_closed_forms_say() {
    let alpha_step = |h: f64| Integrator::GeneralizedAlpha(GeneralizedAlphaOptions::with_step(h));
    let (alpha, mu, v0) = (30f64.to_radians(), 0.3, 0.5);
    let a = G * (alpha.sin() - mu * alpha.cos());
    let (s, v, balance) = run_incline_from(alpha, mu, 1e-6, 1.0, alpha_step(1e-3), v0);
    eprintln!(
        "gen-α slide: v(1) error {:.2e}, s(1) error {:.2e}, balance {balance:.2e}",
        v - v0 - a,
        s - v0 - 0.5 * a
    );
    assert!((v - v0 - a).abs() < 1e-9 * a, "{v} vs {}", v0 + a);
    assert!(
        (s - v0 - 0.5 * a).abs() < 1e-9 * a,
        "{s} vs {}",
        v0 + 0.5 * a
    );
    assert!(balance < 1e-6, "{balance:e}");
    // From rest: the unresolved start costs h μ g cos α / 2 in v, first order in h.
    for h in [1e-3, 5e-4] {
        let (_, v, _) = run_incline_with(alpha, mu, 1e-6, 1.0, alpha_step(h));
        let start = h * mu * G * alpha.cos() / 2.0;
        eprintln!(
            "gen-α from rest, h = {h}: v error {:.3e} ({start:.3e})",
            v - a
        );
        assert!((v - a - start).abs() < 0.05 * start, "{v}");
    }
    let (alpha, mu, vs) = (20f64.to_radians(), 0.5, 1e-4);
    let rho = alpha.tan() / mu;
    let creep = vs * rho / (1.0 - rho * rho).sqrt();
    let (s, v, balance) = run_incline_with(alpha, mu, vs, 0.5, alpha_step(1e-3));
    eprintln!("gen-α stick: creep {creep:.6e}: v {v:.6e}, s {s:.3e}, balance {balance:.2e}");
    assert!((v - creep).abs() < 1e-6 * creep, "{v} {creep}");
    // Plus the unresolved start: one step of g sin α with the friction still at 0.
    let h = 1e-3;
    assert!((s - creep * 0.5).abs() <= G * alpha.sin() * h * h, "{s}");
    assert!(balance < 1e-5, "{balance:e}");
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
    // The constant law: a slide takes a force, not a torque; no negative or non-finite value.
    bad(
        FrictionSpec::new("f", "rail", 0.0).constant_torque(1.0),
        "torque",
    );
    bad(
        FrictionSpec::new("f", "rail", 0.0).constant_force(-1.0),
        "force",
    );
    bad(
        FrictionSpec::new("f", "rail", 0.0).constant_force(f64::NAN),
        "force",
    );
}

/// The constant law (URDF's `<dynamics friction>`): a block sliding down a 30° incline from
/// rest under a friction force F_c independent of the load accelerates at g sin α − F_c/m
/// whatever its normal load (closed form at t = 1 s, to 1e-6 as the Coulomb block); with
/// gravity doubled across the rail only, the same acceleration along it.
#[test]
fn constant_friction_slows_a_slide_by_its_force_whatever_the_load() {
    let (alpha, m, fc) = (30f64.to_radians(), 2.0, 3.0);
    let a = G * alpha.sin() - fc / m;
    let tight = Integrator::Dopri5(Dopri5Options::tolerances(1e-10, 1e-12));
    let axis = Vector3::new(alpha.cos(), -alpha.sin(), 0.0);
    let normal = Vector3::new(alpha.sin(), alpha.cos(), 0.0);
    for extra in [0.0, 1.0] {
        let spec = FrictionSpec::new("dry", "rail", 0.0)
            .constant_force(fc)
            .stiction_velocity(1e-6);
        let model = incline_with(alpha, spec).build().unwrap();
        let mut d = Dynamics::new(&model).unwrap();
        // Gravity, plus (second run) a pull of the normal load's size across the rail.
        let g = Vector3::new(0.0, -G, 0.0) - normal * (extra * G * alpha.cos());
        d.add_force(Force::gravity(g)).unwrap();
        let o = SimulationOptions::new(1.0, 10).integrator(tight);
        let r = d.simulate(&d.initial_guess(), &o).unwrap();
        let b = r.body("block").unwrap();
        let (s, v) = (
            b.r.last().unwrap().dot(&axis),
            b.r_dot.last().unwrap().dot(&axis),
        );
        let balance = (r.energy.balance().iter()).fold(0.0f64, |x, y| x.max(y.abs()));
        eprintln!(
            "constant friction, extra load {extra}: v(1) error {:.2e}, s(1) error {:.2e}, \
             balance {balance:.2e}",
            v - a,
            s - 0.5 * a
        );
        assert!((v - a).abs() < 1e-6 * a, "{v} vs {a}");
        assert!((s - 0.5 * a).abs() < 1e-6 * a, "{s} vs {}", 0.5 * a);
        assert!(balance < 1e-6, "{balance:e}");
    }
}

/// A rod spinning on a vertical pin (no gravity torque) under a constant friction torque T_c
/// slows at T_c / J: ω(t) = ω0 − T_c t / J until it stops (closed form at t = 0.5 s, before
/// the stop at 1 s); then it stays (creeping at the regularization's rate).
#[test]
fn constant_friction_torque_spins_a_rotor_down_linearly() {
    let (m, l, w0) = (1.0, 1.0, 2.0);
    let j = m * l * l / 3.0;
    let tc = w0 * j; // stops at t = 1 s
    let mut b = common::rod_on_a_pin("crank", m, l, 1e-3);
    b.friction(
        FrictionSpec::new("dry", "pin", 0.0)
            .constant_torque(tc)
            .stiction_velocity(1e-6),
    );
    let model = b.build().unwrap();
    let mut d = Dynamics::new(&model).unwrap();
    let mut s = d.initial_guess();
    s.set_velocity(
        0,
        Vector3::new(0.0, w0 * l / 2.0, 0.0),
        Vector3::new(0.0, 0.0, w0),
    );
    let tight = Integrator::Dopri5(Dopri5Options::tolerances(1e-10, 1e-12));
    let r = d
        .simulate(&s, &SimulationOptions::new(1.5, 3).integrator(tight))
        .unwrap();
    let pin = r.kinematics.joint("pin").unwrap();
    let (t_half, w_half) = (r.times()[1], pin.rates[1][0]);
    let err = (w_half - (w0 - tc * t_half / j)).abs();
    let angle_err = (pin.values[1][0] - (w0 * t_half - 0.5 * tc / j * t_half * t_half)).abs();
    let after = pin.rates[3][0].abs();
    eprintln!("friction torque: ω(0.5) error {err:.2e}, θ(0.5) error {angle_err:.2e}, |ω(1.5)| {after:.2e}");
    assert!(err < 1e-6 * w0, "{err}");
    assert!(angle_err < 1e-6, "{angle_err}");
    assert!(after < 1e-5, "{after}");
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
    // The friction's history: the torque −μ r |F| against the turning (ω > 0), its power
    // that torque times ω, at every output time.
    let history = d.friction_history();
    assert_eq!(history.times.len(), res.times().len());
    for (k, &t) in history.times.iter().enumerate() {
        let th = w * t;
        let er = Vector3::new(th.cos(), th.sin(), 0.0);
        let f = m * (-w * w * l / 2.0 * er + Vector3::new(0.0, G, 0.0));
        let torque = -mu * r * f.norm();
        assert!((history.value[k][0] - torque).abs() < 1e-8, "t = {t}");
        assert!((history.power[k][0] - torque * w).abs() < 1e-8, "t = {t}");
    }
}

/// A 1 kg, 1 m rod on a pin with friction (μ = 0.2, r = 2 cm, v_s = 1e-2 rad/s) released
/// horizontally: the friction torque depends on the pin's reaction, which swings with the
/// motion. Generalized-α (the reaction-dependent friction solved with the step's multipliers,
/// not lagged) converges to the tight DOPRI5 run, with the friction's work in the balance.
#[test]
fn pin_friction_under_generalized_alpha_converges_to_dopri5() {
    const VS: f64 = 1e-2;
    let mut b = common::rod_on_a_pin("rod", 1.0, 1.0, 1e-4);
    b.friction(
        FrictionSpec::new("bearing", "pin", 0.2)
            .radius(0.02)
            .stiction_velocity(VS),
    );
    let model = b.build().unwrap();
    let run = |integrator: Integrator| {
        let mut d = Dynamics::new(&model).unwrap();
        d.add_force(Force::gravity(Vector3::new(0.0, -G, 0.0)))
            .unwrap();
        let o = SimulationOptions::new(2.0, 20).integrator(integrator);
        let r = d.simulate(&d.initial_guess(), &o).unwrap();
        let tip: Vec<f64> = r.body("rod").unwrap().r.iter().map(|r| r.x).collect();
        let balance = (r.energy.balance().iter()).fold(0.0f64, |a, x| a.max(x.abs()));
        (tip, balance, r.energy.max_drift())
    };
    let (reference, balance, lost) =
        run(Integrator::Dopri5(Dopri5Options::tolerances(1e-11, 1e-13)));
    assert!(balance < 1e-8, "DOPRI5 balance {balance:e}");
    assert!(lost > 1e-2, "the friction takes energy: {lost}");
    let mut errors = Vec::new();
    for h in [2e-3, 5e-4, 1.25e-4] {
        let step = Integrator::GeneralizedAlpha(GeneralizedAlphaOptions::with_step(h));
        let (x, balance, _) = run(step);
        let error = (x.iter().zip(&reference)).fold(0.0f64, |a, (x, r)| a.max((x - r).abs()));
        eprintln!("h = {h}: x error {error:.3e}, balance {balance:.2e} of {lost:.3} J lost");
        errors.push((error, balance));
    }
    // The balance converges at second order (the scheme's numerical damping and the
    // trapezoidal work; the friction's work is in it). The position converges at second order
    // to h = 0.5 ms and then reaches a floor near 1.2e-6 m (2.7e-5, 2.4e-6, 1.2e-6 m at h = 2,
    // 0.5, 0.125 ms) whose cause is not identified: not the start from rest (the same with a
    // start at 1 rad/s and v_s = 0.1), not the Newton acceptance, not the reference; without
    // friction the same rod converges at 4× per halving.
    assert!(errors[2].0 < 3e-6, "{errors:?}");
    assert!(errors[0].0 / errors[2].0 > 10.0, "{errors:?}");
    for w in errors.windows(2) {
        assert!(
            w[0].1 / w[1].1 > 12.0,
            "balance not second order: {errors:?}"
        );
    }
}

/// A 2 kg top on a ball joint at its centre of mass, spinning at 10 rad/s about its symmetry
/// axis z (I_z = 0.2) under gravity −z, with ball friction μ = 0.2, r = 5 cm, preload 5 N: the
/// joint carries the weight, so the friction torque is μ r (m g + N₀) against the spin and
/// ω(t) = ω₀ − μ r (m g + N₀) t / I_z (no precession: the spin is about a principal axis).
/// Both integrators.
#[test]
fn a_top_on_a_ball_joint_spins_down_at_the_friction_torque() {
    let (m, iz, w0, mu, r, n0) = (2.0, 0.2, 10.0, 0.2, 0.05, 5.0);
    let mut b = MechanismBuilder::new();
    b.body(Body::new("top").mass(m).inertia_diagonal(0.1, 0.1, iz));
    b.point(GROUND, "O", Vector3::zeros());
    b.point("top", "C", Vector3::zeros());
    b.joint(JointSpec::new(
        "ball",
        JointKind::Spherical,
        (GROUND, "O"),
        ("top", "C"),
    ));
    b.friction(
        FrictionSpec::new("socket", "ball", mu)
            .radius(r)
            .preload(n0),
    );
    let model = b.build().unwrap();
    let rate = mu * r * (m * G + n0) / iz;
    for integrator in [
        Integrator::Dopri5(Dopri5Options::tolerances(1e-10, 1e-12)),
        Integrator::GeneralizedAlpha(GeneralizedAlphaOptions::with_step(1e-3)),
    ] {
        let mut d = Dynamics::new(&model).unwrap();
        d.add_force(Force::gravity(Vector3::new(0.0, 0.0, -G)))
            .unwrap();
        let mut start = d.initial_guess();
        start.v[5] = w0;
        let o = SimulationOptions::new(1.0, 10).integrator(integrator);
        let res = d.simulate(&start, &o).unwrap();
        let top = res.body("top").unwrap();
        for (k, &t) in res.times().iter().enumerate() {
            let want = w0 - rate * t;
            let w = top.omega[k];
            assert!(
                (w.z - want).abs() < 1e-8,
                "{integrator:?} t = {t}: {} vs {want}",
                w.z
            );
            assert!(w.x.abs() + w.y.abs() < 1e-10, "precession {w:?}");
        }
        let torque = d.friction_history().value.last().unwrap()[0];
        assert!((torque - mu * r * (m * G + n0)).abs() < 1e-9, "{torque}");
    }
}

/// A 2 kg sleeve on a horizontal cylindrical joint along x (I_x = 0.05) under gravity −y,
/// pushed at 1 m/s and turning at 5 rad/s, with friction μ = 0.3, r = 2 cm: the joint carries
/// the weight across its axis, so the slide decelerates at μ g and the turning at
/// μ r m g / I_x, each against its own rate (the two friction laws of a cylindrical joint).
#[test]
fn a_sleeve_on_a_cylindrical_joint_slows_in_slide_and_turn() {
    let (m, ix, v0, w0, mu, r) = (2.0, 0.05, 1.0, 5.0, 0.3, 0.02);
    let mut b = MechanismBuilder::new();
    b.body(Body::new("sleeve").mass(m).inertia_diagonal(ix, 0.1, 0.1));
    b.point(GROUND, "O", Vector3::zeros())
        .vector(GROUND, "x", Vector3::x());
    b.point("sleeve", "C", Vector3::zeros())
        .vector("sleeve", "x", Vector3::x());
    b.joint(
        JointSpec::new(
            "rail",
            JointKind::Cylindrical,
            (GROUND, "O"),
            ("sleeve", "C"),
        )
        .axes("x", "x"),
    );
    b.friction(FrictionSpec::new("bushing", "rail", mu).radius(r));
    let model = b.build().unwrap();
    for integrator in [
        Integrator::Dopri5(Dopri5Options::tolerances(1e-10, 1e-12)),
        Integrator::GeneralizedAlpha(GeneralizedAlphaOptions::with_step(1e-3)),
    ] {
        let mut d = Dynamics::new(&model).unwrap();
        d.add_force(Force::gravity(Vector3::new(0.0, -G, 0.0)))
            .unwrap();
        let mut start = d.initial_guess();
        start.v[0] = v0;
        start.v[3] = w0;
        let o = SimulationOptions::new(0.2, 10).integrator(integrator);
        let res = d.simulate(&start, &o).unwrap();
        let sleeve = res.body("sleeve").unwrap();
        for (k, &t) in res.times().iter().enumerate() {
            let (v, w) = (sleeve.r_dot[k].x, sleeve.omega[k].x);
            let (v_want, w_want) = (v0 - mu * G * t, w0 - mu * r * m * G / ix * t);
            assert!(
                (v - v_want).abs() < 1e-8,
                "{integrator:?} t = {t}: v {v} vs {v_want}"
            );
            assert!(
                (w - w_want).abs() < 1e-8,
                "{integrator:?} t = {t}: ω {w} vs {w_want}"
            );
        }
    }
}
