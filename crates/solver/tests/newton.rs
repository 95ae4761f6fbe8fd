//! Newton-Raphson: known answers, modified Newton, line search from rough guesses, redundant
//! mechanisms in the 7- and 6-coordinate forms, scale invariance, velocity and acceleration,
//! typed errors, and the property that Newton returns to a solution from a perturbed start.

mod common;

use cardan_solver::{
    AutoSolver, DenseLu, JacobianUpdate, LineSearch, LinearSolver, MinNormQr, Newton,
    NewtonOptions, NonFiniteLocation, NonlinearSystem, RankAnalysis, RankOptions, SolverChoice,
    SolverError, SolverKind, SparseLu, SparsityPattern,
};
use common::{FourBar, FourBar6, Rng};
use proptest::prelude::*;

/// x² + y² + z² = 14, xyz = 6, x + y = z: solution (1, 2, 3) near the start used below.
struct Cubic;
impl NonlinearSystem for Cubic {
    fn num_equations(&self) -> usize {
        3
    }
    fn num_unknowns(&self) -> usize {
        3
    }
    fn residual(&mut self, x: &[f64], out: &mut [f64]) {
        out[0] = x[0] * x[0] + x[1] * x[1] + x[2] * x[2] - 14.0;
        out[1] = x[0] * x[1] * x[2] - 6.0;
        out[2] = x[0] + x[1] - x[2];
    }
    fn jacobian(&mut self, x: &[f64], s: &mut [f64]) {
        s.copy_from_slice(&[
            2.0 * x[0],
            2.0 * x[1],
            2.0 * x[2],
            x[1] * x[2],
            x[0] * x[2],
            x[0] * x[1],
            1.0,
            1.0,
            -1.0,
        ]);
    }
}
fn cubic_pattern() -> SparsityPattern {
    SparsityPattern::new(
        3,
        3,
        &[
            (0, 0),
            (0, 1),
            (0, 2),
            (1, 0),
            (1, 1),
            (1, 2),
            (2, 0),
            (2, 1),
            (2, 2),
        ],
    )
    .unwrap()
}

#[test]
fn known_answer_converges_quadratically() {
    let mut newton = Newton::new(
        &cubic_pattern(),
        AutoSolver::default(),
        NewtonOptions::default(),
    )
    .unwrap();
    let mut x = [1.2, 1.7, 3.3];
    let report = newton.solve(&mut Cubic, &mut x).unwrap();
    for (got, want) in x.iter().zip([1.0, 2.0, 3.0]) {
        assert!((got - want).abs() < 1e-12, "{x:?}");
    }
    assert!(report.iterations <= 6, "{report:?}");
    assert!(report.residual_norm <= 1e-10);
    // Full Newton: one factorization per iteration plus the one at the solution.
    assert_eq!(report.refactorizations, report.iterations + 1);
    assert!(newton.factorization_is_current());
}

#[test]
fn modified_newton_saves_factorizations() {
    let options = NewtonOptions {
        jacobian_update: JacobianUpdate::Modified {
            max_age: 30,
            min_contraction: 0.5,
        },
        factor_at_solution: false,
        ..NewtonOptions::default()
    };
    let mut newton = Newton::new(&cubic_pattern(), AutoSolver::default(), options).unwrap();
    let mut x = [1.02, 1.98, 3.01];
    let report = newton.solve(&mut Cubic, &mut x).unwrap();
    assert!((x[1] - 2.0).abs() < 1e-10, "{x:?}");
    assert!(report.refactorizations < report.iterations, "{report:?}");
    // The factorization is kept for the next solve (time stepping): no refactorization if the
    // next start is close enough.
    let mut y = [1.0 + 1e-4, 2.0 - 1e-4, 3.0];
    let again = newton.solve(&mut Cubic, &mut y).unwrap();
    assert_eq!(again.refactorizations, 0, "{again:?}");
    assert!((y[0] - 1.0).abs() < 1e-10);
}

/// atan(x) = 0 from x₀ = 3: undamped Newton diverges, backtracking converges.
struct Atan;
impl NonlinearSystem for Atan {
    fn num_equations(&self) -> usize {
        1
    }
    fn num_unknowns(&self) -> usize {
        1
    }
    fn residual(&mut self, x: &[f64], out: &mut [f64]) {
        out[0] = x[0].atan();
    }
    fn jacobian(&mut self, x: &[f64], s: &mut [f64]) {
        s[0] = 1.0 / (1.0 + x[0] * x[0]);
    }
}

