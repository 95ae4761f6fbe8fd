//! Contact between collision shapes: closed forms of a sphere on a plane (static Hertz
//! penetration, rebound at the stated restitution, a billiard ball's transition to rolling, a
//! ball rolling or slipping down an incline) and a box resting on a plane.

use cardan_dynamics::{Dopri5Options, Dynamics, Force, Integrator, SimulationOptions};
use cardan_mechanism::{
    Body, Geometry, MaterialSpec, MechanismBuilder, Model, ShapeSpec, Stiffness, GROUND,
};
use nalgebra::Vector3;

const G: f64 = 9.81;

/// A ball of mass m and radius r (solid: J = 2/5 m r²) at height z above the plane z = 0
/// (tilted by `slope` rad about x), of a material with stiffness K (n = 3/2), restitution e
/// and friction μ.
fn ball_on_plane(m: f64, r: f64, z: f64, k: f64, e: f64, mu: f64, slope: f64) -> Model {
    let mut b = MechanismBuilder::new();
    ball(&mut b, "ball", m, r, Vector3::new(0.0, 0.0, z), "steel");
    // Two materials of 2K: K.
    b.material(hertz("steel", 2.0 * k, e).friction(mu).slip_velocity(1e-4));
    let normal = Vector3::new(0.0, -slope.sin(), slope.cos());
    b.shape(ShapeSpec::new("floor", GROUND, Geometry::Plane, "steel").axes(normal, Vector3::x()));
    b.build().unwrap()
}

/// A material of direct stiffness K (n = 3/2) and restitution e, frictionless.
fn hertz(name: &str, k: f64, e: f64) -> MaterialSpec {
    MaterialSpec::new(name, Stiffness::Direct { k, exponent: 1.5 }, e)
}

/// A solid ball `name` of mass m and radius r (J = 2/5 m r²) at `at`, its sphere of `material`.
fn ball(b: &mut MechanismBuilder, name: &str, m: f64, r: f64, at: Vector3<f64>, material: &str) {
    let j = 0.4 * m * r * r;
    b.body(
        Body::new(name)
            .mass(m)
            .inertia_diagonal(j, j, j)
            .position(at),
    );
    b.shape(ShapeSpec::new(
        name,
        name,
        Geometry::Sphere { radius: r },
        material,
    ));
}

fn tight() -> Integrator {
    Integrator::Dopri5(Dopri5Options::tolerances(1e-10, 1e-12))
}

fn dynamics(model: &Model) -> Dynamics<'_> {
    let mut d = Dynamics::new(model).unwrap();
    d.add_force(Force::gravity(Vector3::new(0.0, 0.0, -G)))
        .unwrap();
    d
}

/// The rebound ratio v_out / v_in of a ball thrown at the plane at `v_in` without gravity
/// (measured once the contact has ended).
fn rebound_without_gravity(e: f64, integrator: Integrator) -> f64 {
    let (m, r, k, v_in) = (1.0, 0.05, 1e8, 2.0);
    let model = ball_on_plane(m, r, r + 0.01, k, e, 0.0, 0.0);
    let mut d = Dynamics::new(&model).unwrap();
    let mut s = d.initial_guess();
    s.set_velocity(0, Vector3::new(0.0, 0.0, -v_in), Vector3::zeros());
    let options = SimulationOptions::new(0.02, 2).integrator(integrator);
    let res = d.simulate(&s, &options).unwrap();
    res.body("ball").unwrap().r_dot[2].z / v_in
}

#[test]
fn a_ball_rebounds_at_the_stated_restitution() {
    // The law's hysteresis gives v_out = e v_in exactly for a normal impact (collision::law).
    // The onset located on the dense output starts the contact at its true approach speed (the
    // distance's root found to 1e-13 s; with the onset at the step's end instead, 3e-7); the
    // error left is the integration's: it falls with the tolerance.
    let tighter = Integrator::Dopri5(Dopri5Options::tolerances(1e-12, 1e-14));
    for e in [0.95, 0.7, 0.5, 0.2, 0.05] {
        let ratio = rebound_without_gravity(e, tight());
        let closer = rebound_without_gravity(e, tighter);
        eprintln!("e = {e}: v_out / v_in = {ratio:.10} (rtol 1e-10), {closer:.12} (1e-12)");
        assert!((ratio - e).abs() < 3e-8, "e = {e}: {ratio}");
        assert!((closer - e).abs() < 1e-9, "e = {e}: {closer}");
    }
}

