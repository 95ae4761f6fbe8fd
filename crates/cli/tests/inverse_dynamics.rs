//! Driver efforts through `cardan run`: `kind = "inverse_dynamics"` (the bundled example and a
//! driven pendulum against its closed form) and the `driver_efforts.csv` of a dynamic run with a
//! driver. The checks are independent of the program's own numbers: closed forms, the power
//! balance (driver power = d(kinetic + gravitational energy)/dt, computed from the written body
//! velocities and accelerations) and the dynamics crate's API run separately.

use cardan_cli::commands::run::run_model;
use cardan_dynamics::{Dynamics, Force};
use cardan_mechanism::KinematicOptions;
use cardan_model::prepare::prepare;
use cardan_model::table::parse_csv;
use nalgebra::{Matrix3, Vector3, Vector4};
use std::path::{Path, PathBuf};

mod common;

fn example(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../../examples")
        .join(format!("{name}.toml"))
}

/// A CSV written by the run: columns by header.
struct Csv {
    header: Vec<String>,
    rows: Vec<Vec<f64>>,
}

impl Csv {
    fn read(dir: &Path, name: &str) -> Self {
        let text =
            std::fs::read_to_string(dir.join(name)).unwrap_or_else(|e| panic!("{name}: {e}"));
        let (header, rows) = parse_csv(&text).unwrap_or_else(|| panic!("{name}: not a CSV"));
        assert_eq!(header[0], "t [s]", "{name}");
        assert!(
            header.iter().all(|h| h.ends_with(']')),
            "{name}: {header:?}"
        );
        Self { header, rows }
    }

    fn col(&self, name: &str) -> usize {
        self.header
            .iter()
            .position(|h| h == name)
            .unwrap_or_else(|| panic!("no column {name:?} in {:?}", self.header))
    }

    fn get(&self, k: usize, name: &str) -> f64 {
        self.rows[k][self.col(name)]
    }

    fn vec3(&self, k: usize, prefix: &str, unit: &str) -> Vector3<f64> {
        Vector3::new(
            self.get(k, &format!("{prefix}.x [{unit}]")),
            self.get(k, &format!("{prefix}.y [{unit}]")),
            self.get(k, &format!("{prefix}.z [{unit}]")),
        )
    }
}

/// Asserts that the "motor.torque [N m]" column of `efforts` holds `effort` at `times` (to 1e-9
/// of the largest |effort|, every row) and returns that largest |effort|.
fn same_torques(efforts: &Csv, times: &[f64], effort: &[f64]) -> f64 {
    let scale = effort.iter().fold(0.0f64, |a, e| a.max(e.abs()));
    assert_eq!(efforts.rows.len(), times.len());
    for (k, &t) in times.iter().enumerate() {
        assert_eq!(efforts.rows[k][0], t);
        let tau = efforts.get(k, "motor.torque [N m]");
        assert!(
            (tau - effort[k]).abs() <= 1e-9 * scale,
            "t[{k}]: {tau} vs {}",
            effort[k]
        );
    }
    scale
}

/// d/dt (kinetic + gravitational energy) at output `k`, from bodies.csv, body_velocities.csv
/// and body_accelerations.csv: Σ m ṙ·(r̈ − g) + ω'·J'ω̇' with ω' = Aᵀω, ω̇' = Aᵀω̇ (global ω̇ =
/// A ω̇' since ω × ω = 0).
fn energy_rate(dir: &Path, bodies: &[(&str, f64, Matrix3<f64>)], g: Vector3<f64>) -> Vec<f64> {
    let (pos, vel, acc) = (
        Csv::read(dir, "bodies.csv"),
        Csv::read(dir, "body_velocities.csv"),
        Csv::read(dir, "body_accelerations.csv"),
    );
    (0..pos.rows.len())
        .map(|k| {
            bodies
                .iter()
                .map(|(b, m, j)| {
                    let e = |c: &str| pos.get(k, &format!("{b}.p.{c} [-]"));
                    let a = cardan_eulerparam::a(&Vector4::new(e("e0"), e("e1"), e("e2"), e("e3")));
                    let v = vel.vec3(k, &format!("{b}.r_dot"), "m/s");
                    let w = a.transpose() * vel.vec3(k, &format!("{b}.omega"), "rad/s");
                    let r_dd = acc.vec3(k, &format!("{b}.r_ddot"), "m/s²");
                    let w_d = a.transpose() * acc.vec3(k, &format!("{b}.omega_dot"), "rad/s²");
                    m * v.dot(&(r_dd - g)) + w.dot(&(j * w_d))
                })
                .sum()
        })
        .collect()
}

