//! Static equilibria and vibration modes against closed forms computed here: a 3D pendulum's
//! small-oscillation frequency, a double pendulum's two frequencies, a chain of masses and
//! springs on slides, a four-bar held by a torsion spring under gravity (equilibrium and
//! frequency from its one-coordinate Lagrangian), a slider-crank's holding torque against the
//! principle of virtual work, and the failures (a free slide, a torque beyond the gravity
//! moment).

mod common;
use cardan_constraints::TimeFunction;
use cardan_dynamics::{
    Dynamics, DynamicsError, Force, Frame, ModalOptions, ModeKind, Stability, StaticOptions,
};
use cardan_mechanism::{
    Body, DriverSpec, JointKind, JointSpec, MechanismBuilder, Model, Orientation, GROUND,
};
use common::G;
use nalgebra::{Matrix2, Vector3};
use std::f64::consts::PI;

fn rot_z(angle: f64) -> Orientation {
    Orientation::AxisAngle {
        axis: Vector3::z(),
        angle,
    }
}

/// A body of mass m, inertia diag `j` about its centre of mass, hanging from a pivot at the
/// origin (axis z) at distance l above its centre of mass, drawn rotated by `alpha` about z.
fn pendulum3d(m: f64, j: [f64; 3], l: f64, alpha: f64) -> Model {
    let mut b = MechanismBuilder::new();
    b.body(
        Body::new("rod")
            .mass(m)
            .inertia_diagonal(j[0], j[1], j[2])
            .position(Vector3::new(l * alpha.sin(), -l * alpha.cos(), 0.0))
            .orientation(rot_z(alpha)),
    );
    b.point(GROUND, "O", Vector3::zeros())
        .vector(GROUND, "z", Vector3::z())
        .vector(GROUND, "x", Vector3::x());
    b.point("rod", "O", Vector3::new(0.0, l, 0.0))
        .vector("rod", "z", Vector3::z())
        .vector("rod", "x", Vector3::x());
    b.joint(
        JointSpec::new("pin", JointKind::Revolute, (GROUND, "O"), ("rod", "O"))
            .axes("z", "z")
            .x_axes("x", "x"),
    );
    b.build().unwrap()
}

/// Pendulum: from 40° and from the horizontal (where its reduced stiffness m g l cos θ is
/// zero), the equilibrium hangs below the pivot, the pin carries the weight, it is stable and
/// its frequency is √(m g l / I_O) / 2π with I_O = J_zz + m l².
#[test]
fn pendulum_equilibrium_and_frequency() {
    let (m, j, l) = (2.0, [0.05, 0.3, 0.25], 0.7);
    let exact = (m * G * l / (j[2] + m * l * l)).sqrt() / (2.0 * PI);
    for alpha in [40f64.to_radians(), 90f64.to_radians()] {
        let model = pendulum3d(m, j, l, alpha);
        let mut d = Dynamics::new(&model).unwrap();
        d.add_force(Force::gravity(Vector3::new(0.0, -G, 0.0)))
            .unwrap();
        let r = d.modal(&ModalOptions::default()).unwrap();
        common::assert_sparse_modal_matches(&mut d, &r);
        let eq = &r.equilibrium.equilibria[0];
        let pos = eq.state.r(0);
        assert!(
            (pos - Vector3::new(0.0, -l, 0.0)).norm() < 1e-9,
            "from {alpha}: {pos}"
        );
        assert_eq!(eq.stability, Stability::Stable);
        let pin = r.equilibrium.results.joint_reactions("pin").unwrap();
        let f = pin.on_j[0].force;
        assert!((f - Vector3::new(0.0, m * G, 0.0)).norm() < 1e-8, "{f}");
        assert_eq!(r.modes.len(), 1);
        let mode = &r.modes[0];
        assert_eq!(mode.kind, ModeKind::Elastic);
        let rel = (mode.frequency - exact).abs() / exact;
        println!(
            "pendulum from {:.0}°: {} Hz vs {} Hz (rel {rel:.2e}), {} iterations",
            alpha.to_degrees(),
            mode.frequency,
            exact,
            eq.iterations
        );
        assert!(rel < 1e-7, "{} vs {exact}", mode.frequency);
        assert!(mode.direction.contains("pin"), "{}", mode.direction);
    }
}