#[test]
fn line_search_assembles_from_a_rough_guess() {
    let p = SparsityPattern::dense(1, 1);
    let plain = NewtonOptions {
        line_search: LineSearch::None,
        ..NewtonOptions::default()
    };
    let mut newton = Newton::new(&p, DenseLu::new(), plain).unwrap();
    let mut x = [3.0];
    let err = newton.solve(&mut Atan, &mut x).unwrap_err();
    // Undamped, the iterates overflow: the typed error is whichever symptom comes first.
    assert!(
        matches!(
            err,
            SolverError::NotConverged { .. }
                | SolverError::NonFinite { .. }
                | SolverError::Singular { .. }
        ),
        "{err}"
    );

    let mut newton = Newton::new(&p, DenseLu::new(), NewtonOptions::default()).unwrap();
    let mut x = [3.0];
    let report = newton.solve(&mut Atan, &mut x).unwrap();
    assert!(
        x[0].abs() < 1e-10 && report.damped_steps > 0,
        "{x:?} {report:?}"
    );

    // A step cap alone also works.
    let capped = NewtonOptions {
        line_search: LineSearch::None,
        max_step: Some(0.5),
        ..NewtonOptions::default()
    };
    let mut newton = Newton::new(&p, DenseLu::new(), capped).unwrap();
    let mut x = [3.0];
    newton.solve(&mut Atan, &mut x).unwrap();
    assert!(x[0].abs() < 1e-10);
}

fn perturbed(q: &[f64], amount: f64, rng: &mut Rng) -> Vec<f64> {
    q.iter().map(|v| v + amount * rng.sym()).collect()
}

fn max_diff(a: &[f64], b: &[f64]) -> f64 {
    a.iter()
        .zip(b)
        .fold(0.0f64, |m, (x, y)| m.max((x - y).abs()))
}

#[test]
fn redundant_four_bar_converges_with_min_norm_and_with_rows_dropped() {
    let p = FourBar::pattern();
    let mut fb = FourBar::new(1.0, 0.9);
    let q_star = fb.assembled();
    let mut rng = Rng(42);

    // (a) Rank-revealing solver on the 24 × 21 system (Auto picks it for a rectangular pattern).
    let mut newton = Newton::new(&p, AutoSolver::default(), NewtonOptions::default()).unwrap();
    assert_eq!(newton.linear_solver().kind(), Some(SolverKind::MinNorm));
    let mut q = perturbed(&q_star, 0.05, &mut rng);
    let report = newton.solve(&mut fb, &mut q).unwrap();
    assert!(max_diff(&q, &q_star) < 1e-10, "{report:?}");
    assert_eq!(report.rank, Some(21));
    assert_eq!(report.redundant_equations, 3);

    // (b) Plain LU fails with the dependent equations named.
    let square_rows: Vec<usize> = (0..21).collect();
    let sel = p.select_rows(&square_rows).unwrap();
    let mut lu =
        Newton::with_row_selection(&p, sel, DenseLu::new(), NewtonOptions::default()).unwrap();
    // At the assembled configuration the 21 rows are dependent (off it they are not, and LU would
    // simply take poor steps): factoring there reports the dependent equations.
    let mut q = q_star.clone();
    match lu.solve(&mut fb, &mut q) {
        Err(SolverError::Singular {
            dependent_equations,
        }) => {
            assert_eq!(dependent_equations.len(), 3, "{dependent_equations:?}");
            let message = SolverError::Singular {
                dependent_equations: dependent_equations.clone(),
            }
            .to_string();
            assert!(
                message.contains(&format!("#{}", dependent_equations[0])),
                "{message}"
            );
        }
        other => panic!("expected Singular, got {other:?}"),
    }

    // (c) Decide the redundant rows once at the assembled configuration, drop them, use sparse LU.
    let mut slots = vec![0.0; p.num_slots()];
    fb.jacobian(&q_star, &mut slots);
    let analysis = RankAnalysis::compute(&p, &slots, RankOptions::default()).unwrap();
    let sel = p.select_rows(analysis.independent_rows()).unwrap();
    let mut fast =
        Newton::with_row_selection(&p, sel, SparseLu::new(), NewtonOptions::default()).unwrap();
    for theta in [0.9, 1.0, 1.1, 1.2] {
        // Time stepping: the previous solution is the next starting point.
        fb.theta = theta;
        let want = fb.assembled();
        let report = fast.solve(&mut fb, &mut q).unwrap();
        assert!(max_diff(&q, &want) < 1e-10, "θ = {theta}: {report:?}");
        assert_eq!(report.redundant_equations, 3);
    }
}

#[test]
fn six_coordinate_form_with_rotation_update() {
    let p = FourBar6::pattern();
    let mut fb = FourBar6::new(FourBar::new(1.0, 0.6));
    let q_star = fb.inner.assembled();
    let mut rng = Rng(9);
    let mut q = perturbed(&q_star, 0.02, &mut rng);
    // Re-normalize the perturbed Euler parameters: the 6-coordinate form keeps |p| = 1 itself.
    for b in 0..3 {
        let n = q[7 * b + 3..7 * b + 7]
            .iter()
            .map(|v| v * v)
            .sum::<f64>()
            .sqrt();
        q[7 * b + 3..7 * b + 7].iter_mut().for_each(|v| *v /= n);
    }
    let mut newton = Newton::new(&p, AutoSolver::default(), NewtonOptions::default()).unwrap();
    let report = newton.solve(&mut fb, &mut q).unwrap();
    assert!(
        max_diff(&q, &q_star) < 1e-10,
        "{report:?}\n{q:?}\n{q_star:?}"
    );
    assert_eq!(report.redundant_equations, 3);
    for b in 0..3 {
        let n: f64 = q[7 * b + 3..7 * b + 7].iter().map(|v| v * v).sum();
        assert!((n - 1.0).abs() < 1e-14);
    }
    // Velocity in the 6-coordinate form: v = [ṙ; ω']; crank angular velocity ω'_z = θ̇.
    let theta_dot = 2.0;
    let mut nu = vec![0.0; FourBar6::M];
    nu[20] = theta_dot;
    let mut v = vec![0.0; FourBar6::N];
    newton.solve_linear(&nu, &mut v).unwrap();
    assert!((v[5] - theta_dot).abs() < 1e-10, "{v:?}");
    assert!(v[3].abs() < 1e-10 && v[4].abs() < 1e-10);
}

