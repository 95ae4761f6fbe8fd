//! `[[limit]]` and `[[friction]]` through the model file (issue 48): the bundled pendulum
//! falling onto a stop against its closed forms (impact times, rates, the energy each impact
//! takes, the accumulation of bounces into rest on the stop, the held stop's reaction), a
//! kinematic motion driven into a stop, a block sliding on an incline with joint friction, and
//! every mistake in a limit or a friction an error at its key's line.

mod common;
use common::{check_fails_at, run_text};

const G: f64 = 9.81;
/// The pendulum's hinge inertia J = m (L/2)² + I_zz = 1/4 + 1/12 (examples/pendulum_stop.toml).
const J: f64 = 1.0 / 3.0;
/// m g L / (2 J): ω² = 2 K sin φ from rest at the horizontal (φ below it).
const K: f64 = 1.0 * G * 0.5 / J;
const E: f64 = 0.5;
const STOP: f64 = std::f64::consts::FRAC_PI_3;

fn example(name: &str) -> String {
    let path = std::path::PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../../examples")
        .join(name);
    std::fs::read_to_string(path).unwrap()
}

/// The numbers of a CSV line.
fn numbers(line: &str) -> Vec<f64> {
    line.split(',').map(|x| x.parse().unwrap()).collect()
}

/// The last row of a CSV text, as numbers.
fn last_row(csv: &str) -> Vec<f64> {
    numbers(csv.lines().last().unwrap())
}

/// ∫ f over [a, b] by composite Simpson with `n` (even) intervals.
fn simpson(f: impl Fn(f64) -> f64, a: f64, b: f64, n: usize) -> f64 {
    let h = (b - a) / n as f64;
    let inner: f64 = (1..n)
        .map(|k| f(a + k as f64 * h) * if k % 2 == 1 { 4.0 } else { 2.0 })
        .sum();
    (f(a) + f(b) + inner) * h / 3.0
}

/// The time from rest at the horizontal to the stop: ∫ dφ / √(2K sin φ), with φ = u² to take
/// the root's singularity out.
fn fall_time() -> f64 {
    let f = |u: f64| {
        if u == 0.0 {
            2.0 / (2.0 * K).sqrt()
        } else {
            2.0 * u / (2.0 * K * (u * u).sin()).sqrt()
        }
    };
    simpson(f, 0.0, STOP.sqrt(), 4000)
}

/// The time of a rebound leaving the stop at rate `w` and returning to it: up to the apex φ₀
/// (sin φ₀ = sin 60° − w²/2K) and back, 2 ∫ dφ / √(2K (sin φ − sin φ₀)), with φ = φ₀ + u².
fn flight_time(w: f64) -> f64 {
    if w < 1e-4 {
        // Ballistic against the deceleration K cos 60° (the quadrature loses its digits).
        return 2.0 * w / (K * STOP.cos());
    }
    let s0 = STOP.sin() - w * w / (2.0 * K);
    let p0 = s0.asin();
    let f = |u: f64| {
        if u == 0.0 {
            2.0 / (2.0 * K * p0.cos()).sqrt()
        } else {
            // sin(φ₀ + x) − sin φ₀ = 2 cos(φ₀ + x/2) sin(x/2), without cancellation.
            let x = u * u;
            2.0 * u / (2.0 * K * 2.0 * (p0 + 0.5 * x).cos() * (0.5 * x).sin()).sqrt()
        }
    };
    2.0 * simpson(f, 0.0, (STOP - p0).sqrt(), 4000)
}

/// events.csv's rows: time, event, impact rate, rebound rate, impulse, energy change.
fn events(text: &str) -> Vec<(f64, String, f64, f64, f64, f64)> {
    let mut lines = text.lines();
    assert_eq!(
        lines.next().unwrap(),
        "t [s],stop,joint,event,impact rate,rebound rate,rate unit,impulse,impulse unit,energy change [J]"
    );
    lines
        .map(|l| {
            let c: Vec<&str> = l.split(',').collect();
            let n = |k: usize| c[k].parse::<f64>().unwrap();
            assert_eq!(
                (c[1], c[2], c[6], c[8]),
                ("stop.lower", "hinge", "rad/s", "N m s")
            );
            (n(0), c[3].to_string(), n(4), n(5), n(7), n(9))
        })
        .collect()
}

