//! The report of a modal run animates its modes (issue 26): `index.html` embeds every mode
//! (label, frequency, damping ratio, amplitude) with the shape of each body as the increment
//! [δr; δp] of its body coordinates, equal to `modes.csv` and `mode_shapes.csv` of the same
//! run, about the rest pose of `bodies.csv`; the pose drawn at a quarter period is q₀ + a φ_k
//! with unit Euler parameters, and the default amplitude moves the farthest point by a tenth of
//! the model's size. On the dense path (the bundled example) and the sparse one (100 rods).

mod common;

use cardan_model::table::parse_csv;
use common::{cardan, scratch};
use nalgebra::{Vector3, Vector4};
use std::f64::consts::PI;
use std::path::{Path, PathBuf};

/// A CSV output as (header, rows).
fn csv(dir: &Path, name: &str) -> (Vec<String>, Vec<Vec<f64>>) {
    parse_csv(&std::fs::read_to_string(dir.join(name)).unwrap()).unwrap()
}

fn col(h: &[String], name: &str) -> usize {
    h.iter()
        .position(|c| c == name)
        .unwrap_or_else(|| panic!("no column {name} in {h:?}"))
}

/// The page's data (`<script id="meta">`).
fn meta(dir: &Path) -> serde_json::Value {
    let html = std::fs::read_to_string(dir.join("index.html")).unwrap();
    let start = "<script id=\"meta\" type=\"application/json\">";
    let at = html.find(start).expect("the page's data") + start.len();
    let end = at + html[at..].find("</script>").unwrap();
    serde_json::from_str(&html[at..end]).unwrap()
}

fn f(v: &serde_json::Value) -> f64 {
    v.as_f64().unwrap_or_else(|| panic!("not a number: {v}"))
}

fn vec_of(v: &serde_json::Value) -> Vec<f64> {
    v.as_array().unwrap().iter().map(f).collect()
}

/// Runs `model` into a scratch directory; returns the output directory.
fn run(model: &Path) -> PathBuf {
    let dir = scratch("modal-report");
    let o = cardan(
        &["run", model.to_str().unwrap(), "-o", "out", "--quiet"],
        &dir,
    );
    assert_eq!(o.code, 0, "{}", o.stderr);
    dir.join("out")
}