/// Drawn near the inverted position, Newton finds the inverted equilibrium, which is reported
/// unstable along the pin's angle.
#[test]
fn inverted_pendulum_is_unstable() {
    let model = pendulum3d(2.0, [0.05, 0.3, 0.25], 0.7, 175f64.to_radians());
    let mut d = Dynamics::new(&model).unwrap();
    d.add_force(Force::gravity(Vector3::new(0.0, -G, 0.0)))
        .unwrap();
    let r = d.statics(&StaticOptions::default()).unwrap();
    let eq = &r.equilibria[0];
    assert!((eq.state.r(0) - Vector3::new(0.0, 0.7, 0.0)).norm() < 1e-9);
    assert_eq!(eq.stability, Stability::Unstable);
    assert!(eq.eigenvalues[0] < 0.0);
    assert!(
        eq.soft_directions[0].contains("pin"),
        "{:?}",
        eq.soft_directions
    );
}

/// Double pendulum (two bodies on revolutes about z): the two frequencies of
/// det(K − ω² M) = 0 with M = [[I₁ + m₂L₁², m₂L₁c₂], [m₂L₁c₂, I₂]],
/// K = diag((m₁c₁ + m₂L₁) g, m₂c₂g) (I₁, I₂ about the joints).
#[test]
fn double_pendulum_frequencies() {
    let (m1, m2, l1, c1, c2) = (1.5, 0.8, 1.0, 0.45, 0.6);
    let (j1, j2) = (0.12, 0.07);
    let (a1, a2) = (0.3f64, -0.5f64);
    let mut b = MechanismBuilder::new();
    let p1 = Vector3::new(l1 * a1.sin(), -l1 * a1.cos(), 0.0);
    b.body(
        Body::new("upper")
            .mass(m1)
            .inertia_diagonal(0.06, 0.07, j1)
            .position(Vector3::new(c1 * a1.sin(), -c1 * a1.cos(), 0.0))
            .orientation(rot_z(a1)),
    );
    b.body(
        Body::new("lower")
            .mass(m2)
            .inertia_diagonal(0.03, 0.05, j2)
            .position(p1 + Vector3::new(c2 * a2.sin(), -c2 * a2.cos(), 0.0))
            .orientation(rot_z(a2)),
    );
    b.point(GROUND, "O", Vector3::zeros())
        .vector(GROUND, "z", Vector3::z());
    b.point("upper", "top", Vector3::new(0.0, c1, 0.0))
        .point("upper", "bottom", Vector3::new(0.0, c1 - l1, 0.0))
        .vector("upper", "z", Vector3::z());
    b.point("lower", "top", Vector3::new(0.0, c2, 0.0))
        .vector("lower", "z", Vector3::z());
    b.joint(
        JointSpec::new(
            "shoulder",
            JointKind::Revolute,
            (GROUND, "O"),
            ("upper", "top"),
        )
        .axes("z", "z"),
    );
    b.joint(
        JointSpec::new(
            "elbow",
            JointKind::Revolute,
            ("upper", "bottom"),
            ("lower", "top"),
        )
        .axes("z", "z"),
    );
    let model = b.build().unwrap();
    let mut d = Dynamics::new(&model).unwrap();
    d.add_force(Force::gravity(Vector3::new(0.0, -G, 0.0)))
        .unwrap();
    let r = d.modal(&ModalOptions::default()).unwrap();
    common::assert_sparse_modal_matches(&mut d, &r);
    let mm = Matrix2::new(
        j1 + m1 * c1 * c1 + m2 * l1 * l1,
        m2 * l1 * c2,
        m2 * l1 * c2,
        j2 + m2 * c2 * c2,
    );
    let kk = Matrix2::new((m1 * c1 + m2 * l1) * G, 0.0, 0.0, m2 * c2 * G);
    // a ω⁴ − b ω² + c = 0.
    let a = mm.determinant();
    let bq = mm[(0, 0)] * kk[(1, 1)] + mm[(1, 1)] * kk[(0, 0)];
    let cq = kk.determinant();
    let disc = (bq * bq - 4.0 * a * cq).sqrt();
    let w2 = [(bq - disc) / (2.0 * a), (bq + disc) / (2.0 * a)];
    assert_eq!(r.modes.len(), 2);
    for (mode, w2) in r.modes.iter().zip(w2) {
        let exact = w2.sqrt() / (2.0 * PI);
        let rel = (mode.frequency - exact).abs() / exact;
        println!(
            "double pendulum: {} Hz vs {exact} Hz (rel {rel:.2e})",
            mode.frequency
        );
        assert!(rel < 1e-7, "{} vs {exact}", mode.frequency);
    }
    assert_eq!(r.equilibrium.equilibria[0].stability, Stability::Stable);
}

