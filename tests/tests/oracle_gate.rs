//! The oracle gate: every Rust primitive, joint and driver against the CasADi reference data in
//! `oracle/data/` (regenerate with `cargo xtask oracle`; CI checks they are current with
//! `cargo xtask oracle --check`). Relative tolerance 1e-12; see `cardan_tests::oracle`.

use cardan_tests::oracle::{compare_case, data_dir, load};
use cardan_tests::registry::ELEMENTS;
use std::collections::BTreeSet;

fn oracle_files() -> Vec<std::path::PathBuf> {
    let mut files: Vec<_> = std::fs::read_dir(data_dir())
        .expect("oracle/data exists")
        .map(|e| e.expect("readable entry").path())
        .filter(|p| p.extension().is_some_and(|e| e == "json"))
        .collect();
    files.sort();
    files
}

#[test]
fn every_rust_element_has_oracle_data_and_every_oracle_file_a_rust_element() {
    let have: BTreeSet<String> = oracle_files()
        .iter()
        .map(|p| load(p).expect("loadable oracle file").element)
        .collect();
    let rust: BTreeSet<String> = ELEMENTS.iter().map(|s| s.to_string()).collect();
    let missing: Vec<_> = rust.difference(&have).collect();
    let unknown: Vec<_> = have.difference(&rust).collect();
    assert!(missing.is_empty(), "Rust elements without oracle data (add them to oracle/ and run `cargo xtask oracle`): {missing:?}");
    assert!(unknown.is_empty(), "oracle elements with no Rust implementation registered in tests/src/registry.rs: {unknown:?}");
}

#[test]
fn rust_matches_the_casadi_oracle() {
    let mut report = String::new();
    let (mut n_cases, mut n_bad) = (0, 0);
    for path in oracle_files() {
        let file = load(&path).expect("loadable oracle file");
        assert!(
            file.cases.len() >= 50,
            "{}: only {} cases (at least 50 required)",
            file.element,
            file.cases.len()
        );
        let mut bad = Vec::new();
        for case in &file.cases {
            bad.extend(compare_case(&file.element, case).unwrap_or_else(|e| panic!("{e}")));
        }
        n_cases += file.cases.len();
        n_bad += bad.len();
        for d in bad.iter().take(8) {
            report.push_str(&format!("{d}\n"));
        }
        if bad.len() > 8 {
            report.push_str(&format!(
                "{}: ... and {} more\n",
                file.element,
                bad.len() - 8
            ));
        }
    }
    assert!(
        n_bad == 0,
        "{n_bad} entries disagree with the oracle over {n_cases} cases:\n{report}"
    );
    eprintln!(
        "oracle gate: {n_cases} cases agree to relative {:e}",
        cardan_tests::oracle::RTOL
    );
}
