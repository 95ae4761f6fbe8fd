//! `[[curve]]` and `[[driver]] type = "path"` through the model file (issue 49): a slot as a
//! spline through collinear points equals the straight slot, a pin driven off an open slot's end
//! is an error with the time, and every mistake in a curve or a path driver is an error at its
//! key's line.

mod common;
use common::{check_fails_at, run_text};

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
    check_fails_at(&text, line_after(&text, "\n[[curve]]\n", at), needles);
}

/// The 1-based line of the first `at` after `header` in `text`.
fn line_after(text: &str, header: &str, at: &str) -> usize {
    let start = text.find(header).unwrap();
    let at = start + text[start..].find(at).unwrap_or_else(|| panic!("{at}"));
    text[..at].matches('\n').count() + 1
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
        &["parallel to axis"],
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

/// `base` with the first `from` after its `[[cam]]` header replaced by `to`: `cardan check`
/// fails at the first line after the header containing `at`, with every needle.
fn cam_fails(from: &str, to: &str, at: &str, needles: &[&str]) {
    let base = example("valve_train.toml");
    let start = base.find("\n[[cam]]\n").unwrap();
    let k = start + base[start..].find(from).unwrap_or_else(|| panic!("{from}"));
    let text = format!("{}{to}{}", &base[..k], &base[k + from.len()..]);
    check_fails_at(&text, line_after(&text, "\n[[cam]]\n", at), needles);
}

#[test]
fn cam_mistakes_are_errors_at_their_key() {
    cam_fails(
        "follower = \"flat\"",
        "follower = \"flag\"",
        "follower = \"flag\"",
        &["unknown cam follower \"flag\"", "flat"],
    );
    cam_fails(
        "radius = 0.02",
        "radius = -0.02",
        "radius = -0.02",
        &["cam \"lobe\"", "radius"],
    );
    cam_fails(
        "radius = 0.02\n",
        "",
        "name = \"lobe\"",
        &["missing key \"radius\""],
    );
    cam_fails(
        "radius = 0.02",
        "radius = 0.02\npoints = [[0.0, 0.0, 0.0]]",
        "points =",
        &["points is for profile = \"spline\", not \"disc\""],
    );
    cam_fails(
        "follower = \"flat\"",
        "follower = \"roller\"",
        "name = \"lobe\"",
        &["missing key \"roller_radius\""],
    );
    cam_fails(
        "axis_j = \"x\"",
        "axis_j = \"x\"\nroller_radius = 0.01",
        "roller_radius",
        &["follower = \"flat\" does not take \"roller_radius\""],
    );
    cam_fails(
        "point_i = \"C\"",
        "point_i = \"D\"",
        "point_i = \"D\"",
        &["cam \"lobe\"", "body \"camshaft\" has no point \"D\""],
    );
    cam_fails(
        "profile = \"disc\"",
        "profile = \"spline\"",
        "point_i = \"C\"",
        &["point_i is for profile = \"disc\", not \"spline\""],
    );
}

/// The valve train with a roller of radius 4 mm on its tappet (axis z), the tappet drawn at
/// height `y`.
fn roller_valve_train(base: &str, y: &str) -> String {
    base.replacen(
        "follower = \"flat\"\nbody_i",
        "follower = \"roller\"\nbody_i",
        1,
    )
    .replacen(
        "axis_j = \"x\"              # ... along x",
        "axis_j = \"z\"\nroller_radius = 0.004",
        1,
    )
    .replacen(
        "y = [0.0, 1.0, 0.0] }",
        "y = [0.0, 1.0, 0.0], z = [0.0, 0.0, 1.0] }",
        1,
    )
    .replacen(
        "position = [0.0, 0.015, 0.0]",
        &format!("position = [0.0, {y}, 0.0]"),
        1,
    )
}

/// A roller follower on the same disc: the roller centre follows the closed form
/// s(θ) = e cos θ' + √((R + r)² − e² sin² θ') along the tappet's line of motion, θ' the angle
/// of the disc's centre from that line (here θ' = θ + π: the centre starts below the shaft).
#[test]
fn a_roller_tappet_follows_the_closed_form() {
    let base = example("valve_train.toml");
    let r = 0.004;
    let text = roller_valve_train(&base, "0.019");
    let o = run_text("run", &text);
    assert_eq!(o.code, 0, "{}", o.stderr);
    let csv = std::fs::read_to_string(o.dir.join("out").join("joints.csv")).unwrap();
    let (header, rows) = cardan_model::table::parse_csv(&csv).unwrap();
    let k = header.iter().position(|h| h == "guide.slide [m]").unwrap();
    let (e, big_r, w) = (0.005, 0.02, 100.0 * std::f64::consts::PI);
    let mut worst = 0.0f64;
    for row in &rows {
        // The disc's centre at (e sin θ, −e cos θ): |(0, s) − centre| = R + r.
        let th = w * row[0];
        let l = big_r + r;
        let s = -e * th.cos() + (l * l - e * e * th.sin().powi(2)).sqrt();
        worst = worst.max((row[k] - s).abs());
    }
    eprintln!("roller tappet: |s − s(θ)| = {worst:.1e} m");
    assert!(worst < 1e-12, "{worst}");
}

/// The arm's tool point on a closed spline through 12 points of its circle, driven by
/// `arc_length = true` with S = v t: the tool moves at speed v to 1e-10 (the spline's own
/// parameter, its chord length, would not: without the key the speed varies by 1e-3 of v).
#[test]
fn an_arc_length_path_driver_moves_the_tool_along_a_spline_at_constant_speed() {
    let base = example("arm_path.toml");
    let points: Vec<String> = (0..=12)
        .map(|k| {
            let a = std::f64::consts::TAU * (k % 12) as f64 / 12.0;
            format!("[{}, {}, 0.0]", 0.3 + 0.1 * a.cos(), 0.3 + 0.1 * a.sin())
        })
        .collect();
    let spline = format!(
        "type = \"spline\"\nbody_i = \"ground\"\npoints = [{}]\nclosed = true\n",
        points.join(", ")
    );
    let start = base.find("\n[[curve]]\n").unwrap();
    let end = start + base[start..].find("body_j = \"fore\"").unwrap();
    let from = base[start..end].find("type = ").unwrap() + start;
    let text = format!("{}{spline}{}", &base[..from], &base[end..]);
    let speeds = |text: &str| {
        let o = run_text("run", text);
        assert_eq!(o.code, 0, "{}", o.stderr);
        let csv = std::fs::read_to_string(o.dir.join("out").join("point_velocities.csv")).unwrap();
        let (_, rows) = cardan_model::table::parse_csv(&csv).unwrap();
        rows.iter()
            .map(|r| (r[1] * r[1] + r[2] * r[2] + r[3] * r[3]).sqrt())
            .collect::<Vec<f64>>()
    };
    let worst = |v: &[f64]| v.iter().map(|s| (s - 0.2).abs()).fold(0.0f64, f64::max);
    let by_chord = worst(&speeds(&text));
    let arc = text.replacen("curve = \"path\"", "curve = \"path\"\narc_length = true", 1);
    let by_arc = worst(&speeds(&arc));
    eprintln!("tool speed − v along the spline: {by_arc:.1e} (arc length), {by_chord:.1e} (chord)");
    assert!(by_arc < 1e-10, "{by_arc}");
    assert!(by_chord > 1e-4, "{by_chord}");
}

/// A follower drawn off its cam, a roller drawn into it (the curves cross), and a pin drawn
/// off its slot are errors at the element's name with the gap: the assembly would otherwise
/// pull the bodies together silently (before this check the tappet drawn 15 mm above the disc
/// ran without a word).
#[test]
fn curve_elements_drawn_apart_are_errors_with_the_gap() {
    let vt = example("valve_train.toml");
    let tappet = "position = [0.0, 0.015, 0.0]";
    let off = vt.replacen(tappet, "position = [0.0, 0.030, 0.0]", 1);
    check_fails_at(&off, line_after(&off, "\n[[cam]]\n", "name = \"lobe\""), &[
        "cam \"lobe\": the follower's curve is off the cam's profile at the drawn pose (1.500e-2 m, more than 2.0e-5 m",
        "draw the follower touching the cam",
    ]);
    let roller = roller_valve_train(&vt, "0.017");
    check_fails_at(
        &roller,
        line_after(&roller, "\n[[cam]]\n", "name = \"lobe\""),
        &["crosses the cam's profile instead of touching it"],
    );
    let qr = example("quick_return.toml");
    let lever = "angle = 1.2490457723982544";
    let off = qr.replacen(lever, "angle = 1.3", 1);
    check_fails_at(
        &off,
        line_after(&off, "\n[[curve]]\n", "name = \"slot\""),
        &["point-on-curve \"slot\": the point is off its curve at the drawn pose"],
    );
}

/// The valve train's disc given as a closed spline through 24 of its points: the tappet lifts
/// e(1 − cos θ) to the interpolation error of the spline (R (2π/24)⁴ / 384 ≈ 2.4e-7 m for a
/// circle), and the lift's acceleration follows too (the spline is C²).
#[test]
fn a_spline_cam_profile_lifts_the_tappet_as_its_disc_does() {
    let cubic = spline_cam_lift_error("");
    // interpolation = "quintic": C⁴ through the same points, its error of a circle O(h⁶).
    let quintic = spline_cam_lift_error("\ninterpolation = \"quintic\"");
    eprintln!("spline cam: |s − s(θ)| = {cubic:.1e} m (cubic), {quintic:.1e} m (quintic)");
    assert!(cubic < 1e-6, "{cubic}");
    assert!(quintic < 1e-8 && quintic < cubic / 20.0, "{quintic}");
}

/// The valve train's disc as a closed spline through 24 of its points (`extra` added after the
/// points): the largest |lift − e (1 − cos θ)| over a revolution.
fn spline_cam_lift_error(extra: &str) -> f64 {
    let vt = example("valve_train.toml");
    let points: Vec<String> = (0..=24)
        .map(|k| {
            let a = std::f64::consts::TAU * (k % 24) as f64 / 24.0;
            format!("[{}, {}, 0.0]", 0.02 * a.cos(), -0.005 + 0.02 * a.sin())
        })
        .collect();
    let text = vt.replacen(
        "profile = \"disc\"\npoint_i = \"C\"\nradius = 0.02",
        &format!(
            "profile = \"spline\"\npoints = [{}]{extra}",
            points.join(", ")
        ),
        1,
    );
    assert_ne!(text, vt);
    let o = run_text("run", &text);
    assert_eq!(o.code, 0, "{}", o.stderr);
    let csv = std::fs::read_to_string(o.dir.join("out").join("joints.csv")).unwrap();
    let (header, rows) = cardan_model::table::parse_csv(&csv).unwrap();
    let k = header.iter().position(|h| h == "guide.slide [m]").unwrap();
    let (e, w) = (0.005, 100.0 * std::f64::consts::PI);
    (rows.iter())
        .map(|r| (r[k] - 0.015 - e * (1.0 - (w * r[0]).cos())).abs())
        .fold(0.0f64, f64::max)
}

/// The interpolation key: only cubic or quintic, only on a spline.
#[test]
fn the_interpolation_key_is_checked() {
    let vt = example("valve_train.toml");
    let text = vt.replacen(
        "radius = 0.02",
        "radius = 0.02\ninterpolation = \"quintic\"",
        1,
    );
    check_fails_at(
        &text,
        line_after(&text, "\n[[cam]]\n", "interpolation"),
        &["interpolation is for profile = \"spline\""],
    );
    let text = spline_slot("[[0.0, 0.0, 0.0], [0.5, 0.0, 0.0], [1.0, 0.0, 0.0]]");
    let text = text.replacen(
        "type = \"spline\"",
        "type = \"spline\"\ninterpolation = \"septic\"",
        1,
    );
    check_fails_at(
        &text,
        line_after(&text, "\n[[curve]]\n", "interpolation"),
        &["septic", "quintic"],
    );
}

/// `examples/valve_spring.toml` run at 8400 rpm, above its closed-form lift-off speed
/// ω = √((F₀ + 2 k e)/(m e)) = 836.7 rad/s (7990 rpm): the contact pulls from the first output
/// time past cos θ* = −(F₀ + k e)/(m e ω² − k e), and the run says so in its summary and
/// run.json, naming the cam and the time; at 3000 rpm it says nothing.
#[test]
fn a_tappet_run_above_its_lift_off_speed_is_warned_about_with_the_time() {
    let base = example("valve_spring.toml");
    let clean = run_text("run", &base);
    assert_eq!(clean.code, 0, "{}", clean.stderr);
    let json = std::fs::read_to_string(clean.dir.join("out/run.json")).unwrap();
    assert!(!json.contains("lift off"), "{json}");

    let omega = 8400.0 * std::f64::consts::PI / 30.0;
    let text = base.replace(
        "coefficients = [0.0, 314.1592653589793]",
        &format!("coefficients = [0.0, {omega}]"),
    );
    let text = text.replace("t_end = 0.02 ", "t_end = 0.0071428571428571 ");
    let text = text.replace("steps = 180", "steps = 720");
    let o = run_text("run", &text);
    assert_eq!(o.code, 0, "{}", o.stderr);
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(o.dir.join("out/run.json")).unwrap())
            .unwrap();
    let warning = json["warnings"]
        .as_array()
        .unwrap()
        .iter()
        .filter_map(|w| w.as_str())
        .find(|w| w.contains("lift off"))
        .unwrap_or_else(|| panic!("no lift-off warning: {json}"));
    assert!(
        warning.starts_with("cam \"lobe\": the contact pulls"),
        "{warning}"
    );
    let (m, k, e, f0) = (0.1, 2.0e4, 0.005, 150.0);
    let theta = (-(f0 + k * e) / (m * e * omega * omega - k * e)).acos();
    let h = 0.0071428571428571 / 720.0;
    let from = warning
        .split("from t = ")
        .nth(1)
        .and_then(|r| r.split(' ').next())
        .and_then(|t| t.parse::<f64>().ok())
        .unwrap_or_else(|| panic!("no time in {warning}"));
    eprintln!(
        "lift-off: warned from t = {from} s, closed form θ*/ω = {} s",
        theta / omega
    );
    assert!(
        from >= theta / omega && from < theta / omega + h,
        "{warning}"
    );
    assert!(o.stdout.contains("lift off") || o.stderr.contains("lift off"));
}

