//! The sparse path of the static and modal analyses on a model above the switch point
//! ([`SPARSE_MIN_BODIES`]): a row of pendulums coupled by springs, drawn swung out, against
//! its closed-form equilibrium and lowest frequencies.

mod common;
use cardan_dynamics::{Dynamics, Force, ModeKind, Stability, StaticOptions, SPARSE_MIN_BODIES};
use cardan_mechanism::{Body, JointKind, JointSpec, MechanismBuilder, Model, Orientation, GROUND};
use common::G;
use nalgebra::Vector3;
use std::f64::consts::PI;

/// `n` pendulums (mass m, inertia J about the centre of mass, centre of mass l below its pin
/// about z), pins a apart along x, neighbouring centres of mass joined by springs of stiffness
/// k and free length a; pendulum i drawn swung out by 0.3 sin(i) rad.
fn coupled_pendulums(n: usize, m: f64, j: f64, l: f64, a: f64) -> Model {
    let mut b = MechanismBuilder::new();
    b.vector(GROUND, "z", Vector3::z())
        .vector(GROUND, "x", Vector3::x());
    for i in 0..n {
        let name = format!("p{i}");
        let alpha = 0.3 * (i as f64).sin();
        let pin = Vector3::new(a * i as f64, 0.0, 0.0);
        b.body(
            Body::new(&name)
                .mass(m)
                .inertia_diagonal(j, j, j)
                .position(pin + Vector3::new(l * alpha.sin(), -l * alpha.cos(), 0.0))
                .orientation(Orientation::AxisAngle {
                    axis: Vector3::z(),
                    angle: alpha,
                }),
        );
        b.point(GROUND, &format!("O{i}"), pin);
        b.point(&name, "O", Vector3::new(0.0, l, 0.0))
            .point(&name, "C", Vector3::zeros())
            .vector(&name, "z", Vector3::z())
            .vector(&name, "x", Vector3::x());
        b.joint(
            JointSpec::new(
                format!("pin{i}"),
                JointKind::Revolute,
                (GROUND, &format!("O{i}")),
                (&name, "O"),
            )
            .axes("z", "z")
            .x_axes("x", "x"),
        );
    }
    b.build().unwrap()
}

/// Hanging straight, the springs at their free length: small swings θ_i obey
/// (J + m l²) θ̈_i = −m g l θ_i − k l² (2θ_i − θ_{i−1} − θ_{i+1}) (free ends), so
/// ω_j² = (m g l + 2 k l² (1 − cos(jπ/n))) / (J + m l²), j = 0, 1, …
/// Gravity along −y and springs (stiffness `k`, damping `c`, free length `a`) between the
/// neighbouring bobs of `coupled_pendulums(n, …, a)`.
fn load_pendulums(d: &mut Dynamics, n: usize, a: f64, k: f64, c: f64) {
    d.add_force(Force::gravity(Vector3::new(0.0, -G, 0.0)))
        .unwrap();
    for i in 0..n - 1 {
        d.add_force(Force::spring_damper(
            &format!("s{i}"),
            (&format!("p{i}"), "C"),
            (&format!("p{}", i + 1), "C"),
            k,
            c,
            Some(a),
        ))
        .unwrap();
    }
}

#[test]
fn coupled_pendulums_equilibrium_and_lowest_frequencies_on_the_sparse_path() {
    let (n, m, j, l, a, k) = (SPARSE_MIN_BODIES, 1.0, 0.01, 0.5, 1.0, 1e4);
    let model = coupled_pendulums(n, m, j, l, a);
    let mut d = Dynamics::new(&model).unwrap();
    assert!(d.sparse_path());
    load_pendulums(&mut d, n, a, k, 0.0);
    let exact: Vec<f64> = (0..6)
        .map(|i| {
            let s = 1.0 - (i as f64 * PI / n as f64).cos();
            (m * G * l + 2.0 * k * l * l * s) / (j + m * l * l)
        })
        .collect();
    let r = d.modal_sparse(&StaticOptions::default(), 6).unwrap();
    let eq = &r.equilibrium.equilibria[0];
    for i in 0..n {
        let want = Vector3::new(a * i as f64, -l, 0.0);
        assert!(
            (eq.state.r(i) - want).norm() < 1e-9,
            "{i}: {}",
            eq.state.r(i)
        );
    }
    assert_eq!(eq.stability, Stability::Stable);
    assert!(r.converged);
    assert_eq!(eq.eigenvalues.len(), 6);
    for (i, w2) in exact.iter().enumerate() {
        let f = w2.sqrt() / (2.0 * PI);
        let mode = &r.modes[i];
        assert_eq!(mode.kind, ModeKind::Elastic);
        let rel = (mode.frequency - f).abs() / f;
        let rel_eq = (eq.eigenvalues[i] - w2).abs() / w2;
        println!(
            "mode {i}: {} Hz vs {f} Hz (rel {rel:.1e}), ω² rel {rel_eq:.1e}",
            mode.frequency
        );
        assert!(rel < 1e-8 && rel_eq < 1e-8, "{} vs {f}", mode.frequency);
    }
    println!(
        "{} Newton iterations, {} Lanczos steps",
        eq.iterations, r.lanczos_steps
    );
}

