//! Redundant mechanisms: a planar four-bar of four spatial revolute joints and Bricard's linkage.

mod common;

use cardan_mechanism::{DriverSpec, KinematicOptions, TimeFunction};
use common::{bricard_builder, four_bar_b, four_bar_builder, four_bar_builder_off_plane, FOUR_BAR};
use nalgebra::Vector3;
use std::f64::consts::PI;

/// Four revolutes about z: 3 bodies, 20 equations of rank 17 → DOF 1 with 3 redundant
/// equations (the out-of-plane conditions of the loop).
#[test]
fn four_bar_dof_and_named_redundant_equations() {
    let model = four_bar_builder(0.3, 1.0).build().unwrap();
    let ws = model.workspace();
    let dof = model.dof(&ws).unwrap();
    eprintln!("four-bar: {dof}");
    assert_eq!(dof.dof, 1);
    assert_eq!(dof.joint_equations, 20);
    assert_eq!(dof.rank, 17);
    assert_eq!(dof.redundant.len(), 3);
    for e in &dof.redundant {
        assert_eq!(e.kind, "revolute");
        assert!(["O2", "A", "B", "O4"].contains(&e.element.as_str()));
    }
}

/// Driven at 1 rad/s for a full turn plus: coupler pin B against the planar closed form.
#[test]
fn four_bar_matches_planar_closed_form() {
    let (theta0, omega) = (0.3, 2.0 * PI);
    let model = four_bar_builder(theta0, omega).build().unwrap();
    let r = model
        .run_kinematics(&KinematicOptions::new(0.0, 1.25, 250))
        .unwrap();
    let b = r.point("rocker", "B").unwrap();
    let a = r.point("coupler", "A").unwrap();
    let (mut eb, mut ev) = (0.0f64, 0.0f64);
    let h = 1e-6;
    for (k, &t) in r.times.iter().enumerate() {
        let th = theta0 + omega * t;
        eb = eb.max((b.position[k] - four_bar_b(th)).norm());
        let vb = (four_bar_b(th + h) - four_bar_b(th - h)) / (2.0 * h) * omega;
        ev = ev.max((b.velocity[k] - vb).norm());
        let pa = Vector3::new(th.cos(), th.sin(), 0.0) * FOUR_BAR.1;
        assert!((a.position[k] - pa).norm() < 1e-10);
    }
    let it = *r.iterations.iter().max().unwrap();
    eprintln!("four-bar: max |B − B_exact| = {eb:.2e}, |v_B − v_exact| = {ev:.2e} (FD reference), max iterations {it}");
    assert!(eb < 1e-10, "{eb}");
    assert!(ev < 1e-7, "{ev}");
    // Everything stays in the plane z = 0.
    for p in &r.points {
        assert!(p.position.iter().all(|x| x.z.abs() < 1e-12));
    }
    // The crank angle, unwrapped, reaches θ0 + 2.5π.
    let ang = r.joint("O2").unwrap().values.last().unwrap()[0];
    assert!((ang - (theta0 + 2.5 * PI)).abs() < 1e-9, "{ang}");
}

/// Bricard's linkage: 5 bodies, 30 equations of rank 29, DOF 1 (Grübler would say 0).
#[test]
fn bricard_has_one_dof() {
    let model = bricard_builder().build().unwrap();
    let ws = model.workspace();
    let dof = model.dof(&ws).unwrap();
    eprintln!("Bricard: {dof}");
    assert_eq!(dof.joint_equations, 30);
    assert_eq!(dof.rank, 29);
    assert_eq!(dof.dof, 1);
    assert_eq!(dof.redundant.len(), 1);
}

/// Bricard driven at joint A, θ = 0.3 (1 − cos 2πt) ∈ [0, 0.6] rad: the loop stays closed and
/// P3 = C keeps its distance 1 from B and from D. (Driving through negative angles ends at a
/// limit position at θ = −π/6, where the run stops with a named error: see tests/errors.rs.)
#[test]
fn bricard_driven_stays_closed() {
    let mut b = bricard_builder();
    b.driver(DriverSpec::rotation(
        "swing",
        "A",
        TimeFunction::Harmonic {
            amplitude: -0.3,
            frequency: 2.0 * PI,
            phase: PI / 2.0,
            offset: 0.3,
        },
    ));
    let model = b.build().unwrap();
    let r = model
        .run_kinematics(&KinematicOptions::new(0.0, 1.0, 200))
        .unwrap();
    let max_res = r.residual.iter().cloned().fold(0.0, f64::max);
    let it = *r.iterations.iter().max().unwrap();
    let c = r.point("rod2", "C").unwrap();
    let bb = r.point("rod1", "B").unwrap();
    let d = r.point("rod3", "D").unwrap();
    for k in 0..r.len() {
        assert!(((c.position[k] - bb.position[k]).norm() - 1.0).abs() < 1e-10);
        assert!(((c.position[k] - d.position[k]).norm() - 1.0).abs() < 1e-10);
    }
    let moved = (c.position[50] - Vector3::new(1.0, -1.0, 0.0)).norm();
    eprintln!("Bricard driven: max residual {max_res:.2e}, max iterations {it}, P3 moved {moved:.3} m at t = 0.25");
    assert!(max_res < 1e-10);
    assert!(moved > 0.1);
}

/// A four-bar of spatial revolutes whose ground pivot O4 is drawn 1e-7 m out of the plane
/// (issue 22): no pose satisfies all equations. Assembly finds the least-squares-consistent
/// pose (kept rows exact), the run solves the kept rows exactly at every frame and reports the
/// dropped row that stays off, one per joint, with its worst residual; 1e-3 m is an error naming
/// the joint.
#[test]
fn slightly_inconsistent_four_bar_keeps_its_kept_rows_exact_and_reports_the_dropped_row() {
    use cardan_mechanism::{AnalysisError, AssemblyOptions};
    let offset = |dz: f64| four_bar_builder_off_plane(0.3, 1.0, dz).build().unwrap();
    let model = offset(1e-7);
    let mut ws = model.workspace();
    let rep = model
        .assemble(&mut ws, &AssemblyOptions::default())
        .unwrap();
    assert!(
        rep.dropped_residual > 1e-8 && rep.dropped_residual < 1e-6,
        "{rep:?}"
    );
    let r = model
        .kinematics(&mut ws, &KinematicOptions::new(0.0, 1.0, 20))
        .unwrap();
    assert_eq!(r.dropped_rows.len(), 1, "{:?}", r.dropped_rows);
    let d = &r.dropped_rows[0];
    eprintln!(
        "dropped: {} |Φ| = {:.3e} (scaled {:.3e}) at t = {}",
        d.equation, d.value, d.residual, d.time
    );
    assert!((d.value.abs() - 1e-7).abs() < 1e-12, "{d:?}");
    assert!(
        r.residual.iter().all(|&v| (v - 1e-7).abs() < 1e-12),
        "{:?}",
        r.residual
    );
    let gross = offset(1e-3);
    let mut ws = gross.workspace();
    match gross.assemble(&mut ws, &AssemblyOptions::default()) {
        Err(AnalysisError::InconsistentJoints { dropped, .. }) => {
            assert_eq!(dropped.len(), 1);
            assert_eq!(dropped[0].equation.element, d.equation.element);
        }
        other => panic!("{other:?}"),
    }
}