#[test]
fn millimetres_and_kilometres_converge_alike() {
    let p = FourBar::pattern();
    let mut runs = Vec::new();
    for scale in [1e-3, 1.0, 1e3, 1e6] {
        let mut fb = FourBar::new(scale, 1.3);
        let q_star = fb.assembled();
        // The same relative perturbation at every scale.
        let mut rng = Rng(77);
        let mut q = q_star.clone();
        for b in 0..3 {
            for k in 0..7 {
                let unit = if k < 3 { scale } else { 1.0 };
                q[7 * b + k] += 0.03 * unit * rng.sym();
            }
        }
        let mut newton = Newton::new(&p, AutoSolver::default(), NewtonOptions::default()).unwrap();
        let report = newton.solve(&mut fb, &mut q).unwrap();
        let err = (0..21)
            .map(|i| (q[i] - q_star[i]).abs() / if i % 7 < 3 { scale } else { 1.0 })
            .fold(0.0f64, f64::max);
        assert!(err < 1e-10, "scale {scale}: {err}");
        runs.push(report.iterations);
    }
    assert!(
        runs.windows(2).all(|w| w[0] == w[1]),
        "iterations per scale {runs:?}"
    );
}

#[test]
fn velocity_and_acceleration_reuse_the_position_factorization() {
    // Crank angle θ(t) = ω t: ν = −Φ_t (ω in the driver row), γ# = −(Φ_q q̇)_q q̇ (the driver's
    // Φ_qt q̇ and Φ_tt vanish on the solution). Compare with finite differences of the
    // closed-form assembly.
    let p = FourBar::pattern();
    let (theta, omega) = (0.7, 1.5);
    let mut fb = FourBar::new(2.0, theta);
    let mut q = fb.assembled();
    let mut newton = Newton::new(&p, AutoSolver::default(), NewtonOptions::default()).unwrap();
    let report = newton.solve(&mut fb, &mut q).unwrap();
    assert_eq!(report.iterations, 0);
    assert!(newton.factorization_is_current());

    let mut nu = vec![0.0; FourBar::M];
    nu[23] = omega;
    let mut qd = vec![0.0; FourBar::N];
    newton.solve_linear(&nu, &mut qd).unwrap();

    let h = 1e-5;
    let at = |t: f64| FourBar::new(2.0, t).assembled();
    let (qp, qm) = (at(theta + h), at(theta - h));
    for i in 0..21 {
        let fd = (qp[i] - qm[i]) / (2.0 * h) * omega;
        assert!((qd[i] - fd).abs() < 1e-7, "q̇[{i}] {} vs {fd}", qd[i]);
    }

    // γ# by differentiating Φ_q q̇ along q̇ (central differences), plus −Φ_tt of the driver.
    let mut jp = vec![0.0; p.num_slots()];
    let mut jm = vec![0.0; p.num_slots()];
    let e = 1e-6;
    let qpe: Vec<f64> = q.iter().zip(&qd).map(|(a, b)| a + e * b).collect();
    let qme: Vec<f64> = q.iter().zip(&qd).map(|(a, b)| a - e * b).collect();
    fb.jacobian(&qpe, &mut jp);
    fb.jacobian(&qme, &mut jm);
    let (mut yp, mut ym) = (vec![0.0; FourBar::M], vec![0.0; FourBar::M]);
    p.mul_vec(&jp, &qd, &mut yp).unwrap();
    p.mul_vec(&jm, &qd, &mut ym).unwrap();
    let gamma: Vec<f64> = yp
        .iter()
        .zip(&ym)
        .map(|(a, b)| -(a - b) / (2.0 * e))
        .collect();
    let mut qdd = vec![0.0; FourBar::N];
    newton.solve_linear(&gamma, &mut qdd).unwrap();
    let q0 = at(theta);
    let h = 1e-4;
    for i in 0..21 {
        let fd = (qp_at(&at, theta, h, i) - 2.0 * q0[i] + qm_at(&at, theta, h, i)) / (h * h)
            * omega
            * omega;
        assert!(
            (qdd[i] - fd).abs() < 1e-4 * (1.0 + fd.abs()),
            "q̈[{i}] {} vs {fd}",
            qdd[i]
        );
    }
}

