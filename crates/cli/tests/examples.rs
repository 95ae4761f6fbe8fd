//! Every bundled example (`examples/*.toml`) is run and its motion checked independently:
//! against a closed form where one exists, and always against finite differences of its own
//! position history (velocities and accelerations, second order: the error must shrink about 4×
//! when the step is halved).

use cardan_cli::commands::run::run_model;
use cardan_mechanism::{AssemblyOptions, KinematicOptions, Results};
use cardan_model::prepare::{prepare, Prepared};
use nalgebra::{Vector3, Vector4};
use std::f64::consts::PI;
use std::path::PathBuf;

fn example(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../../examples")
        .join(format!("{name}.toml"))
}

fn out_dir(name: &str) -> PathBuf {
    std::env::temp_dir().join(format!("cardan-example-{name}-{}", std::process::id()))
}

/// Runs the example as `cardan run` does (CSV and SVG written), returns the model and results.
fn run_example(name: &str) -> (Prepared, Results) {
    let dir = out_dir(name);
    let o = run_model(&example(name), Some(&dir), false).expect("example runs");
    assert!(o.error.is_none(), "{name}: {:?}", o.error);
    // Every CSV has the time column, units in every header, and one row per stored step.
    let csvs: Vec<_> = o
        .summary
        .files
        .iter()
        .filter(|f| f.extension().is_some_and(|e| e == "csv"))
        .collect();
    assert!(csvs.len() >= 2, "{name}: {csvs:?}");
    for f in csvs {
        let csv = std::fs::read_to_string(f).unwrap();
        let (header, rows) = cardan_model::table::parse_csv(&csv).unwrap();
        assert_eq!(header[0], "t [s]");
        assert!(header.iter().all(|h| h.ends_with(']')), "{f:?}: {header:?}");
        assert_eq!(rows.len(), o.results.len());
        let svg = f.with_extension("svg");
        assert!(svg.exists() || f.ends_with("residual.csv"), "{svg:?}");
    }
    let _ = std::fs::remove_dir_all(&dir);
    (o.prepared, o.results)
}

/// ω = 2 G(p) ṗ (global).
fn omega_from(p: &Vector4<f64>, p_dot: &Vector4<f64>) -> Vector3<f64> {
    2.0 * cardan_eulerparam::g(p) * p_dot
}

/// Largest FD errors (velocity, acceleration) over all points and bodies, interior steps,
/// for a run of `steps` over the example's time span.
fn fd_errors(p: &Prepared, steps: usize) -> (f64, f64) {
    let a = p.loaded.analysis.as_ref().unwrap();
    let r = p
        .model
        .run_kinematics(&KinematicOptions::new(a.t_start, a.t_end, steps))
        .expect("run");
    let h = (a.t_end - a.t_start) / steps as f64;
    let (mut ev, mut ea) = (0.0f64, 0.0f64);
    for k in 1..steps {
        for pt in &r.points {
            let x = &pt.position;
            let v_fd = (x[k + 1] - x[k - 1]) / (2.0 * h);
            let a_fd = (x[k + 1] - 2.0 * x[k] + x[k - 1]) / (h * h);
            ev = ev.max((v_fd - pt.velocity[k]).amax());
            ea = ea.max((a_fd - pt.acceleration[k]).amax());
        }
        for b in &r.bodies {
            let x = &b.r;
            ev = ev.max(((x[k + 1] - x[k - 1]) / (2.0 * h) - b.r_dot[k]).amax());
            ea = ea.max(((x[k + 1] - 2.0 * x[k] + x[k - 1]) / (h * h) - b.r_ddot[k]).amax());
            let p_dot = (b.p[k + 1] - b.p[k - 1]) / (2.0 * h);
            ev = ev.max((omega_from(&b.p[k], &p_dot) - b.omega[k]).amax());
            let w = &b.omega;
            ea = ea.max(((w[k + 1] - w[k - 1]) / (2.0 * h) - b.omega_dot[k]).amax());
        }
    }
    (ev, ea)
}

/// Checks second-order convergence of the FD errors; returns (ev, ea, order_v, order_a) at the
/// finer step.
fn check_fd(
    name: &str,
    p: &Prepared,
    steps: usize,
    max_v: f64,
    max_a: f64,
) -> (f64, f64, f64, f64) {
    let (ev1, ea1) = fd_errors(p, steps);
    let (ev2, ea2) = fd_errors(p, 2 * steps);
    let (ov, oa) = ((ev1 / ev2).log2(), (ea1 / ea2).log2());
    eprintln!(
        "{name}: FD velocity error {ev1:.3e} → {ev2:.3e} (order {ov:.2}), acceleration {ea1:.3e} → {ea2:.3e} (order {oa:.2})"
    );
    assert!(
        ev2 < max_v && ea2 < max_a,
        "{name}: FD errors {ev2:e}, {ea2:e}"
    );
    assert!((1.8..2.3).contains(&ov), "{name}: velocity FD order {ov}");
    assert!(
        (1.8..2.3).contains(&oa),
        "{name}: acceleration FD order {oa}"
    );
    (ev2, ea2, ov, oa)
}

/// Haug's spatial slider-crank (§2.6 of the benchmarks), crank driven at θ = 2πt.
///
/// Closed form: the crank turns about global x through A = (0, 0.1, 0.12), length 0.08, starting
/// along +z, so B(θ) = (0, 0.1 − 0.08 sin θ, 0.12 + 0.08 cos θ). The slider point C = (x, 0, 0)
/// is 0.3 from B: x² + B_y² + B_z² = 0.09, hence
///
/// ```text
/// x(θ) = √(0.09 − B_y² − B_z²),     ẋ = −(B_y Ḃ_y + B_z Ḃ_z) / x,
/// Ḃ_y = −0.08 cos θ · θ̇,            Ḃ_z = −0.08 sin θ · θ̇,       θ̇ = 2π
/// ```
///
/// (x > 0 on the whole turn: B_y² + B_z² ≤ 0.0558 < 0.09). Velocities are linear in θ̇, so the
/// benchmark's conrod ω = (1.92, −0.96, 0.48) rad/s at θ̇ = 6 becomes (1.92, −0.96, 0.48)·2π/6 at
/// t = 0.
#[test]
fn slider_crank_matches_closed_form() {
    let (p, r) = run_example("slider_crank");
    assert_eq!(r.len(), 201);
    let c = r.point("slider", "C").unwrap();
    let b = r.point("crank", "B").unwrap();
    let (mut ex, mut ev, mut eb) = (0.0f64, 0.0f64, 0.0f64);
    for (k, &t) in r.times.iter().enumerate() {
        let th = 2.0 * PI * t;
        let w = 2.0 * PI;
        let (by, bz) = (0.1 - 0.08 * th.sin(), 0.12 + 0.08 * th.cos());
        let (bdy, bdz) = (-0.08 * th.cos() * w, -0.08 * th.sin() * w);
        let x = (0.09 - by * by - bz * bz).sqrt();
        let xd = -(by * bdy + bz * bdz) / x;
        ex = ex.max((c.position[k] - Vector3::new(x, 0.0, 0.0)).amax());
        ev = ev.max((c.velocity[k] - Vector3::new(xd, 0.0, 0.0)).amax());
        eb = eb.max((b.position[k] - Vector3::new(0.0, by, bz)).amax());
    }
    eprintln!("slider_crank: max |x − x(θ)| = {ex:.2e} m, |ẋ − ẋ(θ)| = {ev:.2e} m/s, |B − B(θ)| = {eb:.2e} m");
    assert!(ex < 1e-10 && eb < 1e-10 && ev < 1e-9, "{ex} {eb} {ev}");
    let w0 = r.body("conrod").unwrap().omega[0];
    let want = Vector3::new(1.92, -0.96, 0.48) * (2.0 * PI / 6.0);
    assert!(
        (w0 - want).amax() < 1e-10,
        "conrod ω(0) = {w0:?}, want {want:?}"
    );
    // Joint output: the crank angle is θ = 2πt, unwrapped over the turn.
    let j = r.joint("crank_pin").unwrap();
    assert!((j.values[200][0] - 2.0 * PI).abs() < 1e-9);
    check_fd("slider_crank", &p, 100, 1e-2, 5e-1);
}

