//! Shared test models: Haug's spatial slider-crank, a planar four-bar of spatial revolutes,
//! Bricard's linkage.
#![allow(dead_code)]

use cardan_mechanism::{
    Body, DriverSpec, JointKind, JointSpec, MechanismBuilder, Model, Orientation, TimeFunction,
    GROUND,
};
use nalgebra::{Matrix3, Vector3};
use std::f64::consts::PI;

/// Haug's spatial slider-crank (benchmark README §2.6), crank driven at `omega` rad/s.
///
/// Crank: revolute to ground at A = (0, 0.1, 0.12) about x, length 0.08, CoM at its midpoint,
/// initially along +z (B = (0, 0.1, 0.2)). Conrod BC, length 0.3: spherical at B, universal at C
/// (slider arm x, conrod arm y_rod ⟂ the rod). Slider: prismatic along global x, C = (x, 0, 0).
pub fn slider_crank_builder(omega: f64) -> MechanismBuilder {
    let mut b = slider_crank_undriven();
    b.driver(DriverSpec::rotation(
        "motor",
        "A",
        TimeFunction::Polynomial(vec![0.0, omega]),
    ));
    b
}

/// The slider-crank's bodies, points and vectors and its joints A, B, C: everything but the
/// slider's guide and the driver.
pub fn slider_crank_links() -> MechanismBuilder {
    let mut b = MechanismBuilder::new();
    let x_rod = Vector3::new(2.0, -1.0, -2.0) / 3.0;
    let y_rod = Vector3::new(0.0, 2.0, -1.0) / 5f64.sqrt();
    b.body(
        Body::new("crank")
            .mass(0.12)
            .inertia_diagonal(1e-4, 1e-4, 1e-5)
            .position(Vector3::new(0.0, 0.1, 0.16)),
    );
    b.body(
        Body::new("conrod")
            .mass(0.5)
            .inertia_diagonal(4e-4, 4e-3, 4e-3)
            .position(Vector3::new(0.1, 0.05, 0.1))
            .orientation(Orientation::Axes {
                z: x_rod.cross(&y_rod),
                x: Some(x_rod),
            }),
    );
    b.body(
        Body::new("slider")
            .mass(2.0)
            .inertia(Matrix3::identity() * 1e-4)
            .position(Vector3::new(0.2, 0.0, 0.0)),
    );
    b.point(GROUND, "A", Vector3::new(0.0, 0.1, 0.12))
        .point(GROUND, "O", Vector3::zeros())
        .vector(GROUND, "x", Vector3::x())
        .vector(GROUND, "z", Vector3::z());
    b.point("crank", "A", Vector3::new(0.0, 0.0, -0.04))
        .point("crank", "B", Vector3::new(0.0, 0.0, 0.04))
        .vector("crank", "x", Vector3::x())
        .vector("crank", "z", Vector3::z());
    b.point("conrod", "B", Vector3::new(-0.15, 0.0, 0.0))
        .point("conrod", "C", Vector3::new(0.15, 0.0, 0.0))
        .vector("conrod", "y", Vector3::y());
    b.point("slider", "C", Vector3::zeros())
        .vector("slider", "x", Vector3::x());
    b.joint(
        JointSpec::new("A", JointKind::Revolute, (GROUND, "A"), ("crank", "A"))
            .axes("x", "x")
            .x_axes("z", "z"),
    );
    b.joint(JointSpec::new(
        "B",
        JointKind::Spherical,
        ("crank", "B"),
        ("conrod", "B"),
    ));
    b.joint(
        JointSpec::new("C", JointKind::Universal, ("slider", "C"), ("conrod", "C")).axes("x", "y"),
    );
    b
}

/// The slider-crank without its driver (1 degree of freedom).
pub fn slider_crank_undriven() -> MechanismBuilder {
    let mut b = slider_crank_links();
    b.joint(
        JointSpec::new(
            "slide",
            JointKind::Prismatic,
            (GROUND, "O"),
            ("slider", "C"),
        )
        .axes("x", "x"),
    );
    b
}

/// The slider-crank at 2π rad/s.
pub fn slider_crank() -> Model {
    slider_crank_builder(2.0 * PI).build().unwrap()
}

/// The slider-crank at `omega` with its crank pin B also held on the circle it runs on (about
/// x through A, radius 0.08): a point-on-curve element whose three rows the revolute implies
/// (two are dropped as redundant); its curve parameter runs u = 0.08 θ + u₀.
pub fn slider_crank_on_rim(omega: f64) -> Model {
    use cardan_constraints::{Circle, Marker};
    let mut b = slider_crank_builder(omega);
    let m = Marker::from_axis(Vector3::new(0.0, 0.1, 0.12), Vector3::x()).unwrap();
    b.curve(cardan_mechanism::CurveSpec::new(
        "rim",
        GROUND,
        Circle::new(&m, 0.08).unwrap(),
        "crank",
        "B",
    ));
    b.build().unwrap()
}

