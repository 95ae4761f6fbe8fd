//! Point-on-curve elements in kinematic runs: the curve parameter u as an extra coordinate.
//!
//! - A pin in a straight slot (point on a line) with the slider's rotation locked equals a
//!   prismatic joint: Haug's spatial slider-crank both ways, poses to 1e-12, and u is the
//!   slide, against the closed form x(θ) with its rates.
//! - A crank pin on a circle about the crank axis: the circle's rows are implied by the revolute
//!   (two of three redundant, dropped), and u = R θ over two turns (continued past the circle's
//!   period), u̇ = R ω, ü = 0.
//! - Refusals: an initial parameter off an open curve; a motion that drives the point off the
//!   end of an open curve stops with the time and the parameter.

mod common;

use cardan_constraints::CubicCurve;
use cardan_mechanism::{
    AnalysisError, CurveSpec, KinematicOptions, MechanismBuilder, ModelError, GROUND,
};
use common::{slider_crank, slider_x, slotted, slotted_slider_crank};
use nalgebra::Vector3;
use std::f64::consts::PI;

#[test]
fn a_pin_in_a_straight_slot_equals_a_prismatic_joint() {
    let omega = 2.0 * PI;
    // Both runs converged to round-off, so they agree to it (at the default tolerance each
    // stops within 1e-10 of the exact pose, by different Newton paths).
    let options = KinematicOptions::new(0.0, 2.0, 400).tolerance(1e-14);
    let slot = slotted_slider_crank(omega).build().unwrap();
    let ws = slot.workspace();
    let dof = slot.dof(&ws).unwrap();
    assert_eq!(dof.dof, 1, "{dof}");
    assert!(dof.redundant.is_empty(), "{dof}");
    let a = slot.run_kinematics(&options).unwrap();
    let b = slider_crank().run_kinematics(&options).unwrap();
    let mut worst = 0.0f64;
    for name in ["crank", "conrod", "slider"] {
        let (x, y) = (a.body(name).unwrap(), b.body(name).unwrap());
        for k in 0..a.len() {
            worst = worst.max((x.r[k] - y.r[k]).norm());
            worst = worst.max((x.p[k] - y.p[k]).norm());
            worst = worst.max((x.r_dot[k] - y.r_dot[k]).norm());
            worst = worst.max((x.omega[k] - y.omega[k]).norm());
            worst = worst.max((x.r_ddot[k] - y.r_ddot[k]).norm() / omega);
        }
    }
    // u is the slide x along the slot, with its rates.
    let u = a.curve("slot").unwrap();
    let (mut eu, mut ev, mut ea) = (0.0f64, 0.0f64, 0.0f64);
    for (k, &t) in a.times.iter().enumerate() {
        let (x, x1, x2) = slider_x(omega * t);
        eu = eu.max((u.u[k] - x).abs());
        ev = ev.max((u.u_dot[k] - x1 * omega).abs());
        ea = ea.max((u.u_ddot[k] - x2 * omega * omega).abs());
    }
    eprintln!(
        "slot vs prismatic: poses, rates, accelerations/ω within {worst:.2e}; u − x(θ) {eu:.2e} m, u̇ {ev:.2e} m/s, ü {ea:.2e} m/s²"
    );
    assert!(worst < 1e-12, "{worst}");
    assert!(eu < 1e-10 && ev < 1e-9 && ea < 1e-8, "{eu} {ev} {ea}");
}

