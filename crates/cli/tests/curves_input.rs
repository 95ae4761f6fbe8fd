//! `[[curve]]` and `[[driver]] type = "path"` through the model file (issue 49): a slot as a
//! spline through collinear points equals the straight slot, a pin driven off an open slot's end
//! is an error with the time, and every mistake in a curve or a path driver is an error at its
//! key's line.

mod common;
use common::run_text;

fn example(name: &str) -> String {
    let path = std::path::PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../../examples")
        .join(name);
    std::fs::read_to_string(path).unwrap()
}

/// `base` with the first `from` after its `[[curve]]` header (or, for a path driver's keys,
/// after `type = "path"`) replaced by `to`.
fn edited(base: &str, from: &str, to: &str) -> String {
    let section = match from.starts_with("curve =") || from.starts_with("function") {
        true => base.find("type = \"path\"").unwrap(),
        false => base.find("\n[[curve]]\n").unwrap(),
    };
    let k = section
        + base[section..]
            .find(from)
            .unwrap_or_else(|| panic!("{from}"));
    format!("{}{to}{}", &base[..k], &base[k + from.len()..])
}

/// `base` with `from` replaced by `to` in its curve (`edited`): `cardan check` fails at the
/// first line after `[[curve]]` containing `at`, with a message containing every needle.
fn fails_in(base: &str, from: &str, to: &str, at: &str, needles: &[&str]) {
    let text = edited(base, from, to);
    let o = run_text("check", &text);
    assert_ne!(o.code, 0, "should fail: {}", o.stdout);
    let start = text.find("\n[[curve]]\n").unwrap();
    let at = start + text[start..].find(at).unwrap();
    let line = text[..at].matches('\n').count() + 1;
    let want = format!("model.toml:{line}:");
    assert!(
        o.stderr.starts_with(&want),
        "want {want}, got: {}",
        o.stderr
    );
    for n in needles {
        assert!(o.stderr.contains(n), "missing {n:?} in: {}", o.stderr);
    }
}

/// The quick-return example with its straight slot written as a spline through `points` (in
/// the lever's coordinates).
fn spline_slot(points: &str) -> String {
    let base = example("quick_return.toml");
    let text = edited(&base, "type = \"line\"", "type = \"spline\"");
    let text = edited(&text, "point_i = \"O4\"", &format!("points = {points} #"));
    edited(&text, "axis_i = \"x\"\n", "")
}

#[test]
fn curve_mistakes_are_errors_at_their_key() {
    let qr = example("quick_return.toml");
    fails_in(
        &qr,
        "type = \"line\"",
        "type = \"lin\"",
        "type = \"lin\"",
        &["unknown curve type \"lin\"", "line"],
    );
    fails_in(
        &qr,
        "point_i = \"O4\"",
        "radius = 0.1\npoint_i = \"O4\"",
        "radius = 0.1",
        &["curve \"slot\"", "type = \"line\" does not take \"radius\""],
    );
    fails_in(
        &qr,
        "axis_i = \"x\"",
        "axis_i = \"xx\"",
        "axis_i = \"xx\"",
        &["curve \"slot\"", "body \"lever\" has no vector \"xx\""],
    );
    fails_in(
        &qr,
        "point_j = \"A\"",
        "point_j = \"B\"",
        "point_j = \"B\"",
        &["slot", "\"B\""],
    );
    fails_in(
        &qr,
        "body_j = \"crank\"",
        "body_j = \"crnk\"",
        "body_j = \"crnk\"",
        &["slot", "crnk", "crank"],
    );
    fails_in(
        &qr,
        "name = \"slot\"",
        "name = \"lever_pivot\"",
        "name = \"lever_pivot\"",
        &["duplicate name \"lever_pivot\""],
    );

    let arm = example("arm_path.toml");
    fails_in(
        &arm,
        "radius = 0.1",
        "radius = 0.0",
        "radius = 0.0",
        &["curve \"path\"", "radius"],
    );
    fails_in(
        &arm,
        "radius = 0.1\n",
        "",
        "name = \"path\"",
        &["missing key \"radius\""],
    );
    fails_in(
        &arm,
        "x_axis_i = \"x\"",
        "x_axis_i = \"z\"",
        "x_axis_i = \"z\"",
        &["parallel to axis_i"],
    );
    fails_in(
        &arm,
        "curve = \"path\"",
        "curve = \"pth\"",
        "curve = \"pth\"",
        &["driver \"feed\"", "pth", "path"],
    );
    fails_in(
        &arm,
        "curve = \"path\"\n",
        "",
        "name = \"feed\"",
        &["missing key \"curve\""],
    );

    let spline = spline_slot("[[0.0, 0.0, 0.0], [0.2, 0.0, 0.0], [0.6, 0.0, 0.0]]");
    let points = "points = [[0.0, 0.0, 0.0], [0.2, 0.0, 0.0], [0.6, 0.0, 0.0]]";
    let repeated = "points = [[0.0, 0.0, 0.0], [0.2, 0.0, 0.0], [0.2, 0.0, 0.0], [0.6, 0.0, 0.0]]";
    fails_in(
        &spline,
        points,
        repeated,
        "points =",
        &["curve \"slot\": points[1] and points[2] coincide"],
    );
    fails_in(
        &spline,
        points,
        "points = [[0.0, 0.0, 0.0]]",
        "points =",
        &["an open spline needs at least 2 points, got 1"],
    );
    fails_in(
        &spline,
        points,
        &format!("{points}\nclosed = true"),
        "points =",
        &["a closed spline needs at least 4 points"],
    );
    let four = "points = [[0.0, 0.0, 0.0], [0.2, 0.0, 0.0], [0.6, 0.1, 0.0], [0.0, 0.3, 0.0]]";
    fails_in(
        &spline,
        points,
        &format!("{four}\nclosed = true"),
        "points =",
        &[
            "is 3.000e-1 from its first",
            "repeat the first point at the end",
        ],
    );
    fails_in(
        &spline,
        points,
        &format!("{points}\ninitial_u = 0.9"),
        "initial_u = 0.9",
        &["slot", "0.9"],
    );
}