#[test]
fn a_dropped_ball_rises_to_e_squared_of_its_height() {
    // Dropped from h above the plane: impact at v = √(2 g h), rebound to e² h. Gravity acts
    // during the contact too, changing the rebound speed by up to g T_c (T_c ≈ 2.94 δ_max / v,
    // δ_max = (5 m v² / (4 K))^(2/5), Johnson 1985 §11.4), which the check allows.
    for e in [0.9, 0.5, 0.2] {
        let (m, r, k, h) = (1.0, 0.05, 1e8, 0.2);
        let model = ball_on_plane(m, r, r + h, k, e, 0.0, 0.0);
        let mut d = dynamics(&model);
        let v_in = (2.0 * G * h).sqrt();
        let t_in = v_in / G;
        let t_out = t_in + 0.01 + e * v_in / G;
        let options = SimulationOptions::new(t_out, 2000).integrator(tight());
        let res = d.simulate(&d.initial_guess(), &options).unwrap();
        let ball = res.body("ball").unwrap();
        let apex = res
            .times()
            .iter()
            .zip(&ball.r)
            .filter(|(t, _)| **t > t_in + 0.005)
            .map(|(_, r)| r.z)
            .fold(f64::MIN, f64::max)
            - r;
        let ratio = (apex / h).sqrt();
        let d_max = (5.0 * m * v_in * v_in / (4.0 * k)).powf(0.4);
        let t_c = 2.94 * d_max / v_in;
        eprintln!(
            "e = {e}: √(apex/h) = {ratio:.6}, g T_c / v = {:.2e}",
            G * t_c / v_in
        );
        assert!((ratio - e).abs() < G * t_c / v_in, "e = {e}: {ratio}");
    }
}

/// A ball on a vertical rail (a prismatic joint along z) drawn 0.1 mm into the plane.
fn ball_on_a_rail(m: f64, r: f64, k: f64) -> Model {
    use cardan_mechanism::{JointKind, JointSpec};
    let mut b = MechanismBuilder::new();
    let j = 0.4 * m * r * r;
    b.body(
        Body::new("ball")
            .mass(m)
            .inertia_diagonal(j, j, j)
            .position(Vector3::new(0.0, 0.0, r - 1e-4)),
    );
    b.point(GROUND, "O", Vector3::zeros())
        .vector(GROUND, "z", Vector3::z())
        .vector(GROUND, "x", Vector3::x());
    b.point("ball", "C", Vector3::zeros())
        .vector("ball", "z", Vector3::z())
        .vector("ball", "x", Vector3::x());
    b.joint(
        JointSpec::new("rail", JointKind::Prismatic, (GROUND, "O"), ("ball", "C"))
            .axes("z", "z")
            .x_axes("x", "x"),
    );
    b.material(hertz("steel", 2.0 * k, 0.5));
    b.shape(ShapeSpec::new(
        "ball",
        "ball",
        Geometry::Sphere { radius: r },
        "steel",
    ));
    b.shape(ShapeSpec::new("floor", GROUND, Geometry::Plane, "steel"));
    b.build().unwrap()
}

#[test]
fn a_resting_ball_sinks_by_hertz_penetration() {
    // m g = K δ^(3/2): δ = (m g / K)^(2/3), the contact force m g. Statics from a pose in
    // contact (in free space the rail would be a free direction).
    use cardan_dynamics::StaticOptions;
    let (m, r, k) = (2.0, 0.1, 1e7);
    let delta = (m * G / k).powf(2.0 / 3.0);
    let model = ball_on_a_rail(m, r, k);
    let mut d = dynamics(&model);
    let res = d.statics(&StaticOptions::default()).unwrap();
    let z = res.results.body("ball").unwrap().r[0].z;
    let sink = r - z;
    eprintln!("statics: penetration {sink:.15e}, Hertz {delta:.15e}");
    assert!((sink - delta).abs() < 1e-9 * delta, "{sink} vs {delta}");
    // Dropped 1 mm onto the floor, the ball settles there.
    let model = ball_on_plane(m, r, r + 1e-3, k, 0.3, 0.0, 0.0);
    let mut d = dynamics(&model);
    let options = SimulationOptions::new(2.0, 4).integrator(tight());
    let res = d.simulate(&d.initial_guess(), &options).unwrap();
    let sink = r - res.body("ball").unwrap().r.last().unwrap().z;
    eprintln!("settled: penetration {sink:.15e}");
    assert!((sink - delta).abs() < 1e-9 * delta, "{sink} vs {delta}");
}

