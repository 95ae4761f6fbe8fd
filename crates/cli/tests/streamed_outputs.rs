//! A kinematic, dynamic or inverse dynamics `cardan run` writes its CSV files frame by frame and
//! keeps only a decimated copy for the plots, the animation and the report (issue 25, target 4). The files it streams must
//! be the files a table held whole writes (the Python package's path, `analyse`, which keeps
//! every frame), byte for byte; a long run's plots say they are decimated, its kept copy has
//! the first and the last frame, and its summary is taken over every frame. The TimeSeries of
//! an ASMT run's `*.solved.asmt` streams too, and must equal the series built whole.

mod common;

use cardan_asmt::solved::{self, SeriesPlan};
use cardan_cli::commands::run::{run_model, run_model_with};
use cardan_model::analysis::{analyse, RunFlags};
use cardan_model::asmt::{Analysis, AsmtOptions, Units};
use cardan_model::prepare::{prepare, prepare_with};
use common::{edited, scratch};
use std::path::{Path, PathBuf};

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

/// Runs `model` with `cardan run` into a scratch directory and compares every CSV file it wrote
/// with the CSV text of the same table computed whole (every frame kept, nothing streamed).
/// Returns the output directory.
fn streamed_equals_whole(model: &Path) -> PathBuf {
    streamed_equals_whole_of(model, "kinematic")
}

/// [`streamed_equals_whole`] of a run of `kind`.
fn streamed_equals_whole_of(model: &Path, kind: &str) -> PathBuf {
    let dir = scratch("streamed").join("out");
    let outcome = run_model(model, Some(&dir), false).unwrap();
    assert!(outcome.error.is_none(), "{:?}", outcome.error);
    let p = prepare(model).unwrap();
    let analysis = p.loaded.analysis.clone().unwrap();
    let (ran, whole) = analyse(&p, &analysis, &RunFlags::default()).unwrap();
    assert_eq!(ran, kind);
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

/// A long run formats and writes its rows on a second thread (10,001 frames of 55 values, past
/// `csv_files::THREAD_MIN_VALUES`): the files are the tables written whole all the same.
#[test]
fn rows_written_on_a_second_thread_equal_the_whole_tables() {
    let text = std::fs::read_to_string(root().join("examples/slider_crank.toml")).unwrap();
    let long = text.replacen("steps = 200", "steps = 10000", 1);
    assert_ne!(long, text);
    let model = scratch("threaded").join("slider_crank.toml");
    std::fs::write(&model, long).unwrap();
    let out = streamed_equals_whole(&model);
    let bodies = std::fs::read_to_string(out.join("bodies.csv")).unwrap();
    assert_eq!(bodies.lines().count(), 1 + 10_001);
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

#[test]
fn streamed_dynamic_and_inverse_csv_files_equal_the_whole_tables_on_the_examples() {
    // Forward dynamics, plain and with redundant joints (dropped rows).
    for name in ["slider_crank_dynamic", "a04_bricard"] {
        let model = root().join(format!("examples/{name}.toml"));
        streamed_equals_whole_of(&model, "dynamic");
    }
    // Inverse dynamics: plain, couplers (angles over turns), a general motion (pose torques).
    for name in ["slider_crank_inverse", "gear_train", "general_motion_path"] {
        let model = root().join(format!("examples/{name}.toml"));
        streamed_equals_whole_of(&model, "inverse_dynamics");
    }
}

/// The largest value of column `col` of a CSV file's text.
fn column_max(csv: &str, col: usize) -> f64 {
    (csv.lines().skip(1))
        .map(|l| l.split(',').nth(col).unwrap().parse::<f64>().unwrap())
        .fold(0.0, f64::max)
}

#[test]
fn a_long_dynamic_run_streams_every_output_and_sums_up_every_output() {
    let dir = scratch("decimated-dynamic");
    let model = dir.join("long.toml");
    let text = std::fs::read_to_string(root().join("examples/slider_crank_dynamic.toml")).unwrap();
    // 4,001 outputs: every 3rd is kept for the plots.
    let text = text
        .replace("t_end = 5.0", "t_end = 2.0")
        .replace("output_dt = 0.01", "output_dt = 0.0005");
    std::fs::write(&model, text).unwrap();
    let out = streamed_equals_whole_of(&model, "dynamic");
    let drift = std::fs::read_to_string(out.join("constraint_drift.csv")).unwrap();
    assert_eq!(drift.lines().count(), 1 + 4001);
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("run.json")).unwrap()).unwrap();
    assert_eq!(json["plotted_frames"]["of"], 4001);
    assert_eq!(json["plotted_frames"]["every"], 3);
    assert_eq!(json["steps"], 4001);
    // The summary's numbers are the largest over every output the files hold.
    assert_eq!(json["constraint_drift"], column_max(&drift, 1));
    let energy = std::fs::read_to_string(out.join("energy.csv")).unwrap();
    let header: Vec<&str> = energy.lines().next().unwrap().split(',').collect();
    let balance = header.iter().position(|h| *h == "balance [J]").unwrap();
    let drift_col = header.iter().position(|h| *h == "drift [J]").unwrap();
    let abs_max = |col: usize| {
        (energy.lines().skip(1))
            .map(|l| l.split(',').nth(col).unwrap().parse::<f64>().unwrap().abs())
            .fold(0.0, f64::max)
    };
    assert_eq!(json["energy_balance"], abs_max(balance));
    assert_eq!(json["energy_drift"], abs_max(drift_col));
    let svg = std::fs::read_to_string(out.join("energy.svg")).unwrap();
    assert!(
        svg.contains("(every 3rd of 4001 frames)"),
        "no note in the plot"
    );
}

