//! Couplers in kinematic runs: each law holds exactly in the joints' own coordinates over many
//! turns (non-integer ratios), whichever side of its joints the coupled bodies are on, on a
//! moving carrier too; DOF and redundancy count them; the builder refuses what they cannot mean.

use cardan_constraints::{JointKind, TimeFunction};
use cardan_mechanism::{
    Body, CouplerSpec, DriverSpec, GearRatio, JointSpec, KinematicOptions, MechanismBuilder,
    ModelError, Results, GROUND,
};
use nalgebra::Vector3;
use std::f64::consts::PI;

const TURNS: f64 = 10.0;

fn disc(b: &mut MechanismBuilder, name: &str, at: Vector3<f64>) {
    b.body(
        Body::new(name)
            .position(at)
            .mass(1.0)
            .inertia_diagonal(0.1, 0.1, 0.2),
    );
    b.point(name, "c", Vector3::zeros());
    b.vector(name, "z", Vector3::z())
        .vector(name, "x", Vector3::x());
}

fn ground_frame(b: &mut MechanismBuilder) {
    b.vector(GROUND, "z", Vector3::z())
        .vector(GROUND, "x", Vector3::x());
    b.vector(GROUND, "-z", -Vector3::z());
}

/// A revolute joint about z between `(bi, pi)` and `(bj, "c")`.
fn revolute(name: &str, (bi, pi): (&str, &str), bj: &str, zi: &str, zj: &str) -> JointSpec {
    JointSpec::new(name, JointKind::Revolute, (bi, pi), (bj, "c"))
        .axes(zi, zj)
        .x_axes("x", "x")
}

fn turn(joint: &str) -> DriverSpec {
    DriverSpec::rotation(
        "motor",
        joint,
        TimeFunction::Polynomial(vec![0.3, 2.0 * PI * TURNS]),
    )
}

fn angle(r: &Results, joint: &str, k: usize) -> f64 {
    r.joint(joint).unwrap().values[k][0]
}

fn run(b: &MechanismBuilder) -> Results {
    let model = b.build().expect("builds");
    model
        .run_kinematics(&KinematicOptions::new(0.0, 1.0, 400))
        .expect("runs")
}

/// A gear pair on ground, gear 1 driven through 10 turns: θ₂ = −(r₁/r₂) θ₁ + c at every frame.
#[test]
fn gear_law_holds_over_ten_turns_with_a_non_integer_ratio() {
    let (r1, r2) = (0.37, 0.81);
    let mut b = MechanismBuilder::new();
    ground_frame(&mut b);
    b.point(GROUND, "A", Vector3::zeros());
    b.point(GROUND, "B", Vector3::new(r1 + r2, 0.0, 0.0));
    disc(&mut b, "g1", Vector3::zeros());
    disc(&mut b, "g2", Vector3::new(r1 + r2, 0.0, 0.0));
    b.joint(revolute("j1", (GROUND, "A"), "g1", "z", "z"));
    b.joint(revolute("j2", (GROUND, "B"), "g2", "z", "z"));
    b.coupler(CouplerSpec::gear(
        "mesh",
        "j1",
        "j2",
        GearRatio::Radii(r1, r2),
    ));
    b.driver(turn("j1"));
    let r = run(&b);
    let c = angle(&r, "j2", 0) + r1 / r2 * angle(&r, "j1", 0);
    let mut worst = 0.0f64;
    for k in 0..r.times.len() {
        let law = angle(&r, "j2", k) + r1 / r2 * angle(&r, "j1", k) - c;
        worst = worst.max(law.abs());
    }
    let last = r.times.len() - 1;
    assert!((angle(&r, "j1", last) - angle(&r, "j1", 0) - 2.0 * PI * TURNS).abs() < 1e-9);
    eprintln!(
        "gear pair on ground, {TURNS} turns: largest |θ₂ + (r₁/r₂) θ₁ − c| = {worst:.2e} rad"
    );
    assert!(worst < 1e-9, "law residual {worst:e}");
    // The speed ratio and the acceleration ratio are exact.
    let (b1, b2) = (r.body("g1").unwrap(), r.body("g2").unwrap());
    for k in 0..r.times.len() {
        let ratio = b2.omega[k].z / b1.omega[k].z;
        assert!(
            (ratio + r1 / r2).abs() < 1e-12,
            "frame {k}: speed ratio {ratio}"
        );
        let alpha = b2.omega_dot[k].z + r1 / r2 * b1.omega_dot[k].z;
        assert!(alpha.abs() < 1e-9, "frame {k}: {alpha:e}");
    }
}

