//! The seam the driver loop offers events and impulses (module docs of
//! [`crate::integrators`]): each stepper's state inside an accepted step
//! ([`Stepper::interpolate`]) is as accurate as the step's ends, and [`Stepper::restart`] is a
//! fresh start.

use super::dopri5::Dopri5;
use super::generalized_alpha::GeneralizedAlpha;
use super::stepper::{Attempt, Span, Stepper};
use crate::{
    Dopri5Options, Dynamics, Force, GeneralizedAlphaOptions, Integrator, SimulationOptions, State,
};
use cardan_constraints::JointKind;
use cardan_mechanism::{Body, JointSpec, MechanismBuilder, Model, GROUND};
use nalgebra::Vector3;

/// A 1 m rod hung from a spherical joint at its end, released horizontally with a sideways
/// velocity: it swings and turns about the vertical at once.
fn pendulum() -> Model {
    let mut b = MechanismBuilder::new();
    b.body(
        Body::new("rod")
            .mass(1.0)
            .inertia_diagonal(1e-3, 1.0 / 12.0, 1.0 / 12.0)
            .position(Vector3::new(0.5, 0.0, 0.0)),
    );
    b.point(GROUND, "O", Vector3::zeros());
    b.point("rod", "O", Vector3::new(-0.5, 0.0, 0.0));
    b.joint(JointSpec::new(
        "ball",
        JointKind::Spherical,
        (GROUND, "O"),
        ("rod", "O"),
    ));
    b.build().unwrap()
}

/// The dynamics under gravity and the consistent start state.
fn start(model: &Model) -> (Dynamics<'_>, State) {
    let mut d = Dynamics::new(model).unwrap();
    d.add_force(Force::gravity(Vector3::new(0.0, -9.81, 0.0)))
        .unwrap();
    let mut guess = d.initial_guess();
    guess.set_velocity(0, Vector3::new(0.0, 0.0, 1.5), Vector3::zeros());
    let s0 = d.consistent_state(&guess).unwrap();
    (d, s0)
}

/// `n` accepted steps toward `t_end` (all but the last closed by `advance`): the last one's
/// interval, still open.
fn steps<S: Stepper>(s: &mut S, d: &mut Dynamics, n: usize, t_end: f64) -> Span {
    let mut span = None;
    for _ in 0..n {
        if span.is_some() {
            s.advance(d).unwrap();
        }
        s.prepare(d).unwrap();
        span = loop {
            if let Attempt::Accepted(sp) = s.attempt(d, t_end).unwrap() {
                break Some(sp);
            }
        };
    }
    span.unwrap()
}

/// The rod's centre at `times` from a tight DOPRI5 run.
fn reference(model: &Model, times: &[f64]) -> Vec<Vector3<f64>> {
    let (mut d, s0) = start(model);
    let options = SimulationOptions::new(times[times.len() - 1], 1)
        .integrator(Integrator::Dopri5(Dopri5Options::tolerances(1e-12, 1e-14)))
        .output_times(times.to_vec());
    let res = d.simulate_consistent(s0, &options).unwrap();
    res.kinematics.bodies[0].r.clone()
}

/// Inside the stepper's 20th step: the error of its state is within a few times the error at
/// the step's ends, and its bend away from the chord between the ends is the motion's (the
/// error of that bend against the reference's, relative to the bend, is returned).
fn dense_output_follows_the_motion<S: Stepper>(o: &S::Options) -> f64 {
    let model = pendulum();
    let (mut d, s0) = start(&model);
    let mut s = S::new(&mut d, s0, o, 1.0).unwrap();
    let span = steps(&mut s, &mut d, 20, 1.0);
    let times = [span.t0, 0.5 * (span.t0 + span.t1), span.t1];
    let want = reference(&model, &times);
    let got: Vec<Vector3<f64>> = times
        .iter()
        .map(|&t| {
            let st = s.interpolate(t);
            assert_eq!(st.t, t);
            st.r(0)
        })
        .collect();
    let err: Vec<f64> = got.iter().zip(&want).map(|(g, w)| (g - w).norm()).collect();
    assert!(
        err[1] <= 3.0 * err[0].max(err[2]) + 1e-10,
        "errors at t0, the midpoint, t1: {err:?}"
    );
    let bend = |x: &[Vector3<f64>]| x[1] - 0.5 * (x[0] + x[2]);
    let (bg, bw) = (bend(&got), bend(&want));
    let relative = (bg - bw).norm() / bw.norm();
    eprintln!(
        "step {:.2e}: errors at t0, the midpoint, t1 {err:?}; bend {:.2e}, its error {relative:.2e}",
        span.t1 - span.t0,
        bw.norm()
    );
    relative
}

#[test]
fn dopri5_dense_output_inside_a_step() {
    let bend = dense_output_follows_the_motion::<Dopri5>(&Dopri5Options::tolerances(1e-6, 1e-8));
    assert!(bend < 1e-4, "{bend:e}");
}

#[test]
fn generalized_alpha_interpolant_inside_a_step() {
    let bend = dense_output_follows_the_motion::<GeneralizedAlpha>(
        &GeneralizedAlphaOptions::with_step(1e-2),
    );
    assert!(bend < 1e-2, "{bend:e}");
}

/// Steps after a restart from the start state repeat those of a new stepper there.
fn restart_is_a_fresh_start<S: Stepper>(o: &S::Options) {
    let model = pendulum();
    let (mut da, s0) = start(&model);
    let (mut db, _) = start(&model);
    let mut a = S::new(&mut da, s0.clone(), o, 1.0).unwrap();
    steps(&mut a, &mut da, 7, 1.0);
    a.advance(&mut da).unwrap();
    a.restart(&mut da, &s0).unwrap();
    assert_eq!(a.time(), s0.t);
    let sa = steps(&mut a, &mut da, 5, 1.0);
    let mut b = S::new(&mut db, s0, o, 1.0).unwrap();
    let sb = steps(&mut b, &mut db, 5, 1.0);
    assert_eq!(sa, sb);
    let (qa, qb) = (a.interpolate(sa.t1).clone(), b.interpolate(sb.t1));
    for (x, y) in qa.q.iter().chain(&qa.v).zip(qb.q.iter().chain(&qb.v)) {
        assert!((x - y).abs() <= 1e-12 * (1.0 + y.abs()), "{x} {y}");
    }
    assert_eq!(a.stats().steps, 12);
}

#[test]
fn dopri5_restart() {
    restart_is_a_fresh_start::<Dopri5>(&Dopri5Options::tolerances(1e-6, 1e-8));
}

#[test]
fn generalized_alpha_restart() {
    restart_is_a_fresh_start::<GeneralizedAlpha>(&GeneralizedAlphaOptions::with_step(1e-2));
}
