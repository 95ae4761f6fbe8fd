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

/// The drive's model as `cardan import` writes it (into `dir`).
fn imported(dir: &std::path::Path) -> String {
    let o = cardan(
        &["import", bent_cv().to_str().unwrap(), "-o", "bent.toml"],
        dir,
    );
    assert_eq!(o.code, 0, "{}", o.stderr);
    std::fs::read_to_string(dir.join("bent.toml")).unwrap()
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
    let toml = imported(&dir);
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

/// The same assembly without its motion, under-driven by one: the held run (least change,
/// `free_dof = "hold"`) starts from the assembly that drops the open row and solves the other
/// rows at every time (the least change over all rows cannot converge: the open row never
/// closes; it stopped at t = 0 "after 500 iterations ... a limit of its motion or a singular
/// configuration"). Nothing drives it, so every part holds still.
#[test]
fn an_inconsistent_under_driven_assembly_is_held_on_its_other_rows() {
    let dir = scratch("bent-cv-free");
    let toml = imported(&dir);
    let (head, tail) = toml.split_at(toml.find("[[driver]]").expect("the motion"));
    let toml = format!(
        "{head}{}",
        &tail[tail.find("[analysis]").unwrap()..].replacen(
            "kind = \"kinematic\"",
            "kind = \"kinematic\"\ninconsistent_joints = \"drop\"",
            1,
        )
    );
    std::fs::write(dir.join("free.toml"), toml).unwrap();
    let o = cardan(&["run", "free.toml", "-o", "out"], &dir);
    assert_eq!(o.code, 0, "{}", o.stderr);
    let json = std::fs::read_to_string(dir.join("out/run.json")).unwrap();
    for needle in [
        "THE MODEL IS INCONSISTENT",
        "1 degree of freedom no driver prescribes",
        "cannot close the inconsistent rows",
    ] {
        assert!(json.contains(needle), "missing {needle:?}: {json}");
    }
    // Held still: every row of bodies.csv after the header has the first row's poses.
    let bodies = std::fs::read_to_string(dir.join("out/bodies.csv")).unwrap();
    let rows: Vec<Vec<f64>> = bodies
        .lines()
        .skip(1)
        .map(|l| l.split(',').skip(1).map(|v| v.parse().unwrap()).collect())
        .collect();
    assert_eq!(rows.len(), 21);
    for r in &rows {
        for (a, b) in r.iter().zip(&rows[0]) {
            assert!((a - b).abs() <= 1e-12, "{a} vs {b}");
        }
    }
    let _ = std::fs::remove_dir_all(&dir);
}
