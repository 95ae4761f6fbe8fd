//! Linear solves: random well-posed systems, mechanism-like patterns, badly scaled systems,
//! singular systems, and the automatic choice.

mod common;

use cardan_solver::{
    AutoPolicy, AutoSolver, DenseLu, LinearSolver, MinNormQr, SolverChoice, SolverError,
    SolverKind, SparseLu, SparsityPattern,
};
use common::Rng;
use proptest::prelude::*;

/// ‖J x − b‖∞ / (‖J‖max ‖x‖∞ + ‖b‖∞)
fn relative_residual(p: &SparsityPattern, slots: &[f64], x: &[f64], b: &[f64]) -> f64 {
    let mut y = vec![0.0; p.nrows()];
    p.mul_vec(slots, x, &mut y).unwrap();
    let r = y
        .iter()
        .zip(b)
        .fold(0.0f64, |a, (y, b)| a.max((y - b).abs()));
    let jn = slots.iter().fold(0.0f64, |a, v| a.max(v.abs()));
    let xn = x.iter().fold(0.0f64, |a, v| a.max(v.abs()));
    let bn = b.iter().fold(0.0f64, |a, v| a.max(v.abs()));
    r / (jn * xn + bn)
}

fn solve_with(
    solver: &mut dyn LinearSolver,
    p: &SparsityPattern,
    slots: &[f64],
    b: &[f64],
) -> Vec<f64> {
    solver.analyze(p).unwrap();
    solver.factor(slots).unwrap();
    let mut x = vec![0.0; p.ncols()];
    solver.solve(b, &mut x).unwrap();
    x
}

/// Random sparse pattern with a full diagonal; values random with a diagonal shift.
fn random_system(
    n: usize,
    density: f64,
    shift: f64,
    rng: &mut Rng,
) -> (SparsityPattern, Vec<f64>, Vec<f64>) {
    let mut entries = Vec::new();
    let mut slots = Vec::new();
    for i in 0..n {
        entries.push((i, i));
        slots.push(shift * (1.0 + rng.next_f64()));
        for j in 0..n {
            if i != j && rng.next_f64() < density {
                entries.push((i, j));
                slots.push(rng.sym());
            }
        }
    }
    let b = (0..n).map(|_| rng.sym()).collect();
    (SparsityPattern::new(n, n, &entries).unwrap(), slots, b)
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    /// Dense LU, sparse LU and the min-norm QR agree on random well-posed square systems.
    #[test]
    fn random_well_posed_systems_agree(seed in 1u64.., n in 1usize..40, density in 0.02f64..0.6) {
        let mut rng = Rng(seed);
        let (p, slots, b) = random_system(n, density, 3.0, &mut rng);
        let xd = solve_with(&mut DenseLu::new(), &p, &slots, &b);
        let xs = solve_with(&mut SparseLu::new(), &p, &slots, &b);
        let xq = solve_with(&mut MinNormQr::new(), &p, &slots, &b);
        prop_assert!(relative_residual(&p, &slots, &xd, &b) < 1e-13);
        prop_assert!(relative_residual(&p, &slots, &xs, &b) < 1e-13);
        prop_assert!(relative_residual(&p, &slots, &xq, &b) < 1e-12);
        for k in 0..n {
            prop_assert!((xd[k] - xs[k]).abs() <= 1e-10 * (1.0 + xd[k].abs()), "{k}: {} vs {}", xd[k], xs[k]);
            prop_assert!((xd[k] - xq[k]).abs() <= 1e-9 * (1.0 + xd[k].abs()), "{k}: {} vs {}", xd[k], xq[k]);
        }
    }
}

#[test]
fn known_answer_with_duplicate_slots() {
    // [[4, 1], [2, 3]] with the (0,0) entry split across two slots; x = [1, 2] → b = [6, 8].
    let p = SparsityPattern::new(2, 2, &[(0, 0), (1, 0), (0, 1), (1, 1), (0, 0)]).unwrap();
    let slots = [3.0, 2.0, 1.0, 3.0, 1.0];
    for solver in [
        &mut DenseLu::new() as &mut dyn LinearSolver,
        &mut SparseLu::new(),
        &mut MinNormQr::new(),
    ] {
        let x = solve_with(solver, &p, &slots, &[6.0, 8.0]);
        assert!(
            (x[0] - 1.0).abs() < 1e-14 && (x[1] - 2.0).abs() < 1e-14,
            "{}: {x:?}",
            solver.name()
        );
    }
}

