//! Issue 53, item 2: an over-constrained assembly that is inconsistent as drawn (a bent
//! two-shaft drive: a constant-velocity joint, a revolute and a cylindrical joint whose axis
//! passes 0.24 m from the joint point; `crates/asmt/tests/data/small/bent_cv.asmt`) is refused
//! with a diagnosis: the best fit of all equations, the row that stays open there and by how
//! much, and the option that runs it as OndselSolver does. With `inconsistent_joints = "drop"`
//! it runs, warning loudly at every run, and `--strict` fails it (exit 3).

mod common;
use common::{cardan, scratch};
use std::path::PathBuf;

fn bent_cv() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../asmt/tests/data/small/bent_cv.asmt")
}

#[test]
fn an_inconsistent_assembly_is_diagnosed_and_runs_only_when_asked() {
    let dir = scratch("bent-cv");
    let file = bent_cv();
    let o = cardan(&["run", file.to_str().unwrap(), "-o", "out"], &dir);
    assert_eq!(o.code, 3, "{}", o.stderr);
    for needle in [
        "over-constrained and inconsistent",
        "at its best fit",
        "stays off by 2.400e-1 m",
        "inconsistent_joints = \"drop\"",
        "cardan import",
    ] {
        assert!(
            o.stderr.contains(needle),
            "missing {needle:?}: {}",
            o.stderr
        );
    }
    // Imported, with the option: it runs, warning that the model is inconsistent.
    let o = cardan(&["import", file.to_str().unwrap(), "-o", "bent.toml"], &dir);
    assert_eq!(o.code, 0, "{}", o.stderr);
    let toml = std::fs::read_to_string(dir.join("bent.toml")).unwrap();
    let toml = toml.replacen(
        "kind = \"kinematic\"",
        "kind = \"kinematic\"\ninconsistent_joints = \"drop\"",
        1,
    );
    std::fs::write(dir.join("bent.toml"), toml).unwrap();
    let o = cardan(&["run", "bent.toml", "-o", "out"], &dir);
    assert_eq!(o.code, 0, "{}", o.stderr);
    assert!(
        o.stdout.contains("THE MODEL IS INCONSISTENT")
            || o.stderr.contains("THE MODEL IS INCONSISTENT"),
        "{}{}",
        o.stdout,
        o.stderr
    );
    let json = std::fs::read_to_string(dir.join("out/run.json")).unwrap();
    assert!(json.contains("THE MODEL IS INCONSISTENT"), "{json}");
    let o = cardan(&["run", "bent.toml", "-o", "out2", "--strict"], &dir);
    assert_eq!(o.code, 3, "{}", o.stderr);
    let _ = std::fs::remove_dir_all(&dir);
}