/// Gear 1 as body i of its joint and gear 2's joint axis reversed: the law is still in the
/// joints' own coordinates, θ₂ = ratio · θ₁ + c.
#[test]
fn gear_law_is_in_the_joints_own_coordinates_whatever_their_sides_and_axes() {
    let ratio = -0.6180339887;
    let mut b = MechanismBuilder::new();
    ground_frame(&mut b);
    b.point(GROUND, "A", Vector3::zeros());
    b.point(GROUND, "B", Vector3::new(1.0, 0.2, 0.0));
    disc(&mut b, "g1", Vector3::zeros());
    disc(&mut b, "g2", Vector3::new(1.0, 0.2, 0.0));
    b.vector("g2", "-z", -Vector3::z());
    b.joint(
        JointSpec::new("j1", JointKind::Revolute, ("g1", "c"), (GROUND, "A"))
            .axes("z", "z")
            .x_axes("x", "x"),
    );
    b.joint(revolute("j2", (GROUND, "B"), "g2", "-z", "-z"));
    b.coupler(CouplerSpec::gear("mesh", "j1", "j2", GearRatio::Ratio(ratio)).constant(0.0));
    b.driver(DriverSpec::rotation(
        "motor",
        "j2",
        TimeFunction::Polynomial(vec![0.0, 2.0 * PI * 3.3]),
    ));
    let r = run(&b);
    for k in 0..r.times.len() {
        let law = angle(&r, "j2", k) - ratio * angle(&r, "j1", k);
        assert!(law.abs() < 1e-9, "frame {k}: {law:e}");
    }
}

/// Both gears on a carrier that itself turns: the law holds relative to the carrier.
#[test]
fn gear_law_holds_on_a_turning_carrier() {
    let (r1, r2) = (0.3, 0.45);
    let mut b = MechanismBuilder::new();
    ground_frame(&mut b);
    b.point(GROUND, "O", Vector3::zeros());
    disc(&mut b, "arm", Vector3::zeros());
    b.point("arm", "A", Vector3::new(0.2, 0.0, 0.0));
    b.point("arm", "B", Vector3::new(0.2 + r1 + r2, 0.0, 0.0));
    disc(&mut b, "g1", Vector3::new(0.2, 0.0, 0.0));
    disc(&mut b, "g2", Vector3::new(0.2 + r1 + r2, 0.0, 0.0));
    b.joint(revolute("arm_pivot", (GROUND, "O"), "arm", "z", "z"));
    b.joint(revolute("j1", ("arm", "A"), "g1", "z", "z"));
    b.joint(revolute("j2", ("arm", "B"), "g2", "z", "z"));
    b.coupler(CouplerSpec::gear(
        "mesh",
        "j1",
        "j2",
        GearRatio::Radii(r1, r2),
    ));
    b.driver(turn("j1"));
    b.driver(DriverSpec::rotation(
        "arm_motor",
        "arm_pivot",
        TimeFunction::Polynomial(vec![0.0, -2.0 * PI * 1.7]),
    ));
    let r = run(&b);
    let c = angle(&r, "j2", 0) + r1 / r2 * angle(&r, "j1", 0);
    for k in 0..r.times.len() {
        let law = angle(&r, "j2", k) + r1 / r2 * angle(&r, "j1", k) - c;
        assert!(law.abs() < 1e-9, "frame {k}: {law:e}");
    }
}