#[test]
fn a_pendulum_falling_onto_a_stop_bounces_to_rest_as_the_closed_form_says() {
    let o = run_text("run", &example("pendulum_stop.toml"));
    assert_eq!(o.code, 0, "{}", o.stderr);
    let out = o.dir.join("out");
    let ev = events(&std::fs::read_to_string(out.join("events.csv")).unwrap());
    assert!(ev.len() >= 10, "{} events", ev.len());
    let mut w = (2.0 * K * STOP.sin()).sqrt();
    let mut t = fall_time();
    for (k, (time, event, before, after, impulse, de)) in ev.iter().enumerate() {
        // Rates and energies from e and the energy balance; times from the quadratures, while
        // the rates are large enough for the location tolerance to be small beside them.
        if w > 1e-3 {
            assert!((time - t).abs() < 1e-8, "impact {k}: t {time} vs {t}");
            assert!(
                (before + w).abs() < 1e-8 * w.max(1.0),
                "impact {k}: {before} vs −{w}"
            );
            assert!(
                (after - E * w).abs() < 1e-8 * w.max(1.0),
                "impact {k}: {after}"
            );
            assert!(
                (impulse - J * (1.0 + E) * w).abs() < 1e-8,
                "impact {k}: {impulse}"
            );
            let lost = -0.5 * J * (1.0 - E * E) * w * w;
            assert!(
                (de - lost).abs() < 1e-8 * lost.abs().max(1e-3),
                "impact {k}: {de} vs {lost}"
            );
            assert_eq!(event, "impact");
        }
        t += flight_time(E * w);
        w *= E;
    }
    // The bounces accumulate in finite time: t₁ + Σ T(eⁿ ω₁); the last one holds the stop.
    let mut t_rest = fall_time();
    let mut w = (2.0 * K * STOP.sin()).sqrt();
    while w > 1e-12 {
        t_rest += flight_time(E * w);
        w *= E;
    }
    let (last_t, last_event, ..) = ev.last().unwrap();
    assert_eq!(last_event, "impact_held");
    assert!((last_t - t_rest).abs() < 1e-5, "{last_t} vs {t_rest}");
    // Held on the stop, it carries m g (L/2) cos 60° (stops.csv, the last output).
    let stops = std::fs::read_to_string(out.join("stops.csv")).unwrap();
    assert!(stops.starts_with("t [s],stop.lower held [-],stop.lower force [N m]\n"));
    let last = last_row(&stops);
    assert_eq!(last[1], 1.0);
    assert!((last[2] - G * 0.5 * STOP.cos()).abs() < 1e-6, "{}", last[2]);
    // The impacts' work enters W_nc: the balance closes.
    let json = std::fs::read_to_string(out.join("run.json")).unwrap();
    assert!(json.contains("\"warnings\": []"), "{json}");
    // The summary line and run.json count the events: every row of events.csv an impact, the
    // last one held, the stop held at the end.
    let n = ev.len();
    let counts = format!(
        "\"stops\": {{\n    \"impacts\": {n},\n    \"held_impacts\": 1,\n    \"releases\": 0,\n    \"held_at_end\": 1\n  }}"
    );
    assert!(json.contains(&counts), "{json}");
    let line = format!("{n} impacts (1 held), 0 releases, 1 stop held at the end");
    assert!(o.stdout.contains(&line), "{}", o.stdout);
}

/// The pendulum with `from` replaced by `to`: `cardan check` fails at the line of `at` with a
/// message containing every needle.
fn fails(from: &str, to: &str, at: &str, needles: &[&str]) {
    let base = example("pendulum_stop.toml");
    assert!(base.contains(from), "{from}");
    let text = base.replacen(from, to, 1);
    let line = text.lines().position(|l| l.contains(at)).unwrap() + 1;
    check_fails_at(&text, line, needles);
}