#[test]
fn mechanism_patterns_sparse_matches_dense_and_refactors() {
    let mut rng = Rng(7);
    for (name, (p, mut slots)) in [
        ("chain", common::chain(40, &mut rng)),
        ("ladder", common::ladder(40, &mut rng)),
    ] {
        let n = p.ncols();
        let b: Vec<f64> = (0..n).map(|i| (i as f64 * 0.37).sin()).collect();
        let mut dense = DenseLu::new();
        let mut sparse = SparseLu::new();
        dense.analyze(&p).unwrap();
        sparse.analyze(&p).unwrap();
        // Same pattern, new values each step: refill, refactor, resolve.
        for step in 0..3 {
            for v in slots.iter_mut() {
                *v *= 1.0 + 0.01 * step as f64;
            }
            dense.factor(&slots).unwrap();
            sparse.factor(&slots).unwrap();
            let (mut xd, mut xs) = (vec![0.0; n], vec![0.0; n]);
            dense.solve(&b, &mut xd).unwrap();
            sparse.solve(&b, &mut xs).unwrap();
            let diff = xd
                .iter()
                .zip(&xs)
                .fold(0.0f64, |a, (u, v)| a.max((u - v).abs()));
            assert!(diff < 1e-12, "{name} step {step}: {diff}");
            assert!(relative_residual(&p, &slots, &xs, &b) < 1e-14);
        }
        assert!(
            sparse.factor_nnz() < 4 * p.nnz(),
            "{name}: fill {} for nnz {}",
            sparse.factor_nnz(),
            p.nnz()
        );
    }
}

#[test]
fn badly_scaled_rows_and_columns() {
    // J = D_r A D_c with scales from 1e-8 to 1e8: the solution must still satisfy J x = b to
    // working accuracy row by row (relative to each row's size).
    let mut rng = Rng(99);
    let n = 30;
    let (p, mut slots, b) = random_system(n, 0.2, 3.0, &mut rng);
    let row_scale: Vec<f64> = (0..n).map(|i| 10f64.powi((i as i32 % 17) - 8)).collect();
    let col_scale: Vec<f64> = (0..n).map(|j| 10f64.powi(8 - (j as i32 % 17))).collect();
    for (k, (r, c)) in p.entries().enumerate() {
        slots[k] *= row_scale[r] * col_scale[c];
    }
    let b: Vec<f64> = b.iter().zip(&row_scale).map(|(b, s)| b * s).collect();
    // The QR path needs column equilibration for a 1e16 column-scale range (Newton would instead
    // pass unknowns divided by the caller's scales).
    let equilibrated = cardan_solver::RankOptions {
        equilibrate_columns: true,
        ..Default::default()
    };
    for solver in [
        &mut DenseLu::new() as &mut dyn LinearSolver,
        &mut SparseLu::new(),
        &mut MinNormQr::with_options(equilibrated),
    ] {
        let x = solve_with(solver, &p, &slots, &b);
        let mut y = vec![0.0; n];
        p.mul_vec(&slots, &x, &mut y).unwrap();
        for i in 0..n {
            // Row-relative residual: |(Jx − b)_i| / (Σ_j |J_ij x_j| + |b_i|)
            let mut mag = b[i].abs();
            for (k, (r, c)) in p.entries().enumerate() {
                if r == i {
                    mag += (slots[k] * x[c]).abs();
                }
            }
            let rel = (y[i] - b[i]).abs() / mag;
            // LU works on the equilibrated matrix; the QR path only normalizes rows after a
            // column equilibration, so it is a little less accurate on this 1e16 scale range.
            let tol = if solver.name() == "min-norm-qr" {
                1e-8
            } else {
                1e-11
            };
            assert!(
                rel < tol,
                "{}: row {i} relative residual {rel:e}",
                solver.name()
            );
        }
    }
}

