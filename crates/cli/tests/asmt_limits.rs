//! `RotationLimit` and `TranslationLimit` of ASMT files (FreeCAD's joint limits; issue 48):
//! imported as `[[limit]]` tables on the joint's angle or slide, enforced in every analysis
//! (OndselSolver applies them only while dragging). The bundled piston (OndselSolver's engine
//! example) with limits added: its crank turns at θ = 2πt, so a limit on the crank's angle is
//! reached at a time known in closed form.

mod common;

use common::{cardan, scratch};

/// examples/asmt/piston.asmt with one limit block (`kind`, on `joint`, `Limit` = `value`,
/// `Type` = `ty`) in its ConstraintSets.
fn piston_with(kind: &str, joint: &str, value: &str, ty: &str) -> String {
    let path = std::path::PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../../examples/asmt/piston.asmt");
    let text = std::fs::read_to_string(path).unwrap();
    let block = format!(
        "\t\tLimits\n\t\t\t{kind}\n\t\t\t\tName\n\t\t\t\t\tStop\n\t\t\t\tMotionJoint\n\t\t\t\t\t\
         /Assembly1/{joint}\n\t\t\t\tLimit\n\t\t\t\t\t{value}\n\t\t\t\tType\n\t\t\t\t\t{ty}\n\
         \t\t\t\tTol\n\t\t\t\t\t1.0e-9\n"
    );
    let at = text.find("\t\tGeneralConstraintSets\n").unwrap();
    format!("{}{block}{}", &text[..at], &text[at..])
}

fn run(cmd: &str, text: &str) -> common::Outcome {
    let dir = scratch("asmt-limits");
    std::fs::write(dir.join("piston.asmt"), text).unwrap();
    match cmd {
        "run" => cardan(&["run", "piston.asmt", "-o", "out", "--quiet"], &dir),
        "import" => cardan(&["import", "piston.asmt", "-o", "piston.toml"], &dir),
        other => cardan(&[other, "piston.asmt"], &dir),
    }
}

#[test]
fn a_rotation_limit_stops_the_driven_crank_where_the_closed_form_says() {
    // θ = 2π t reaches 3 rad at t = 3/(2π).
    let text = piston_with("RotationLimit", "Joint1", "3.0", "=<");
    let import = run("import", &text);
    assert_eq!(import.code, 0, "{}", import.stderr);
    let toml = std::fs::read_to_string(import.dir.join("piston.toml")).unwrap();
    assert!(
        toml.contains(
            "[[limit]]   # /Assembly1/Stop (line 363)\nname = \"Stop\"\njoint = \"Joint1\"\n\
             coordinate = \"angle\"\nupper = 3.0\n"
        ),
        "{toml}"
    );
    let o = run("run", &text);
    assert_eq!(o.code, 3, "{}", o.stderr);
    let message = o.stderr.lines().next().unwrap();
    let t: f64 = message
        .split("reached at t = ")
        .nth(1)
        .and_then(|r| r.split(':').next())
        .and_then(|v| v.parse().ok())
        .unwrap_or_else(|| panic!("{message}"));
    assert!((t - 3.0 / std::f64::consts::TAU).abs() < 1e-9, "{t}");
    assert!(
        message.contains("joint \"Joint1\" has angle = 3"),
        "{message}"
    );
    // The check lists it.
    let c = run("check", &text);
    assert_eq!(c.code, 0, "{}", c.stderr);
    assert!(c.stdout.contains("limits (1)"), "{}", c.stdout);
}