/// Issue 25: `position_tolerance = 1e-14` gives positions within 1e-14 m of the closed form
/// (the error itself, not the residual), and the tolerance is what sets it: at 1e-6 the same
/// run is measurably less accurate. The closed form is that of `slider_crank_matches_closed_form`.
#[test]
fn position_tolerance_sets_the_position_error() {
    let text = std::fs::read_to_string(example("slider_crank")).unwrap();
    let error_at = |tol: &str| {
        let path = std::env::temp_dir().join(format!(
            "cardan-position-tolerance-{tol}-{}.toml",
            std::process::id()
        ));
        let edited = text.replace(
            "[analysis]",
            &format!("[analysis]\nposition_tolerance = {tol}"),
        );
        assert_ne!(edited, text);
        std::fs::write(&path, edited).unwrap();
        let p = prepare(&path).expect("prepares");
        let _ = std::fs::remove_file(&path);
        let a = p.loaded.analysis.as_ref().unwrap();
        assert_eq!(a.tolerance, tol.parse::<f64>().unwrap());
        let r = p
            .model
            .run_kinematics(
                &KinematicOptions::new(a.t_start, a.t_end, a.steps).tolerance(a.tolerance),
            )
            .expect("runs");
        let (c, b) = (
            r.point("slider", "C").unwrap(),
            r.point("crank", "B").unwrap(),
        );
        let mut e = 0.0f64;
        for (k, &t) in r.times.iter().enumerate() {
            let th = 2.0 * PI * t;
            let (by, bz) = (0.1 - 0.08 * th.sin(), 0.12 + 0.08 * th.cos());
            let x = (0.09 - by * by - bz * bz).sqrt();
            e = e.max((c.position[k] - Vector3::new(x, 0.0, 0.0)).amax());
            e = e.max((b.position[k] - Vector3::new(0.0, by, bz)).amax());
        }
        e
    };
    let (tight, loose) = (error_at("1e-14"), error_at("1e-6"));
    eprintln!(
        "slider_crank: position error {loose:.2e} m at 1e-6, {:.2e} m at 1e-8, {:.2e} m at \
         1e-10, {:.2e} m at 1e-12, {tight:.2e} m at 1e-14",
        error_at("1e-8"),
        error_at("1e-10"),
        error_at("1e-12")
    );
    assert!(
        tight <= 1e-14,
        "position error {tight:e} m at position_tolerance = 1e-14"
    );
    assert!(loose > 10.0 * tight, "{loose:e} vs {tight:e}");
}

/// The slider-crank driven by the expression θ(t) = 2πt + 0.3 sin(2πt): the same closed form
/// with that θ and θ̇ = 2π(1 + 0.3 cos 2πt); accelerations by the finite-difference check.
#[test]
fn expression_driver_matches_closed_form() {
    let (p, r) = run_example("expression_driver");
    assert_eq!(r.len(), 201);
    let c = r.point("slider", "C").unwrap();
    let (mut ex, mut ev) = (0.0f64, 0.0f64);
    for (k, &t) in r.times.iter().enumerate() {
        let th = 2.0 * PI * t + 0.3 * (2.0 * PI * t).sin();
        let w = 2.0 * PI * (1.0 + 0.3 * (2.0 * PI * t).cos());
        let (by, bz) = (0.1 - 0.08 * th.sin(), 0.12 + 0.08 * th.cos());
        let (bdy, bdz) = (-0.08 * th.cos() * w, -0.08 * th.sin() * w);
        let x = (0.09 - by * by - bz * bz).sqrt();
        let xd = -(by * bdy + bz * bdz) / x;
        ex = ex.max((c.position[k] - Vector3::new(x, 0.0, 0.0)).amax());
        ev = ev.max((c.velocity[k] - Vector3::new(xd, 0.0, 0.0)).amax());
    }
    eprintln!("expression_driver: max |x − x(θ)| = {ex:.2e} m, |ẋ − ẋ(θ)| = {ev:.2e} m/s");
    assert!(ex < 1e-10 && ev < 1e-9, "{ex} {ev}");
    check_fd("expression_driver", &p, 100, 2e-2, 1.0);
}

/// Spatial RSSR four-bar. The crank tip is P(θ) = (a cos θ, a sin θ, 0), a = 0.1; the rocker turns
/// about global y through G = (0.3, 0.15, 0.1) and its tip is Q(ψ) = G + b (cos ψ, 0, sin ψ),
/// b = 0.2; the coupler keeps |Q − P| = L = 0.35. With w = G − P:
///
/// ```text
/// |w|² + b² + 2b (w_x cos ψ + w_z sin ψ) = L²
/// ⇒ A cos ψ + B sin ψ = C,   A = w_x, B = w_z, C = (L² − |w|² − b²) / (2b)
/// ⇒ ψ = atan2(B, A) + acos(C / √(A² + B²))      (the branch of the file's initial pose)
/// ```
///
/// A = 0.3 − a cos θ > 0, so atan2 is continuous over the turn, and √(A² + B²) − |C| ≥ 0.098:
/// no dead point.
#[test]
fn rssr_matches_closed_form() {
    let (p, r) = run_example("rssr_fourbar");
    let q = r.point("rocker", "Q").unwrap();
    let (a, b, l) = (0.1, 0.2, 0.35);
    let g = Vector3::new(0.3, 0.15, 0.1);
    let mut err = 0.0f64;
    for (k, &t) in r.times.iter().enumerate() {
        let th = 2.0 * PI * t;
        let pp = Vector3::new(a * th.cos(), a * th.sin(), 0.0);
        let w = g - pp;
        let (ca, cb) = (w.x, w.z);
        let cc = (l * l - w.norm_squared() - b * b) / (2.0 * b);
        let psi = cb.atan2(ca) + (cc / ca.hypot(cb)).acos();
        let want = g + b * Vector3::new(psi.cos(), 0.0, psi.sin());
        err = err.max((q.position[k] - want).amax());
    }
    eprintln!("rssr: max |Q − Q(ψ(θ))| = {err:.2e} m");
    assert!(err < 1e-10, "{err}");
    check_fd("rssr_fourbar", &p, 100, 1e-2, 5e-1);
}

