//! Power, work and the energy balance (issue 28): E(t) − E(t₀) − W_nc(t) is the integration
//! error, and each element's work equals an independent computation.
//!
//! The model: a crank turned by a rotation driver, an arm hanging from its tip on a revolute
//! joint with a rotational spring-damper, a strut (spring, damper and constant actuator tension)
//! from a ground point to the arm's tip, a constant torque on the arm, gravity. Its energy changes
//! by joules (the drift), all of it explained by the work of the driver, the dampers, the
//! actuator and the torque.

mod common;
use cardan_constraints::{JointKind, TimeFunction};
use cardan_dynamics::{
    Dopri5Options, DynamicResults, Dynamics, Force, Frame, GeneralizedAlphaOptions, Integrator,
    SimulationOptions,
};
use cardan_mechanism::{
    Body, BodyId, DriverSpec, JointSpec, KinematicOptions, MechanismBuilder, Model, GROUND,
};
use nalgebra::Vector3;

const C_ELBOW: f64 = 0.3;
const C_STRUT: f64 = 0.5;
const F_ACTUATOR: f64 = 1.0;
const TORQUE: f64 = 0.2;
const D: [f64; 3] = [0.0, -1.5, 0.0];

/// The crank's angle θ(t) = 2 t + 0.5 t² and its rate.
fn crank_angle() -> TimeFunction {
    TimeFunction::Polynomial(vec![0.0, 2.0, 0.5])
}

fn crank_rate(t: f64) -> f64 {
    2.0 + t
}

/// Crank (0.5 m, 1 kg) pinned at the origin about z, arm (0.6 m, 0.8 kg) pinned at its tip.
fn model(driven: bool) -> Model {
    let mut b = MechanismBuilder::new();
    b.body(
        Body::new("crank")
            .mass(1.0)
            .inertia_diagonal(1e-3, 0.5 * 0.5 / 12.0, 0.5 * 0.5 / 12.0)
            .position(Vector3::new(0.25, 0.0, 0.0)),
    );
    b.body(
        Body::new("arm")
            .mass(0.8)
            .inertia_diagonal(1e-3, 0.8 * 0.36 / 12.0, 0.8 * 0.36 / 12.0)
            .position(Vector3::new(0.8, 0.0, 0.0)),
    );
    b.point(GROUND, "O", Vector3::zeros())
        .vector(GROUND, "z", Vector3::z())
        .vector(GROUND, "x", Vector3::x());
    b.point("crank", "O", Vector3::new(-0.25, 0.0, 0.0))
        .point("crank", "tip", Vector3::new(0.25, 0.0, 0.0))
        .vector("crank", "z", Vector3::z())
        .vector("crank", "x", Vector3::x());
    b.point("arm", "A", Vector3::new(-0.3, 0.0, 0.0))
        .point("arm", "B", Vector3::new(0.3, 0.0, 0.0))
        .vector("arm", "z", Vector3::z())
        .vector("arm", "x", Vector3::x());
    b.joint(
        JointSpec::new("pin", JointKind::Revolute, (GROUND, "O"), ("crank", "O"))
            .axes("z", "z")
            .x_axes("x", "x"),
    );
    b.joint(
        JointSpec::new("elbow", JointKind::Revolute, ("crank", "tip"), ("arm", "A"))
            .axes("z", "z")
            .x_axes("x", "x"),
    );
    if driven {
        b.driver(DriverSpec::rotation("motor", "pin", crank_angle()));
    }
    b.build().unwrap()
}

/// The model's dynamics: gravity, plus (when `damped`) the elbow's spring-damper, the strut and
/// the torque.
fn dynamics(model: &Model, damped: bool) -> Dynamics<'_> {
    let mut d = Dynamics::new(model).unwrap();
    d.add_force(Force::gravity(Vector3::new(0.0, -9.81, 0.0)))
        .unwrap();
    if damped {
        d.add_force(Force::rotational_spring_damper(
            "elbow_damper",
            "elbow",
            2.0,
            C_ELBOW,
            0.0,
        ))
        .unwrap();
        d.add_force(Force::SpringDamperActuator {
            name: "strut".into(),
            body_i: GROUND.into(),
            point_i: Vector3::from(D).into(),
            body_j: "arm".into(),
            point_j: "B".into(),
            stiffness: 10.0,
            damping: C_STRUT,
            free_length: Some(1.5),
            actuator: Some(TimeFunction::Polynomial(vec![F_ACTUATOR])),
        })
        .unwrap();
        d.add_force(Force::torque(
            "twist",
            "arm",
            Vector3::new(0.0, 0.0, TORQUE),
            Frame::Global,
        ))
        .unwrap();
    }
    d
}

