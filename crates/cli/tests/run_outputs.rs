//! The output directory of `cardan run` (issue 27, item 10): written into a temporary sibling
//! and renamed into place as a whole, locked against a concurrent run, never a truncated file,
//! partial results marked; `run.json` describes every run that wrote a directory.

mod common;

use common::{cardan, edited, run_text, scratch, BASE};
use std::path::Path;

/// `DIR/run.json`, parsed.
fn run_json(dir: &Path) -> serde_json::Value {
    let text = std::fs::read_to_string(dir.join("run.json"))
        .unwrap_or_else(|e| panic!("{}/run.json: {e}", dir.display()));
    serde_json::from_str(&text).unwrap_or_else(|e| panic!("run.json: {e}\n{text}"))
}

/// The names of the files in `dir`, sorted.
fn names(dir: &Path) -> Vec<String> {
    let mut v: Vec<String> = std::fs::read_dir(dir)
        .unwrap_or_else(|e| panic!("{}: {e}", dir.display()))
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    v.sort();
    v
}

/// Every file of `dir` with its contents.
fn snapshot(dir: &Path) -> Vec<(String, Vec<u8>)> {
    names(dir)
        .into_iter()
        .map(|n| {
            let bytes = std::fs::read(dir.join(&n)).unwrap();
            (n, bytes)
        })
        .collect()
}

/// A model whose crank tip is pushed along x past the stretched position: the kinematics is
/// singular at t = 1 s (tip at x = 1), so the run stops after 51 of 101 steps.
fn stretched_crank() -> String {
    edited(
        "type = \"rotation\"\njoint = \"pivot\"",
        "type = \"coordinate\"\nbody = \"crank\"\npoint = \"tip\"\ncoordinate = \"x\"",
    )
    .replacen(
        "position = [0.5, 0.0, 0.0]",
        "position = [0.0, 0.5, 0.0]\norientation = { axis = [0.0, 0.0, 1.0], angle = 1.5707963267948966 }",
        1,
    )
    .replacen("t_end = 1.0\nsteps = 10", "t_end = 2.0\nsteps = 100", 1)
}

#[test]
fn run_json_describes_a_complete_run() {
    let o = run_text("run", BASE);
    assert_eq!(o.code, 0, "{}", o.stderr);
    let out = o.dir.join("out");
    let j = run_json(&out);
    assert_eq!(j["status"], "complete", "{j}");
    assert!(j["reason"].is_null(), "{j}");
    assert_eq!(j["exit_code"], 0);
    assert_eq!(j["model"]["name"], "crank");
    assert_eq!(j["model"]["path"], "model.toml");
    assert_eq!(j["analysis"], "kinematic");
    assert_eq!(j["steps"], 11);
    assert_eq!(j["t_reached"], 1.0);
    assert!(j["newton_iterations"].as_u64().unwrap() > 0, "{j}");
    assert!(j["largest_residual"].as_f64().unwrap() < 1e-9, "{j}");
    assert!(j["constraint_drift"].is_null() && j["energy_drift"].is_null());
    assert_eq!(j["warnings"], serde_json::json!([]));
    // The list of files is what the directory holds besides run.json.
    let mut listed: Vec<String> = j["files"]
        .as_array()
        .unwrap()
        .iter()
        .map(|f| f.as_str().unwrap().to_string())
        .collect();
    listed.push("run.json".into());
    listed.sort();
    assert_eq!(listed, names(&out));
    // Nothing is left beside the directory: no temporary directory, no lock.
    assert_eq!(names(&o.dir), ["model.toml", "out"]);
}

#[test]
fn a_rerun_replaces_the_directory_as_a_whole() {
    let o = run_text("run", BASE);
    assert_eq!(o.code, 0, "{}", o.stderr);
    let out = o.dir.join("out");
    // A table of an older version, under a name this version does not write.
    std::fs::write(out.join("old.csv"), "t [s]\n").unwrap();
    assert!(names(&out).contains(&"joints.csv".to_string()));
    // The second run writes only the points: the joint and body tables of the first are gone.
    let text = BASE.replacen(
        "steps = 10\n",
        "steps = 10\n\n[analysis.outputs]\npoints = [\"crank.tip\"]\n",
        1,
    );
    std::fs::write(o.dir.join("model.toml"), text).unwrap();
    let o2 = cardan(&["run", "model.toml", "-o", "out", "--quiet"], &o.dir);
    assert_eq!(o2.code, 0, "{}", o2.stderr);
    let files = names(&out);
    assert!(!files.contains(&"joints.csv".to_string()), "{files:?}");
    assert!(!files.contains(&"bodies.csv".to_string()), "{files:?}");
    assert!(!files.contains(&"old.csv".to_string()), "{files:?}");
    assert!(files.contains(&"points.csv".to_string()), "{files:?}");
}