/// A rack on a prismatic joint along x and a pinion above it: s = −r θ + c over ten turns.
#[test]
fn rack_displacement_is_minus_radius_times_angle() {
    let radius = 0.123;
    let mut b = MechanismBuilder::new();
    ground_frame(&mut b);
    b.vector(GROUND, "ex", Vector3::x())
        .vector(GROUND, "ey", Vector3::y());
    b.point(GROUND, "P", Vector3::new(0.0, radius, 0.0));
    b.point(GROUND, "R", Vector3::zeros());
    disc(&mut b, "pinion", Vector3::new(0.0, radius, 0.0));
    disc(&mut b, "rack", Vector3::zeros());
    b.vector("rack", "ex", Vector3::x())
        .vector("rack", "ey", Vector3::y());
    b.joint(revolute("pin", (GROUND, "P"), "pinion", "z", "z"));
    b.joint(
        JointSpec::new("slide", JointKind::Prismatic, (GROUND, "R"), ("rack", "c"))
            .axes("ex", "ex")
            .x_axes("ey", "ey"),
    );
    b.coupler(CouplerSpec::rack_pinion("teeth", "slide", "pin", radius));
    b.driver(turn("pin"));
    let r = run(&b);
    let s = |k: usize| r.joint("slide").unwrap().values[k][0];
    let c = s(0) + radius * angle(&r, "pin", 0);
    for k in 0..r.times.len() {
        let law = s(k) + radius * angle(&r, "pin", k) - c;
        assert!(law.abs() < 1e-10, "frame {k}: {law:e}");
    }
    let last = r.times.len() - 1;
    assert!((s(last) - s(0) + radius * 2.0 * PI * TURNS).abs() < 1e-9);
}

/// A screw on one cylindrical joint and a screw between a revolute and a prismatic joint: the
/// advance is the pitch times the turns.
#[test]
fn screw_advance_is_pitch_times_turns() {
    let pitch = 0.0042;
    for two_joints in [false, true] {
        let mut b = MechanismBuilder::new();
        ground_frame(&mut b);
        b.point(GROUND, "O", Vector3::zeros());
        disc(&mut b, "screw", Vector3::zeros());
        if two_joints {
            disc(&mut b, "nut", Vector3::new(0.3, 0.0, 0.0));
            b.vector(GROUND, "ey", Vector3::y())
                .vector("nut", "ey", Vector3::y());
            b.point(GROUND, "N", Vector3::new(0.3, 0.0, 0.0));
            b.joint(revolute("turn", (GROUND, "O"), "screw", "z", "z"));
            b.joint(
                JointSpec::new("lift", JointKind::Prismatic, ("nut", "c"), (GROUND, "N"))
                    .axes("z", "z")
                    .x_axes("ey", "ey"),
            );
            b.coupler(CouplerSpec::screw("thread", "lift", "turn", pitch));
        } else {
            b.joint(
                JointSpec::new(
                    "turn",
                    JointKind::Cylindrical,
                    (GROUND, "O"),
                    ("screw", "c"),
                )
                .axes("z", "z")
                .x_axes("x", "x"),
            );
            b.coupler(CouplerSpec::screw("thread", "turn", "turn", pitch));
        }
        b.driver(turn("turn"));
        let r = run(&b);
        let slide = |k: usize| {
            let j = r.joint(if two_joints { "lift" } else { "turn" }).unwrap();
            j.values[k][if two_joints { 0 } else { 1 }]
        };
        let last = r.times.len() - 1;
        let advance = slide(last) - slide(0);
        assert!(
            (advance - pitch * TURNS).abs() < 1e-12,
            "two joints {two_joints}: advance {advance}, want {}",
            pitch * TURNS
        );
    }
}

/// DOF: two gears on ground are one degree of freedom; a third gear meshing with both (a
/// closed triangle of consistent ratios) adds one redundant equation, named.
#[test]
fn dof_and_redundancy_count_couplers() {
    let mut b = MechanismBuilder::new();
    ground_frame(&mut b);
    let at = [
        Vector3::zeros(),
        Vector3::new(1.0, 0.0, 0.0),
        Vector3::new(0.5, 0.8, 0.0),
    ];
    for (k, p) in at.iter().enumerate() {
        b.point(GROUND, &format!("P{k}"), *p);
        disc(&mut b, &format!("g{k}"), *p);
        b.joint(revolute(
            &format!("j{k}"),
            (GROUND, &format!("P{k}")),
            &format!("g{k}"),
            "z",
            "z",
        ));
    }
    b.coupler(CouplerSpec::gear("m01", "j0", "j1", GearRatio::Ratio(-2.0)));
    let model = b.build().unwrap();
    let ws = model.workspace();
    assert_eq!(model.dof(&ws).unwrap().dof, 2);
    // θ1 = −2 θ0, θ2 = 0.5 θ1 = −θ0: m12 and m02 are consistent, one redundant.
    b.coupler(CouplerSpec::gear("m12", "j1", "j2", GearRatio::Ratio(0.5)));
    b.coupler(CouplerSpec::gear("m02", "j0", "j2", GearRatio::Ratio(-1.0)));
    let model = b.build().unwrap();
    let ws = model.workspace();
    let report = model.dof(&ws).unwrap();
    assert_eq!(report.dof, 1);
    assert_eq!(report.redundant.len(), 1, "{:?}", report.redundant);
    assert!(["m01", "m12", "m02"].contains(&report.redundant[0].element.as_str()));
}

