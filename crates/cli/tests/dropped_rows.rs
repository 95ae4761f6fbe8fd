//! Redundant equations dropped by the rank analysis are checked at the solution (issue 22):
//! a dropped row left violated is a warning naming the joint in the summary and run.json, or
//! an error at assembly when the joints disagree grossly; a consistent redundant model gives
//! no warning.

mod common;

use common::{cardan, scratch};
use std::path::Path;

/// A parallelogram four-bar of spatial revolutes, driven at the crank: a planar loop, so 3 of
/// its equations are redundant (the loop's out-of-plane translation and two tilts). The
/// coupler's right pin is drawn `dz` out of the plane of the others: the loop cannot close
/// (revolute axes parallel, pin heights not summing to zero), so one dropped row (the z row of
/// the last revolute's spherical part, "s") stays off by |Φ| = `dz` (the
/// kept rows hold exactly). `kind`: the analysis.
fn fourbar(dz: &str, kind: &str) -> String {
    MODEL
        .replace("{DZ}", dz)
        .replace("kind = \"kinematic\"", &format!("kind = \"{kind}\""))
}

const MODEL: &str = r#"
[model]
name = "redundant_fourbar"
units = "SI"

[ground]
points = { A = [0.0, 0.0, 0.0], B = [1.0, 0.0, 0.0] }
vectors = { x = [1.0, 0.0, 0.0], z = [0.0, 0.0, 1.0] }

[[body]]
name = "crank"
mass = 1.0
inertia = { diag = [0.1, 0.1, 0.1] }
position = [0.0, 0.25, 0.0]
points = { bottom = [0.0, -0.25, 0.0], top = [0.0, 0.25, 0.0] }
vectors = { x = [1.0, 0.0, 0.0], z = [0.0, 0.0, 1.0] }

[[body]]
name = "coupler"
mass = 1.0
inertia = { diag = [0.1, 0.1, 0.1] }
position = [0.5, 0.5, 0.0]
points = { left = [-0.5, 0.0, 0.0], right = [0.5, 0.0, {DZ}] }
vectors = { z = [0.0, 0.0, 1.0] }

[[body]]
name = "rocker"
mass = 1.0
inertia = { diag = [0.1, 0.1, 0.1] }
position = [1.0, 0.25, 0.0]
points = { bottom = [0.0, -0.25, 0.0], top = [0.0, 0.25, 0.0] }
vectors = { z = [0.0, 0.0, 1.0] }

[[joint]]
name = "A"
type = "revolute"
body_i = "ground"
point_i = "A"
axis_i = "z"
x_axis_i = "x"
body_j = "crank"
point_j = "bottom"
axis_j = "z"
x_axis_j = "x"

[[joint]]
name = "B"
type = "revolute"
body_i = "crank"
point_i = "top"
axis_i = "z"
body_j = "coupler"
point_j = "left"
axis_j = "z"

[[joint]]
name = "C"
type = "revolute"
body_i = "coupler"
point_i = "right"
axis_i = "z"
body_j = "rocker"
point_j = "top"
axis_j = "z"

[[joint]]
name = "D"
type = "revolute"
body_i = "rocker"
point_i = "bottom"
axis_i = "z"
body_j = "ground"
point_j = "B"
axis_j = "z"

[[driver]]
name = "motor"
type = "rotation"
joint = "A"
function = { kind = "polynomial", coefficients = [0.0, 1.0] }

[analysis]
kind = "kinematic"
t_end = 1.0
steps = 10
"#;

fn run(dir: &Path, text: &str) -> common::Outcome {
    std::fs::write(dir.join("model.toml"), text).unwrap();
    cardan(&["run", "model.toml", "-o", "out", "--quiet"], dir)
}

fn run_json(dir: &Path) -> serde_json::Value {
    serde_json::from_str(&std::fs::read_to_string(dir.join("out/run.json")).unwrap()).unwrap()
}

/// The one warning line of a run (and run.json's one warning), checked for the joint, the
/// equation and the residual.
fn one_dropped_row_warning(dir: &Path, o: &common::Outcome) {
    assert_eq!(o.code, 0, "{}\n{}", o.stdout, o.stderr);
    assert!(o.stdout.contains("1 warning"), "{}", o.stdout);
    let line = o
        .stdout
        .lines()
        .find(|l| l.starts_with("warning: "))
        .unwrap_or_else(|| panic!("no warning line: {}", o.stdout));
    for needle in [
        "revolute \"D\" row 2 (s)",
        "dropped as redundant",
        "|Φ| = 1.00e-7 m",
        "relative to the model's size",
        "t = ",
    ] {
        assert!(line.contains(needle), "missing {needle:?}: {line}");
    }
    let j = run_json(dir);
    assert_eq!(j["status"], "complete");
    let w = j["warnings"].as_array().unwrap();
    assert_eq!(w.len(), 1, "{j}");
    assert!(w[0].as_str().unwrap().contains("revolute \"D\""), "{j}");
}

#[test]
fn a_slightly_inconsistent_redundant_fourbar_warns_naming_the_joint() {
    let dir = scratch("dropped-slight");
    let o = run(&dir, &fourbar("1e-7", "kinematic"));
    one_dropped_row_warning(&dir, &o);
}

#[test]
fn inverse_dynamics_of_the_slightly_inconsistent_fourbar_warns_too() {
    let dir = scratch("dropped-slight-inverse");
    let o = run(&dir, &fourbar("1e-7", "inverse_dynamics"));
    one_dropped_row_warning(&dir, &o);
}

#[test]
fn a_dynamic_run_of_the_slightly_inconsistent_fourbar_warns_at_the_output_times() {
    let dir = scratch("dropped-slight-dynamic");
    let text = fourbar("1e-7", "dynamic")
        .replace("steps = 10", "integrator = \"dopri5\"\noutput_dt = 0.1");
    let o = run(&dir, &text);
    // One warning: the dropped row's, not also a constraint drift it explains.
    one_dropped_row_warning(&dir, &o);
}

#[test]
fn a_consistent_redundant_fourbar_does_not_warn() {
    let dir = scratch("dropped-consistent");
    for kind in ["kinematic", "inverse_dynamics"] {
        let o = run(&dir, &fourbar("0.0", kind));
        assert_eq!(o.code, 0, "{}\n{}", o.stdout, o.stderr);
        assert!(!o.stdout.contains("warning"), "{kind}: {}", o.stdout);
        assert!(run_json(&dir)["warnings"].as_array().unwrap().is_empty());
        std::fs::remove_dir_all(dir.join("out")).unwrap();
    }
}

#[test]
fn a_grossly_inconsistent_redundant_fourbar_fails_naming_the_joints() {
    let dir = scratch("dropped-gross");
    let o = run(&dir, &fourbar("1e-3", "kinematic"));
    assert_ne!(o.code, 0, "{}\n{}", o.stdout, o.stderr);
    for needle in [
        "redundant joints disagree",
        "over-constrained and inconsistent",
        "revolute \"D\" row 2 (s)",
        "stays off by",
        "cylindrical",
    ] {
        assert!(
            o.stderr.contains(needle),
            "missing {needle:?}: {}",
            o.stderr
        );
    }
}
