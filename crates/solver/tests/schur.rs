//! The Schur-complement saddle-point solver against LU of the full matrix
//! `[A Bᵀ; B 0]`, and its failure modes (singular B, non-SPD block, non-finite input).

mod common;

use cardan_solver::{
    LinearSolver, NonFiniteLocation, SchurSolver, SolverError, SparseLu, SparsityPattern,
};
use common::Rng;

const BS: usize = 6;

/// A random saddle-point system: `nb` blocks A_k = diag(m I, J) with J = G Gᵀ + δ I (or a full
/// random SPD 6 × 6 when `full_blocks`), and `m` rows of B, each touching one or two blocks (a
/// chain-like or random graph) with random values.
struct Case {
    nb: usize,
    m: usize,
    a: Vec<f64>,
    entries: Vec<(usize, usize)>,
    b: Vec<f64>,
}

fn spd(rng: &mut Rng, n: usize, shift: f64) -> Vec<f64> {
    let g: Vec<f64> = (0..n * n).map(|_| rng.sym()).collect();
    let mut a = vec![0.0; n * n];
    for i in 0..n {
        for j in 0..n {
            let mut s = 0.0;
            for k in 0..n {
                s += g[k * n + i] * g[k * n + j];
            }
            a[j * n + i] = s + if i == j { shift } else { 0.0 };
        }
    }
    a
}

fn case(rng: &mut Rng, nb: usize, rows_per_block: usize, chain: bool, full_blocks: bool) -> Case {
    let mut a = Vec::new();
    for _ in 0..nb {
        if full_blocks {
            a.extend(spd(rng, BS, 0.5));
        } else {
            // diag(m I, J): mass 0.1 … 10, inertia of another scale.
            let m = 10f64.powf(rng.sym());
            let j = spd(rng, 3, 0.1);
            let mut blk = vec![0.0; BS * BS];
            for i in 0..3 {
                blk[i * BS + i] = m;
                for k in 0..3 {
                    blk[(3 + k) * BS + 3 + i] = 1e-2 * j[k * 3 + i];
                }
            }
            a.extend(blk);
        }
    }
    let m = rows_per_block * nb;
    let mut entries = Vec::new();
    let mut b = Vec::new();
    for r in 0..m {
        let k = r / rows_per_block;
        let other = if chain {
            k.checked_sub(1)
        } else {
            let o = (rng.next_f64() * nb as f64) as usize % nb;
            (o != k).then_some(o)
        };
        for blk in std::iter::once(k).chain(other) {
            for c in 0..BS {
                entries.push((r, BS * blk + c));
                b.push(rng.sym() * if c < 3 { 1.0 } else { 0.3 });
            }
        }
    }
    Case {
        nb,
        m,
        a,
        entries,
        b,
    }
}

impl Case {
    fn n(&self) -> usize {
        BS * self.nb
    }

    /// The full matrix as a pattern with its slots (A's lower and upper triangle, B, Bᵀ).
    fn full(&self) -> (SparsityPattern, Vec<f64>) {
        let n = self.n();
        let mut pos = Vec::new();
        let mut slots = Vec::new();
        for k in 0..self.nb {
            for c in 0..BS {
                for r in 0..BS {
                    pos.push((BS * k + r, BS * k + c));
                    slots.push(self.a[k * BS * BS + c * BS + r]);
                }
            }
        }
        for (&(r, c), &v) in self.entries.iter().zip(&self.b) {
            pos.push((n + r, c));
            slots.push(v);
            pos.push((c, n + r));
            slots.push(v);
        }
        let size = n + self.m;
        (SparsityPattern::new(size, size, &pos).unwrap(), slots)
    }

    fn schur(&self) -> SchurSolver {
        let mut s = SchurSolver::new();
        s.analyze(BS, self.nb, self.m, &self.entries).unwrap();
        s
    }
}

fn rel_diff(a: &[f64], b: &[f64]) -> f64 {
    let d = a
        .iter()
        .zip(b)
        .fold(0.0f64, |m, (x, y)| m.max((x - y).abs()));
    let s = b.iter().fold(0.0f64, |m, y| m.max(y.abs()));
    d / s
}