/// Universal (Cardan) joint at a bend β = 30°.
///
/// Shaft 1 turns about a₁ = x, shaft 2 about a₂ = (cos β, sin β, 0); both axes meet at the cross
/// centre. Measure φ₁ from the position where shaft 1's arm lies in the plane of the shafts:
/// u₁ = (0, cos φ₁, sin φ₁). Shaft 2's arm starts along the plane normal z and turns about a₂:
/// u₂ = z cos φ₂ + (a₂ × z) sin φ₂ = (sin β sin φ₂, −cos β sin φ₂, cos φ₂). The cross keeps its
/// arms perpendicular, u₁ · u₂ = 0:
///
/// ```text
/// −cos β sin φ₂ cos φ₁ + sin φ₁ cos φ₂ = 0   ⇒   tan φ₂ = tan φ₁ / cos β
/// ```
///
/// and, differentiating, φ̇₂ / φ̇₁ = cos β / (1 − sin² β cos² φ₁).
#[test]
fn universal_joint_follows_cardan_formula() {
    let (p, r) = run_example("universal_drive");
    let beta = PI / 6.0;
    let a2 = Vector3::new(beta.cos(), beta.sin(), 0.0);
    let n2 = a2.cross(&Vector3::z());
    let (s1, s2) = (r.body("shaft1").unwrap(), r.body("shaft2").unwrap());
    let (mut e_angle, mut e_rate) = (0.0f64, 0.0f64);
    for k in 0..r.len() {
        let u1 = cardan_eulerparam::a(&s1.p[k]) * Vector3::y();
        let u2 = cardan_eulerparam::a(&s2.p[k]) * Vector3::z();
        let phi1 = u1.z.atan2(u1.y);
        let phi2 = u2.dot(&n2).atan2(u2.z);
        // tan φ₂ = tan φ₁ / cos β, in the quadrant of φ₁.
        let want = phi1.sin().atan2(phi1.cos() * beta.cos());
        let d = (phi2 - want + PI).rem_euclid(2.0 * PI) - PI;
        e_angle = e_angle.max(d.abs());
        let w1 = s1.omega[k].dot(&Vector3::x());
        let w2 = s2.omega[k].dot(&a2);
        let ratio = beta.cos() / (1.0 - beta.sin().powi(2) * phi1.cos().powi(2));
        e_rate = e_rate.max((w2 - ratio * w1).abs());
    }
    eprintln!("universal_drive: max |φ₂ − φ₂(φ₁)| = {e_angle:.2e} rad, |ω₂ − ratio ω₁| = {e_rate:.2e} rad/s");
    assert!(e_angle < 1e-10 && e_rate < 1e-9, "{e_angle} {e_rate}");
    // Two revolute bearings and the cross: 14 equations of rank 11 for 12 unknowns.
    assert_eq!(dof_and_redundant(&p), (1, 3));
    check_fd("universal_drive", &p, 100, 1e-2, 5e-1);
}

/// DOF and number of redundant equations of the joints, assembled at t = 0 without drivers.
fn dof_and_redundant(p: &Prepared) -> (usize, usize) {
    let mut ws = p.model.workspace();
    let opts = AssemblyOptions {
        include_drivers: false,
        ..AssemblyOptions::at(0.0)
    };
    p.model.assemble(&mut ws, &opts).unwrap();
    let dof = p.model.dof(&ws).unwrap();
    (dof.dof, dof.redundant.len())
}

/// The CV driveline: the output shaft's bearing angle equals the input's at every instant, and
/// so do the speeds (the universal_drive example at the same bend fluctuates).
#[test]
fn cv_driveline_turns_the_output_at_the_input_speed() {
    let (p, r) = run_example("cv_driveline");
    let beta = PI / 6.0;
    let a2 = Vector3::new(beta.cos(), beta.sin(), 0.0);
    let (b1, b2) = (r.joint("bearing1").unwrap(), r.joint("bearing2").unwrap());
    let (s1, s2) = (r.body("shaft1").unwrap(), r.body("shaft2").unwrap());
    let (mut e_angle, mut e_rate) = (0.0f64, 0.0f64);
    for k in 0..r.len() {
        e_angle = e_angle.max((b2.values[k][0] - b1.values[k][0]).abs());
        let w1 = s1.omega[k].dot(&Vector3::x());
        e_rate = e_rate.max((s2.omega[k].dot(&a2) - w1).abs());
    }
    eprintln!("cv_driveline: max |φ₂ − φ₁| = {e_angle:.2e} rad, |ω₂ − ω₁| = {e_rate:.2e} rad/s");
    assert!(e_angle < 1e-10 && e_rate < 1e-9, "{e_angle} {e_rate}");
    // Two revolute bearings and the CV joint: 14 equations of rank 11 (its point is redundant).
    // (No finite-difference order check: both shafts turn at constant speed, so the differences
    // of the accelerations are already at roundoff.)
    assert_eq!(dof_and_redundant(&p), (1, 3));
}

/// The wobble-plate pump: each piston follows z = R tan α sin(φ − θ), θ = 2π t.
#[test]
fn wobble_plate_pistons_follow_the_closed_form() {
    let (p, r) = run_example("wobble_plate_pump");
    let (alpha, radius, w) = (15f64.to_radians(), 0.1, 2.0 * PI);
    let c = radius * alpha.tan();
    let (mut ez, mut ev) = (0.0f64, 0.0f64);
    for k in 0..3 {
        let phi = 2.0 * PI * k as f64 / 3.0;
        let piston = r.body(&format!("piston{k}")).unwrap();
        for (n, &t) in r.times.iter().enumerate() {
            ez = ez.max((piston.r[n].z - c * (phi - w * t).sin()).abs());
            ev = ev.max((piston.r_dot[n].z + c * w * (phi - w * t).cos()).abs());
        }
    }
    eprintln!("wobble_plate_pump: max |z − z(θ)| = {ez:.2e} m, |ż − ż(θ)| = {ev:.2e} m/s");
    assert!(ez < 1e-12 && ev < 1e-11, "{ez} {ev}");
    check_fd("wobble_plate_pump", &p, 100, 1e-2, 5e-1);
}

/// Cubic Hermite interpolation of a point history at time t (positions and velocities).
fn hermite(r: &Results, x: &[Vector3<f64>], v: &[Vector3<f64>], t: f64) -> Vector3<f64> {
    let k = r.times.partition_point(|&s| s <= t).clamp(1, r.len() - 1) - 1;
    let (t0, t1) = (r.times[k], r.times[k + 1]);
    let h = t1 - t0;
    let s = (t - t0) / h;
    let (h00, h10, h01, h11) = (
        2.0 * s.powi(3) - 3.0 * s * s + 1.0,
        s.powi(3) - 2.0 * s * s + s,
        -2.0 * s.powi(3) + 3.0 * s * s,
        s.powi(3) - s * s,
    );
    x[k] * h00 + v[k] * (h10 * h) + x[k + 1] * h01 + v[k + 1] * (h11 * h)
}

