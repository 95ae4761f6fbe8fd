//! Bad input, each a clear error: the real binary is run on a broken model file, and each test
//! checks the exit code (≠ 0), that nothing panicked, and what the message says (with file, line
//! and column where the problem is in the file).

use std::path::PathBuf;

mod common;
use common::{cardan, edited, run_text, Outcome, BASE};

fn scratch() -> PathBuf {
    common::scratch("bad")
}

/// BASE with `from` replaced by `to` (which must occur).
/// Runs the edited model and checks a failure whose message starts with `model.toml:LINE:COL`
/// and contains every `needle`.
fn fails_at(from: &str, to: &str, line_col: &str, needles: &[&str]) -> Outcome {
    let want = format!("model.toml:{line_col}: error: ");
    let o = common::fails_with("run", &edited(from, to), &want, needles);
    assert_eq!(
        cardan_model::diag::message_paragraph(&o.stderr)
            .lines()
            .count(),
        1,
        "one paragraph: {}",
        o.stderr
    );
    o
}

#[test]
fn the_base_model_runs() {
    let o = run_text("run", BASE);
    assert_eq!(o.code, 0, "{}", o.stderr);
    assert!(o.stdout.contains("11 steps"), "{}", o.stdout);
    let csv = std::fs::read_to_string(o.dir.join("out/points.csv")).unwrap();
    assert!(csv.starts_with("t [s],crank.O.x [m],"), "{csv}");
    assert!(o.dir.join("out/joints.svg").exists());
}