/// A chain of N equal masses on parallel slides joined by N + 1 equal springs between two
/// walls (gravity across the slides): ω_j² = (2k/m)(1 − cos(jπ/(N + 1))), the eigenvalues
/// of the tridiagonal stiffness k·tridiag(−1, 2, −1) over m.
#[test]
fn spring_mass_chain_frequencies() {
    let (n, m, k) = (4usize, 0.7, 130.0);
    let mut b = MechanismBuilder::new();
    b.point(GROUND, "left", Vector3::zeros())
        .point(GROUND, "right", Vector3::new((n + 1) as f64, 0.0, 0.0))
        .vector(GROUND, "x", Vector3::x())
        .vector(GROUND, "y", Vector3::y());
    for i in 0..n {
        let name = format!("m{i}");
        let x = (i + 1) as f64;
        b.body(
            Body::new(&name)
                .mass(m)
                .inertia_diagonal(0.01, 0.02, 0.03)
                .position(Vector3::new(x, 0.0, 0.0)),
        );
        b.point(GROUND, &format!("s{i}"), Vector3::new(x, 0.0, 0.0));
        b.point(&name, "c", Vector3::zeros())
            .vector(&name, "x", Vector3::x())
            .vector(&name, "y", Vector3::y());
        b.joint(
            JointSpec::new(
                format!("slide{i}"),
                JointKind::Prismatic,
                (GROUND, &format!("s{i}")),
                (&name, "c"),
            )
            .axes("x", "x")
            .x_axes("y", "y"),
        );
    }
    let model = b.build().unwrap();
    let mut d = Dynamics::new(&model).unwrap();
    d.add_force(Force::gravity(Vector3::new(0.0, -G, 0.0)))
        .unwrap();
    for i in 0..=n {
        let left = if i == 0 {
            (GROUND.to_string(), "left")
        } else {
            (format!("m{}", i - 1), "c")
        };
        let right = if i == n {
            (GROUND.to_string(), "right")
        } else {
            (format!("m{i}"), "c")
        };
        d.add_force(Force::spring_damper(
            &format!("k{i}"),
            (&left.0, left.1),
            (&right.0, right.1),
            k,
            0.0,
            None,
        ))
        .unwrap();
    }
    let r = d.modal(&ModalOptions::default()).unwrap();
    common::assert_sparse_modal_matches(&mut d, &r);
    assert_eq!(r.modes.len(), n);
    for (j, mode) in r.modes.iter().enumerate() {
        let w2 = 2.0 * k / m * (1.0 - ((j + 1) as f64 * PI / (n + 1) as f64).cos());
        let exact = w2.sqrt() / (2.0 * PI);
        let rel = (mode.frequency - exact).abs() / exact;
        println!(
            "chain mode {j}: {} Hz vs {exact} Hz (rel {rel:.2e})",
            mode.frequency
        );
        assert!(rel < 1e-7, "mode {j}: {} vs {exact}", mode.frequency);
        assert_eq!(mode.kind, ModeKind::Elastic);
        assert!(mode.direction.contains("slide"), "{}", mode.direction);
    }
}

