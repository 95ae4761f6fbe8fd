//! Limits in forward dynamics (issue 48): impacts on stops located on the dense output, with
//! Newton's restitution, against closed forms: a pendulum falling onto a stop, a ball bouncing
//! on a prismatic limit until its impacts accumulate to rest, the energy through impacts.

use cardan_constraints::JointKind;
use cardan_dynamics::{
    Dopri5Options, Dynamics, Force, GeneralizedAlphaOptions, Integrator, SimulationOptions,
};
use cardan_mechanism::{Body, JointSpec, LimitSpec, MechanismBuilder, Model, GROUND};
use nalgebra::Vector3;
use std::f64::consts::PI;

mod common;

const G: f64 = 9.81;

/// A 1 kg, 1 m rod pinned at its end O about global z, released horizontally (angle 0) with a
/// lower stop at `lo` (the angle falls under gravity −y).
fn pendulum(lo: f64, e: f64) -> Model {
    let mut b = common::rod_on_a_pin("rod", 1.0, 1.0, 1e-4);
    b.limit(LimitSpec::new("stop", "pin").lower(lo).restitution(e));
    b.build().unwrap()
}

/// A 1 kg ball on a vertical prismatic joint (slide = height), dropped from `h` onto a lower
/// limit at 0 with restitution `e`.
fn ball(h: f64, e: f64) -> Model {
    let mut b = MechanismBuilder::new();
    b.body(
        Body::new("ball")
            .mass(1.0)
            .inertia_diagonal(0.1, 0.1, 0.1)
            .position(Vector3::new(0.0, h, 0.0)),
    );
    b.point(GROUND, "O", Vector3::zeros())
        .vector(GROUND, "y", Vector3::y())
        .vector(GROUND, "x", Vector3::x());
    b.point("ball", "C", Vector3::zeros())
        .vector("ball", "y", Vector3::y())
        .vector("ball", "x", Vector3::x());
    b.joint(
        JointSpec::new("rail", JointKind::Prismatic, (GROUND, "O"), ("ball", "C"))
            .axes("y", "y")
            .x_axes("x", "x"),
    );
    b.limit(LimitSpec::new("floor", "rail").lower(0.0).restitution(e));
    b.build().unwrap()
}

fn dynamics(model: &Model) -> Dynamics<'_> {
    let mut d = Dynamics::new(model).unwrap();
    d.add_force(Force::gravity(Vector3::new(0.0, -G, 0.0)))
        .unwrap();
    d
}

fn tight() -> Integrator {
    Integrator::Dopri5(Dopri5Options::tolerances(1e-12, 1e-14))
}

/// t(θ) of the pendulum released at rest from 0: ∫₀^|θ| dφ / √(k sin φ), k = 3g/L, with
/// φ = u² (the integrand 2u / √(k sin u²) is smooth), composite Simpson.
fn fall_time(theta: f64) -> f64 {
    let k = 3.0 * G;
    let (a, b, n) = (0.0, theta.abs().sqrt(), 20_000);
    let f = |u: f64| {
        if u == 0.0 {
            2.0 / k.sqrt()
        } else {
            2.0 * u / (k * (u * u).sin()).sqrt()
        }
    };
    let h = (b - a) / n as f64;
    let mut s = f(a) + f(b);
    for i in 1..n {
        s += f(a + i as f64 * h) * if i % 2 == 1 { 4.0 } else { 2.0 };
    }
    s * h / 3.0
}

