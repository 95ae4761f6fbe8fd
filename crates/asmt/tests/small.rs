//! Joint kinds the ten testapp files do not use, against OndselSolver: small assemblies written
//! for these tests and solved once by OndselSolver (pyondsel 0.0.3; `tests/data/small/README.md`
//! says how). Compared per part at every output time: the part-frame origin and rotation matrix
//! (≤ 1e-9 of the mechanism's size), velocity, ω, acceleration, α (≤ 1e-8 of dimensionally
//! consistent scales, as `tests/ondsel.rs`).

use cardan_asmt::series::{Item, TimeSeries};
use cardan_asmt::solved;
use cardan_eulerparam::p_from_euler_123;
use cardan_mechanism::KinematicOptions;
use nalgebra::Vector3;
use std::path::PathBuf;

fn data(name: &str) -> String {
    let p = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data/small")
        .join(name);
    std::fs::read_to_string(&p).unwrap_or_else(|e| panic!("{}: {e}", p.display()))
}

fn v3(item: &Item, labels: [&str; 3], k: usize) -> Vector3<f64> {
    Vector3::new(
        item.row(labels[0]).unwrap()[k],
        item.row(labels[1]).unwrap()[k],
        item.row(labels[2]).unwrap()[k],
    )
}

/// Largest relative differences (pose, rates) of cardan's solution of `name` from OndselSolver's.
fn compare(name: &str) -> (f64, f64) {
    let (doc, import) =
        cardan_asmt::load(&data(&format!("{name}.asmt"))).unwrap_or_else(|e| panic!("{name}: {e}"));
    let model = import
        .builder()
        .build()
        .unwrap_or_else(|e| panic!("{name}: {e}"));
    let s = import.settings.unwrap();
    let results = model
        .run_kinematics(&KinematicOptions::new(s.t_start, s.t_end, s.steps()))
        .unwrap_or_else(|e| panic!("{name}: {e}"));
    let ours = solved::time_series(&doc, &import, &results);
    let theirs: TimeSeries = cardan_asmt::read_time_series(&data(&format!("{name}.solved.asmt")))
        .unwrap()
        .unwrap();
    assert_eq!(ours.times.len(), theirs.times.len(), "{name}: frames");
    let size = doc.size().max(1.0);
    let rates = [
        ["VX", "VY", "VZ"],
        ["OmegaX", "OmegaY", "OmegaZ"],
        ["AX", "AY", "AZ"],
        ["AlphaX", "AlphaY", "AlphaZ"],
    ];
    let mut peak = [0.0f64; 4];
    for item in theirs.items.iter().filter(|i| i.kind == "PartSeries") {
        for k in 0..theirs.times.len() {
            for (g, l) in rates.iter().enumerate() {
                peak[g] = peak[g].max(v3(item, *l, k).norm());
            }
        }
    }
    // Dimensionally consistent scales (a rotor at constant speed has α = 0 up to rounding):
    // V = max(|v|, |ω| L), A = max(|a|, |α| L, V²/L); ω and α relative to V/L and A/L.
    let v = peak[0].max(peak[1] * size);
    let a = peak[2].max(peak[3] * size).max(v * v / size);
    let scale = [v, v / size, a, a / size];
    let (mut pose, mut rate): (f64, f64) = (0.0, 0.0);
    for item in ours.items.iter().filter(|i| i.kind == "PartSeries") {
        let r = theirs.item(&item.path).unwrap();
        for k in 0..theirs.times.len() {
            let d = v3(item, ["X", "Y", "Z"], k) - v3(r, ["X", "Y", "Z"], k);
            pose = pose.max(d.norm() / size);
            let a = |i: &Item| {
                let b = v3(i, ["Bryantx", "Bryanty", "Bryantz"], k);
                p_from_euler_123(b.x, b.y, b.z).unwrap().a()
            };
            pose = pose.max((a(item) - a(r)).abs().max());
            for (g, l) in rates.iter().enumerate() {
                rate = rate.max((v3(item, *l, k) - v3(r, *l, k)).norm() / scale[g]);
            }
        }
    }
    println!("{name}: pose {pose:.2e}, rates {rate:.2e}");
    (pose, rate)
}

/// An AngleJoint at 60° between two shafts, imported as cardan's `cone` joint (the same row,
/// z_iᵀz_j − cos θ). With the former `angle` joint (z_j in a plane through x_i) the poses differed
/// by 6.2e-3 (rates 5.3e-2), since z_B leaves that plane while staying on the cone.
#[test]
fn angle_joint() {
    let (pose, rate) = compare("angle");
    assert!(
        pose <= 1e-9 && rate <= 1e-8,
        "pose {pose:.2e}, rates {rate:.2e}"
    );
}

/// A ConstantVelocityJoint between shafts at 30°: OndselSolver's facing markers
/// (x_Iᵀy_J + y_Iᵀx_J) imported with marker J's z reversed (cardan's x_iᵀy_j − y_iᵀx_j).
#[test]
fn constant_velocity_joint() {
    let (pose, rate) = compare("cv");
    assert!(
        pose <= 1e-9 && rate <= 1e-8,
        "pose {pose:.2e}, rates {rate:.2e}"
    );
}

/// A ScrewJoint whose two parts are held by one cylindrical joint (no common third body): a
/// one-joint cardan screw, s = (pitch/2π) θ + c.
#[test]
fn screw_on_one_cylindrical_joint() {
    let (pose, rate) = compare("screw_cyl");
    assert!(
        pose <= 1e-9 && rate <= 1e-8,
        "pose {pose:.2e}, rates {rate:.2e}"
    );
}
