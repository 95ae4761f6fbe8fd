//! ASMT files on the command line: `cardan check` and `cardan run` take `.asmt` directly,
//! `cardan import` writes an equivalent TOML model (issue 22).

mod common;

use common::{cardan, scratch};
use std::path::PathBuf;

const FILES: [&str; 10] = [
    "crank_slider",
    "fourbar",
    "piston",
    "00backhoe",
    "parm",
    "dxfmotion",
    "circular",
    "wobpump",
    "rackscrew",
    "Gears",
];

fn asmt(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../asmt/tests/data")
        .join(format!("{name}.asmt"))
}

#[test]
fn every_testapp_file_checks_and_imports() {
    for name in FILES {
        let dir = scratch("asmt");
        let file = asmt(name);
        let check = cardan(&["check", file.to_str().unwrap()], &dir);
        assert_eq!(check.code, 0, "{name}: {}{}", check.stdout, check.stderr);
        let import = cardan(
            &["import", file.to_str().unwrap(), "-o", "model.toml"],
            &dir,
        );
        assert_eq!(import.code, 0, "{name}: {}", import.stderr);
        let text = std::fs::read_to_string(dir.join("model.toml")).unwrap();
        assert!(text.contains("# /"), "{name}: paths traced in comments");
        // The imported model checks the same: same report but for the file name.
        let again = cardan(&["check", "model.toml"], &dir);
        assert_eq!(again.code, 0, "{name}: {}", again.stderr);
        let strip = |s: &str| {
            s.lines()
                .filter(|l| !l.contains(".asmt") && !l.contains("model.toml"))
                .collect::<Vec<_>>()
                .join("\n")
        };
        assert_eq!(strip(&check.stdout), strip(&again.stdout), "{name}");
    }
}

#[test]
fn run_takes_an_asmt_file() {
    let dir = scratch("asmt-run");
    let file = asmt("crank_slider");
    let run = cardan(
        &["run", file.to_str().unwrap(), "-o", "out", "--quiet"],
        &dir,
    );
    assert_eq!(run.code, 0, "{}{}", run.stdout, run.stderr);
    // The solved file reads back with cardan's reader, one column per output time.
    let solved = std::fs::read_to_string(dir.join("out/crank_slider.solved.asmt")).unwrap();
    let doc = cardan_asmt::read(&solved).unwrap();
    let series = doc.series.unwrap();
    assert_eq!(series.times.len(), 101);
    assert_eq!(series.items.len(), 1 + doc.parts.len());
    // Written inside the directory's atomic commit: listed in run.json with the other outputs.
    let report = std::fs::read_to_string(dir.join("out/run.json")).unwrap();
    assert!(report.contains("crank_slider.solved.asmt"), "{report}");
    // A second run replaces the directory (the solved file is a run's own output).
    let again = cardan(
        &["run", file.to_str().unwrap(), "-o", "out", "--quiet"],
        &dir,
    );
    assert_eq!(again.code, 0, "{}{}", again.stdout, again.stderr);
    assert!(dir.join("out/crank_slider.solved.asmt").exists());
}

#[test]
fn a_bad_asmt_file_is_an_error_at_its_line() {
    let dir = scratch("asmt-bad");
    let text = std::fs::read_to_string(asmt("piston")).unwrap().replacen(
        "\t\t\tRevoluteJoint",
        "\t\t\tHingeJoint",
        1,
    );
    let line = text.lines().position(|l| l == "\t\t\tHingeJoint").unwrap() + 1;
    std::fs::write(dir.join("bad.asmt"), text).unwrap();
    let out = cardan(&["check", "bad.asmt"], &dir);
    assert_eq!(out.code, 1, "{}", out.stderr);
    assert!(
        out.stderr.contains(&format!("bad.asmt:{line}:1")),
        "{}",
        out.stderr
    );
    assert!(out.stderr.contains("HingeJoint"), "{}", out.stderr);
}

/// `--analysis inverse_dynamics`: the imported model asks for inverse dynamics on the file's
/// grid and runs (wobpump: every part has a mass).
#[test]
fn import_for_inverse_dynamics() {
    let dir = scratch("asmt-inverse");
    let file = asmt("wobpump");
    let import = cardan(
        &[
            "import",
            file.to_str().unwrap(),
            "-o",
            "wob.toml",
            "--analysis",
            "inverse_dynamics",
        ],
        &dir,
    );
    assert_eq!(import.code, 0, "{}", import.stderr);
    let text = std::fs::read_to_string(dir.join("wob.toml")).unwrap();
    assert!(text.contains("kind = \"inverse_dynamics\""));
    assert!(text.contains("name = \"wobpump\""));
    let run = cardan(&["run", "wob.toml", "-o", "out", "--quiet"], &dir);
    assert_eq!(run.code, 0, "{}{}", run.stdout, run.stderr);
    assert!(dir.join("out/driver_efforts.csv").exists());
}
