//! `[[coupler]]` input: the bundled gear train checks, and each mistake in a coupler is an error
//! at the line of the offending key (or the coupler's name), in one paragraph, without a panic.

mod common;
use common::{check_fails_at, run_text};

fn gear_train() -> String {
    let path =
        std::path::PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../examples/gear_train.toml");
    std::fs::read_to_string(path).unwrap()
}

/// The 1-based line of the first line of `text` that contains `needle`.
fn line_of(text: &str, needle: &str) -> usize {
    text.lines()
        .position(|l| l.contains(needle))
        .unwrap_or_else(|| panic!("{needle}"))
        + 1
}

/// The gear train with `from` replaced by `to`: `cardan check` fails at the line of `at` (in
/// the edited text) with a message containing every needle.
fn fails(from: &str, to: &str, at: &str, needles: &[&str]) {
    let base = gear_train();
    assert!(base.contains(from), "{from}");
    let text = base.replacen(from, to, 1);
    check_fails_at(&text, line_of(&text, at), needles);
}

#[test]
fn the_gear_train_checks_and_lists_its_couplers() {
    let o = run_text("check", &gear_train());
    assert_eq!(o.code, 0, "{}", o.stderr);
    assert!(o.stdout.contains("couplers (2)"), "{}", o.stdout);
    assert!(o.stdout.contains("degrees of freedom: 1"), "{}", o.stdout);
}

#[test]
fn coupler_mistakes_are_located() {
    fails(
        r#"joint_j = "counter_shaft""#,
        r#"joint_j = "countershaft""#,
        r#"joint_j = "countershaft""#,
        &[
            r#"coupler "stage1": unknown joint "countershaft""#,
            r#"did you mean "counter_shaft"?"#,
        ],
    );
    fails(
        "radius_i = 0.02\n",
        "radius_i = 0.0\n",
        "radius_i = 0.0",
        &[r#"coupler "stage1""#, "radius_i", "must be non-zero"],
    );
    fails(
        r#"type = "gear""#,
        r#"type = "gears""#,
        r#"type = "gears""#,
        &[r#"unknown coupler type "gears""#, r#"did you mean "gear"?"#],
    );
    fails(
        "radius_j = 0.06\n",
        "pitch = 0.06\n",
        "pitch = 0.06",
        &[r#"type = "gear" does not take "pitch" (it applies to type = "screw")"#],
    );
    fails(
        r#"name = "stage2""#,
        r#"name = "stage1""#,
        r#"name = "stage1"                # gear C"#,
        &[r#"duplicate name "stage1""#],
    );
}