#[test]
fn pendulum_falling_onto_a_stop_matches_energy_conservation_and_restitution() {
    let (lo, e) = (-PI / 3.0, 0.6);
    let model = pendulum(lo, e);
    let mut d = dynamics(&model);
    let options = SimulationOptions::new(0.6, 60).integrator(tight());
    let res = d.simulate(&d.initial_guess(), &options).unwrap();
    let ev = d.impact_events();
    assert!(!ev.is_empty(), "no impact");
    let first = &ev[0];
    // ω² = (3g/L)(sin 0 − sin θ) at θ = lo.
    let omega = (3.0 * G * (-lo.sin())).sqrt();
    let t_star = fall_time(lo);
    eprintln!(
        "impact at {} (closed form {t_star}, diff {:.2e}); ω⁻ {} ({omega}, diff {:.2e}); ω⁺ {} (diff {:.2e})",
        first.time,
        first.time - t_star,
        first.impact_velocity,
        first.impact_velocity + omega,
        first.rebound_velocity,
        first.rebound_velocity - e * omega
    );
    assert!((first.time - t_star).abs() < 1e-9);
    assert!((first.impact_velocity + omega).abs() < 1e-9);
    assert!((first.rebound_velocity - e * omega).abs() < 1e-9);
    assert!(!first.held && !first.release);
    // The energy lost is ½ I_O (1 − e²) ω², I_O = m L²/3; the balance closes with it.
    let lost = 0.5 / 3.0 * (1.0 - e * e) * omega * omega;
    assert!(
        (first.energy_change + lost).abs() < 1e-9,
        "{}",
        first.energy_change
    );
    let balance = res.energy.balance();
    let worst = balance.iter().fold(0.0f64, |a, b| a.max(b.abs()));
    assert!(worst < 1e-8, "energy balance {worst:e}");
    // The angle never passes the stop.
    let angles = &res.kinematics.joints[0].values;
    assert!(angles.iter().all(|a| a[0] >= lo - 1e-9));
}

#[test]
fn elastic_impacts_conserve_energy() {
    let model = pendulum(-PI / 4.0, 1.0);
    let mut d = dynamics(&model);
    let options = SimulationOptions::new(3.0, 300).integrator(tight());
    let res = d.simulate(&d.initial_guess(), &options).unwrap();
    let n = d.impact_events().len();
    assert!(n >= 3, "{n} impacts");
    let drift = res.energy.max_drift();
    eprintln!("{n} elastic impacts, energy drift {drift:.2e}");
    assert!(drift < 1e-8, "{drift:e}");
}

/// Closed form of the bouncing ball: v₀ = √(2gh) at the first impact t₁ = v₀/g, then the n-th
/// impact (n ≥ 1) at closing speed eⁿ⁻¹ v₀, t_{n+1} = t_n + 2 eⁿ v₀/g; the impacts accumulate at
/// T∞ = t₁ + 2 v₀ e / (g (1 − e)).
fn bounces(h: f64, e: f64, rest: f64) -> (Vec<(f64, f64)>, f64) {
    let v0 = (2.0 * G * h).sqrt();
    let mut out = Vec::new();
    let (mut t, mut v) = (v0 / G, v0);
    loop {
        out.push((t, v));
        if v < rest {
            break;
        }
        t += 2.0 * e * v / G;
        v *= e;
    }
    (out, v0 / G + 2.0 * v0 * e / (G * (1.0 - e)))
}

fn bouncing_ball(integrator: Integrator, time_tol: f64, velocity_tol: f64) {
    let (h, e, rest) = (1.0, 0.5, 1e-5);
    let model = ball(h, e);
    let mut d = dynamics(&model);
    let (want, t_inf) = bounces(h, e, rest);
    let options = SimulationOptions::new(t_inf + 0.5, 100).integrator(integrator);
    let res = match d.simulate(&d.initial_guess(), &options) {
        Ok(r) => r,
        Err(e) => {
            for ev in d.impact_events() {
                eprintln!("{ev:?}");
            }
            panic!("{e}")
        }
    };
    let ev = d.impact_events();
    eprintln!(
        "{} impacts (closed form {}), held at {} (T∞ = {t_inf})",
        ev.len(),
        want.len(),
        ev.last().unwrap().time
    );
    assert_eq!(ev.len(), want.len());
    let (mut dt, mut dv) = (0.0f64, 0.0f64);
    for (k, (got, (t, v))) in ev.iter().zip(&want).enumerate() {
        dt = dt.max((got.time - t).abs());
        dv = dv.max((got.impact_velocity + v).abs());
        // Apex heights h e^(2n): the rebound speed is e times the impact speed.
        if !got.held {
            assert!(
                (got.rebound_velocity - e * v).abs() < velocity_tol,
                "impact {k}"
            );
            let lost = 0.5 * (1.0 - e * e) * v * v;
            assert!(
                (got.energy_change + lost).abs() < velocity_tol,
                "impact {k}"
            );
        }
    }
    eprintln!("max error of the impact times {dt:.2e}, of the impact velocities {dv:.2e}");
    assert!(dt < time_tol && dv < velocity_tol);
    assert!(ev.last().unwrap().held);
    assert!(ev.last().unwrap().time < t_inf);
    // At rest on the stop afterwards.
    let y = &res.body("ball").unwrap().r;
    let last = y.last().unwrap();
    assert!(last.y.abs() < 1e-8, "{}", last.y);
    let worst = res
        .energy
        .balance()
        .iter()
        .fold(0.0f64, |a, b| a.max(b.abs()));
    eprintln!("energy balance {worst:.2e}");
    assert!(worst < 10.0 * velocity_tol);
}

