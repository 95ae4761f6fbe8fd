//! The joint-space outputs of an inverse dynamics run ([`cardan_dynamics::joint_space`])
//! against the closed forms of a planar double pendulum of two uniform rods (Spong, Hutchinson
//! & Vidyasagar 2006 §7.3.2, the two-link planar arm with θ₂ relative to link 1):
//!
//! ```text
//! M₁₁ = I₁ + m₁l_c1² + I₂ + m₂(l₁² + l_c2² + 2 l₁ l_c2 cos θ₂)
//! M₁₂ = I₂ + m₂(l_c2² + l₁ l_c2 cos θ₂),   M₂₂ = I₂ + m₂ l_c2²
//! h₁ = −m₂ l₁ l_c2 sin θ₂ (2 θ̇₁θ̇₂ + θ̇₂²) + (m₁ l_c1 + m₂ l₁) g cos θ₁ + m₂ l_c2 g cos(θ₁ + θ₂)
//! h₂ = m₂ l₁ l_c2 sin θ₂ θ̇₁² + m₂ l_c2 g cos(θ₁ + θ₂)
//! ```
//!
//! and the tip's Jacobian. (h is computed as the efforts less M θ̈, so τ = M θ̈ + h holds by
//! construction; the closed form of h is what checks it.)

mod common;
use cardan_constraints::{JointKind, TimeFunction};
use cardan_dynamics::{Dynamics, DynamicsError, Force, JointSpacePoint};
use cardan_mechanism::{
    Body, BodyId, DriverSpec, JointSpec, KinematicOptions, MechanismBuilder, Model, GROUND,
};
use common::G;
use nalgebra::{Matrix2, Vector2, Vector3};

const M1: f64 = 2.0;
const L1: f64 = 0.8;
const M2: f64 = 1.5;
const L2: f64 = 0.6;

/// θ₁(t), θ₂(t): polynomials c₀ + c₁ t + c₂ t².
const LAW: [[f64; 3]; 2] = [[0.3, 1.0, 0.5], [0.5, -0.8, 0.3]];

fn rod(b: &mut MechanismBuilder, name: &str, m: f64, l: f64, x0: f64) {
    let i = m * l * l / 12.0;
    b.body(
        Body::new(name)
            .mass(m)
            .inertia_diagonal(1e-3, i, i)
            .position(Vector3::new(x0 + l / 2.0, 0.0, 0.0)),
    );
    b.point(name, "O", Vector3::new(-l / 2.0, 0.0, 0.0))
        .point(name, "tip", Vector3::new(l / 2.0, 0.0, 0.0))
        .vector(name, "z", Vector3::z())
        .vector(name, "x", Vector3::x());
}

fn double_pendulum(drive: bool) -> Model {
    let mut b = MechanismBuilder::new();
    b.point(GROUND, "O", Vector3::zeros())
        .vector(GROUND, "z", Vector3::z())
        .vector(GROUND, "x", Vector3::x());
    rod(&mut b, "link1", M1, L1, 0.0);
    rod(&mut b, "link2", M2, L2, L1);
    b.joint(
        JointSpec::new("pin1", JointKind::Revolute, (GROUND, "O"), ("link1", "O"))
            .axes("z", "z")
            .x_axes("x", "x"),
    );
    b.joint(
        JointSpec::new(
            "pin2",
            JointKind::Revolute,
            ("link1", "tip"),
            ("link2", "O"),
        )
        .axes("z", "z")
        .x_axes("x", "x"),
    );
    if drive {
        for (k, law) in LAW.iter().enumerate() {
            let f = TimeFunction::Polynomial(law.to_vec());
            b.driver(DriverSpec::rotation(
                format!("d{}", k + 1),
                &format!("pin{}", k + 1),
                f,
            ));
        }
    }
    b.build().unwrap()
}

/// θ, θ̇, θ̈ of the drivers at t.
fn law(t: f64) -> [Vector2<f64>; 3] {
    let [a, b] = LAW;
    let q = |c: [f64; 3]| {
        [
            c[0] + c[1] * t + c[2] * t * t,
            c[1] + 2.0 * c[2] * t,
            2.0 * c[2],
        ]
    };
    let (qa, qb) = (q(a), q(b));
    [0, 1, 2].map(|k| Vector2::new(qa[k], qb[k]))
}