/// An ASMT file in `data` with `hout` (its output step) replaced by `hout`.
fn asmt_with_hout(name: &str, hout: &str) -> PathBuf {
    let file = root().join(format!("crates/asmt/tests/data/{name}.asmt"));
    let text = std::fs::read_to_string(file).unwrap();
    let mut lines: Vec<&str> = text.lines().collect();
    let at = lines.iter().position(|l| l.trim() == "hout").unwrap() + 1;
    lines[at] = hout;
    let out = scratch("streamed-asmt").join(format!("{name}.asmt"));
    std::fs::write(&out, lines.join("\n") + "\n").unwrap();
    out
}

/// Runs the ASMT file `file` with `cardan run` as `asmt` says and compares its
/// `*.solved.asmt`, whose TimeSeries is written a quantity per row from frames that streamed a
/// time at a time (through a spill file when they exceed memory), with the series built from
/// every frame kept (`analyse`), byte for byte.
fn solved_equals_whole(file: &Path, asmt: AsmtOptions) {
    let dir = scratch("streamed-asmt-out").join("out");
    let flags = RunFlags {
        asmt: asmt.clone(),
        ..RunFlags::default()
    };
    let outcome = run_model_with(file, Some(&dir), &flags).unwrap();
    assert!(outcome.error.is_none(), "{:?}", outcome.error);
    let p = prepare_with(file, asmt.clone()).unwrap();
    let analysis = p.loaded.analysis.clone().unwrap();
    let (_, whole) = analyse(&p, &analysis, &flags).unwrap();
    let text = std::fs::read_to_string(file).unwrap();
    let doc = cardan_asmt::read_model(&text).unwrap();
    let (doc, factor) = match asmt.units {
        Units::Si => (doc, 1.0),
        Units::Mm => (doc.scaled(1e-3), 1e3),
    };
    let import = cardan_asmt::import(&doc).unwrap();
    let dynamics = whole.dynamic.as_ref();
    let plan = SeriesPlan::new(&doc, &import, &whole.results, dynamics, factor);
    let series = plan.series(&whole.results, dynamics);
    assert_eq!(series.times.len(), outcome.summary.steps);
    let want = solved::solved_text(&text, &series);
    let stem = file.file_stem().unwrap().to_string_lossy();
    let got = std::fs::read_to_string(dir.join(format!("{stem}.solved.asmt"))).unwrap();
    assert!(got == want, "{}: the solved file differs", file.display());
    // The spill file is gone: the directory holds what run.json lists, and run.json.
    let listed = std::fs::read_to_string(dir.join("run.json")).unwrap();
    for entry in std::fs::read_dir(&dir).unwrap() {
        let name = entry.unwrap().file_name().to_string_lossy().into_owned();
        assert!(
            name == "run.json" || listed.contains(&format!("\"{name}\"")),
            "{name}"
        );
    }
}

#[test]
fn an_asmt_runs_solved_series_streams_the_whole_series() {
    let asmt = |units, analysis| AsmtOptions {
        units,
        analysis,
        ..AsmtOptions::default()
    };
    // 10,001 frames of 91 rows: past the memory budget, so the frames spill to disk.
    let long = asmt_with_hout("crank_slider", "\t\t\t1.0e-4 ");
    solved_equals_whole(&long, asmt(Units::Si, Analysis::Kinematic));
    // Reactions, in millimetres; and a dynamic run's output times.
    let fourbar = root().join("crates/asmt/tests/data/fourbar.asmt");
    solved_equals_whole(&fourbar, asmt(Units::Mm, Analysis::InverseDynamics));
    solved_equals_whole(&fourbar, asmt(Units::Si, Analysis::Dynamic));
}