#[test]
fn bouncing_ball_accumulates_to_rest_dopri5() {
    bouncing_ball(tight(), 1e-9, 1e-9);
}

#[test]
fn bouncing_ball_accumulates_to_rest_generalized_alpha() {
    bouncing_ball(
        Integrator::GeneralizedAlpha(GeneralizedAlphaOptions::with_step(1e-3)),
        1e-6,
        1e-6,
    );
}

#[test]
fn a_ball_dropped_with_e_zero_stays_on_the_stop() {
    let model = ball(0.5, 0.0);
    let mut d = dynamics(&model);
    let options = SimulationOptions::new(1.0, 10).integrator(tight());
    let res = d.simulate(&d.initial_guess(), &options).unwrap();
    let ev = d.impact_events();
    assert_eq!(ev.len(), 1);
    assert!(ev[0].held);
    let y = &res.body("ball").unwrap().r;
    assert!(y.last().unwrap().y.abs() < 1e-9);
    // Resting: the stop carries the weight, λ_s = −m g (the reaction −Gᵀλ pushes up).
    let (held, lambda) = d.stop_states();
    assert!(held[0]);
    assert!((lambda[0] + G).abs() < 1e-6, "{}", lambda[0]);
    // The history per output time: open while falling, then held with the weight on it.
    let h = d.stop_history();
    assert_eq!(h.times.len(), res.times().len());
    assert!(!h.held[1][0] && h.force[1][0] == 0.0);
    assert!(*h.held.last().unwrap().first().unwrap());
    assert!((h.force.last().unwrap()[0] - G).abs() < 1e-6);
}

#[test]
fn a_held_stop_releases_where_its_multiplier_changes_sign() {
    // The ball rests on the floor (h = 0, e = 0) and is lifted by F(t) = 2 m g t: the stop
    // carries m g − F until t = 0.5, then the ball rises with ÿ = 2 g t − g, so
    // y(t) = g (t − ½)³ / 3.
    let model = ball(0.0, 0.0);
    let mut d = dynamics(&model);
    d.set_user_forces(|t, f| {
        f.add_force(
            cardan_mechanism::BodyId::Moving(0),
            &Vector3::new(0.0, 2.0 * G * t, 0.0),
        )
    });
    let options = SimulationOptions::new(1.0, 10).integrator(tight());
    let res = d.simulate(&d.initial_guess(), &options).unwrap();
    let ev = d.impact_events();
    let release = ev.iter().find(|e| e.release).expect("a release");
    eprintln!("{ev:?}");
    assert!((release.time - 0.5).abs() < 1e-9, "{}", release.time);
    let y = res.body("ball").unwrap().r.last().unwrap().y;
    let want = G * 0.5f64.powi(3) / 3.0;
    assert!((y - want).abs() < 1e-8, "{y} {want}");
    // Before the release the height stays 0 (held), not below.
    for (t, r) in res.times().iter().zip(&res.body("ball").unwrap().r) {
        if *t < 0.5 {
            assert!(r.y.abs() < 1e-9, "{t}: {}", r.y);
        }
    }
}

#[test]
fn a_state_beyond_a_limit_at_the_start_is_an_error() {
    let model = ball(1.0, 0.5);
    let mut d = dynamics(&model);
    let mut s = d.initial_guess();
    s.set_pose(
        0,
        Vector3::new(0.0, -0.1, 0.0),
        nalgebra::Vector4::new(1.0, 0.0, 0.0, 0.0),
    );
    let e = d
        .simulate(&s, &SimulationOptions::new(0.1, 1))
        .expect_err("beyond the floor");
    let msg = e.to_string();
    assert!(msg.contains("\"floor\"") && msg.contains("lower"), "{msg}");
}