/// The bundled example runs through `cardan run` (library entry), writes the kinematic tables,
/// driver efforts and reactions with their plots, and its motor torque is the one of the
/// dynamics API and satisfies the power balance τ θ̇ = d(T + V)/dt with θ̇ = 2π.
#[test]
fn slider_crank_inverse_example() {
    let dir = common::scratch("inverse-example");
    let o = run_model(&example("slider_crank_inverse"), Some(&dir), false).expect("runs");
    assert!(o.error.is_none(), "{:?}", o.error);
    for f in [
        "points",
        "point_velocities",
        "point_accelerations",
        "joints",
        "bodies",
        "body_velocities",
        "body_accelerations",
        "driver_efforts",
        "reactions",
        "reactions_local",
    ] {
        let csv = Csv::read(&dir, &format!("{f}.csv"));
        assert_eq!(csv.rows.len(), 201, "{f}");
        assert!(dir.join(format!("{f}.svg")).exists(), "{f}.svg");
    }
    assert_eq!(Csv::read(&dir, "residual.csv").rows.len(), 201);
    assert!(!dir.join("constraint_drift.csv").exists());
    // energy.csv: the motor's power and work along the prescribed motion (trapezoidal rule on
    // the 200-step grid) explain the energy change; the balance is the quadrature's error.
    let energy = Csv::read(&dir, "energy.csv");
    assert_eq!(energy.rows.len(), 201);
    let col = |name: &str| energy.header.iter().position(|h| h == name).unwrap();
    let (drift, work, balance) = (col("drift [J]"), col("motor.W [J]"), col("balance [J]"));
    assert!(col("motor.P [W]") > 0 && col("W_nc [J]") > 0);
    let peak = energy
        .rows
        .iter()
        .fold(0.0f64, |a, r| a.max(r[drift].abs()));
    let worst = energy
        .rows
        .iter()
        .fold(0.0f64, |a, r| a.max(r[balance].abs()));
    let last = energy.rows.last().unwrap();
    eprintln!(
        "slider-crank inverse: motor work {:.6e} J, ΔE {:.6e} J, max |ΔE| {peak:.3e} J, balance \
         {worst:.3e} J",
        last[work], last[drift]
    );
    assert!(
        worst < 1e-3 * peak.max(1e-9) || worst < 1e-9,
        "balance {worst:e}, drift {peak:e}"
    );
    let efforts = Csv::read(&dir, "driver_efforts.csv");
    assert_eq!(efforts.header, ["t [s]", "motor.torque [N m]"]);
    let reactions = Csv::read(&dir, "reactions.csv");
    // The torque's reference point is named: the joint's point on that body (the prismatic
    // slide's points differ: O on ground, C on the slider).
    for (j, point) in [
        ("crank_pin.ground", "A"),
        ("crank_pin.crank", "A"),
        ("ball.conrod", "B"),
        ("cross.slider", "C"),
        ("slide.ground", "O"),
        ("slide.slider", "C"),
    ] {
        reactions.col(&format!("{j}.F.x [N]"));
        reactions.col(&format!("{j}.T@{point}.z [N m]"));
    }
    Csv::read(&dir, "reactions_local.csv").col("slide.slider.T@C.y [N m]");

    // The dynamics API on the same model, gravity added here, on the file's grid.
    let p = prepare(&example("slider_crank_inverse")).unwrap();
    let mut d = Dynamics::new(&p.model).unwrap();
    d.add_force(Force::gravity(Vector3::new(0.0, 0.0, -9.81)))
        .unwrap();
    let api = d
        .inverse_dynamics(&KinematicOptions::new(0.0, 1.0, 200))
        .unwrap();
    let motor = api.driver("motor").unwrap();
    let pin = api.joint_reactions("crank_pin").unwrap();
    let scale = same_torques(&efforts, api.times(), &motor.effort);
    assert!(scale > 0.1, "a real torque: {scale}");
    for k in 0..201 {
        let f = reactions.vec3(k, "crank_pin.crank.F", "N");
        assert!((f - pin.on_j[k].force).amax() <= 1e-9 * pin.on_j[k].force.amax().max(1.0));
    }

    // Power balance: the joints are ideal and fixed, so only the motor does work.
    let rate = energy_rate(
        &dir,
        &[
            (
                "crank",
                0.12,
                Matrix3::from_diagonal(&Vector3::new(1e-4, 1e-4, 1e-5)),
            ),
            (
                "conrod",
                0.5,
                Matrix3::from_diagonal(&Vector3::new(4e-4, 4e-3, 4e-3)),
            ),
            (
                "slider",
                2.0,
                Matrix3::from_diagonal(&Vector3::new(1e-4, 1e-4, 1e-4)),
            ),
        ],
        Vector3::new(0.0, 0.0, -9.81),
    );
    let omega = 2.0 * std::f64::consts::PI;
    let worst = (0..201)
        .map(|k| (efforts.get(k, "motor.torque [N m]") * omega - rate[k]).abs())
        .fold(0.0f64, f64::max);
    eprintln!("slider_crank_inverse: power balance {worst:.2e} W (peak torque {scale:.4} N m)");
    assert!(
        worst < 1e-9 * scale * omega,
        "power balance off by {worst:e} W"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// A rod (m = 2 kg, centre of mass l = 0.5 m from the pivot, J_c = 0.1 kg m² about z) driven
/// through θ(t) = 0.3 + 0.8 sin 2t about global z under gravity g = 9.81 m/s² along −y:
///
/// ```text
/// τ = (J_c + m l²) θ̈ + m g l cos θ,            θ̈ = −3.2 sin 2t, θ̇ = 1.6 cos 2t
/// F_pin→rod = m (a_c − g),   a_c = l θ̈ (−sin θ, cos θ) − l θ̇² (cos θ, sin θ)
/// ```
///
/// and the pin (a revolute about z) carries no torque about z: that is the driver's.
const PENDULUM: &str = r#"[model]
name = "driven_pendulum"
gravity = [0.0, -9.81, 0.0]

[ground]
points = { O = [0.0, 0.0, 0.0] }
vectors = { z = [0.0, 0.0, 1.0], x = [1.0, 0.0, 0.0] }

[[body]]
name = "rod"
mass = 2.0
inertia = { diag = [0.002, 0.1, 0.1] }
position = [0.4777, 0.1478, 0.0]
orientation = { axis = [0.0, 0.0, 1.0], angle = 0.3 }
points = { O = [-0.5, 0.0, 0.0], tip = [0.5, 0.0, 0.0] }
vectors = { z = [0.0, 0.0, 1.0], x = [1.0, 0.0, 0.0] }

[[joint]]
name = "pivot"
type = "revolute"
body_i = "ground"
point_i = "O"
axis_i = "z"
x_axis_i = "x"
body_j = "rod"
point_j = "O"
axis_j = "z"
x_axis_j = "x"

[[driver]]
name = "motor"
type = "rotation"
joint = "pivot"
function = { kind = "harmonic", amplitude = 0.8, frequency = 2.0, offset = 0.3 }

[analysis]
kind = "inverse_dynamics"
t_end = 3.0
steps = 60
"#;

#[test]
fn driven_pendulum_matches_closed_form() {
    let common::Outcome {
        code,
        stdout,
        stderr,
        dir,
    } = common::run_text("run", PENDULUM);
    assert_eq!(code, 0, "{stderr}");
    assert!(
        stdout.contains("driven_pendulum: 61 steps")
            && stdout.contains("peak |driver effort| motor"),
        "{stdout}"
    );
    let out = dir.join("out");
    let efforts = Csv::read(&out, "driver_efforts.csv");
    let reactions = Csv::read(&out, "reactions.csv");
    let (m, l, jc, g) = (2.0, 0.5, 0.1, 9.81);
    assert_eq!(efforts.rows.len(), 61);
    let (mut worst_tau, mut worst_f) = (0.0f64, 0.0f64);
    for k in 0..61 {
        let t = efforts.rows[k][0];
        let th = 0.3 + 0.8 * (2.0 * t).sin();
        let thd = 1.6 * (2.0 * t).cos();
        let thdd = -3.2 * (2.0 * t).sin();
        let tau = (jc + m * l * l) * thdd + m * g * l * th.cos();
        worst_tau = worst_tau.max((efforts.get(k, "motor.torque [N m]") - tau).abs());
        let ac = l * thdd * Vector3::new(-th.sin(), th.cos(), 0.0)
            - l * thd * thd * Vector3::new(th.cos(), th.sin(), 0.0);
        let f = m * (ac - Vector3::new(0.0, -g, 0.0));
        worst_f = worst_f.max((reactions.vec3(k, "pivot.rod.F", "N") - f).amax());
        worst_f = worst_f.max((reactions.vec3(k, "pivot.ground.F", "N") + f).amax());
        assert!(
            reactions.get(k, "pivot.rod.T@O.z [N m]").abs() < 1e-9,
            "t = {t}"
        );
    }
    eprintln!("driven pendulum: torque error {worst_tau:.2e} N m, pin force error {worst_f:.2e} N");
    assert!(worst_tau < 1e-9, "torque off by {worst_tau:e} N m");
    assert!(worst_f < 1e-9, "pin force off by {worst_f:e} N");
    let _ = std::fs::remove_dir_all(&dir);
}

/// A double pendulum whose upper link is driven at a constant 1.5 rad/s while the lower one
/// swings freely under gravity (`kind = "dynamic"`): driver_efforts.csv holds the dynamics API's
/// DriverEfforts, and the motor's power equals d(T + V)/dt from the written body states.
#[test]
fn dynamic_run_writes_driver_efforts() {
    let text = PENDULUM
        .replace("name = \"driven_pendulum\"", "name = \"driven_double_pendulum\"")
        .replace(
            "tip = [0.5, 0.0, 0.0] }\nvectors = { z = [0.0, 0.0, 1.0], x = [1.0, 0.0, 0.0] }",
            "tip = [0.5, 0.0, 0.0] }\nvectors = { z = [0.0, 0.0, 1.0], x = [1.0, 0.0, 0.0] }\n\n\
             [[body]]\nname = \"link\"\nmass = 1.0\ninertia = { diag = [0.001, 0.02, 0.02] }\n\
             position = [1.1942, 0.3694, 0.2]\norientation = { axis = [0.0, 0.0, 1.0], angle = 0.3 }\n\
             points = { P = [-0.25, 0.0, -0.2], end = [0.25, 0.0, 0.0] }\nvectors = { z = [0.0, 0.0, 1.0] }",
        )
        .replace(
            "[[driver]]",
            "[[joint]]\nname = \"elbow\"\ntype = \"revolute\"\nbody_i = \"rod\"\npoint_i = \"tip\"\n\
             axis_i = \"z\"\nbody_j = \"link\"\npoint_j = \"P\"\naxis_j = \"z\"\n\n[[driver]]",
        )
        .replace(
            "{ kind = \"harmonic\", amplitude = 0.8, frequency = 2.0, offset = 0.3 }",
            "{ kind = \"polynomial\", coefficients = [0.3, 1.5] }",
        )
        .replace(
            "kind = \"inverse_dynamics\"\nt_end = 3.0\nsteps = 60",
            "kind = \"dynamic\"\nrtol = 1e-9\natol = 1e-11\nt_end = 2.0\noutput_dt = 0.05",
        );
    let common::Outcome {
        code,
        stdout,
        stderr,
        dir,
    } = common::run_text("run", &text);
    assert_eq!(code, 0, "{stderr}");
    assert!(stdout.contains("peak |driver effort| motor"), "{stdout}");
    let out = dir.join("out");
    let efforts = Csv::read(&out, "driver_efforts.csv");
    assert_eq!(efforts.header, ["t [s]", "motor.torque [N m]"]);
    assert_eq!(efforts.rows.len(), 41);
    assert!(out.join("driver_efforts.svg").exists());

    // The same file through the dynamics API.
    std::fs::write(dir.join("same.toml"), &text).unwrap();
    let p = prepare(&dir.join("same.toml")).unwrap();
    let api = cardan_model::analysis::dynamic::simulate(&p, None).unwrap();
    let motor = api.driver("motor").unwrap();
    let scale = same_torques(&efforts, api.times(), &motor.effort);
    assert!(scale > 1.0, "the motor works: {scale}");

    // Power balance on the written states: τ θ̇ = d(T + V)/dt (the elbow is free and ideal).
    let rate = energy_rate(
        &out,
        &[
            (
                "rod",
                2.0,
                Matrix3::from_diagonal(&Vector3::new(0.002, 0.1, 0.1)),
            ),
            (
                "link",
                1.0,
                Matrix3::from_diagonal(&Vector3::new(0.001, 0.02, 0.02)),
            ),
        ],
        Vector3::new(0.0, -9.81, 0.0),
    );
    let worst = (0..41)
        .map(|k| (efforts.get(k, "motor.torque [N m]") * 1.5 - rate[k]).abs())
        .fold(0.0f64, f64::max);
    eprintln!("driven double pendulum: power balance {worst:.2e} W (peak torque {scale:.4} N m)");
    assert!(worst < 1e-9 * scale, "power balance off by {worst:e} W");
    let _ = std::fs::remove_dir_all(&dir);
}

/// The general motion example: the probe's centre follows the prescribed helix, and the six
/// efforts are the force m (r̈ − g) along ground x, y, z and the torque A (J' ω̇' + ω' × J' ω')
/// about its centre (ground components): the driver alone moves it.
#[test]
fn general_motion_efforts_are_the_newton_euler_force_and_torque() {
    let dir = common::scratch("general-motion");
    let o = run_model(&example("general_motion_path"), Some(&dir), false).expect("runs");
    assert!(o.error.is_none(), "{:?}", o.error);
    let bodies = Csv::read(&dir, "bodies.csv");
    let vel = Csv::read(&dir, "body_velocities.csv");
    let acc = Csv::read(&dir, "body_accelerations.csv");
    let eff = Csv::read(&dir, "driver_efforts.csv");
    let (m, j) = (1.5, Matrix3::from_diagonal(&Vector3::new(0.02, 0.03, 0.04)));
    let g = Vector3::new(0.0, 0.0, -9.81);
    let (mut e_path, mut e_force, mut e_torque) = (0.0f64, 0.0f64, 0.0f64);
    for k in 0..eff.rows.len() {
        let t = eff.rows[k][0];
        let w = std::f64::consts::PI;
        let r = Vector3::new(0.3 * (w * t).cos(), 0.3 * (w * t).sin(), 0.1 * t);
        e_path = e_path.max((bodies.vec3(k, "probe.r", "m") - r).norm());
        let force = Vector3::new(
            eff.get(k, "path.x.force [N]"),
            eff.get(k, "path.y.force [N]"),
            eff.get(k, "path.z.force [N]"),
        );
        let a = acc.vec3(k, "probe.r_ddot", "m/s²");
        e_force = e_force.max((force - m * (a - g)).norm());
        let p = Vector4::new(
            bodies.get(k, "probe.p.e0 [-]"),
            bodies.get(k, "probe.p.e1 [-]"),
            bodies.get(k, "probe.p.e2 [-]"),
            bodies.get(k, "probe.p.e3 [-]"),
        );
        let rot = cardan_eulerparam::a(&p);
        let (wl, dwl) = (
            rot.transpose() * vel.vec3(k, "probe.omega", "rad/s"),
            rot.transpose() * acc.vec3(k, "probe.omega_dot", "rad/s²"),
        );
        let torque = Vector3::new(
            eff.get(k, "path.angle_1.torque [N m]"),
            eff.get(k, "path.angle_2.torque [N m]"),
            eff.get(k, "path.angle_3.torque [N m]"),
        );
        e_torque = e_torque.max((torque - rot * (j * dwl + wl.cross(&(j * wl)))).norm());
    }
    eprintln!(
        "general motion: path {e_path:.1e} m, force {e_force:.1e} N, torque {e_torque:.1e} N m"
    );
    assert!(e_path < 1e-12, "{e_path}");
    assert!(e_force < 1e-9 && e_torque < 1e-9, "{e_force} {e_torque}");
}

/// `[analysis.outputs] energy = false` is accepted by an inverse dynamics run (it was refused
/// before energy.csv had the drivers' work) and leaves energy.csv out.
#[test]
fn inverse_dynamics_energy_output_can_be_turned_off() {
    let dir = common::scratch("inverse-no-energy");
    let text = std::fs::read_to_string(example("slider_crank_inverse")).unwrap();
    let text = text.replacen(
        "[analysis.outputs]",
        "[analysis.outputs]\nenergy = false",
        1,
    );
    assert!(text.contains("energy = false"));
    std::fs::write(dir.join("model.toml"), text).unwrap();
    let o = run_model(&dir.join("model.toml"), Some(&dir.join("out")), false).expect("runs");
    assert!(o.error.is_none(), "{:?}", o.error);
    assert!(dir.join("out/driver_efforts.csv").exists());
    assert!(!dir.join("out/energy.csv").exists());
}

/// An inverse dynamics run that writes bodies and efforts alone computes no point or joint
/// history (the dynamics' recorder is told what the outputs need), and its efforts are those
/// of the run that writes everything.
#[test]
fn a_run_asking_for_no_points_or_joints_computes_none() {
    let text = std::fs::read_to_string(example("slider_crank")).unwrap();
    let inverse = text.replace("kind = \"kinematic\"", "kind = \"inverse_dynamics\"");
    let lean = inverse
        .replace("points = [\"crank.B\", \"slider.C\"]\n", "points = []\n")
        .replace("joints = [\"crank_pin\", \"slide\"]\n", "joints = []\n");
    let run = |text: &str| {
        let dir = common::scratch("inverse-lean");
        std::fs::write(dir.join("model.toml"), text).unwrap();
        let p = prepare(&dir.join("model.toml")).unwrap();
        let a = p.loaded.analysis.clone().unwrap();
        let flags = cardan_model::analysis::RunFlags::default();
        let (_, analysed) = cardan_model::analysis::analyse(&p, &a, &flags).unwrap();
        analysed.dynamic.unwrap()
    };
    let (full, lean) = (run(&inverse), run(&lean));
    assert!(!full.kinematics.points.is_empty() && !full.kinematics.joints.is_empty());
    assert!(lean.kinematics.points.is_empty() && lean.kinematics.joints.is_empty());
    assert_eq!(full.drivers.len(), lean.drivers.len());
    for (a, b) in full.drivers.iter().zip(&lean.drivers) {
        assert_eq!(a.effort, b.effort);
    }
}

/// An empty list in `[analysis.outputs]` is a choice, not an absence: an inverse dynamics run
/// whose outputs list no point, joint or body writes its efforts and no pose table (it wrote
/// every table when all three lists were empty, as if `[analysis.outputs]` were absent).
#[test]
fn empty_output_lists_write_the_efforts_alone() {
    let text = std::fs::read_to_string(example("slider_crank")).unwrap();
    let lean = text
        .replace("kind = \"kinematic\"", "kind = \"inverse_dynamics\"")
        .replace("points = [\"crank.B\", \"slider.C\"]\n", "points = []\n")
        .replace("joints = [\"crank_pin\", \"slide\"]\n", "joints = []\n")
        .replace("bodies = [\"conrod\"]\n", "bodies = []\n");
    assert!(lean.contains("bodies = []"));
    let o = common::run_text("run", &lean);
    assert_eq!(o.code, 0, "{}", o.stderr);
    let out = o.dir.join("out");
    assert!(out.join("driver_efforts.csv").exists());
    for table in [
        "bodies.csv",
        "points.csv",
        "joints.csv",
        "body_velocities.csv",
    ] {
        assert!(!out.join(table).exists(), "{table} written");
    }
}