/// Closed form of the slider position x(θ) and its θ-derivatives x', x''.
///
/// B = A + 0.08 (0, −sin θ, cos θ) (the crank +z rotated by θ about x), C = (x, 0, 0), and
/// |C − B| = 0.3 gives x² = 0.09 − (0.1 − 0.08 sin θ)² − (0.12 + 0.08 cos θ)² (x > 0 branch).
/// Differentiating x² in θ: x x' = 0.008 cos θ + 0.0096 sin θ, and
/// x'² + x x'' = −0.008 sin θ + 0.0096 cos θ.
pub fn slider_x(theta: f64) -> (f64, f64, f64) {
    let (s, c) = theta.sin_cos();
    let x = (0.09 - (0.1 - 0.08 * s).powi(2) - (0.12 + 0.08 * c).powi(2)).sqrt();
    let x1 = (0.008 * c + 0.0096 * s) / x;
    let x2 = (-0.008 * s + 0.0096 * c - x1 * x1) / x;
    (x, x1, x2)
}

/// Four-bar lengths: ground d, crank a, coupler b, rocker c (Grashof crank-rocker).
pub const FOUR_BAR: (f64, f64, f64, f64) = (3.0, 1.0, 3.5, 2.5);

/// Closed form of the four-bar: coupler-rocker pin B for crank angle θ (upper branch).
///
/// A = a (cos θ, sin θ); B lies on the circle of radius c about O4 = (d, 0) at distance b from A:
/// with D = O4 − A, δ = |D|, u = D/δ, l = (b² − c² + δ²)/(2δ), h = √(b² − l²),
/// B = A + l u + h (−u_y, u_x).
pub fn four_bar_b(theta: f64) -> Vector3<f64> {
    let (d, a, b, c) = FOUR_BAR;
    let pa = Vector3::new(a * theta.cos(), a * theta.sin(), 0.0);
    let dd = Vector3::new(d, 0.0, 0.0) - pa;
    let delta = dd.norm();
    let u = dd / delta;
    let l = (b * b - c * c + delta * delta) / (2.0 * delta);
    let h = (b * b - l * l).sqrt();
    pa + l * u + h * Vector3::new(-u.y, u.x, 0.0)
}

fn link(
    b: &mut MechanismBuilder,
    name: &str,
    p: Vector3<f64>,
    q: Vector3<f64>,
    ends: (&str, &str),
) {
    let d = q - p;
    let len = d.norm();
    let angle = d.y.atan2(d.x);
    b.body(
        Body::new(name)
            .mass(1.0)
            .inertia_diagonal(0.01, len * len / 12.0, len * len / 12.0)
            .position((p + q) / 2.0)
            .orientation(Orientation::AxisAngle {
                axis: Vector3::z(),
                angle,
            }),
    );
    b.point(name, ends.0, Vector3::new(-len / 2.0, 0.0, 0.0))
        .point(name, ends.1, Vector3::new(len / 2.0, 0.0, 0.0))
        .vector(name, "z", Vector3::z())
        .vector(name, "x", Vector3::x());
}

/// The planar four-bar as four spatial revolute joints (3 redundant equations), crank driven
/// with θ(t) = θ0 + ω t.
pub fn four_bar_builder(theta0: f64, omega: f64) -> MechanismBuilder {
    four_bar_builder_off_plane(theta0, omega, 0.0)
}

/// [`four_bar_builder`] with the ground pivot O4 drawn `dz` out of the plane (the rocker
/// drawn in the plane): the loop cannot close for dz ≠ 0 (the revolute axes are parallel), a
/// redundant model whose joints disagree by |dz|.
#[allow(dead_code)]
pub fn four_bar_builder_off_plane(theta0: f64, omega: f64, dz: f64) -> MechanismBuilder {
    let mut b = four_bar_links(theta0, dz);
    b.driver(DriverSpec::rotation(
        "motor",
        "O2",
        TimeFunction::Polynomial(vec![theta0, omega]),
    ));
    b
}