#[test]
fn a_pendulum_rests_on_its_stop_in_statics_with_the_stop_reaction() {
    // Gravity pulls the horizontal rod down; the stop at −30° holds it. The stop's reaction
    // (the holding driver's effort) balances the gravity torque m g (L/2) cos θ and pushes
    // into the range (positive at a lower stop).
    use cardan_constraints::Bound;
    use cardan_dynamics::StaticOptions;
    let lo = -PI / 6.0;
    let mut b = MechanismBuilder::new();
    b.body(
        Body::new("rod")
            .mass(1.0)
            .inertia_diagonal(1e-4, 1.0 / 12.0, 1.0 / 12.0)
            .position(Vector3::new(0.5, 0.0, 0.0)),
    );
    b.point(GROUND, "O", Vector3::zeros())
        .vector(GROUND, "z", Vector3::z())
        .vector(GROUND, "x", Vector3::x());
    b.point("rod", "O", Vector3::new(-0.5, 0.0, 0.0))
        .vector("rod", "z", Vector3::z())
        .vector("rod", "x", Vector3::x());
    b.joint(
        JointSpec::new("pin", JointKind::Revolute, (GROUND, "O"), ("rod", "O"))
            .axes("z", "z")
            .x_axes("x", "x"),
    );
    b.limit(LimitSpec::new("stop", "pin").lower(lo));
    let held = b.holding_stop("stop", Bound::Lower).unwrap();
    let model = held.build().unwrap();
    let mut d = dynamics(&model);
    let r = d.statics(&StaticOptions::at(0.0)).unwrap();
    let angle = r.results.kinematics.joints[0].values[0][0];
    let effort = r.results.drivers[0].effort[0];
    let want = G * 0.5 * lo.cos();
    eprintln!("resting at {angle} (stop {lo}); stop reaction {effort} N m (closed form {want})");
    assert_eq!(r.results.drivers[0].name, "stop.lower");
    assert!((angle - lo).abs() < 1e-12);
    assert!((effort - want).abs() < 1e-9, "{effort} {want}");
    // An upper bound the limit does not have is an error.
    assert!(b.holding_stop("stop", Bound::Upper).is_err());
}

#[test]
fn a_compliant_floor_returns_an_elastic_ball_to_its_height() {
    // F = k δ on the penetration δ: the contact is a half-oscillation about δ_eq = m g / k of
    // amplitude A = √(δ_eq² + (v₀/ω)²), lasting (π + 2 asin(δ_eq/A))/ω, ω = √(k/m); the ball
    // leaves at v₀ and is back at h at t₁ + T_c + v₀/g, reaching δ_eq + A at the bottom.
    use cardan_mechanism::Compliance;
    let (h, k) = (1.0, 1e5);
    let mut b = MechanismBuilder::new();
    b.body(
        Body::new("ball")
            .mass(1.0)
            .inertia_diagonal(0.1, 0.1, 0.1)
            .position(Vector3::new(0.0, h, 0.0)),
    );
    b.point(GROUND, "O", Vector3::zeros())
        .vector(GROUND, "y", Vector3::y())
        .vector(GROUND, "x", Vector3::x());
    b.point("ball", "C", Vector3::zeros())
        .vector("ball", "y", Vector3::y())
        .vector("ball", "x", Vector3::x());
    b.joint(
        JointSpec::new("rail", JointKind::Prismatic, (GROUND, "O"), ("ball", "C"))
            .axes("y", "y")
            .x_axes("x", "x"),
    );
    b.limit(
        LimitSpec::new("floor", "rail")
            .lower(0.0)
            .compliant(Compliance {
                stiffness: k,
                damping: 0.0,
                exponent: 1.0,
            }),
    );
    let model = b.build().unwrap();
    compliant_floor_checks(&model, h, k);
}