/// Bricard's mechanism: 30 joint equations of rank 29 (Grübler 0, mobility 1), driven at J1.
///
/// Independent check: the point P3 = C of the IFToMM A04 benchmark moves on a fixed curve
/// whatever drives it, so the reference positions of the dynamic benchmark
/// (shared/benchmarks/README.md §2.4) must lie on our kinematic path. For each reference point we
/// find the time at which our P3.x equals the reference x (bisection on the cubic Hermite
/// interpolant of positions and velocities) and compare y and z there.
#[test]
fn bricard_is_mobile_with_one_redundant_equation() {
    let (p, r) = run_example("bricard");
    let mut ws = p.model.workspace();
    let opts = AssemblyOptions {
        include_drivers: false,
        ..AssemblyOptions::at(0.0)
    };
    p.model.assemble(&mut ws, &opts).unwrap();
    let dof = p.model.dof(&ws).unwrap();
    assert_eq!(dof.joint_equations, 30);
    assert_eq!(dof.rank, 29);
    assert_eq!(dof.dof, 1);
    assert_eq!(dof.redundant.len(), 1);
    let res = r.residual.iter().fold(0.0f64, |a, &b| a.max(b));
    eprintln!("bricard: largest constraint residual {res:.2e}");
    assert!(res < 1e-10);
    let c = r.point("rod2", "C").unwrap();
    // The first half of the run (θ rising 0 → 3) sweeps P3.x from 1 down past −0.7.
    let half = r.len() / 2;
    let mut worst = 0.0f64;
    for want in [
        Vector3::new(0.774717808, -0.979815048, -0.199906159),
        Vector3::new(0.274481319, -0.886707939, -0.462330003),
        Vector3::new(-0.778135373, -0.980352683, -0.197252671),
    ] {
        let k = (1..=half)
            .find(|&k| (c.position[k - 1].x - want.x) * (c.position[k].x - want.x) <= 0.0)
            .expect("P3.x passes the reference value");
        let (mut lo, mut hi) = (r.times[k - 1], r.times[k]);
        let f = |t: f64| hermite(&r, &c.position, &c.velocity, t).x - want.x;
        for _ in 0..60 {
            let mid = 0.5 * (lo + hi);
            if f(lo) * f(mid) <= 0.0 {
                hi = mid;
            } else {
                lo = mid;
            }
        }
        let got = hermite(&r, &c.position, &c.velocity, 0.5 * (lo + hi));
        worst = worst.max((got - want).amax());
    }
    eprintln!("bricard: P3 path vs benchmark reference points: max deviation {worst:.2e} m");
    assert!(worst < 1e-6, "{worst}");
    check_fd("bricard", &p, 200, 1e-1, 5.0);
}