#[test]
fn singular_square_systems_report_dependent_equations() {
    // Row 3 = row 0 + 2 row 1.
    let mut rng = Rng(3);
    let n = 6;
    let mut a = vec![vec![0.0; n]; n];
    for (i, row) in a.iter_mut().enumerate() {
        for (j, v) in row.iter_mut().enumerate() {
            *v = rng.sym() + if i == j { 3.0 } else { 0.0 };
        }
    }
    a[3] = (0..n).map(|j| a[0][j] + 2.0 * a[1][j]).collect();
    let p = SparsityPattern::dense(n, n);
    let slots: Vec<f64> = (0..n)
        .flat_map(|j| (0..n).map(move |i| (i, j)))
        .map(|(i, j)| a[i][j])
        .collect();
    for solver in [
        &mut DenseLu::new() as &mut dyn LinearSolver,
        &mut SparseLu::new(),
    ] {
        solver.analyze(&p).unwrap();
        match solver.factor(&slots) {
            Err(SolverError::Singular {
                dependent_equations,
            }) => {
                assert_eq!(dependent_equations, vec![3], "{}", solver.name());
            }
            other => panic!("{}: expected Singular, got {other:?}", solver.name()),
        }
        // No panic on solve after a failed factor: a typed error.
        let mut x = vec![0.0; n];
        assert!(matches!(
            solver.solve(&[0.0; 6], &mut x),
            Err(SolverError::NotReady { .. })
        ));
    }
    // Exactly zero column: structurally fine, numerically singular.
    let p = SparsityPattern::new(2, 2, &[(0, 0), (1, 0), (0, 1), (1, 1)]).unwrap();
    let mut s = SparseLu::new();
    s.analyze(&p).unwrap();
    assert!(matches!(
        s.factor(&[1.0, 2.0, 0.0, 0.0]),
        Err(SolverError::Singular { .. })
    ));
    // Structurally singular (empty row).
    let p = SparsityPattern::new(2, 2, &[(0, 0), (0, 1)]).unwrap();
    let mut s = SparseLu::new();
    s.analyze(&p).unwrap();
    assert!(matches!(
        s.factor(&[1.0, 2.0]),
        Err(SolverError::Singular { .. })
    ));
}

#[test]
fn bad_input_is_a_typed_error() {
    let p = SparsityPattern::new(2, 3, &[(0, 0), (1, 1), (1, 2)]).unwrap();
    assert!(matches!(
        DenseLu::new().analyze(&p),
        Err(SolverError::NotSquare { nrows: 2, ncols: 3 })
    ));
    assert!(matches!(
        SparseLu::new().analyze(&p),
        Err(SolverError::NotSquare { .. })
    ));
    let p = SparsityPattern::dense(2, 2);
    let mut d = DenseLu::new();
    assert!(matches!(
        d.factor(&[1.0; 4]),
        Err(SolverError::NotReady { missing: "analyze" })
    ));
    d.analyze(&p).unwrap();
    assert!(matches!(
        d.factor(&[1.0; 3]),
        Err(SolverError::DimensionMismatch {
            expected: 4,
            found: 3,
            ..
        })
    ));
    assert!(matches!(
        d.factor(&[1.0, f64::NAN, 0.0, 1.0]),
        Err(SolverError::NonFinite {
            location: cardan_solver::NonFiniteLocation::Jacobian {
                slot: 1,
                row: 1,
                col: 0
            },
            ..
        })
    ));
    d.factor(&[1.0, 0.0, 0.0, 1.0]).unwrap();
    let mut x = [0.0; 2];
    assert!(matches!(
        d.solve(&[1.0], &mut x),
        Err(SolverError::DimensionMismatch { .. })
    ));
    assert!(matches!(
        d.solve(&[1.0, f64::INFINITY], &mut x),
        Err(SolverError::NonFinite { .. })
    ));
}

