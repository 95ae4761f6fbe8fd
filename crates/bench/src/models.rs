//! Benchmark mechanisms.
//!
//! All links are slender rods of length `L = 1 m`, mass 1 kg, inertia about the centre of mass
//! diag(0.001, 1/12, 1/12) along the rod's own x axis (the rockers of the ladder are rods along
//! y: diag(1/12, 0.001, 1/12)).
//!
//! - [`revolute_chain`]: an open chain of `n` links along +x, joint k a revolute about z (k even)
//!   or y (k odd), every joint driven (θ_k = 0.1 t): n DOF, n drivers. Block-bidiagonal Jacobian.
//! - [`ladder`]: a row of `loops` closed R-S-U-R loops sharing rockers (the IFToMM N-four-bar
//!   made non-redundant for spatial joints): rocker k pinned to ground by a revolute about z,
//!   coupler k joined to the top of rocker k by a spherical joint and to rocker k + 1 by a
//!   universal joint (arms: coupler z, rocker y: the coupler cannot spin). 2 loops + 1 bodies, 1 DOF, the first revolute
//!   driven (θ = 0.2 t).
//! - [`spherical_chain`]: `n` links along +x joined by spherical joints (the first to the ground
//!   at the origin), gravity −z, at rest: the dynamic chain of the peer comparison.

use cardan_constraints::{JointKind, TimeFunction};
use cardan_mechanism::{Body, DriverSpec, JointSpec, MechanismBuilder, Model, GROUND};
use nalgebra::Vector3;

/// Link length \[m\].
pub const L: f64 = 1.0;

fn rod_x(name: &str, centre: Vector3<f64>) -> Body {
    Body::new(name)
        .mass(1.0)
        .inertia_diagonal(0.001, 1.0 / 12.0, 1.0 / 12.0)
        .position(centre)
}

fn rod_y(name: &str, centre: Vector3<f64>) -> Body {
    Body::new(name)
        .mass(1.0)
        .inertia_diagonal(1.0 / 12.0, 0.001, 1.0 / 12.0)
        .position(centre)
}

fn frame_vectors(b: &mut MechanismBuilder, body: &str) {
    b.vector(body, "x", Vector3::x())
        .vector(body, "y", Vector3::y())
        .vector(body, "z", Vector3::z());
}

/// Links along x: body `b<k>` with end points `a` (−L/2) and `b` (+L/2).
fn links(b: &mut MechanismBuilder, n: usize) {
    b.point(GROUND, "O", Vector3::zeros());
    frame_vectors(b, GROUND);
    for k in 0..n {
        let name = format!("b{k}");
        b.body(rod_x(&name, Vector3::new((k as f64 + 0.5) * L, 0.0, 0.0)));
        b.point(&name, "a", Vector3::new(-0.5 * L, 0.0, 0.0)).point(
            &name,
            "b",
            Vector3::new(0.5 * L, 0.0, 0.0),
        );
        frame_vectors(b, &name);
    }
}

fn prev(k: usize) -> (String, &'static str) {
    if k == 0 {
        (GROUND.to_string(), "O")
    } else {
        (format!("b{}", k - 1), "b")
    }
}

/// The driven open chain of `n` revolute joints (see the module docs).
pub fn revolute_chain_builder(n: usize) -> MechanismBuilder {
    let mut b = MechanismBuilder::new();
    links(&mut b, n);
    for k in 0..n {
        let (pb, pp) = prev(k);
        let name = format!("b{k}");
        let axis = if k % 2 == 0 { "z" } else { "y" };
        let j = format!("j{k}");
        b.joint(
            JointSpec::new(&j, JointKind::Revolute, (&pb, pp), (&name, "a"))
                .axes(axis, axis)
                .x_axes("x", "x"),
        );
        b.driver(DriverSpec::rotation(
            format!("d{k}"),
            &j,
            TimeFunction::Polynomial(vec![0.0, 0.1]),
        ));
    }
    b
}

/// [`revolute_chain_builder`], built.
pub fn revolute_chain(n: usize) -> Model {
    revolute_chain_builder(n).build().expect("valid chain")
}

/// The spherical-joint chain of `n` links (no drivers; see the module docs).
pub fn spherical_chain(n: usize) -> Model {
    let mut b = MechanismBuilder::new();
    links(&mut b, n);
    for k in 0..n {
        let (pb, pp) = prev(k);
        let name = format!("b{k}");
        b.joint(JointSpec::new(
            format!("s{k}"),
            JointKind::Spherical,
            (&pb, pp),
            (&name, "a"),
        ));
    }
    b.build().expect("valid chain")
}

/// The ladder of `loops` R-S-U-R loops (2 loops + 1 bodies), driven when `driven`.
pub fn ladder(loops: usize, driven: bool) -> Model {
    let mut b = MechanismBuilder::new();
    frame_vectors(&mut b, GROUND);
    for k in 0..=loops {
        let r = format!("r{k}");
        b.point(
            GROUND,
            &format!("G{k}"),
            Vector3::new(k as f64 * L, 0.0, 0.0),
        );
        b.body(rod_y(&r, Vector3::new(k as f64 * L, 0.5 * L, 0.0)));
        b.point(&r, "base", Vector3::new(0.0, -0.5 * L, 0.0)).point(
            &r,
            "top",
            Vector3::new(0.0, 0.5 * L, 0.0),
        );
        frame_vectors(&mut b, &r);
        b.joint(
            JointSpec::new(
                format!("G{k}"),
                JointKind::Revolute,
                (GROUND, &format!("G{k}")),
                (&r, "base"),
            )
            .axes("z", "z")
            .x_axes("x", "x"),
        );
    }
    for k in 0..loops {
        let c = format!("c{k}");
        b.body(rod_x(&c, Vector3::new((k as f64 + 0.5) * L, L, 0.0)));
        b.point(&c, "a", Vector3::new(-0.5 * L, 0.0, 0.0)).point(
            &c,
            "b",
            Vector3::new(0.5 * L, 0.0, 0.0),
        );
        frame_vectors(&mut b, &c);
        b.joint(JointSpec::new(
            format!("S{k}"),
            JointKind::Spherical,
            (&format!("r{k}"), "top"),
            (&c, "a"),
        ));
        b.joint(
            JointSpec::new(
                format!("U{k}"),
                JointKind::Universal,
                (&c, "b"),
                (&format!("r{}", k + 1), "top"),
            )
            .axes("z", "y"),
        );
    }
    if driven {
        b.driver(DriverSpec::rotation(
            "motor",
            "G0",
            TimeFunction::Polynomial(vec![0.0, 0.2]),
        ));
    }
    b.build().expect("valid ladder")
}

/// Loops of a ladder with about `n` bodies (2 loops + 1 = n rounded to odd).
pub fn ladder_loops(n: usize) -> usize {
    (n.max(3) - 1) / 2
}
