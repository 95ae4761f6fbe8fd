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

use cardan_constraints::{BodyPair, BodyState, TimeFunction};
use cardan_dynamics::{
    matrix_market, Dynamics, Force, Frame, Input, ModalOptions, Output, State, StaticOptions,
};
use cardan_mechanism::{
    Body, DriverSpec, JointKind, JointSpec, MechanismBuilder, Model, Orientation, GROUND,
};
use nalgebra::{DMatrix, DVector, Vector3};

fn four_bar() -> Model {
    four_bar_builder(false).build().unwrap()
}

/// The four-bar; with `products`, the coupler has products of inertia.
fn four_bar_builder(products: bool) -> MechanismBuilder {
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
        let mut inertia = nalgebra::Matrix3::from_diagonal(&Vector3::new(0.01, j, j + 0.005));
        if products && name == "coupler" {
            for (r, c, v) in [(0, 2, 0.003), (1, 2, -0.002)] {
                inertia[(r, c)] = v;
                inertia[(c, r)] = v;
            }
        }
        b.body(
            Body::new(name)
                .mass(m)
                .inertia(inertia)
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
    b
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
    // About a state at rest in equilibrium the moving-state linearization is the same.
    let moving = d.linearize_moving(&eq.state).unwrap();
    for (a, b) in [
        (&moving.stiffness, &lin.stiffness),
        (&moving.damping, &lin.damping),
        (&moving.mass, &lin.mass),
    ] {
        assert!((a - b).amax() <= 1e-6 * b.amax(), "{a} vs {b}");
    }
    assert_eq!(moving.transport.amax(), 0.0);
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

/// The four-bar of spatial revolutes (three redundant rows) with products of inertia on the
/// coupler and a bob hanging from it on a spherical joint (d = 4, three-dimensional motion).
fn four_bar_with_bob() -> Model {
    let mut b = four_bar_builder(true);
    let mut jb = nalgebra::Matrix3::from_diagonal(&Vector3::new(0.02, 0.03, 0.015));
    jb[(0, 1)] = 0.004;
    jb[(1, 0)] = 0.004;
    let hook = Vector3::new(0.2, 0.0, 0.15);
    let top = Vector3::new(0.1, 0.35, -0.05);
    // The coupler's pose from the plain four-bar (its position and angle).
    let base = four_bar();
    let s = State::initial(&base, 0.0);
    let cb = s.body_state(1);
    let at = cb.r + cb.a * hook - top;
    b.body(Body::new("bob").mass(0.8).inertia(jb).position(at));
    b.point("bob", "top", top).point("coupler", "hook", hook);
    b.joint(JointSpec::new(
        "ball",
        JointKind::Spherical,
        ("coupler", "hook"),
        ("bob", "top"),
    ));
    b.build().unwrap()
}

/// M (n × n) from the masses and inertias.
fn mass_matrix(d: &Dynamics, nb: usize) -> DMatrix<f64> {
    let n = 6 * nb;
    let mut m = DMatrix::zeros(n, n);
    for k in 0..nb {
        for a in 0..3 {
            m[(6 * k + a, 6 * k + a)] = d.mass(k);
            for b in 0..3 {
                m[(6 * k + 3 + a, 6 * k + 3 + b)] = d.inertia(k)[(a, b)];
            }
        }
    }
    m
}

/// The linearization about a moving state (crank turning, bob swinging in 3D) against central
/// differences of the nonlinear accelerations in the body-frame chart (src/moving.rs): with
/// w' = P T₀ δv' the independent velocities (P = M_r⁻¹NᵀM, v' = [Aᵀṙ; ω']), P T₀ v̇' must
/// change by −M_r⁻¹K' along z and −M_r⁻¹C' along w', where C' = C_r − M_r G and
/// K' = K_r − C' G; and G (ż = w' − G z) against central differences in time of z = P T₀ δ'
/// along the two motions. Without the velocity terms (the gyroscopic matrix, the
/// velocity-constraint coupling X, the frame terms, G) the differences are off by far more
/// than 1e-6.
#[test]
fn linearization_about_a_moving_state_matches_the_nonlinear_dynamics() {
    let model = four_bar_with_bob();
    let mut d = loaded(&model, None);
    let nb = model.num_bodies();
    let n = 6 * nb;
    let mut s0 = State::initial(&model, 0.3);
    d.project_positions(&mut s0, 1e-15).unwrap();
    // Some velocity of every body, made consistent.
    for k in 0..nb {
        let f = (k + 1) as f64;
        s0.set_velocity(
            k,
            Vector3::new(0.3 * f, -0.5, 0.2 * f),
            Vector3::new(0.7 - 0.2 * f, 1.1 * f, 2.5 - 0.3 * f),
        );
    }
    d.project_velocities(&mut s0).unwrap();
    assert!(s0.v.iter().map(|x| x.abs()).fold(0.0, f64::max) > 0.5);
    let lin = d.linearize_moving(&s0).unwrap();
    let dof = lin.dof();
    assert_eq!(dof, 4);
    let m = mass_matrix(&d, nb);
    let nbasis = &lin.basis;
    let mr = nbasis.transpose() * &m * nbasis;
    let mr_inv = mr.clone().try_inverse().unwrap();
    let p = &mr_inv * nbasis.transpose() * &m;
    // P T₀ with T₀ = diag(A₀, I) per body: body-frame components to z.
    let mut t0 = DMatrix::zeros(n, n);
    for k in 0..nb {
        let a = s0.body_state(k).a;
        t0.view_mut((6 * k, 6 * k), (3, 3)).copy_from(&a);
        for c in 3..6 {
            t0[(6 * k + c, 6 * k + c)] = 1.0;
        }
    }
    let pt = &p * &t0;
    // Body-frame velocities v' = [Aᵀṙ; ω'] and accelerations [Aᵀr̈ − ω' × v'_r; ω̇'].
    let body_v = |s: &State| {
        let mut out = DVector::zeros(n);
        for k in 0..nb {
            let a = s.body_state(k).a;
            let vr = a.transpose() * s.r_dot(k);
            for c in 0..3 {
                out[6 * k + c] = vr[c];
                out[6 * k + 3 + c] = s.v[6 * k + 3 + c];
            }
        }
        out
    };
    let v0_body = body_v(&s0);
    let w_of = |s: &State| &pt * (body_v(s) - &v0_body);
    let pa = |d: &mut Dynamics, s: &State| {
        let mut vdot = vec![0.0; n];
        let mut lambda = vec![0.0; model.num_equations()];
        d.accelerations(s, &mut vdot, &mut lambda).unwrap();
        let mut out = DVector::zeros(n);
        for k in 0..nb {
            let a = s.body_state(k).a;
            let vr = a.transpose() * s.r_dot(k);
            let ar = a.transpose() * Vector3::from_column_slice(&vdot[6 * k..6 * k + 3])
                - s.omega_local(k).cross(&vr);
            for c in 0..3 {
                out[6 * k + c] = ar[c];
                out[6 * k + 3 + c] = vdot[6 * k + 3 + c];
            }
        }
        &pt * out
    };
    // z of a state relative to the reference r at the same time: P T₀ δ',
    // δ' = [A_rᵀ(r − r_r); log(A_rᵀA)] per body.
    let z_of = |s: &State, r: &State| {
        let mut delta = DVector::zeros(n);
        for k in 0..nb {
            let (a, b) = (s.body_state(k), r.body_state(k));
            // The small rotation from the skew part of A_rᵀA (exact to O(|θ|³)).
            let rel = b.a.transpose() * a.a;
            let th = Vector3::new(
                rel[(2, 1)] - rel[(1, 2)],
                rel[(0, 2)] - rel[(2, 0)],
                rel[(1, 0)] - rel[(0, 1)],
            ) / 2.0;
            let dr = b.a.transpose() * (a.r - b.r);
            for c in 0..3 {
                delta[6 * k + c] = dr[c];
                delta[6 * k + 3 + c] = th[c];
            }
        }
        &pt * delta
    };
    let advance = |s: &State, h: f64| {
        let mut x = s.clone();
        let dq: Vec<f64> = s.v.iter().map(|v| v * h).collect();
        cardan_mechanism::apply_rotation_step(&mut x.q, &dq);
        x
    };
    let eps = 1e-5;
    let h = 1e-5;
    let mut fd_k = DMatrix::zeros(dof, dof);
    let mut fd_c = DMatrix::zeros(dof, dof);
    let mut fd_g = DMatrix::zeros(dof, dof);
    for i in 0..dof {
        let (mut kc, mut cc, mut gc) = (Vec::new(), Vec::new(), Vec::new());
        for sign in [1.0, -1.0] {
            let dz = nbasis.column(i) * (sign * eps);
            let mut s = s0.clone();
            cardan_mechanism::apply_rotation_step(&mut s.q, dz.as_slice());
            d.project_positions(&mut s, 1e-15).unwrap();
            d.project_velocities(&mut s).unwrap();
            // w' = 0 to first order: remove the independent velocity the pose change made.
            let dw = nbasis * w_of(&s);
            for c in 0..n {
                s.v[c] -= dw[c];
            }
            d.project_velocities(&mut s).unwrap();
            kc.push(pa(&mut d, &s));
            let zdot = (z_of(&advance(&s, h), &advance(&s0, h))
                - z_of(&advance(&s, -h), &advance(&s0, -h)))
                / (2.0 * h);
            gc.push(zdot);
            let mut s = s0.clone();
            for c in 0..n {
                s.v[c] += dz[c];
            }
            d.project_velocities(&mut s).unwrap();
            cc.push(pa(&mut d, &s));
        }
        fd_k.set_column(i, &((&kc[0] - &kc[1]) / (2.0 * eps)));
        fd_c.set_column(i, &((&cc[0] - &cc[1]) / (2.0 * eps)));
        fd_g.set_column(i, &(-(&gc[0] - &gc[1]) / (2.0 * eps)));
    }
    let g = &lin.transport;
    let c_body = &lin.damping - &lin.mass * g;
    let k_body = &lin.stiffness - &c_body * g;
    let lin_k = -(&mr_inv * &k_body);
    let lin_c = -(&mr_inv * &c_body);
    let rel = |a: &DMatrix<f64>, b: &DMatrix<f64>| (a - b).amax() / b.amax();
    let (rk, rc, rg) = (rel(&lin_k, &fd_k), rel(&lin_c, &fd_c), rel(g, &fd_g));
    println!("K': rel {rk:.2e}; C': rel {rc:.2e}; G: rel {rg:.2e}");
    assert!(rk < 1e-6, "K: {lin_k} vs {fd_k}: rel {rk:.3e}");
    assert!(rc < 1e-6, "C: {lin_c} vs {fd_c}: rel {rc:.3e}");
    assert!(rg < 1e-6, "G: {g} vs {fd_g}: rel {rg:.3e}");
    // The velocity terms matter here: the equilibrium-style matrices (no gyroscopic matrix,
    // no X, no G) would fail the test by far.
    assert!(g.amax() > 0.1 * lin.mass.amax().min(1.0));
    // Modes of the first-order form: eigenvalues of A, none lost.
    let modes = d.modes(&s0, &lin).unwrap();
    let roots: usize = modes
        .iter()
        .map(|m| if m.kind.name() == "elastic" { 2 } else { 1 })
        .sum();
    assert!(roots >= dof, "{modes:?}");
}

const M_ROD: f64 = 1.2;
const L_C: f64 = 0.5;
const J_C: f64 = 0.1;
const TH0: f64 = -1.0;

/// A rod (mass M_ROD, centre of mass L_C from its pin, inertia J_C about it) pinned at the
/// origin about z, drawn at the angle TH0 of its centre of mass from the x axis; with a
/// rotation driver "motor" holding it at TH0 + 0.1 if `driven`.
fn pendulum(driven: bool) -> Model {
    let (m, lc, jc, th0) = (M_ROD, L_C, J_C, TH0);
    let mut b = MechanismBuilder::new();
    b.body(
        Body::new("rod")
            .mass(m)
            .inertia_diagonal(0.02, jc, jc)
            .position(Vector3::new(lc * th0.cos(), lc * th0.sin(), 0.0))
            .orientation(Orientation::AxisAngle {
                axis: Vector3::z(),
                angle: th0,
            }),
    );
    b.point(GROUND, "O", Vector3::zeros())
        .vector(GROUND, "z", Vector3::z())
        .vector(GROUND, "x", Vector3::x());
    b.point("rod", "O", Vector3::new(-lc, 0.0, 0.0))
        .vector("rod", "z", Vector3::z())
        .vector("rod", "x", Vector3::x());
    b.joint(
        JointSpec::new("O", JointKind::Revolute, (GROUND, "O"), ("rod", "O"))
            .axes("z", "z")
            .x_axes("x", "x"),
    );
    if driven {
        b.driver(DriverSpec::rotation(
            "motor",
            "O",
            TimeFunction::Polynomial(vec![th0 + 0.1]),
        ));
    }
    b.build().unwrap()
}

/// A pendulum held by a rotation driver at its pin; the driver released, its effort an input:
/// the one coordinate's stiffness is −m g l_c sin θ (θ the angle of the centre of mass from
/// the x axis, gravity along −y), its frequency √(K / J_O), and the static gain from the
/// effort to the joint angle, −C A⁻¹ B, the compliance 1 / K.
#[test]
fn driver_effort_input_of_a_held_pendulum() {
    let (m, lc, jc) = (M_ROD, L_C, J_C);
    let model = pendulum(true);
    let mut d = Dynamics::new(&model).unwrap();
    d.add_force(Force::gravity(Vector3::new(0.0, -9.81, 0.0)))
        .unwrap();
    let st = d.statics(&StaticOptions::default()).unwrap();
    let eq = &st.equilibria[0];
    let r = eq.state.r(0);
    let th = r.y.atan2(r.x);
    let k = -m * 9.81 * lc * th.sin();
    let j_o = jc + m * lc * lc;
    assert_eq!(d.linearize(eq).unwrap().dof(), 0);
    let lin = d.linearize_released(eq, &["motor".to_string()]).unwrap();
    assert_eq!(lin.dof(), 1);
    let w2 = lin.stiffness[(0, 0)] / lin.mass[(0, 0)];
    assert!((w2 - k / j_o).abs() < 1e-7 * k / j_o, "{w2} vs {}", k / j_o);
    let ss = d
        .state_space(
            &eq.state,
            &lin,
            &[Input::Driver {
                driver: "motor".into(),
            }],
            &[Output::Joint {
                joint: "O".into(),
                index: 0,
            }],
        )
        .unwrap();
    let gain = -(&ss.c * ss.a.clone().try_inverse().unwrap() * &ss.b)[(0, 0)];
    println!("gain {gain} vs {}", 1.0 / k);
    assert!((gain - 1.0 / k).abs() < 1e-7 / k, "{gain} vs {}", 1.0 / k);
    // Unknown drivers and pose drivers are refused by name.
    let e = d.linearize_released(eq, &["nope".to_string()]).unwrap_err();
    assert!(e.to_string().contains("nope"), "{e}");
}

/// A pendulum swinging at 3 rad/s linearizes as its joint angle does, J_O z̈ = −m g l_c sin θ z
/// (the frame terms of the body-frame chart cancel the centripetal term a fixed direction
/// would see; G = 0 in plane motion), with no damping.
#[test]
fn swinging_pendulum_linearizes_as_its_joint_angle() {
    let model = pendulum(false);
    let mut d = Dynamics::new(&model).unwrap();
    d.add_force(Force::gravity(Vector3::new(0.0, -9.81, 0.0)))
        .unwrap();
    let mut s = State::initial(&model, 0.0);
    d.project_positions(&mut s, 1e-15).unwrap();
    let om = 3.0;
    let r = s.r(0);
    s.set_velocity(0, Vector3::z().cross(&r) * om, Vector3::z() * om);
    d.project_velocities(&mut s).unwrap();
    let lin = d.linearize_moving(&s).unwrap();
    assert_eq!(lin.dof(), 1);
    let th = r.y.atan2(r.x);
    let want = -M_ROD * 9.81 * L_C * th.sin() / (J_C + M_ROD * L_C * L_C);
    let got = lin.stiffness[(0, 0)] / lin.mass[(0, 0)];
    println!("K/M {got} vs {want}");
    assert!((got - want).abs() < 1e-6 * want.abs(), "{got} vs {want}");
    assert!(lin.transport.amax() < 1e-9, "{}", lin.transport);
    assert!(
        lin.damping.amax() < 1e-6 * lin.stiffness.amax(),
        "{}",
        lin.damping
    );
}