#[test]
fn limit_mistakes_are_errors_at_their_key() {
    let lower = "lower = -1.0471975511965976   # −60°, in rad\n";
    fails(
        lower,
        "lower = 0.5\nupper = 0.2\n",
        "upper = 0.2",
        &["limit \"stop\"", "range is empty"],
    );
    fails(
        lower,
        "lower = 0.5\n",
        "lower = 0.5",
        &["drawn pose violates its lower bound"],
    );
    fails(
        "restitution = 0.5",
        "restitution = 1.5",
        "restitution = 1.5",
        &["e = 1.5 must lie in [0, 1]"],
    );
    fails(
        "restitution = 0.5",
        "restitution = -0.1",
        "restitution = -0.1",
        &["must lie in [0, 1]"],
    );
    fails(
        "restitution = 0.5",
        "restitution = 0.5\ncoordinate = \"slide\"",
        "coordinate = \"slide\"",
        &[
            "a revolute joint has no coordinate \"slide\"",
            "its coordinates: angle",
        ],
    );
    fails(
        "restitution = 0.5",
        "stiffness = 1e4",
        "stiffness = 1e4",
        &["law = \"impact\" does not take \"stiffness\" (it applies to law = \"compliant\")"],
    );
    fails(
        "restitution = 0.5",
        "law = \"springy\"",
        "law = \"springy\"",
        &["unknown limit law \"springy\""],
    );
    fails(
        "restitution = 0.5",
        "law = \"compliant\"",
        "name = \"stop\"",
        &["missing key \"stiffness\""],
    );
    fails(
        "joint = \"hinge\"           #",
        "joint = \"hing\"           #",
        "joint = \"hing\"           #",
        &["unknown joint \"hing\"", "did you mean \"hinge\"?"],
    );
    fails(
        lower,
        "",
        "name = \"stop\"",
        &["give a lower bound, an upper bound or both"],
    );
    fails(
        "name = \"stop\"",
        "name = \"hinge\"   # the limit",
        "name = \"hinge\"   # the limit",
        &["duplicate name \"hinge\": a joint of that name"],
    );
    // An angle needs its zero: the joint's x axes.
    let text = example("pendulum_stop.toml")
        .replace("x_axis_i = \"x\"\n", "")
        .replace("x_axis_j = \"x\"\n", "");
    let o = run_text("check", &text);
    assert_ne!(o.code, 0);
    assert!(o.stderr.contains("needs its x axes"), "{}", o.stderr);
}

#[test]
fn friction_mistakes_are_errors_at_their_key() {
    let add = |extra: &str| {
        format!("[[friction]]\nname = \"pin\"\njoint = \"hinge\"\n{extra}\n\n[analysis]")
    };
    let base = "[analysis]";
    fails(
        base,
        &add("coefficient = -0.1\nradius = 0.01"),
        "coefficient = -0.1",
        &["friction \"pin\"", "coefficient"],
    );
    fails(
        base,
        &add("coefficient = 0.1"),
        "name = \"pin\"",
        &["radius"],
    );
    fails(
        base,
        &add("radius = 0.01"),
        "name = \"pin\"",
        &["missing key \"coefficient\""],
    );
    fails(
        base,
        &add("coefficient = 0.1\nradius = 0.01\nrestitution = 0.2"),
        "restitution = 0.2",
        &["unknown key \"restitution\""],
    );
    // The constant law: a pin takes a torque, not a force; it must have one; it takes no μ.
    fails(
        base,
        &add("law = \"constant\"\nforce = 2.0"),
        "force = 2.0",
        &["friction \"pin\"", "is revolute, which has no slide"],
    );
    fails(
        base,
        &add("law = \"constant\""),
        "name = \"pin\"",
        &["a constant friction needs a force (N, a slide) or a torque"],
    );
    fails(
        base,
        &add("law = \"constant\"\ntorque = 0.5\ncoefficient = 0.1"),
        "coefficient = 0.1",
        &["law = \"constant\" does not take \"coefficient\" (it applies to law = \"coulomb\")"],
    );
    fails(
        base,
        &add("law = \"constant\"\ntorque = -0.5"),
        "torque = -0.5",
        &["must be ≥ 0"],
    );
}

