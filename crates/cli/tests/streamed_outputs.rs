//! A kinematic `cardan run` writes its CSV files frame by frame and keeps only a decimated copy
//! for the plots, the animation and the report (issue 25, target 4). The files it streams must
//! be the files a table held whole writes (the Python package's path, `analyse`, which keeps
//! every frame), byte for byte; a long run's plots say they are decimated, its kept copy has
//! the first and the last frame, and its summary is taken over every frame.

mod common;

use cardan_cli::commands::prepare;
use cardan_cli::commands::run::{analyse, run_model, RunFlags};
use common::{edited, scratch};
use std::path::{Path, PathBuf};

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

/// Runs `model` with `cardan run` into a scratch directory and compares every CSV file it wrote
/// with the CSV text of the same table computed whole (every frame kept, nothing streamed).
/// Returns the output directory.
fn streamed_equals_whole(model: &Path) -> PathBuf {
    let dir = scratch("streamed").join("out");
    let outcome = run_model(model, Some(&dir), false).unwrap();
    assert!(outcome.error.is_none(), "{:?}", outcome.error);
    let p = prepare(model).unwrap();
    let analysis = p.loaded.analysis.clone().unwrap();
    let (kind, whole) = analyse(&p, &analysis, &RunFlags::default()).unwrap();
    assert_eq!(kind, "kinematic");
    assert!(whole.streamed.is_none());
    assert_eq!(whole.results.len(), outcome.summary.steps);
    for t in &whole.tables {
        let name = format!("{}.csv", t.name);
        let written = std::fs::read_to_string(dir.join(&name))
            .unwrap_or_else(|e| panic!("{}: {name}: {e}", model.display()));
        assert!(written == t.to_csv(), "{}: {name} differs", model.display());
    }
    dir
}

#[test]
fn streamed_csv_files_equal_the_whole_tables_on_the_examples() {
    // A plain model, redundant joints (Bricard), couplers with angles continued over turns.
    for name in ["slider_crank", "bricard", "rack_pinion_steering"] {
        let model = root().join(format!("examples/{name}.toml"));
        streamed_equals_whole(&model);
    }
    // In millimetres: the rows are converted as they are written.
    let mm = scratch("streamed-mm").join("crank_mm.toml");
    std::fs::write(
        &mm,
        edited("name = \"crank\"", "name = \"crank\"\nunits = \"mm\""),
    )
    .unwrap();
    let dir = streamed_equals_whole(&mm);
    let points = std::fs::read_to_string(dir.join("points.csv")).unwrap();
    assert!(points.starts_with("t [s],crank.O.x [mm]"), "{points}");
}

#[test]
fn a_long_run_plots_a_decimated_copy_with_its_first_and_last_frames() {
    let steps = 2_500;
    let dir = scratch("decimated");
    let model = dir.join("long.toml");
    std::fs::write(&model, edited("steps = 10", &format!("steps = {steps}"))).unwrap();
    let out = streamed_equals_whole(&model);
    // Every frame in the CSV files.
    let bodies = std::fs::read_to_string(out.join("bodies.csv")).unwrap();
    assert_eq!(bodies.lines().count(), 1 + steps + 1);
    // The plots and run.json say how the frames were decimated.
    let svg = std::fs::read_to_string(out.join("bodies.svg")).unwrap();
    assert!(
        svg.contains("(every 2nd of 2501 frames)"),
        "no note in the plot"
    );
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("run.json")).unwrap()).unwrap();
    let plotted = &json["plotted_frames"];
    assert_eq!(plotted["of"], 2501);
    assert_eq!(plotted["every"], 2);
    assert_eq!(plotted["kept"], 1251);
    assert_eq!(json["steps"], 2501);
    // The kept copy (what the animation and report show) has the first and the last frame.
    let outcome = run_model(&model, Some(&dir.join("again")), false).unwrap();
    let kept = &outcome.results;
    assert_eq!(kept.len(), 1251);
    assert_eq!(kept.times.first(), Some(&0.0));
    assert_eq!(kept.times.last(), Some(&1.0));
    assert_eq!(outcome.summary.steps, steps + 1);
    // A short run is not decimated.
    let short = streamed_equals_whole(&root().join("examples/slider_crank.toml"));
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(short.join("run.json")).unwrap()).unwrap();
    assert!(json["plotted_frames"].is_null());
}