/// The billiard ball's closed form (module test below): the speed at `t` of a ball launched
/// sliding at v₀ without spin. Friction μ m g decelerates it and spins it up until it rolls.
/// The contact point P lies at mid-penetration, ρ = r − δ/2 below the centre (δ the static
/// penetration), so the ball rolls on ρ: v = ω ρ after t_r = v₀ / (μ g (1 + m ρ²/J)), at
/// v₀ / (1 + J/(m ρ²)) — for δ → 0, 2 v₀/(7 μ g) and 5 v₀/7.
fn billiard_closed_form(m: f64, r: f64, delta: f64, mu: f64, v0: f64, t: f64) -> f64 {
    let j = 0.4 * m * r * r;
    let rho = r - 0.5 * delta;
    let t_roll = v0 / (mu * G * (1.0 + m * rho * rho / j));
    if t < t_roll {
        v0 - mu * G * t
    } else {
        v0 / (1.0 + j / (m * rho * rho))
    }
}

#[test]
fn a_billiard_ball_slides_then_rolls_at_five_sevenths() {
    let (m, r, k, mu, v0) = (0.17, 0.028575, 1e8, 0.2, 2.0);
    let delta = (m * G / k).powf(2.0 / 3.0);
    let model = ball_on_plane(m, r, r - delta, k, 0.5, mu, 0.0);
    let mut d = dynamics(&model);
    let mut s = d.initial_guess();
    s.set_velocity(0, Vector3::new(v0, 0.0, 0.0), Vector3::zeros());
    let t_roll = 2.0 * v0 / (7.0 * mu * G);
    let times = vec![0.0, 0.5 * t_roll, 2.0 * t_roll];
    let options = SimulationOptions::new(2.0 * t_roll, 2)
        .integrator(tight())
        .output_times(times.clone());
    let res = d.simulate(&s, &options).unwrap();
    let ball = res.body("ball").unwrap();
    for k in 1..3 {
        let v = ball.r_dot[k].x;
        let exact = billiard_closed_form(m, r, delta, mu, v0, times[k]);
        eprintln!(
            "t = {:.4}: v = {v:.10} (closed form {exact:.10}; δ → 0: {:.10})",
            times[k],
            if k == 1 {
                v0 - mu * G * times[k]
            } else {
                5.0 * v0 / 7.0
            }
        );
        assert!((v - exact).abs() < 1e-8 * v0, "{v} vs {exact}");
    }
}