#[test]
fn a_motion_driven_into_a_stop_ends_at_the_stop_with_the_limit_named() {
    let text = example("slider_crank.toml").replacen(
        "[[driver]]",
        "[[limit]]\nname = \"stroke\"\njoint = \"slide\"\nupper = 0.21\n\n[[driver]]",
        1,
    );
    let o = run_text("run", &text);
    assert_eq!(o.code, 3, "{}", o.stderr);
    let line = text.lines().position(|l| l == "upper = 0.21").unwrap() + 1;
    assert!(
        o.stderr.starts_with(&format!("model.toml:{line}:")),
        "{}",
        o.stderr
    );
    for n in [
        "limit \"stroke\" reached at t = 0.0361",
        "joint \"slide\"",
        "upper bound 0.21",
    ] {
        assert!(o.stderr.contains(n), "missing {n:?}: {}", o.stderr);
    }
    // The check lists the limit and the assembled pose's slide.
    let c = run_text("check", &text);
    assert_eq!(c.code, 0, "{}", c.stderr);
    assert!(c.stdout.contains("limits (1)"), "{}", c.stdout);
    assert!(
        c.stdout
            .contains("stroke  slide of slide  [-, 0.21] m  impact (e 0)  0.2 m      inside"),
        "{}",
        c.stdout
    );
}

/// A 2 kg block on a rail down an incline of angle α with μ = 0.3.
fn incline(alpha_deg: f64, mu: f64) -> String {
    let a = alpha_deg.to_radians();
    let (c, s) = (a.cos(), a.sin());
    format!(
        r#"[model]
name = "incline"
gravity = [0.0, -9.81, 0.0]

[ground]
points = {{ O = [0.0, 0.0, 0.0] }}
vectors = {{ d = [{c}, {ms}, 0.0], z = [0.0, 0.0, 1.0] }}

[[body]]
name = "block"
mass = 2.0
inertia = {{ diag = [0.1, 0.1, 0.1] }}
points = {{ C = [0.0, 0.0, 0.0] }}
vectors = {{ d = [{c}, {ms}, 0.0], z = [0.0, 0.0, 1.0] }}

[[joint]]
name = "rail"
type = "prismatic"
body_i = "ground"
point_i = "O"
axis_i = "d"
x_axis_i = "z"
body_j = "block"
point_j = "C"
axis_j = "d"
x_axis_j = "z"

[[friction]]
name = "dry"
joint = "rail"
coefficient = {mu}
stiction_velocity = 1e-6

[analysis]
kind = "dynamic"
integrator = "dopri5"
rtol = 1e-10
atol = 1e-12
t_end = 1.0
output_dt = 0.1

[analysis.outputs]
joints = ["rail"]
energy = true
"#,
        ms = -s
    )
}

