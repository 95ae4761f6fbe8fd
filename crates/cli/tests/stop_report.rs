//! The report marks active end stops (issue 48): the page of a dynamic run with `[[limit]]`
//! carries per stop its name, its joint and where that joint is drawn, and per frame whether
//! the stop is active and its force, with the impacts as events, all as `stops.csv` and
//! `events.csv` of the same run say: `examples/pendulum_stop.toml` is inactive before its first
//! impact, active in the frame of every impact and held on the stop at the end with the static
//! torque m g (L/2) cos 60°; a compliant stop is active exactly where its force is not zero; a
//! run whose frames the page decimates still shows every impact; a model without limits carries
//! no stop data and none of the stops' script.

mod common;

use cardan_model::table::parse_csv;
use common::{cardan, run_text, scratch};
use std::path::{Path, PathBuf};

fn example(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../examples")
        .join(name)
}

/// Runs the model file `model`; returns the output directory.
fn run(model: &Path) -> PathBuf {
    let dir = scratch("stop-report");
    let o = cardan(
        &["run", model.to_str().unwrap(), "-o", "out", "--quiet"],
        &dir,
    );
    assert_eq!(o.code, 0, "{}", o.stderr);
    dir.join("out")
}

/// Runs the text of `examples/pendulum_stop.toml` with `from` replaced by `to`.
fn run_edited(edits: &[(&str, &str)]) -> PathBuf {
    let mut text = std::fs::read_to_string(example("pendulum_stop.toml")).unwrap();
    for (from, to) in edits {
        assert!(text.contains(from), "{from}");
        text = text.replacen(from, to, 1);
    }
    let o = run_text("run", &text);
    assert_eq!(o.code, 0, "{}", o.stderr);
    o.dir.join("out")
}

/// The page's data (`<script id="meta">`) and the whole page.
fn page(dir: &Path) -> (serde_json::Value, String) {
    let html = std::fs::read_to_string(dir.join("index.html")).unwrap();
    let start = "<script id=\"meta\" type=\"application/json\">";
    let at = html.find(start).expect("the page's data") + start.len();
    let end = at + html[at..].find("</script>").unwrap();
    (serde_json::from_str(&html[at..end]).unwrap(), html)
}

/// A CSV output as (header, rows).
fn rows(dir: &Path, name: &str) -> (Vec<String>, Vec<Vec<f64>>) {
    parse_csv(&std::fs::read_to_string(dir.join(name)).unwrap()).unwrap()
}

/// `events.csv` as (time, stop, event).
fn events(dir: &Path) -> Vec<(f64, String, String)> {
    let text = std::fs::read_to_string(dir.join("events.csv")).unwrap();
    text.lines()
        .skip(1)
        .map(|l| {
            let f: Vec<&str> = l.split(',').collect();
            (f[0].parse().unwrap(), f[1].to_string(), f[3].to_string())
        })
        .collect()
}

/// The frame whose interval (t_{k−1}, t_k] holds `t`.
fn frame_of(times: &[f64], t: f64) -> usize {
    times.iter().position(|&tk| t <= tk).unwrap()
}

/// The one stop of a pendulum's page: its data, its state and force per frame.
struct Stop {
    json: serde_json::Value,
    active: Vec<bool>,
    force: Vec<f64>,
}

fn the_stop(meta: &serde_json::Value) -> Stop {
    let list = meta["stops"]["list"].as_array().expect("the stops' data");
    assert_eq!(list.len(), 1);
    let json = list[0].clone();
    let active = (json["active"].as_array().unwrap().iter())
        .map(|a| a.as_u64().unwrap() == 1)
        .collect();
    let force = (json["force"].as_array().unwrap().iter())
        .map(|f| f.as_f64().unwrap())
        .collect();
    Stop {
        json,
        active,
        force,
    }
}

