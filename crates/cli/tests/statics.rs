//! `kind = "static"`, `"quasi_static"` and `"modal"` through `cardan run`: the bundled examples
//! against numbers computed here independently (the four-bar's one-coordinate Lagrangian from
//! its closed-form positions; the slider-crank's virtual-work balance from the written poses),
//! and the refusal of keys that do not apply.

use cardan_cli::commands::run::run_model;
use cardan_model::table::parse_csv;
use nalgebra::Vector3;
use std::f64::consts::PI;
use std::path::{Path, PathBuf};

mod common;
use common::{edited, run_text};

const G: f64 = 9.81;

fn example(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../../examples")
        .join(format!("{name}.toml"))
}

/// Runs the example into a scratch directory; returns the directory.
fn run_example(name: &str) -> PathBuf {
    let dir = common::scratch(name).join("out");
    let o = run_model(&example(name), Some(&dir), false).expect("example runs");
    assert!(o.error.is_none(), "{name}: {:?}", o.error);
    dir
}

/// A written CSV: (header, rows).
fn csv(dir: &Path, name: &str) -> (Vec<String>, Vec<Vec<f64>>) {
    let text = std::fs::read_to_string(dir.join(name)).unwrap_or_else(|e| panic!("{name}: {e}"));
    let (h, r) = parse_csv(&text).unwrap();
    assert_eq!(h[0], "t [s]");
    assert!(h.iter().all(|c| c.ends_with(']')), "{name}: {h:?}");
    (h, r)
}

fn col(h: &[String], name: &str) -> usize {
    h.iter()
        .position(|c| c == name)
        .unwrap_or_else(|| panic!("no {name} in {h:?}"))
}

/// The examples' four-bar: crank a, coupler b, rocker c, ground d; uniform rods of FB_MASS;
/// torsion spring k at the crank pivot with rest angle 60°.
const FB: (f64, f64, f64, f64) = (0.4, 1.0, 0.8, 1.0);
const FB_MASS: [f64; 3] = [1.0, 2.0, 1.5];
const K: f64 = 20.0;

/// Centres of mass and link angles at crank angle θ (upper assembly branch).
fn centres(th: f64) -> [(Vector3<f64>, f64); 3] {
    let (a, b, c, d) = FB;
    let p = Vector3::new(a * th.cos(), a * th.sin(), 0.0);
    let bp = Vector3::new(d, 0.0, 0.0);
    let e = bp - p;
    let dist = e.norm();
    let x = (b * b - c * c + dist * dist) / (2.0 * dist);
    let h = (b * b - x * x).sqrt();
    let u = e / dist;
    let q = p + u * x + Vector3::new(-u.y, u.x, 0.0) * h;
    let ang = |v: Vector3<f64>| v.y.atan2(v.x);
    [
        (p / 2.0, th),
        ((p + q) / 2.0, ang(q - p)),
        ((bp + q) / 2.0, ang(q - bp)),
    ]
}

/// V(θ) = ½ k (θ − θ₀)² + g Σ mᵢ yᵢ.
fn potential(th: f64) -> f64 {
    let cs = centres(th);
    0.5 * K * (th - PI / 3.0).powi(2) + G * (0..3).map(|i| FB_MASS[i] * cs[i].0.y).sum::<f64>()
}

/// I(θ) = Σ mᵢ |drᵢ/dθ|² + Jᵢ (dφᵢ/dθ)².
fn inertia(th: f64) -> f64 {
    let h = 1e-6;
    let (p, m) = (centres(th + h), centres(th - h));
    let lens = [FB.0, FB.1, FB.2];
    (0..3)
        .map(|i| {
            let dr = (p[i].0 - m[i].0) / (2.0 * h);
            let dphi = (p[i].1 - m[i].1) / (2.0 * h);
            FB_MASS[i] * (dr.norm_squared() + lens[i].powi(2) / 12.0 * dphi * dphi)
        })
        .sum()
}