#[test]
fn schur_equals_lu_on_random_saddle_point_systems() {
    let mut rng = Rng(0x5EED_2026);
    let mut worst = 0.0f64;
    for seed_case in 0..40 {
        let nb = 2 + seed_case % 23;
        let rows = 1 + seed_case % 5;
        let chain = seed_case % 2 == 0;
        let full_blocks = seed_case % 3 == 0;
        let mut c = case(&mut rng, nb, rows, chain, full_blocks);
        if seed_case % 4 == 1 {
            // Entries in a scrambled order, one split in two duplicates (summed): the general
            // gather instead of the contiguous copy.
            let mut order: Vec<usize> = (0..c.entries.len()).collect();
            for i in (1..order.len()).rev() {
                let j = (rng.next_f64() * (i + 1) as f64) as usize % (i + 1);
                order.swap(i, j);
            }
            let mut entries: Vec<(usize, usize)> = order.iter().map(|&i| c.entries[i]).collect();
            let mut b: Vec<f64> = order.iter().map(|&i| c.b[i]).collect();
            entries.push(entries[0]);
            b[0] *= 0.25;
            b.push(b[0] * 3.0);
            c.entries = entries;
            c.b = b;
        }
        let (pattern, slots) = c.full();
        let mut lu = SparseLu::new();
        lu.analyze(&pattern).unwrap();
        lu.factor(&slots).unwrap();
        let mut schur = c.schur();
        schur.factor(&c.a, &c.b).unwrap();
        let size = c.n() + c.m;
        for _ in 0..3 {
            let rhs: Vec<f64> = (0..size).map(|_| rng.sym()).collect();
            let mut x_lu = vec![0.0; size];
            let mut x_s = vec![0.0; size];
            lu.solve(&rhs, &mut x_lu).unwrap();
            schur.solve(&rhs, &mut x_s).unwrap();
            let (n, m) = (c.n(), c.m);
            let dx = rel_diff(&x_s[..n], &x_lu[..n]);
            let dl = rel_diff(&x_s[n..], &x_lu[n..]);
            worst = worst.max(dx).max(dl);
            assert!(
                dx < 1e-11 && dl < 1e-11,
                "case {seed_case} (nb {nb}, m {m}): x differs by {dx:.2e}, λ by {dl:.2e}"
            );
            // And the residual of the full system is at roundoff.
            let mut y = vec![0.0; size];
            pattern.mul_vec(&slots, &x_s, &mut y).unwrap();
            let r = rel_diff(&y, &rhs);
            assert!(r < 1e-11, "case {seed_case}: residual {r:.2e}");
        }
    }
    eprintln!("largest relative difference Schur vs LU: {worst:.2e}");
}

#[test]
fn refactoring_with_new_values_uses_them() {
    let mut rng = Rng(7);
    let c1 = case(&mut rng, 12, 3, true, false);
    let mut c2 = case(&mut rng, 12, 3, true, true);
    c2.entries = c1.entries.clone();
    let mut schur = c1.schur();
    let size = c1.n() + c1.m;
    let rhs: Vec<f64> = (0..size).map(|_| rng.sym()).collect();
    for c in [&c1, &c2, &c1] {
        schur.factor(&c.a, &c.b).unwrap();
        let (pattern, slots) = c.full();
        let mut x = vec![0.0; size];
        schur.solve(&rhs, &mut x).unwrap();
        let mut y = vec![0.0; size];
        pattern.mul_vec(&slots, &x, &mut y).unwrap();
        assert!(rel_diff(&y, &rhs) < 1e-12);
    }
}

#[test]
fn dependent_rows_are_reported_singular_not_nan() {
    let mut rng = Rng(11);
    let mut c = case(&mut rng, 8, 2, true, false);
    // Row 7 := row 5 (rows 4, 5 touch blocks 2 and 1; 6, 7 touch 3 and 2): give row 7 the same
    // entries and values as row 5.
    let row5: Vec<((usize, usize), f64)> = c
        .entries
        .iter()
        .zip(&c.b)
        .filter(|(e, _)| e.0 == 5)
        .map(|(e, v)| (*e, *v))
        .collect();
    let keep: Vec<usize> = (0..c.entries.len())
        .filter(|&i| c.entries[i].0 != 7)
        .collect();
    c.entries = keep.iter().map(|&i| c.entries[i]).collect();
    c.b = keep.iter().map(|&i| c.b[i]).collect();
    for ((_, col), v) in &row5 {
        c.entries.push((7, *col));
        c.b.push(*v);
    }
    let mut schur = c.schur();
    match schur.factor(&c.a, &c.b) {
        Err(SolverError::Singular {
            dependent_equations,
        }) => assert!(
            dependent_equations.iter().any(|&r| r == 5 || r == 7),
            "{dependent_equations:?}"
        ),
        other => panic!("expected Singular, got {other:?}"),
    }
    let mut x = vec![0.0; c.n() + c.m];
    assert!(matches!(
        schur.solve(&vec![1.0; c.n() + c.m], &mut x),
        Err(SolverError::NotReady { .. })
    ));

    // Nearly dependent (row 7 = row 5 + 1e-6 noise): pivot ratio ≈ 1e-12, below the default
    // tolerance 1e-4; accepted with τ = 0, and then the solve is still finite.
    let first = c.b.len() - row5.len();
    for v in &mut c.b[first..] {
        *v += 1e-6 * rng.sym();
    }
    let mut schur = c.schur();
    assert!(matches!(
        schur.factor(&c.a, &c.b),
        Err(SolverError::Singular { .. })
    ));
    assert!(schur.min_pivot_ratio() < 1e-8);
    let mut loose = SchurSolver::new().with_pivot_tolerance(0.0);
    loose.analyze(BS, c.nb, c.m, &c.entries).unwrap();
    loose.factor(&c.a, &c.b).unwrap();
    loose.solve(&vec![1.0; c.n() + c.m], &mut x).unwrap();
    assert!(x.iter().all(|v| v.is_finite()));
}