#[test]
fn a_crank_pin_on_a_circle_about_its_axis_runs_along_it_over_turns() {
    let omega = 2.0 * PI;
    let model = common::slider_crank_on_rim(omega);
    let ws = model.workspace();
    let dof = model.dof(&ws).unwrap();
    assert_eq!(dof.dof, 1, "{dof}");
    assert_eq!(dof.redundant.len(), 2, "{dof}");
    let res = model
        .run_kinematics(&KinematicOptions::new(0.0, 2.0, 100))
        .unwrap();
    let u = res.curve("rim").unwrap();
    let u0 = u.u[0];
    for (k, &t) in res.times.iter().enumerate() {
        assert!(
            (u.u[k] - u0 - 0.08 * omega * t).abs() < 1e-10,
            "t = {t}: {}",
            u.u[k]
        );
        assert!((u.u_dot[k] - 0.08 * omega).abs() < 1e-10);
        assert!(u.u_ddot[k].abs() < 1e-8);
    }
    // Two turns: u went twice round the circle.
    assert!((u.u[100] - u0 - 2.0 * 2.0 * PI * 0.08).abs() < 1e-10);
}

/// A slot of spline points along x from 0 to `end`; the slider-crank's stroke is x ∈ [0.15,
/// 0.27].
fn spline_slot(start: f64, end: f64) -> CubicCurve {
    let pts = (0..6)
        .map(|k| Vector3::new(start + (end - start) * k as f64 / 5.0, 0.0, 0.0))
        .collect();
    CubicCurve::new(pts, false).unwrap()
}

fn with_slot(curve: CubicCurve, initial_u: Option<f64>) -> MechanismBuilder {
    let mut spec = CurveSpec::new("slot2", GROUND, curve, "slider", "C");
    spec.initial_u = initial_u;
    slotted(2.0 * PI, spec)
}

#[test]
fn a_spline_slot_along_the_line_gives_the_same_motion() {
    let model = with_slot(spline_slot(0.0, 0.4), None).build().unwrap();
    let res = model
        .run_kinematics(&KinematicOptions::new(0.0, 1.0, 100))
        .unwrap();
    let u = res.curve("slot2").unwrap();
    for (k, &t) in res.times.iter().enumerate() {
        let (x, x1, _) = slider_x(2.0 * PI * t);
        assert!((u.u[k] - x).abs() < 1e-12, "{} {x}", u.u[k]);
        assert!((u.u_dot[k] - x1 * 2.0 * PI).abs() < 1e-10);
    }
}

#[test]
fn a_point_is_refused_off_an_open_curve_and_stopped_at_its_end() {
    // Initial parameter given off the curve.
    let e = with_slot(spline_slot(0.0, 0.4), Some(0.5))
        .build()
        .unwrap_err();
    assert!(matches!(e, ModelError::CurveParameterOff { .. }), "{e}");
    assert!(e.to_string().contains("lies off the open curve"), "{e}");
    // The slot ends at x = 0.24 inside the stroke (0.15 .. 0.27): the run stops there.
    let model = with_slot(spline_slot(0.0, 0.24), None).build().unwrap();
    let err = model
        .run_kinematics(&KinematicOptions::new(0.0, 1.0, 100))
        .unwrap_err();
    let AnalysisError::CurveEnd { time, u, end, .. } = &err else {
        panic!("{err}");
    };
    eprintln!("{err}");
    assert!(*u > *end && *time > 0.0 && *time < 0.5, "{err}");
    let partial = err.partial_results().map_or(0, |r| r.len());
    assert!(partial > 0, "no partial results");
}

