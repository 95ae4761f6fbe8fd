//! Rank-deficient systems with known redundancy, and the minimum-norm solver.

mod common;

use cardan_solver::{
    LinearSolver, MinNormQr, NonlinearSystem, RankAnalysis, RankOptions, SparsityPattern,
};
use common::{FourBar, FourBar6, Rng};
use proptest::prelude::*;

/// m × n dense matrix (column-major slots of `SparsityPattern::dense`) whose rows `dependent`
/// are random combinations of the other rows, with row magnitudes spread over `spread` decades.
fn deficient(m: usize, n: usize, dependent: &[usize], spread: i32, rng: &mut Rng) -> Vec<f64> {
    let mut rows: Vec<Vec<f64>> = (0..m)
        .map(|_| (0..n).map(|_| rng.sym()).collect())
        .collect();
    let independent: Vec<usize> = (0..m).filter(|i| !dependent.contains(i)).collect();
    for &d in dependent {
        let mut row = vec![0.0; n];
        for &i in &independent {
            let c = rng.sym();
            for j in 0..n {
                row[j] += c * rows[i][j];
            }
        }
        rows[d] = row;
    }
    for (i, row) in rows.iter_mut().enumerate() {
        let s = 10f64.powi((i as i32 % (2 * spread + 1)) - spread);
        row.iter_mut().for_each(|v| *v *= s);
    }
    (0..n)
        .flat_map(|j| (0..m).map(move |i| (i, j)))
        .map(|(i, j)| rows[i][j])
        .collect()
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    /// Random matrices with a known number of dependent rows (placed last), rows scaled over
    /// 1e±4: the redundancy is found, the rows kept are independent, and the min-norm solution of
    /// a consistent right-hand side satisfies every equation.
    #[test]
    fn known_redundancy_is_found(seed in 1u64.., n in 2usize..25, extra in 0usize..5, deficit in 0usize..4) {
        let mut rng = Rng(seed);
        let k = n.saturating_sub(deficit).max(1); // independent rows
        let m = k + extra;
        let dependent: Vec<usize> = (k..m).collect();
        let slots = deficient(m, n, &dependent, 4, &mut rng);
        let p = SparsityPattern::dense(m, n);
        let a = RankAnalysis::compute(&p, &slots, RankOptions::default()).unwrap();
        prop_assert_eq!(a.rank(), k);
        prop_assert_eq!(a.redundancy(), extra);
        prop_assert_eq!(a.degrees_of_freedom(), n - k);
        prop_assert_eq!(a.dependent_rows().len(), extra);
        let kept = p.select_rows(a.independent_rows()).unwrap();
        let mut kept_slots = vec![0.0; kept.pattern().num_slots()];
        kept.gather_slots(&slots, &mut kept_slots).unwrap();
        let again = RankAnalysis::compute(kept.pattern(), &kept_slots, RankOptions::default()).unwrap();
        prop_assert_eq!(again.rank(), k);
        prop_assert_eq!(again.redundancy(), 0);
        // Consistent right-hand side: the min-norm solution satisfies every equation.
        let x0: Vec<f64> = (0..n).map(|_| rng.sym()).collect();
        let mut b = vec![0.0; m];
        p.mul_vec(&slots, &x0, &mut b).unwrap();
        let mut solver = MinNormQr::new();
        solver.analyze(&p).unwrap();
        solver.factor(&slots).unwrap();
        prop_assert_eq!(solver.rank(), Some(k));
        let mut x = vec![0.0; n];
        solver.solve(&b, &mut x).unwrap();
        let mut y = vec![0.0; m];
        p.mul_vec(&slots, &x, &mut y).unwrap();
        for i in 0..m {
            let tol = 1e-9 * (b[i].abs() + slots.iter().skip(i).step_by(m).map(|v| v.abs()).sum::<f64>());
            prop_assert!((y[i] - b[i]).abs() <= tol, "row {}: {} vs {}", i, y[i], b[i]);
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    /// The multipliers of a right-hand side in the row space of J (Jᵀ μ₀ for a random μ₀; and,
    /// without column equilibration, a minimum-norm solution): Jᵀ μ reproduces it with every
    /// dependent row's μ zero, with and without column equilibration, rows scaled over 1e±4.
    #[test]
    fn multipliers_of_a_row_space_vector(seed in 1u64.., n in 2usize..20, extra in 0usize..4, deficit in 0usize..4, equilibrate: bool) {
        let mut rng = Rng(seed);
        let k = n.saturating_sub(deficit).max(1);
        let m = k + extra;
        let dependent: Vec<usize> = (k..m).collect();
        let slots = deficient(m, n, &dependent, 4, &mut rng);
        let p = SparsityPattern::dense(m, n);
        let mut solver = MinNormQr::with_options(RankOptions {
            equilibrate_columns: equilibrate,
            ..RankOptions::default()
        });
        solver.analyze(&p).unwrap();
        solver.factor(&slots).unwrap();
        let column = |j: usize| &slots[j * m..(j + 1) * m];
        let mu0: Vec<f64> = (0..m).map(|_| rng.sym()).collect();
        let mut targets = vec![(0..n).map(|j| column(j).iter().zip(&mu0).map(|(a, b)| a * b).sum()).collect::<Vec<f64>>()];
        if !equilibrate {
            let x0: Vec<f64> = (0..n).map(|_| rng.sym()).collect();
            let mut b = vec![0.0; m];
            p.mul_vec(&slots, &x0, &mut b).unwrap();
            let mut x = vec![0.0; n];
            solver.solve(&b, &mut x).unwrap();
            targets.push(x);
        }
        for y in &targets {
            let mut mu = vec![f64::NAN; m];
            solver.solve_transpose(y, &mut mu).unwrap();
            for i in solver.dependent_equations() {
                prop_assert_eq!(mu[*i], 0.0);
            }
            for j in 0..n {
                let back: f64 = column(j).iter().zip(&mu).map(|(a, b)| a * b).sum();
                let size: f64 = column(j).iter().zip(&mu).map(|(a, b)| (a * b).abs()).sum::<f64>() + y[j].abs();
                prop_assert!((back - y[j]).abs() <= 1e-9 * size, "column {}: {} vs {}", j, back, y[j]);
            }
        }
    }
}

#[test]
fn minimum_norm_step_for_underdetermined_systems() {
    // One equation x + y + z = 3: minimum-norm solution (1, 1, 1) (Euclidean, columns equal).
    let p = SparsityPattern::dense(1, 3);
    let mut s = MinNormQr::new();
    s.analyze(&p).unwrap();
    s.factor(&[1.0, 1.0, 1.0]).unwrap();
    let mut x = [0.0; 3];
    s.solve(&[3.0], &mut x).unwrap();
    for v in x {
        assert!((v - 1.0).abs() < 1e-14, "{x:?}");
    }
    // Plain Euclidean metric with unequal columns: x + 2y = 5 → (1, 2).
    let mut s = MinNormQr::with_options(RankOptions {
        equilibrate_columns: false,
        ..RankOptions::default()
    });
    let p = SparsityPattern::dense(1, 2);
    s.analyze(&p).unwrap();
    s.factor(&[1.0, 2.0]).unwrap();
    let mut x = [0.0; 2];
    s.solve(&[5.0], &mut x).unwrap();
    assert!(
        (x[0] - 1.0).abs() < 1e-14 && (x[1] - 2.0).abs() < 1e-14,
        "{x:?}"
    );
}

#[test]
fn the_last_rows_of_a_dependent_group_are_reported() {
    let mut rng = Rng(11);
    for spread in [0, 3, 6] {
        let dependent = [5, 6];
        let slots = deficient(7, 5, &dependent, spread, &mut rng);
        let a = RankAnalysis::compute(
            &SparsityPattern::dense(7, 5),
            &slots,
            RankOptions::default(),
        )
        .unwrap();
        assert_eq!(a.dependent_rows(), &dependent, "spread 1e±{spread}");
    }
}

#[test]
fn zero_rows_and_duplicate_rows_are_dependent() {
    // Rows: r0, 0, r0 (duplicate), r1.
    let p = SparsityPattern::new(4, 2, &[(0, 0), (0, 1), (2, 0), (2, 1), (3, 1)]).unwrap();
    let a = RankAnalysis::compute(&p, &[1.0, 2.0, 1.0, 2.0, 5.0], RankOptions::default()).unwrap();
    assert_eq!(a.rank(), 2);
    assert_eq!(a.dependent_rows(), &[1, 2]);
    assert_eq!(a.independent_rows(), &[0, 3]);
    assert!(a.pivots()[2] <= a.tolerance());
}

#[test]
fn four_bar_from_spatial_revolutes_has_three_redundant_equations() {
    let p = FourBar::pattern();
    for theta in [0.3, 1.0, 2.5, -1.2] {
        let mut fb = FourBar::new(1.0, theta);
        let q = fb.assembled();
        let mut r = vec![0.0; FourBar::M];
        fb.residual(&q, &mut r);
        assert!(
            r.iter().all(|v| v.abs() < 1e-13),
            "assembled residual {r:?}"
        );
        assert!(common::fd_jacobian_error(&mut fb, &p, &q) < 1e-8);
        let mut slots = vec![0.0; p.num_slots()];
        fb.jacobian(&q, &mut slots);
        let a = RankAnalysis::compute(&p, &slots, RankOptions::default()).unwrap();
        assert_eq!(
            (a.rank(), a.redundancy(), a.degrees_of_freedom()),
            (21, 3, 0),
            "θ = {theta}"
        );
        // The out-of-plane equations are the redundant ones, and with the lowest-index preference
        // the last of them go: the z row and both parallel rows of the last joint.
        assert_eq!(a.dependent_rows(), &[17, 18, 19], "θ = {theta}");
    }
}

#[test]
fn four_bar_six_coordinate_form_has_three_redundant_equations() {
    let p = FourBar6::pattern();
    let mut fb = FourBar6::new(FourBar::new(1.0, 0.8));
    let q = fb.inner.assembled();
    assert!(common::fd_jacobian_error(&mut fb, &p, &q) < 1e-8);
    let mut slots = vec![0.0; p.num_slots()];
    fb.jacobian(&q, &mut slots);
    let a = RankAnalysis::compute(&p, &slots, RankOptions::default()).unwrap();
    assert_eq!((a.rank(), a.redundancy()), (18, 3));
}

#[test]
fn four_bar_redundancy_does_not_depend_on_units() {
    let p = FourBar::pattern();
    let mut found = Vec::new();
    for scale in [1e-3, 1.0, 1e3, 1e6] {
        let mut fb = FourBar::new(scale, 0.7);
        let q = fb.assembled();
        let mut slots = vec![0.0; p.num_slots()];
        fb.jacobian(&q, &mut slots);
        let a = RankAnalysis::compute(&p, &slots, RankOptions::default()).unwrap();
        found.push((a.rank(), a.dependent_rows().to_vec()));
    }
    assert!(found.windows(2).all(|w| w[0] == w[1]), "{found:?}");
    assert_eq!(found[0].0, 21);
}

/// Assembles a Bennett linkage (a = 1, α = 30°, b = √3, β = 60°, so a / sin α = b / sin β) at
/// crank angle θ1: the DH loop closure is solved for θ2..θ4 (this crate's Newton, rank-revealing
/// least squares; the closure converges only linearly, so a residual of 1e-6 is accepted), the
/// absolute coordinates are built from the angles, then polished with the minimum-norm Newton on
/// the 23 absolute-coordinate equations.
fn bennett(theta1: f64) -> (common::Bennett, Vec<f64>) {
    use cardan_solver::{AutoSolver, Newton, NewtonOptions};
    let (a, alpha, beta) = (1.0, 30f64.to_radians(), 60f64.to_radians());
    let b = a * beta.sin() / alpha.sin();
    let params = [(a, alpha), (b, beta), (a, alpha), (b, beta)];
    let mut closure = common::BennettClosure { theta1, params };
    let p = SparsityPattern::dense(12, 3);
    let options = NewtonOptions {
        max_iterations: 60,
        ..NewtonOptions::default()
    };
    let mut newton = Newton::new(&p, AutoSolver::default(), options).unwrap();
    // In this convention the closure has θ3 = −θ1 and θ4 = −θ2.
    for t2 in [3.0, 2.8, 2.4, 2.0, 1.5, 1.0] {
        let mut x = [t2, -theta1, -t2];
        let close = match newton.solve(&mut closure, &mut x) {
            Ok(_) => true,
            Err(cardan_solver::SolverError::NotConverged {
                residual_history, ..
            }) => residual_history.last().is_some_and(|r| *r < 1e-6),
            Err(_) => false,
        };
        if close && x[0].sin().abs() > 0.1 {
            let (mut linkage, mut q) = common::Bennett::new(params, [theta1, x[0], x[1], x[2]]);
            let mut polish = Newton::new(
                &common::Bennett::pattern(),
                MinNormQr::new(),
                NewtonOptions::default(),
            )
            .unwrap();
            polish.solve(&mut linkage, &mut q).unwrap();
            return (linkage, q);
        }
    }
    panic!("Bennett closure not found for θ1 = {theta1}");
}

#[test]
fn bennett_linkage_is_mobile_with_three_redundant_equations() {
    let p = common::Bennett::pattern();
    for theta1 in [0.5, 0.8, 1.1, 2.0] {
        let (mut linkage, q) = bennett(theta1);
        let mut r = vec![0.0; common::Bennett::M];
        linkage.residual(&q, &mut r);
        assert!(
            r.iter().all(|v| v.abs() < 1e-9),
            "θ1 = {theta1}: residual {r:?}"
        );
        assert!(common::fd_jacobian_error(&mut linkage, &p, &q) < 1e-7);
        let mut slots = vec![0.0; p.num_slots()];
        linkage.jacobian(&q, &mut slots);
        let a = RankAnalysis::compute(&p, &slots, RankOptions::default()).unwrap();
        // Grübler: 6·3 − 4·5 = −2, yet the Bennett linkage moves with one degree of freedom.
        assert_eq!(
            (a.rank(), a.redundancy(), a.degrees_of_freedom()),
            (20, 3, 1),
            "θ1 = {theta1}: pivots {:?}",
            a.pivots()
        );
    }
}

#[test]
fn bennett_assembles_from_a_perturbed_guess_with_min_norm_steps() {
    use cardan_solver::{Newton, NewtonOptions};
    let p = common::Bennett::pattern();
    let (mut linkage, q_star) = bennett(0.8);
    let mut rng = Rng(5);
    let mut q: Vec<f64> = q_star.iter().map(|v| v + 0.02 * rng.sym()).collect();
    // Under-driven (one degree of freedom) and redundant: 23 equations, rank 20, 21 unknowns.
    let mut newton = Newton::new(&p, MinNormQr::new(), NewtonOptions::default()).unwrap();
    let report = newton.solve(&mut linkage, &mut q).unwrap();
    assert_eq!(report.rank, Some(20), "{report:?}");
    assert_eq!(report.redundant_equations, 3);
    let mut r = vec![0.0; common::Bennett::M];
    linkage.residual(&q, &mut r);
    assert!(r.iter().all(|v| v.abs() < 1e-10), "{r:?}");
    // It lands near the start (a small motion along the one free direction at most).
    let moved = q
        .iter()
        .zip(&q_star)
        .fold(0.0f64, |m, (a, b)| m.max((a - b).abs()));
    assert!(moved < 0.2, "moved {moved}");
}
