//! Newton–Euler balance of the joint reactions of every kind in the kind table.
//!
//! One body hangs from ground by a joint of each kind, in a gravity field tilted so that it has a
//! component along every axis, and is set spinning. Along the dynamic run, the joint's reaction
//! on the body (force F and torque n about the joint point P_j, as written to reactions.csv)
//! must satisfy Newton's and Euler's equations for the body:
//!
//! m r̈ = m g + F,   A (J' ω̇' + ω' × J' ω') = n + (P_j − r) × F.
//!
//! The multipliers λ come from the equations of motion, so what this checks is everything after
//! them: the reaction's force and torque from −Φ_qᵀ λ of the kind's rows, the moment taken about
//! the right point, the global components. A wrong sign, a torque about the centre of mass
//! instead of P_j or a body-frame component written as global fails it. A kind added to the
//! table is checked here without an edit.

mod common;
use cardan_constraints::{JointKind, KINDS};
use cardan_dynamics::{Dopri5Options, Dynamics, Force, Integrator, SimulationOptions};
use cardan_mechanism::{Body, JointSpec, MechanismBuilder, Model, GROUND};
use nalgebra::{Matrix3, Vector3};

const MASS: f64 = 2.0;
const POINT: [f64; 3] = [0.3, 0.2, -0.1];

fn inertia() -> Matrix3<f64> {
    Matrix3::from_diagonal(&Vector3::new(0.3, 0.4, 0.5))
}

/// Body `b` at the origin hanging from ground by a joint of `kind` at POINT (axes along z, or
/// z and x for the kinds whose axes are drawn perpendicular, tilted for the cone). Returns the
/// model and P_j on the body.
fn hanging(kind: JointKind) -> (Model, Vector3<f64>) {
    let info = kind.info();
    let p = Vector3::from(POINT);
    let radial = info
        .blocks
        .contains(&cardan_constraints::joints::Block::RadialDistance);
    let pj = match (info.length, radial) {
        (true, true) => p + Vector3::new(0.5, 0.0, 0.0),
        (true, false) => p + Vector3::new(0.0, 0.0, 0.5),
        _ => p,
    };
    let crossed = matches!(
        kind,
        JointKind::Universal | JointKind::Perpendicular | JointKind::LineInPlane
    );
    let (zj, xj) = if crossed {
        (Vector3::x(), Vector3::y())
    } else if kind == JointKind::Cone {
        // A cone is refused at α = 0: its axes drawn at acos 0.8 ≈ 37°.
        (Vector3::new(0.0, 0.6, 0.8), Vector3::x())
    } else {
        (Vector3::z(), Vector3::x())
    };
    let mut b = MechanismBuilder::new();
    b.body(Body::new("b").mass(MASS).inertia(inertia()));
    b.point(GROUND, "P", p)
        .vector(GROUND, "z", Vector3::z())
        .vector(GROUND, "x", Vector3::x());
    b.point("b", "P", pj)
        .vector("b", "z", zj)
        .vector("b", "x", xj);
    let mut js = JointSpec::new("j", kind, (GROUND, "P"), ("b", "P"));
    if info.axes.accepted() && info.axes.on_j() {
        js = js.axes("z", "z");
        if info.x_axes && kind != JointKind::Universal {
            js = js.x_axes("x", "x");
        }
    } else if info.axes.accepted() {
        js = js.axis_i("z");
        if info.x_axes {
            js = js.x_axis_i("x");
        }
    }
    b.joint(js);
    (b.build().unwrap(), pj)
}

/// The largest Newton and Euler residuals (N, N m) along the run of `kind`.
fn balance(kind: JointKind) -> (f64, f64) {
    let (model, pj_local) = hanging(kind);
    let mut d = Dynamics::new(&model).unwrap();
    let g = Vector3::new(1.5, -2.5, -9.81);
    d.add_force(Force::gravity(g)).unwrap();
    let mut s = d.initial_guess();
    s.set_velocity(
        0,
        Vector3::new(0.2, -0.1, 0.3),
        Vector3::new(0.5, -0.3, 2.0),
    );
    let opts = SimulationOptions::new(0.5, 10)
        .integrator(Integrator::Dopri5(Dopri5Options::tolerances(1e-10, 1e-12)));
    let res = d.simulate(&s, &opts).unwrap();
    let b = res.body("b").unwrap();
    let r = res.joint_reactions("j").unwrap();
    let j = inertia();
    let (mut newton, mut euler): (f64, f64) = (0.0, 0.0);
    for k in 0..res.len() {
        let f = r.on_j[k].force;
        newton = newton.max((MASS * b.r_ddot[k] - MASS * g - f).norm());
        let a = cardan_eulerparam::a(&b.p[k]);
        let (w, wd) = (b.omega_local[k], b.omega_dot_local[k]);
        let lhs = a * (j * wd + w.cross(&(j * w)));
        let arm = a * pj_local;
        euler = euler.max((lhs - r.on_j[k].torque - arm.cross(&f)).norm());
    }
    (newton, euler)
}

#[test]
fn every_kind_s_reactions_balance_the_body_s_newton_euler_equations() {
    let mut bad = Vec::new();
    for info in KINDS {
        let (n, e) = balance(info.kind);
        eprintln!("{:20} Newton {n:.1e} N, Euler {e:.1e} N m", info.name);
        if n > 1e-7 || e > 1e-7 {
            bad.push(format!("{}: Newton {n:.2e}, Euler {e:.2e}", info.name));
        }
    }
    assert!(bad.is_empty(), "{}", bad.join("\n"));
}