fn closed_form(th: Vector2<f64>, thd: Vector2<f64>) -> (Matrix2<f64>, Vector2<f64>) {
    let (lc1, lc2) = (L1 / 2.0, L2 / 2.0);
    let (i1, i2) = (M1 * L1 * L1 / 12.0, M2 * L2 * L2 / 12.0);
    let (c2, s2) = (th[1].cos(), th[1].sin());
    let (c1, c12) = (th[0].cos(), (th[0] + th[1]).cos());
    let m11 = i1 + M1 * lc1 * lc1 + i2 + M2 * (L1 * L1 + lc2 * lc2 + 2.0 * L1 * lc2 * c2);
    let m12 = i2 + M2 * (lc2 * lc2 + L1 * lc2 * c2);
    let m22 = i2 + M2 * lc2 * lc2;
    let k = M2 * L1 * lc2 * s2;
    let h1 = -k * (2.0 * thd[0] * thd[1] + thd[1] * thd[1])
        + (M1 * lc1 + M2 * L1) * G * c1
        + M2 * lc2 * G * c12;
    let h2 = k * thd[0] * thd[0] + M2 * lc2 * G * c12;
    (Matrix2::new(m11, m12, m12, m22), Vector2::new(h1, h2))
}

#[test]
fn double_pendulum_mass_matrix_bias_and_jacobian_match_the_closed_form() {
    let model = double_pendulum(true);
    let mut d = Dynamics::new(&model).unwrap();
    d.add_force(Force::gravity(Vector3::new(0.0, -G, 0.0)))
        .unwrap();
    let link2 = model.body_id("link2").unwrap();
    let tip = JointSpacePoint {
        name: "link2.tip".into(),
        body: link2,
        local: Vector3::new(L2 / 2.0, 0.0, 0.0),
    };
    let ground = JointSpacePoint {
        name: "ground.O".into(),
        body: BodyId::Ground,
        local: Vector3::zeros(),
    };
    d.request_joint_space(vec![tip, ground]).unwrap();
    let res = d
        .inverse_dynamics(&KinematicOptions::new(0.0, 2.0, 40))
        .unwrap();
    let js = &res.joint_space;
    assert_eq!(js.coordinates, ["d1", "d2"]);
    assert_eq!(js.mass.len(), 41 * 4);
    let (mut em, mut eh, mut ej): (f64, f64, f64) = (0.0, 0.0, 0.0);
    for (k, &t) in res.times().iter().enumerate() {
        let [th, thd, _] = law(t);
        let (m, h) = closed_form(th, thd);
        let mine = Matrix2::from_row_slice(js.mass_at(k));
        em = em.max((mine - m).abs().max());
        eh = eh.max((Vector2::from_column_slice(js.bias_at(k)) - h).abs().max());
        let (s1, c1) = th[0].sin_cos();
        let (s12, c12) = (th[0] + th[1]).sin_cos();
        #[rustfmt::skip]
        let j = [
            -L1 * s1 - L2 * s12, -L2 * s12,
            L1 * c1 + L2 * c12, L2 * c12,
            0.0, 0.0,
            0.0, 0.0,
            0.0, 0.0,
            1.0, 1.0,
        ];
        let jm = js.jacobian_at(k, 0);
        ej = ej.max(
            j.iter()
                .zip(jm)
                .map(|(a, b)| (a - b).abs())
                .fold(0.0, f64::max),
        );
        assert!(
            js.jacobian_at(k, 1).iter().all(|&x| x == 0.0),
            "the ground's point"
        );
    }
    eprintln!("double pendulum: |ΔM| {em:.2e}, |Δh| {eh:.2e}, |ΔJ| {ej:.2e}");
    assert!(em < 1e-12, "{em}");
    assert!(eh < 1e-10, "{eh}");
    assert!(ej < 1e-12, "{ej}");
}

#[test]
fn no_joint_space_without_drivers() {
    let model = double_pendulum(false);
    let mut d = Dynamics::new(&model).unwrap();
    let err = d.request_joint_space(Vec::new()).unwrap_err();
    assert!(matches!(err, DynamicsError::JointSpace { .. }), "{err}");
    assert!(err.to_string().contains("no drivers"), "{err}");
}

#[test]
fn without_a_request_nothing_is_recorded() {
    let model = double_pendulum(true);
    let mut d = Dynamics::new(&model).unwrap();
    let res = d
        .inverse_dynamics(&KinematicOptions::new(0.0, 1.0, 4))
        .unwrap();
    assert!(!res.joint_space.is_requested());
    assert!(res.joint_space.mass.is_empty());
}

