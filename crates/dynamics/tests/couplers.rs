//! Couplers in dynamic runs against closed forms.
//! - Forward dynamics: two gears on ground, a constant torque T on gear 1. The pair moves as one
//!   inertia J₁ + ρ² J₂ (ρ = r₁/r₂): θ₁ = ½ T/(J₁ + ρ² J₂) t², θ₂ = −ρ θ₁ + c, over many turns
//!   with a non-integer ratio, with DOPRI5 and generalized-α.
//! - Forward dynamics of a back-driven screw: a nut of mass m on a prismatic joint falls under
//!   gravity and turns a screw of inertia J through a thread of pitch p: the slide accelerates
//!   at −m g / (m + J (2π/p)²), over many turns of the screw.
//! - Inverse dynamics: gear 1 driven; the motor torque is (J₁ + ρ² J₂) θ̈₁, the coupler's effort
//!   on gear 2 is J₂ θ̈₂ (tooth force J₂ θ̈₂ / r₂), the coupler does no work, and each gear's
//!   forces balance (Newton–Euler: the joint and coupler forces on a gear whose centre is fixed
//!   sum to zero; the torques about its axis to J θ̈).

use cardan_constraints::{JointKind, TimeFunction};
use cardan_dynamics::{
    Dopri5Options, Dynamics, Force, Frame, GeneralizedAlphaOptions, Integrator, SimulationOptions,
};
use cardan_mechanism::{
    Body, CouplerSpec, DriverSpec, GearRatio, JointSpec, KinematicOptions, MechanismBuilder, Model,
    GROUND,
};
use nalgebra::Vector3;
use std::f64::consts::PI;

const R1: f64 = 0.37;
const R2: f64 = 0.81;
const J1: f64 = 0.02;
const J2: f64 = 0.15;

fn gears(driven: bool) -> Model {
    let mut b = MechanismBuilder::new();
    b.vector(GROUND, "z", Vector3::z())
        .vector(GROUND, "x", Vector3::x());
    b.point(GROUND, "A", Vector3::zeros());
    b.point(GROUND, "B", Vector3::new(R1 + R2, 0.0, 0.0));
    for (name, at, j) in [("g1", 0.0, J1), ("g2", R1 + R2, J2)] {
        b.body(
            Body::new(name)
                .position(Vector3::new(at, 0.0, 0.0))
                .mass(1.5)
                .inertia_diagonal(j, j, j),
        );
        b.point(name, "c", Vector3::zeros());
        b.vector(name, "z", Vector3::z())
            .vector(name, "x", Vector3::x());
    }
    for (name, p, g) in [("j1", "A", "g1"), ("j2", "B", "g2")] {
        b.joint(
            JointSpec::new(name, JointKind::Revolute, (GROUND, p), (g, "c"))
                .axes("z", "z")
                .x_axes("x", "x"),
        );
    }
    b.coupler(CouplerSpec::gear(
        "mesh",
        "j1",
        "j2",
        GearRatio::Radii(R1, R2),
    ));
    if driven {
        b.driver(DriverSpec::rotation(
            "motor",
            "j1",
            TimeFunction::Polynomial(vec![0.0, 1.0, 3.0]),
        ));
    }
    b.build().unwrap()
}

/// (largest error of θ₁ against the closed form, of the law θ₂ + ρ θ₁, of the mesh torque).
fn forward(integrator: Integrator) -> (f64, f64, f64) {
    let model = gears(false);
    let torque = 0.5;
    let mut d = Dynamics::new(&model).unwrap();
    d.add_force(Force::torque(
        "T",
        "g1",
        Vector3::new(0.0, 0.0, torque),
        Frame::Global,
    ))
    .unwrap();
    let t_end = 4.0;
    let opts = SimulationOptions::new(t_end, 200).integrator(integrator);
    let res = d.simulate(&d.initial_guess(), &opts).unwrap();
    let rho = R1 / R2;
    let alpha = torque / (J1 + rho * rho * J2);
    let th = |name: &str, k: usize| res.kinematics.joint(name).unwrap().values[k][0];
    let (mut motion, mut law, mut torque_err) = (0.0f64, 0.0f64, 0.0f64);
    for (k, &t) in res.times().iter().enumerate() {
        motion = motion.max((th("j1", k) - 0.5 * alpha * t * t).abs());
        law = law.max((th("j2", k) + rho * th("j1", k)).abs());
        // The mesh torque on gear 2 is J₂ θ̈₂ = −ρ J₂ α.
        let q = res.coupler("mesh").unwrap().efforts[k];
        torque_err = torque_err.max((q[1] + rho * J2 * alpha).abs());
    }
    let turns = 0.5 * alpha * t_end * t_end / (2.0 * PI);
    assert!(turns > 10.0, "{turns} turns");
    (motion, law, torque_err)
}