#[test]
fn the_pendulum_page_marks_its_stop_at_every_impact_and_held_at_the_end() {
    let out = run(&example("pendulum_stop.toml"));
    let (meta, html) = page(&out);
    assert!(html.contains("window.cardanStops"), "the stops' script");
    let stop = the_stop(&meta);
    assert_eq!(stop.json["name"], "stop.lower");
    assert_eq!(stop.json["joint"], "hinge");
    assert_eq!(stop.json["unit"], "N m");
    // Drawn on the rod (the hinge's body i is the ground) at its end O, about z.
    let body = stop.json["body"].as_u64().unwrap() as usize;
    assert_eq!(meta["bodies"][body]["name"], "rod");
    assert_eq!(stop.json["point"], serde_json::json!([-0.5, 0.0, 0.0]));
    assert_eq!(stop.json["direction"], serde_json::json!([0.0, 0.0, 1.0]));

    // Every frame as stops.csv and events.csv say (the run is not decimated).
    let (header, table) = rows(&out, "stops.csv");
    assert_eq!(header[1], "stop.lower held [-]");
    let times: Vec<f64> = table.iter().map(|r| r[0]).collect();
    assert_eq!(stop.active.len(), times.len());
    let ev = events(&out);
    assert_eq!(ev.len(), 20);
    for (k, r) in table.iter().enumerate() {
        let before = if k == 0 {
            f64::NEG_INFINITY
        } else {
            times[k - 1]
        };
        let struck = ev.iter().any(|e| before < e.0 && e.0 <= times[k]);
        let want = r[1] == 1.0 || r[2] != 0.0 || struck;
        assert_eq!(stop.active[k], want, "frame {k} at t = {}", times[k]);
        assert_eq!(stop.force[k], r[2], "frame {k}");
    }
    // Inactive before the first impact, active in each impact's frame, held at the end with
    // the torque that holds the rod at 60° below the horizontal: m g (L/2) cos 60°.
    let first = frame_of(&times, ev[0].0);
    assert!(first > 30 && stop.active[..first].iter().all(|a| !a));
    for e in &ev {
        assert!(stop.active[frame_of(&times, e.0)], "impact at {}", e.0);
    }
    assert!(*stop.active.last().unwrap());
    let held = 1.0 * 9.81 * 0.5 * 0.5;
    assert!((stop.force.last().unwrap() - held).abs() < 1e-9);
    // The events, in time order, at events.csv's times.
    let listed = meta["stops"]["events"].as_array().unwrap();
    assert_eq!(listed.len(), ev.len());
    for (l, e) in listed.iter().zip(&ev) {
        assert_eq!(l[0].as_f64().unwrap(), e.0);
        assert_eq!(l[1], 0);
        assert_eq!(l[2], e.2.as_str());
    }
    assert_eq!(listed.last().unwrap()[2], "impact_held");
}

#[test]
fn a_compliant_stop_is_active_where_its_force_is_not_zero() {
    let out = run_edited(&[(
        "restitution = 0.5",
        "law = \"compliant\"\nstiffness = 2e3\ndamping = 20.0",
    )]);
    let stop = the_stop(&page(&out).0);
    let (_, table) = rows(&out, "stops.csv");
    assert_eq!(stop.active.len(), table.len());
    assert!(events(&out).is_empty());
    for (k, r) in table.iter().enumerate() {
        assert_eq!(stop.active[k], r[2] != 0.0, "frame {k} at t = {}", r[0]);
    }
    let contact = stop.active.iter().filter(|a| **a).count();
    assert!(contact > 10 && contact < table.len(), "{contact} frames");
}

/// 6,001 outputs, of which the page keeps about 2,000: the frame of each impact, between two
/// kept frames, is still active.
#[test]
fn a_decimated_page_still_marks_every_impact() {
    let out = run_edited(&[("output_dt = 0.01", "output_dt = 0.0005")]);
    let (meta, _) = page(&out);
    let stop = the_stop(&meta);
    let (_, table) = rows(&out, "stops.csv");
    assert_eq!(table.len(), 6001);
    let kept = stop.active.len();
    assert!(kept < 3000, "{kept} frames: not decimated");
    // The kept frames' times: every stride-th output and the last (run.json says the stride).
    let run: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("run.json")).unwrap()).unwrap();
    let stride = run["plotted_frames"]["every"].as_u64().unwrap() as usize;
    let mut times: Vec<f64> = table.iter().step_by(stride).map(|r| r[0]).collect();
    if *times.last().unwrap() != table.last().unwrap()[0] {
        times.push(table.last().unwrap()[0]);
    }
    assert_eq!(times.len(), kept);
    for e in events(&out) {
        assert!(stop.active[frame_of(&times, e.0)], "impact at {}", e.0);
    }
    assert!(*stop.active.last().unwrap());
}

#[test]
fn a_model_without_limits_carries_no_stop_data() {
    let out = run(&example("slider_crank_dynamic.toml"));
    let (meta, html) = page(&out);
    assert!(meta.get("stops").is_none());
    assert!(!html.contains("cardanStops") && !html.contains("[stops]"));
    assert!(!html.contains("#stop-ticks"));
    assert!(!out.join("stops.csv").exists());
}