#[test]
fn a_failed_mid_run_leaves_no_mix_and_is_marked_partial() {
    // A complete run with every table, then a run that stops at t = 1 s writing only points.
    let o = run_text("run", BASE);
    assert_eq!(o.code, 0, "{}", o.stderr);
    let text = stretched_crank().replacen(
        "steps = 100\n",
        "steps = 100\n\n[analysis.outputs]\npoints = [\"crank.tip\"]\n",
        1,
    );
    std::fs::write(o.dir.join("model.toml"), text).unwrap();
    let o2 = cardan(&["run", "model.toml", "-o", "out", "--quiet"], &o.dir);
    assert_eq!(o2.code, 3, "{}", o2.stderr);
    let out = o.dir.join("out");
    let files = names(&out);
    assert!(!files.contains(&"joints.csv".to_string()), "{files:?}");
    let j = run_json(&out);
    assert_eq!(j["status"], "partial", "{j}");
    assert_eq!(j["exit_code"], 3);
    assert_eq!(j["steps"], 51);
    assert_eq!(j["t_reached"], 1.0);
    let reason = j["reason"].as_str().unwrap();
    assert!(reason.contains("singular"), "{reason}");
}

#[test]
fn a_run_that_fails_before_its_first_step_leaves_the_previous_directory() {
    let o = run_text("run", BASE);
    assert_eq!(o.code, 0, "{}", o.stderr);
    let out = o.dir.join("out");
    let before = snapshot(&out);
    // The tip point cannot reach a point 5 m away: assembly fails.
    let text = BASE.replacen(
        "tip = [0.5, 0.0, 0.0] }",
        "tip = [0.5, 0.0, 0.0] }\n\n[[joint]]\nname = \"far\"\ntype = \"spherical\"\nbody_i = \"ground\"\npoint_i = \"O\"\nbody_j = \"crank\"\npoint_j = \"tip\"",
        1,
    );
    std::fs::write(o.dir.join("model.toml"), text).unwrap();
    let o2 = cardan(&["run", "model.toml", "-o", "out", "--quiet"], &o.dir);
    assert_ne!(o2.code, 0, "{}", o2.stdout);
    assert!(snapshot(&out) == before, "changed: {}", o2.stderr);
    assert_eq!(names(&o.dir), ["model.toml", "out"]);
}

#[test]
fn a_concurrent_run_is_refused_naming_the_directory_and_the_other_run() {
    let dir = scratch("lock");
    std::fs::write(dir.join("model.toml"), BASE).unwrap();
    // A lock held by a live process (this test).
    let me = std::process::id();
    std::fs::write(dir.join("out.lock"), format!("{me}\n")).unwrap();
    let o = cardan(&["run", "model.toml", "-o", "out", "--quiet"], &dir);
    assert_eq!(o.code, 1, "{}", o.stderr);
    assert!(
        o.stderr.contains("out") && o.stderr.contains(&format!("process {me}")),
        "{}",
        o.stderr
    );
    assert!(o.stderr.contains("out.lock"), "{}", o.stderr);
    assert!(!dir.join("out").exists());
    // The other run's lock is left alone.
    assert_eq!(
        std::fs::read_to_string(dir.join("out.lock")).unwrap(),
        format!("{me}\n")
    );
}

#[test]
fn a_stale_lock_of_a_dead_process_is_taken_over() {
    let dir = scratch("stale");
    std::fs::write(dir.join("model.toml"), BASE).unwrap();
    let mut child = std::process::Command::new("true").spawn().unwrap();
    let dead = child.id();
    child.wait().unwrap();
    std::fs::write(dir.join("out.lock"), format!("{dead}\n")).unwrap();
    let o = cardan(&["run", "model.toml", "-o", "out", "--quiet"], &dir);
    assert_eq!(o.code, 0, "{}", o.stderr);
    assert_eq!(run_json(&dir.join("out"))["status"], "complete");
    assert_eq!(names(&dir), ["model.toml", "out"]);
}

