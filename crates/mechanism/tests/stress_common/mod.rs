//! Helpers shared by the stress suites (`tests/stress_*.rs`).
#![allow(dead_code)]

use cardan_mechanism::Results;

/// Proptest case count: `CARDAN_STRESS_CASES` if set (`cargo xtask stress`), else `default`
/// (the quick subset run by `cargo test`).
pub fn cases(default: u32) -> u32 {
    std::env::var("CARDAN_STRESS_CASES")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(default)
}

/// Every stored number of a run is finite.
pub fn results_finite(r: &Results) -> bool {
    let v3 = |v: &[nalgebra::Vector3<f64>]| v.iter().all(|x| x.iter().all(|c| c.is_finite()));
    let v4 = |v: &[nalgebra::Vector4<f64>]| v.iter().all(|x| x.iter().all(|c| c.is_finite()));
    r.times.iter().all(|t| t.is_finite())
        && r.residual.iter().all(|t| t.is_finite())
        && r.bodies.iter().all(|b| {
            v3(&b.r)
                && v4(&b.p)
                && v3(&b.r_dot)
                && v4(&b.p_dot)
                && v3(&b.omega)
                && v3(&b.omega_local)
                && v3(&b.r_ddot)
                && v4(&b.p_ddot)
                && v3(&b.omega_dot)
                && v3(&b.omega_dot_local)
        })
        && r.points
            .iter()
            .all(|p| v3(&p.position) && v3(&p.velocity) && v3(&p.acceleration))
        && r.joints
            .iter()
            .all(|j| j.values.iter().all(|v| v.iter().all(|c| c.is_finite())))
}