/// `examples/valve_spring.toml` as a static analysis at θ = 1.1 rad: the contact force is the
/// spring's, N = F₀ + k e (1 − cos θ), and the motor holds the camshaft with T = N e sin θ.
#[test]
fn the_valve_train_held_still_needs_the_closed_form_torque() {
    let base = example("valve_spring.toml");
    let omega = 100.0 * std::f64::consts::PI;
    let th: f64 = 1.1;
    let at = base.find("[analysis]").unwrap();
    let text = format!(
        "{}[analysis]\nkind = \"static\"\ntime = {}\n\n[analysis.outputs]\njoints = [\"lobe\"]\n",
        &base[..at],
        th / omega
    );
    let o = run_text("run", &text);
    assert_eq!(o.code, 0, "{}", o.stderr);
    let read = |name: &str| {
        let csv = std::fs::read_to_string(o.dir.join("out").join(name)).unwrap();
        cardan_model::table::parse_csv(&csv).unwrap()
    };
    let (header, rows) = read("cam_forces.csv");
    let k = header
        .iter()
        .position(|h| h == "lobe.normal_force [N]")
        .unwrap();
    let (e, stiffness, f0) = (0.005, 2.0e4, 150.0);
    let n = f0 + stiffness * e * (1.0 - th.cos());
    let (_, efforts) = read("driver_efforts.csv");
    let (nerr, terr) = (
        (rows[0][k] - n).abs(),
        (efforts[0][1] - n * e * th.sin()).abs(),
    );
    eprintln!("held valve train: |N − N(θ)| {nerr:.1e} N, |T − N e sin θ| {terr:.1e} N m");
    assert!(nerr < 1e-9 && terr < 1e-11, "{nerr} {terr}");
}