#[test]
fn forward_dynamics_follows_the_closed_form_over_many_turns() {
    let (motion, law, torque) =
        forward(Integrator::Dopri5(Dopri5Options::tolerances(1e-10, 1e-12)));
    eprintln!("DOPRI5: θ₁ error {motion:.2e} rad, law {law:.2e} rad, mesh torque {torque:.2e} N m");
    assert!(motion < 1e-7 && law < 1e-9 && torque < 1e-9, "DOPRI5");
    let (motion, law, torque) = forward(Integrator::GeneralizedAlpha(
        GeneralizedAlphaOptions::with_step(1e-3),
    ));
    eprintln!(
        "generalized-α: θ₁ error {motion:.2e} rad, law {law:.2e} rad, mesh torque {torque:.2e} N m"
    );
    assert!(
        motion < 1e-3 && law < 1e-8 && torque < 1e-6,
        "generalized-α"
    );
}

#[test]
fn inverse_dynamics_efforts_and_newton_euler_balance() {
    let model = gears(true);
    let mut d = Dynamics::new(&model).unwrap();
    let res = d
        .inverse_dynamics(&KinematicOptions::new(0.0, 2.0, 40))
        .unwrap();
    let rho = R1 / R2;
    let motor = res.driver("motor").unwrap();
    let mesh = res.coupler("mesh").unwrap();
    let j2 = res.joint_reactions("j2").unwrap();
    let mut worst = 0.0f64;
    for (k, &t) in res.times().iter().enumerate() {
        let (thd, thdd) = (1.0 + 6.0 * t, 6.0);
        worst = worst.max((motor.effort[k] - (J1 + rho * rho * J2) * thdd).abs());
        // Effort on gear 2's angle, tooth force, no work.
        worst = worst.max((mesh.efforts[k][1] - J2 * (-rho * thdd)).abs());
        let force = mesh.force.as_ref().unwrap()[k];
        worst = worst.max((force - J2 * (-rho * thdd) / R2).abs());
        worst = worst.max((mesh.efforts[k][0] * thd + mesh.efforts[k][1] * (-rho * thd)).abs());
        // Newton–Euler on gear 2 (body j of the mesh and of j2): forces sum to m a = 0, the
        // torque about z to J₂ θ̈₂.
        let f = mesh.reactions.on_j[k].force + j2.on_j[k].force;
        worst = worst.max(f.norm());
        let tz = mesh.reactions.on_j[k].torque.z + j2.on_j[k].torque.z;
        worst = worst.max((tz - J2 * (-rho * thdd)).abs());
    }
    eprintln!("inverse dynamics with a gear pair: worst error {worst:.2e}");
    assert!(worst < 1e-8, "{worst:e}");
}

#[test]
fn a_back_driven_screw_falls_as_the_closed_form_says() {
    let (m, j, pitch) = (4.0, 2e-3, 0.05);
    let mut b = MechanismBuilder::new();
    b.vector(GROUND, "z", Vector3::z())
        .vector(GROUND, "x", Vector3::x());
    b.point(GROUND, "O", Vector3::zeros())
        .point(GROUND, "N", Vector3::new(0.0, 0.0, 1.0));
    b.body(Body::new("screw").mass(1.0).inertia_diagonal(0.1, 0.1, j));
    b.body(
        Body::new("nut")
            .position(Vector3::new(0.0, 0.0, 1.0))
            .mass(m)
            .inertia_diagonal(0.01, 0.01, 0.02),
    );
    for body in ["screw", "nut"] {
        b.point(body, "c", Vector3::zeros());
        b.vector(body, "z", Vector3::z())
            .vector(body, "x", Vector3::x());
    }
    b.joint(
        JointSpec::new(
            "bearing",
            JointKind::Revolute,
            (GROUND, "O"),
            ("screw", "c"),
        )
        .axes("z", "z")
        .x_axes("x", "x"),
    );
    b.joint(
        JointSpec::new("guide", JointKind::Prismatic, (GROUND, "N"), ("nut", "c"))
            .axes("z", "z")
            .x_axes("x", "x"),
    );
    b.coupler(CouplerSpec::screw("thread", "guide", "bearing", pitch));
    let model = b.build().unwrap();
    let mut d = Dynamics::new(&model).unwrap();
    d.add_force(Force::gravity(Vector3::new(0.0, 0.0, -9.81)))
        .unwrap();
    // Outputs fine enough for the recorded joint angle to be unwrapped between them (44 turns).
    let opts = SimulationOptions::new(2.0, 1000)
        .integrator(Integrator::Dopri5(Dopri5Options::tolerances(1e-10, 1e-12)));
    let res = d.simulate(&d.initial_guess(), &opts).unwrap();
    let lead = pitch / (2.0 * PI);
    let a = -m * 9.81 / (m + j / (lead * lead));
    let (mut slide, mut law) = (0.0f64, 0.0f64);
    for (k, &t) in res.times().iter().enumerate() {
        let s = res.kinematics.joint("guide").unwrap().values[k][0];
        let th = res.kinematics.joint("bearing").unwrap().values[k][0];
        slide = slide.max((s - 0.5 * a * t * t).abs());
        law = law.max((s - lead * th).abs());
    }
    let turns = (0.5 * a * 4.0 / pitch).abs();
    eprintln!("screw: {turns:.1} turns, slide error {slide:.2e} m, law {law:.2e} m");
    assert!(turns > 10.0, "{turns}");
    assert!(slide < 1e-8 && law < 1e-10, "{slide:e} {law:e}");
}