fn qp_at(at: &dyn Fn(f64) -> Vec<f64>, t: f64, h: f64, i: usize) -> f64 {
    at(t + h)[i]
}
fn qm_at(at: &dyn Fn(f64) -> Vec<f64>, t: f64, h: f64, i: usize) -> f64 {
    at(t - h)[i]
}

/// One equation in two unknowns, x² + y² = 1 (assembly of an under-driven system).
struct Circle;
impl NonlinearSystem for Circle {
    fn num_equations(&self) -> usize {
        1
    }
    fn num_unknowns(&self) -> usize {
        2
    }
    fn residual(&mut self, x: &[f64], out: &mut [f64]) {
        out[0] = x[0] * x[0] + x[1] * x[1] - 1.0;
    }
    fn jacobian(&mut self, x: &[f64], s: &mut [f64]) {
        s.copy_from_slice(&[2.0 * x[0], 2.0 * x[1]]);
    }
}

#[test]
fn underdetermined_assembly_takes_minimum_norm_steps() {
    // From (2, 1) the minimum-norm steps go along the gradient: the point moves radially onto
    // the circle, to (2, 1)/√5, the closest point.
    let p = SparsityPattern::dense(1, 2);
    let mut newton = Newton::new(&p, AutoSolver::default(), NewtonOptions::default()).unwrap();
    assert_eq!(newton.linear_solver().kind(), Some(SolverKind::MinNorm));
    let mut x = [2.0, 1.0];
    let report = newton.solve(&mut Circle, &mut x).unwrap();
    let s5 = 5f64.sqrt();
    assert!(
        (x[0] - 2.0 / s5).abs() < 1e-10 && (x[1] - 1.0 / s5).abs() < 1e-10,
        "{x:?}"
    );
    assert_eq!(report.rank, Some(1));
    assert_eq!(report.redundant_equations, 0);
}

/// Broyden's tridiagonal function, n = 3000 (sparse path): (3 − 2xᵢ)xᵢ − xᵢ₋₁ − 2xᵢ₊₁ + 1 = 0.
struct Broyden(usize);
impl NonlinearSystem for Broyden {
    fn num_equations(&self) -> usize {
        self.0
    }
    fn num_unknowns(&self) -> usize {
        self.0
    }
    fn residual(&mut self, x: &[f64], out: &mut [f64]) {
        let n = self.0;
        for i in 0..n {
            let l = if i > 0 { x[i - 1] } else { 0.0 };
            let r = if i + 1 < n { x[i + 1] } else { 0.0 };
            out[i] = (3.0 - 2.0 * x[i]) * x[i] - l - 2.0 * r + 1.0;
        }
    }
    fn jacobian(&mut self, x: &[f64], s: &mut [f64]) {
        // slots: for each i: (i, i−1), (i, i), (i, i+1) where present
        let mut k = 0;
        for i in 0..self.0 {
            if i > 0 {
                s[k] = -1.0;
                k += 1;
            }
            s[k] = 3.0 - 4.0 * x[i];
            k += 1;
            if i + 1 < self.0 {
                s[k] = -2.0;
                k += 1;
            }
        }
    }
}
fn broyden_pattern(n: usize) -> SparsityPattern {
    let mut e = Vec::new();
    for i in 0..n {
        if i > 0 {
            e.push((i, i - 1));
        }
        e.push((i, i));
        if i + 1 < n {
            e.push((i, i + 1));
        }
    }
    SparsityPattern::new(n, n, &e).unwrap()
}

#[test]
fn large_sparse_system_converges() {
    let n = 3000;
    let p = broyden_pattern(n);
    let mut newton = Newton::new(&p, AutoSolver::default(), NewtonOptions::default()).unwrap();
    assert_eq!(newton.linear_solver().kind(), Some(SolverKind::Sparse));
    let mut x = vec![-1.0; n];
    let report = newton.solve(&mut Broyden(n), &mut x).unwrap();
    assert!(
        report.residual_norm < 1e-10 && report.iterations < 10,
        "{report:?}"
    );
}