/// θ* with V'(θ*) = 0 and V''(θ*), by differences and Newton.
fn equilibrium() -> (f64, f64) {
    let h = 1e-4;
    let d1 = |t: f64| (potential(t + h) - potential(t - h)) / (2.0 * h);
    let d2 = |t: f64| (potential(t + h) - 2.0 * potential(t) + potential(t - h)) / (h * h);
    let mut th = PI / 3.0;
    for _ in 0..50 {
        th -= d1(th) / d2(th);
    }
    (th, d2(th))
}

#[test]
fn static_four_bar_rests_where_its_potential_is_least() {
    let dir = run_example("fourbar_spring_static");
    let (h, rows) = csv(&dir, "joints.csv");
    assert_eq!(rows.len(), 1);
    let got = rows[0][col(&h, "A.angle [rad]")];
    let (th, _) = equilibrium();
    assert!((got - th).abs() < 1e-7, "{got} vs {th}");
    let (h, rows) = csv(&dir, "stability.csv");
    assert_eq!(rows[0][col(&h, "stability [-]")], 1.0);
    // The ground pins carry the weight: the vertical forces on the ground sum to −m g.
    let (h, rows) = csv(&dir, "reactions.csv");
    let fy: f64 = ["A", "B"]
        .iter()
        .map(|j| rows[0][col(&h, &format!("{j}.ground.F.y [N]"))])
        .sum();
    let weight: f64 = FB_MASS.iter().sum::<f64>() * G;
    assert!((fy + weight).abs() < 1e-8 * weight, "{fy} vs −{weight}");
    let _ = std::fs::remove_dir_all(dir.parent().unwrap());
}

#[test]
fn modal_four_bar_frequency_and_damping_ratio() {
    let dir = run_example("fourbar_spring_modal");
    let (h, rows) = csv(&dir, "modes.csv");
    assert_eq!(rows.len(), 1);
    let (th, k_eff) = equilibrium();
    let i = inertia(th);
    let c = 0.5;
    let f = (k_eff / i).sqrt() / (2.0 * PI);
    let zeta = c / (2.0 * (k_eff * i).sqrt());
    let got_f = rows[0][col(&h, "frequency [Hz]")];
    let got_z = rows[0][col(&h, "damping_ratio [-]")];
    println!("modal four-bar: {got_f} Hz vs {f} Hz, ζ {got_z} vs {zeta}");
    assert!((got_f - f).abs() < 1e-6 * f, "{got_f} vs {f}");
    assert!((got_z - zeta).abs() < 1e-6 * zeta, "{got_z} vs {zeta}");
    assert_eq!(rows[0][col(&h, "kind [-]")], 0.0);
    let (h, rows) = csv(&dir, "mode_shapes.csv");
    // The crank turns about z: its δθ.z is the largest component (rotations weighted by L).
    assert!(rows[0][col(&h, "crank.dtheta.z [rad]")].abs() > 0.1);
    let _ = std::fs::remove_dir_all(dir.parent().unwrap());
}

/// Quasi-statically the motor's power balances the loads': T θ̇ = dV_g/dt − F ẋ_slider with
/// V_g = Σ mᵢ g zᵢ, differenced from the written poses (second order in the grid step).
#[test]
fn quasi_static_slider_crank_holding_torque_balances_the_loads() {
    let dir = run_example("slider_crank_quasi_static");
    let (hb, bodies) = csv(&dir, "bodies.csv");
    let (he, efforts) = csv(&dir, "driver_efforts.csv");
    assert_eq!(bodies.len(), 73);
    let masses = [("crank", 0.12), ("conrod", 0.5), ("slider", 2.0)];
    let vg = |k: usize| {
        masses
            .iter()
            .map(|(b, m)| m * G * bodies[k][col(&hb, &format!("{b}.r.z [m]"))])
            .sum::<f64>()
    };
    let xs = |k: usize| bodies[k][col(&hb, "slider.r.x [m]")];
    let dt = bodies[1][0] - bodies[0][0];
    let fx = -20.0;
    let mut worst = 0.0f64;
    let mut peak = 0.0f64;
    for k in 1..bodies.len() - 1 {
        let dv = (vg(k + 1) - vg(k - 1)) / (2.0 * dt);
        let dx = (xs(k + 1) - xs(k - 1)) / (2.0 * dt);
        let t = efforts[k][col(&he, "motor.torque [N m]")];
        let expected = (dv - fx * dx) / (2.0 * PI);
        worst = worst.max((t - expected).abs());
        peak = peak.max(t.abs());
    }
    println!("quasi-static slider-crank: largest |T − balance| {worst:.3e} N m (peak {peak})");
    assert!(worst < 5e-3 * peak, "{worst} of {peak}");
    let _ = std::fs::remove_dir_all(dir.parent().unwrap());
}

