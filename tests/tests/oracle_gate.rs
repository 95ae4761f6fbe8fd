//! The oracle gate: every Rust primitive, joint and driver against the CasADi reference data in
//! `oracle/data/` (regenerate with `cargo xtask oracle`; CI checks they are current with
//! `cargo xtask oracle --check`). Relative tolerance 1e-12; see `cardan_tests::oracle`.

use cardan_constraints::TimeFunction;
use cardan_tests::expressions;
use cardan_tests::oracle::{compare_case, data_dir, function_kinds, load, Mismatch, OracleFile};
use cardan_tests::registry::{build, elements};

fn oracle_files() -> Vec<std::path::PathBuf> {
    let mut files: Vec<_> = std::fs::read_dir(data_dir())
        .expect("oracle/data exists")
        .map(|e| e.expect("readable entry").path())
        .filter(|p| p.extension().is_some_and(|e| e == "json"))
        .filter(|p| p.file_name().is_none_or(|n| n != expressions::FILE))
        .collect();
    files.sort();
    files
}

fn loaded() -> Vec<OracleFile> {
    oracle_files()
        .iter()
        .map(|p| load(p).expect("loadable oracle file"))
        .collect()
}

/// The element names of the Rust side (primitives, the kind table's joints, drivers) against
/// the oracle files.
fn element_mismatch(rust: &[&str], files: &[OracleFile]) -> Mismatch {
    Mismatch::between(
        rust.iter().copied(),
        files.iter().map(|f| f.element.as_str()),
    )
}

/// The time-function kinds of the Rust side against those the driver cases exercise.
fn function_mismatch(rust: &[&str], files: &[OracleFile]) -> Mismatch {
    let exercised = function_kinds(files);
    Mismatch::between(rust.iter().copied(), exercised.iter().map(String::as_str))
}

#[test]
fn every_rust_element_has_oracle_data_and_every_oracle_file_a_rust_element() {
    let files = loaded();
    let m = element_mismatch(&elements(), &files);
    assert!(m.missing.is_empty(), "Rust elements without oracle data (add them to oracle/ and run `cargo xtask oracle`): {:?}", m.missing);
    assert!(m.unknown.is_empty(), "oracle elements with no Rust implementation (joint kinds come from cardan_constraints::KINDS, the others from tests/src/registry.rs): {:?}", m.unknown);
    let m = function_mismatch(&TimeFunction::KINDS, &files);
    assert!(
        m.is_empty(),
        "time-function kinds without oracle cases / unknown in Rust: {m:?}"
    );
}

/// The gate's check can fail: a joint kind added to the table without oracle data, an oracle
/// file naming a kind that does not exist, a time-function kind no case exercises.
#[test]
fn the_gate_fails_for_a_kind_without_oracle_data_and_for_data_without_a_kind() {
    let files = loaded();
    let mut rust = elements();
    rust.push("phantom_joint");
    let m = element_mismatch(&rust, &files);
    assert_eq!(m.missing, ["phantom_joint"]);
    assert!(m.unknown.is_empty());

    let mut rust = elements();
    rust.retain(|&n| n != "revolute");
    let m = element_mismatch(&rust, &files);
    assert_eq!(m.unknown, ["revolute"]);

    // A limit measure without its oracle file.
    let without: Vec<OracleFile> = loaded()
        .into_iter()
        .filter(|f| f.element != "limit_angle")
        .collect();
    let m = element_mismatch(&elements(), &without);
    assert_eq!(m.missing, ["limit_angle"]);

    let mut kinds = TimeFunction::KINDS.to_vec();
    kinds.push("sawtooth");
    let m = function_mismatch(&kinds, &files);
    assert_eq!(m.missing, ["sawtooth"]);
}

/// Every registered name builds an element from the parameters of its first oracle case (so the
/// lists of the registry and its builder agree).
#[test]
fn every_registered_element_is_built_from_its_oracle_parameters() {
    for f in loaded() {
        let e = build(&f.element, &f.cases[0]["params"])
            .unwrap_or_else(|e| panic!("{}: {e}", f.element));
        assert_eq!(e.oracle_name(), f.element);
    }
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

/// Expression time functions: f, ḟ, f̈ of every case of `oracle/data/expressions.json` (each
/// written both as cardan text and as a CasADi expression) at relative 1e-12; the cases use
/// every function, constant and operator of the grammar.
#[test]
fn expressions_match_the_casadi_oracle() {
    let cases = expressions::load().expect("oracle/data/expressions.json loads");
    let bad: Vec<String> = cases.iter().filter_map(expressions::compare).collect();
    assert!(
        bad.is_empty(),
        "{} of {} expression cases disagree:\n{}",
        bad.len(),
        cases.len(),
        bad.join("\n")
    );
    let missing = expressions::uncovered(expressions::vocabulary(), &cases);
    assert!(
        missing.is_empty(),
        "parts of the expression grammar without oracle cases: {missing:?}"
    );
    // The coverage check can fail.
    let mut more = expressions::vocabulary();
    more.push("sawtooth");
    assert_eq!(expressions::uncovered(more, &cases), ["sawtooth"]);
}
