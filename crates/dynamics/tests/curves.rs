//! Point-on-curve elements are kinematic only for now: every dynamic analysis refuses them by
//! name instead of running without their equations.

use cardan_constraints::{Line, Marker};
use cardan_dynamics::{Dynamics, DynamicsError};
use cardan_mechanism::{Body, CurveSpec, MechanismBuilder, GROUND};
use nalgebra::Vector3;

#[test]
fn dynamics_refuses_a_point_on_a_curve_by_name() {
    let mut b = MechanismBuilder::new();
    b.body(Body::new("bead").mass(1.0).inertia_diagonal(1.0, 1.0, 1.0));
    b.point("bead", "P", Vector3::zeros());
    let wire = Line::new(&Marker::from_axis(Vector3::zeros(), Vector3::x()).unwrap());
    b.curve(CurveSpec::new("wire", GROUND, wire, "bead", "P"));
    let model = b.build().unwrap();
    let Err(err) = Dynamics::new(&model) else {
        panic!("a model with a point on a curve was accepted");
    };
    assert!(
        matches!(&err, DynamicsError::CurveElement { element, .. } if element == "wire"),
        "{err}"
    );
    assert!(err.to_string().contains("kind = \"kinematic\""), "{err}");
}