#[test]
fn a_block_on_an_incline_slides_with_a_equal_g_sin_minus_mu_cos() {
    let (alpha, mu) = (30.0f64, 0.3);
    let o = run_text("run", &incline(alpha, mu));
    assert_eq!(o.code, 0, "{}", o.stderr);
    let joints = std::fs::read_to_string(o.dir.join("out/joints.csv")).unwrap();
    let header: Vec<&str> = joints.lines().next().unwrap().split(',').collect();
    let k = header
        .iter()
        .position(|h| h.starts_with("rail.slide"))
        .unwrap();
    let last = last_row(&joints);
    let a = G * (alpha.to_radians().sin() - mu * alpha.to_radians().cos());
    assert!((last[0] - 1.0).abs() < 1e-12);
    assert!(
        (last[k] - 0.5 * a).abs() < 1e-6 * a,
        "s(1) = {} vs {}",
        last[k],
        0.5 * a
    );
    // The friction's power is in energy.csv and the balance closes (no warning).
    let energy = std::fs::read_to_string(o.dir.join("out/energy.csv")).unwrap();
    assert!(
        energy.lines().next().unwrap().contains("dry"),
        "{}",
        energy.lines().next().unwrap()
    );
    let json = std::fs::read_to_string(o.dir.join("out/run.json")).unwrap();
    assert!(json.contains("\"warnings\": []"), "{json}");
    // friction.csv: the sliding block's friction force μ m g cos α against the motion (down
    // the slide, so negative along it once sliding), its power that force times the speed.
    let friction = std::fs::read_to_string(o.dir.join("out/friction.csv")).unwrap();
    assert_eq!(
        friction.lines().next().unwrap(),
        "t [s],dry force [N],dry power [W]"
    );
    let row = last_row(&friction);
    let expected = -mu * 2.0 * G * alpha.to_radians().cos();
    assert!((row[1] - expected).abs() < 1e-6 * expected.abs(), "{row:?}");
    assert!(
        (row[2] - expected * a).abs() < 1e-6 * (expected * a).abs(),
        "{row:?}"
    );
    // Generalized-α takes the friction too (its start from rest is off by h μ g cos α / 2 in
    // the speed, `crates/dynamics/tests/friction.rs`; the sliding friction force is exact).
    let text = incline(alpha, mu).replace(
        "integrator = \"dopri5\"\nrtol = 1e-10\natol = 1e-12",
        "integrator = \"generalized_alpha\"\ndt = 1e-3",
    );
    let o = run_text("run", &text);
    assert_eq!(o.code, 0, "{}\n{text}", o.stderr);
    let friction = std::fs::read_to_string(o.dir.join("out/friction.csv")).unwrap();
    let row = last_row(&friction);
    assert!((row[1] - expected).abs() < 1e-9 * expected.abs(), "{row:?}");
    // tan 15° < μ: it sticks (creeping at about v_s ρ/√(1 − ρ²)).
    let o = run_text("run", &incline(15.0, mu));
    assert_eq!(o.code, 0, "{}", o.stderr);
    let joints = std::fs::read_to_string(o.dir.join("out/joints.csv")).unwrap();
    let last = last_row(&joints);
    assert!(last[k].abs() < 1e-5, "stuck block moved {}", last[k]);
}

/// A double pendulum whose upper rod would hang at −90° but rests on a stop at −30°; the lower
/// rod hangs from its tip.
fn double_pendulum(kind: &str) -> String {
    format!(
        r#"[model]
name = "double"
gravity = [0.0, -9.81, 0.0]

[ground]
points = {{ O = [0.0, 0.0, 0.0] }}
vectors = {{ z = [0.0, 0.0, 1.0], x = [1.0, 0.0, 0.0] }}

[[body]]
name = "upper"
mass = 1.0
inertia = {{ diag = [1e-4, 0.083333333333333333, 0.083333333333333333] }}
position = [0.5, 0.0, 0.0]
points = {{ O = [-0.5, 0.0, 0.0], tip = [0.5, 0.0, 0.0] }}
vectors = {{ z = [0.0, 0.0, 1.0], x = [1.0, 0.0, 0.0] }}

[[body]]
name = "lower"
mass = 1.0
inertia = {{ diag = [1e-4, 0.083333333333333333, 0.083333333333333333] }}
position = [1.5, 0.0, 0.0]
points = {{ O = [-0.5, 0.0, 0.0] }}
vectors = {{ z = [0.0, 0.0, 1.0], x = [1.0, 0.0, 0.0] }}

[[joint]]
name = "shoulder"
type = "revolute"
body_i = "ground"
point_i = "O"
axis_i = "z"
x_axis_i = "x"
body_j = "upper"
point_j = "O"
axis_j = "z"
x_axis_j = "x"

[[joint]]
name = "elbow"
type = "revolute"
body_i = "upper"
point_i = "tip"
axis_i = "z"
body_j = "lower"
point_j = "O"
axis_j = "z"

[[limit]]
name = "rest"
joint = "shoulder"
lower = -0.5235987755982988   # −30°
upper = 0.5

[analysis]
kind = "{kind}"
"#
    )
}

