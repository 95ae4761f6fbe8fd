//! One meaning per exit code (docs/cli.md, "Exit codes"; issue 45, item 9): each row of the
//! table, run through the real binary. 0 success (warnings allowed), 1 a file problem (the model
//! cannot be read, parsed or validated, or an output cannot be written), 2 command-line misuse,
//! 3 the analysis failed or `--strict` found a warning. (130, Ctrl-C, is tested in
//! `long_runs.rs`.)

mod common;
use common::{cardan, edited, scratch, BASE};
use std::path::Path;

/// Runs `cardan ARGS` in a fresh directory holding `model.toml` = `text`.
fn code(text: &str, args: &[&str]) -> (i32, String) {
    let dir = scratch("exit");
    std::fs::write(dir.join("model.toml"), text).unwrap();
    let o = cardan(args, &dir);
    (o.code, o.stderr)
}

fn expect(text: &str, args: &[&str], want: i32, what: &str) {
    let (got, stderr) = code(text, args);
    assert_eq!(got, want, "{what}: {args:?}: {stderr}");
    if want != 0 {
        assert!(!stderr.trim().is_empty(), "{what}: no message");
    }
}

#[test]
fn zero_is_success_with_or_without_warnings() {
    expect(
        BASE,
        &["run", "model.toml", "-o", "out", "--quiet"],
        0,
        "a run",
    );
    expect(BASE, &["check", "model.toml"], 0, "check");
    // A dynamic run whose energy balance is doubtful: a warning, still 0 without --strict.
    let loose = doubtful();
    let dir = scratch("exit-warn");
    std::fs::write(dir.join("model.toml"), &loose).unwrap();
    let o = cardan(&["run", "model.toml", "-o", "out", "--quiet"], &dir);
    assert_eq!(o.code, 0, "{}", o.stderr);
    assert!(o.stdout.contains("warning"), "{}", o.stdout);
}

/// The A01 pendulum with 10 kg and fixed DOPRI5 steps of 0.25 s near the stability limit: its
/// energy grows by about 19 J of 200 J, a doubtful result (a warning; doubtful_results.rs).
fn doubtful() -> String {
    let text = std::fs::read_to_string(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/a01_pendulum.toml"),
    )
    .unwrap();
    let from =
        "integrator = \"dopri5\"\nrtol = 1e-10\natol = 1e-12\nt_end = 10.0\noutput_dt = 0.05";
    assert!(text.contains(from));
    text.replacen(
        from,
        "integrator = \"dopri5\"\ndt = 0.25\nt_end = 20.0\noutput_dt = 0.5",
        1,
    )
    .replacen("mass = 1.0", "mass = 10.0", 1)
}

#[test]
fn one_is_a_file_problem() {
    expect(BASE, &["run", "missing.toml"], 1, "a missing file");
    expect(
        "[model\nname = ",
        &["check", "model.toml"],
        1,
        "TOML syntax",
    );
    expect(
        &edited("type = \"revolute\"", "type = \"revolut\""),
        &["check", "model.toml"],
        1,
        "a bad value",
    );
    let undriven = {
        let i = BASE.find("[[driver]]").unwrap();
        let j = BASE[i..].find("\n[").map_or(BASE.len(), |k| i + k + 1);
        format!("{}{}", &BASE[..i], &BASE[j..])
    };
    expect(
        &undriven,
        &["run", "model.toml", "-o", "out"],
        1,
        "a driver count off",
    );
}

#[test]
fn two_is_command_line_misuse() {
    expect(BASE, &["run"], 2, "no model");
    expect(
        BASE,
        &["run", "model.toml", "--frobnicate"],
        2,
        "an unknown flag",
    );
    expect(
        BASE,
        &["eval", "model.toml", "--t", "abc"],
        2,
        "a flag value clap refuses",
    );
    expect(
        BASE,
        &["eval", "model.toml", "--t", "nan"],
        2,
        "a flag value cardan refuses",
    );
    expect(
        BASE,
        &["run", "model.toml", "--units", "mm"],
        2,
        "--units with a TOML file",
    );
    // An output directory that holds a user's file is not replaced.
    let dir = scratch("exit-foreign");
    std::fs::write(dir.join("model.toml"), BASE).unwrap();
    std::fs::create_dir(dir.join("out")).unwrap();
    std::fs::write(dir.join("out/notes.txt"), "mine").unwrap();
    let o = cardan(&["run", "model.toml", "-o", "out", "--quiet"], &dir);
    assert_eq!(o.code, 2, "{}", o.stderr);
    assert!(Path::new(&dir.join("out/notes.txt")).exists());
    // An output path that is a file.
    let o = cardan(&["run", "model.toml", "-o", "model.toml", "--quiet"], &dir);
    assert_eq!(o.code, 2, "{}", o.stderr);
}

#[test]
fn three_is_a_failed_analysis_or_a_strict_warning() {
    // A distance joint the crank cannot reach: the joints cannot be assembled.
    let open = edited(
        "[[driver]]",
        "[[joint]]\nname = \"tether\"\ntype = \"spherical_spherical\"\nbody_i = \"ground\"\n\
         point_i = \"O\"\nbody_j = \"crank\"\npoint_j = \"tip\"\nlength = 5.0\n\n[[driver]]",
    );
    expect(
        &open,
        &["run", "model.toml", "-o", "out", "--quiet"],
        3,
        "no assembly",
    );
    let dir = scratch("exit-strict");
    std::fs::write(dir.join("model.toml"), doubtful()).unwrap();
    let o = cardan(
        &["run", "model.toml", "-o", "out", "--quiet", "--strict"],
        &dir,
    );
    assert_eq!(o.code, 3, "{}", o.stderr);
    assert!(dir.join("out/run.json").exists());
}
