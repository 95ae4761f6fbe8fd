//! Issue 27, item 5: a kinematic run on a coarse grid (a few steps per crank turn) must follow
//! the assembly branch of its drawn pose, as a fine run does: the grid detects a step whose
//! solution leaves the branch and solves it in substeps, and `cardan run` reports how many steps
//! it subdivided (summary line and run.json, not a warning).

mod common;
use cardan_mechanism::{KinematicOptions, Outputs};
use cardan_model::prepare::prepare;
use common::rssr_q;
use nalgebra::Vector3;
use std::f64::consts::PI;
use std::path::PathBuf;

fn example(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../../examples")
        .join(format!("{name}.toml"))
}

/// Largest |Q − Q(θ)| of an RSSR run of `steps` steps from 0 to `t_end` (θ = 2πt), and the
/// number of subdivided steps.
fn rssr_error(steps: usize, t_end: f64) -> (f64, usize) {
    let p = prepare(&example("rssr_fourbar")).unwrap();
    let r = p
        .model
        .run_kinematics(&KinematicOptions::new(0.0, t_end, steps))
        .unwrap_or_else(|e| panic!("{steps} steps: {e}"));
    let q = r.point("rocker", "Q").unwrap();
    let err = r
        .times
        .iter()
        .zip(&q.position)
        .map(|(&t, x)| (x - rssr_q(2.0 * PI * t)).amax())
        .fold(0.0, f64::max);
    (err, r.subdivided_steps)
}

#[test]
fn rssr_on_coarse_grids_stays_on_the_drawn_branch() {
    for (steps, t_end) in [(2, 1.0), (3, 1.0), (4, 1.0), (4, 2.0), (5, 2.0), (6, 3.0)] {
        let (err, sub) = rssr_error(steps, t_end);
        eprintln!(
            "rssr, {steps} steps to t = {t_end}: max |Q − Q(θ)| = {err:.2e} m, {sub} subdivided"
        );
        assert!(
            err < 1e-10,
            "{steps} steps to {t_end}: |Q − Q(θ)| = {err} m"
        );
    }
}

#[test]
fn a_fine_grid_subdivides_nothing() {
    let (err, sub) = rssr_error(200, 1.0);
    assert!(err < 1e-10 && sub == 0, "{err} m, {sub} subdivided");
    let p = prepare(&example("slider_crank")).unwrap();
    let r = p
        .model
        .run_kinematics(&KinematicOptions::new(0.0, 1.0, 200))
        .unwrap();
    assert_eq!(r.subdivided_steps, 0);
    // The first-order predictors (velocities only; extrapolation without velocities) too.
    for outputs in [Outputs::with_velocity(), Outputs::position_only()] {
        let r = p
            .model
            .run_kinematics(&KinematicOptions::new(0.0, 1.0, 50).outputs(outputs))
            .unwrap();
        assert_eq!(r.subdivided_steps, 0, "{outputs:?}");
    }
}

/// Haug's slider-crank with a few steps per turn: the slider x(θ) of the closed form of
/// `examples.rs::slider_crank_matches_closed_form`.
#[test]
fn slider_crank_on_coarse_grids_follows_the_closed_form() {
    let p = prepare(&example("slider_crank")).unwrap();
    for steps in [2, 3, 4, 5] {
        let r = p
            .model
            .run_kinematics(&KinematicOptions::new(0.0, 2.0, steps))
            .unwrap();
        let c = r.point("slider", "C").unwrap();
        for (&t, x) in r.times.iter().zip(&c.position) {
            let th = 2.0 * PI * t;
            let (by, bz) = (0.1 - 0.08 * th.sin(), 0.12 + 0.08 * th.cos());
            let want = (0.09 - by * by - bz * bz).sqrt();
            assert!(
                (x - Vector3::new(want, 0.0, 0.0)).amax() < 1e-10,
                "{steps} steps, t = {t}: C = {x:?}, want x = {want}"
            );
        }
    }
}

/// The bundled RSSR file with another grid (and analysis kind).
fn rssr_text(steps: usize, kind: &str) -> String {
    std::fs::read_to_string(example("rssr_fourbar"))
        .unwrap()
        .replace("steps = 200", &format!("steps = {steps}"))
        .replace("kind = \"kinematic\"", &format!("kind = \"{kind}\""))
}

/// Column `col` of a CSV file, every row.
fn column(csv: &str, col: &str) -> Vec<f64> {
    let mut lines = csv.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let k = header.iter().position(|h| h.starts_with(col)).unwrap();
    lines
        .map(|l| l.split(',').nth(k).unwrap().parse().unwrap())
        .collect()
}

#[test]
fn cardan_run_reports_subdivided_steps_and_strict_accepts_them() {
    let o = common::run_text("run", &rssr_text(2, "kinematic"));
    assert_eq!(o.code, 0, "{}", o.stderr);
    let dir = common::scratch("coarse-strict");
    std::fs::write(dir.join("model.toml"), rssr_text(2, "kinematic")).unwrap();
    let o = common::cardan(&["run", "model.toml", "-o", "out", "--strict"], &dir);
    assert_eq!(o.code, 0, "--strict: {}", o.stderr);
    assert!(
        o.stdout
            .contains("2 steps subdivided to follow the motion continuously"),
        "{}",
        o.stdout
    );
    let json = std::fs::read_to_string(dir.join("out/run.json")).unwrap();
    let v: serde_json::Value = serde_json::from_str(&json).unwrap();
    assert_eq!(v["subdivided_steps"], 2, "{json}");
    assert_eq!(v["warnings"].as_array().unwrap().len(), 0, "{json}");
    let joints = std::fs::read_to_string(dir.join("out/joints.csv")).unwrap();
    let psi = column(&joints, "rocker_pivot.angle");
    // The rocker angle at θ = π on the drawn branch (fine run: −2.5459136692…).
    assert!((psi[1] + 2.545_913_669_214_6).abs() < 1e-9, "{psi:?}");
}

