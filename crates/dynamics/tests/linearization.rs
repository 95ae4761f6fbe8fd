//! The linearization about an equilibrium against central differences of the nonlinear
//! equations of motion, on a 3D model with redundant joints: a four-bar of spatial revolutes
//! (three redundant rows) under a gravity with components along all axes (the out-of-plane part
//! loads the redundant rows), with a torsion spring-damper at the crank pivot and an
//! out-of-plane translational spring-damper from the coupler to ground.
//!
//! For each independent coordinate z_i: the pose q₀ ⊕ (±ε N e_i) projected back onto Φ = 0
//! (least change in the metric of M, which leaves z = M_r⁻¹NᵀM δ unchanged to first order),
//! at rest; the nonlinear accelerations v̇ of the augmented system give
//! z̈ = M_r⁻¹NᵀM v̇, and (z̈₊ − z̈₋)/2ε must equal column i of −M_r⁻¹K_r. Likewise with
//! velocities ±ε N e_i at q₀ for −M_r⁻¹C_r (the quadratic velocity terms cancel in the
//! central difference).

use cardan_constraints::{BodyPair, BodyState};
use cardan_dynamics::{matrix_market, Dynamics, Force, Frame, Input, ModalOptions, Output, State};
use cardan_mechanism::{Body, JointKind, JointSpec, MechanismBuilder, Model, Orientation, GROUND};
use nalgebra::{DMatrix, DVector, Vector3};

fn four_bar() -> Model {
    let (a, bl, c, dl) = (0.4, 1.0, 0.8, 1.0);
    let th = 1.0f64;
    let p = Vector3::new(a * th.cos(), a * th.sin(), 0.0);
    let bpt = Vector3::new(dl, 0.0, 0.0);
    let e = bpt - p;
    let dist = e.norm();
    let x = (bl * bl - c * c + dist * dist) / (2.0 * dist);
    let h = (bl * bl - x * x).sqrt();
    let u = e / dist;
    let q = p + u * x + Vector3::new(-u.y, u.x, 0.0) * h;
    let links = [
        ("crank", Vector3::zeros(), p, a, 1.0),
        ("coupler", p, q, bl, 2.0),
        ("rocker", bpt, q, c, 1.5),
    ];
    let mut b = MechanismBuilder::new();
    for (name, s, e, len, m) in links {
        let dir = e - s;
        let j = m * len * len / 12.0;
        b.body(
            Body::new(name)
                .mass(m)
                .inertia_diagonal(0.01, j, j + 0.005)
                .position((s + e) / 2.0)
                .orientation(Orientation::AxisAngle {
                    axis: Vector3::z(),
                    angle: dir.y.atan2(dir.x),
                }),
        );
        b.point(name, "start", Vector3::new(-len / 2.0, 0.0, 0.0))
            .point(name, "end", Vector3::new(len / 2.0, 0.0, 0.0))
            .point(name, "mid", Vector3::new(0.0, 0.05, 0.1))
            .vector(name, "z", Vector3::z())
            .vector(name, "x", Vector3::x());
    }
    b.point(GROUND, "A", Vector3::zeros())
        .point(GROUND, "B", bpt)
        .point(GROUND, "S", Vector3::new(0.5, 1.5, 0.6))
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

/// The model's forces, plus a constant force `extra` at the coupler's point "mid" if given.
fn loaded(model: &Model, extra: Option<Vector3<f64>>) -> Dynamics<'_> {
    let mut d = Dynamics::new(model).unwrap();
    d.add_force(Force::gravity(Vector3::new(1.5, -9.81, 2.0)))
        .unwrap();
    d.add_force(Force::rotational_spring_damper(
        "torsion", "A", 25.0, 0.4, 1.0,
    ))
    .unwrap();
    d.add_force(Force::spring_damper(
        "tie",
        ("coupler", "mid"),
        (GROUND, "S"),
        300.0,
        3.0,
        Some(0.9),
    ))
    .unwrap();
    if let Some(f) = extra {
        d.add_force(Force::point_force(
            "probe",
            "coupler",
            "mid",
            f,
            Frame::Global,
        ))
        .unwrap();
    }
    d
}