/// The compliant floor's closed forms (see the test above) checked on `model`, with a tight
/// run and with a loose one (rtol 1e-6), whose steps would straddle the contact's onset and end
/// (the force's kinks) were they not located.
fn compliant_floor_checks(model: &Model, h: f64, k: f64) {
    let mut d = dynamics(model);
    let v0 = (2.0 * G * h).sqrt();
    let w = k.sqrt();
    let deq = G / k;
    let a = (deq * deq + (v0 / w).powi(2)).sqrt();
    let tc = (PI + 2.0 * (deq / a).asin()) / w;
    let t1 = v0 / G;
    let t_bottom = t1 + (0.5 * PI + (deq / a).asin()) / w;
    let t_apex = t1 + tc + v0 / G;
    let options = SimulationOptions::new(t_apex, 1)
        .integrator(tight())
        .output_times(vec![0.0, t_bottom, t_apex]);
    let res = d.simulate(&d.initial_guess(), &options).unwrap();
    let y = &res.body("ball").unwrap().r;
    eprintln!(
        "bottom {} (closed form {}), apex {} (closed form {h})",
        y[1].y,
        -(deq + a),
        y[2].y
    );
    assert!((y[1].y + deq + a).abs() < 1e-9);
    assert!((y[2].y - h).abs() < 1e-8);
    assert!(d.impact_events().is_empty());
    let worst = res
        .energy
        .balance()
        .iter()
        .fold(0.0f64, |m, x| m.max(x.abs()));
    assert!(worst < 1e-7, "{worst:e}");
    // Loose: the located kinks keep the run on the closed form to its tolerance.
    let loose = Integrator::Dopri5(Dopri5Options::tolerances(1e-6, 1e-8));
    let options = SimulationOptions::new(t_apex, 1)
        .integrator(loose)
        .output_times(vec![0.0, t_bottom, t_apex]);
    let res = d.simulate(&d.initial_guess(), &options).unwrap();
    let y = &res.body("ball").unwrap().r;
    eprintln!(
        "loose: bottom error {:.3e}, apex error {:.3e}, {} steps ({} rejected)",
        y[1].y + deq + a,
        y[2].y - h,
        res.stats.steps,
        res.stats.rejected
    );
    // Without the kinks located: apex 2.1e-4 m off (the steps straddling them); with: 8.4e-6.
    assert!((y[2].y - h).abs() < 3e-5, "apex {}", y[2].y);
    assert!((y[1].y + deq + a).abs() < 1e-6, "bottom {}", y[1].y);
}

#[test]
fn a_motor_driving_through_a_stop_is_an_error_naming_the_limit() {
    // The crank's angle is prescribed θ = −t: the stop at −0.5 rad cannot act on it.
    let model = {
        let mut b = MechanismBuilder::new();
        b.body(
            Body::new("rod")
                .mass(1.0)
                .inertia_diagonal(1e-4, 1.0 / 12.0, 1.0 / 12.0)
                .position(Vector3::new(0.5, 0.0, 0.0)),
        );
        b.point(GROUND, "O", Vector3::zeros())
            .vector(GROUND, "z", Vector3::z())
            .vector(GROUND, "x", Vector3::x());
        b.point("rod", "O", Vector3::new(-0.5, 0.0, 0.0))
            .vector("rod", "z", Vector3::z())
            .vector("rod", "x", Vector3::x());
        b.joint(
            JointSpec::new("pin", JointKind::Revolute, (GROUND, "O"), ("rod", "O"))
                .axes("z", "z")
                .x_axes("x", "x"),
        );
        b.driver(cardan_mechanism::DriverSpec::rotation(
            "motor",
            "pin",
            cardan_mechanism::TimeFunction::Polynomial(vec![0.0, -1.0]),
        ));
        b.limit(LimitSpec::new("stop", "pin").lower(-0.5));
        b.build().unwrap()
    };
    let mut d = dynamics(&model);
    let e = d
        .simulate(
            &d.initial_guess(),
            &SimulationOptions::new(1.0, 10).integrator(tight()),
        )
        .expect_err("the motor drives through the stop");
    let msg = e.to_string();
    eprintln!("{msg}");
    assert!(
        msg.contains("\"stop\"") && msg.contains("cannot act"),
        "{msg}"
    );
    let t: f64 = msg
        .split("reached at t = ")
        .nth(1)
        .unwrap()
        .split(',')
        .next()
        .unwrap()
        .parse()
        .unwrap();
    assert!((t - 0.5).abs() < 1e-12, "{t}");
}