#[test]
fn failures_are_typed_and_readable() {
    let p = cubic_pattern();
    // Iteration cap.
    let options = NewtonOptions {
        max_iterations: 1,
        ..NewtonOptions::default()
    };
    let mut newton = Newton::new(&p, AutoSolver::default(), options).unwrap();
    let mut x = [1.4, 1.6, 2.5];
    match newton.solve(&mut Cubic, &mut x) {
        Err(e @ SolverError::NotConverged { .. }) => {
            let SolverError::NotConverged {
                iterations,
                ref residual_history,
                ref worst_equations,
            } = e
            else {
                unreachable!()
            };
            assert_eq!(iterations, 1);
            assert_eq!(residual_history.len(), 2);
            assert!(
                !worst_equations.is_empty()
                    && worst_equations[0].1 >= worst_equations.last().unwrap().1
            );
            let msg = e.to_string();
            assert!(
                msg.contains("after 1 iterations")
                    && msg.contains(&format!("#{}", worst_equations[0].0)),
                "{msg}"
            );
        }
        other => panic!("{other:?}"),
    }
    // Wrong state length.
    let mut newton = Newton::new(&p, AutoSolver::default(), NewtonOptions::default()).unwrap();
    assert!(matches!(
        newton.solve(&mut Cubic, &mut [1.0, 2.0]),
        Err(SolverError::DimensionMismatch {
            expected: 3,
            found: 2,
            ..
        })
    ));
    // NaN residual.
    struct Nan;
    impl NonlinearSystem for Nan {
        fn num_equations(&self) -> usize {
            2
        }
        fn num_unknowns(&self) -> usize {
            2
        }
        fn residual(&mut self, x: &[f64], out: &mut [f64]) {
            out[0] = x[0] - 1.0;
            out[1] = (x[1] - 2.0).sqrt();
        }
        fn jacobian(&mut self, _x: &[f64], s: &mut [f64]) {
            s.copy_from_slice(&[1.0, 0.0, 0.0, 1.0]);
        }
    }
    let mut newton = Newton::new(
        &SparsityPattern::dense(2, 2),
        AutoSolver::default(),
        NewtonOptions::default(),
    )
    .unwrap();
    let err = newton.solve(&mut Nan, &mut [0.0, 0.0]).unwrap_err();
    assert_eq!(
        err,
        SolverError::NonFinite {
            location: NonFiniteLocation::Residual { equation: 1 },
            iteration: Some(0)
        }
    );
    /// Factors nothing, solves to zero.
    #[derive(Debug)]
    struct Blind(usize);
    impl LinearSolver for Blind {
        fn analyze(&mut self, _: &SparsityPattern) -> Result<(), SolverError> {
            Ok(())
        }
        fn factor(&mut self, _: &[f64]) -> Result<(), SolverError> {
            Ok(())
        }
        fn solve(&mut self, _: &[f64], x: &mut [f64]) -> Result<(), SolverError> {
            x.fill(0.0);
            Ok(())
        }
        fn nrows(&self) -> usize {
            self.0
        }
        fn ncols(&self) -> usize {
            self.0
        }
        fn name(&self) -> &'static str {
            "blind"
        }
    }
    // A non-finite Jacobian entry is named by slot, row and column, with the iteration: with
    // every row solved (the check is folded into the copy to the solver), and with a row
    // selection whose dropped row holds the bad entry (not copied, checked all the same).
    struct BadJacobian {
        value: f64,
    }
    impl NonlinearSystem for BadJacobian {
        fn num_equations(&self) -> usize {
            3
        }
        fn num_unknowns(&self) -> usize {
            2
        }
        fn residual(&mut self, x: &[f64], out: &mut [f64]) {
            out.copy_from_slice(&[x[0] - 1.0, x[1] - 2.0, x[0] + x[1] - 3.0]);
        }
        // Slots (column-major dense): (0,0) (1,0) (2,0) (0,1) (1,1) (2,1).
        fn jacobian(&mut self, _x: &[f64], s: &mut [f64]) {
            s.copy_from_slice(&[1.0, 0.0, 1.0, 0.0, 1.0, self.value]);
        }
    }
    let p3 = SparsityPattern::dense(3, 2);
    for (value, selected) in [
        (f64::NAN, false),
        (f64::INFINITY, false),
        (f64::NAN, true),
        (f64::NEG_INFINITY, true),
    ] {
        let mut system = BadJacobian { value };
        let err = if selected {
            let sel = p3.select_rows(&[0, 1]).unwrap();
            Newton::with_row_selection(&p3, sel, SparseLu::new(), NewtonOptions::default())
                .unwrap()
                .solve(&mut system, &mut [0.0, 0.0])
        } else {
            // A linear solver that never looks at the values: the error must be Newton's own.
            Newton::new(&p3, Blind(2), NewtonOptions::default())
                .unwrap()
                .solve(&mut system, &mut [0.0, 0.0])
        }
        .unwrap_err();
        assert_eq!(
            err,
            SolverError::NonFinite {
                location: NonFiniteLocation::Jacobian {
                    slot: 5,
                    row: 2,
                    col: 1
                },
                iteration: Some(1)
            },
            "value {value}, row selection {selected}"
        );
    }
    // The same system with a finite entry solves, with and without the selection.
    let mut newton = Newton::with_row_selection(
        &p3,
        p3.select_rows(&[0, 1]).unwrap(),
        SparseLu::new(),
        NewtonOptions::default(),
    )
    .unwrap();
    let mut x = [0.0, 0.0];
    newton
        .solve(&mut BadJacobian { value: 1.0 }, &mut x)
        .unwrap();
    assert!(
        (x[0] - 1.0).abs() < 1e-14 && (x[1] - 2.0).abs() < 1e-14,
        "{x:?}"
    );
    // Velocity before any factorization.
    let mut newton = Newton::new(&p, AutoSolver::default(), NewtonOptions::default()).unwrap();
    assert!(matches!(
        newton.solve_linear(&[0.0; 3], &mut [0.0; 3]),
        Err(SolverError::NotReady { .. })
    ));
    // A row selection made from another pattern.
    let other = SparsityPattern::dense(3, 3).select_rows(&[0, 2]).unwrap();
    assert!(matches!(
        Newton::with_row_selection(&p, other, DenseLu::new(), NewtonOptions::default()),
        Err(SolverError::InvalidRowSelection { .. }) | Err(SolverError::NotSquare { .. })
    ));
    let other = SparsityPattern::dense(3, 3)
        .select_rows(&[0, 1, 2])
        .unwrap();
    assert!(matches!(
        Newton::with_row_selection(&p, other, DenseLu::new(), NewtonOptions::default()),
        Err(SolverError::InvalidRowSelection { .. })
    ));
    // LU on a rectangular pattern.
    assert!(matches!(
        Newton::new(
            &FourBar::pattern(),
            AutoSolver::new(SolverChoice::Dense),
            NewtonOptions::default()
        ),
        Err(SolverError::NotSquare {
            nrows: 24,
            ncols: 21
        })
    ));
}