#[test]
fn keys_that_do_not_apply_are_refused() {
    let kind = "kind = \"kinematic\"";
    let cases = [
        (
            edited(kind, "kind = \"kinematic\"\ntime = 0.5"),
            "kind = \"kinematic\" does not take \"time\" (it applies to kind = \"static\", kind = \"modal\"",
        ),
        (edited(kind, "kind = \"static\""), "kind = \"static\" does not take \"t_end\""),
        (
            edited(
                "kind = \"kinematic\"\nt_end = 1.0\nsteps = 10",
                "kind = \"modal\"\nload_steps = 0",
            ),
            "load_steps must be between",
        ),
        (
            edited(
                "kind = \"kinematic\"\nt_end = 1.0\nsteps = 10",
                "kind = \"quasi_static\"\ntime = 1.0",
            ),
            "kind = \"quasi_static\" does not take \"time\"",
        ),
        (
            edited(kind, "kind = \"kinematic\"\ninputs = [\"motor\"]"),
            "kind = \"kinematic\" does not take \"inputs\" (it applies to kind = \"dynamic\", kind = \"modal\")",
        ),
        (
            edited(
                "kind = \"kinematic\"\nt_end = 1.0\nsteps = 10",
                "kind = \"modal\"\ninputs = [\"pivot\"]",
            ),
            "is not a [[force]] of type point_force or torque, nor a one-coordinate [[driver]]",
        ),
        (
            edited(
                "kind = \"kinematic\"\nt_end = 1.0\nsteps = 10",
                "kind = \"stati\"",
            ),
            "did you mean",
        ),
    ];
    for (text, want) in cases {
        let o = run_text("run", &text);
        assert_eq!(o.code, 1, "{want}: {}", o.stderr);
        assert!(o.stderr.contains(want), "{want}: {}", o.stderr);
    }
}

/// A static run of a driven crank under gravity: the holding torque is m g (l/2) cos θ.
#[test]
fn static_driven_crank_holding_torque() {
    let text = edited(
        "[analysis]\nkind = \"kinematic\"\nt_end = 1.0\nsteps = 10",
        "[analysis]\nkind = \"static\"\ntime = 0.7",
    )
    .replacen(
        "name = \"crank\"\n",
        "name = \"crank\"\ngravity = [0.0, -9.81, 0.0]\n",
        1,
    );
    let o = run_text("run", &text);
    assert_eq!(o.code, 0, "{}", o.stderr);
    assert!(o.stdout.contains(": 1 equilibrium, "), "{}", o.stdout);
    let (h, rows) = csv(&o.dir.join("out"), "driver_efforts.csv");
    let t = rows[0][col(&h, "motor.torque [N m]")];
    let exact = 1.0 * G * 0.5 * (0.7f64).cos();
    assert!((t - exact).abs() < 1e-9 * exact, "{t} vs {exact}");
}

/// `cardan check` accepts a static model without drivers (its free DOF settle under the loads).
#[test]
fn check_accepts_static_models_without_drivers() {
    for name in ["fourbar_spring_static", "fourbar_spring_modal"] {
        let dir = common::scratch("check");
        let path = example(name);
        let o = common::cardan(&["check", path.to_str().unwrap()], &dir);
        assert_eq!(o.code, 0, "{name}: {}", o.stderr);
        assert!(
            o.stdout.contains("analysis: 1 DOF left free"),
            "{}",
            o.stdout
        );
    }
}