/// The links and joints of [`four_bar_builder_off_plane`], drawn at crank angle θ0, without a
/// driver (1 DOF).
#[allow(dead_code)]
pub fn four_bar_links(theta0: f64, dz: f64) -> MechanismBuilder {
    let (d, a, _, _) = FOUR_BAR;
    let mut b = MechanismBuilder::new();
    let pa = Vector3::new(a * theta0.cos(), a * theta0.sin(), 0.0);
    let pb = four_bar_b(theta0);
    let o4 = Vector3::new(d, 0.0, 0.0);
    link(&mut b, "crank", Vector3::zeros(), pa, ("O", "A"));
    link(&mut b, "coupler", pa, pb, ("A", "B"));
    link(&mut b, "rocker", o4, pb, ("O", "B"));
    b.point(GROUND, "O2", Vector3::zeros())
        .point(GROUND, "O4", o4 + Vector3::new(0.0, 0.0, dz))
        .vector(GROUND, "z", Vector3::z())
        .vector(GROUND, "x", Vector3::x());
    let rev = |n: &str, i: (&str, &str), j: (&str, &str)| {
        JointSpec::new(n, JointKind::Revolute, i, j)
            .axes("z", "z")
            .x_axes("x", "x")
    };
    b.joint(rev("O2", (GROUND, "O2"), ("crank", "O")));
    b.joint(rev("A", ("crank", "A"), ("coupler", "A")));
    b.joint(rev("B", ("coupler", "B"), ("rocker", "B")));
    b.joint(rev("O4", (GROUND, "O4"), ("rocker", "O")));
    b
}

/// Bricard's linkage (benchmark README §2.4): five unit rods, six revolutes, 30 equations of
/// rank 29. Without driver.
pub fn bricard_builder() -> MechanismBuilder {
    let mut b = MechanismBuilder::new();
    let pts = [
        Vector3::new(0.0, 0.0, 0.0),
        Vector3::new(1.0, 0.0, 0.0),
        Vector3::new(1.0, -1.0, 0.0),
        Vector3::new(1.0, -1.0, 1.0),
        Vector3::new(0.0, -1.0, 1.0),
        Vector3::new(0.0, 0.0, 1.0),
    ];
    let axes = [
        Vector3::y(),
        Vector3::z(),
        Vector3::x(),
        Vector3::y(),
        Vector3::z(),
        Vector3::x(),
    ];
    let names = ["A", "B", "C", "D", "E", "F"];
    b.vector(GROUND, "x", Vector3::x())
        .vector(GROUND, "y", Vector3::y())
        .vector(GROUND, "z", Vector3::z());
    b.point(GROUND, "A", pts[0]).point(GROUND, "F", pts[5]);
    for k in 0..5 {
        let name = format!("rod{}", k + 1);
        let mid = (pts[k] + pts[k + 1]) / 2.0;
        b.body(
            Body::new(&name)
                .mass(1.0)
                .inertia_diagonal(1.01 / 12.0, 1.01 / 12.0, 1.01 / 12.0)
                .position(mid),
        );
        b.point(&name, names[k], pts[k] - mid)
            .point(&name, names[k + 1], pts[k + 1] - mid)
            .vector(&name, "x", Vector3::x())
            .vector(&name, "y", Vector3::y())
            .vector(&name, "z", Vector3::z());
    }
    let axis_name = |v: &Vector3<f64>| {
        if v.x != 0.0 {
            "x"
        } else if v.y != 0.0 {
            "y"
        } else {
            "z"
        }
    };
    for k in 0..6 {
        let bi = if k == 0 {
            GROUND.to_string()
        } else {
            format!("rod{k}")
        };
        let bj = if k == 5 {
            GROUND.to_string()
        } else {
            format!("rod{}", k + 1)
        };
        let a = axis_name(&axes[k]);
        let ref_axis = if a == "x" { "y" } else { "x" };
        b.joint(
            JointSpec::new(
                names[k],
                JointKind::Revolute,
                (&bi, names[k]),
                (&bj, names[k]),
            )
            .axes(a, a)
            .x_axes(ref_axis, ref_axis),
        );
    }
    b
}

/// Haug's slider-crank with its prismatic joint replaced by the slider's point C on a line
/// along global x through O (a pin in a straight slot) and a no-rotation joint.
pub fn slotted_slider_crank(omega: f64) -> MechanismBuilder {
    slotted(omega, straight_slot())
}

/// The slider's point C on a line along global x through O.
pub fn straight_slot() -> cardan_mechanism::CurveSpec {
    let slot = cardan_constraints::Line::new(
        &cardan_constraints::Marker::from_axis(Vector3::zeros(), Vector3::x()).unwrap(),
    );
    cardan_mechanism::CurveSpec::new("slot", GROUND, slot, "slider", "C")
}

/// [`slotted`] without its motor: one degree of freedom left free.
pub fn slotted_undriven(slot: cardan_mechanism::CurveSpec) -> MechanismBuilder {
    let mut b = slider_crank_links();
    b.joint(
        JointSpec::new(
            "keep",
            JointKind::NoRotation,
            (GROUND, "O"),
            ("slider", "C"),
        )
        .axes("x", "x"),
    );
    b.curve(slot);
    b
}

/// The slider-crank with the slider's point C held by `slot` and its rotation locked.
pub fn slotted(omega: f64, slot: cardan_mechanism::CurveSpec) -> MechanismBuilder {
    let mut b = slotted_undriven(slot);
    b.driver(DriverSpec::rotation(
        "motor",
        "A",
        TimeFunction::Polynomial(vec![0.0, omega]),
    ));
    b
}