/// Planar four-bar positions in closed form: crank angle θ → (crank tip P, rocker tip Q)
/// for crank a, coupler b, rocker c, ground d (pivots (0,0) and (d,0)), Q on the upper
/// branch.
fn four_bar_points(a: f64, b: f64, c: f64, d: f64, th: f64) -> (Vector3<f64>, Vector3<f64>) {
    let p = Vector3::new(a * th.cos(), a * th.sin(), 0.0);
    let bb = Vector3::new(d, 0.0, 0.0);
    let e = bb - p;
    let dist = e.norm();
    let x = (b * b - c * c + dist * dist) / (2.0 * dist);
    let h = (b * b - x * x).sqrt();
    let u = e / dist;
    let nrm = Vector3::new(-u.y, u.x, 0.0);
    let q = p + u * x + nrm * h;
    (p, q)
}

const FB: (f64, f64, f64, f64) = (0.4, 1.0, 0.8, 1.0);
const FB_MASS: [f64; 3] = [1.0, 2.0, 1.5];

/// The four-bar of [`four_bar_points`] at crank angle θ, uniform rods (mass FB_MASS, centres
/// at the middles), spatial revolutes about z (three redundant rows), x axes at the crank
/// pivot (angle from ground x to crank x).
fn four_bar(th: f64) -> Model {
    let (a, bl, c, dl) = FB;
    let (p, q) = four_bar_points(a, bl, c, dl, th);
    let bpt = Vector3::new(dl, 0.0, 0.0);
    let links = [
        ("crank", Vector3::zeros(), p, a),
        ("coupler", p, q, bl),
        ("rocker", bpt, q, c),
    ];
    let mut b = MechanismBuilder::new();
    for (k, (name, s, e, len)) in links.iter().enumerate() {
        let dir = e - s;
        let ang = dir.y.atan2(dir.x);
        let j = FB_MASS[k] * len * len / 12.0;
        b.body(
            Body::new(*name)
                .mass(FB_MASS[k])
                .inertia_diagonal(1e-3, j, j)
                .position((s + e) / 2.0)
                .orientation(rot_z(ang)),
        );
        b.point(name, "start", Vector3::new(-len / 2.0, 0.0, 0.0))
            .point(name, "end", Vector3::new(len / 2.0, 0.0, 0.0))
            .point(name, "mid", Vector3::zeros())
            .vector(name, "z", Vector3::z())
            .vector(name, "x", Vector3::x());
    }
    b.point(GROUND, "A", Vector3::zeros())
        .point(GROUND, "B", bpt)
        .point(GROUND, "S", Vector3::new(0.5, 1.5, 0.4))
        .vector(GROUND, "z", Vector3::z())
        .vector(GROUND, "x", Vector3::x());
    let rev = |n: &str, i: (&str, &str), j: (&str, &str)| {
        JointSpec::new(n, JointKind::Revolute, i, j).axes("z", "z")
    };
    b.joint(rev("A", (GROUND, "A"), ("crank", "start")).x_axes("x", "x"));
    b.joint(rev("P", ("crank", "end"), ("coupler", "start")));
    b.joint(rev("Q", ("rocker", "end"), ("coupler", "end")));
    b.joint(rev("B", (GROUND, "B"), ("rocker", "start")));
    b.build().unwrap()
}