#[test]
fn linearization_matches_differences_of_the_nonlinear_dynamics() {
    let model = four_bar();
    let mut d = loaded(&model, None);
    let r = d.modal(&ModalOptions::default()).unwrap();
    let eq = &r.equilibrium.equilibria[0];
    assert!(
        !r.equilibrium.results.redundant.is_empty(),
        "redundant rows"
    );
    let lin = &r.linearization;
    assert_eq!(lin.dof(), 1);
    let nb = model.num_bodies();
    let n = 6 * nb;
    // M, built here from the masses and inertias.
    let mut m = DMatrix::zeros(n, n);
    for k in 0..nb {
        for a in 0..3 {
            m[(6 * k + a, 6 * k + a)] = d.mass(k);
            for b in 0..3 {
                m[(6 * k + 3 + a, 6 * k + 3 + b)] = d.inertia(k)[(a, b)];
            }
        }
    }
    let nbasis = &lin.basis;
    let mr = nbasis.transpose() * &m * nbasis;
    assert!((&mr - &lin.mass).amax() <= 1e-12 * mr.amax());
    let mr_inv = mr.clone().try_inverse().unwrap();
    let zdd = |d: &mut Dynamics, s: &State| {
        let mut vdot = vec![0.0; n];
        let mut lambda = vec![0.0; model.num_equations()];
        d.accelerations(s, &mut vdot, &mut lambda).unwrap();
        &mr_inv * nbasis.transpose() * &m * DVector::from_vec(vdot)
    };
    let dof = lin.dof();
    let eps = 1e-5;
    let mut fd_k = DMatrix::zeros(dof, dof);
    let mut fd_c = DMatrix::zeros(dof, dof);
    for i in 0..dof {
        let mut cols = Vec::new();
        let mut ccols = Vec::new();
        for sign in [1.0, -1.0] {
            let dz = nbasis.column(i) * (sign * eps);
            let mut s = eq.state.clone();
            cardan_mechanism::apply_rotation_step(&mut s.q, dz.as_slice());
            d.project_positions(&mut s, 1e-15).unwrap();
            cols.push(zdd(&mut d, &s));
            let mut s = eq.state.clone();
            s.v.copy_from_slice(dz.as_slice());
            ccols.push(zdd(&mut d, &s));
        }
        fd_k.set_column(i, &((&cols[0] - &cols[1]) / (2.0 * eps)));
        fd_c.set_column(i, &((&ccols[0] - &ccols[1]) / (2.0 * eps)));
    }
    let lin_k = -(&mr_inv * &lin.stiffness);
    let lin_c = -(&mr_inv * &lin.damping);
    let rel_k = (&lin_k - &fd_k).amax() / fd_k.amax();
    let rel_c = (&lin_c - &fd_c).amax() / fd_c.amax();
    println!(
        "−M⁻¹K: {lin_k} vs {fd_k} (rel {rel_k:.2e}); −M⁻¹C: {lin_c} vs {fd_c} (rel {rel_c:.2e})"
    );
    assert!(rel_k < 1e-6, "K: rel {rel_k:.3e}");
    assert!(rel_c < 1e-6, "C: rel {rel_c:.3e}");
    // The damped mode: ω_n² = K_r/M_r, ζ = C_r / (2 √(K_r M_r)) for one coordinate.
    let (kr, cr, mm) = (lin.stiffness[(0, 0)], lin.damping[(0, 0)], lin.mass[(0, 0)]);
    let wn = (kr / mm).sqrt();
    let zeta = cr / (2.0 * (kr * mm).sqrt());
    let mode = &r.modes[0];
    assert!((mode.frequency - wn / (2.0 * std::f64::consts::PI)).abs() < 1e-9 * wn);
    assert!(
        (mode.damping_ratio - zeta).abs() < 1e-9,
        "{} vs {zeta}",
        mode.damping_ratio
    );
}