/// Φ(x) = A x + 0.3 sin(x) − b with A diagonally dominant: a unique solution x*.
struct Mildly {
    a: Vec<f64>, // dense column-major
    b: Vec<f64>,
    n: usize,
}
impl NonlinearSystem for Mildly {
    fn num_equations(&self) -> usize {
        self.n
    }
    fn num_unknowns(&self) -> usize {
        self.n
    }
    fn residual(&mut self, x: &[f64], out: &mut [f64]) {
        for i in 0..self.n {
            out[i] = 0.3 * x[i].sin() - self.b[i]
                + (0..self.n)
                    .map(|j| self.a[i + self.n * j] * x[j])
                    .sum::<f64>();
        }
    }
    fn jacobian(&mut self, x: &[f64], s: &mut [f64]) {
        s.copy_from_slice(&self.a);
        for i in 0..self.n {
            s[i + self.n * i] += 0.3 * x[i].cos();
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(48))]

    /// Started from a perturbed solution, Newton returns to it (random mildly nonlinear systems,
    /// dense and sparse LU, full and modified Newton).
    #[test]
    fn newton_returns_to_the_solution(seed in 1u64.., n in 1usize..30, amount in 0.0f64..0.5, modified: bool, sparse: bool) {
        let mut rng = Rng(seed);
        let mut a = vec![0.0; n * n];
        for j in 0..n {
            for i in 0..n {
                a[i + n * j] = 0.5 * rng.sym() / n as f64 + if i == j { 2.0 } else { 0.0 };
            }
        }
        let x_star: Vec<f64> = (0..n).map(|_| 2.0 * rng.sym()).collect();
        let mut sys = Mildly { a, b: vec![0.0; n], n };
        let mut r = vec![0.0; n];
        sys.residual(&x_star, &mut r);
        sys.b = r;
        let options = NewtonOptions {
            jacobian_update: if modified { JacobianUpdate::Modified { max_age: 5, min_contraction: 0.3 } } else { JacobianUpdate::EveryIteration },
            ..NewtonOptions::default()
        };
        let choice = if sparse { SolverChoice::Sparse } else { SolverChoice::Dense };
        let mut newton = Newton::new(&SparsityPattern::dense(n, n), AutoSolver::new(choice), options).unwrap();
        let mut x = perturbed(&x_star, amount, &mut rng);
        let report = newton.solve(&mut sys, &mut x).unwrap();
        prop_assert!(max_diff(&x, &x_star) < 1e-9, "{:?}", report);
    }

    /// The redundant four-bar returns to its assembled configuration (same crank angle) from a
    /// perturbed one, for any crank angle.
    #[test]
    fn four_bar_returns_to_its_assembly(seed in 1u64.., theta in -3.0f64..3.0, amount in 0.0f64..0.02) {
        let p = FourBar::pattern();
        let mut fb = FourBar::new(1.0, theta);
        let q_star = fb.assembled();
        let mut rng = Rng(seed);
        let mut q = perturbed(&q_star, amount, &mut rng);
        let mut newton = Newton::new(&p, MinNormQr::new(), NewtonOptions::default()).unwrap();
        let report = newton.solve(&mut fb, &mut q).unwrap();
        prop_assert!(max_diff(&q, &q_star) < 1e-9, "{:?}", report);
        prop_assert_eq!(newton.linear_solver().rank(), Some(21));
    }
}

fn chord_options() -> NewtonOptions {
    NewtonOptions {
        jacobian_update: JacobianUpdate::Modified {
            max_age: 4,
            min_contraction: 0.3,
        },
        factor_at_solution: false,
        ..NewtonOptions::default()
    }
}