/// Potential V(θ) = ½ k (θ − θ₀)² + g Σ mᵢ yᵢ(θ) and the generalized inertia
/// I(θ) = Σ mᵢ |drᵢ/dθ|² + Jᵢ (dφᵢ/dθ)² of the four-bar, from the closed form.
fn four_bar_lagrangian(k: f64, th0: f64) -> (impl Fn(f64) -> f64, impl Fn(f64) -> f64) {
    let (a, bl, c, dl) = FB;
    let bpt = Vector3::new(dl, 0.0, 0.0);
    let centres = move |th: f64| {
        let (p, q) = four_bar_points(a, bl, c, dl, th);
        let ang = |v: Vector3<f64>| v.y.atan2(v.x);
        [
            (p / 2.0, th),
            ((p + q) / 2.0, ang(q - p)),
            ((bpt + q) / 2.0, ang(q - bpt)),
        ]
    };
    let v = move |th: f64| {
        let cs = centres(th);
        0.5 * k * (th - th0).powi(2) + G * (0..3).map(|i| FB_MASS[i] * cs[i].0.y).sum::<f64>()
    };
    let inertia = move |th: f64| {
        let h = 1e-6;
        let (cp, cm) = (centres(th + h), centres(th - h));
        let lens = [a, bl, c];
        (0..3)
            .map(|i| {
                let dr = (cp[i].0 - cm[i].0) / (2.0 * h);
                let dphi = (cp[i].1 - cm[i].1) / (2.0 * h);
                FB_MASS[i] * dr.norm_squared() + FB_MASS[i] * lens[i].powi(2) / 12.0 * dphi * dphi
            })
            .sum::<f64>()
    };
    (v, inertia)
}

/// Four-bar held by a torsion spring at the crank pivot under gravity: the equilibrium crank
/// angle solves V'(θ) = 0 and the frequency is √(V''(θ*) / I(θ*)) / 2π, both from the
/// one-coordinate Lagrangian computed here by differences of the closed-form positions. The
/// constraint forces are not zero there, so the geometric stiffness counts.
#[test]
fn four_bar_torsion_spring_equilibrium_and_frequency() {
    let (k, th0) = (20.0, 60f64.to_radians());
    let model = four_bar(th0);
    let mut d = Dynamics::new(&model).unwrap();
    d.add_force(Force::gravity(Vector3::new(0.0, -G, 0.0)))
        .unwrap();
    d.add_force(Force::rotational_spring_damper("spring", "A", k, 0.0, th0))
        .unwrap();
    let r = d.modal(&ModalOptions::default()).unwrap();
    common::assert_sparse_modal_matches(&mut d, &r);
    let (v, inertia) = four_bar_lagrangian(k, th0);
    let h = 1e-4;
    let dv = |th: f64| (v(th + h) - v(th - h)) / (2.0 * h);
    let ddv = |th: f64| (v(th + h) - 2.0 * v(th) + v(th - h)) / (h * h);
    let mut th = th0;
    for _ in 0..50 {
        th -= dv(th) / ddv(th);
    }
    let eq = &r.equilibrium.equilibria[0];
    let crank = eq.state.body_state(0).a * Vector3::x();
    let got = crank.y.atan2(crank.x);
    println!(
        "four-bar equilibrium: {got} rad vs {th} rad (diff {:.2e})",
        got - th
    );
    assert!((got - th).abs() < 1e-7, "{got} vs {th}");
    let exact = (ddv(th) / inertia(th)).sqrt() / (2.0 * PI);
    assert_eq!(r.modes.len(), 1);
    let rel = (r.modes[0].frequency - exact).abs() / exact;
    println!(
        "four-bar frequency: {} Hz vs {exact} Hz (rel {rel:.2e})",
        r.modes[0].frequency
    );
    assert!(rel < 1e-6, "{} vs {exact}", r.modes[0].frequency);
    assert_eq!(eq.stability, Stability::Stable);
    // Redundant rows were dropped and the constraint forces are loaded.
    assert!(!r.equilibrium.results.redundant.is_empty());
    assert!(eq.lambda.iter().any(|l| l.abs() > 1.0));
}

const SC: (f64, f64) = (0.3, 1.0);
const SC_MASS: (f64, f64, f64) = (0.5, 1.2, 2.0);
const SC_FORCE: f64 = -50.0;

