//! `kind = "modal"` on the sparse path (100 moving bodies and more) through `cardan run`: a row of
//! 100 pendulums coupled by springs, its lowest modes (`[analysis] modes = 4`) and every
//! eigenvalue of its written linearization against the closed form, the files written, and
//! `modes` refused where it cannot apply.

use cardan_model::table::parse_csv;
use nalgebra::DMatrix;
use std::f64::consts::PI;
use std::fmt::Write as _;

mod common;
use common::run_text;

const G: f64 = 9.81;
/// Pendulums (the sparse path's switch point).
const N: usize = 100;
/// Mass (kg), inertia about the centre of mass (kg m²), pin to centre of mass (m), pin spacing
/// (m), spring stiffness (N/m).
const M: f64 = 1.0;
const J: f64 = 0.01;
const L: f64 = 0.5;
const A: f64 = 1.0;
const K: f64 = 40.0;

/// `n` pendulums hanging from pins `A` apart along x, neighbouring centres of mass joined by
/// springs at their free length `A`; `analysis` is the `[analysis]` table's body.
fn pendulums(n: usize, analysis: &str) -> String {
    let mut s = String::from(
        "[model]\nname = \"row\"\ngravity = [0.0, -9.81, 0.0]\n\n[ground]\n\
         vectors = { z = [0.0, 0.0, 1.0] }\npoints = { ",
    );
    let pins: Vec<String> = (0..n)
        .map(|i| format!("O{i} = [{}, 0.0, 0.0]", A * i as f64))
        .collect();
    s.push_str(&pins.join(", "));
    s.push_str(" }\n");
    for i in 0..n {
        let _ = write!(
            s,
            "\n[[body]]\nname = \"p{i}\"\nmass = {M}\ninertia = {{ diag = [{J}, {J}, {J}] }}\n\
             position = [{}, {}, 0.0]\npoints = {{ O = [0.0, {L}, 0.0], C = [0.0, 0.0, 0.0] }}\n\
             vectors = {{ z = [0.0, 0.0, 1.0] }}\n\n[[joint]]\nname = \"pin{i}\"\n\
             type = \"revolute\"\nbody_i = \"ground\"\npoint_i = \"O{i}\"\naxis_i = \"z\"\n\
             body_j = \"p{i}\"\npoint_j = \"O\"\naxis_j = \"z\"\n",
            A * i as f64,
            -L
        );
    }
    for i in 0..n - 1 {
        let _ = write!(
            s,
            "\n[[force]]\nname = \"s{i}\"\ntype = \"spring_damper\"\nbody_i = \"p{i}\"\n\
             point_i = \"C\"\nbody_j = \"p{}\"\npoint_j = \"C\"\nstiffness = {K}\ndamping = 0.0\n",
            i + 1
        );
    }
    let _ = write!(s, "\n[analysis]\n{analysis}\n");
    s
}

/// ω_j² of the row hanging straight: (J + m l²) θ̈_i = −m g l θ_i − k l² (2θ_i − θ_{i−1} −
/// θ_{i+1}) with free ends, so ω_j² = (m g l + 2 k l² (1 − cos(jπ/n))) / (J + m l²).
fn exact(j: usize) -> f64 {
    let s = 1.0 - (j as f64 * PI / N as f64).cos();
    (M * G * L + 2.0 * K * L * L * s) / (J + M * L * L)
}

/// y = A x for triplets.
fn mul(e: &[(usize, usize, f64)], rows: usize, x: &DMatrix<f64>) -> DMatrix<f64> {
    let mut y = DMatrix::zeros(rows, x.ncols());
    for &(r, c, v) in e {
        for k in 0..x.ncols() {
            y[(r, k)] += v * x[(c, k)];
        }
    }
    y
}