/// Cost of a step with a limit that is never reached against the same run without it, and of
/// the events of the bouncing ball (`cargo test -p cardan-dynamics --test limits cost --
/// --ignored --nocapture`; wall time, so run it on a quiet machine).
#[test]
#[ignore]
fn cost_of_steps_and_events() {
    let time = |limit: bool| {
        let model = {
            let mut b = MechanismBuilder::new();
            b.body(
                Body::new("rod")
                    .mass(1.0)
                    .inertia_diagonal(1e-4, 1.0 / 12.0, 1.0 / 12.0)
                    .position(Vector3::new(0.5, 0.0, 0.0)),
            );
            b.point(GROUND, "O", Vector3::zeros())
                .vector(GROUND, "z", Vector3::z())
                .vector(GROUND, "x", Vector3::x());
            b.point("rod", "O", Vector3::new(-0.5, 0.0, 0.0))
                .vector("rod", "z", Vector3::z())
                .vector("rod", "x", Vector3::x());
            b.joint(
                JointSpec::new("pin", JointKind::Revolute, (GROUND, "O"), ("rod", "O"))
                    .axes("z", "z")
                    .x_axes("x", "x"),
            );
            if limit {
                b.limit(LimitSpec::new("stop", "pin").range(-3.5, 3.5));
            }
            b.build().unwrap()
        };
        let mut best = f64::INFINITY;
        let mut steps = 0;
        for _ in 0..5 {
            let mut d = dynamics(&model);
            let o = SimulationOptions::new(50.0, 100)
                .integrator(Integrator::Dopri5(Dopri5Options::tolerances(1e-9, 1e-11)));
            let r = d.simulate(&d.initial_guess(), &o).unwrap();
            assert!(d.impact_events().is_empty());
            steps = r.stats.steps;
            best = best.min(r.stats.wall_time / steps as f64);
        }
        (best, steps)
    };
    let (free, n0) = time(false);
    let (limited, n1) = time(true);
    eprintln!(
        "step without limits {:.3} µs ({n0} steps), with an unreached limit {:.3} µs ({n1} steps): {:+.1} %",
        free * 1e6,
        limited * 1e6,
        100.0 * (limited / free - 1.0)
    );
    let model = ball(1.0, 0.5);
    let mut best = f64::INFINITY;
    let (mut n, mut steps) = (0, 0);
    for _ in 0..5 {
        let mut d = dynamics(&model);
        let o = SimulationOptions::new(2.0, 100).integrator(tight());
        let r = d.simulate(&d.initial_guess(), &o).unwrap();
        best = best.min(r.stats.wall_time);
        n = d.impact_events().len();
        steps = r.stats.steps;
    }
    eprintln!(
        "bouncing ball: {n} events, {steps} steps, {:.1} µs in all, {:.1} µs per event at most",
        best * 1e6,
        best * 1e6 / n as f64
    );
}

/// A three-link arm hanging from ground by revolute joints about z, released at rest straight
/// along +x (every angle 0, inside its range) under gravity −y, with a range of ±0.6 rad on
/// every joint and restitution `e`.
fn arm(e: f64) -> Model {
    let mut b = MechanismBuilder::new();
    b.point(GROUND, "O", Vector3::zeros())
        .vector(GROUND, "z", Vector3::z())
        .vector(GROUND, "x", Vector3::x());
    let mut parent = GROUND.to_string();
    for k in 0..3 {
        let name = format!("link{k}");
        let x0 = 0.25 + 0.5 * k as f64;
        b.body(
            Body::new(&name)
                .mass(1.0)
                .inertia_diagonal(1e-3, 1.0 / 12.0 * 0.25, 1.0 / 12.0 * 0.25)
                .position(Vector3::new(x0, 0.0, 0.0)),
        );
        b.point(&name, "A", Vector3::new(-0.25, 0.0, 0.0))
            .point(&name, "B", Vector3::new(0.25, 0.0, 0.0))
            .vector(&name, "z", Vector3::z())
            .vector(&name, "x", Vector3::x());
        let at = if k == 0 { "O" } else { "B" };
        let joint = format!("j{k}");
        b.joint(
            JointSpec::new(
                &joint,
                JointKind::Revolute,
                (parent.as_str(), at),
                (name.as_str(), "A"),
            )
            .axes("z", "z")
            .x_axes("x", "x"),
        );
        b.limit(
            LimitSpec::new(format!("range{k}"), &joint)
                .range(-0.6, 0.6)
                .restitution(e),
        );
        parent = name;
    }
    b.build().unwrap()
}