#[test]
fn generalized_alpha_rebounds_and_rolls_at_a_practical_step() {
    use cardan_dynamics::GeneralizedAlphaOptions;
    for h in [1e-4, 2.5e-5] {
        let ga = Integrator::GeneralizedAlpha(GeneralizedAlphaOptions::with_step(h));
        for e in [0.8, 0.3] {
            let ratio = rebound_without_gravity(e, ga);
            eprintln!("generalized-α h = {h:e}, e = {e}: v_out / v_in = {ratio:.6}");
            // About 18 and 72 steps over the contact (T_c ≈ 1.8 ms).
            // Measured: 2 % at e = 0.3 and h = 0.1 ms, 0.02 % at 25 µs.
            assert!((ratio - e).abs() < 0.03 * h / 1e-4 * e, "{ratio}");
        }
    }
    let (m, r, k, mu, v0) = (0.17, 0.028575, 1e8, 0.2, 2.0);
    let delta = (m * G / k).powf(2.0 / 3.0);
    let model = ball_on_plane(m, r, r - delta, k, 0.5, mu, 0.0);
    for h in [4e-3, 1e-3, 2.5e-4] {
        let mut d = dynamics(&model);
        let mut s = d.initial_guess();
        s.set_velocity(0, Vector3::new(v0, 0.0, 0.0), Vector3::zeros());
        let t_roll = 2.0 * v0 / (7.0 * mu * G);
        let ga = Integrator::GeneralizedAlpha(GeneralizedAlphaOptions::with_step(h));
        let options = SimulationOptions::new(2.0 * t_roll, 2)
            .integrator(ga)
            .output_times(vec![0.0, 0.5 * t_roll, 2.0 * t_roll]);
        let res = d.simulate(&s, &options).unwrap();
        let ball = res.body("ball").unwrap();
        let slide = ball.r_dot[1].x - billiard_closed_form(m, r, delta, mu, v0, 0.5 * t_roll);
        let roll = ball.r_dot[2].x - billiard_closed_form(m, r, delta, mu, v0, 2.0 * t_roll);
        eprintln!(
            "generalized-α h = {h:e}: sliding error {slide:.3e}, rolling error {roll:.3e}, {} \
             steps",
            res.stats.steps
        );
        assert!(slide.abs().max(roll.abs()) < 1e-6 * v0);
    }
}

#[test]
fn a_ball_rolls_down_an_incline_at_five_sevenths_or_slips() {
    // On a slope α, a ball rolls without slip when μ ≥ (2/7) tan α: a = g sin α / (1 + J/(m ρ²))
    // (5/7 g sin α for ρ → r), and slips otherwise: a = g (sin α − μ cos α). From rest, the
    // speed after T is a T, plus what the regularized law adds: rolling, the friction f = J a/ρ²
    // it needs makes it creep at the slip s* = v_s x / √(1 − x²), x = f / (μ N), which puts
    // s* / (1 + m ρ²/J) on the centre's speed; slipping, the friction's deficit μ N (1 − φ(s))
    // while the slip s builds up (φ = s/√(s² + v_s²), ṡ = A − B φ with A = g sin α and
    // B = μ g cos α (1 + m ρ²/J)) adds μ g cos α ∫₀^∞ (1 − φ)/(A − B φ) ds to it.
    let (m, r, k, alpha, t) = (1.0, 0.05, 1e9, 20f64.to_radians(), 0.5);
    let down = Vector3::new(0.0, -alpha.cos(), -alpha.sin());
    let normal = Vector3::new(0.0, -alpha.sin(), alpha.cos());
    for mu in [0.5, 0.05] {
        let rolls = mu >= 2.0 / 7.0 * alpha.tan();
        let delta = (m * G * alpha.cos() / k).powf(2.0 / 3.0);
        let mut b = MechanismBuilder::new();
        let j = 0.4 * m * r * r;
        b.body(
            Body::new("ball")
                .mass(m)
                .inertia_diagonal(j, j, j)
                .position(normal * (r - delta)),
        );
        b.material(hertz("m", 2.0 * k, 0.5).friction(mu).slip_velocity(1e-4));
        b.shape(ShapeSpec::new(
            "ball",
            "ball",
            Geometry::Sphere { radius: r },
            "m",
        ));
        b.shape(ShapeSpec::new("slope", GROUND, Geometry::Plane, "m").axes(normal, Vector3::x()));
        let model = b.build().unwrap();
        let mut d = dynamics(&model);
        let options = SimulationOptions::new(t, 1).integrator(tight());
        let res = d.simulate(&d.initial_guess(), &options).unwrap();
        let v = res.body("ball").unwrap().r_dot[1].dot(&down);
        let rho = r - 0.5 * delta;
        let (a, creep) = if rolls {
            let a = G * alpha.sin() / (1.0 + j / (m * rho * rho));
            let x = j * a / (rho * rho) / (mu * m * G * alpha.cos());
            let s_star = 1e-4 * x / (1.0 - x * x).sqrt();
            (a, s_star / (1.0 + m * rho * rho / j))
        } else {
            let (vs, aa) = (1e-4, G * alpha.sin());
            let bb = mu * G * alpha.cos() * (1.0 + m * rho * rho / j);
            // Simpson's rule on s = v_s sinh u, u ∈ [0, 12] (the integrand is e^(−2u) beyond).
            let f = |u: f64| {
                let phi = u.tanh();
                (1.0 - phi) / (aa - bb * phi) * vs * u.cosh()
            };
            let n = 20_000;
            let hu = 12.0 / n as f64;
            let sum: f64 = (0..=n)
                .map(|i| {
                    let w = if i == 0 || i == n {
                        1.0
                    } else if i % 2 == 1 {
                        4.0
                    } else {
                        2.0
                    };
                    w * f(i as f64 * hu)
                })
                .sum();
            (
                G * (alpha.sin() - mu * alpha.cos()),
                mu * G * alpha.cos() * sum * hu / 3.0,
            )
        };
        eprintln!(
            "μ = {mu} ({}): v = {v:.10}, closed form {:.10} (5/7 g sin α T = {:.10})",
            if rolls { "rolls" } else { "slips" },
            a * t + creep,
            5.0 / 7.0 * G * alpha.sin() * t
        );
        assert!((v - a * t - creep).abs() < 1e-8, "{v} vs {}", a * t + creep);
    }
}