#[test]
fn a_row_touching_no_block_is_singular() {
    let mut rng = Rng(3);
    let c = case(&mut rng, 4, 2, true, false);
    let mut schur = SchurSolver::new();
    // One more row (index m) with no entries.
    schur.analyze(BS, c.nb, c.m + 1, &c.entries).unwrap();
    assert_eq!(
        schur.factor(&c.a, &c.b),
        Err(SolverError::Singular {
            dependent_equations: vec![c.m]
        })
    );
}

#[test]
fn indefinite_block_and_non_finite_values_are_errors() {
    let mut rng = Rng(5);
    let mut c = case(&mut rng, 5, 2, true, false);
    let mut schur = c.schur();
    c.a[2 * BS * BS + 4 * BS + 4] = -1.0;
    assert!(matches!(
        schur.factor(&c.a, &c.b),
        Err(SolverError::Singular { .. })
    ));
    c.a[2 * BS * BS + 4 * BS + 4] = 1.0;
    schur.factor(&c.a, &c.b).unwrap();
    // A point mass with a negligible inertia, diag(m I, 1e-13 m I): SPD, but condition 1e13,
    // beyond 1/τ; with a relaxed tolerance it is accepted.
    let saved = c.a.clone();
    let m = c.a[2 * BS * BS];
    for r in 3..BS {
        for col in 3..BS {
            c.a[2 * BS * BS + col * BS + r] = if r == col { 1e-13 * m } else { 0.0 };
        }
    }
    assert!(matches!(
        schur.factor(&c.a, &c.b),
        Err(SolverError::Singular { .. })
    ));
    let mut loose = SchurSolver::new()
        .with_block_tolerance(1e-15)
        .with_pivot_tolerance(0.0);
    loose.analyze(BS, c.nb, c.m, &c.entries).unwrap();
    loose.factor(&c.a, &c.b).unwrap();
    c.a = saved;
    // Non-finite values of B (NaN, ±∞, in a row whose S row is not first in the ordering) and
    // of A are reported as such, naming the entry.
    for (slot, v) in [
        (3, f64::NAN),
        (c.b.len() - 2, f64::INFINITY),
        (40, f64::NEG_INFINITY),
    ] {
        let keep = c.b[slot];
        c.b[slot] = v;
        let (row, col) = c.entries[slot];
        assert_eq!(
            schur.factor(&c.a, &c.b),
            Err(SolverError::NonFinite {
                location: NonFiniteLocation::Jacobian { slot, row, col },
                iteration: None,
            }),
            "B slot {slot} = {v}"
        );
        c.b[slot] = keep;
    }
    let keep = c.a[BS * BS + 7];
    c.a[BS * BS + 7] = f64::NAN;
    assert_eq!(
        schur.factor(&c.a, &c.b),
        Err(SolverError::NonFinite {
            location: NonFiniteLocation::Jacobian {
                slot: BS * BS + 7,
                row: BS + 1,
                col: BS + 1
            },
            iteration: None,
        })
    );
    c.a[BS * BS + 7] = keep;
    schur.factor(&c.a, &c.b).unwrap();
    let mut rhs = vec![1.0; c.n() + c.m];
    let mut x = vec![0.0; c.n() + c.m];
    for index in [1, c.n() + 2] {
        rhs[index] = f64::INFINITY;
        assert_eq!(
            schur.solve(&rhs, &mut x),
            Err(SolverError::NonFinite {
                location: NonFiniteLocation::RightHandSide { index },
                iteration: None,
            })
        );
        rhs[index] = 1.0;
    }
    schur.solve(&rhs, &mut x).unwrap();
}

#[test]
fn entries_outside_b_are_rejected() {
    let mut schur = SchurSolver::new();
    assert!(matches!(
        schur.analyze(BS, 2, 3, &[(0, 0), (3, 1)]),
        Err(SolverError::EntryOutOfBounds { index: 1, .. })
    ));
    assert!(matches!(
        schur.analyze(BS, 2, 3, &[(0, 12)]),
        Err(SolverError::EntryOutOfBounds { index: 0, .. })
    ));
}