/// The straight slot written as a natural cubic spline through collinear points is the same
/// line (a natural spline reproduces linear data), parametrized by the distance from its first
/// point: the quick return's lever angle and slot parameter agree with the line's run.
#[test]
fn a_spline_slot_through_collinear_points_is_the_straight_slot() {
    let line = run_text("run", &example("quick_return.toml"));
    assert_eq!(line.code, 0, "{}", line.stderr);
    let text =
        spline_slot("[[0.0, 0.0, 0.0], [0.15, 0.0, 0.0], [0.25, 0.0, 0.0], [0.6, 0.0, 0.0]]");
    let spline = run_text("run", &text);
    assert_eq!(spline.code, 0, "{}", spline.stderr);
    for table in [
        "joints.csv",
        "joint_velocities.csv",
        "joint_accelerations.csv",
    ] {
        let a = std::fs::read_to_string(line.dir.join("out").join(table)).unwrap();
        let b = std::fs::read_to_string(spline.dir.join("out").join(table)).unwrap();
        let (ha, ra) = cardan_model::table::parse_csv(&a).unwrap();
        let (hb, rb) = cardan_model::table::parse_csv(&b).unwrap();
        assert_eq!(ha, hb);
        let worst = (ra.iter().zip(&rb))
            .flat_map(|(x, y)| x.iter().zip(y).map(|(p, q)| (p - q).abs()))
            .fold(0.0f64, f64::max);
        eprintln!("{table}: spline slot vs line slot {worst:.1e}");
        assert!(worst < 1e-10, "{table}: {worst:e}");
    }
}

/// A slot too short for the pin: the run stops where the pin leaves the slot's end, with the
/// time and the parameter, and the rows before are kept.
#[test]
fn a_pin_driven_off_its_slot_is_an_error_with_the_time() {
    // |O4 A| ranges over [0.2, 0.4]: a slot ending at 0.35 is left at the top of the stroke.
    let text = spline_slot("[[0.0, 0.0, 0.0], [0.2, 0.0, 0.0], [0.35, 0.0, 0.0]]");
    let o = run_text("run", &text);
    assert_ne!(o.code, 0, "{}", o.stdout);
    for needle in [
        "\"slot\"",
        "at t = ",
        "run off the end of its open curve",
        "0.35",
    ] {
        assert!(
            o.stderr.contains(needle),
            "missing {needle:?} in: {}",
            o.stderr
        );
    }
}
