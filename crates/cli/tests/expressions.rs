//! Expression time functions through the real binary: a driver written as text runs like the
//! same polynomial; a syntax error points at the character inside the TOML string; a function
//! undefined at an analysis time names the driver or force, the time and the failing part.

mod common;
use common::{cardan, edited, run_text, scratch};

const POLY: &str = r#"function = { kind = "polynomial", coefficients = [0.0, 1.0] }"#;

fn with_text(text: &str) -> String {
    edited(
        POLY,
        &format!(r#"function = {{ kind = "expression", text = "{text}" }}"#),
    )
}

#[test]
fn an_expression_driver_runs_like_the_same_polynomial() {
    let poly = run_text("run", common::BASE);
    let expr = run_text("run", &with_text("0.5*(2*t)"));
    assert_eq!((poly.code, expr.code), (0, 0), "{}", expr.stderr);
    for f in ["joints.csv", "bodies.csv"] {
        let a = std::fs::read_to_string(poly.dir.join("out").join(f));
        let b = std::fs::read_to_string(expr.dir.join("out").join(f));
        if let (Ok(a), Ok(b)) = (a, b) {
            assert_eq!(a, b, "{f}");
        }
    }
}

#[test]
fn a_syntax_error_points_inside_the_string() {
    let o = run_text("check", &with_text("0.5 + sinn(t)"));
    assert_eq!(o.code, 1, "{}", o.stderr);
    // `function = { kind = "expression", text = "` is 42 characters: "sinn" is at column 49.
    for n in [
        "model.toml:32:49: error:",
        "driver \"motor\"",
        "column 7",
        "unknown name \"sinn\"",
        "did you mean \"sin\"",
    ] {
        assert!(o.stderr.contains(n), "{n} in {}", o.stderr);
    }
    let caret = o.stderr.lines().last().unwrap();
    assert_eq!(
        caret.trim_start_matches([' ', '|']).len(),
        4,
        "{}",
        o.stderr
    );
    let o = run_text("check", &with_text("atan2(t)"));
    assert!(
        o.stderr.contains("atan2() takes 2 arguments"),
        "{}",
        o.stderr
    );
    let o = run_text("check", &with_text("sin(t"));
    assert_eq!(o.code, 1, "{}", o.stderr);
    let o = run_text(
        "check",
        &edited(POLY, r#"function = { kind = "expression" }"#),
    );
    assert!(o.stderr.contains("missing key \"text\""), "{}", o.stderr);
}

#[test]
fn a_driver_undefined_at_an_analysis_time_names_driver_time_and_function() {
    let o = run_text("run", &with_text("sqrt(0.55 - t)"));
    assert_eq!(o.code, 1, "{}", o.stderr);
    for n in [
        "model.toml:29:",
        "driver \"motor\"",
        "not finite at t = 0.6",
        "expression \"sqrt(0.55 - t)\"",
        "sqrt of -0.05",
    ] {
        assert!(o.stderr.contains(n), "{n} in {}", o.stderr);
    }
    // `cardan eval --t` checks the same.
    let dir = scratch("expr-eval");
    std::fs::write(dir.join("model.toml"), with_text("log(abs(t - 0.55))")).unwrap();
    let o = cardan(&["eval", "model.toml", "--t", "0.55"], &dir);
    assert_eq!(o.code, 1, "{}", o.stderr);
    assert!(o.stderr.contains("log of 0"), "{}", o.stderr);
}

const DYNAMIC: &str = r#"[model]
name = "pendulum"
gravity = [0.0, -9.81, 0.0]

[ground]
points = { O = [0.0, 0.0, 0.0] }
vectors = { z = [0.0, 0.0, 1.0], x = [1.0, 0.0, 0.0] }

[[body]]
name = "rod"
mass = 1.0
inertia = { diag = [1e-4, 0.0833, 0.0833] }
position = [0.5, 0.0, 0.0]
points = { O = [-0.5, 0.0, 0.0], tip = [0.5, 0.0, 0.0] }
vectors = { z = [0.0, 0.0, 1.0], x = [1.0, 0.0, 0.0] }

[[joint]]
name = "pivot"
type = "revolute"
body_i = "ground"
point_i = "O"
axis_i = "z"
x_axis_i = "x"
body_j = "rod"
point_j = "O"
axis_j = "z"
x_axis_j = "x"

[[force]]
name = "motor"
type = "torque"
body = "rod"
components = [{ kind = "constant", value = 0.0 }, { kind = "constant", value = 0.0 }, { kind = "expression", text = "TORQUE" }]

[analysis]
kind = "dynamic"
t_end = 1.0
output_dt = 0.1
"#;

#[test]
fn a_force_undefined_at_an_output_time_names_force_time_and_function() {
    let ok = run_text(
        "run",
        &DYNAMIC.replace("TORQUE", "0.1*step(t, 0, 0, 0.5, 1)"),
    );
    assert_eq!(ok.code, 0, "{}", ok.stderr);
    let o = run_text("run", &DYNAMIC.replace("TORQUE", "0.1*log(0.55 - t)"));
    assert_eq!(o.code, 1, "{}", o.stderr);
    for n in [
        "force \"motor\" component z",
        "not finite at t = 0.6",
        "log of -0.05",
    ] {
        assert!(o.stderr.contains(n), "{n} in {}", o.stderr);
    }
}

#[test]
fn literal_strings_are_located_too_and_long_texts_refused() {
    // A TOML literal string: the caret is still on the character.
    let o = run_text(
        "check",
        &edited(
            POLY,
            r#"function = { kind = "expression", text = '2*t +' }"#,
        ),
    );
    assert_eq!(o.code, 1, "{}", o.stderr);
    assert!(
        o.stderr.contains("model.toml:32:48: error:"),
        "{}",
        o.stderr
    );
    assert!(
        o.stderr.contains("the end of the expression"),
        "{}",
        o.stderr
    );
    // Longer than 10 000 bytes: refused before parsing.
    let long = format!("t{}", " + t".repeat(3000));
    let o = run_text("check", &with_text(&long));
    assert_eq!(o.code, 1, "{}", o.stderr);
    assert!(o.stderr.contains("at most 10000"), "{}", o.stderr);
}

/// Between output times (a DOPRI5 stage), a non-finite force stops the run with an error that
/// names the force, the time and the failing part of its expression.
#[test]
fn a_force_undefined_between_output_times_is_named_by_the_run_error() {
    let text = DYNAMIC
        .replace("TORQUE", "0.1*piecewise(t, 0, 0.02, sqrt(t - 1), 0.08, 0)")
        .replace("output_dt = 0.1", "output_dt = 0.1\ndt = 0.01");
    let o = run_text("run", &text);
    assert_eq!(o.code, 3, "{}", o.stderr);
    for n in [
        "model.toml:30:8: error: dynamic analysis: t = 0.02",
        "the cause: force \"motor\" component z",
        "at \"sqrt(t - 1)\" (column 27): sqrt of -0.98",
    ] {
        assert!(o.stderr.contains(n), "{n} in {}", o.stderr);
    }
}