/// A slider-crank (crank r, rod l, slider on a slide along x) drawn at crank angle θ, its crank
/// driven by `drive`; with the virtual work per unit crank rotation of the loads of
/// [`add_slider_crank_loads`], F ds/dθ − g Σ mᵢ dyᵢ/dθ, from s(θ) = r cos θ +
/// √(l² − r² sin² θ) differentiated here.
fn slider_crank(th: f64, drive: Option<TimeFunction>) -> (Model, impl Fn(f64) -> f64) {
    let (r, l) = SC;
    let (mc, mr, ms) = SC_MASS;
    let s = move |t: f64| r * t.cos() + (l * l - r * r * t.sin().powi(2)).sqrt();
    let pts = move |t: f64| {
        let p = Vector3::new(r * t.cos(), r * t.sin(), 0.0);
        let q = Vector3::new(s(t), 0.0, 0.0);
        (p, q)
    };
    let (p, q) = pts(th);
    let mut b = MechanismBuilder::new();
    let rod = q - p;
    b.body(
        Body::new("crank")
            .mass(mc)
            .inertia_diagonal(1e-3, 0.01, 0.01)
            .position(p / 2.0)
            .orientation(rot_z(th)),
    );
    b.body(
        Body::new("rod")
            .mass(mr)
            .inertia_diagonal(1e-3, 0.1, 0.1)
            .position((p + q) / 2.0)
            .orientation(rot_z(rod.y.atan2(rod.x))),
    );
    b.body(
        Body::new("slider")
            .mass(ms)
            .inertia_diagonal(0.01, 0.01, 0.01)
            .position(q),
    );
    b.point(GROUND, "O", Vector3::zeros())
        .point(GROUND, "track", Vector3::new(1.0, 0.0, 0.0))
        .vector(GROUND, "z", Vector3::z())
        .vector(GROUND, "x", Vector3::x())
        .vector(GROUND, "y", Vector3::y());
    b.point("crank", "O", Vector3::new(-r / 2.0, 0.0, 0.0))
        .point("crank", "P", Vector3::new(r / 2.0, 0.0, 0.0))
        .vector("crank", "z", Vector3::z())
        .vector("crank", "x", Vector3::x());
    b.point("rod", "P", Vector3::new(-l / 2.0, 0.0, 0.0))
        .point("rod", "Q", Vector3::new(l / 2.0, 0.0, 0.0))
        .vector("rod", "z", Vector3::z());
    b.point("slider", "Q", Vector3::zeros())
        .vector("slider", "z", Vector3::z())
        .vector("slider", "x", Vector3::x())
        .vector("slider", "y", Vector3::y());
    let rev = |n: &str, i: (&str, &str), j: (&str, &str)| {
        JointSpec::new(n, JointKind::Revolute, i, j).axes("z", "z")
    };
    b.joint(rev("O", (GROUND, "O"), ("crank", "O")).x_axes("x", "x"));
    b.joint(rev("P", ("crank", "P"), ("rod", "P")));
    b.joint(rev("Q", ("rod", "Q"), ("slider", "Q")));
    b.joint(
        JointSpec::new(
            "slide",
            JointKind::Prismatic,
            (GROUND, "track"),
            ("slider", "Q"),
        )
        .axes("x", "x")
        .x_axes("y", "y"),
    );
    if let Some(f) = drive {
        b.driver(DriverSpec::rotation("motor", "O", f));
    }
    let work = move |th: f64| {
        let h = 1e-6;
        let (pp, qp) = pts(th + h);
        let (pm, qm) = pts(th - h);
        let dy = |a: f64, b: f64| (a - b) / (2.0 * h);
        SC_FORCE * dy(qp.x, qm.x)
            - G * (mc * dy(pp.y / 2.0, pm.y / 2.0)
                + mr * dy((pp.y + qp.y) / 2.0, (pm.y + qm.y) / 2.0))
    };
    (b.build().unwrap(), work)
}

/// Gravity and the force F along x on the slider.
fn add_slider_crank_loads(d: &mut Dynamics) {
    d.add_force(Force::gravity(Vector3::new(0.0, -G, 0.0)))
        .unwrap();
    d.add_force(Force::point_force(
        "load",
        "slider",
        "Q",
        Vector3::new(SC_FORCE, 0.0, 0.0),
        Frame::Global,
    ))
    .unwrap();
}