#[test]
fn an_equilibrium_rests_on_the_stop_it_would_pass_and_vibrates_about_it() {
    // Static: the upper rod held at −30° by its stop, the lower one hanging from its tip; the
    // stop's torque balances both rods' weights about the shoulder.
    let o = run_text("run", &double_pendulum("static"));
    assert_eq!(o.code, 0, "{}", o.stderr);
    let efforts = std::fs::read_to_string(o.dir.join("out/driver_efforts.csv")).unwrap();
    let mut lines = efforts.lines();
    assert_eq!(lines.next().unwrap(), "t [s],rest.lower.torque [N m]");
    let torque = numbers(lines.next().unwrap())[1];
    let c = (-30f64).to_radians().cos();
    let expected = G * (0.5 * c + 1.0 * c); // upper's CM at L/2, lower's weight at the tip
    assert!((torque - expected).abs() < 1e-9, "{torque} vs {expected}");
    // Modal: the lower rod swings as a compound pendulum about the elbow, ω² = m g (L/2) / J.
    let o = run_text("run", &double_pendulum("modal"));
    assert_eq!(o.code, 0, "{}", o.stderr);
    let modes = std::fs::read_to_string(o.dir.join("out/modes.csv")).unwrap();
    let header: Vec<&str> = modes.lines().next().unwrap().split(',').collect();
    let row: Vec<&str> = modes.lines().nth(1).unwrap().split(',').collect();
    let k = header.iter().position(|h| *h == "frequency [Hz]").unwrap();
    let omega = std::f64::consts::TAU * row[k].parse::<f64>().unwrap();
    let expected = (G * 0.5 / J).sqrt();
    assert!(
        (omega - expected).abs() < 1e-8 * expected,
        "{omega} vs {expected}: {modes}"
    );
    assert_eq!(modes.lines().count(), 2, "one mode: {modes}");
    // The equilibrium inside the range holds no stop: with the stop below −90° nothing is held.
    let free =
        double_pendulum("static").replace("lower = -0.5235987755982988   # −30°", "lower = -2.0");
    let o = run_text("run", &free);
    assert_eq!(o.code, 0, "{}", o.stderr);
    assert!(!o.dir.join("out/driver_efforts.csv").exists());
}

/// Two 1 kg, 1 m rods along +x under gravity −y: the upper one turned about the shoulder at
/// θ = t by a rotation driver, the lower one free at the elbow but drawn on the elbow's lower
/// stop at 0 (gravity pushes it onto the stop while θ < 90°). Inverse dynamics, 2 s.
fn arm_on_a_stop() -> String {
    double_pendulum("inverse_dynamics")
        .replace(
            "axis_i = \"z\"\nbody_j = \"lower\"",
            "axis_i = \"z\"\nx_axis_i = \"x\"\nbody_j = \"lower\"",
        )
        .replace(
            "axis_j = \"z\"\n\n[[limit]]",
            "axis_j = \"z\"\nx_axis_j = \"x\"\n\n[[limit]]",
        )
        .replace(
            "name = \"rest\"\njoint = \"shoulder\"\nlower = -0.5235987755982988   # −30°\nupper = 0.5",
            "name = \"bend\"\njoint = \"elbow\"\nlower = 0.0\nupper = 2.0\n\n[[driver]]\nname = \
             \"motor\"\ntype = \"rotation\"\njoint = \"shoulder\"\nfunction = { kind = \
             \"polynomial\", coefficients = [0.0, 1.0] }",
        )
        .replace(
            "kind = \"inverse_dynamics\"",
            "kind = \"inverse_dynamics\"\nt_end = 2.0\nsteps = 200",
        )
}