/// The lowest 4 modes of the 100-pendulum row on the sparse path match the closed form; the
/// full matrices (M, C_t, K_t, Φ_v) and the reduced ones are written, and every eigenvalue of
/// the written K_r x = ω² M_r x (100 of them, the Lanczos iteration not involved) is the
/// closed form's; Φ_v N = 0; the state-space A is [0 I; −M_r⁻¹K_r −M_r⁻¹C_r].
#[test]
fn sparse_modal_run_writes_the_lowest_modes_and_the_linearized_model() {
    let analysis = "kind = \"modal\"\nmodes = 4\n\n[analysis.outputs]\njoints = [\"pin3\"]";
    let o = run_text("run", &pendulums(N, analysis));
    assert_eq!(o.code, 0, "{}", o.stderr);
    let out = o.dir.join("out");
    let text = std::fs::read_to_string(out.join("modes.csv")).unwrap();
    let (h, rows) = parse_csv(&text).unwrap();
    assert_eq!(rows.len(), 4, "modes = 4");
    let f = h.iter().position(|c| c == "frequency [Hz]").unwrap();
    for (j, row) in rows.iter().enumerate() {
        let want = exact(j).sqrt() / (2.0 * PI);
        assert!(
            (row[f] - want).abs() < 1e-8 * want,
            "mode {j}: {} vs {want}",
            row[f]
        );
    }
    let n = 6 * N;
    let (mf, k_full, c_full, phi) = (
        common::matrix_market_triplets(&out.join("lin_M_full.mtx")),
        common::matrix_market_triplets(&out.join("lin_K_full.mtx")),
        common::matrix_market_triplets(&out.join("lin_C_full.mtx")),
        common::matrix_market_triplets(&out.join("lin_Phi_v.mtx")),
    );
    for (what, (r, c, _)) in [("M", &mf), ("K", &k_full), ("C", &c_full)] {
        assert_eq!((*r, *c), (n, n), "{what}");
    }
    assert_eq!((phi.0, phi.1), (5 * N, n));
    assert!(mf.2.contains(&(0, 0, M)) && mf.2.contains(&(5, 5, J)), "M");
    assert!(c_full.2.is_empty(), "no dampers: C = 0");
    let basis = common::matrix_market_dense(&out.join("lin_N.mtx"));
    let mr = common::matrix_market_dense(&out.join("lin_M.mtx"));
    let kr = common::matrix_market_dense(&out.join("lin_K.mtx"));
    assert_eq!(basis.shape(), (n, N));
    assert!(mul(&phi.2, phi.0, &basis).amax() < 1e-10, "Φ_v N");
    let knr = basis.transpose() * mul(&k_full.2, n, &basis);
    assert!((knr - &kr).amax() < 1e-8 * kr.amax(), "K_r = NᵀKN");
    // M_r = I on the sparse path: K_r's eigenvalues are the ω².
    assert!(
        (&mr - DMatrix::<f64>::identity(N, N)).amax() < 1e-10,
        "M_r = I"
    );
    let mut w2: Vec<f64> = kr
        .clone()
        .symmetric_eigen()
        .eigenvalues
        .iter()
        .copied()
        .collect();
    w2.sort_by(f64::total_cmp);
    for (j, w) in w2.iter().enumerate() {
        assert!((w - exact(j)).abs() < 1e-6 * exact(j), "ω²_{j}: {w}");
    }
    let a = common::matrix_market_dense(&out.join("ss_A.mtx"));
    assert_eq!(a.shape(), (2 * N, 2 * N));
    assert!((a.view((N, 0), (N, N)) + &kr).amax() < 1e-8 * kr.amax());
    for f in [
        "ss_B.mtx",
        "ss_C.mtx",
        "ss_D.mtx",
        "state_space.txt",
        "mode_shapes.csv",
    ] {
        assert!(out.join(f).is_file(), "{f} not written");
    }
    let _ = std::fs::remove_dir_all(&o.dir);
}

/// `modes` must be a whole number from 1 to the model's unknowns (6 per moving body); the
/// refusal names the key's line.
#[test]
fn modes_is_refused_where_it_cannot_apply() {
    let n = 2;
    for (modes, want) in [
        ("0", "modes must be between 1 and 10000, got 0"),
        ("13", "modes = 13 is more than the model's 12 unknowns"),
        ("2.5", "modes"),
        ("\"four\"", "modes"),
    ] {
        let text = pendulums(n, &format!("kind = \"modal\"\nmodes = {modes}"));
        let line = text.lines().position(|l| l.starts_with("modes =")).unwrap() + 1;
        let o = run_text("run", &text);
        assert_eq!(o.code, 1, "modes = {modes}: {}", o.stderr);
        assert!(o.stderr.contains(want), "modes = {modes}: {}", o.stderr);
        assert!(
            o.stderr.contains(&format!("model.toml:{line}:")),
            "modes = {modes}: line {line} not named: {}",
            o.stderr
        );
    }
    let o = run_text("run", &pendulums(n, "kind = \"modal\"\nmodes = 12"));
    assert_eq!(o.code, 0, "{}", o.stderr);
}