/// Inverse dynamics runs on the same grid: the coarse run's motor torque equals the fine run's
/// at the common times, and the coarse run reports its subdivided steps (the inverse run's
/// summary and run.json said 0 before the efforts pass passed the kinematic pass's count on).
#[test]
fn inverse_dynamics_on_a_coarse_grid_gives_the_fine_torque() {
    let coarse = common::run_text("run", &rssr_text(2, "inverse_dynamics"));
    let fine = common::run_text("run", &rssr_text(200, "inverse_dynamics"));
    assert_eq!(coarse.code, 0, "{}", coarse.stderr);
    assert_eq!(fine.code, 0, "{}", fine.stderr);
    assert!(
        coarse
            .stdout
            .contains("2 steps subdivided to follow the motion continuously"),
        "{}",
        coarse.stdout
    );
    let json = std::fs::read_to_string(coarse.dir.join("out/run.json")).unwrap();
    let v: serde_json::Value = serde_json::from_str(&json).unwrap();
    assert_eq!(v["subdivided_steps"], 2, "{json}");
    let read = |o: &common::Outcome| {
        let csv = std::fs::read_to_string(o.dir.join("out/driver_efforts.csv")).unwrap();
        column(&csv, "motor.torque")
    };
    let (c, f) = (read(&coarse), read(&fine));
    for (k, tc) in c.iter().enumerate() {
        let tf = f[100 * k];
        assert!(
            (tc - tf).abs() <= 1e-8 * tf.abs().max(1e-3),
            "t = {}: coarse {tc} N m, fine {tf} N m",
            k as f64 / 2.0
        );
    }
}

/// The bundled examples whose analysis runs on the kinematic time grid (kinematic and inverse
/// dynamics), with their analysis span and step count.
fn grid_examples() -> Vec<(String, f64, f64, usize)> {
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../examples");
    let mut names: Vec<String> = std::fs::read_dir(&dir)
        .unwrap()
        .filter_map(|e| {
            let path = e.unwrap().path();
            let name = path.file_stem()?.to_str()?.to_string();
            (path.extension()? == "toml").then_some(name)
        })
        .collect();
    names.sort();
    names
        .into_iter()
        .filter_map(|name| {
            let p = prepare(&example(&name)).unwrap();
            let a = p.loaded.analysis.as_ref()?;
            let grid = a.integrator().is_none() && a.statics().is_none() && a.steps > 0;
            grid.then_some((name, a.t_start, a.t_end, a.steps))
        })
        .collect()
}

/// Issue 45: a kinematic run gives the same states at the times it shares with a fine run,
/// whatever its output grid: the body poses and the joint coordinates (angles continued over
/// turns), or an error; never a different answer. Every bundled example on the kinematic grid,
/// with 2, 3, 4, 7 steps and its own count, against a reference whose grid holds all their
/// times (a multiple of 84 steps).
#[test]
fn every_grid_example_gives_the_same_states_on_any_output_grid() {
    let examples = grid_examples();
    assert!(examples.len() >= 10, "{examples:?}");
    for (name, t0, t1, bundled) in examples {
        let p = prepare(&example(&name)).unwrap();
        let l = p.model.characteristic_length();
        let run = |steps: usize| {
            p.model
                .run_kinematics(&KinematicOptions::new(t0, t1, steps))
                .unwrap_or_else(|e| panic!("{name}, {steps} steps: {e}"))
        };
        let fine_steps = 84 * bundled.div_ceil(84).max(2);
        let fine = run(fine_steps);
        for steps in [2, 3, 4, 7, bundled] {
            let r = run(steps);
            // Time k of this run is time k · fine_steps / steps of the reference when that is a
            // whole number (always for 2, 3, 4 and 7).
            for k in 0..=steps {
                if (k * fine_steps) % steps != 0 {
                    continue;
                }
                let kf = k * fine_steps / steps;
                let what = format!("{name}, {steps} steps, t = {}", r.times[k]);
                for (b, bf) in r.bodies.iter().zip(&fine.bodies) {
                    let dr = (b.r[k] - bf.r[kf]).amax() / l;
                    let dp = (b.p[k] - bf.p[kf]).amax();
                    assert!(
                        dr < 1e-8 && dp < 1e-8,
                        "{what}: body {} off by {dr:e} L, {dp:e}",
                        b.name
                    );
                }
                for (j, jf) in r.joints.iter().zip(&fine.joints) {
                    for (q, c) in j.coordinates.iter().enumerate() {
                        let (v, vf) = (j.values[k][q], jf.values[kf][q]);
                        let scale = match c.measure.quantity() {
                            cardan_constraints::joints::CoordinateQuantity::Angle => 1.0,
                            _ => l,
                        };
                        assert!(
                            (v - vf).abs() < 1e-8 * scale,
                            "{what}: joint {} {} = {v}, the fine run's {vf}",
                            j.name,
                            c.name
                        );
                    }
                }
            }
        }
    }
}