#[test]
fn sparse_lu_names_the_first_non_finite_slot_with_and_without_duplicates() {
    // Without duplicates the check is folded into the scatter; with them the values are summed
    // first. Either way the first bad slot (not its compressed-column position: the slots are
    // listed row by row) is named, and the solver factors again afterwards.
    let plain = SparsityPattern::new(2, 2, &[(0, 0), (0, 1), (1, 0), (1, 1)]).unwrap();
    let dup = SparsityPattern::new(2, 2, &[(0, 0), (0, 1), (1, 0), (1, 1), (0, 0)]).unwrap();
    let good = [2.0, 0.25, 0.5, 3.0, 1.0];
    for (p, bad_slots) in [(&plain, [1usize, 2]), (&dup, [1, 4]), (&dup, [4, 4])] {
        let mut s = SparseLu::new();
        s.analyze(p).unwrap();
        for bad in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
            let mut slots = good[..p.num_slots()].to_vec();
            for &k in &bad_slots {
                slots[k] = bad;
            }
            let first = bad_slots[0];
            let (row, col) = p.entry(first);
            assert_eq!(
                s.factor(&slots),
                Err(SolverError::NonFinite {
                    location: cardan_solver::NonFiniteLocation::Jacobian {
                        slot: first,
                        row,
                        col
                    },
                    iteration: None
                }),
                "{} slots, value {bad} at {bad_slots:?}",
                p.num_slots()
            );
            let mut x = [0.0; 2];
            assert!(matches!(
                s.solve(&[1.0, 1.0], &mut x),
                Err(SolverError::NotReady { .. })
            ));
        }
        assert!(matches!(
            s.factor(&vec![1.0; p.num_slots() + 1]),
            Err(SolverError::DimensionMismatch { .. })
        ));
        let slots = &good[..p.num_slots()];
        let x = solve_with(&mut s, p, slots, &[1.0, 2.0]);
        assert!(
            relative_residual(p, slots, &x, &[1.0, 2.0]) < 1e-15,
            "{x:?}"
        );
    }
}

#[test]
fn sparse_lu_equilibrates_the_summed_entries() {
    // Row 0 is [1 − 1 + 2⁻⁴⁵, 2⁻⁴⁴] once its (0, 0) slots are summed: its scale must come from
    // the sums (≈ 2⁻⁴⁴), not from the slots (1), or its pivot looks like 2⁻⁴⁵ and is refused.
    let p = SparsityPattern::new(2, 2, &[(0, 0), (0, 0), (0, 1), (1, 0), (1, 1)]).unwrap();
    let t = 2f64.powi(-45);
    let slots = [1.0, -1.0 + t, 2.0 * t, 1.0, 1.0];
    let mut s = SparseLu::new();
    s.analyze(&p).unwrap();
    s.factor(&slots).unwrap();
    let b = [3.0 * t, 2.0];
    let mut x = [0.0; 2];
    s.solve(&b, &mut x).unwrap();
    // [t 2t; 1 1] x = [3t; 2] → x = [1, 1].
    assert!(
        (x[0] - 1.0).abs() < 1e-12 && (x[1] - 1.0).abs() < 1e-12,
        "{x:?}"
    );
}

#[test]
fn auto_choice_follows_size_and_density_and_can_be_overridden() {
    let mut rng = Rng(5);
    let (small, _) = common::chain(4, &mut rng); // 28 unknowns
    let (large, slots) = common::ladder(60, &mut rng); // 420 unknowns, sparse
    let mut auto = AutoSolver::default();
    auto.analyze(&small).unwrap();
    assert_eq!(auto.kind(), Some(SolverKind::Dense));
    auto.analyze(&large).unwrap();
    assert_eq!(auto.kind(), Some(SolverKind::Sparse));
    auto.factor(&slots).unwrap();
    assert_eq!(auto.name(), "sparse-lu");
    let dense_large = SparsityPattern::dense(200, 200);
    auto.analyze(&dense_large).unwrap();
    assert_eq!(
        auto.kind(),
        Some(SolverKind::Dense),
        "dense matrices stay dense"
    );
    let rect = SparsityPattern::dense(3, 5);
    auto.analyze(&rect).unwrap();
    assert_eq!(auto.kind(), Some(SolverKind::MinNorm));
    let mut forced = AutoSolver::new(SolverChoice::Sparse);
    forced.analyze(&small).unwrap();
    assert_eq!(forced.kind(), Some(SolverKind::Sparse));
    let policy = AutoPolicy {
        dense_max_dim: 1000,
        ..AutoPolicy::default()
    };
    let mut custom = AutoSolver::new(SolverChoice::Auto(policy));
    custom.analyze(&large).unwrap();
    assert_eq!(custom.kind(), Some(SolverKind::Dense));
}