fn simulate(driven: bool, damped: bool, integrator: Integrator, outputs: usize) -> DynamicResults {
    let m = model(driven);
    let mut d = dynamics(&m, damped);
    let opts = SimulationOptions::new(2.0, outputs).integrator(integrator);
    let s = d.initial_guess();
    d.simulate(&s, &opts).unwrap()
}

fn dopri5() -> Integrator {
    Integrator::Dopri5(Dopri5Options::tolerances(1e-10, 1e-12))
}

fn gen_alpha(h: f64) -> Integrator {
    Integrator::GeneralizedAlpha(GeneralizedAlphaOptions {
        dt: h,
        ..GeneralizedAlphaOptions::default()
    })
}

/// Composite Simpson's rule of the samples `f` on the uniform grid `t` (an even number of
/// intervals): ∫ f dt.
fn simpson(t: &[f64], f: &[f64]) -> f64 {
    let n = t.len() - 1;
    assert!(n.is_multiple_of(2) && n > 0);
    let h = (t[n] - t[0]) / n as f64;
    let mut s = f[0] + f[n];
    for k in 1..n {
        s += if k % 2 == 1 { 4.0 } else { 2.0 } * f[k];
    }
    s * h / 3.0
}

fn max_abs(v: &[f64]) -> f64 {
    v.iter().fold(0.0f64, |a, x| a.max(x.abs()))
}

/// The largest kinetic energy plus the range of the potential energy: the energy the motion
/// exchanges.
fn energy_scale(r: &DynamicResults) -> f64 {
    let e = &r.energy;
    let pot: Vec<f64> = e
        .gravity
        .iter()
        .zip(&e.spring)
        .map(|(g, s)| g + s)
        .collect();
    let (lo, hi) = pot
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), &v| {
            (l.min(v), h.max(v))
        });
    e.kinetic.iter().fold(0.0f64, |a, &k| a.max(k)) + (hi - lo)
}

/// Each element's work against an independent computation from the stored motion: the
/// elbow damper's −∫ c θ̇² dt and the strut's −∫ c ℓ̇² dt − f_a Δℓ from the output velocities
/// and positions (Simpson), the torque's T Δφ from the arm's angle (closed form), the motor's
/// ∫ τ θ̇ dt with the prescribed rate (Simpson). Returns the largest relative error.
fn check_elements(label: &str, r: &DynamicResults) -> f64 {
    let t = r.times();
    let n = t.len() - 1;
    let crank = r.body("crank").unwrap();
    let arm = r.body("arm").unwrap();
    let elbow_rate: Vec<f64> = (0..=n).map(|k| arm.omega[k].z - crank.omega[k].z).collect();
    let damper = -C_ELBOW * simpson(t, &elbow_rate.iter().map(|w| w * w).collect::<Vec<_>>());
    let b = r.point("arm", "B").unwrap();
    let d = Vector3::from(D);
    let len = |k: usize| (b.position[k] - d).norm();
    let ldot: Vec<f64> = (0..=n)
        .map(|k| (b.position[k] - d).normalize().dot(&b.velocity[k]))
        .collect();
    let strut = -C_STRUT * simpson(t, &ldot.iter().map(|v| v * v).collect::<Vec<_>>())
        - F_ACTUATOR * (len(n) - len(0));
    // The arm's absolute angle: crank angle plus elbow angle (joint coordinates, continued).
    let phi = |k: usize| r.kinematics.joints[0].values[k][0] + r.kinematics.joints[1].values[k][0];
    let torque = TORQUE * (phi(n) - phi(0));
    let motor = r.driver("motor").unwrap();
    let motor_power: Vec<f64> = (0..=n)
        .map(|k| motor.effort[k] * crank_rate(t[k]))
        .collect();
    let motor_work = simpson(t, &motor_power);
    let mut worst = 0.0f64;
    for (name, expected) in [
        ("elbow_damper", damper),
        ("strut", strut),
        ("twist", torque),
        ("motor", motor_work),
    ] {
        let w = *r.energy.element(name).unwrap().work.last().unwrap();
        let rel = (w - expected).abs() / expected.abs();
        eprintln!(
            "{label}: {name} work {w:.9} J, independent {expected:.9} J, rel. error {rel:.1e}"
        );
        worst = worst.max(rel);
    }
    worst
}