/// The page's modes equal `modes.csv` and `mode_shapes.csv` (δr, and δp = ½ Gᵀ(p₀) δθ at the
/// rest Euler parameters p₀ of `bodies.csv`), for the moving `bodies`; the ground's shape and
/// rest pose are null. Returns the modes' list.
fn check_modes_match_the_tables(out: &Path, bodies: &[String]) -> serde_json::Value {
    let m = meta(out);
    let modes = &m["modes"];
    let (hm, rows) = csv(out, "modes.csv");
    let (hs, shapes) = csv(out, "mode_shapes.csv");
    let (hb, rest) = csv(out, "bodies.csv");
    let list = modes["list"].as_array().unwrap();
    assert_eq!(list.len(), rows.len());
    assert_eq!(modes["computed"].as_u64(), Some(rows.len() as u64));
    assert_eq!(modes["rest"].as_array().unwrap().len(), bodies.len() + 1);
    assert!(modes["rest"][bodies.len()].is_null(), "the ground");
    for (k, b) in bodies.iter().enumerate() {
        let q0 = &modes["rest"][k];
        for (c, ax) in ["x", "y", "z"].iter().enumerate() {
            assert_eq!(f(&q0[0][c]), rest[0][col(&hb, &format!("{b}.r.{ax} [m]"))]);
        }
        for (c, e) in ["e0", "e1", "e2", "e3"].iter().enumerate() {
            assert_eq!(f(&q0[1][c]), rest[0][col(&hb, &format!("{b}.p.{e} [-]"))]);
        }
    }
    for (i, (mode, row)) in list.iter().zip(&rows).enumerate() {
        assert_eq!(mode["number"].as_u64(), Some(i as u64 + 1));
        assert_eq!(f(&mode["frequency"]), row[col(&hm, "frequency [Hz]")]);
        assert_eq!(
            f(&mode["damping_ratio"]),
            row[col(&hm, "damping_ratio [-]")]
        );
        let rigid = row[col(&hm, "kind [-]")] == 1.0;
        assert_eq!(mode["kind"] == "rigid", rigid);
        let label = mode["label"].as_str().unwrap();
        assert_eq!(label.contains("rigid"), rigid, "{label}");
        assert!(label.starts_with(&format!("{} · ", i + 1)), "{label}");
        let shape = mode["shape"].as_array().unwrap();
        assert_eq!(shape.len(), bodies.len() + 1);
        assert!(shape[bodies.len()].is_null(), "the ground does not move");
        for (k, b) in bodies.iter().enumerate() {
            let phi = vec_of(&shape[k]);
            assert_eq!(phi.len(), 7);
            let s = &shapes[i];
            let get = |name: String| s[col(&hs, &name)];
            let dr = Vector3::from_fn(|c, _| get(format!("{b}.dr.{} [m]", ["x", "y", "z"][c])));
            let dth =
                Vector3::from_fn(|c, _| get(format!("{b}.dtheta.{} [rad]", ["x", "y", "z"][c])));
            let dp = Vector4::from_fn(|c, _| get(format!("{b}.dp.e{c} [-]")));
            let p0 = Vector4::from_fn(|c, _| f(&modes["rest"][k][1][c]));
            // δp = ½ Gᵀ δθ, tangent, and back: δθ = 2 G δp.
            let want_dp = 0.5 * cardan_eulerparam::g(&p0).transpose() * dth;
            assert!((dp - want_dp).amax() < 1e-12, "{b}: {dp} vs {want_dp}");
            assert!(p0.dot(&dp).abs() < 1e-12);
            assert!((2.0 * cardan_eulerparam::g(&p0) * dp - dth).amax() < 1e-12);
            // The page: single precision.
            for c in 0..3 {
                assert!((phi[c] - dr[c]).abs() <= 1e-6 * (1.0 + dr[c].abs()), "{b}");
            }
            for c in 0..4 {
                assert!(
                    (phi[3 + c] - dp[c]).abs() <= 1e-6 * (1.0 + dp[c].abs()),
                    "{b}"
                );
            }
        }
    }
    modes.clone()
}

/// Global position of body point `s` at pose (r, p).
fn at(r: &Vector3<f64>, p: &Vector4<f64>, s: &Vector3<f64>) -> Vector3<f64> {
    r + cardan_eulerparam::a(p) * s
}

#[test]
fn modal_report_animates_each_mode_about_the_rest_pose() {
    let model =
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/turntable_pendulum_modal.toml");
    let out = run(&model);
    let bodies = ["arm".to_string(), "bob".to_string()];
    let modes = check_modes_match_the_tables(&out, &bodies);
    let list = modes["list"].as_array().unwrap();
    assert_eq!(list.len(), 2);
    assert_eq!(list[0]["kind"], "rigid");
    assert_eq!(list[0]["label"], "1 · rigid");
    // The compound pendulum √(m g c / I_pivot) / 2π (the swing does not turn the arm).
    let want = (0.5f64 * 9.81 * 0.3 / (0.015 + 0.5 * 0.09)).sqrt() / (2.0 * PI);
    let got = f(&list[1]["frequency"]);
    assert!((got - want).abs() < 1e-6 * want, "{got} vs {want}");
    assert_eq!(list[1]["label"], "2 · 0.7882 Hz · ζ 0.0000");
    let html = std::fs::read_to_string(out.join("index.html")).unwrap();
    assert!(html.contains("<option value=\"1\">2 · 0.7882 Hz · ζ 0.0000</option>"));
    assert!(html.contains("id=\"amplitude\""));

    // Body points (body coordinates) of the model, the origin included.
    let points = [
        vec![
            Vector3::zeros(),
            Vector3::new(-0.25, 0.0, 0.0),
            Vector3::new(0.25, 0.0, 0.0),
        ],
        vec![
            Vector3::zeros(),
            Vector3::new(0.0, 0.3, 0.0),
            Vector3::new(0.0, -0.3, 0.0),
        ],
    ];
    let extent = f(&meta(&out)["extent"]);
    for mode in list {
        let a = f(&mode["amplitude"]);
        let s = a * (2.0 * PI * 0.25).sin();
        let mut largest: f64 = 0.0;
        for (k, pts) in points.iter().enumerate() {
            let q0 = &modes["rest"][k];
            let r0 = Vector3::from_fn(|c, _| f(&q0[0][c]));
            let p0 = Vector4::from_fn(|c, _| f(&q0[1][c]));
            let phi = vec_of(&mode["shape"][k]);
            let inc = cardan_report::BodyIncrement {
                dr: [phi[0], phi[1], phi[2]],
                dp: [phi[3], phi[4], phi[5], phi[6]],
            };
            let (r, p) = cardan_report::mode_pose(&r0.into(), &p0.into(), &inc, s);
            let (r, p) = (Vector3::from(r), Vector4::from(p));
            // q₀ + a φ: the position exactly, the Euler parameters up to their unit norm.
            let dr = Vector3::new(phi[0], phi[1], phi[2]);
            let dp = Vector4::new(phi[3], phi[4], phi[5], phi[6]);
            assert!((r - (r0 + a * dr)).amax() < 1e-14, "{r} vs {}", r0 + a * dr);
            let q = p0 + a * dp;
            assert!((p.norm() - 1.0).abs() < 1e-15);
            assert!((p - q / q.norm()).amax() < 1e-15);
            for pt in pts {
                largest = largest.max((at(&r, &p, pt) - at(&r0, &p0, pt)).norm());
            }
        }
        // A tenth of the model's size (to second order in the rotation a|δθ|).
        let ratio = largest / extent;
        println!(
            "mode {}: a = {a:.4e}, largest motion {ratio:.4} L",
            mode["number"]
        );
        assert!((ratio - 0.1).abs() < 0.005, "{ratio}");
    }
    let _ = std::fs::remove_dir_all(out.parent().unwrap());
}

