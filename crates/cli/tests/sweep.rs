//! `cardan sweep` through the real binary: each row is the run `cardan run --set` makes of its
//! case, reduced by the outputs; a failing case is a row with its error; a grid too large, an
//! unknown parameter or column, cases given twice are refused before anything runs.

mod common;
use common::{cardan, scratch};
use std::path::{Path, PathBuf};

fn parametric() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/slider_crank_parametric.toml")
}

fn csv(path: &Path) -> (Vec<String>, Vec<Vec<String>>) {
    let text = std::fs::read_to_string(path).unwrap();
    let mut lines = text.lines();
    let header = lines.next().unwrap().split(',').map(String::from).collect();
    let rows = lines
        .map(|l| l.splitn(6, ',').map(String::from).collect())
        .collect();
    (header, rows)
}

#[test]
fn each_row_is_the_run_of_its_case() {
    let dir = scratch("sweep");
    let m = parametric();
    let m = m.to_str().unwrap();
    let o = cardan(
        &[
            "sweep",
            m,
            "--set",
            "crank=60 mm:100 mm:3",
            "--set",
            "speed=1,4",
            "--output",
            "peak=max(abs(motor.torque))",
            "--output",
            "top=max(abs(slider.C.x'))",
            "-o",
            "sw",
            "-j",
            "2",
        ],
        &dir,
    );
    assert_eq!(o.code, 0, "{}", o.stderr);
    assert!(
        o.stdout
            .contains("sweep of 6 cases on 2 thread(s): 6 ok, 0 failed"),
        "{}",
        o.stdout
    );
    let (header, rows) = csv(&dir.join("sw/sweep.csv"));
    assert_eq!(header, ["crank", "speed", "peak", "top", "status", "error"]);
    assert_eq!(rows.len(), 6);
    // Case 3 (crank = 80 mm, speed = 4 rad/s) as `cardan run --set` runs it.
    assert_eq!(rows[3][0..2], ["0.08", "4.0"]);
    let run = cardan(
        &[
            "run",
            m,
            "--set",
            "crank=0.08 m",
            "--set",
            "speed=4.0",
            "-o",
            "one",
            "--quiet",
        ],
        &dir,
    );
    assert_eq!(run.code, 0, "{}", run.stderr);
    let efforts = std::fs::read_to_string(dir.join("one/driver_efforts.csv")).unwrap();
    let peak = (efforts.lines().skip(1))
        .map(|l| l.split(',').nth(1).unwrap().parse::<f64>().unwrap().abs())
        .fold(0.0, f64::max);
    assert_eq!(rows[3][2].parse::<f64>().unwrap(), peak);
    for f in [
        "peak_vs_crank.svg",
        "peak_vs_speed.svg",
        "top_vs_crank.svg",
        "run.json",
    ] {
        assert!(dir.join("sw").join(f).is_file(), "{f}");
    }
    let json = std::fs::read_to_string(dir.join("sw/run.json")).unwrap();
    assert!(
        json.contains("\"status\": \"complete\"") && json.contains("\"ok\": 6"),
        "{json}"
    );
}

#[test]
fn a_failing_case_is_a_row_with_its_error() {
    let dir = scratch("sweep-fail");
    let m = parametric();
    // A crank of 0.5 m cannot reach the slider: its x_c is the sqrt of a negative number.
    std::fs::write(dir.join("cases.csv"), "crank,speed\n0.08,2\n0.5,2\n").unwrap();
    let o = cardan(
        &[
            "sweep",
            m.to_str().unwrap(),
            "--cases",
            "cases.csv",
            "--output",
            "p=max(motor.torque)",
            "-o",
            "sw",
        ],
        &dir,
    );
    assert_eq!(o.code, 0, "{}", o.stderr);
    assert!(o.stdout.contains("1 ok, 1 failed"), "{}", o.stdout);
    assert!(
        o.stdout.contains("warning: case crank=0.5 speed=2: "),
        "{}",
        o.stdout
    );
    let (_, rows) = csv(&dir.join("sw/sweep.csv"));
    assert_eq!(rows[0][3], "ok");
    assert_eq!(rows[1][3], "error");
    assert!(rows[1][4].contains("sqrt of"), "{:?}", rows[1]);
}

#[test]
fn mistakes_are_refused_before_anything_runs() {
    let dir = scratch("sweep-bad");
    let m = parametric();
    let m = m.to_str().unwrap();
    let out = "--output";
    let p = "p=max(motor.torque)";
    let cases: Vec<(Vec<&str>, &str)> = vec![
        (
            vec![
                "--set",
                "crank=0:1:1000",
                "--set",
                "speed=0:1:1000",
                "--set",
                "rod=0.3:0.4:1000",
                out,
                p,
            ],
            "1000000000 cases (1000 crank × 1000 speed × 1000 rod), more than 100000",
        ),
        (
            vec!["--set", "crnak=1,2", out, p],
            "did you mean \"crank\"?",
        ),
        (
            vec!["--set", "crank=0.06,0.08", out, "p=max(motor.torqe)"],
            "did you mean \"motor.torque\"?",
        ),
        (
            vec!["--set", "crank=0.06,0.08", out, "p=abs(motor.torque)"],
            "reduce it with max",
        ),
        (vec!["--set", "crank=1 m:2 s:3", out, p], "different units"),
        (vec!["--set", "crank=1,2"], "no outputs"),
        (vec![out, p], "nothing to sweep"),
        (
            vec!["--set", "crank=1,2", "--cases", "c.csv", out, p],
            "not both",
        ),
    ];
    for (extra, want) in cases {
        let mut args = vec!["sweep", m, "-o", "sw"];
        args.extend(extra);
        let o = cardan(&args, &dir);
        assert_eq!(o.code, 2, "{args:?}: {}", o.stderr);
        assert!(
            o.stderr.contains(want),
            "{args:?}: want {want:?} in {}",
            o.stderr
        );
        assert!(!dir.join("sw").exists(), "{args:?} wrote files");
    }
}