/// Checks the first `rows` rows of `driver_efforts.csv` under `dir/out` of the arm on its stop
/// against the rigid rotation's closed forms (the stop m g (L/2) cos θ, the motor
/// m g (L/2 + 3L/2) cos θ, within 1e-9 N m); returns the rows checked.
fn arm_efforts_as_closed_form(dir: &std::path::Path, rows: usize) -> usize {
    let efforts = std::fs::read_to_string(dir.join("out/driver_efforts.csv")).unwrap();
    let mut lines = efforts.lines();
    assert_eq!(
        lines.next().unwrap(),
        "t [s],motor.torque [N m],bend.lower.torque [N m]"
    );
    let mut checked = 0;
    for line in lines.take(rows) {
        let v = numbers(line);
        let c = v[0].cos();
        assert!(
            (v[2] - G * 0.5 * c).abs() < 1e-9,
            "stop at t {}: {}",
            v[0],
            v[2]
        );
        assert!(
            (v[1] - G * 2.0 * c).abs() < 1e-9,
            "motor at t {}: {}",
            v[0],
            v[1]
        );
        checked += 1;
    }
    checked
}

#[test]
fn inverse_dynamics_of_a_motion_resting_on_a_stop_reports_its_reaction_and_when_it_leaves() {
    let text = arm_on_a_stop();
    assert!(text.contains("x_axis_j = \"x\"\n\n[[limit]]"), "{text}");
    let o = run_text("run", &text);
    assert_eq!(o.code, 0, "{}\n{text}", o.stderr);
    // The rods turn rigidly at ω = 1 about the shoulder (α = 0): the elbow's moment on the
    // lower rod is its weight's, m g (L/2) cos θ (its centripetal acceleration points through
    // the elbow), and the motor carries both rods' weights, m g (L/2 + 3L/2) cos θ.
    assert_eq!(arm_efforts_as_closed_form(&o.dir, usize::MAX), 201);
    // At θ = 90° the weight's moment changes sign: the stop would pull, the rod leaves it.
    let json = std::fs::read_to_string(o.dir.join("out/run.json")).unwrap();
    assert!(
        o.stdout
            .contains("the prescribed motion leaves stop bend.lower at about t = 1.570796 s"),
        "{}",
        o.stdout
    );
    assert!(json.contains("leaves stop bend.lower"), "{json}");
    // `cardan check` agrees: the stop counts as driven.
    let o = run_text("check", &text);
    assert_eq!(o.code, 0, "{}", o.stderr);
    assert!(
        o.stdout.contains(
            "inverse dynamics: 1 driver and 1 stop the start rests on (bend.lower) for 2 DOF: ok"
        ),
        "{}",
        o.stdout
    );
    // A stop on the driven shoulder, which the motion starts on, drives nothing new: the elbow
    // is still free, and the run says so (it held that stop before, as a conflicting driver).
    let own = text.replace(
        "joint = \"elbow\"\nlower = 0.0",
        "joint = \"shoulder\"\nlower = 0.0",
    );
    assert_ne!(own, text);
    let o = run_text("run", &own);
    assert_eq!(o.code, 1, "{}", o.stdout);
    assert!(o.stderr.contains("fully driven"), "{}", o.stderr);
    // Drawn off the stop, the lower rod is free: not fully driven, said as before.
    let off = text.replace("lower = 0.0\nupper = 2.0", "lower = -0.5\nupper = 2.0");
    let o = run_text("run", &off);
    assert_eq!(o.code, 1, "{}", o.stdout);
    assert!(o.stderr.contains("fully driven"), "{}", o.stderr);
    assert!(
        o.stderr
            .contains("whose start lies on a [[limit]]'s bound counts as driven"),
        "{}",
        o.stderr
    );
}