/// The chord iteration keeps the last factorization from a good start and refactors when the
/// start is bad (poor contraction), converging to the same accuracy either way.
#[test]
fn chord_iteration_refactors_when_the_start_is_bad() {
    let mut newton = Newton::new(&cubic_pattern(), AutoSolver::default(), chord_options()).unwrap();
    let mut x = [1.02, 1.98, 3.01];
    newton.solve(&mut Cubic, &mut x).unwrap();
    // Good start: chord steps with the kept factorization only.
    let mut good = [1.0 + 1e-5, 2.0 - 1e-5, 3.0];
    let r = newton.solve(&mut Cubic, &mut good).unwrap();
    assert_eq!(r.refactorizations, 0, "{r:?}");
    // Bad start: the kept factorization contracts poorly, so Newton refactors.
    let mut bad = [1.4, 1.5, 3.4];
    let r = newton.solve(&mut Cubic, &mut bad).unwrap();
    assert!(r.refactorizations >= 1, "{r:?}");
    for x in [good, bad] {
        for (g, w) in x.iter().zip([1.0, 2.0, 3.0]) {
            assert!((g - w).abs() < 1e-12, "{x:?}");
        }
    }
}

/// A chord step passes the step test only when the error it leaves, θ/(1 − θ) ‖Δ‖, is below
/// τ_step² (1e-12 by default), the error full Newton leaves after a step of τ_step.
#[test]
fn chord_iteration_meets_the_squared_step_tolerance() {
    let mut full = Newton::new(
        &cubic_pattern(),
        AutoSolver::default(),
        NewtonOptions::default(),
    )
    .unwrap();
    let mut chord = Newton::new(&cubic_pattern(), AutoSolver::default(), chord_options()).unwrap();
    let mut x = [1.0, 2.0, 3.0];
    chord.factor_at(&mut Cubic, &x).unwrap();
    for k in 1..20 {
        let d = 1e-3 * k as f64;
        let start = [1.0 + d, 2.0 - 0.5 * d, 3.0 + 0.3 * d];
        let (mut a, mut b) = (start, start);
        full.solve(&mut Cubic, &mut a).unwrap();
        chord.solve(&mut Cubic, &mut b).unwrap();
        for (p, q) in a.iter().zip(&b) {
            // Both within a few τ_step² of the solution.
            assert!((p - q).abs() < 1e-11, "{a:?} vs {b:?}");
        }
        x = b;
    }
    assert!((x[2] - 3.0).abs() < 1e-12);
}

/// `solve_linear_at` after a solve that ended away from its factorization (chord steps or a
/// last Newton step) gives the solution of a fresh factorization at the solution, to rounding.
#[test]
fn solve_linear_at_matches_a_fresh_factorization() {
    let mut newton = Newton::new(&cubic_pattern(), AutoSolver::default(), chord_options()).unwrap();
    let mut fresh = Newton::new(
        &cubic_pattern(),
        AutoSolver::default(),
        NewtonOptions::default(),
    )
    .unwrap();
    let rhs = [0.3, -1.7, 2.5];
    for start in [
        [1.02, 1.98, 3.01],
        [1.0 + 1e-6, 2.0, 3.0 - 1e-6],
        [1.3, 1.6, 3.2],
    ] {
        let mut x = start;
        newton.solve(&mut Cubic, &mut x).unwrap();
        let mut v = [0.0; 3];
        newton
            .solve_linear_at(&mut Cubic, &x, &rhs, &mut v)
            .unwrap();
        // The same factors serve a second right-hand side.
        let mut w = [0.0; 3];
        newton.solve_linear_at(&mut Cubic, &x, &v, &mut w).unwrap();
        fresh.factor_at(&mut Cubic, &x).unwrap();
        let (mut v_ref, mut w_ref) = ([0.0; 3], [0.0; 3]);
        fresh.solve_linear(&rhs, &mut v_ref).unwrap();
        fresh.solve_linear(&v, &mut w_ref).unwrap();
        for (a, b) in v.iter().zip(&v_ref).chain(w.iter().zip(&w_ref)) {
            assert!(
                (a - b).abs() <= 1e-12 * b.abs().max(1.0),
                "{v:?} {v_ref:?} {w:?} {w_ref:?}"
            );
        }
    }
}

/// A stiff string of `n` nodes: `2 x_i − x_{i−1} − x_{i+1} + α x_i³ = b_i` (ends fixed at 0).
/// Its Jacobian, the 1-D Laplacian plus a small diagonal, has condition number about n²: the
/// shape of a long chain's Φ_q.
struct String1d {
    n: usize,
    alpha: f64,
}

impl String1d {
    fn pattern(&self) -> SparsityPattern {
        let mut e = Vec::new();
        for i in 0..self.n {
            if i > 0 {
                e.push((i, i - 1));
            }
            e.push((i, i));
            if i + 1 < self.n {
                e.push((i, i + 1));
            }
        }
        SparsityPattern::new(self.n, self.n, &e).unwrap()
    }
}

impl NonlinearSystem for String1d {
    fn num_equations(&self) -> usize {
        self.n
    }
    fn num_unknowns(&self) -> usize {
        self.n
    }
    fn residual(&mut self, x: &[f64], out: &mut [f64]) {
        let n = self.n;
        for i in 0..n {
            let l = if i > 0 { x[i - 1] } else { 0.0 };
            let r = if i + 1 < n { x[i + 1] } else { 0.0 };
            out[i] = 2.0 * x[i] - l - r + self.alpha * x[i].powi(3) - 1.0 / n as f64;
        }
    }
    fn jacobian(&mut self, x: &[f64], s: &mut [f64]) {
        let mut k = 0;
        for i in 0..self.n {
            if i > 0 {
                s[k] = -1.0;
                k += 1;
            }
            s[k] = 2.0 + 3.0 * self.alpha * x[i] * x[i];
            k += 1;
            if i + 1 < self.n {
                s[k] = -1.0;
                k += 1;
            }
        }
    }
}