#[test]
fn dopri5_balance_is_the_integration_error_of_a_damped_driven_model() {
    let r = simulate(true, true, dopri5(), 2000);
    let names: Vec<&str> = r.energy.elements.iter().map(|e| e.name.as_str()).collect();
    assert_eq!(names, ["motor", "elbow_damper", "strut", "twist"]);
    let drift = r.energy.max_drift();
    let balance = r.energy.max_balance();
    let scale = energy_scale(&r);
    let joints = max_abs(&r.energy.constraint_power);
    eprintln!(
        "DOPRI5 rtol 1e-10: drift {drift:.3e} J, balance {balance:.3e} J, energy scale \
         {scale:.3e} J, joint power {joints:.1e} W, {} steps",
        r.stats.steps
    );
    assert!(drift > 1.0, "the elements should work: drift {drift}");
    assert!(balance < 1e-8 * scale, "balance {balance:e}");
    assert!(joints < 1e-8, "joint power {joints:e}");
    // The elements' work against independent quadratures of the output motion (Simpson on
    // 2000 intervals: about 1e-12 relative).
    let worst = check_elements("DOPRI5", &r);
    assert!(worst < 1e-8, "{worst:e}");
    // The damper dissipates: its power is never positive.
    assert!(r
        .energy
        .element("elbow_damper")
        .unwrap()
        .power
        .iter()
        .all(|&p| p <= 0.0));
}

/// The work is a quadrature over the integration steps, not over the outputs: with 4 outputs
/// instead of 2000, the work at t_end is the same up to the tolerance (a rule over the outputs
/// would be off by percent).
#[test]
fn dopri5_work_does_not_depend_on_the_output_grid() {
    let fine = simulate(true, true, dopri5(), 2000);
    let sparse = simulate(true, true, dopri5(), 4);
    for e in &fine.energy.elements {
        let a = *e.work.last().unwrap();
        let b = *sparse.energy.element(&e.name).unwrap().work.last().unwrap();
        eprintln!(
            "{}: W(t_end) {a:.10} J with 2000 outputs, {b:.10} J with 4",
            e.name
        );
        assert!(
            (a - b).abs() < 1e-8 * a.abs().max(1.0),
            "{}: {a} vs {b}",
            e.name
        );
    }
    let balance = sparse.energy.max_balance();
    eprintln!("4 outputs: balance {balance:.3e} J");
    assert!(balance < 1e-8 * energy_scale(&sparse), "{balance:e}");
}

#[test]
fn generalized_alpha_balance_falls_like_h_squared() {
    let coarse = simulate(true, true, gen_alpha(2e-3), 1000);
    let fine = simulate(true, true, gen_alpha(1e-3), 1000);
    let drift = fine.energy.max_drift();
    let (bc, bf) = (coarse.energy.max_balance(), fine.energy.max_balance());
    eprintln!(
        "gen-α: drift {drift:.3e} J, balance {bc:.3e} J (h = 2 ms), {bf:.3e} J (h = 1 ms), \
         ratio {:.2}",
        bc / bf
    );
    assert!(bf < 1e-4 * drift, "balance {bf:e} vs drift {drift:e}");
    assert!((3.0..5.0).contains(&(bc / bf)), "order: {bc:e} / {bf:e}");
    // Each element's work against the independent quadratures, to the scheme's accuracy.
    let worst = check_elements("gen-α h = 1 ms", &fine);
    assert!(worst < 1e-4, "{worst:e}");
}