/// `n` boxes of 0.2 × 0.2 × 0.1 m and 1 kg stacked on the floor, each drawn 0.1 mm above the one
/// below.
fn stack(n: usize) -> Model {
    let mut b = MechanismBuilder::new();
    let (a, c, m) = (0.2, 0.1, 1.0);
    for i in 0..n {
        let name = format!("box{i}");
        let jxx = m * (a * a + c * c) / 12.0;
        b.body(
            Body::new(&name)
                .mass(m)
                .inertia_diagonal(jxx, jxx, m * (a * a + a * a) / 12.0)
                .position(Vector3::new(
                    0.0,
                    0.0,
                    (i as f64 + 0.5) * c + (i as f64 + 1.0) * 1e-4,
                )),
        );
        b.shape(ShapeSpec::new(
            &name,
            &name,
            Geometry::Box {
                size: Vector3::new(a, a, c),
            },
            "wood",
        ));
    }
    b.material(hertz("wood", 2e7, 0.3).friction(0.5).slip_velocity(1e-4));
    b.shape(ShapeSpec::new("floor", GROUND, Geometry::Plane, "wood"));
    b.build().unwrap()
}

#[test]
fn boxes_rest_on_the_floor_and_on_each_other_without_drift_creep_or_energy_gain() {
    use cardan_dynamics::GeneralizedAlphaOptions;
    for (n, integrator, label) in [
        (1, tight(), "DOPRI5"),
        (
            1,
            Integrator::GeneralizedAlpha(GeneralizedAlphaOptions::with_step(1e-3)),
            "generalized-α h = 1 ms",
        ),
        (
            5,
            Integrator::GeneralizedAlpha(GeneralizedAlphaOptions::with_step(1e-3)),
            "generalized-α h = 1 ms",
        ),
    ] {
        let model = stack(n);
        let mut d = dynamics(&model);
        let t_end = 10.0;
        let options = SimulationOptions::new(t_end, 100).integrator(integrator);
        let res = d.simulate(&d.initial_guess(), &options).unwrap();
        // Settled by 1 s; from there on nothing moves and no energy appears.
        let settled = res.times().iter().position(|&t| t >= 1.0).unwrap();
        let mut drift: f64 = 0.0;
        let mut tilt: f64 = 0.0;
        for i in 0..n {
            let bx = res.body(&format!("box{i}")).unwrap();
            for k in settled..res.times().len() {
                drift = drift.max((bx.r[k] - bx.r[settled]).norm());
                tilt = tilt.max((bx.p[k] - bx.p[0]).norm());
            }
        }
        let e = &res.energy.total;
        let gain = (settled + 1..e.len())
            .map(|k| e[k] - e[k - 1])
            .fold(f64::MIN, f64::max);
        eprintln!(
            "{n} box(es), {label}: drift after 1 s {drift:.2e} m, tilt {tilt:.2e}, largest \
             energy gain between outputs {gain:.2e} J, {} steps",
            res.stats.steps
        );
        assert!(drift < 1e-7, "{drift}");
        assert!(tilt < 1e-6, "{tilt}");
        assert!(gain < 1e-9, "{gain}");
    }
}