#[test]
fn an_arm_with_limits_on_every_joint_runs_through_its_impacts_with_both_integrators() {
    let (bouncing, plastic) = (arm(0.3), arm(0.0));
    let dopri = Integrator::Dopri5(Dopri5Options::tolerances(1e-9, 1e-11));
    let alpha = Integrator::GeneralizedAlpha(GeneralizedAlphaOptions::with_step(1e-3));
    for (model, integrator, t_end) in [
        (&bouncing, dopri, 3.0),
        (&plastic, dopri, 3.0),
        (&bouncing, alpha, 1.0),
    ] {
        let mut d = dynamics(model);
        let o = SimulationOptions::new(t_end, 100).integrator(integrator);
        let r = match d.simulate(&d.initial_guess(), &o) {
            Ok(r) => r,
            Err(e) => {
                let all = d.impact_events();
                for ev in &all[all.len().saturating_sub(30)..] {
                    eprintln!(
                        "{:.6} {} v {:.3e} p {:.3e} v+ {:.3e} held {} release {}",
                        ev.time,
                        ev.stop,
                        ev.impact_velocity,
                        ev.impulse,
                        ev.rebound_velocity,
                        ev.held,
                        ev.release
                    );
                }
                panic!("{e}");
            }
        };
        let ev = d.impact_events();
        let impacts = ev.iter().filter(|e| !e.release).count();
        let releases = ev.iter().filter(|e| e.release).count();
        // Every joint angle stays in its range (to the hold tolerance).
        let worst = r
            .kinematics
            .joints
            .iter()
            .flat_map(|j| j.values.iter().map(|v| v[0].abs() - 0.6))
            .fold(f64::NEG_INFINITY, f64::max);
        let balance = r
            .energy
            .balance()
            .iter()
            .fold(0.0f64, |a, x| a.max(x.abs()));
        let lost: f64 = ev.iter().map(|e| e.energy_change).sum();
        eprintln!(
            "{integrator:?}: {impacts} impacts, {releases} releases, {} steps, worst overshoot \
             {worst:.1e} rad, energy lost in impacts {lost:.4} J, balance {balance:.1e} J",
            r.stats.steps
        );
        assert!(impacts >= 3);
        assert!(lost < 0.0);
        // DOPRI5 locates every impact on its dense output; generalized-α holds the closed
        // stops by a projection after each step (first order at the contact), so a chain of
        // closed stops re-impacts at the step size (documented in docs/validation.md).
        let (overshoot, relative) = match integrator {
            Integrator::Dopri5(_) => (1e-9, 1e-8),
            _ => (1e-4, 5e-3),
        };
        assert!(worst < overshoot, "{worst:e}");
        assert!(balance < relative * lost.abs(), "{balance:e}");
    }
}

/// A stop the motion only grazes: the pendulum released horizontally turns back at −π, and a
/// lower stop at −π + δ is passed by δ for 2 √(2δ/α) ≈ 7 ms (α = 3g/(2L) at the turning
/// point), inside one step of a loose DOPRI5 run (rtol 1e-6: 34 steps in 1.5 s). The gap is
/// positive at both ends of that step; the impact must still be found (the rate ġ turns from
/// closing to opening inside the step), at the closing rate √(3 g sin δ / L) of energy
/// conservation (to the loose run's accuracy), and no output may be beyond the stop.
#[test]
fn a_stop_grazed_inside_one_step_is_not_missed() {
    let delta = 1e-4;
    let lo = -PI + delta;
    let model = pendulum(lo, 0.5);
    let mut d = dynamics(&model);
    let loose = Integrator::Dopri5(Dopri5Options::tolerances(1e-6, 1e-8));
    let options = SimulationOptions::new(1.5, 300).integrator(loose);
    let res = d.simulate(&d.initial_guess(), &options).unwrap();
    let ev = d.impact_events();
    eprintln!("{} steps; events {ev:?}", res.stats.steps);
    assert!(!ev.is_empty(), "the grazing impact was missed");
    let omega = (3.0 * G * delta.sin()).sqrt();
    assert!(
        (ev[0].impact_velocity.abs() - omega).abs() < 1e-2 * omega,
        "closing rate {} against {omega}",
        ev[0].impact_velocity
    );
    let angles = &res.kinematics.joints[0].values;
    assert!(angles.iter().all(|a| a[0] >= lo - 1e-9));
}