#[test]
fn a_conservative_model_has_no_work_and_its_balance_is_its_drift() {
    for (label, integrator) in [("DOPRI5", dopri5()), ("gen-α", gen_alpha(1e-3))] {
        let r = simulate(false, false, integrator, 200);
        assert!(r.energy.elements.is_empty());
        assert!(r.energy.work.iter().all(|&w| w == 0.0));
        assert_eq!(r.energy.balance(), r.energy.drift(), "{label}");
        eprintln!(
            "{label} conservative: drift = balance = {:.3e} J",
            r.energy.max_balance()
        );
    }
}

/// Inverse dynamics: the motor's work along the prescribed motion (the trapezoidal rule on the
/// output grid with Gregory's end corrections and a Simpson first interval, `work::SampledWork`)
/// equals the change of kinetic plus potential energy, to the quadrature's fourth order (the
/// trapezoid alone was second order: ratio 4 between 100 and 200 steps).
#[test]
fn inverse_dynamics_driver_work_is_the_energy_change() {
    let m = common::crank(2.0, 0.5, Some(crank_angle()));
    let run = |steps: usize| {
        let mut d = Dynamics::new(&m).unwrap();
        d.add_force(Force::gravity(Vector3::new(0.0, -9.81, 0.0)))
            .unwrap();
        d.inverse_dynamics(&KinematicOptions::new(0.0, 2.0, steps))
            .unwrap()
    };
    let (coarse, fine) = (run(100), run(200));
    let drift = fine.energy.max_drift();
    let (bc, bf) = (coarse.energy.max_balance(), fine.energy.max_balance());
    let motor = fine.energy.element("motor").unwrap();
    let de = fine.energy.drift();
    eprintln!(
        "inverse: motor work {:.6} J, ΔE {:.6} J, balance {bc:.3e} J (100 steps), {bf:.3e} J \
         (200 steps), ratio {:.2}",
        motor.work.last().unwrap(),
        de.last().unwrap(),
        bc / bf
    );
    assert!(drift > 1.0);
    assert!(bf < 1e-3 * drift, "{bf:e}");
    assert!((13.0..19.0).contains(&(bc / bf)), "order: {bc:e} / {bf:e}");
    // The power is effort × rate at every output.
    let effort = &fine.driver("motor").unwrap().effort;
    for (k, &t) in fine.times().iter().enumerate() {
        let p = effort[k] * crank_rate(t);
        assert!((motor.power[k] - p).abs() < 1e-9 * p.abs().max(1.0), "{t}");
    }
    assert!(max_abs(&fine.energy.constraint_power) < 1e-8);
}

/// The user callback's power: gravity applied by a callback is not in the potential, so its
/// work (the `user` channel) is the whole energy change, and equals m gᵀ (r(t) − r(t₀)) at
/// every output.
#[test]
fn the_user_callback_work_is_counted() {
    let m = common::pendulum(2.0, 1e-3, 1.0);
    let mut d = Dynamics::new(&m).unwrap();
    d.set_user_forces(|_, f| f.add_force(BodyId::Moving(0), &Vector3::new(0.0, -2.0 * 9.81, 0.0)));
    let opts = SimulationOptions::new(2.0, 200).integrator(dopri5());
    let s = d.initial_guess();
    let r = d.simulate(&s, &opts).unwrap();
    let user = r.energy.element("user").unwrap();
    assert_eq!(user.kind, "user");
    let y = &r.body("mass").unwrap().r;
    let mut worst = 0.0f64;
    for (k, w) in user.work.iter().enumerate() {
        let expected = -2.0 * 9.81 * (y[k].y - y[0].y);
        worst = worst.max((w - expected).abs());
    }
    let (drift, balance) = (r.energy.max_drift(), r.energy.max_balance());
    eprintln!(
        "user gravity: drift {drift:.3e} J, balance {balance:.3e} J, work error {worst:.1e} J"
    );
    assert!(drift > 10.0 && balance < 1e-8 * drift && worst < 1e-8 * drift);
}
