//! `[parameters]` through the real binary: the parametric slider-crank at its defaults is the
//! literal one; `--set` changes the geometry that follows from a parameter; `check` prints the
//! values; every mistake (a name defined twice, a cycle, an unknown name, a unit mismatch, a
//! `--set` of a name the file lacks or in another unit) is an error at its place.

mod common;
use common::{cardan, check_fails_at, edited, run_text, scratch};
use std::path::{Path, PathBuf};

fn example(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../examples")
        .join(name)
}

/// A CSV's numeric rows.
fn rows(path: &Path) -> Vec<Vec<f64>> {
    let text = std::fs::read_to_string(path).unwrap();
    (text.lines().skip(1))
        .map(|l| l.split(',').map(|v| v.parse().unwrap()).collect())
        .collect()
}

fn run_example(name: &str, extra: &[&str]) -> PathBuf {
    let dir = scratch("parameters");
    let model = example(name);
    let mut args = vec!["run", model.to_str().unwrap(), "-o", "out", "--quiet"];
    args.extend_from_slice(extra);
    let o = cardan(&args, &dir);
    assert_eq!(o.code, 0, "{}", o.stderr);
    dir.join("out")
}

#[test]
fn the_parametric_slider_crank_at_its_defaults_is_the_literal_one() {
    let literal = run_example("slider_crank_inverse.toml", &[]);
    let parametric = run_example("slider_crank_parametric.toml", &[]);
    let (a, b) = (
        rows(&literal.join("driver_efforts.csv")),
        rows(&parametric.join("driver_efforts.csv")),
    );
    assert_eq!(a.len(), b.len());
    let peak = a.iter().map(|r| r[1].abs()).fold(0.0, f64::max);
    for (x, y) in a.iter().zip(&b) {
        assert!((x[1] - y[1]).abs() < 1e-9 * peak, "{x:?} {y:?}");
    }
}

#[test]
fn set_moves_what_follows_from_a_parameter() {
    // crank = 60 mm: the slider starts at x_c = sqrt(rod² − offset² − (height + crank)²).
    let x_c = (0.3f64.powi(2) - 0.1f64.powi(2) - 0.18f64.powi(2)).sqrt();
    let plain = run_example("slider_crank_parametric.toml", &["--set", "crank=0.06"]);
    let unit = run_example("slider_crank_parametric.toml", &["--set", "crank=60 mm"]);
    let body = rows(&plain.join("bodies.csv"));
    // Columns: t, then per body r (3) and p (4): the slider is the third body.
    assert!(
        (body[0][15] - x_c).abs() < 1e-12,
        "{} vs {x_c}",
        body[0][15]
    );
    assert_eq!(
        std::fs::read_to_string(plain.join("driver_efforts.csv")).unwrap(),
        std::fs::read_to_string(unit.join("driver_efforts.csv")).unwrap()
    );
    // The speed: twice the speed, the crank turns through twice the angle in the same time.
    let fast = run_example("slider_crank_parametric.toml", &["--set", "speed=120 rpm"]);
    let (slow, fast) = (
        rows(&plain.join("joints.csv")),
        rows(&fast.join("joints.csv")),
    );
    let k = 10;
    assert!(
        (fast[k][1] - 2.0 * slow[k][1]).abs() < 1e-12,
        "{} {}",
        fast[k][1],
        slow[k][1]
    );
}

#[test]
fn check_prints_the_parameters_and_what_was_set() {
    let dir = scratch("parameters-check");
    let model = example("slider_crank_parametric.toml");
    let m = model.to_str().unwrap();
    let o = cardan(&["check", m, "--set", "crank=60 mm"], &dir);
    assert_eq!(o.code, 0, "{}", o.stderr);
    for n in [
        "parameters (7)",
        "--set crank=60 mm (the file: 80 mm)",
        "x_c          0.218174 m",
        "sqrt(rod^2 - offset^2 - (height + crank)^2)",
    ] {
        assert!(o.stdout.contains(n), "missing {n:?} in:\n{}", o.stdout);
    }
}

/// [`common::BASE`] with parameters: the crank's length and the motor's speed.
fn with_parameters(table: &str) -> String {
    edited("[ground]", &format!("[parameters]\n{table}\n\n[ground]"))
}

#[test]
fn parameters_reach_numbers_and_time_expressions_in_the_model_units() {
    // A mm model: "0.5 m" is 500 (mm) where the file wants a length; the expression driver
    // sees `speed` as a constant.
    let text = with_parameters("half = \"0.5 m\"\nspeed = \"2 rad/s\"")
        .replace(
            "name = \"crank\"\n\n",
            "name = \"crank\"\nunits = \"mm\"\n\n",
        )
        .replace(
            "position = [0.5, 0.0, 0.0]",
            "position = [\"half\", 0.0, 0.0]",
        )
        .replace(
            "points = { O = [-0.5, 0.0, 0.0], tip = [0.5, 0.0, 0.0] }",
            "points = { O = [\"-half\", 0.0, 0.0], tip = [\"half\", 0.0, 0.0] }",
        )
        .replace(
            "function = { kind = \"polynomial\", coefficients = [0.0, 1.0] }",
            "function = { kind = \"expression\", text = \"speed * t\" }",
        );
    assert!(text.contains("units = \"mm\""));
    let o = run_text("run", &text);
    assert_eq!(o.code, 0, "{}", o.stderr);
    let joints = rows(&o.dir.join("out/joints.csv"));
    let last = joints.last().unwrap();
    assert!((last[1] - 2.0).abs() < 1e-12, "{last:?}");
    let points = rows(&o.dir.join("out/points.csv"));
    // The tip at 1000 mm from the pivot (the first point column is crank.tip's x at t = 0).
    let header = std::fs::read_to_string(o.dir.join("out/points.csv")).unwrap();
    let col = header
        .lines()
        .next()
        .unwrap()
        .split(',')
        .position(|c| c.starts_with("crank.tip.x"))
        .unwrap();
    assert!((points[0][col] - 1000.0).abs() < 1e-9, "{}", points[0][col]);
}