#[test]
fn a_directory_that_holds_other_files_is_not_replaced() {
    let dir = scratch("foreign");
    std::fs::write(dir.join("model.toml"), BASE).unwrap();
    std::fs::create_dir(dir.join("out")).unwrap();
    std::fs::write(dir.join("out/notes.txt"), "mine").unwrap();
    let o = cardan(&["run", "model.toml", "-o", "out", "--quiet"], &dir);
    assert_eq!(o.code, 2, "{}", o.stderr);
    assert!(
        o.stderr.contains("notes.txt") && o.stderr.contains("out"),
        "{}",
        o.stderr
    );
    assert_eq!(names(&dir.join("out")), ["notes.txt"]);
}

/// A write error (here a file-size limit, as a full disk would give: the limit holds for root
/// too, unlike an unwritable directory) leaves the previous run's directory as it was, and no
/// truncated file anywhere.
#[test]
fn a_write_error_leaves_the_previous_directory_intact() {
    let o = run_text("run", BASE);
    assert_eq!(o.code, 0, "{}", o.stderr);
    let out = o.dir.join("out");
    let before = snapshot(&out);
    // 400 steps: points.csv is far larger than the 512-byte limit.
    let text = BASE.replacen("steps = 10", "steps = 400", 1);
    std::fs::write(o.dir.join("model.toml"), text).unwrap();
    let script = format!(
        "ulimit -f 1; trap '' XFSZ; exec '{}' run model.toml -o out --quiet",
        env!("CARGO_BIN_EXE_cardan")
    );
    let r = std::process::Command::new("sh")
        .args(["-c", &script])
        .current_dir(&o.dir)
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&r.stderr);
    assert_eq!(r.status.code(), Some(1), "{stderr}");
    assert!(stderr.contains("cannot write"), "{stderr}");
    assert!(!stderr.contains("panicked"), "{stderr}");
    assert!(snapshot(&out) == before, "changed: {:?}", names(&out));
    assert_eq!(names(&o.dir), ["model.toml", "out"]);
}

/// The factor from a SI column unit to the mm system's, or 1 (an independent table, not the
/// command's).
fn mm_factor(header: &str) -> f64 {
    let unit = header
        .rsplit_once(" [")
        .map_or("", |(_, u)| u.trim_end_matches(']'));
    match unit {
        "m" | "m/s" | "m/s²" | "N m" | "J" | "W" => 1e3,
        _ => 1.0,
    }
}

/// slider_crank_dynamic in millimetres: lengths, velocities and gravity ×1000, inertias ×1e6.
fn slider_crank_in_mm(si: &str) -> String {
    let scale_numbers = |line: &str, f: f64| -> String {
        let mut out = String::new();
        let mut num = String::new();
        let flush = |num: &mut String, out: &mut String| {
            if !num.is_empty() {
                let v: f64 = num.parse().unwrap();
                out.push_str(&format!("{:?}", v * f));
                num.clear();
            }
        };
        for c in line.chars() {
            let starts = c.is_ascii_digit() || c == '-' || c == '.';
            let continues = !num.is_empty()
                && (c.is_ascii_digit() || c == '.' || c == 'e' || (c == '-' && num.ends_with('e')));
            if (num.is_empty() && starts) || continues {
                num.push(c);
            } else {
                flush(&mut num, &mut out);
                out.push(c);
            }
        }
        flush(&mut num, &mut out);
        out
    };
    si.lines()
        .map(|l| {
            let l = l.split('#').next().unwrap_or("");
            let (key, rest) = l.split_once(" = ").unwrap_or((l, ""));
            match key {
                "units" => "units = \"mm\"".to_string(),
                "t_end" => "t_end = 0.5".to_string(),
                // (Not [analysis.outputs] points = ["crank.B", ...].)
                "gravity" | "position" | "points" | "global_points" | "velocity"
                    if !rest.contains('"') =>
                {
                    format!("{key} = {}", scale_numbers(rest, 1e3))
                }
                "inertia" => format!("{key} = {}", scale_numbers(rest, 1e6)),
                _ => l.to_string(),
            }
        })
        .collect::<Vec<_>>()
        .join("\n")
}