#[test]
fn invalid_toml_reports_line_and_column() {
    fails_at(r#"name = "crank""#, r#"name = "crank"#, "2:14", &["string"]);
    fails_at("steps = 10", "steps = = 10", "37:9", &["extra `=`"]);
}

#[test]
fn duplicate_toml_key_is_located() {
    fails_at(
        "points = { O = [0.0, 0.0, 0.0] }",
        "points = { O = [0.0, 0.0, 0.0], O = [1.0, 0.0, 0.0] }",
        "5:33",
        &["duplicate key \"O\"", "[ground]"],
    );
    // Issue 27, item 11: the key and the table are named (the message was "duplicate key").
    fails_at(
        "mass = 1.0",
        "mass = 1.0\nmass = 2.0",
        "11:1",
        &[
            "duplicate key \"mass\" in [[body]]",
            "first given at line 10",
        ],
    );
}

/// Issue 27, item 11: `[body]` where `[[body]]` is meant read "invalid type: map, expected a
/// sequence"; an integer beyond i64 read "as i128, expected i64".
#[test]
fn single_table_headers_and_oversized_integers_get_a_hint() {
    fails_at("[[body]]", "[body]", "8:1", &["[body]", "write [[body]]"]);
    fails_at(
        "steps = 10",
        "steps = 99999999999999999999999",
        "37:9",
        &["steps = 99999999999999999999999", "between 1 and 10000000"],
    );
}

#[test]
fn unreadable_file() {
    let dir = scratch();
    let o = cardan(&["run", "missing.toml"], &dir);
    assert_eq!(o.code, 1);
    assert!(
        o.stderr
            .contains("cannot read the model file missing.toml: no such file"),
        "{}",
        o.stderr
    );
    let o = cardan(&["check", "."], &dir);
    assert_eq!(o.code, 1);
    assert!(
        o.stderr.contains("cannot read the model file"),
        "{}",
        o.stderr
    );
    std::fs::write(dir.join("bin.toml"), [0xff, 0xfe, 0x00, 0x41]).unwrap();
    let o = cardan(&["check", "bin.toml"], &dir);
    assert_eq!(o.code, 1);
    assert!(o.stderr.contains("not valid UTF-8"), "{}", o.stderr);
}

#[test]
fn unknown_key_suggests_nearest() {
    fails_at(
        "mass = 1.0",
        "mas = 1.0",
        "10:1",
        &[r#"unknown key "mas""#, r#"did you mean "mass"?"#],
    );
    fails_at(
        "t_end = 1.0",
        "tend = 1.0",
        "36:1",
        &[r#"did you mean "t_end"?"#],
    );
    fails_at(
        "[analysis]",
        "[analysys]",
        "34:2",
        &[r#"did you mean "analysis"?"#],
    );
}

#[test]
fn unknown_body_point_vector_joint_suggest_nearest() {
    fails_at(
        r#"body_j = "crank""#,
        r#"body_j = "crnak""#,
        "22:10",
        &[
            r#"joint "pivot": unknown body "crnak""#,
            r#"did you mean "crank"?"#,
        ],
    );
    fails_at(
        r#"point_j = "O""#,
        r#"point_j = "tpi""#,
        "23:11",
        &[
            r#"body "crank" has no point "tpi""#,
            r#"did you mean "tip"?"#,
        ],
    );
    fails_at(
        r#"axis_j = "z""#,
        r#"axis_j = "zz""#,
        "24:10",
        &[r#"has no vector "zz""#, r#"did you mean "z"?"#],
    );
    fails_at(
        r#"joint = "pivot""#,
        r#"joint = "pivto""#,
        "31:9",
        &[
            r#"driver "motor": unknown joint "pivto""#,
            r#"did you mean "pivot"?"#,
        ],
    );
    let o = fails_at(
        r#"type = "revolute""#,
        r#"type = "revolut""#,
        "18:8",
        &[r#"did you mean "revolute"?"#],
    );
    // Under the message: the line of the file with the value underlined.
    let excerpt: Vec<&str> = o.stderr.trim_end().lines().skip(1).collect();
    assert_eq!(
        excerpt,
        ["   |", r#"18 | type = "revolut""#, "   |        ^^^^^^^^^"],
        "{}",
        o.stderr
    );
}

#[test]
fn duplicate_names() {
    fails_at(
        "[[joint]]",
        "[[body]]\nname = \"crank\"\n\n[[joint]]",
        "17:8",
        &[r#"duplicate body name "crank""#, "line 9"],
    );
    fails_at(
        "[analysis]",
        "[[driver]]\nname = \"pivot\"\ntype = \"rotation\"\njoint = \"pivot\"\nfunction = { kind = \"constant\", value = 0.0 }\n\n[analysis]",
        "35:8",
        &[r#"duplicate name "pivot""#],
    );
    fails_at(
        "vectors = { z = [0.0, 0.0, 1.0], x = [1.0, 0.0, 0.0] }\n\n[[joint]]",
        "vectors = { z = [0.0, 0.0, 1.0], x = [1.0, 0.0, 0.0] }\nglobal_points = { O = [0.0, 0.0, 0.0] }\n\n[[joint]]",
        "15:19",
        &[r#"duplicate point "O" on body "crank""#],
    );
}

#[test]
fn nan_infinite_and_absurd_numbers() {
    fails_at(
        "mass = 1.0",
        "mass = nan",
        "10:8",
        &["mass of body \"crank\" is NaN"],
    );
    fails_at(
        "position = [0.5, 0.0, 0.0]",
        "position = [0.5, -inf, 0.0]",
        "12:18",
        &["position of body \"crank\" y is infinite"],
    );
    fails_at(
        "position = [0.5, 0.0, 0.0]",
        "position = [1e308, 0.0, 0.0]",
        "12:13",
        &["beyond the limit of"],
    );
    fails_at(
        "t_end = 1.0",
        "t_end = 1e300",
        "36:9",
        &["t_end", "beyond the limit of"],
    );
    fails_at(
        "coefficients = [0.0, 1.0]",
        "coefficients = [0.0, nan]",
        "32:56",
        &["coefficients[1] is NaN"],
    );
}

/// Issue 27, item 12: one blanket limit (|x| ≤ 1e9 on every number) refused legitimate SI
/// values (a ship's inertia, a contact stiffness) and let absurd lengths through. Each
/// quantity now has its own SI bound (`cardan_mechanism::sanity::Quantity`).
#[test]
fn magnitudes_are_checked_per_quantity() {
    // A 10 000 t body with a ship's inertia: legitimate SI values beyond 1e9.
    let heavy = edited(
        "mass = 1.0\ninertia = { diag = [0.01, 0.1, 0.1] }",
        "mass = 1e7\ninertia = { diag = [2e10, 3e10, 3e10] }",
    );
    let o = run_text("check", &heavy);
    assert_eq!(o.code, 0, "{}", o.stderr);
    // A length of 1e8 m (100 000 km) is a typo, though below the old blanket limit.
    fails_at(
        "position = [0.5, 0.0, 0.0]",
        "position = [1e8, 0.0, 0.0]",
        "12:13",
        &["position of body \"crank\" x = 1e8 m", "length", "1e7 m"],
    );
    fails_at(
        "mass = 1.0",
        "mass = 1e11",
        "10:8",
        &["mass of body \"crank\" = 1e11 kg", "1e10 kg"],
    );
}

#[test]
fn zero_length_axes() {
    fails_at(
        "vectors = { z = [0.0, 0.0, 1.0], x = [1.0, 0.0, 0.0] }\n\n[[joint]]",
        "vectors = { z = [0.0, 0.0, 0.0] }\n\n[[joint]]",
        "14:17",
        &[r#"vector "z" of body "crank" has zero length"#],
    );
    fails_at(
        "position = [0.5, 0.0, 0.0]",
        "position = [0.5, 0.0, 0.0]\norientation = { axis = [0.0, 0.0, 0.0], angle = 1.0 }",
        "13:24",
        &["orientation axis has zero length"],
    );
}

#[test]
fn bad_mass_and_inertia() {
    fails_at(
        "mass = 1.0",
        "mass = -2.0",
        "10:8",
        &["body \"crank\": mass must be positive, got -2 kg"],
    );
    fails_at(
        "inertia = { diag = [0.01, 0.1, 0.1] }",
        "inertia = { diag = [0.01, 0.1, -0.1] }",
        "11:11",
        &["not positive definite"],
    );
    fails_at(
        "inertia = { diag = [0.01, 0.1, 0.1] }",
        "inertia = [[0.01, 0.0, 0.0], [0.05, 0.1, 0.0], [0.0, 0.0, 0.1]]",
        "11:11",
        &["not symmetric"],
    );
    fails_at(
        "inertia = { diag = [0.01, 0.1, 0.1] }",
        "inertia = [[0.01, 0.0], [0.0, 0.1]]",
        "11:11",
        &["3×3 matrix"],
    );
    // Issue 27, item 8: no rigid body has these principal moments (0.3 > 0.1 + 0.1).
    fails_at(
        "inertia = { diag = [0.01, 0.1, 0.1] }",
        "inertia = { diag = [0.3, 0.1, 0.1] }",
        "11:11",
        &["body \"crank\"", "triangle inequality", "0.3"],
    );
}

#[test]
fn joint_from_a_body_to_itself() {
    fails_at(
        r#"body_i = "ground""#,
        r#"body_i = "crank""#,
        "22:10",
        &[r#"joint "pivot" connects body "crank" to itself"#],
    );
}

#[test]
fn too_few_or_too_many_drivers() {
    let start = BASE.find("[[driver]]").unwrap();
    let end = BASE.find("[analysis]").unwrap();
    let none = format!("{}{}", &BASE[..start], &BASE[end..]);
    for cmd in ["run", "check"] {
        let o = run_text(cmd, &none);
        assert_eq!(o.code, 1, "{}", o.stderr);
        assert!(
            o.stderr
                .contains("the joints leave 1 DOF, but the file has 0 drivers"),
            "{}",
            o.stderr
        );
        assert!(o.stderr.contains("add 1 driver"), "{}", o.stderr);
    }
    let two = edited(
        "[analysis]",
        "[[driver]]\nname = \"motor2\"\ntype = \"rotation\"\njoint = \"pivot\"\nfunction = { kind = \"constant\", value = 0.0 }\n\n[analysis]",
    );
    let o = run_text("run", &two);
    assert_eq!(o.code, 1);
    assert!(
        o.stderr.starts_with("model.toml:29:8: error: "),
        "{}",
        o.stderr
    );
    assert!(
        o.stderr
            .contains("2 drivers (motor, motor2); remove 1 driver"),
        "{}",
        o.stderr
    );
}

/// Two cranks joined by a coupler of 3 m whose pivots are 1 m apart and whose cranks are 0.5 m
/// long: the loop cannot close.
#[test]
fn assembly_that_cannot_close_names_the_open_joint() {
    let text = BASE.replacen(
        "[[driver]]",
        r#"[[body]]
name = "rocker"
position = [1.5, 0.0, 0.0]
points = { O = [-0.5, 0.0, 0.0], tip = [0.5, 0.0, 0.0] }
vectors = { z = [0.0, 0.0, 1.0] }

[[joint]]
name = "rocker_pivot"
type = "revolute"
body_i = "ground"
point_i = "P"
axis_i = "z"
body_j = "rocker"
point_j = "tip"
axis_j = "z"

[[joint]]
name = "coupler"
type = "spherical_spherical"
body_i = "crank"
point_i = "tip"
body_j = "rocker"
point_j = "O"
length = 3.0

[[driver]]"#,
        1,
    );
    let text = text.replacen(
        "points = { O = [0.0, 0.0, 0.0] }",
        "points = { O = [0.0, 0.0, 0.0], P = [2.0, 0.0, 0.0] }",
        1,
    );
    let o = run_text("run", &text);
    assert_eq!(o.code, 3, "{}", o.stderr);
    assert!(o.stderr.contains("cannot be assembled"), "{}", o.stderr);
    assert!(o.stderr.contains("\"coupler\" (|Φ| = "), "{}", o.stderr);
    let line: usize = o.stderr.split(':').nth(1).unwrap().parse().unwrap();
    let want = text[..text.find("name = \"coupler\"").unwrap()]
        .lines()
        .count()
        + 1;
    assert_eq!(line, want, "{}", o.stderr);
}

/// The crank tip's x coordinate is pushed to x = t: at t = 1 the crank is stretched along x
/// (the Jacobian is singular), after that no position exists.
#[test]
fn singular_configuration_mid_run_writes_partial_results() {
    let text = edited(
        "type = \"rotation\"\njoint = \"pivot\"",
        "type = \"coordinate\"\nbody = \"crank\"\npoint = \"tip\"\ncoordinate = \"x\"",
    )
    .replacen(
        "position = [0.5, 0.0, 0.0]",
        "position = [0.0, 0.5, 0.0]\norientation = { axis = [0.0, 0.0, 1.0], angle = 1.5707963267948966 }",
        1,
    )
    .replacen("t_end = 1.0\nsteps = 10", "t_end = 2.0\nsteps = 100", 1);
    let o = run_text("run", &text);
    assert_eq!(o.code, 3, "{}", o.stderr);
    for needle in [
        // The failed step is subdivided down to 1/1024 of it: the run stops just past the
        // limit of the motion at t = 1 s, not at the next output time.
        "at t = 1.00001953125 s",
        "At the last solved time t = 1 s the constraint Jacobian was singular",
        "dependent equations: ",
        "coordinate_driver \"push\"",
        "revolute \"pivot\"",
        "results up to t = 1 s (51 steps) were written to out",
    ] {
        let needle = needle.replace("\"push\"", "\"motor\"");
        assert!(
            o.stderr.contains(&needle),
            "missing {needle:?}: {}",
            o.stderr
        );
    }
    let csv = std::fs::read_to_string(o.dir.join("out/points.csv")).unwrap();
    let (_, rows) = cardan_model::table::parse_csv(&csv).unwrap();
    assert_eq!(rows.len(), 51);
    assert!((rows[50][0] - 1.0).abs() < 1e-12);
    // The tip reached x = 1 (stretched), within the accuracy of a singular root.
    assert!((rows[50][4] - 1.0).abs() < 1e-6, "{:?}", rows[50]);
    assert!(o.stdout.contains("51 steps"), "{}", o.stdout);
}

#[test]
fn usage_errors_do_not_panic() {
    let dir = scratch();
    let o = cardan(&["frobnicate"], &dir);
    assert_eq!(o.code, 2);
    let o = cardan(&["run"], &dir);
    assert_eq!(o.code, 2);
    let o = cardan(&["eval", "x.toml", "--t", "abc"], &dir);
    assert_eq!(o.code, 2);
}

#[test]
fn check_and_eval_describe_the_model() {
    let o = run_text("check", BASE);
    assert_eq!(o.code, 0, "{}", o.stderr);
    for needle in [
        "pivot",
        "revolute",
        "ground – crank",
        "degrees of freedom: 1",
        "redundant equations: none",
        "1 driver for 1 DOF: ok",
    ] {
        assert!(
            o.stdout.contains(needle),
            "missing {needle:?}: {}",
            o.stdout
        );
    }
    let o = run_text("eval", BASE);
    assert_eq!(o.code, 0, "{}", o.stderr);
    for needle in [
        "Φ",
        "ν",
        "γ#",
        "Jacobian Φ_v pattern",
        "rrrwww",
        "Jacobian Φ_v values",
        "crank.ω'.z",
    ] {
        assert!(
            o.stdout.contains(needle),
            "missing {needle:?}: {}",
            o.stdout
        );
    }
}

/// BASE as `kind = "inverse_dynamics"` with `edits` applied; `cardan run` and `cardan check`
/// both fail with exit code 1 at `line_col` with every needle, in one paragraph.
fn inverse_fails_at(edits: &[(&str, &str)], line_col: &str, needles: &[&str]) {
    let mut text = edited("kind = \"kinematic\"", "kind = \"inverse_dynamics\"");
    for (from, to) in edits {
        assert!(text.contains(from), "{from}");
        text = text.replacen(from, to, 1);
    }
    for cmd in ["run", "check"] {
        let o = run_text(cmd, &text);
        assert_eq!(o.code, 1, "{cmd}: {}{}", o.stdout, o.stderr);
        let want = format!("model.toml:{line_col}: error: ");
        assert!(
            o.stderr.starts_with(&want),
            "{cmd}: want {want}, got: {}",
            o.stderr
        );
        for n in needles {
            assert!(
                o.stderr.contains(n),
                "{cmd}: missing {n:?} in: {}",
                o.stderr
            );
        }
        assert_eq!(
            cardan_model::diag::message_paragraph(&o.stderr)
                .lines()
                .count(),
            1,
            "{}",
            o.stderr
        );
        assert!(!o.dir.join("out").exists(), "{cmd}: nothing is written");
        // A missing mass is found by the run only (check validates the kinematic model).
        if needles.iter().any(|n| n.contains("needs a mass")) {
            break;
        }
    }
}

const DRIVER: &str = "[[driver]]\nname = \"motor\"\ntype = \"rotation\"\njoint = \"pivot\"\n\
                      function = { kind = \"polynomial\", coefficients = [0.0, 1.0] }\n";

#[test]
fn inverse_dynamics_needs_a_fully_driven_mechanism() {
    // No driver (located at [analysis] kind): the message says how many DOF the joints leave.
    inverse_fails_at(
        &[(DRIVER, "")],
        "30:8",
        &[
            "inverse dynamics needs a fully driven mechanism",
            "the joints leave 1 DOF and the file has 0 drivers (none)",
            "add 1 driver",
        ],
    );
    // One driver too many, named.
    inverse_fails_at(
        &[(
            "[analysis]",
            "[[driver]]\nname = \"brake\"\ntype = \"rotation\"\njoint = \"pivot\"\n\
             function = { kind = \"constant\", value = 0.0 }\n\n[analysis]",
        )],
        "29:8",
        &[
            "the joints leave 1 DOF and the file has 2 drivers (motor, brake)",
            "remove 1 driver",
        ],
    );
    // A cylindrical joint leaves a slide free.
    inverse_fails_at(
        &[("type = \"revolute\"", "type = \"cylindrical\"")],
        "29:8",
        &[
            "the joints leave 2 DOF and the file has 1 driver (motor)",
            "add 1 driver",
        ],
    );
    // A structure: nothing to drive.
    inverse_fails_at(
        &[(DRIVER, ""), ("type = \"revolute\"", "type = \"fixed\"")],
        "30:8",
        &[
            "the joints leave 0 DOF and the file has 0 drivers (none)",
            "structure",
        ],
    );
}

#[test]
fn inverse_dynamics_needs_masses() {
    inverse_fails_at(
        &[("mass = 1.0\n", "")],
        "9:8",
        &[
            "inverse dynamics: body \"crank\"",
            "needs a mass and an inertia tensor",
        ],
    );
    inverse_fails_at(
        &[("inertia = { diag = [0.01, 0.1, 0.1] }\n", "")],
        "9:8",
        &[
            "inverse dynamics: body \"crank\"",
            "needs a mass and an inertia tensor",
        ],
    );
}

#[test]
fn inverse_dynamics_rejects_integrator_keys() {
    inverse_fails_at(
        &[("t_end = 1.0", "rtol = 1e-6\nt_end = 1.0")],
        "36:1",
        &[
            "kind = \"inverse_dynamics\" does not take \"rtol\" (it applies to kind = \"dynamic\")",
            "it takes \"t_start\", \"t_end\", \"steps\", \"dt\", \"position_tolerance\"",
        ],
    );
    inverse_fails_at(
        &[("steps = 10", "output_dt = 0.1")],
        "37:1",
        &["does not take \"output_dt\" (it applies to kind = \"dynamic\": the output step of a kinematic"],
    );
    inverse_fails_at(
        &[("\"inverse_dynamics\"", "\"inverse-dynamics\"")],
        "35:8",
        &["did you mean \"inverse_dynamics\""],
    );
}

/// As `singular_configuration_mid_run_writes_partial_results`, as inverse dynamics: the efforts
/// up to the last solved time are written (the force grows without bound near the stretched
/// position), and the exit code is 3.
#[test]
fn inverse_dynamics_mid_run_failure_writes_partial_results() {
    let text = edited(
        "type = \"rotation\"\njoint = \"pivot\"",
        "type = \"coordinate\"\nbody = \"crank\"\npoint = \"tip\"\ncoordinate = \"x\"",
    )
    .replacen(
        "position = [0.5, 0.0, 0.0]",
        "position = [0.0, 0.5, 0.0]\norientation = { axis = [0.0, 0.0, 1.0], angle = 1.5707963267948966 }",
        1,
    )
    .replacen(
        "kind = \"kinematic\"\nt_end = 1.0\nsteps = 10",
        "kind = \"inverse_dynamics\"\nt_end = 2.0\nsteps = 100",
        1,
    );
    let o = run_text("run", &text);
    assert_eq!(o.code, 3, "{}", o.stderr);
    assert!(
        o.stderr.contains("at t = 1.00001953125 s")
            && o.stderr
                .contains("results up to t = 1 s (51 steps) were written to out"),
        "{}",
        o.stderr
    );
    let csv = std::fs::read_to_string(o.dir.join("out/driver_efforts.csv")).unwrap();
    let (h, rows) = cardan_model::table::parse_csv(&csv).unwrap();
    assert_eq!(h, ["t [s]", "motor.force [N]"]);
    assert_eq!(rows.len(), 51);
    assert!((rows[50][0] - 1.0).abs() < 1e-12);
    // No gravity, no force at rest: the effort is the crank's inertia alone, growing as the
    // tip speed does near the stretched position.
    assert!(
        rows[40][1].abs() > rows[10][1].abs(),
        "{:?} {:?}",
        rows[10],
        rows[40]
    );
}

/// A rotation driver on a joint without x axes: the angle would be measured from a hidden
/// zero, so the file is refused at the driver, naming the joint and the keys to add.
#[test]
fn driven_joint_without_x_axes_is_refused() {
    // Located at the driver's `joint` key (the builder's error names its site).
    fails_at(
        "x_axis_i = \"x\"\nx_axis_j = \"x\"\n",
        "",
        "29:9",
        &[
            "driver \"motor\"",
            "joint \"pivot\"",
            "x_axis_i",
            "x_axis_j",
        ],
    );
}

/// Issue 27, item 11: a driver whose value overflows at the requested time was reported as an
/// assembly failure of nothing ("these joints/drivers stay open: .") by `eval --t 1e308`, and
/// as "non-finite value ... in the residual of equation 5" by a run. Both now name the driver,
/// its line and the time.
#[test]
fn a_driver_value_that_is_not_finite_names_the_driver() {
    let text = edited("coefficients = [0.0, 1.0]", "coefficients = [0.0, 10.0]");
    let dir = scratch();
    std::fs::write(dir.join("model.toml"), &text).unwrap();
    let o = cardan(&["eval", "model.toml", "--t", "1e308"], &dir);
    assert_eq!(o.code, 1, "{}", o.stderr);
    for n in [
        "model.toml:29:8: error:",
        "driver \"motor\"",
        "not finite at t = 1e308 s",
    ] {
        assert!(o.stderr.contains(n), "missing {n:?} in: {}", o.stderr);
    }
    // A polynomial far beyond any angle within the run's time span (it used to fail with
    // "non-finite value (NaN or infinity) in the residual of equation 0").
    let o = fails_at(
        "coefficients = [0.0, 1.0]",
        "coefficients = [0.0, 1.0, 1e300]",
        "29:8",
        &[
            "driver \"motor\": at t = 0.1 s its value = 1e298 rad",
            "beyond the limit of 1e7 rad for an angle",
        ],
    );
    assert!(!o.stderr.contains("equation"), "{}", o.stderr);
}

/// Issue 27, item 11: the model name names the output directory; "." and ".." were refused
/// without a reason, and a newline made a directory with a newline in its name.
#[test]
fn model_names_that_cannot_name_a_directory_say_why() {
    let name = r#"name = "crank""#;
    fails_at(
        name,
        r#"name = "..""#,
        "2:8",
        &["\"..\"", "parent", "out/<name>/"],
    );
    fails_at(name, r#"name = ".""#, "2:8", &["\".\"", "itself"]);
    fails_at(
        name,
        r#"name = "a\nb""#,
        "2:8",
        &["control character", "U+000A"],
    );
    fails_at(
        name,
        r#"name = "a\tb""#,
        "2:8",
        &["control character", "U+0009"],
    );
    fails_at(name, r#"name = "a/b""#, "2:8", &["path separator '/'"]);
}

/// Issue 27, item 11: "marker" is an internal word; a message about axes uses the keys of the
/// model format ("invalid marker on body ...: marker axes: the axes are parallel").
#[test]
fn axis_messages_use_the_model_format_words() {
    let o = fails_at(
        "x_axis_i = \"x\"\n",
        "x_axis_i = \"z\"\n",
        "17:8",
        &[
            "joint \"pivot\"",
            "x_axis_i",
            "parallel to axis_i",
            "perpendicular",
        ],
    );
    assert!(!o.stderr.contains("marker"), "{}", o.stderr);
}

/// A two-DOF model (a crank and a slider) whose two drivers both drive the crank.
const DEPENDENT_DRIVERS: &str = r#"[model]
name = "dep"

[ground]
points = { O = [0.0, 0.0, 0.0], S = [0.0, 1.0, 0.0] }
vectors = { z = [0.0, 0.0, 1.0], x = [1.0, 0.0, 0.0] }

[[body]]
name = "crank"
position = [0.5, 0.0, 0.0]
points = { O = [-0.5, 0.0, 0.0], tip = [0.5, 0.0, 0.0] }
vectors = { z = [0.0, 0.0, 1.0], x = [1.0, 0.0, 0.0] }

[[body]]
name = "slider"
position = [0.0, 1.0, 0.0]
points = { S = [0.0, 0.0, 0.0] }
vectors = { x = [1.0, 0.0, 0.0], z = [0.0, 0.0, 1.0] }

[[joint]]
name = "pivot"
type = "revolute"
body_i = "ground"
point_i = "O"
axis_i = "z"
x_axis_i = "x"
body_j = "crank"
point_j = "O"
axis_j = "z"
x_axis_j = "x"

[[joint]]
name = "way"
type = "prismatic"
body_i = "ground"
point_i = "S"
axis_i = "x"
body_j = "slider"
point_j = "S"
axis_j = "x"

[[driver]]
name = "motor"
type = "rotation"
joint = "pivot"
function = { kind = "polynomial", coefficients = [0.0, 1.0] }

[[driver]]
name = "lift"
type = "coordinate"
body = "crank"
point = "tip"
coordinate = "y"
function = { kind = "polynomial", coefficients = [0.0, 0.5] }

[analysis]
kind = "kinematic"
t_end = 1.0
steps = 10
"#;

/// Issue 27, item 11: `cardan check` approved two drivers that depend on each other (and left
/// the slider free), which `run` then refused; it approved a universal joint drawn with
/// parallel arms, which no assembly can close.
#[test]
fn check_finds_dependent_drivers_and_parallel_universal_arms() {
    let o = run_text("check", DEPENDENT_DRIVERS);
    assert_ne!(o.code, 0, "{}", o.stdout);
    for n in ["model.toml:49:8:", "drivers do not control", "\"lift\""] {
        assert!(o.stderr.contains(n), "missing {n:?} in: {}", o.stderr);
    }
    let drive = std::fs::read_to_string(
        std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("../../examples/universal_drive.toml"),
    )
    .unwrap();
    let arm = "vectors = { axis = [1.0, 0.0, 0.0], arm = [0.0, 0.0, 1.0] }";
    assert!(drive.contains(arm));
    let parallel = drive.replace(
        arm,
        "vectors = { axis = [1.0, 0.0, 0.0], arm = [0.0, 1.0, 0.0] }",
    );
    for cmd in ["check", "run"] {
        let o = run_text(cmd, &parallel);
        assert_eq!(o.code, 1, "{cmd}: {}", o.stderr);
        for n in ["joint \"cross\"", "arms", "perpendicular"] {
            assert!(
                o.stderr.contains(n),
                "{cmd}: missing {n:?} in: {}",
                o.stderr
            );
        }
    }
}

/// Keys a joint kind does not use are refused by the builder (from the kind table) and located
/// at the key: a length on a revolute joint, axes on a spherical-spherical joint; a negative
/// length is located at its value (issue 20: one validator, the CLI maps the builder's site).
#[test]
fn keys_a_joint_kind_does_not_use_are_refused_at_the_key() {
    fails_at(
        "x_axis_j = \"x\"\n",
        "x_axis_j = \"x\"\nlength = 1.0\n",
        "27:10",
        &["joint \"pivot\" (revolute)", "takes no length"],
    );
    let ss = BASE
        .replacen("type = \"revolute\"", "type = \"spherical_spherical\"", 1)
        .replacen("point_j = \"O\"", "point_j = \"tip\"", 1)
        .replacen("x_axis_i = \"x\"\nx_axis_j = \"x\"\n", "length = 1.0\n", 1)
        .replacen("[[driver]]\nname = \"motor\"\ntype = \"rotation\"\njoint = \"pivot\"\nfunction = { kind = \"polynomial\", coefficients = [0.0, 1.0] }\n", "", 1);
    let o = run_text("check", &ss);
    assert_eq!(o.code, 1, "{}", o.stdout);
    assert!(
        o.stderr.starts_with("model.toml:21:10: error: ")
            && o.stderr
                .contains("spherical_spherical joint takes no axis_i and axis_j"),
        "{}",
        o.stderr
    );
    let o = run_text(
        "check",
        &ss.replacen("axis_i = \"z\"\n", "", 1)
            .replacen("axis_j = \"z\"\n", "", 1)
            .replacen("length = 1.0", "length = -1.0", 1),
    );
    assert_eq!(o.code, 1, "{}", o.stdout);
    assert!(
        o.stderr.starts_with("model.toml:23:10: error: ")
            && o.stderr.contains("length must be positive, got -1"),
        "{}",
        o.stderr
    );
}

/// A driver of a joint kind it cannot drive: the builder's error (kinds from the table),
/// located at the driver's `joint` key.
#[test]
fn a_driver_on_a_joint_it_cannot_drive_is_located_at_its_joint_key() {
    fails_at(
        "type = \"rotation\"",
        "type = \"translation\"",
        "31:9",
        &[
            "driver \"motor\": joint \"pivot\" is revolute",
            "a translation driver needs a cylindrical, prismatic, point_in_line",
        ],
    );
}

/// A coordinate driver on the ground and a distance driver between two points of one body: the
/// builder's errors, located at the key (the CLI no longer resolves drivers' bodies itself).
#[test]
fn drivers_on_the_ground_or_within_one_body_are_located_at_the_key() {
    let joint_driver = "type = \"rotation\"\njoint = \"pivot\"\n";
    fails_at(
        joint_driver,
        "type = \"coordinate\"\nbody = \"ground\"\npoint = \"O\"\ncoordinate = \"x\"\n",
        "31:8",
        &["driver \"motor\": acts on the ground, which cannot move"],
    );
    fails_at(
        joint_driver,
        "type = \"distance\"\nbody_i = \"crank\"\npoint_i = \"O\"\nbody_j = \"crank\"\npoint_j = \"tip\"\n",
        "33:10",
        &["driver \"motor\" connects body \"crank\" to itself"],
    );
    fails_at(
        joint_driver,
        "type = \"distance\"\nbody_i = \"ground\"\npoint_i = \"O\"\nbody_j = \"crank\"\npoint_j = \"tpi\"\n",
        "34:11",
        &["body \"crank\" has no point \"tpi\"", "did you mean \"tip\"?"],
    );
}

/// `[analysis] tolerance` sets the position solves' tolerance of a kinematic run; outside its
/// range [1e-14, 1e-6] it is refused at the key, and a dynamic run refuses it (its accuracy is
/// set by rtol/atol or newton_tolerance).
#[test]
fn the_kinematic_tolerance_is_used_and_checked_at_its_key() {
    let o = run_text(
        "run",
        &edited("steps = 10", "steps = 10\ntolerance = 1e-13"),
    );
    assert_eq!(o.code, 0, "{}", o.stderr);
    fails_at(
        "steps = 10",
        "steps = 10\ntolerance = 1e-3",
        "38:13",
        &["tolerance = 0.001 is outside its sensible range [1e-14, 1e-6]"],
    );
    fails_at(
        "kind = \"kinematic\"",
        "kind = \"dynamic\"\ntolerance = 1e-10",
        "36:1",
        &[
            "kind = \"dynamic\" does not take \"tolerance\"",
            "a dynamic run's accuracy is set by rtol and atol",
        ],
    );
}

/// `[analysis] position_tolerance` is the documented name of the kinematic position tolerance
/// (`tolerance` stays accepted with the same meaning): it is checked at its key like
/// `tolerance`, both at once are refused, and so is `position_tolerance` in a dynamic or a
/// static run (a static run's equilibrium tolerance is `tolerance`).
#[test]
fn position_tolerance_is_the_kinematic_tolerance_and_checked_at_its_key() {
    let o = run_text(
        "run",
        &edited("steps = 10", "steps = 10\nposition_tolerance = 1e-14"),
    );
    assert_eq!(o.code, 0, "{}", o.stderr);
    fails_at(
        "steps = 10",
        "steps = 10\nposition_tolerance = 1e-3",
        "38:22",
        &["residual tolerance = 0.001 is outside its sensible range [1e-14, 1e-6]"],
    );
    fails_at(
        "steps = 10",
        "steps = 10\nposition_tolerance = 1e-12\ntolerance = 1e-12",
        "39:1",
        &["give position_tolerance or tolerance, not both"],
    );
    fails_at(
        "kind = \"kinematic\"",
        "kind = \"dynamic\"\nposition_tolerance = 1e-10",
        "36:1",
        &["kind = \"dynamic\" does not take \"position_tolerance\" (it applies to kind = \"kinematic\", kind = \"inverse_dynamics\": a dynamic run's accuracy is set by rtol and atol"],
    );
    fails_at(
        "kind = \"kinematic\"",
        "kind = \"static\"\nposition_tolerance = 1e-10",
        "36:1",
        &[
            "kind = \"static\" does not take \"position_tolerance\"",
            "equilibrium_tolerance",
        ],
    );
}

/// A cone joint's angle near 0 (where its row z_iᵀz_j − cos α loses rank) is refused at its
/// `angle` key (radians), as is one near π; a valid one runs.
#[test]
fn a_cone_angle_near_0_is_refused_at_its_key() {
    let cone = |angle: &str| {
        format!(
            "{BASE}\n[[joint]]\nname = \"tilt\"\ntype = \"cone\"\nbody_i = \"ground\"\n\
             point_i = \"O\"\naxis_i = \"x\"\nbody_j = \"crank\"\npoint_j = \"O\"\n\
             axis_j = \"z\"\nangle = {angle}\n"
        )
    };
    let ok = run_text("run", &cone("1.5707963267948966"));
    assert_eq!(ok.code, 0, "{}", ok.stderr);
    for bad in ["0.0005", "3.1412"] {
        let text = cone(bad);
        let line = 1 + text.lines().position(|l| l.starts_with("angle =")).unwrap();
        let o = run_text("check", &text);
        assert_eq!(o.code, 1, "{}", o.stdout);
        assert!(
            o.stderr
                .starts_with(&format!("model.toml:{line}:9: error: "))
                && o.stderr.contains("joint \"tilt\" (cone)")
                && o.stderr.contains("loses rank"),
            "{bad}: {}",
            o.stderr
        );
    }
}
