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

/// Piston with a rotation limit and a force element: both are read and ignored.
fn piston_with_ignored_elements() -> String {
    std::fs::read_to_string(asmt("piston"))
        .unwrap()
        .replacen(
            "\t\tMotions\n",
            "\t\tMotions\n\t\t\tAllowRotation\n\t\t\t\tName\n\t\t\t\t\tFree\n",
            1,
        )
        .replacen(
            "\tForceTorques\n",
            "\tForceTorques\n\t\tForceTorque\n\t\t\tName\n\t\t\t\tSpring\n",
            1,
        )
}

/// The import's warnings (an ignored AllowRotation and force element) reach the run's summary and
/// `run.json`, and `check`'s report, each with the ASMT line.
#[test]
fn import_warnings_reach_the_summary_and_run_json() {
    let dir = scratch("asmt-warnings");
    let text = piston_with_ignored_elements();
    let line = text
        .lines()
        .position(|l| l == "\t\t\tAllowRotation")
        .unwrap()
        + 1;
    std::fs::write(dir.join("p.asmt"), &text).unwrap();
    let run = cardan(&["run", "p.asmt", "-o", "out", "--quiet"], &dir);
    assert_eq!(run.code, 0, "{}{}", run.stdout, run.stderr);
    let expected = format!("p.asmt:{line}: AllowRotation \"Free\"");
    assert!(
        run.stdout.contains(&format!("warning: {expected}")),
        "{}",
        run.stdout
    );
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("out/run.json")).unwrap()).unwrap();
    let warnings: Vec<&str> = json["warnings"]
        .as_array()
        .unwrap()
        .iter()
        .filter_map(|w| w.as_str())
        .collect();
    assert!(
        warnings.iter().any(|w| w.contains(&expected)),
        "{warnings:?}"
    );
    assert!(
        warnings
            .iter()
            .any(|w| w.contains("ForceTorque \"Spring\"")),
        "{warnings:?}"
    );
    let check = cardan(&["check", "p.asmt"], &dir);
    assert_eq!(check.code, 0, "{}", check.stderr);
    assert!(check.stdout.contains(&expected), "{}", check.stdout);
    // --strict counts them: the file's ignored elements make its results doubtful.
    let strict = cardan(
        &["run", "p.asmt", "-o", "out2", "--quiet", "--strict"],
        &dir,
    );
    assert_eq!(strict.code, 3, "{}", strict.stderr);
}

/// `--units` and `--analysis` belong to ASMT files: a TOML model is refused with them.
#[test]
fn asmt_flags_are_refused_for_a_toml_model() {
    let dir = scratch("asmt-flags");
    let import = cardan(
        &["import", asmt("piston").to_str().unwrap(), "-o", "p.toml"],
        &dir,
    );
    assert_eq!(import.code, 0, "{}", import.stderr);
    for flag in ["--units", "--analysis"] {
        let value = if flag == "--units" { "mm" } else { "dynamic" };
        let out = cardan(&["check", "p.toml", flag, value], &dir);
        // Command-line misuse (docs/cli.md, "Exit codes").
        assert_eq!(out.code, 2, "{flag}: {}", out.stderr);
        assert!(out.stderr.contains("apply to ASMT files"), "{}", out.stderr);
    }
}

/// The largest |a − b| over two CSV files of the same shape, relative to the largest |a|.
fn csv_difference(a: &str, b: &str) -> f64 {
    let (_, ra) = cardan_model::table::parse_csv(a).unwrap();
    let (_, rb) = cardan_model::table::parse_csv(b).unwrap();
    assert_eq!(ra.len(), rb.len());
    let (mut diff, mut size) = (0.0f64, 0.0f64);
    for (x, y) in ra.iter().flatten().zip(rb.iter().flatten()) {
        diff = diff.max((x - y).abs());
        size = size.max(x.abs());
    }
    diff / size.max(f64::MIN_POSITIVE)
}

