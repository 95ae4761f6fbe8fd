//! What a newcomer reads first (issue 46): `cardan --help` says everything the command does,
//! and the summary of a run ends with where its results are: the report page to open and the
//! directory that holds every file.

mod common;

use common::{cardan, scratch, BASE};

#[test]
fn help_names_every_analysis_and_asmt() {
    let o = cardan(&["--help"], &scratch("help"));
    assert_eq!(o.code, 0, "{}", o.stderr);
    let about = o.stdout.lines().next().unwrap_or_default().to_lowercase();
    for word in [
        "kinematic",
        "static",
        "modal",
        "inverse",
        "forward dynamics",
        "asmt",
    ] {
        assert!(about.contains(word), "{word:?} missing from {about:?}");
    }
}

#[test]
fn the_summary_ends_with_the_report_and_the_directory() {
    let dir = scratch("where");
    std::fs::write(dir.join("model.toml"), BASE).unwrap();
    let o = cardan(&["run", "model.toml", "-o", "results", "--quiet"], &dir);
    assert_eq!(o.code, 0, "{}", o.stderr);
    let last = o.stdout.lines().last().unwrap_or_default();
    let page = std::path::Path::new("results").join("index.html");
    assert!(
        last.contains(&page.display().to_string()) && last.contains("results/"),
        "last line: {last:?}"
    );
    assert!(dir.join(&page).is_file());
}

/// Warnings come before it: the last line is still where to look.
#[test]
fn the_report_line_follows_the_warnings() {
    let dir = scratch("where-warn");
    let text = std::fs::read_to_string(
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/a01_pendulum.toml"),
    )
    .unwrap();
    let adaptive = "rtol = 1e-10\natol = 1e-12\nt_end = 10.0\noutput_dt = 0.05";
    assert!(text.contains(adaptive));
    let unstable = text.replacen(adaptive, "dt = 0.25\nt_end = 20.0\noutput_dt = 0.5", 1);
    std::fs::write(dir.join("model.toml"), unstable).unwrap();
    let o = cardan(&["run", "model.toml", "-o", "out", "--quiet"], &dir);
    assert_eq!(o.code, 0, "{}", o.stderr);
    let lines: Vec<&str> = o.stdout.lines().collect();
    assert!(
        lines.iter().any(|l| l.starts_with("warning: ")),
        "{}",
        o.stdout
    );
    assert!(lines.last().unwrap().contains("index.html"), "{}", o.stdout);
}