fn two_gears() -> MechanismBuilder {
    let mut b = MechanismBuilder::new();
    ground_frame(&mut b);
    b.point(GROUND, "A", Vector3::zeros());
    b.point(GROUND, "B", Vector3::new(1.0, 0.0, 0.0));
    disc(&mut b, "g1", Vector3::zeros());
    disc(&mut b, "g2", Vector3::new(1.0, 0.0, 0.0));
    b.joint(revolute("j1", (GROUND, "A"), "g1", "z", "z"));
    b.joint(revolute("j2", (GROUND, "B"), "g2", "z", "z"));
    b
}

fn refused(b: &MechanismBuilder) -> ModelError {
    match b.build() {
        Err(e) => e,
        Ok(_) => panic!("built"),
    }
}

#[test]
fn the_builder_refuses_what_a_coupler_cannot_mean() {
    // A zero radius.
    let mut b = two_gears();
    b.coupler(CouplerSpec::gear(
        "mesh",
        "j1",
        "j2",
        GearRatio::Radii(0.0, 1.0),
    ));
    let e = refused(&b).to_string();
    assert!(
        e.contains("coupler \"mesh\"") && e.contains("radius_i"),
        "{e}"
    );
    // A joint of the wrong kind.
    let mut b = two_gears();
    b.point(GROUND, "C", Vector3::new(0.0, 2.0, 0.0));
    disc(&mut b, "s", Vector3::new(0.0, 2.0, 0.0));
    b.joint(JointSpec::new(
        "ball",
        JointKind::Spherical,
        (GROUND, "C"),
        ("s", "c"),
    ));
    b.coupler(CouplerSpec::gear(
        "mesh",
        "j1",
        "ball",
        GearRatio::Ratio(1.0),
    ));
    let e = refused(&b).to_string();
    assert!(e.contains("joint_j \"ball\" is spherical"), "{e}");
    // No shared body.
    let mut b = two_gears();
    disc(&mut b, "g3", Vector3::new(0.0, 1.0, 0.0));
    b.point("g2", "Q", Vector3::new(0.0, 1.0, 0.0));
    b.joint(revolute("j3", ("g2", "Q"), "g3", "z", "z"));
    b.coupler(CouplerSpec::gear("mesh", "j1", "j3", GearRatio::Ratio(1.0)));
    let e = refused(&b).to_string();
    assert!(e.contains("share no body"), "{e}");
    // Collinear axes.
    let mut b = two_gears();
    disc(&mut b, "g3", Vector3::zeros());
    b.joint(revolute("j3", (GROUND, "A"), "g3", "z", "z"));
    b.coupler(CouplerSpec::gear("mesh", "j1", "j3", GearRatio::Ratio(1.0)));
    let e = refused(&b).to_string();
    assert!(e.contains("same line"), "{e}");
    // A rack across nothing: slide along the pinion axis.
    let mut b = two_gears();
    b.joint(
        JointSpec::new("slide", JointKind::Prismatic, (GROUND, "A"), ("g1", "c"))
            .axes("z", "z")
            .x_axes("x", "x"),
    );
    let mut b2 = b.clone();
    b2.coupler(CouplerSpec::rack_pinion("teeth", "slide", "j2", 0.1));
    let e = refused(&b2).to_string();
    assert!(e.contains("not perpendicular"), "{e}");
    // A screw whose slide is not along its axis.
    let mut b = two_gears();
    disc(&mut b, "nut", Vector3::new(3.0, 0.0, 0.0));
    b.point(GROUND, "N", Vector3::new(3.0, 0.0, 0.0));
    b.joint(
        JointSpec::new("slide", JointKind::Prismatic, (GROUND, "N"), ("nut", "c"))
            .axes("x", "x")
            .x_axes("z", "z"),
    );
    b.coupler(CouplerSpec::screw("thread", "slide", "j1", 0.01));
    let e = refused(&b).to_string();
    assert!(e.contains("not along the axis"), "{e}");
}