/// A bead on a helix (R = 0.3, pitch 0.2) sent along it by a path driver at constant arc-length
/// speed v = 0.5 m/s: its speed is v and its acceleration the Frenet closed form v² κ n (κ =
/// R/k², n toward the axis), with no tangential part; after one turn it has risen by the pitch.
#[test]
fn a_path_driver_sends_a_point_along_a_helix_at_constant_speed() {
    use cardan_constraints::{Helix, Marker};
    use cardan_mechanism::{Body, JointKind, JointSpec, PathSpec, TimeFunction};
    let (r, pitch, v) = (0.3, 0.2, 0.5);
    let axis =
        Marker::from_axis(Vector3::new(0.1, -0.2, 0.0), Vector3::new(0.0, 0.0, 1.0)).unwrap();
    let helix = Helix::new(&axis, r, pitch).unwrap();
    let start = cardan_constraints::Curve::from(helix).jet(0.0).c;
    let mut b = MechanismBuilder::new();
    b.body(Body::new("bead").position(start));
    b.point("bead", "P", Vector3::zeros())
        .point(GROUND, "O", Vector3::zeros())
        .vector(GROUND, "z", Vector3::z())
        .vector("bead", "z", Vector3::z());
    b.joint(
        JointSpec::new("keep", JointKind::NoRotation, (GROUND, "O"), ("bead", "P")).axes("z", "z"),
    );
    b.curve(CurveSpec::new("wire", GROUND, helix, "bead", "P"));
    b.path(PathSpec::new(
        "feed",
        "wire",
        TimeFunction::Polynomial(vec![0.0, v]),
    ));
    let model = b.build().unwrap();
    let k2 = r * r + (pitch / (2.0 * PI)).powi(2);
    let turn = 2.0 * PI * k2.sqrt() / v;
    let res = model
        .run_kinematics(&KinematicOptions::new(0.0, turn, 200))
        .unwrap();
    let bead = res.body("bead").unwrap();
    let (mut speed, mut acc, mut tangential) = (0.0f64, 0.0f64, 0.0f64);
    for k in 0..res.len() {
        speed = speed.max((bead.r_dot[k].norm() - v).abs());
        let c = cardan_constraints::Curve::from(helix).jet(v * res.times[k]);
        acc = acc.max((bead.r_ddot[k] - c.c_uu * (v * v)).norm());
        tangential = tangential.max(bead.r_ddot[k].dot(&bead.r_dot[k]).abs());
        let kappa = bead.r_ddot[k].norm() / (v * v);
        assert!((kappa - r / k2).abs() < 1e-9, "κ {kappa}");
    }
    let rise = bead.r[200] - bead.r[0];
    eprintln!(
        "helix at v = {v}: | |ṙ| − v | ≤ {speed:.1e}, |r̈ − v² c''| ≤ {acc:.1e}, |r̈·ṙ| ≤ {tangential:.1e}, rise after a turn {:.15}",
        rise.z
    );
    assert!(speed < 1e-10, "{speed}");
    assert!(acc < 1e-9 && tangential < 1e-9, "{acc} {tangential}");
    assert!(
        (rise - Vector3::new(0.0, 0.0, pitch)).norm() < 1e-10,
        "{rise:?}"
    );
    let u = res.curve("wire").unwrap();
    assert!((u.u[200] - v * turn).abs() < 1e-12);
}

/// The least change (held runs, drag) has no weight for a curve parameter yet: each refuses a
/// model with a point on a curve, saying so, instead of indexing past its bodies.
#[test]
fn the_least_change_refuses_a_point_on_a_curve() {
    use cardan_mechanism::{BodyWeights, Drag, FreeDof, HoldMetric, LeastChange};
    let model = slotted_slider_crank(2.0 * PI).build().unwrap();
    let weights = vec![
        BodyWeights {
            translation: 1.0,
            rotation: [1.0; 4],
        };
        model.num_bodies()
    ];
    let e = LeastChange::new(&model, weights)
        .err()
        .map(|e| e.to_string());
    assert!(e.is_some_and(|e| e.contains("point-on-curve")));
    let e = Drag::new(&model, "slider", Vector3::zeros(), 1.0)
        .err()
        .map(|e| e.to_string());
    assert!(e.is_some_and(|e| e.contains("point-on-curve")));
    let mut options = KinematicOptions::new(0.0, 1.0, 10);
    options.free_dof = FreeDof::Hold(HoldMetric::Scaled);
    // Driven in every degree of freedom, it runs as without the option (nothing to hold);
    // with a degree of freedom left free, the held run refuses the curve.
    let driven = model.run_kinematics(&options);
    assert!(driven.is_ok_and(|r| r.held_dof == 0));
    let free = common::slotted_undriven(common::straight_slot())
        .build()
        .unwrap();
    let e = free.run_kinematics(&options).unwrap_err().to_string();
    assert!(e.contains("does not take curve elements"), "{e}");
}
