//! Shared models for the dynamics tests.
#![allow(dead_code)]

use cardan_constraints::{JointKind, TimeFunction};
use cardan_mechanism::{Body, DriverSpec, JointSpec, MechanismBuilder, Model, GROUND};
use nalgebra::Vector3;

pub const G: f64 = 9.81;

/// A01: a point mass `m` (tiny inertia `i`) at the end of a massless link of length `l`,
/// pinned at the origin about z, released from rest at (+l, 0, 0).
pub fn pendulum(m: f64, i: f64, l: f64) -> Model {
    let mut b = MechanismBuilder::new();
    b.body(
        Body::new("mass")
            .mass(m)
            .inertia_diagonal(i, i, i)
            .position(Vector3::new(l, 0.0, 0.0)),
    );
    b.point(GROUND, "O", Vector3::zeros())
        .vector(GROUND, "z", Vector3::z())
        .vector(GROUND, "x", Vector3::x());
    b.point("mass", "O", Vector3::new(-l, 0.0, 0.0))
        .vector("mass", "z", Vector3::z())
        .vector("mass", "x", Vector3::x());
    b.joint(
        JointSpec::new("pin", JointKind::Revolute, (GROUND, "O"), ("mass", "O"))
            .axes("z", "z")
            .x_axes("x", "x"),
    );
    b.build().unwrap()
}

/// A uniform rod `name` (mass m, length l, CoM at its middle, axial inertia `axial`) pinned
/// at its end O at the origin by the revolute joint `pin` about z (x axes for its angle),
/// initially along +x; its other end is `tip`. The builder, for a driver, limit or friction.
pub fn rod_on_a_pin(name: &str, m: f64, l: f64, axial: f64) -> MechanismBuilder {
    let mut b = MechanismBuilder::new();
    let i = m * l * l / 12.0;
    b.body(
        Body::new(name)
            .mass(m)
            .inertia_diagonal(axial, i, i)
            .position(Vector3::new(l / 2.0, 0.0, 0.0)),
    );
    b.point(GROUND, "O", Vector3::zeros())
        .vector(GROUND, "z", Vector3::z())
        .vector(GROUND, "x", Vector3::x());
    b.point(name, "O", Vector3::new(-l / 2.0, 0.0, 0.0))
        .point(name, "tip", Vector3::new(l / 2.0, 0.0, 0.0))
        .vector(name, "z", Vector3::z())
        .vector(name, "x", Vector3::x());
    b.joint(
        JointSpec::new("pin", JointKind::Revolute, (GROUND, "O"), (name, "O"))
            .axes("z", "z")
            .x_axes("x", "x"),
    );
    b
}

/// A uniform rod (mass m, length l, CoM at its middle) pinned at its end at the origin about
/// z, initially along +x, optionally driven by `drive` (angle of the pin).
pub fn crank(m: f64, l: f64, drive: Option<TimeFunction>) -> Model {
    let mut b = rod_on_a_pin("crank", m, l, 1e-3);
    if let Some(f) = drive {
        b.driver(DriverSpec::rotation("motor", "pin", f));
    }
    b.build().unwrap()
}

/// One free body with diagonal inertia.
pub fn free_body(m: f64, j: [f64; 3]) -> Model {
    let mut b = MechanismBuilder::new();
    b.body(
        Body::new("body")
            .mass(m)
            .inertia_diagonal(j[0], j[1], j[2])
            .position(Vector3::new(0.0, 0.0, 1.0)),
    );
    b.point("body", "c", Vector3::zeros());
    b.build().unwrap()
}

/// Exact A01 positions (x, y) of the mass, from `shared/benchmarks/simple_pendulum_exact.csv`
/// (released from rest at (+1, 0)).
pub const A01: [(f64, f64, f64); 6] = [
    (0.5, 0.391048791550546, -0.920369948785192),
    (1.0, -0.986291751131875, -0.165010853125541),
    (2.0, 0.793566195343322, -0.608483930443792),
    (5.0, 0.942305435043757, -0.334754338414001),
    (10.0, 0.275087462576117, -0.961419205099125),
    (20.0, -0.996907173991, -0.0785880808093),
];

/// A chain of `n` uniform 1 m rods (1 kg) along +x joined by spherical joints, the first
/// to the ground at the origin (points "a" and "b" at the rod ends).
pub fn spherical_chain(n: usize) -> Model {
    let mut b = MechanismBuilder::new();
    b.point(GROUND, "O", Vector3::zeros());
    for k in 0..n {
        let body = format!("b{k}");
        b.body(
            Body::new(&body)
                .mass(1.0)
                .inertia_diagonal(0.001, 1.0 / 12.0, 1.0 / 12.0)
                .position(Vector3::new(k as f64 + 0.5, 0.0, 0.0)),
        );
        b.point(&body, "a", Vector3::new(-0.5, 0.0, 0.0)).point(
            &body,
            "b",
            Vector3::new(0.5, 0.0, 0.0),
        );
        let prev = if k == 0 {
            (GROUND.to_string(), "O")
        } else {
            (format!("b{}", k - 1), "b")
        };
        b.joint(JointSpec::new(
            format!("s{k}"),
            JointKind::Spherical,
            (&prev.0, prev.1),
            (&body, "a"),
        ));
    }
    b.build().unwrap()
}

/// The sparse path of the modal analysis ([`cardan_dynamics::Dynamics::modal_sparse`]) against
/// the dense one on the same model: the sparse tangents K_t and C_t equal the dense ones (the
/// same central differences, grouped), and, without damping, the same modes (kind and
/// frequency to 1e-8 relative, rigid ones as rigid).
pub fn assert_sparse_modal_matches(
    d: &mut cardan_dynamics::Dynamics,
    dense: &cardan_dynamics::ModalResults,
) {
    let sparse = d
        .modal_sparse(
            &cardan_dynamics::StaticOptions::default(),
            dense.modes.len(),
        )
        .unwrap();
    assert!(sparse.converged);
    let close = |a: &nalgebra::DMatrix<f64>, b: &nalgebra::DMatrix<f64>, what: &str| {
        let big = b.amax().max(1e-300);
        let err = (a - b).amax();
        assert!(err <= 1e-9 * big, "{what}: {err:.3e} of {big:.3e}");
    };
    let lin = &dense.linearization;
    close(&sparse.stiffness.to_dense(), &lin.full_stiffness, "K_t");
    close(&sparse.damping.to_dense(), &lin.full_damping, "C_t");
    if lin.is_damped() {
        return;
    }
    assert_eq!(sparse.modes.len(), dense.modes.len());
    for (s, m) in sparse.modes.iter().zip(&dense.modes) {
        assert_eq!(s.kind, m.kind);
        let rel = (s.frequency - m.frequency).abs() / m.frequency.max(1e-300);
        assert!(
            rel < 1e-8 || s.frequency == m.frequency,
            "{} vs {} Hz",
            s.frequency,
            m.frequency
        );
    }
}
