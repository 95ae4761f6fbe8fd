//! A run that starts where the driven angle is far from the drawn one follows θ(t), not θ ± π:
//! the joint angle written to joints.csv and the motor torque of inverse dynamics (whose sign
//! flips on the wrong branch) are checked against closed forms; `eval --t` assembles there too.

mod common;
use common::{cardan, edited, run_text};

/// Column `col` of the first data row of a CSV file.
fn first_value(csv: &str, col: &str) -> f64 {
    let mut lines = csv.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let k = header.iter().position(|h| h.starts_with(col)).unwrap();
    lines
        .next()
        .unwrap()
        .split(',')
        .nth(k)
        .unwrap()
        .parse()
        .unwrap()
}

#[test]
fn a_late_start_follows_the_driven_angle() {
    // θ = t; the crank is drawn at 0 and the run starts at t = 2.5 rad (143°).
    let text = edited(
        "kind = \"kinematic\"",
        "kind = \"kinematic\"\nt_start = 2.5",
    )
    .replace("t_end = 1.0", "t_end = 3.5");
    let o = run_text("run", &text);
    assert_eq!(o.code, 0, "{}", o.stderr);
    let joints = std::fs::read_to_string(o.dir.join("out/joints.csv")).unwrap();
    let angle = first_value(&joints, "pivot.angle");
    assert!((angle - 2.5).abs() < 1e-9, "angle {angle} at t = 2.5");
}

#[test]
fn a_late_start_gives_the_motor_torque_with_its_sign() {
    // θ = t²/2, no gravity: T = J_O θ̈ = (Izz + m (0.5 m)²) · 1 = 0.35 N m at every time.
    let text = edited(
        "kind = \"kinematic\"",
        "kind = \"inverse_dynamics\"\nt_start = 2.5",
    )
    .replace("t_end = 1.0", "t_end = 3.0")
    .replace(
        "coefficients = [0.0, 1.0]",
        "coefficients = [0.0, 0.0, 0.5]",
    );
    let o = run_text("run", &text);
    assert_eq!(o.code, 0, "{}", o.stderr);
    let efforts = std::fs::read_to_string(o.dir.join("out/driver_efforts.csv")).unwrap();
    let torque = first_value(&efforts, "motor.torque");
    assert!((torque - 0.35).abs() < 1e-9, "torque {torque} N m");
}

#[test]
fn eval_at_a_late_time_assembles_on_the_driven_branch() {
    let dir = common::scratch("eval-branch");
    std::fs::write(dir.join("model.toml"), common::BASE).unwrap();
    let o = cardan(&["eval", "model.toml", "--t", "2.5"], &dir);
    assert_eq!(o.code, 0, "{}", o.stderr);
    // The centre of mass at θ = 2.5: 0.5 m (cos 2.5, sin 2.5, 0); eval prints the body poses
    // (on the wrong branch it would be at −0.5 m (cos 2.5, sin 2.5, 0)).
    let want = format!("({:.6}, {:.6}, 0)", 0.5 * 2.5f64.cos(), 0.5 * 2.5f64.sin());
    assert!(o.stdout.contains(&want), "no {want} in:\n{}", o.stdout);
}