/// A free body (CoM at its frame's origin) driven from the ground by a general motion:
/// translations (0.1 t², −0.2 t, 0.3 + 0.05 t³) and angles (0.4 t, 0.3 t², −0.5 t) of the
/// sequence x-y-z.
fn flying_box(from: &str) -> Model {
    let mut b = MechanismBuilder::new();
    b.point(GROUND, "O", Vector3::zeros());
    b.body(
        Body::new("box")
            .mass(3.0)
            .inertia_diagonal(0.1, 0.2, 0.3)
            .position(Vector3::new(0.0, 0.0, 0.3)),
    );
    b.point("box", "c", Vector3::zeros());
    if from != GROUND {
        rod(&mut b, from, 1.0, 1.0, 2.0);
    }
    let poly = |c: &[f64]| TimeFunction::Polynomial(c.to_vec());
    b.driver(DriverSpec::pose(
        "base",
        cardan_mechanism::PoseTarget {
            body_i: from.into(),
            point_i: "O".into(),
            axis_i: None,
            x_axis_i: None,
            body_j: "box".into(),
            point_j: "c".into(),
            axis_j: None,
            x_axis_j: None,
            order: cardan_constraints::drivers::RotationOrder([0, 1, 2]),
            functions: [
                poly(&[0.0, 0.0, 0.1]),
                poly(&[0.0, -0.2]),
                poly(&[0.3, 0.0, 0.0, 0.05]),
                poly(&[0.0, 0.4]),
                poly(&[0.0, 0.0, 0.3]),
                poly(&[0.0, -0.5]),
            ],
        },
    ));
    b.build().unwrap()
}

#[test]
fn a_free_body_driven_from_the_ground_has_the_rigid_body_joint_space() {
    // Quasi-coordinates u = [ṙ (ground axes); ω'_y, −ω'_x, −ω'_z] = diag(A, P) [Aᵀṙ; ω'], so
    // M = diag(m I, P J Pᵀ) = diag(m I, J_y, J_x, J_z) and h = [−m g; P (ω' × J ω')].
    let model = flying_box(GROUND);
    let mut d = Dynamics::new(&model).unwrap();
    d.add_force(Force::gravity(Vector3::new(0.0, 0.0, -G)))
        .unwrap();
    d.request_joint_space(Vec::new()).unwrap();
    let res = d
        .inverse_dynamics(&KinematicOptions::new(0.0, 1.0, 10))
        .unwrap();
    let js = &res.joint_space;
    let (j, p) = (
        nalgebra::Matrix3::from_diagonal(&Vector3::new(0.1, 0.2, 0.3)),
        nalgebra::Matrix3::new(0.0, 1.0, 0.0, -1.0, 0.0, 0.0, 0.0, 0.0, -1.0),
    );
    let mut m = nalgebra::Matrix6::zeros();
    m.fixed_view_mut::<3, 3>(0, 0)
        .copy_from(&(3.0 * nalgebra::Matrix3::identity()));
    m.fixed_view_mut::<3, 3>(3, 3)
        .copy_from(&(p * j * p.transpose()));
    let (mut em, mut eh): (f64, f64) = (0.0, 0.0);
    for k in 0..res.len() {
        let mine = nalgebra::Matrix6::from_row_slice(js.mass_at(k));
        em = em.max((mine - m).abs().max());
        let w = res.kinematics.bodies[0].omega_local[k];
        let gyro = p * w.cross(&(j * w));
        let h = [0.0, 0.0, 3.0 * G, gyro.x, gyro.y, gyro.z];
        let mine = js.bias_at(k);
        eh = eh.max(
            h.iter()
                .zip(mine)
                .map(|(a, b)| (a - b).abs())
                .fold(0.0, f64::max),
        );
    }
    eprintln!("free body: |ΔM| {em:.2e}, |Δh| {eh:.2e}");
    assert!(em < 1e-12, "{em}");
    assert!(eh < 1e-10, "{eh}");
}

#[test]
fn a_general_motion_from_a_moving_body_is_refused() {
    let model = flying_box("link1");
    let mut d = Dynamics::new(&model).unwrap();
    let err = d.request_joint_space(Vec::new()).unwrap_err();
    assert!(
        err.to_string().contains("relative to a moving body"),
        "{err}"
    );
}