#[test]
fn mistakes_are_errors_at_their_place() {
    // Defined twice: TOML's duplicate key, at the second definition.
    check_fails_at(&with_parameters("a = 1.0\na = 2.0"), 6, &["duplicate key"]);
    // A cycle, named along its chain.
    check_fails_at(
        &with_parameters("a = \"b + 1\"\nb = \"2 * a\""),
        5,
        &["the parameters form a cycle: a → b → a"],
    );
    // An unknown name in a definition, at the name, with the nearest one.
    check_fails_at(
        &with_parameters("crank = \"80 mm\"\nrod = \"3 * crnak\""),
        6,
        &["uses \"crnak\"", "did you mean \"crank\"?"],
    );
    // A unit mismatch, with both values.
    check_fails_at(
        &with_parameters("bad = \"80 mm + 2 s\""),
        5,
        &["cannot add 0.08 m and 2 s", "their units differ (m and s)"],
    );
    // An unknown name where a number is used, at the use.
    check_fails_at(
        &with_parameters("half = 0.5").replace("mass = 1.0", "mass = \"halve\""),
        13,
        &["no parameter \"halve\"; did you mean \"half\"?"],
    );
    // No [parameters] at all.
    check_fails_at(
        &common::BASE.replace("mass = 1.0", "mass = \"m\""),
        10,
        &["\"m\" is not a number, nor a parameter: the file has no [parameters] table"],
    );
    // A name that is a function, a value of another type.
    check_fails_at(
        &with_parameters("sin = 1.0"),
        5,
        &["is a function or constant"],
    );
    // The names expression functions read as the time, a constant or a function: a parameter
    // of that name would be shadowed there.
    for name in ["t", "time", "e", "step", "spline"] {
        check_fails_at(
            &with_parameters(&format!("{name} = 2.0")),
            5,
            &["expression functions", "call the parameter otherwise"],
        );
    }
    check_fails_at(
        &with_parameters("a = [1, 2]"),
        5,
        &["is a number or a text"],
    );
    // Hostile: a chain too long to evaluate safely, a power tower, both at their place.
    let chain = "1+".repeat(100_000) + "1";
    check_fails_at(
        &with_parameters("a = 1.0").replace("mass = 1.0", &format!("mass = \"{chain}\"")),
        13,
        &["more than 512 operations"],
    );
    let tower = "2^".repeat(10_000) + "1";
    check_fails_at(
        &with_parameters("a = 1.0").replace("mass = 1.0", &format!("mass = \"{tower}\"")),
        13,
        &["nested deeper than 64 levels"],
    );
    check_fails_at(
        &with_parameters("a = \"sqrt(-1 m^2)\""),
        5,
        &["sqrt of -1 m^2 is not defined"],
    );
}

#[test]
fn set_mistakes_are_usage_errors_naming_the_parameters() {
    let dir = scratch("parameters-set");
    std::fs::write(dir.join("model.toml"), with_parameters("crank = \"80 mm\"")).unwrap();
    let o = cardan(&["check", "model.toml", "--set", "crnak=1"], &dir);
    assert_eq!(o.code, 2, "{}", o.stderr);
    assert!(o.stderr.contains("did you mean \"crank\"?"), "{}", o.stderr);
    let o = cardan(&["check", "model.toml", "--set", "crank=2 s"], &dir);
    assert_eq!(o.code, 2, "{}", o.stderr);
    assert!(
        o.stderr.contains("the file gives crank in m"),
        "{}",
        o.stderr
    );
    let o = cardan(&["check", "model.toml", "--set", "crank"], &dir);
    assert_eq!(o.code, 2, "{}", o.stderr);
    assert!(o.stderr.contains("is not NAME=VALUE"), "{}", o.stderr);
    let asmt = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/asmt");
    let file = std::fs::read_dir(&asmt)
        .unwrap()
        .filter_map(Result::ok)
        .map(|e| e.path())
        .find(|p| p.extension().is_some_and(|e| e == "asmt"))
        .unwrap();
    let o = cardan(&["check", file.to_str().unwrap(), "--set", "a=1"], &dir);
    assert_eq!(o.code, 2, "{}", o.stderr);
    assert!(o.stderr.contains("has none"), "{}", o.stderr);
}

#[test]
fn eval_takes_set_values() {
    let dir = scratch("parameters-eval");
    let model = example("slider_crank_parametric.toml");
    let m = model.to_str().unwrap();
    let state = |extra: &[&str]| {
        let mut args = vec!["eval", m, "--format", "json"];
        args.extend_from_slice(extra);
        let o = cardan(&args, &dir);
        assert_eq!(o.code, 0, "{}", o.stderr);
        let v: serde_json::Value = serde_json::from_str(&o.stdout).unwrap();
        v["bodies"].clone()
    };
    let file = state(&[]);
    assert_eq!(state(&["--set", "crank=80 mm"]), file);
    assert_ne!(state(&["--set", "crank=60 mm"]), file);
    let o = cardan(&["eval", m, "--set", "crnak=1"], &dir);
    assert_eq!(o.code, 2, "{}", o.stderr);
    assert!(o.stderr.contains("did you mean \"crank\"?"), "{}", o.stderr);
}