/// The state-space model: B against the accelerations a small force at the input produces
/// (exactly linear at rest), C against central differences of the point coordinate and the
/// joint angle along the constraint manifold; the MatrixMarket text reads back.
#[test]
fn state_space_matches_the_nonlinear_model() {
    let model = four_bar();
    let mut d = loaded(&model, None);
    let r = d.modal(&ModalOptions::default()).unwrap();
    let eq = &r.equilibrium.equilibria[0];
    let lin = &r.linearization;
    let dir = Vector3::new(0.3, -1.0, 0.2).normalize();
    let mid = Vector3::new(0.0, 0.05, 0.1);
    let inputs = [Input::Force {
        body: "coupler".into(),
        point: mid,
        direction: dir,
    }];
    let outputs = [
        Output::Point {
            body: "rocker".into(),
            point: Vector3::new(0.4, 0.0, 0.0),
            direction: Vector3::x(),
        },
        Output::Joint {
            joint: "A".into(),
            index: 0,
        },
    ];
    let ss = d.state_space(&eq.state, lin, &inputs, &outputs).unwrap();
    let dof = lin.dof();
    let n = 6 * model.num_bodies();
    let mut m = DMatrix::zeros(n, n);
    for k in 0..model.num_bodies() {
        for a in 0..3 {
            m[(6 * k + a, 6 * k + a)] = d.mass(k);
            for b in 0..3 {
                m[(6 * k + 3 + a, 6 * k + 3 + b)] = d.inertia(k)[(a, b)];
            }
        }
    }
    let nb = &lin.basis;
    let mr_inv = (nb.transpose() * &m * nb).try_inverse().unwrap();
    let acc = |d: &mut Dynamics| {
        let mut vdot = vec![0.0; n];
        let mut lambda = vec![0.0; model.num_equations()];
        d.accelerations(&eq.state, &mut vdot, &mut lambda).unwrap();
        DVector::from_vec(vdot)
    };
    let eps = 1e-3;
    let v0 = acc(&mut d);
    let mut d2 = loaded(&model, Some(dir * eps));
    let v1 = acc(&mut d2);
    let fd_b = &mr_inv * nb.transpose() * &m * (v1 - v0) / eps;
    let b = ss.b.view((dof, 0), (dof, 1)).into_owned();
    let rel_b = (&b - &fd_b).amax() / fd_b.amax();
    println!("B: {b} vs {fd_b} (rel {rel_b:.2e})");
    assert!(rel_b < 1e-7, "B rel {rel_b:.3e}");
    // C by central differences along the manifold.
    let ys = |s: &State| {
        let rk = model.body_id("rocker").unwrap();
        let p = s.point_position(rk, &Vector3::new(0.4, 0.0, 0.0));
        let j = &model.joints()[model.joint_index("A").unwrap()];
        let (g, c) = (BodyState::ground(), s.body_state(0));
        let angle = j.joint.coordinates(&BodyPair::new(&g, &c)).values[0];
        [p.x, angle]
    };
    let e = 1e-5;
    for i in 0..dof {
        let mut y = Vec::new();
        for sign in [1.0, -1.0] {
            let dz = nb.column(i) * (sign * e);
            let mut s = eq.state.clone();
            cardan_mechanism::apply_rotation_step(&mut s.q, dz.as_slice());
            d.project_positions(&mut s, 1e-15).unwrap();
            y.push(ys(&s));
        }
        for o in 0..2 {
            let fd = (y[0][o] - y[1][o]) / (2.0 * e);
            let got = ss.c[(o, i)];
            println!("C[{o}, {i}]: {got} vs {fd}");
            assert!(
                (got - fd).abs() < 1e-7 * fd.abs().max(1e-3),
                "{got} vs {fd}"
            );
        }
    }
    assert_eq!(ss.d.shape(), (2, 1));
    assert!(ss.c.view((0, dof), (2, dof)).iter().all(|&v| v == 0.0));
    // MatrixMarket round trip.
    let text = matrix_market(&ss.a);
    let mut lines = text.lines();
    assert_eq!(
        lines.next(),
        Some("%%MatrixMarket matrix coordinate real general")
    );
    let dims: Vec<usize> = lines
        .next()
        .unwrap()
        .split_whitespace()
        .map(|x| x.parse().unwrap())
        .collect();
    assert_eq!(&dims[..2], &[2 * dof, 2 * dof]);
    let mut back = DMatrix::zeros(dims[0], dims[1]);
    for l in lines {
        let f: Vec<&str> = l.split_whitespace().collect();
        let (r, c): (usize, usize) = (f[0].parse().unwrap(), f[1].parse().unwrap());
        back[(r - 1, c - 1)] = f[2].parse::<f64>().unwrap();
    }
    assert_eq!(back, ss.a);
}