/// The state-space model of the modal run with a torque input on the crank and the crank angle
/// as output: its static gain −C A⁻¹ B is the compliance 1 / V''(θ*) of the one-coordinate
/// potential, computed here.
#[test]
fn modal_state_space_static_gain_is_the_compliance() {
    let text = std::fs::read_to_string(example("fourbar_spring_modal")).unwrap();
    let text = text
        .replacen(
            "[analysis]",
            "[[force]]\nname = \"probe\"\ntype = \"torque\"\nbody = \"crank\"\n\
             value = [0.0, 0.0, 1e-9]\n\n[analysis]",
            1,
        )
        .replacen(
            "kind = \"modal\"",
            "kind = \"modal\"\ninputs = [\"probe\"]",
            1,
        );
    let o = run_text("run", &text);
    assert_eq!(o.code, 0, "{}", o.stderr);
    let dir = o.dir.join("out");
    let read = |name: &str| common::matrix_market_dense(&dir.join(name));
    let (a, b, c) = (read("ss_A.mtx"), read("ss_B.mtx"), read("ss_C.mtx"));
    assert_eq!((a.nrows(), b.ncols(), c.nrows()), (2, 1, 2));
    let gain = -(&c * a.try_inverse().unwrap() * &b);
    let (_, k_eff) = equilibrium();
    // Output 1: joint A's angle (the crank), input 1: the torque about z on the crank.
    let got = gain[(0, 0)];
    println!("static gain {got} rad/(N m) vs 1/V'' = {}", 1.0 / k_eff);
    assert!((got * k_eff - 1.0).abs() < 1e-6, "{got} vs {}", 1.0 / k_eff);
    let signals = std::fs::read_to_string(dir.join("state_space.txt")).unwrap();
    assert!(signals.contains("input 1: probe [N m]"), "{signals}");
    assert!(signals.contains("output 1: A.angle [rad]"), "{signals}");
}

/// The crank of the common model held under gravity by its driver at θ = −0.7 rad; with the
/// driver as the state-space input (released), the static gain from its effort to the joint
/// angle is the compliance 1 / (−m g l_c sin θ), and the natural frequency of the released
/// crank √(K / J_O) follows from lin_K / lin_M.
#[test]
fn modal_driver_effort_input_static_gain() {
    let text = edited(
        "[analysis]\nkind = \"kinematic\"\nt_end = 1.0\nsteps = 10",
        "[analysis]\nkind = \"modal\"\ntime = -0.7\ninputs = [\"motor\"]\n\
         [analysis.outputs]\njoints = [\"pivot\"]",
    )
    .replacen(
        "name = \"crank\"\n",
        "name = \"crank\"\ngravity = [0.0, -9.81, 0.0]\n",
        1,
    );
    let o = run_text("run", &text);
    assert_eq!(o.code, 0, "{}", o.stderr);
    let dir = o.dir.join("out");
    let read = |name: &str| common::matrix_market_dense(&dir.join(name));
    let (a, b, c) = (read("ss_A.mtx"), read("ss_B.mtx"), read("ss_C.mtx"));
    assert_eq!((a.nrows(), b.ncols(), c.nrows()), (2, 1, 1));
    let gain = -(&c * a.try_inverse().unwrap() * &b)[(0, 0)];
    let k = -G * 0.5 * (-0.7f64).sin();
    println!("static gain {gain} vs {}", 1.0 / k);
    assert!((gain * k - 1.0).abs() < 1e-7, "{gain} vs {}", 1.0 / k);
    let w2 = read("lin_K.mtx")[(0, 0)] / read("lin_M.mtx")[(0, 0)];
    let j_o = 0.1 + 0.25;
    assert!((w2 * j_o / k - 1.0).abs() < 1e-7, "{w2} vs {}", k / j_o);
    let signals = std::fs::read_to_string(dir.join("state_space.txt")).unwrap();
    assert!(signals.contains("input 1: motor [N m]"), "{signals}");
}