/// `[model] units = "mm"`: the same mechanism written in SI and in millimetres gives the same
/// outputs after scaling (a dynamic run: positions, velocities, reactions, energy), with the
/// headers in mm, N mm and mJ; run.json says so.
#[test]
fn a_model_in_millimetres_writes_millimetres() {
    let dir = scratch("units-mm");
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples");
    let si = std::fs::read_to_string(root.join("slider_crank_dynamic.toml"))
        .unwrap()
        .replace("t_end = 5.0", "t_end = 0.5");
    std::fs::write(dir.join("si.toml"), &si).unwrap();
    std::fs::write(dir.join("mm.toml"), slider_crank_in_mm(&si)).unwrap();
    for (model, out) in [("si.toml", "si"), ("mm.toml", "mm")] {
        let r = cardan(&["run", model, "-o", out, "--quiet"], &dir);
        assert_eq!(r.code, 0, "{model}: {}{}", r.stdout, r.stderr);
    }
    assert_eq!(run_json(&dir.join("mm"))["units"], "mm");
    assert_eq!(run_json(&dir.join("si"))["units"], "SI");
    let mut compared = 0;
    for name in names(&dir.join("si")) {
        let Some(stem) = name.strip_suffix(".csv") else {
            continue;
        };
        let read = |d: &str| std::fs::read_to_string(dir.join(d).join(&name)).unwrap();
        let (ha, ra) = cardan_model::table::parse_csv(&read("si")).unwrap();
        let (hb, rb) = cardan_model::table::parse_csv(&read("mm")).unwrap();
        let factors: Vec<f64> = ha.iter().map(|h| mm_factor(h)).collect();
        for (a, b) in ha.iter().zip(&hb) {
            // Mixed units ("m or -": constraint_drift) stay SI.
            if a.contains(" or ") {
                assert_eq!(a, b);
                continue;
            }
            let expected = a
                .replace(" [m]", " [mm]")
                .replace(" [m/s", " [mm/s")
                .replace(" [N m]", " [N mm]")
                .replace(" [J]", " [mJ]")
                .replace(" [W]", " [mW]");
            assert_eq!(&expected, b, "{stem}");
        }
        assert_eq!(ra.len(), rb.len(), "{stem}");
        // Columns that are zero but for rounding (the power of ideal joints) are compared
        // with the table's largest value.
        let table = ra
            .iter()
            .flat_map(|r| &r[1..])
            .fold(0.0f64, |m, v| m.max(v.abs()));
        for k in 0..factors.len() {
            let size = ra.iter().fold(1e-6 * table, |m, r| m.max(r[k].abs()));
            for (x, y) in ra.iter().zip(&rb) {
                let d = (x[k] * factors[k] - y[k]).abs() / (size * factors[k]);
                // Residuals and drifts are rounding-level numbers: not compared.
                assert!(
                    d < 1e-6 || stem == "residual" || stem == "constraint_drift",
                    "{stem} {}: {} vs {}",
                    ha[k],
                    x[k],
                    y[k]
                );
            }
        }
        compared += 1;
    }
    assert!(compared >= 4, "{compared} tables");
}

/// The magnitude limits apply to SI values: 5e9 mm (5000 km) is within the length limit of
/// 1e7 m, 5e9 m is not; and a 5 mm link is no more suspicious than a 5 m one.
#[test]
fn magnitude_checks_see_si_values() {
    let mm = edited("[model]\n", "[model]\nunits = \"mm\"\n");
    let far = |text: &str| text.replacen("[0.0, 0.0, 0.0]", "[5e9, 0.0, 0.0]", 1);
    let si_far = run_text("check", &far(&edited("", "")));
    assert_eq!(si_far.code, 1, "{}", si_far.stderr);
    assert!(
        si_far.stderr.contains("beyond the limit of"),
        "{}",
        si_far.stderr
    );
    let mm_far = run_text("check", &far(&mm));
    assert!(
        !mm_far.stderr.contains("beyond the limit"),
        "{}",
        mm_far.stderr
    );
    // 5e10 mm is 5e7 m: beyond the limit, said in both units.
    let mm_too_far = run_text(
        "check",
        &mm.replacen("[0.0, 0.0, 0.0]", "[5e10, 0.0, 0.0]", 1),
    );
    assert_eq!(mm_too_far.code, 1, "{}", mm_too_far.stderr);
    assert!(
        mm_too_far
            .stderr
            .contains("(5e10 mm) = 5e7 m is beyond the limit of 1e7 m"),
        "{}",
        mm_too_far.stderr
    );
    let bad = run_text("check", &edited("[model]\n", "[model]\nunits = \"inch\"\n"));
    assert_eq!(bad.code, 1);
    assert!(bad.stderr.contains("units = \"mm\""), "{}", bad.stderr);
}