/// On an ill-conditioned system (α tiny: κ ≈ 1e5, the Laplacian's) the refinement of
/// `solve_linear_at` stalls at corrections of a few hundred ε ‖v‖ while the backward error of
/// `v` is already at rounding level: it must accept that solution (as good as a fresh
/// factorization's) rather than refactor. The factors are made 2e-6 from the solution, so the
/// chord steps drift less than [`cardan_solver::REFINE_MAX_DRIFT`].
#[test]
fn solve_linear_at_accepts_a_backward_stable_refinement_of_an_ill_conditioned_system() {
    let mut sys = String1d {
        n: 600,
        alpha: 1e-9,
    };
    let pattern = sys.pattern();
    let mut x = vec![0.0; sys.n];
    let mut exact = Newton::new(&pattern, SparseLu::new(), NewtonOptions::default()).unwrap();
    exact.solve(&mut sys, &mut x).unwrap();
    let mut newton = Newton::new(&pattern, SparseLu::new(), chord_options()).unwrap();
    let mut start: Vec<f64> = x.iter().map(|v| v + 2e-6).collect();
    newton.factor_at(&mut sys, &start).unwrap();
    let report = newton.solve(&mut sys, &mut start).unwrap();
    assert!(
        report.iterations >= 1,
        "the start already solved the system"
    );
    assert!(!newton.factorization_is_current(), "the solve refactored");
    let rhs: Vec<f64> = (0..sys.n).map(|i| ((i % 7) as f64 - 3.0) * 1e-3).collect();
    let mut v = vec![0.0; sys.n];
    newton
        .solve_linear_at(&mut sys, &start, &rhs, &mut v)
        .unwrap();
    assert!(
        !newton.factorization_is_current(),
        "refined to the backward error of a fresh factorization, but refactored anyway"
    );
    // The factorization made by factor_at served the chord steps and the refinement.
    assert_eq!(newton.factorization_count(), 1);
    exact.factor_at(&mut sys, &start).unwrap();
    let mut v_ref = vec![0.0; sys.n];
    exact.solve_linear(&rhs, &mut v_ref).unwrap();
    let scale = v_ref.iter().fold(0.0f64, |m, a| m.max(a.abs()));
    for (a, b) in v.iter().zip(&v_ref) {
        // Both are backward stable: they agree to about κ ε.
        assert!((a - b).abs() <= 1e-9 * scale, "{a} {b} (scale {scale})");
    }
}

/// x = 1, y = 2, x + y = 3 + ε: redundant and slightly inconsistent (issue 22).
struct Inconsistent(f64);
impl NonlinearSystem for Inconsistent {
    fn num_equations(&self) -> usize {
        3
    }
    fn num_unknowns(&self) -> usize {
        2
    }
    fn residual(&mut self, x: &[f64], out: &mut [f64]) {
        out[0] = x[0] - 1.0;
        out[1] = x[1] - 2.0;
        out[2] = x[0] + x[1] - 3.0 - self.0;
    }
    // slots: (0,0), (1,1), (2,0), (2,1)
    fn jacobian(&mut self, _x: &[f64], s: &mut [f64]) {
        s.copy_from_slice(&[1.0, 1.0, 1.0, 1.0]);
    }
}

/// With the last row dropped, Newton judges all rows by default (the dropped row of a
/// consistent system holds too), so an inconsistency of 1e-7 does not converge; judged on the
/// kept rows it solves them exactly and leaves the dropped row its 1e-7.
#[test]
fn kept_rows_only_solves_an_inconsistent_redundant_system_on_its_kept_rows() {
    let p = SparsityPattern::new(3, 2, &[(0, 0), (1, 1), (2, 0), (2, 1)]).unwrap();
    let sel = p.select_rows(&[0, 1]).unwrap();
    let mut newton =
        Newton::with_row_selection(&p, sel, DenseLu::new(), NewtonOptions::default()).unwrap();
    let mut x = [0.5, 0.5];
    assert!(matches!(
        newton.solve(&mut Inconsistent(1e-7), &mut x),
        Err(SolverError::NotConverged { .. })
    ));
    assert!(!newton.judges_kept_rows_only());
    newton.judge_kept_rows_only(true);
    assert!(newton.judges_kept_rows_only());
    let mut x = [0.5, 0.5];
    let rep = newton.solve(&mut Inconsistent(1e-7), &mut x).unwrap();
    assert_eq!(x, [1.0, 2.0]);
    assert_eq!(rep.residual_norm, 0.0);
    let mut out = [0.0; 3];
    Inconsistent(1e-7).residual(&x, &mut out);
    assert!((out[2] + 1e-7).abs() < 1e-15, "{out:?}");
}