/// Two balls of 1 cm stacked above the floor (steel, K = 1e9 N/m^1.5), dropped 5 mm.
fn two_balls() -> Model {
    let mut b = MechanismBuilder::new();
    let (r, m) = (0.01, 0.0327);
    for (k, z) in [(0, 1.5 * r), (1, 4.0 * r)] {
        ball(
            &mut b,
            &format!("ball{k}"),
            m,
            r,
            Vector3::new(0.0, 0.0, z),
            "steel",
        );
    }
    b.material(hertz("steel", 2e9, 0.5).friction(0.3));
    b.shape(ShapeSpec::new("floor", GROUND, Geometry::Plane, "steel"));
    b.build().unwrap()
}

#[test]
fn stacked_balls_settle_with_both_integrators() {
    // Two balls dropped 5 mm onto the floor, one on the other: they come to rest at their
    // static penetrations (the lower carries both: δ₁ = (2 m g / K)^(2/3), δ₂ = (m g / K)^(2/3),
    // K = 1e9 for the pair), and the energy balance E − E₀ − W_nc closes to the integrator's
    // accuracy: DOPRI5 at rtol 1e-10, generalized-α to second order once the impacts are
    // resolved (0.26 ms contacts: the 0.2 ms step does not resolve them).
    use cardan_dynamics::GeneralizedAlphaOptions;
    let model = two_balls();
    let (r, m, k) = (0.01, 0.0327, 1e9);
    let d1 = (2.0 * m * G / k).powf(2.0 / 3.0);
    let d2 = (m * G / k).powf(2.0 / 3.0);
    let ga = |h: f64| Integrator::GeneralizedAlpha(GeneralizedAlphaOptions::with_step(h));
    let mut balances = Vec::new();
    for (integrator, label, bound) in [
        (tight(), "DOPRI5", 1e-9),
        (ga(2e-4), "generalized-α h = 0.2 ms", 2e-3),
        (ga(2e-5), "generalized-α h = 0.02 ms", 3e-6),
        (ga(2e-6), "generalized-α h = 0.002 ms", 3e-9),
    ] {
        let mut d = dynamics(&model);
        let options = SimulationOptions::new(0.3, 30).integrator(integrator);
        let res = d.simulate(&d.initial_guess(), &options).unwrap();
        let z0 = res.body("ball0").unwrap().r.last().unwrap().z;
        let z1 = res.body("ball1").unwrap().r.last().unwrap().z;
        let balance = res.energy.max_balance();
        eprintln!(
            "{label}: z = {z0:.9} / {z1:.9}, balance {balance:.2e} J, {} steps ({} rejected), {} Newton iterations",
            res.stats.steps, res.stats.rejected, res.stats.newton_iterations
        );
        assert!((z0 - (r - d1)).abs() < 1e-3 * d1, "{label}: {z0}");
        assert!(
            (z1 - (3.0 * r - d1 - d2)).abs() < 1e-3 * d1,
            "{label}: {z1}"
        );
        assert!(balance < bound, "{label}: balance {balance:e}");
        balances.push(balance);
    }
    // Second order or better from 0.02 to 0.002 ms.
    assert!(balances[3] < balances[2] / 100.0, "{balances:?}");
}

