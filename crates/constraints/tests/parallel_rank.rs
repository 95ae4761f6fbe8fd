//! The two-row parallel constraints keep rank 2 in every orientation.
//!
//! Body i turns through full turns about several axes; body j follows so that s_j = s_i
//! (A_j = A_i R(s'_i, β) A_off, s'_j = A_offᵀ s'_i) while also turning through a full turn β about
//! the common axis. At every configuration Φ = 0 and the 2 × 12 Jacobian Φ_v must have
//! σ_min / σ_max above a fixed bound, for s'_i along each coordinate axis and obliquely.
//! A frozen choice of two *global* rows of s̃_i s_j is checked to lose rank on the same sweep,
//! which shows the test can fail and why the body-frame selection exists.

use cardan_constraints::*;
use cardan_eulerparam::EulerParams;
use nalgebra::{Matrix2, Vector3};

fn rot(axis: Vector3<f64>, angle: f64) -> EulerParams {
    EulerParams::from_axis_angle(&axis, angle).unwrap()
}

/// σ_min / σ_max of a 2 × 12 matrix, from the eigenvalues of J Jᵀ.
fn sigma_ratio(rows: &[[f64; 6]], rows_j: &[[f64; 6]]) -> f64 {
    let row = |k: usize| -> Vec<f64> { rows[k].iter().chain(rows_j[k].iter()).copied().collect() };
    let (a, b) = (row(0), row(1));
    let dot = |x: &[f64], y: &[f64]| x.iter().zip(y).map(|(p, q)| p * q).sum::<f64>();
    let g = Matrix2::new(dot(&a, &a), dot(&a, &b), dot(&a, &b), dot(&b, &b));
    let e = g.symmetric_eigenvalues();
    (e.min().max(0.0) / e.max()).sqrt()
}

struct Sweep {
    s_i: Vector3<f64>,
    configs: Vec<(BodyState, BodyState, Vector3<f64>)>, // (i, j, s'_j)
}

fn sweep(s_i: Vector3<f64>, sp_i: Vector3<f64>, sp_j: Vector3<f64>) -> Sweep {
    let off = rot(Vector3::new(0.3, -0.5, 0.8), 0.7);
    let s_j = off.a().transpose() * s_i;
    let mut configs = Vec::new();
    for axis in [
        Vector3::x(),
        Vector3::y(),
        Vector3::z(),
        Vector3::new(1.0, 2.0, 3.0),
    ] {
        for a in 0..72 {
            let alpha = a as f64 * 5f64.to_radians();
            for b in 0..12 {
                let beta = b as f64 * 30f64.to_radians() + 0.1;
                let pi = rot(axis, alpha);
                let pj = pi.compose(&rot(s_i, beta)).compose(&off);
                let r_i = Vector3::new(0.2, -0.4, 1.1);
                // d = λ s_i with λ = 0.7 (for p2): place body j accordingly.
                let d = 0.7 * (pi.a() * s_i);
                let r_j = r_i + pi.a() * sp_i + d - pj.a() * sp_j;
                configs.push((
                    BodyState::at(r_i, *pi.as_vector()),
                    BodyState::at(r_j, *pj.as_vector()),
                    s_j,
                ));
            }
        }
    }
    Sweep { s_i, configs }
}

fn directions() -> Vec<Vector3<f64>> {
    vec![
        Vector3::x(),
        Vector3::y(),
        Vector3::z(),
        -Vector3::x(),
        Vector3::new(1.0, 1.0, 1.0).normalize(),
        Vector3::new(0.2, -0.9, 0.4).normalize(),
    ]
}

fn worst_ratio<C: Constraint>(sw: &Sweep, make: impl Fn(Vector3<f64>) -> C) -> f64 {
    let mut worst = f64::INFINITY;
    for (i, j, s_j) in &sw.configs {
        let c = make(*s_j);
        let x = BodyPair::new(i, j);
        let mut phi = [0.0; 2];
        c.phi(&x, 0.0, &mut phi);
        assert!(
            phi.iter().all(|v| v.abs() < 1e-12),
            "{}: configuration not on the constraint (Φ = {phi:?}) for s'_i = {:?}",
            c.name(),
            sw.s_i
        );
        let (mut ji, mut jj) = ([[0.0; 6]; 2], [[0.0; 6]; 2]);
        c.phi_v(&x, 0.0, &mut ji, &mut jj);
        worst = worst.min(sigma_ratio(&ji, &jj));
    }
    worst
}