/// `--units mm`: the file's numbers are millimetres, the analysis works in SI and the outputs
/// are in millimetres. The same numbers read as SI and as mm describe mechanisms 1000 times
/// apart, so their outputs in their own units are the same numbers, with mm headers.
#[test]
fn a_millimetre_run_writes_millimetres() {
    let dir = scratch("asmt-mm");
    let file = asmt("crank_slider");
    let file = file.to_str().unwrap();
    let si = cardan(&["run", file, "-o", "si", "--quiet"], &dir);
    assert_eq!(si.code, 0, "{}{}", si.stdout, si.stderr);
    let mm = cardan(&["run", file, "-o", "mm", "--quiet", "--units", "mm"], &dir);
    assert_eq!(mm.code, 0, "{}{}", mm.stdout, mm.stderr);
    for name in ["bodies.csv", "points.csv", "point_velocities.csv"] {
        let (a, b) = (
            std::fs::read_to_string(dir.join("si").join(name)),
            std::fs::read_to_string(dir.join("mm").join(name)),
        );
        let (Ok(a), Ok(b)) = (a, b) else { continue };
        let header_si = a.lines().next().unwrap().to_string();
        let header_mm = b.lines().next().unwrap().to_string();
        assert!(
            header_si.contains(" [m]") || header_si.contains(" [m/s]"),
            "{header_si}"
        );
        assert!(
            !header_mm.contains(" [m]") && !header_mm.contains(" [m/s]"),
            "{header_mm}"
        );
        assert_eq!(
            header_si
                .replace(" [m]", " [mm]")
                .replace(" [m/s", " [mm/s"),
            header_mm
        );
        let d = csv_difference(&a, &b);
        assert!(d < 1e-9, "{name}: {d:e}");
    }
    let json = std::fs::read_to_string(dir.join("mm/run.json")).unwrap();
    assert!(json.contains("\"units\": \"mm\""), "{json}");
    // The solved file is in the file's units too: the same part positions as the SI run.
    let solved = |d: &str| {
        let text = std::fs::read_to_string(dir.join(d).join("crank_slider.solved.asmt")).unwrap();
        cardan_asmt::read(&text).unwrap().series.unwrap()
    };
    let (a, b) = (solved("si"), solved("mm"));
    for label in ["X", "Y", "VX", "AX", "Bryantz"] {
        // Relative to the largest value of the row over all parts.
        let scale = a
            .items
            .iter()
            .flat_map(|i| i.row(label).unwrap())
            .fold(1e-300f64, |m, v| m.max(v.abs()));
        for (ia, ib) in a.items.iter().zip(&b.items) {
            let (x, y) = (ia.row(label).unwrap(), ib.row(label).unwrap());
            for (u, v) in x.iter().zip(y) {
                assert!(
                    (u - v).abs() <= 1e-9 * scale,
                    "{} {label}: {u} {v}",
                    ia.path
                );
            }
        }
    }
}

/// `--analysis dynamic`: forward dynamics on the file's time grid. fourbar is driven by its
/// motion, so the dynamic run (DOPRI5, rtol = the file's errorTol 1e-6) follows the kinematic
/// one; its driver efforts are written.
#[test]
fn dynamic_analysis_of_an_asmt_file() {
    let dir = scratch("asmt-dynamic");
    let file = asmt("fourbar");
    let file = file.to_str().unwrap();
    let kin = cardan(&["run", file, "-o", "kin", "--quiet"], &dir);
    assert_eq!(kin.code, 0, "{}{}", kin.stdout, kin.stderr);
    let dynamic = cardan(
        &["run", file, "-o", "dyn", "--quiet", "--analysis", "dynamic"],
        &dir,
    );
    assert_eq!(dynamic.code, 0, "{}{}", dynamic.stdout, dynamic.stderr);
    let json = std::fs::read_to_string(dir.join("dyn/run.json")).unwrap();
    assert!(json.contains("\"analysis\": \"dynamic\""), "{json}");
    assert!(dir.join("dyn/driver_efforts.csv").exists());
    assert!(dir.join("dyn/fourbar.solved.asmt").exists());
    let read = |d: &str| std::fs::read_to_string(dir.join(d).join("bodies.csv")).unwrap();
    let d = csv_difference(&read("kin"), &read("dyn"));
    assert!(d < 1e-4, "dynamic vs kinematic positions: {d:e}");
    let import = cardan(&["import", file, "--analysis", "dynamic"], &dir);
    assert!(
        import.stdout.contains("kind = \"dynamic\""),
        "{}",
        import.stdout
    );
    assert!(import.stdout.contains("rtol = 1e-6"), "{}", import.stdout);
}

/// Dynamics of a file with parts of mass 0: refused, naming every such part and what to do.
#[test]
fn dynamics_of_massless_parts_is_refused_by_name() {
    let dir = scratch("asmt-massless");
    let file = asmt("Gears");
    for analysis in ["dynamic", "inverse_dynamics"] {
        let out = cardan(
            &[
                "run",
                file.to_str().unwrap(),
                "--quiet",
                "--analysis",
                analysis,
            ],
            &dir,
        );
        assert_eq!(out.code, 1, "{analysis}: {}", out.stderr);
        assert!(out.stderr.contains("mass 0: /"), "{}", out.stderr);
        assert!(
            out.stderr.contains("--analysis kinematic"),
            "{}",
            out.stderr
        );
        assert!(!dir.join("out").exists());
    }
}

/// An AngleJoint imports as a `cone` joint (no warning about it), and the written TOML runs.
#[test]
fn an_angle_joint_imports_as_a_cone_and_runs() {
    let dir = scratch("asmt-cone");
    let file =
        PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../asmt/tests/data/small/angle.asmt");
    let import = cardan(
        &["import", file.to_str().unwrap(), "-o", "model.toml"],
        &dir,
    );
    assert_eq!(import.code, 0, "{}", import.stderr);
    assert!(!import.stderr.contains("AngleJoint"), "{}", import.stderr);
    let text = std::fs::read_to_string(dir.join("model.toml")).unwrap();
    assert!(text.contains("type = \"cone\""), "{text}");
    let run = cardan(&["run", "model.toml", "-o", "out", "--quiet"], &dir);
    assert_eq!(run.code, 0, "{}{}", run.stdout, run.stderr);
}
