//! Factor-and-solve time of the dense and sparse LU on mechanism-like patterns.
//!
//! Patterns (see `tests/common/mod.rs`): 7 × 7 blocks per body; a *chain* (body i coupled to
//! i ± 1) and a *ladder of closed loops* (two rails, a rung between bodies 2k and 2k + 1).
//! Sizes from 21 to 21,000 unknowns; the dense LU only up to 2,100.
//!
//! ```text
//! cargo bench -p cardan-solver --bench linear                   # everything (a few minutes)
//! cargo bench -p cardan-solver --bench linear -- --quick        # faster, less precise
//! cargo bench -p cardan-solver --bench linear -- 'ladder/sparse' # one family
//! ```
//!
//! Each iteration refills the values (same pattern), factors and solves: the work of one Newton
//! iteration's linear algebra. The symbolic analysis is done once, outside the timing.

#[path = "../tests/common/mod.rs"]
mod common;

use cardan_solver::{DenseLu, LinearSolver, SparseLu, SparsityPattern};
use common::Rng;
use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion, Throughput};
use std::hint::black_box;
use std::time::Duration;

/// Bodies per size: n = 7 · bodies unknowns.
const BODIES: &[usize] = &[3, 5, 8, 10, 15, 20, 30, 100, 300, 1000, 3000];
const DENSE_MAX_BODIES: usize = 300;

fn bench_family(
    c: &mut Criterion,
    name: &str,
    make: fn(usize, &mut Rng) -> (SparsityPattern, Vec<f64>),
) {
    let mut group = c.benchmark_group(name);
    group
        .sample_size(10)
        .warm_up_time(Duration::from_millis(300))
        .measurement_time(Duration::from_secs(1));
    for &nb in BODIES {
        let mut rng = Rng(12345 + nb as u64);
        let (pattern, slots) = make(nb, &mut rng);
        let n = pattern.ncols();
        let b: Vec<f64> = (0..n).map(|i| (i as f64).sin()).collect();
        let mut x = vec![0.0; n];
        group.throughput(Throughput::Elements(n as u64));
        let mut sparse = SparseLu::new();
        sparse.analyze(&pattern).unwrap();
        group.bench_with_input(BenchmarkId::new("sparse", n), &n, |bench, _| {
            bench.iter(|| {
                sparse.factor(black_box(&slots)).unwrap();
                sparse.solve(black_box(&b), &mut x).unwrap();
            })
        });
        if nb >= 100 {
            // For comparison only: faer's high-level sparse LU (supernodal where faer's default
            // heuristic picks it), which allocates in every factorization.
            use faer::linalg::solvers::SolveCore;
            use faer::sparse::linalg::solvers::{Lu, SymbolicLu};
            let symbolic = SymbolicLu::try_new(pattern.symbolic()).unwrap();
            let mut csc = vec![0.0; pattern.nnz()];
            group.bench_with_input(BenchmarkId::new("faer-default", n), &n, |bench, _| {
                bench.iter(|| {
                    pattern.scatter_csc(black_box(&slots), &mut csc).unwrap();
                    let a = faer::sparse::SparseColMatRef::new(pattern.symbolic(), &csc);
                    let lu = Lu::try_new_with_symbolic(symbolic.clone(), a).unwrap();
                    x.copy_from_slice(&b);
                    lu.solve_in_place_with_conj(
                        faer::Conj::No,
                        faer::MatMut::from_column_major_slice_mut(&mut x, n, 1),
                    );
                })
            });
        }
        if nb <= DENSE_MAX_BODIES {
            let mut dense = DenseLu::new();
            dense.analyze(&pattern).unwrap();
            group.bench_with_input(BenchmarkId::new("dense", n), &n, |bench, _| {
                bench.iter(|| {
                    dense.factor(black_box(&slots)).unwrap();
                    dense.solve(black_box(&b), &mut x).unwrap();
                })
            });
        }
    }
    group.finish();
}

fn chain(c: &mut Criterion) {
    bench_family(c, "chain", common::chain);
}

fn ladder(c: &mut Criterion) {
    bench_family(c, "ladder", common::ladder);
}

criterion_group!(benches, chain, ladder);
criterion_main!(benches);