/// The sparse path's linearization (M-orthonormal basis from the saddle-point factorization)
/// against the dense one (SVD basis) on a small row of coupled pendulums: a different basis,
/// the same physics. N spans the null space of Φ_v (Φ_v N = 0, NᵀMN = I), the eigenvalues
/// of (K_r, M_r) are the dense path's, and so is the static gain −C A⁻¹ B of a state-space
/// model (force on the first pendulum, displacement of the fourth), which does not depend on
/// the basis.
#[test]
fn sparse_linearization_is_the_dense_one_in_another_basis() {
    use cardan_dynamics::{Input, ModalOptions, Output};
    let (n, m, j, l, a, k) = (6, 1.0, 0.01, 0.5, 1.0, 50.0);
    let model = coupled_pendulums(n, m, j, l, a);
    let forces = |d: &mut Dynamics| load_pendulums(d, n, a, k, 0.3);
    let mut ds = Dynamics::new(&model).unwrap();
    forces(&mut ds);
    let r = ds.modal_sparse(&StaticOptions::default(), n).unwrap();
    let eq = r.equilibrium.equilibria[0].clone();
    let lin = ds.linearize_sparse(&eq, &r.stiffness, &r.damping).unwrap();
    let full = ds.linearization_matrices(&eq.state).unwrap();
    assert_eq!(lin.dof(), n);
    assert_eq!(full.jacobian.rows, 5 * n);
    let jn = {
        let mut jd = nalgebra::DMatrix::zeros(full.jacobian.rows, full.jacobian.cols);
        for &(r, c, v) in &full.jacobian.entries {
            jd[(r, c)] = v;
        }
        jd * &lin.basis
    };
    assert!(jn.amax() < 1e-12, "Φ_v N: {}", jn.amax());
    let eye = nalgebra::DMatrix::<f64>::identity(n, n);
    assert!((&lin.mass - eye).amax() < 1e-12, "NᵀMN − I");
    let mt = full.mass.to_dense();
    let mn = lin.basis.transpose() * mt * &lin.basis;
    assert!(
        (&mn - &lin.mass).amax() < 1e-12,
        "M of linearization_matrices"
    );

    let mut dd = Dynamics::new(&model).unwrap();
    forces(&mut dd);
    let dense = dd.modal(&ModalOptions::default()).unwrap();
    let deq = &dense.equilibrium.equilibria[0];
    // Undamped eigenvalues of both reduced pencils.
    let eig = |lin: &cardan_dynamics::Linearization| {
        let l = lin.mass.clone().cholesky().unwrap().l();
        let li = l.clone().try_inverse().unwrap();
        let mut w: Vec<f64> = (&li * &lin.stiffness * li.transpose())
            .symmetric_eigen()
            .eigenvalues
            .iter()
            .copied()
            .collect();
        w.sort_by(f64::total_cmp);
        w
    };
    let (ws, wd) = (eig(&lin), eig(&dense.linearization));
    for (a, b) in ws.iter().zip(&wd) {
        assert!((a - b).abs() < 1e-8 * b.abs(), "ω² {a} vs {b}");
    }
    let input = [Input::Force {
        body: "p0".into(),
        point: Vector3::zeros(),
        direction: Vector3::x(),
    }];
    let output = [Output::Point {
        body: "p3".into(),
        point: Vector3::zeros(),
        direction: Vector3::x(),
    }];
    let gain = |d: &mut Dynamics, state, lin| {
        let ss = d.state_space(state, lin, &input, &output).unwrap();
        let x = ss.a.clone().lu().solve(&ss.b).unwrap();
        -(&ss.c * x)[(0, 0)]
    };
    let gs = gain(&mut ds, &eq.state, &lin);
    let gd = gain(&mut dd, &deq.state, &dense.linearization);
    println!("static gain: sparse {gs:e}, dense {gd:e}");
    assert!(
        gd.abs() > 1e-6 && (gs - gd).abs() < 1e-8 * gd.abs(),
        "{gs} vs {gd}"
    );
}