/// Bennett's linkage: 20 joint equations of rank 17 with one degree of freedom. The 17 rows kept
/// at the drawn pose lose rank at t = 0.420422528454052 (issue 27, item 1): a run whose last
/// frame lands there chooses the rows again, closes every equation, and says so in the summary
/// and in run.json.
#[test]
fn bennett_chooses_its_rows_again_where_the_first_choice_is_singular() {
    let (p, r) = run_example("bennett");
    let res = r.residual.iter().fold(0.0f64, |a, &b| a.max(b));
    assert!(res < 1e-10, "{res}");
    assert_eq!(
        p.model.num_equations(),
        21,
        "20 joint equations and the driver"
    );
    check_fd("bennett", &p, 200, 1e-1, 5.0);

    let text = std::fs::read_to_string(example("bennett"))
        .unwrap()
        .replace("t_end = 1.0", "t_end = 0.420422528454052")
        .replace("steps = 200", "steps = 50");
    let dir = out_dir("bennett-singular");
    std::fs::create_dir_all(&dir).unwrap();
    let model = dir.join("bennett.toml");
    std::fs::write(&model, text).unwrap();
    let o = run_model(&model, Some(&dir.join("out")), false).expect("runs");
    assert!(o.error.is_none(), "{:?}", o.error);
    let res = o.results.residual.iter().fold(0.0f64, |a, &b| a.max(b));
    assert!(res < 1e-10, "{res}");
    assert!(o.summary.row_reselections >= 1, "{:?}", o.summary);
    let json = std::fs::read_to_string(dir.join("out/run.json")).unwrap();
    assert!(json.contains(&format!(
        "\"row_reselections\": {}",
        o.summary.row_reselections
    )));
    let mut line = Vec::new();
    cardan_model::analysis::print_summary(&o.summary, &mut line).unwrap();
    let line = String::from_utf8(line).unwrap();
    assert!(line.contains("redundant equations chosen again"), "{line}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// RSCR four-bar with a cylindrical joint. The ball centre is P(θ) = (a cos θ, a sin θ, h),
/// a = 0.1, h = 0.15. The rocker turns about global y through G = (0.35, 0, 0); its arm is the
/// line through G with direction u(ψ) = (sin ψ, 0, cos ψ). The coupler holds P at distance
/// e = 0.15 from its cylinder axis, which the cylindrical joint lays on the arm, so with
/// w = P − G:
///
/// ```text
/// |w × u|² = |w|² − (w · u)² = e²   ⇒   w_x sin ψ + w_z cos ψ = +√(|w|² − e²)
/// ⇒ ψ = atan2(w_x, w_z) + acos(√(|w|² − e²) / √(w_x² + w_z²))
/// ```
///
/// (sign and branch of the initial pose u = (−8, 0, 15)/17). The margin
/// (w_x² + w_z²) − (|w|² − e²) = e² − a² sin² θ ≥ 0.0125 keeps the crank clear of dead points.
#[test]
fn rscr_matches_closed_form() {
    let (p, r) = run_example("spatial_fourbar_cylindrical");
    let (a, h, e) = (0.1, 0.15, 0.15);
    let g = Vector3::new(0.35, 0.0, 0.0);
    let arm = p
        .model
        .vectors()
        .iter()
        .find(|v| v.body_name == "rocker" && v.name == "arm")
        .unwrap()
        .local
        .normalize();
    let rocker = r.body("rocker").unwrap();
    let mut err = 0.0f64;
    for (k, &t) in r.times.iter().enumerate() {
        let th = 2.0 * PI * t;
        let w = Vector3::new(a * th.cos(), a * th.sin(), h) - g;
        let c = (w.norm_squared() - e * e).sqrt();
        let psi = w.x.atan2(w.z) + (c / w.x.hypot(w.z)).acos();
        let want = Vector3::new(psi.sin(), 0.0, psi.cos());
        let got = cardan_eulerparam::a(&rocker.p[k]) * arm;
        err = err.max((got - want).amax());
    }
    eprintln!("rscr: max |u − u(ψ(θ))| = {err:.2e}");
    assert!(err < 1e-10, "{err}");
    check_fd("spatial_fourbar_cylindrical", &p, 100, 1e-2, 5e-1);
}

/// The crank and slotted lever (`examples/quick_return.toml`): a pin in a straight slot, the
/// slot a `[[curve]]` of type line. With the pin A = (a cos θ, d + a sin θ), θ = ω t:
///
/// ```text
/// u = |A|,  u̇ = A·Ȧ / u,  ü = (|Ȧ|² + A·Ä − u̇²) / u
/// φ = atan2(A_y, A_x),  φ̇ = (A × Ȧ)_z / u²,  φ̈ = (A × Ä)_z / u² − 2 u̇ φ̇ / u
/// ```
///
/// read from the joint tables as written (`slot.u [m]`, `lever_pivot.angle [rad]`...).
#[test]
fn quick_return_lever_follows_the_pin_in_its_slot() {
    let (a, d, w) = (0.1, 0.3, 2.0 * PI);
    let mut worst = [0.0f64; 6];
    for (k, table) in ["joints", "joint_velocities", "joint_accelerations"]
        .into_iter()
        .enumerate()
    {
        let (_, _, header, rows) = run_with_table("quick_return", table);
        let per = ["", "/s", "/s²"][k];
        let u = column(&header, &rows, &format!("slot.u [m{per}]"));
        let phi = column(&header, &rows, &format!("lever_pivot.angle [rad{per}]"));
        for (n, row) in rows.iter().enumerate() {
            let th = w * row[0];
            let p = Vector3::new(a * th.cos(), d + a * th.sin(), 0.0);
            let v = a * w * Vector3::new(-th.sin(), th.cos(), 0.0);
            let acc = -a * w * w * Vector3::new(th.cos(), th.sin(), 0.0);
            let l = p.norm();
            let l_dot = p.dot(&v) / l;
            let phi_dot = p.cross(&v).z / (l * l);
            let want = match k {
                0 => (l, p.y.atan2(p.x)),
                1 => (l_dot, phi_dot),
                _ => (
                    (v.norm_squared() + p.dot(&acc) - l_dot * l_dot) / l,
                    p.cross(&acc).z / (l * l) - 2.0 * l_dot * phi_dot / l,
                ),
            };
            worst[2 * k] = worst[2 * k].max((u[n] - want.0).abs());
            worst[2 * k + 1] = worst[2 * k + 1].max((phi[n] - want.1).abs());
        }
    }
    eprintln!(
        "quick_return: |u − u(θ)|, |φ − φ(θ)| and their rates, accelerations: {:?}",
        worst.map(|e| format!("{e:.1e}"))
    );
    assert!(worst.iter().all(|&e| e < 1e-10), "{worst:?}");
    let p = prepare(&example("quick_return")).unwrap();
    check_fd("quick_return", &p, 100, 1e-2, 5e-1);
}

/// The two-link arm whose tool point follows a circle at constant speed
/// (`examples/arm_path.toml`: a circle `[[curve]]` and a path driver u = v t). The tool point is
/// P = C + R (cos(vt/R), sin(vt/R), 0) with speed v and acceleration v²/R toward C, and the
/// joint angles are the elbow-up inverse kinematics of P:
/// θ2 = acos((|P|² − l1² − l2²) / (2 l1 l2)), θ1 = atan2(P_y, P_x) − atan2(l2 sin θ2, l1 + l2 cos θ2).
#[test]
fn arm_path_tool_follows_the_circle_at_constant_speed() {
    let (p, r) = run_example("arm_path");
    let (l1, l2, radius, v) = (0.4, 0.3, 0.1, 0.2);
    let c = Vector3::new(0.3, 0.3, 0.0);
    let tool = r.point("fore", "tool").unwrap();
    let (shoulder, elbow) = (r.joint("shoulder").unwrap(), r.joint("elbow").unwrap());
    let path = r.curve("path").unwrap();
    let mut worst = [0.0f64; 5];
    for (k, &t) in r.times.iter().enumerate() {
        let a = v * t / radius;
        let want = c + radius * Vector3::new(a.cos(), a.sin(), 0.0);
        let acc = -v * v / radius * Vector3::new(a.cos(), a.sin(), 0.0);
        let th2 = ((want.norm_squared() - l1 * l1 - l2 * l2) / (2.0 * l1 * l2)).acos();
        let th1 = want.y.atan2(want.x) - (l2 * th2.sin()).atan2(l1 + l2 * th2.cos());
        let e = [
            (tool.position[k] - want).amax(),
            (tool.velocity[k].norm() - v).abs(),
            (tool.acceleration[k] - acc).amax(),
            (shoulder.values[k][0] - th1)
                .abs()
                .max((elbow.values[k][0] - th2).abs()),
            (path.u[k] - v * t).abs().max((path.u_dot[k] - v).abs()),
        ];
        for (w, e) in worst.iter_mut().zip(e) {
            *w = w.max(e);
        }
    }
    eprintln!(
        "arm_path: |P − P(t)|, ||Ṗ| − v|, |P̈ − P̈(t)|, |θ − θ_IK|, |u − vt|: {:?}",
        worst.map(|e| format!("{e:.1e}"))
    );
    assert!(worst.iter().all(|&e| e < 1e-10), "{worst:?}");
    check_fd("arm_path", &p, 100, 1e-2, 5e-1);
}

/// The harmonic cam and flat-faced tappet (`examples/valve_train.toml`, a `[[cam]]` with
/// `follower = "flat"`): lift e (1 − cos θ), ṡ = e ω sin θ, s̈ = e ω² cos θ, and the contact
/// point on the face at w = e sin θ, read from the joint tables as written.
#[test]
fn valve_train_tappet_lifts_e_one_minus_cos() {
    let (e, w) = (0.005, 100.0 * PI);
    let mut worst = [0.0f64; 6];
    for (k, table) in ["joints", "joint_velocities", "joint_accelerations"]
        .into_iter()
        .enumerate()
    {
        let (_, _, header, rows) = run_with_table("valve_train", table);
        let per = ["", "/s", "/s²"][k];
        let s = column(&header, &rows, &format!("guide.slide [m{per}]"));
        let face = column(&header, &rows, &format!("lobe.w [m{per}]"));
        for (n, row) in rows.iter().enumerate() {
            let th = w * row[0];
            let want = match k {
                0 => (0.015 + e * (1.0 - th.cos()), e * th.sin()),
                1 => (e * w * th.sin(), e * w * th.cos()),
                _ => (e * w * w * th.cos(), -e * w * w * th.sin()),
            };
            // Relative to the lift's, rate's, acceleration's scale e ω^k.
            let scale = e * w.powi(k as i32);
            worst[2 * k] = worst[2 * k].max((s[n] - want.0).abs() / scale);
            worst[2 * k + 1] = worst[2 * k + 1].max((face[n] - want.1).abs() / scale);
        }
    }
    eprintln!(
        "valve_train: |s − s(θ)|, |w − w(θ)| and their rates, accelerations, over e ω^k: {:?}",
        worst.map(|e| format!("{e:.1e}"))
    );
    assert!(worst.iter().all(|&e| e < 1e-10), "{worst:?}");
    // The contact point on the face above the disc's centre, the pressure angle 0 (the face's
    // normal is the tappet's direction of motion).
    let (_, _, header, rows) = run_with_table("valve_train", "cams");
    let (x, y) = (
        column(&header, &rows, "lobe.contact.x [m]"),
        column(&header, &rows, "lobe.contact.y [m]"),
    );
    let angle = column(&header, &rows, "lobe.pressure_angle [rad]");
    for (n, row) in rows.iter().enumerate() {
        let th = w * row[0];
        assert!((x[n] - e * th.sin()).abs() < 1e-15, "{}", x[n]);
        assert!(
            (y[n] - 0.015 - e * (1.0 - th.cos())).abs() < 1e-15,
            "{}",
            y[n]
        );
        assert!(angle[n].abs() < 1e-12, "{}", angle[n]);
    }
    let p = prepare(&example("valve_train")).unwrap();
    // The FD errors scale with e ω (1.6 m/s) and e ω² (490 m/s²); their order is the check.
    check_fd("valve_train", &p, 100, 5e-2, 5.0);
}

/// The valve train against its spring by inverse dynamics (`examples/valve_spring.toml`): the
/// cam's contact force on the tappet N(θ) = F₀ + k e (1 − cos θ) + m e ω² cos θ along the
/// tappet's axis, and the camshaft torque T = N e sin θ (T ω = N ṡ), read from cam_forces.csv
/// and driver_efforts.csv as written.
#[test]
fn valve_spring_contact_force_and_camshaft_torque_follow_the_closed_form() {
    let (e, w, m, k, f0) = (0.005, 100.0 * PI, 0.1, 2.0e4, 150.0);
    let contact = |th: f64| f0 + k * e * (1.0 - th.cos()) + m * e * w * w * th.cos();
    let (_, _, header, rows) = run_with_table("valve_spring", "cam_forces");
    let normal = column(&header, &rows, "lobe.normal_force [N]");
    let fy = column(&header, &rows, "lobe.force.y [N]");
    let mut worst = [0.0f64; 2];
    for (n, row) in rows.iter().enumerate() {
        let want = contact(w * row[0]);
        worst[0] = worst[0]
            .max((normal[n] - want).abs())
            .max((fy[n] - want).abs());
    }
    let (_, _, header, rows) = run_with_table("valve_spring", "driver_efforts");
    let torque = column(&header, &rows, "motor.torque [N m]");
    for (n, row) in rows.iter().enumerate() {
        let th = w * row[0];
        worst[1] = worst[1].max((torque[n] - contact(th) * e * th.sin()).abs());
    }
    eprintln!(
        "valve_spring: |N − N(θ)| {:.1e} N, |T − N e sin θ| {:.1e} N m",
        worst[0], worst[1]
    );
    assert!(worst[0] < 1e-9 && worst[1] < 1e-11, "{worst:?}");
}

/// The arm whose tip rides a torus (`examples/torus_follower.toml`, a `[[surface]]` with
/// `type = "torus"`): the shaft's height z(θ) = √((R + √(r² − ρ² cos² θ))² − ρ² sin² θ), read
/// from joints.csv as written, and the tip on the torus (its distance from the centre circle r).
#[test]
fn torus_follower_height_follows_the_closed_form() {
    let (big, tube, rho, w) = (1.0f64, 0.4f64, 0.3f64, 2.0 * PI);
    let z = |th: f64| {
        let (x, y) = (rho * th.cos(), rho * th.sin());
        ((big + (tube * tube - x * x).sqrt()).powi(2) - y * y).sqrt()
    };
    let (_, r, header, rows) = run_with_table("torus_follower", "joints");
    let slide = column(&header, &rows, "shaft.slide [m]");
    let mut worst = [0.0f64; 2];
    for (n, row) in rows.iter().enumerate() {
        worst[0] = worst[0].max((slide[n] - z(w * row[0])).abs());
    }
    let tip = r.point("arm", "T").unwrap();
    for p in &tip.position {
        let off = (p.y.hypot(p.z) - big).hypot(p.x);
        worst[1] = worst[1].max((off - tube).abs());
    }
    eprintln!(
        "torus_follower: |z − z(θ)| {:.1e} m, tip off the torus {:.1e} m",
        worst[0], worst[1]
    );
    assert!(worst[0] < 1e-12 && worst[1] < 1e-12, "{worst:?}");
    let p = prepare(&example("torus_follower")).unwrap();
    check_fd("torus_follower", &p, 100, 5e-2, 5e-1);
}

/// Every example also passes `cardan check` (through the library) with DOF = drivers.
#[test]
fn every_example_checks() {
    for name in [
        "slider_crank",
        "rssr_fourbar",
        "universal_drive",
        "bricard",
        "bennett",
        "spatial_fourbar_cylindrical",
        "slider_crank_inverse",
        "gear_train",
        "screw_jack",
        "rack_pinion_steering",
        "cv_driveline",
        "wobble_plate_pump",
        "expression_driver",
        "quick_return",
        "arm_path",
        "valve_train",
        "valve_spring",
        "torus_follower",
    ] {
        let p = prepare(&example(name)).unwrap();
        let mut out = Vec::new();
        cardan_model::check::check(&example(name), &mut out).unwrap();
        let text = String::from_utf8(out).unwrap();
        assert!(text.contains("degrees of freedom: 1"), "{name}: {text}");
        assert!(text.contains(": ok"), "{name}: {text}");
        assert_eq!(p.model.drivers().len() + p.model.paths().len(), 1);
        let mut out = Vec::new();
        cardan_model::eval::eval(&example(name), None, Default::default(), &mut out).unwrap();
        let text = String::from_utf8(out).unwrap();
        assert!(text.contains("Jacobian Φ_v pattern"), "{name}");
    }
}

/// The annotated example of docs/model-format.md is a valid model: it checks (1 DOF, 1 driver)
/// and runs, and its slider follows the planar slider-crank closed form
/// x = a cos θ + √(l² − a² sin² θ) with a = 0.1, l = 0.3, θ = t.
#[test]
fn documented_example_runs() {
    let doc = std::fs::read_to_string(
        PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../docs/model-format.md"),
    )
    .unwrap();
    let start = doc.find("```toml\n").unwrap() + 8;
    let end = start + doc[start..].find("```").unwrap();
    let dir = out_dir("doc");
    std::fs::create_dir_all(&dir).unwrap();
    let file = dir.join("doc.toml");
    std::fs::write(&file, &doc[start..end]).unwrap();
    let mut out = Vec::new();
    cardan_model::check::check(&file, &mut out).unwrap();
    let text = String::from_utf8(out).unwrap();
    assert!(
        text.contains("degrees of freedom: 1") && text.contains(": ok"),
        "{text}"
    );
    let o = run_model(&file, Some(&dir.join("out")), false).unwrap();
    assert!(o.error.is_none());
    let b = o.results.point("slider", "B").unwrap();
    let mut err = 0.0f64;
    for (k, &t) in o.results.times.iter().enumerate() {
        let x = 0.1 * t.cos() + (0.09 - 0.01 * t.sin().powi(2)).sqrt();
        err = err.max((b.position[k] - Vector3::new(x, 0.0, 0.0)).amax());
    }
    assert!(err < 1e-10, "{err}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// A long run goes through the path that drives the progress bar: its results must be those of
/// the plain run (same times, joint angles continued over turns).
#[test]
fn progress_run_equals_plain_run() {
    let text = std::fs::read_to_string(example("slider_crank"))
        .unwrap()
        .replace("t_end = 1.0\nsteps = 200", "t_end = 2.5\nsteps = 2500");
    let dir = out_dir("chunked");
    std::fs::create_dir_all(&dir).unwrap();
    let file = dir.join("long.toml");
    std::fs::write(&file, text).unwrap();
    let chunked = run_model(&file, Some(&dir.join("a")), true).unwrap();
    let single = run_model(&file, Some(&dir.join("b")), false).unwrap();
    let (a, b) = (&chunked.results, &single.results);
    // Both keep the same decimated copy (every 2nd frame) for the plots; the CSVs hold all.
    assert_eq!(chunked.summary.steps, 2501);
    assert_eq!(a.len(), 1251);
    assert_eq!(a.times.len(), b.times.len());
    assert!(a
        .times
        .iter()
        .zip(&b.times)
        .all(|(x, y)| (x - y).abs() < 1e-12));
    let (ja, jb) = (a.joint("crank_pin").unwrap(), b.joint("crank_pin").unwrap());
    for k in 0..a.len() {
        assert!((ja.values[k][0] - jb.values[k][0]).abs() < 1e-9, "step {k}");
        let (pa, pb) = (
            a.point("slider", "C").unwrap(),
            b.point("slider", "C").unwrap(),
        );
        assert!((pa.position[k] - pb.position[k]).amax() < 1e-9);
        assert!((pa.acceleration[k] - pb.acceleration[k]).amax() < 1e-6);
    }
    assert!((ja.values[1250][0] - 5.0 * PI).abs() < 1e-9);
    let _ = std::fs::remove_dir_all(&dir);
}

/// `cardan eval --format json` (issue 28): every float reads back bit for bit to the value the
/// library computed, and the rows and columns are mapped to elements, primitives, bodies and
/// coordinates.
#[test]
fn eval_json_round_trips_every_float_exactly() {
    use cardan_model::eval::{evaluate, COORDINATES};
    for name in ["slider_crank", "bricard", "universal_drive"] {
        let out = std::process::Command::new(env!("CARGO_BIN_EXE_cardan"))
            .args(["eval", "--format", "json", "--t", "0.3"])
            .arg(example(name))
            .output()
            .unwrap();
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
        let (p, want) = evaluate(&example(name), Some(0.3)).unwrap();
        let floats = |key: &str| -> Vec<f64> {
            v[key]
                .as_array()
                .unwrap()
                .iter()
                .map(|x| x.as_f64().unwrap())
                .collect()
        };
        let bits = |a: &[f64]| a.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
        assert_eq!(bits(&floats("phi")), bits(&want.phi), "{name}: Φ");
        assert_eq!(bits(&floats("nu")), bits(&want.nu), "{name}: ν");
        assert_eq!(bits(&floats("gamma")), bits(&want.gamma), "{name}: γ#");
        let jac = v["jacobian"].as_array().unwrap();
        assert_eq!(jac.len(), want.jacobian.len());
        for (got, &(r, c, x)) in jac.iter().zip(&want.jacobian) {
            assert_eq!(got[0].as_u64(), Some(r as u64));
            assert_eq!(got[1].as_u64(), Some(c as u64));
            assert_eq!(
                got[2].as_f64().unwrap().to_bits(),
                x.to_bits(),
                "{name}: Φ_v[{r},{c}]"
            );
        }
        // Row and column maps.
        let rows = v["rows"].as_array().unwrap();
        assert_eq!(rows.len(), p.model.num_equations());
        for (r, row) in rows.iter().enumerate() {
            let eq = p.model.equation(r).unwrap();
            assert_eq!(row["element"], eq.element.as_str());
            assert_eq!(row["primitive"], eq.primitive);
            assert_eq!(row["local_row"], eq.local_row);
        }
        let cols = v["columns"].as_array().unwrap();
        assert_eq!(cols.len(), p.model.num_unknowns());
        for (c, col) in cols.iter().enumerate() {
            assert_eq!(col["body"], p.model.bodies()[c / 6].name.as_str());
            assert_eq!(col["coordinate"], COORDINATES[c % 6]);
        }
        let t = v["t"].as_f64().unwrap();
        assert_eq!(t, 0.3);
    }
}

/// Runs an example and reads one of its tables (before the output directory is removed).
fn run_with_table(name: &str, table: &str) -> (Prepared, Results, Vec<String>, Vec<Vec<f64>>) {
    let dir = out_dir(&format!("{name}-{table}"));
    let o = run_model(&example(name), Some(&dir), false).expect("example runs");
    assert!(o.error.is_none(), "{name}: {:?}", o.error);
    let csv = std::fs::read_to_string(dir.join(format!("{table}.csv"))).unwrap();
    assert!(
        dir.join(format!("{table}.svg")).exists(),
        "{name}: {table}.svg"
    );
    let (header, rows) = cardan_model::table::parse_csv(&csv).unwrap();
    let _ = std::fs::remove_dir_all(&dir);
    (o.prepared, o.results, header, rows)
}

fn column(header: &[String], rows: &[Vec<f64>], name: &str) -> Vec<f64> {
    let k = header
        .iter()
        .position(|h| h == name)
        .unwrap_or_else(|| panic!("no column {name} in {header:?}"));
    rows.iter().map(|r| r[k]).collect()
}

/// The two-stage gear train: the output turns exactly 1/6 as far as the input over its 10
/// turns; each mesh's torques are in the ratio of its radii and do no work; the tooth force is
/// the torque on gear j over its pitch radius; the motor torque drives the reflected inertias
/// and the load.
#[test]
fn gear_train_ratio_and_tooth_forces() {
    let (_, r, h, rows) = run_with_table("gear_train", "coupler_efforts");
    run_example("gear_train");
    let q = |j: &str, k: usize| r.joint(j).unwrap().values[k][0];
    let last = r.times.len() - 1;
    assert!((q("input_shaft", last) - 20.0 * PI).abs() < 1e-9);
    let mut worst = 0.0f64;
    for k in 0..r.times.len() {
        worst = worst.max((q("output_shaft", k) - q("input_shaft", k) / 6.0).abs());
        worst = worst.max((q("counter_shaft", k) + q("input_shaft", k) / 3.0).abs());
    }
    assert!(worst < 1e-9, "ratio error {worst:e}");
    // θ̈_in = 10π; J and radii of the example.
    let a_in = 10.0 * PI;
    let (j_in, j_c, j_out, load) = (6e-5, 2.2e-3, 1.1e-3, 3.0);
    let (a_c, a_out) = (-a_in / 3.0, a_in / 6.0);
    let t1_c = column(&h, &rows, "stage1.counter_shaft.torque [N m]");
    let t1_in = column(&h, &rows, "stage1.input_shaft.torque [N m]");
    let f1 = column(&h, &rows, "stage1.tooth_force [N]");
    let t2_out = column(&h, &rows, "stage2.output_shaft.torque [N m]");
    let f2 = column(&h, &rows, "stage2.tooth_force [N]");
    for k in 0..rows.len() {
        // Output gear: mesh torque = J θ̈ + load.
        assert!(
            (t2_out[k] - (j_out * a_out + load)).abs() < 1e-9,
            "{}",
            t2_out[k]
        );
        assert!((f2[k] - t2_out[k] / 0.05).abs() < 1e-9);
        // No work: Q_in θ̇_in + Q_c θ̇_c = 0 with θ̇_c = −θ̇_in / 3.
        assert!((t1_in[k] - t1_c[k] / 3.0).abs() < 1e-9);
        assert!((f1[k] - t1_c[k] / 0.06).abs() < 1e-9);
    }
    // Counter shaft: the two meshes' torques on it sum to J_c θ̈_c.
    let t2_c = column(&h, &rows, "stage2.counter_shaft.torque [N m]");
    for k in 0..rows.len() {
        assert!((t1_c[k] + t2_c[k] - j_c * a_c).abs() < 1e-9);
    }
    // Motor: J_in θ̈_in minus the mesh torque on the input angle.
    let (_, _, hd, rd) = run_with_table("gear_train", "driver_efforts");
    let motor = column(&hd, &rd, "motor.torque [N m]");
    for k in 0..rd.len() {
        assert!(
            (motor[k] - (j_in * a_in - t1_in[k])).abs() < 1e-9,
            "{}",
            motor[k]
        );
    }
}

/// The screw jack: the platform rises pitch × turns; the thread's axial force carries the
/// platform's weight (constant speed) and the crank torque is m g · pitch / 2π.
#[test]
fn screw_jack_advance_and_thread_force() {
    let (_, r, h, rows) = run_with_table("screw_jack", "coupler_efforts");
    run_example("screw_jack");
    let s = &r.joint("guide").unwrap().values;
    let last = r.times.len() - 1;
    let (pitch, turns, weight) = (0.005, 8.0, 60.0 * 9.81);
    assert!((s[last][0] - s[0][0] - pitch * turns).abs() < 1e-12);
    let axial = column(&h, &rows, "thread.axial_force [N]");
    let (_, _, hd, rd) = run_with_table("screw_jack", "driver_efforts");
    let crank = column(&hd, &rd, "crank.torque [N m]");
    for k in 0..rows.len() {
        assert!((axial[k] - weight).abs() < 1e-9, "{}", axial[k]);
        assert!(
            (crank[k] - weight * pitch / (2.0 * PI)).abs() < 1e-9,
            "{}",
            crank[k]
        );
    }
}

/// The steering: the rack's slide is −r θ + c of the column angle at every frame; the knuckles
/// turn both ways; finite differences confirm velocities and accelerations.
#[test]
fn rack_pinion_steering_follows_the_pinion() {
    let (p, r) = run_example("rack_pinion_steering");
    let radius = 0.008;
    let s = |k: usize| r.joint("rack_guide").unwrap().values[k][0];
    let th = |k: usize| r.joint("steering_column").unwrap().values[k][0];
    let c = s(0) + radius * th(0);
    for k in 0..r.times.len() {
        assert!((s(k) + radius * th(k) - c).abs() < 1e-12, "frame {k}");
    }
    let left = &r.joint("kingpin_left").unwrap().values;
    let (lo, hi) = left
        .iter()
        .fold((f64::MAX, f64::MIN), |(a, b), v| (a.min(v[0]), b.max(v[0])));
    assert!(lo < -0.4 && hi > 0.4, "knuckle range {lo}..{hi}");
    check_fd("rack_pinion_steering", &p, 400, 1e-2, 1.0);
}
/// joint_velocities.csv and joint_accelerations.csv (the exact rates of the joint coordinates)
/// against central differences of joints.csv and of the rates, on kinematic examples of many
/// joint kinds, and against the body quantities on the slider-crank (crank rate 2π, slide rate =
/// the slider's ẋ).
#[test]
fn joint_rates_match_differences_of_the_joint_coordinates() {
    for name in [
        "slider_crank",
        "bennett",
        "cv_driveline",
        "wobble_plate_pump",
        "universal_drive",
        "spatial_fourbar_cylindrical",
    ] {
        let (_, r) = run_example(name);
        let h = r.times[1] - r.times[0];
        let (mut ev, mut ea, mut scale) = (0.0f64, 0.0f64, 1.0f64);
        for j in &r.joints {
            assert_eq!(j.rates.len(), r.len(), "{name}");
            assert_eq!(j.accelerations.len(), r.len(), "{name}");
            for q in 0..j.coordinates.len() {
                for k in 1..r.len() - 1 {
                    let fd = (j.values[k + 1][q] - j.values[k - 1][q]) / (2.0 * h);
                    let fa = (j.rates[k + 1][q] - j.rates[k - 1][q]) / (2.0 * h);
                    ev = ev.max((fd - j.rates[k][q]).abs());
                    ea = ea.max((fa - j.accelerations[k][q]).abs());
                    scale = scale.max(j.accelerations[k][q].abs());
                }
            }
        }
        eprintln!(
            "{name}: |ċ − Δc/2h| ≤ {ev:.1e}, |c̈ − Δċ/2h| ≤ {ea:.1e} (h = {h}, max |c̈| {scale:.1e})"
        );
        // Central differences err by h²/6 · (third derivative): small against the scale.
        assert!(ev < 1e-3 * scale && ea < 1e-2 * scale, "{name}: {ev} {ea}");
    }
    let (_, r) = run_example("slider_crank");
    let (crank, slide) = (r.joint("crank_pin").unwrap(), r.joint("slide").unwrap());
    let slider = r.body("slider").unwrap();
    for k in 0..r.len() {
        assert!((crank.rates[k][0] - 2.0 * PI).abs() < 1e-9);
        assert!((slide.rates[k][0] - slider.r_dot[k].x).abs() < 1e-12);
        assert!((slide.accelerations[k][0] - slider.r_ddot[k].x).abs() < 1e-10);
    }
}

/// `cardan eval --format csv`: one line per equation with its element and primitive, Φ, ν, γ#
/// and its dense row of Φ_v; every float reads back to the same f64 as the evaluation's.
#[test]
fn eval_csv_round_trips_every_float_exactly() {
    use cardan_model::eval::evaluate;
    for name in ["slider_crank", "wobble_plate_pump"] {
        let out = std::process::Command::new(env!("CARGO_BIN_EXE_cardan"))
            .args(["eval", "--format", "csv", "--t", "0.3"])
            .arg(example(name))
            .output()
            .unwrap();
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        let text = String::from_utf8(out.stdout).unwrap();
        let (_, want) = evaluate(&example(name), Some(0.3)).unwrap();
        let mut lines = text.lines();
        let header: Vec<&str> = lines.next().unwrap().split(',').collect();
        assert_eq!(
            header[..8],
            [
                "row",
                "element",
                "kind",
                "primitive",
                "local_row",
                "phi",
                "nu",
                "gamma"
            ]
        );
        assert_eq!(header.len(), 8 + want.columns.len());
        let mut dense = vec![vec![0.0; want.columns.len()]; want.rows.len()];
        for &(r, c, v) in &want.jacobian {
            dense[r][c] += v;
        }
        let rows: Vec<Vec<&str>> = lines.map(|l| l.split(',').collect()).collect();
        assert_eq!(rows.len(), want.rows.len());
        for (k, f) in rows.iter().enumerate() {
            assert_eq!(f[1], want.rows[k].element);
            assert_eq!(f[3], want.rows[k].primitive);
            let num = |s: &str| s.parse::<f64>().unwrap().to_bits();
            assert_eq!(num(f[5]), want.phi[k].to_bits(), "{name} Φ[{k}]");
            assert_eq!(num(f[6]), want.nu[k].to_bits(), "{name} ν[{k}]");
            assert_eq!(num(f[7]), want.gamma[k].to_bits(), "{name} γ#[{k}]");
            for (c, x) in dense[k].iter().enumerate() {
                assert_eq!(num(f[8 + c]), x.to_bits(), "{name} Φ_v[{k},{c}]");
            }
        }
    }
}