#[test]
fn a_quasi_static_path_rests_on_its_stops_and_changes_stop_where_the_load_turns() {
    // The arm turned at θ = t with its forearm on the elbow's lower stop, as equilibria: the
    // stop carries the forearm's weight moment m g (L/2) cos θ, the motor both rods',
    // m g (L/2 + 3L/2) cos θ. Past θ = 90° the lower stop would pull: the forearm falls over
    // onto the upper stop (φ = 2 rad, the forearm at a = θ + 2), which carries
    // m g (L/2) cos a (negative: an upper stop pushes back), the motor
    // m g (3L/2 cos θ + L/2 cos a). The path's second segment starts at t = 1.6 s.
    let text = arm_on_a_stop().replace(
        "kind = \"inverse_dynamics\"\nt_end = 2.0\nsteps = 200",
        "kind = \"quasi_static\"\nt_end = 2.0\nsteps = 20",
    );
    let o = run_text("run", &text);
    assert_eq!(o.code, 0, "{}\n{text}", o.stderr);
    assert!(!o.stdout.contains("warning"), "{}", o.stdout);
    let efforts = std::fs::read_to_string(o.dir.join("out/driver_efforts.csv")).unwrap();
    let mut lines = efforts.lines();
    assert_eq!(
        lines.next().unwrap(),
        "t [s],motor.torque [N m],bend.lower.torque [N m],bend.upper.torque [N m]"
    );
    let mut rows = 0;
    for line in lines {
        let v = numbers(line);
        let (t, c) = (v[0], v[0].cos());
        let (lower, upper, motor) = if t < std::f64::consts::FRAC_PI_2 {
            (G * 0.5 * c, 0.0, G * 2.0 * c)
        } else {
            let ca = (t + 2.0).cos();
            (0.0, G * 0.5 * ca, G * (1.5 * c + 0.5 * ca))
        };
        assert!((v[2] - lower).abs() < 1e-9, "lower stop at t {t}: {}", v[2]);
        assert!((v[3] - upper).abs() < 1e-9, "upper stop at t {t}: {}", v[3]);
        assert!((v[1] - motor).abs() < 1e-9, "motor at t {t}: {}", v[1]);
        rows += 1;
    }
    assert_eq!(rows, 21);
    // Up to θ = 1 rad one stop carries it all the way.
    let o = run_text(
        "run",
        &text.replace("t_end = 2.0\nsteps = 20", "t_end = 1.0\nsteps = 10"),
    );
    assert_eq!(o.code, 0, "{}", o.stderr);
    assert!(!o.stdout.contains("warning"), "{}", o.stdout);
    assert_eq!(arm_efforts_as_closed_form(&o.dir, usize::MAX), 11);
}

#[test]
fn a_load_no_equilibrium_can_carry_without_its_stop_rests_on_the_stop() {
    // A 1 kg, 1 m rod pinned at its end under gravity −y, turned by a constant 10 N m about z:
    // more than its weight's largest moment m g L/2 = 4.905 N m, so there is no equilibrium
    // with the stop open; it rests on its upper stop at 0.5 rad, which carries
    // τ − m g (L/2) cos 0.5 (negative: an upper stop pushes back).
    let text = r#"[model]
name = "lever"
gravity = [0.0, -9.81, 0.0]

[ground]
points = { O = [0.0, 0.0, 0.0] }
vectors = { z = [0.0, 0.0, 1.0], x = [1.0, 0.0, 0.0] }

[[body]]
name = "rod"
mass = 1.0
inertia = { diag = [1e-4, 0.083333333333333333, 0.083333333333333333] }
position = [0.5, 0.0, 0.0]
points = { O = [-0.5, 0.0, 0.0] }
vectors = { z = [0.0, 0.0, 1.0], x = [1.0, 0.0, 0.0] }

[[joint]]
name = "pin"
type = "revolute"
body_i = "ground"
point_i = "O"
axis_i = "z"
x_axis_i = "x"
body_j = "rod"
point_j = "O"
axis_j = "z"
x_axis_j = "x"

[[force]]
name = "push"
type = "torque"
body = "rod"
components = [{ kind = "constant", value = 0.0 }, { kind = "constant", value = 0.0 }, { kind = "constant", value = 10.0 }]

[[limit]]
name = "stop"
joint = "pin"
lower = -1.0
upper = 0.5

[analysis]
kind = "static"
"#;
    let o = run_text("run", text);
    assert_eq!(o.code, 0, "{}", o.stderr);
    let efforts = std::fs::read_to_string(o.dir.join("out/driver_efforts.csv")).unwrap();
    let mut lines = efforts.lines();
    assert_eq!(lines.next().unwrap(), "t [s],stop.upper.torque [N m]");
    let torque = numbers(lines.next().unwrap())[1];
    let expected = -(10.0 - G * 0.5 * 0.5f64.cos());
    assert!((torque - expected).abs() < 1e-9, "{torque} vs {expected}");
}