/// `linearize_at` in a dynamic run: the crank of the common model released and swinging under
/// gravity, linearized at t = 0.3 (not an output time): modes.csv at that time with the
/// frequency of the joint angle's linearization √(−m g l_c sin θ / J_O) (θ from the run's
/// bodies.csv would need t = 0.3 as an output: here it is checked against a run with 0.3 as
/// the end time), the matrices written; refused outside [t_start, t_end] and in other kinds.
#[test]
fn dynamic_linearize_at_writes_modes_and_matrices() {
    let base = common::BASE
        .replacen(
            "name = \"crank\"\n",
            "name = \"crank\"\ngravity = [0.0, -9.81, 0.0]\n",
            1,
        )
        .replacen(
            "[[driver]]\nname = \"motor\"\ntype = \"rotation\"\njoint = \"pivot\"\n\
             function = { kind = \"polynomial\", coefficients = [0.0, 1.0] }\n",
            "",
            1,
        );
    let model = |analysis: &str| {
        base.replacen(
            "[analysis]\nkind = \"kinematic\"\nt_end = 1.0\nsteps = 10",
            analysis,
            1,
        )
    };
    let o = run_text(
        "run",
        &model(
            "[analysis]\nkind = \"dynamic\"\nt_end = 0.5\nsteps = 4\nlinearize_at = 0.3\n\
             rtol = 1e-10\natol = 1e-12",
        ),
    );
    assert_eq!(o.code, 0, "{}", o.stderr);
    let dir = o.dir.join("out");
    for f in [
        "lin_M.mtx",
        "lin_K.mtx",
        "lin_G.mtx",
        "ss_A.mtx",
        "state_space.txt",
    ] {
        assert!(dir.join(f).exists(), "{f}");
    }
    let (h, rows) = csv(&dir, "modes.csv");
    assert_eq!(rows.len(), 1);
    assert_eq!(rows[0][0], 0.3);
    let f = rows[0][col(&h, "frequency [Hz]")];
    // The angle at 0.3 s from a run that ends there.
    let o2 = run_text(
        "run",
        &model(
            "[analysis]\nkind = \"dynamic\"\nt_end = 0.3\nsteps = 1\nrtol = 1e-10\n\
             atol = 1e-12\n[analysis.outputs]\nbodies = [\"crank\"]",
        ),
    );
    assert_eq!(o2.code, 0, "{}", o2.stderr);
    let (h2, rows2) = csv(&o2.dir.join("out"), "bodies.csv");
    let (x, y) = (
        rows2[1][col(&h2, "crank.r.x [m]")],
        rows2[1][col(&h2, "crank.r.y [m]")],
    );
    let th = y.atan2(x);
    let k = -G * 0.5 * th.sin();
    let want = (k / 0.35).abs().sqrt() / (2.0 * PI);
    println!("f {f} vs {want} (θ = {th})");
    assert!((f - want).abs() < 1e-6 * want, "{f} vs {want}");
    for (analysis, msg) in [
        (
            "[analysis]\nkind = \"dynamic\"\nt_end = 0.5\nlinearize_at = 0.7",
            "must lie between",
        ),
        (
            "[analysis]\nkind = \"modal\"\nlinearize_at = 0.1",
            "kind = \"modal\" does not take \"linearize_at\" (it applies to kind = \"dynamic\"",
        ),
    ] {
        let o = run_text("run", &model(analysis));
        assert_ne!(o.code, 0);
        assert!(o.stderr.contains(msg), "{}", o.stderr);
    }
}

/// A modal run writes MatrixMarket files and `state_space.txt`; a second run into the same
/// directory replaces them (they are outputs of a run, not foreign files).
#[test]
fn a_modal_run_replaces_its_own_matrix_files() {
    let dir = run_example("fourbar_spring_modal");
    for f in ["lin_K.mtx", "ss_A.mtx", "state_space.txt"] {
        assert!(dir.join(f).is_file(), "{f} not written");
    }
    let again = run_model(&example("fourbar_spring_modal"), Some(&dir), false);
    let o = again.expect("a second modal run into the same directory");
    assert!(o.error.is_none(), "{:?}", o.error);
}