/// Slider-crank held by a rotation driver at θ, loaded by a force F on the slider and gravity:
/// the driver's holding torque T satisfies the principle of virtual work
/// T + F ds/dθ − g Σ mᵢ dyᵢ/dθ = 0.
#[test]
fn slider_crank_holding_torque_by_virtual_work() {
    for th in [0.4f64, 1.3, 2.5] {
        let (model, work) = slider_crank(th, Some(TimeFunction::Polynomial(vec![th])));
        let mut d = Dynamics::new(&model).unwrap();
        add_slider_crank_loads(&mut d);
        let res = d.statics(&StaticOptions::default()).unwrap();
        let torque = res.results.driver("motor").unwrap().effort[0];
        let exact = -work(th);
        let rel = (torque - exact).abs() / exact.abs();
        println!(
            "slider-crank θ = {th}: holding torque {torque} vs virtual work {exact} (rel {rel:.2e})"
        );
        assert!(rel < 1e-7, "θ = {th}: {torque} vs {exact}");
    }
}

/// A slider on a slide along x with gravity tilted along it and no spring: no equilibrium,
/// and the error names the slide.
#[test]
fn free_slide_under_load_is_named() {
    let mut b = MechanismBuilder::new();
    b.body(
        Body::new("block")
            .mass(1.0)
            .inertia_diagonal(0.01, 0.01, 0.01),
    );
    b.point(GROUND, "O", Vector3::zeros())
        .vector(GROUND, "x", Vector3::x())
        .vector(GROUND, "y", Vector3::y());
    b.point("block", "O", Vector3::zeros())
        .vector("block", "x", Vector3::x())
        .vector("block", "y", Vector3::y());
    b.joint(
        JointSpec::new("slide", JointKind::Prismatic, (GROUND, "O"), ("block", "O"))
            .axes("x", "x")
            .x_axes("y", "y"),
    );
    let model = b.build().unwrap();
    let mut d = Dynamics::new(&model).unwrap();
    d.add_force(Force::gravity(Vector3::new(1.0, -G, 0.0)))
        .unwrap();
    let e = d.statics(&StaticOptions::default()).unwrap_err();
    match &e {
        DynamicsError::FreeDirection { direction, .. } => {
            assert!(direction.contains("slide"), "{direction}")
        }
        e => panic!("{e}"),
    }
    // Gravity across the slide: a neutral equilibrium, reported as such.
    let mut d = Dynamics::new(&model).unwrap();
    d.add_force(Force::gravity(Vector3::new(0.0, -G, 0.0)))
        .unwrap();
    let r = d.modal(&ModalOptions::default()).unwrap();
    common::assert_sparse_modal_matches(&mut d, &r);
    assert_eq!(r.equilibrium.equilibria[0].stability, Stability::Neutral);
    assert_eq!(r.modes.len(), 1);
    assert_eq!(r.modes[0].kind, ModeKind::Rigid);
}