#[test]
fn p1_two_row_forms_keep_rank_two_through_full_turns() {
    for s_i in directions() {
        let sw = sweep(s_i, Vector3::zeros(), Vector3::zeros());
        let frame = cardan_eulerparam::frame_from_axis(&s_i).unwrap();
        let (f, g) = (frame.column(0).into_owned(), frame.column(1).into_owned());
        let perp = worst_ratio(&sw, |s_j| P1Perp::new(f, g, s_j));
        let select = worst_ratio(&sw, |s_j| P1Select::new(s_i, s_j));
        assert!(
            perp > 0.99,
            "p1_perp lost rank for s'_i = {s_i:?}: σmin/σmax = {perp}"
        );
        assert!(
            select > 0.55,
            "p1_select lost rank for s'_i = {s_i:?}: σmin/σmax = {select}"
        );
    }
}

#[test]
fn p2_two_row_forms_keep_rank_two_through_full_turns() {
    let (sp_i, sp_j) = (Vector3::new(0.1, 0.5, -0.3), Vector3::new(-0.4, 0.2, 0.6));
    for s_i in directions() {
        let sw = sweep(s_i, sp_i, sp_j);
        let frame = cardan_eulerparam::frame_from_axis(&s_i).unwrap();
        let (f, g) = (frame.column(0).into_owned(), frame.column(1).into_owned());
        let perp = worst_ratio(&sw, |_| P2Perp::new(f, g, sp_i, sp_j));
        let select = worst_ratio(&sw, |_| P2Select::new(s_i, sp_i, sp_j));
        assert!(
            perp > 0.85,
            "p2_perp lost rank for s'_i = {s_i:?}: σmin/σmax = {perp}"
        );
        assert!(
            select > 0.5,
            "p2_select lost rank for s'_i = {s_i:?}: σmin/σmax = {select}"
        );
    }
}

/// Two fixed rows of the *global* s̃_i s_j (what a naive implementation of the seed's rule
/// freezes at assembly) become dependent as body i turns: the reason for the body-frame choice.
#[test]
fn frozen_global_row_choice_loses_rank_on_the_same_sweep() {
    let s_i = Vector3::z();
    let sw = sweep(s_i, Vector3::zeros(), Vector3::zeros());
    let worst = worst_ratio(&sw, |s_j| GlobalRows01(P1::new(s_i, s_j)));
    assert!(
        worst < 1e-6,
        "expected a rank drop, worst σmin/σmax = {worst}"
    );
}

/// Rows 0 and 1 of the three-row p1, fixed.
struct GlobalRows01(P1);

impl Constraint for GlobalRows01 {
    fn name(&self) -> &'static str {
        "p1 rows 0,1 (global, frozen)"
    }
    fn rows(&self) -> usize {
        2
    }
    fn dimension(&self, _row: usize) -> cardan_constraints::Dimension {
        cardan_constraints::Dimension::Dimensionless
    }
    fn footprint(&self) -> Footprint {
        self.0.footprint()
    }
    fn phi(&self, x: &BodyPair, t: f64, out: &mut [f64]) {
        let mut v = [0.0; 3];
        self.0.phi(x, t, &mut v);
        out.copy_from_slice(&v[..2]);
    }
    fn jacobian<const N: usize, F: Form<N>>(
        &self,
        x: &BodyPair,
        t: f64,
        out_i: &mut [[f64; N]],
        out_j: &mut [[f64; N]],
    ) {
        let (mut a, mut b) = ([[0.0; N]; 3], [[0.0; N]; 3]);
        self.0.jacobian::<N, F>(x, t, &mut a, &mut b);
        out_i.copy_from_slice(&a[..2]);
        out_j.copy_from_slice(&b[..2]);
    }
    fn gamma_sharp<const N: usize, F: Form<N>>(&self, _x: &BodyPair, _t: f64, _out: &mut [f64]) {}
}
