//! Issue 53 (speed): `cardan run --outputs` writes only the files asked for besides run.json,
//! so an ASMT file's run can write just its `.solved.asmt` as OndselSolver does. An unknown
//! value is a usage error (exit 2).

mod common;
use common::{cardan, scratch};
use std::path::PathBuf;

fn piston() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../examples/asmt/piston.asmt")
}

fn written(dir: &std::path::Path) -> Vec<String> {
    let mut names: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().into_string().unwrap())
        .collect();
    names.sort();
    names
}

#[test]
fn outputs_names_what_is_written() {
    let dir = scratch("outputs-flag");
    let file = piston();
    let f = file.to_str().unwrap();
    let o = cardan(
        &["run", f, "-o", "asmt", "--outputs", "asmt", "--quiet"],
        &dir,
    );
    assert_eq!(o.code, 0, "{}", o.stderr);
    assert_eq!(
        written(&dir.join("asmt")),
        ["piston.solved.asmt", "run.json"]
    );
    let json = std::fs::read_to_string(dir.join("asmt/run.json")).unwrap();
    assert!(json.contains("piston.solved.asmt"), "{json}");

    let o = cardan(
        &["run", f, "-o", "csv", "--outputs", "csv", "--quiet"],
        &dir,
    );
    assert_eq!(o.code, 0, "{}", o.stderr);
    let names = written(&dir.join("csv"));
    assert!(
        names.iter().all(|n| n.ends_with(".csv") || n == "run.json"),
        "{names:?}"
    );
    assert!(names.contains(&"points.csv".to_string()), "{names:?}");

    let o = cardan(
        &[
            "run",
            f,
            "-o",
            "two",
            "--outputs",
            "plots,report",
            "--quiet",
        ],
        &dir,
    );
    assert_eq!(o.code, 0, "{}", o.stderr);
    let names = written(&dir.join("two"));
    assert!(
        names.contains(&"index.html".to_string()) && names.contains(&"points.svg".to_string()),
        "{names:?}"
    );
    assert!(
        !names
            .iter()
            .any(|n| n.ends_with(".csv") || n.ends_with(".solved.asmt")),
        "{names:?}"
    );

    // The default writes everything, as before.
    let o = cardan(&["run", f, "-o", "all", "--quiet"], &dir);
    assert_eq!(o.code, 0, "{}", o.stderr);
    let names = written(&dir.join("all"));
    for n in [
        "points.csv",
        "points.svg",
        "index.html",
        "animation.glb",
        "piston.solved.asmt",
        "run.json",
    ] {
        assert!(names.contains(&n.to_string()), "{n}: {names:?}");
    }

    let o = cardan(&["run", f, "-o", "bad", "--outputs", "pdf"], &dir);
    assert_eq!(o.code, 2, "{}", o.stderr);
    let _ = std::fs::remove_dir_all(&dir);
}