/// A pendulum (no gravity) held by a zero-length spring of stiffness k from its centre of mass
/// to a ground point at distance H below the pivot, under a torque T about its pin: the
/// spring's moment k l H sin φ is at most k l H, so with T = 2 k l H there is no equilibrium,
/// and the load stepping (the torque is a load, the spring is not scaled) reaches just below
/// the load factor k l H / T = 0.5.
#[test]
fn torque_beyond_the_spring_moment_reports_the_load_factor() {
    let (k, l, h) = (40.0, 0.7, 1.2);
    let model = pendulum3d(2.0, [0.05, 0.3, 0.25], l, 0.0);
    let mut d = Dynamics::new(&model).unwrap();
    d.add_force(Force::spring_damper(
        "spring",
        ("rod", Vector3::zeros()),
        (GROUND, Vector3::new(0.0, -h, 0.0)),
        k,
        0.0,
        Some(0.0),
    ))
    .unwrap();
    let t = 2.0 * k * l * h;
    d.add_force(Force::torque(
        "motor",
        "rod",
        Vector3::new(0.0, 0.0, t),
        Frame::Global,
    ))
    .unwrap();
    let e = d.statics(&StaticOptions::default()).unwrap_err();
    let limit = k * l * h / t;
    match e {
        DynamicsError::NoEquilibrium { load_factor, .. } => {
            println!("load factor reached {load_factor}, limit {limit}");
            assert!(
                load_factor <= limit && load_factor > limit - 0.01,
                "{load_factor}"
            );
        }
        e => panic!("{e}"),
    }
    // Below the limit the equilibrium angle solves k l H sin φ = T.
    let mut d = Dynamics::new(&model).unwrap();
    d.add_force(Force::spring_damper(
        "spring",
        ("rod", Vector3::zeros()),
        (GROUND, Vector3::new(0.0, -h, 0.0)),
        k,
        0.0,
        Some(0.0),
    ))
    .unwrap();
    let t = 0.8 * k * l * h;
    d.add_force(Force::torque(
        "motor",
        "rod",
        Vector3::new(0.0, 0.0, t),
        Frame::Global,
    ))
    .unwrap();
    let r = d.statics(&StaticOptions::default()).unwrap();
    let c = r.equilibria[0].state.r(0);
    let phi = c.x.atan2(-c.y);
    let exact = (t / (k * l * h)).asin();
    println!("spring-held pendulum: φ = {phi} vs {exact}");
    assert!((phi - exact).abs() < 1e-9, "{phi} vs {exact}");
}

/// Quasi-static: the spring-held pendulum of the test above under a torque growing in time,
/// T(t) = 0.9 k l H t (t in [0, 1]): at every output time sin φ = T(t) / (k l H), continued
/// from the previous equilibrium, and the holding of the pin balances the spring.
#[test]
fn quasi_static_follows_a_growing_torque() {
    let (k, l, h) = (40.0, 0.7, 1.2);
    let model = pendulum3d(2.0, [0.05, 0.3, 0.25], l, 0.0);
    let mut d = Dynamics::new(&model).unwrap();
    d.add_force(Force::spring_damper(
        "spring",
        ("rod", Vector3::zeros()),
        (GROUND, Vector3::new(0.0, -h, 0.0)),
        k,
        0.0,
        Some(0.0),
    ))
    .unwrap();
    let tmax = 0.9 * k * l * h;
    d.add_force(Force::torque(
        "motor",
        "rod",
        cardan_dynamics::VectorFunction::function(move |t| Vector3::new(0.0, 0.0, tmax * t)),
        Frame::Global,
    ))
    .unwrap();
    let times: Vec<f64> = (0..=10).map(|i| i as f64 / 10.0).collect();
    let r = d.quasi_statics(&times, &StaticOptions::default()).unwrap();
    assert_eq!(r.results.len(), times.len());
    let body = r.results.body("rod").unwrap();
    for (i, &t) in times.iter().enumerate() {
        let c = body.r[i];
        let phi = c.x.atan2(-c.y);
        let exact = (tmax * t / (k * l * h)).asin();
        assert!((phi - exact).abs() < 1e-9, "t = {t}: {phi} vs {exact}");
        assert_eq!(r.equilibria[i].stability, Stability::Stable);
    }
}

/// Quasi-static slider-crank driven through half a turn, loaded by a force on the slider and
/// gravity: the driver's holding torque at every time against the principle of virtual work.
#[test]
fn quasi_static_slider_crank_holding_torque() {
    let times: Vec<f64> = (0..=12).map(|i| i as f64 / 4.0).collect();
    let (model, work) = slider_crank(0.2, Some(TimeFunction::Polynomial(vec![0.2, 1.0])));
    let mut d = Dynamics::new(&model).unwrap();
    add_slider_crank_loads(&mut d);
    let r = d.quasi_statics(&times, &StaticOptions::default()).unwrap();
    let efforts = &r.results.driver("motor").unwrap().effort;
    for (i, &t) in times.iter().enumerate() {
        let exact = -work(0.2 + t);
        let rel = (efforts[i] - exact).abs() / exact.abs().max(1.0);
        assert!(rel < 1e-7, "t = {t}: {} vs {exact}", efforts[i]);
    }
}