#[test]
fn a_translation_limit_bounds_the_pistons_slide_from_below_or_above() {
    // The slide runs from 0.975 down to −0.097 m and up to 1.499 m over the run.
    let o = run(
        "run",
        &piston_with("TranslationLimit", "Joint4", "1.2", "=<"),
    );
    assert_eq!(o.code, 3, "{}", o.stderr);
    assert!(
        o.stderr.contains("limit \"Stop\" reached at t = 0.55"),
        "{}",
        o.stderr
    );
    assert!(o.stderr.contains("at its upper bound 1.2"), "{}", o.stderr);
    let o = run(
        "run",
        &piston_with("TranslationLimit", "Joint4", "0.0", "=>"),
    );
    assert_eq!(o.code, 3, "{}", o.stderr);
    assert!(o.stderr.contains("at its lower bound 0"), "{}", o.stderr);
    // Inside the range: the run is the plain piston's.
    let o = run(
        "run",
        &piston_with("TranslationLimit", "Joint4", "2.0", "=<"),
    );
    assert_eq!(o.code, 0, "{}", o.stderr);
}

#[test]
fn a_translation_limit_is_in_the_files_unit_under_units_mm() {
    // With --units mm every length of the file is in millimetres, the limit's too: the same
    // numbers, the same crossing (had the bound been read in metres, 1.2 m = 1200 mm would
    // never be reached by a slide of at most 1.499 mm).
    let dir = scratch("asmt-limits-mm");
    let text = piston_with("TranslationLimit", "Joint4", "1.2", "=<");
    std::fs::write(dir.join("piston.asmt"), text).unwrap();
    let o = cardan(
        &[
            "run",
            "piston.asmt",
            "--units",
            "mm",
            "-o",
            "out",
            "--quiet",
        ],
        &dir,
    );
    assert_eq!(o.code, 3, "{}", o.stderr);
    assert!(
        o.stderr.contains("limit \"Stop\" reached at t = 0.55"),
        "{}",
        o.stderr
    );
    assert!(
        o.stderr.contains("at its upper bound 1.2 mm"),
        "{}",
        o.stderr
    );
    // The imported model file says the bound in the file's unit.
    let o = cardan(
        &[
            "import",
            "piston.asmt",
            "--units",
            "mm",
            "-o",
            "piston.toml",
        ],
        &dir,
    );
    assert_eq!(o.code, 0, "{}", o.stderr);
    let toml = std::fs::read_to_string(dir.join("piston.toml")).unwrap();
    assert!(toml.contains("units = \"mm\""), "{toml}");
    assert!(toml.contains("upper = 1.2"), "{toml}");
}

#[test]
fn limit_mistakes_in_asmt_are_errors_at_their_line() {
    let cases = [
        (
            piston_with("TranslationLimit", "Joint1", "0.5", "=<"),
            "piston.asmt:363:",
            "its joint \"Joint1\" is a revolute, which has no slide to limit",
        ),
        (
            // Equal at t = 0 and t = 1, and not constant.
            piston_with("TranslationLimit", "Joint4", "0.5+time*(time-1)", "=<"),
            "piston.asmt:369:",
            "a limit must be a finite constant",
        ),
        (
            piston_with("TranslationLimit", "Joint4", "0.5", "<>"),
            "piston.asmt:371:",
            "Type of limit \"Stop\" is \"<>\"; expected =< (at most the limit) or => (at least)",
        ),
        (
            piston_with("TranslationLimit", "Joint4", "0.5*time", "=<"),
            "piston.asmt:369:",
            "a limit must be a finite constant",
        ),
        (
            piston_with("TranslationLimit", "Joint9", "0.5", "=<"),
            "piston.asmt:",
            "no joint has the path \"/Assembly1/Joint9\"",
        ),
        (
            piston_with("TranslationLimit", "Joint4", "0.5", "=<"),
            "piston.asmt.toml:",
            "the drawn pose violates its upper bound",
        ),
    ];
    for (text, at, needle) in cases {
        let o = run("check", &text);
        assert_eq!(o.code, 1, "{needle}: {}", o.stderr);
        assert!(o.stderr.starts_with(at), "{at}: {}", o.stderr);
        assert!(o.stderr.contains(needle), "{needle}: {}", o.stderr);
    }
}