/// `examples/torus_follower.toml` with `from` replaced by `to` in its `[[surface]]`: `cardan
/// check` fails at the first line after the header containing `at`, with every needle.
fn surface_fails(from: &str, to: &str, at: &str, needles: &[&str]) {
    let base = example("torus_follower.toml");
    let section = base.find("\n[[surface]]\n").unwrap();
    let k = section
        + base[section..]
            .find(from)
            .unwrap_or_else(|| panic!("{from}"));
    let text = format!("{}{to}{}", &base[..k], &base[k + from.len()..]);
    check_fails_at(&text, line_after(&text, "\n[[surface]]\n", at), needles);
}

/// Every mistake in a `[[surface]]` is an error at its key's line.
#[test]
fn surface_mistakes_are_errors_at_their_key() {
    surface_fails(
        "type = \"torus\"",
        "type = \"donut\"",
        "type",
        &["unknown surface type \"donut\"", "torus"],
    );
    surface_fails(
        "tube_radius = 0.4",
        "tube_radius = 1.5",
        "tube_radius",
        &["tube radius", "smaller than its major radius"],
    );
    surface_fails(
        "tube_radius = 0.4\n",
        "",
        "name",
        &["missing key \"tube_radius\""],
    );
    surface_fails(
        "radius = 1.0 ",
        "radius = -1.0 ",
        "radius",
        &["radius", "-1"],
    );
    let torus_keys = "point_i = \"O\"\naxis_i = \"x\"              # the torus' axis\n\
                      x_axis_i = \"y\"            # u = 0 on the centre circle's +y point\n\
                      radius = 1.0              # the centre circle\ntube_radius = 0.4\n";
    let base = example("torus_follower.toml").replace(torus_keys, "");
    let at = base.find("\n[[surface]]\n").unwrap();
    let patch = format!(
        "{}{}",
        &base[..at],
        base[at..].replacen(
            "type = \"torus\"",
            "type = \"patch\"\npoints = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0]]",
            1
        )
    );
    check_fails_at(
        &patch,
        line_after(&patch, "\n[[surface]]\n", "points"),
        &["16 control points", "got 2"],
    );
    surface_fails(
        "type = \"torus\"",
        "type = \"plane\"\npitch = 2.0",
        "pitch",
        &["pitch"],
    );
    // The tip drawn 5 cm off the torus.
    surface_fails(
        "tube_radius = 0.4",
        "tube_radius = 0.35",
        "name",
        &["point is off its surface", "draw the point on the surface"],
    );
    surface_fails(
        "point_j = \"T\"",
        "point_j = \"T\"\ninitial_u = 0.5",
        "initial_u",
        &["initial_u needs initial_v"],
    );
}