#[test]
fn a_fast_ball_is_not_stepped_through_a_thin_wall() {
    // A 5 mm ball at 50 m/s towards a 2 mm wall 0.5 m away, no gravity: in free flight DOPRI5's
    // error estimate lets the step grow without bound, and a step longer than the wall and the
    // ball together would carry it through unseen. It must bounce back.
    let (m, r) = (0.004, 0.005);
    let j = 0.4 * m * r * r;
    let mut b = MechanismBuilder::new();
    b.body(
        Body::new("ball")
            .mass(m)
            .inertia_diagonal(j, j, j)
            .position(Vector3::zeros()),
    );
    b.material(hertz("steel", 2e9, 0.8));
    b.shape(ShapeSpec::new(
        "ball",
        "ball",
        Geometry::Sphere { radius: r },
        "steel",
    ));
    b.shape(
        ShapeSpec::new(
            "wall",
            GROUND,
            Geometry::Box {
                size: Vector3::new(0.002, 0.2, 0.2),
            },
            "steel",
        )
        .center(Vector3::new(0.5, 0.0, 0.0)),
    );
    let model = b.build().unwrap();
    let mut d = Dynamics::new(&model).unwrap();
    let mut s = d.initial_guess();
    s.set_velocity(0, Vector3::new(50.0, 0.0, 0.0), Vector3::zeros());
    let options = SimulationOptions::new(0.04, 4)
        .integrator(Integrator::Dopri5(Dopri5Options::tolerances(1e-8, 1e-10)));
    let res = d.simulate(&s, &options).unwrap();
    let ball = res.body("ball").unwrap();
    let (x, v) = (ball.r.last().unwrap().x, ball.r_dot.last().unwrap().x);
    eprintln!(
        "after 40 ms: x = {x:.4} m, v = {v:.4} m/s, {} steps",
        res.stats.steps
    );
    assert!(
        x < 0.5 && v < 0.0,
        "the ball went through the wall: x = {x}, v = {v}"
    );
    assert!((v + 0.8 * 50.0).abs() < 0.05 * 50.0, "{v}");
}

#[test]
fn generalized_alpha_settles_a_small_pile_with_friction() {
    // Eight 1 cm balls in two layers in a 5 cm box (a floor and four walls), drawn a little off
    // a grid so that they press on the walls and land off-centre on each other (friction turns
    // them), generalized-α at 0.2 ms. Before, Newton never converged once bodies in contact
    // coupled a free ball's torque-free rotation to the solve: its residual group held
    // roundoff only and read 1.0 relative forever ("step size below the minimum" at t = 0.043 s).
    use cardan_dynamics::GeneralizedAlphaOptions;
    let (r, m) = (0.01, 0.0327);
    let mut b = MechanismBuilder::new();
    let at = [
        [-0.013962543023550395, -0.01111026505225107, 0.015],
        [-0.011444901524093545, 0.011520276102957683, 0.015],
        [0.012481740348367762, -0.012702035740845049, 0.015],
        [0.013106371890891049, 0.01365489340454205, 0.015],
        [-0.01412456165290306, -0.014386610093911976, 0.04],
        [-0.011156939584320522, 0.01223106827162021, 0.04],
        [0.013549120329831766, -0.014491575786595559, 0.04],
        [0.012281548776219203, 0.013386160129363127, 0.04],
    ];
    for (k, p) in at.iter().enumerate() {
        ball(&mut b, &format!("s{k}"), m, r, Vector3::from(*p), "steel");
    }
    b.material(hertz("steel", 2e9, 0.5).friction(0.3));
    b.shape(ShapeSpec::new("floor", GROUND, Geometry::Plane, "steel"));
    for (k, (c, n)) in [
        (Vector3::new(-0.025, 0.0, 0.0), Vector3::x()),
        (Vector3::new(0.025, 0.0, 0.0), -Vector3::x()),
        (Vector3::new(0.0, -0.025, 0.0), Vector3::y()),
        (Vector3::new(0.0, 0.025, 0.0), -Vector3::y()),
    ]
    .into_iter()
    .enumerate()
    {
        let wall = ShapeSpec::new(format!("w{k}"), GROUND, Geometry::Plane, "steel");
        b.shape(wall.center(c).axes(n, Vector3::z()));
    }
    let model = b.build().unwrap();
    let mut d = dynamics(&model);
    let ga = Integrator::GeneralizedAlpha(GeneralizedAlphaOptions::with_step(2e-4));
    let res = d
        .simulate(
            &d.initial_guess(),
            &SimulationOptions::new(0.2, 20).integrator(ga),
        )
        .unwrap_or_else(|e| panic!("{e}"));
    let z_min = (0..8)
        .map(|k| res.body(&format!("s{k}")).unwrap().r.last().unwrap().z)
        .fold(f64::INFINITY, f64::min);
    eprintln!(
        "pile: {} steps ({} rejected), lowest centre {z_min:.6} m",
        res.stats.steps, res.stats.rejected
    );
    assert!(z_min > 0.9 * r, "a ball sank through the floor: {z_min}");
}