/// A hanging chain of `n` rods (length 0.1 m, 0.1 kg) on revolutes about z, its lowest
/// `modes` modes asked: from 100 bodies on, the sparse path.
fn chain(n: usize, modes: usize) -> String {
    let mut s = String::from(
        "[model]\nname = \"chain\"\nunits = \"SI\"\ngravity = [0.0, -9.81, 0.0]\n\n\
         [ground]\npoints = { O = [0.0, 0.0, 0.0] }\nvectors = { z = [0.0, 0.0, 1.0] }\n",
    );
    for k in 0..n {
        s.push_str(&format!(
            "\n[[body]]\nname = \"b{k}\"\nmass = 0.1\ninertia = {{ diag = [8.3333e-5, 1e-6, \
             8.3333e-5] }}\nposition = [0.0, {}, 0.0]\npoints = {{ top = [0.0, 0.05, 0.0], \
             bottom = [0.0, -0.05, 0.0] }}\nvectors = {{ z = [0.0, 0.0, 1.0] }}\n",
            -0.1 * (k as f64 + 0.5)
        ));
        let (bi, pi) = if k == 0 {
            ("ground".to_string(), "O")
        } else {
            (format!("b{}", k - 1), "bottom")
        };
        s.push_str(&format!(
            "\n[[joint]]\nname = \"j{k}\"\ntype = \"revolute\"\nbody_i = \"{bi}\"\npoint_i = \
             \"{pi}\"\naxis_i = \"z\"\nbody_j = \"b{k}\"\npoint_j = \"top\"\naxis_j = \"z\"\n"
        ));
    }
    s.push_str(&format!(
        "\n[analysis]\nkind = \"modal\"\nmodes = {modes}\n"
    ));
    s
}

#[test]
fn sparse_path_modes_reach_the_report() {
    let n = cardan_dynamics::SPARSE_MIN_BODIES;
    let dir = scratch("modal-report-sparse");
    let model = dir.join("chain.toml");
    std::fs::write(&model, chain(n, 3)).unwrap();
    let out = run(&model);
    let bodies: Vec<String> = (0..n).map(|k| format!("b{k}")).collect();
    let modes = check_modes_match_the_tables(&out, &bodies);
    let list = modes["list"].as_array().unwrap();
    assert_eq!(list.len(), 3);
    let freqs: Vec<f64> = list.iter().map(|m| f(&m["frequency"])).collect();
    assert!(
        freqs[0] > 0.0 && freqs[0] < freqs[1] && freqs[1] < freqs[2],
        "{freqs:?}"
    );
    for m in list {
        assert!(f(&m["amplitude"]) > 0.0);
    }
    let _ = std::fs::remove_dir_all(&dir);
}
