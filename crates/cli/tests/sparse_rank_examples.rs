//! The sparse rank analysis reports the same redundant equations as the dense one on every
//! bundled example (`examples/*.toml`), at the pose `cardan check` assembles (joints only, at the
//! analysis's start time), over all rows (joints and drivers).

use cardan_mechanism::AssemblyOptions;
use cardan_model::prepare::prepare;
use cardan_solver::{RankAnalysis, RankOptions};
use std::path::PathBuf;

#[test]
fn sparse_and_dense_rank_analyses_agree_on_every_example() {
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../examples");
    let mut files: Vec<PathBuf> = std::fs::read_dir(&dir)
        .unwrap()
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|e| e == "toml"))
        .collect();
    files.sort();
    assert!(files.len() >= 20, "{files:?}");
    let mut redundant = 0;
    for path in &files {
        let p = prepare(path).unwrap();
        let model = &p.model;
        let t0 = p.loaded.analysis.as_ref().map_or(0.0, |a| a.t_start);
        let mut ws = model.workspace();
        let opts = AssemblyOptions {
            include_drivers: false,
            ..AssemblyOptions::at(t0)
        };
        model.assemble(&mut ws, &opts).unwrap();
        let mut slots = vec![0.0; model.pattern().num_slots()];
        model.eval_jacobian(&ws, t0, &mut slots);
        let dense = RankAnalysis::compute(model.pattern(), &slots, RankOptions::default()).unwrap();
        let sparse =
            RankAnalysis::compute_sparse(model.pattern(), &slots, RankOptions::default()).unwrap();
        assert_eq!(
            dense.dependent_rows(),
            sparse.dependent_rows(),
            "{}",
            path.display()
        );
        redundant += dense.redundancy();
    }
    // The examples do exercise redundancy (four-bars of spatial revolutes, Bricard, Bennett).
    assert!(redundant >= 10, "{redundant}");
}
