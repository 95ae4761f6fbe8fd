//! Degrees of freedom for each joint kind: one body jointed to ground has 6 − (joint rows).

use cardan_mechanism::{Body, JointKind, JointSpec, MechanismBuilder, GROUND};
use nalgebra::Vector3;

fn one_joint(kind: JointKind) -> MechanismBuilder {
    let mut b = MechanismBuilder::new();
    b.body(Body::new("b").position(Vector3::new(1.0, 0.0, 0.0)));
    b.point(GROUND, "P", Vector3::zeros())
        .vector(GROUND, "z", Vector3::z())
        .vector(GROUND, "x", Vector3::x());
    b.point("b", "P", Vector3::new(-1.0, 0.0, 0.0))
        .vector("b", "z", Vector3::z())
        .vector("b", "x", Vector3::x())
        .point("b", "R", Vector3::zeros());
    // A spherical-spherical joint needs distinct points (its length defaults to their distance).
    let pj = if kind == JointKind::SphericalSpherical {
        "R"
    } else {
        "P"
    };
    let spec = JointSpec::new("j", kind, (GROUND, "P"), ("b", pj));
    let spec = match kind {
        JointKind::Spherical | JointKind::SphericalSpherical => spec,
        // The cross arms of a universal joint are perpendicular.
        JointKind::Universal => spec.axes("z", "x"),
        _ => spec.axes("z", "z").x_axes("x", "x"),
    };
    b.joint(spec);
    b
}

#[test]
fn dof_of_every_joint_kind() {
    let expected = [
        (JointKind::Spherical, 3),
        (JointKind::Universal, 2),
        (JointKind::Revolute, 1),
        (JointKind::Cylindrical, 2),
        (JointKind::Prismatic, 1),
        (JointKind::Fixed, 0),
        (JointKind::SphericalSpherical, 5),
        (JointKind::Planar, 3),
    ];
    for (kind, dof) in expected {
        let model = one_joint(kind).build().unwrap();
        let ws = model.workspace();
        let rep = model.dof(&ws).unwrap();
        eprintln!("{}: {rep}", kind.name());
        assert_eq!(rep.dof, dof, "{}", kind.name());
        assert_eq!(rep.dof, 6 - kind.rows(), "{}", kind.name());
        assert!(rep.redundant.is_empty());
    }
}

/// A free body has 6 degrees of freedom; two revolutes on the same axis leave 1 with 5
/// redundant equations.
#[test]
fn free_body_and_doubled_revolute() {
    let mut b = MechanismBuilder::new();
    b.body(Body::new("free"));
    let model = b.build().unwrap();
    assert_eq!(model.dof(&model.workspace()).unwrap().dof, 6);

    let mut b = one_joint(JointKind::Revolute);
    b.point(GROUND, "Q", Vector3::new(0.0, 0.0, 1.0))
        .point("b", "Q", Vector3::new(-1.0, 0.0, 1.0));
    b.joint(JointSpec::new("j2", JointKind::Revolute, (GROUND, "Q"), ("b", "Q")).axes("z", "z"));
    let model = b.build().unwrap();
    let rep = model.dof(&model.workspace()).unwrap();
    eprintln!("doubled revolute: {rep}");
    assert_eq!(rep.dof, 1);
    assert_eq!(rep.redundant.len(), 5);
    assert!(rep.redundant.iter().all(|e| e.element == "j2"));
}
