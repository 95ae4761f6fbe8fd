//! Cross-check of the 6-coordinate analysis with the 7-coordinate form.
//!
//! At configurations computed along the slider-crank run (6-coordinate Newton, v = [ṙ; ω']), the
//! 7-coordinate velocity and acceleration equations with the normalization rows,
//!
//! ```text
//! [Φ_q; 2 pᵀ] q̇ = [ν; 0],     [Φ_q; 2 pᵀ] q̈ = [γ#_q; −2 ṗᵀṗ],
//! ```
//!
//! solved densely, must give ṗ = ½ Lᵀ ω' and p̈ = ½ Lᵀ ω̇' − ¼ |ω'|² p and the same ṙ, r̈.

mod common;

use cardan_constraints::{BodyPair, BodyState, Constraint};
use cardan_mechanism::{BodyId, KinematicOptions, Model};
use nalgebra::{DMatrix, DVector, Vector3, Vector4};

fn state(states: &[BodyState], id: BodyId) -> BodyState {
    match id {
        BodyId::Ground => BodyState::ground(),
        BodyId::Moving(k) => states[k],
    }
}

/// Rows of one element in the 7-coordinate form: Φ_q into `a`, ν into `nu`, γ#_q into `gam`.
fn fill<C: Constraint>(
    c: &C,
    ids: (BodyId, BodyId),
    rows: std::ops::Range<usize>,
    states: &[BodyState],
    t: f64,
    a: &mut DMatrix<f64>,
    nu: &mut DVector<f64>,
    gam: &mut DVector<f64>,
) {
    let (si, sj) = (state(states, ids.0), state(states, ids.1));
    let pair = BodyPair::new(&si, &sj);
    let n = rows.len();
    let mut bi = vec![[0.0; 7]; n];
    let mut bj = vec![[0.0; 7]; n];
    c.phi_q(&pair, t, &mut bi, &mut bj);
    let mut v = vec![0.0; n];
    c.nu(&pair, t, &mut v);
    let mut g = vec![0.0; n];
    c.gamma_sharp_q(&pair, t, &mut g);
    for r in 0..n {
        for (id, blk) in [(ids.0, &bi), (ids.1, &bj)] {
            if let BodyId::Moving(k) = id {
                for c in 0..7 {
                    a[(rows.start + r, 7 * k + c)] += blk[r][c];
                }
            }
        }
        nu[rows.start + r] = v[r];
        gam[rows.start + r] = g[r];
    }
}

fn seven(model: &Model, states: &[BodyState], t: f64) -> (DVector<f64>, DVector<f64>) {
    let nb = model.num_bodies();
    let m = model.num_equations();
    let mut a = DMatrix::zeros(m + nb, 7 * nb);
    let mut nu = DVector::zeros(m + nb);
    let mut gam = DVector::zeros(m + nb);
    for j in model.joints() {
        fill(
            &j.joint,
            (j.body_i, j.body_j),
            j.rows.clone(),
            states,
            t,
            &mut a,
            &mut nu,
            &mut gam,
        );
    }
    for d in model.drivers() {
        fill(
            &d.driver,
            (d.body_i, d.body_j),
            d.rows.clone(),
            states,
            t,
            &mut a,
            &mut nu,
            &mut gam,
        );
    }
    for (k, s) in states.iter().enumerate() {
        for c in 0..4 {
            a[(m + k, 7 * k + 3 + c)] = 2.0 * s.p[c];
        }
        gam[m + k] = -2.0 * s.p_dot.dot(&s.p_dot);
    }
    let lu = a.lu();
    (lu.solve(&nu).unwrap(), lu.solve(&gam).unwrap())
}

#[test]
fn six_and_seven_coordinate_forms_agree() {
    let model = common::slider_crank();
    let r = model
        .run_kinematics(&KinematicOptions::new(0.0, 1.0, 20))
        .unwrap();
    let nb = model.num_bodies();
    let (mut ev, mut ea) = (0.0f64, 0.0f64);
    for k in 0..r.len() {
        let states: Vec<BodyState> = (0..nb)
            .map(|b| {
                let h = &r.bodies[b];
                BodyState::at(h.r[k], h.p[k]).with_v(h.r_dot[k], h.omega_local[k])
            })
            .collect();
        let (qd, qdd) = seven(&model, &states, r.times[k]);
        for (b, h) in r.bodies.iter().enumerate() {
            let rd = Vector3::from_column_slice(&qd.as_slice()[7 * b..7 * b + 3]);
            let pd = Vector4::from_column_slice(&qd.as_slice()[7 * b + 3..7 * b + 7]);
            let rdd = Vector3::from_column_slice(&qdd.as_slice()[7 * b..7 * b + 3]);
            let pdd = Vector4::from_column_slice(&qdd.as_slice()[7 * b + 3..7 * b + 7]);
            ev = ev
                .max((rd - h.r_dot[k]).norm())
                .max((pd - h.p_dot[k]).norm());
            ea = ea
                .max((rdd - h.r_ddot[k]).norm())
                .max((pdd - h.p_ddot[k]).norm());
        }
    }
    eprintln!("6- vs 7-coordinate form: max velocity difference {ev:.2e}, acceleration {ea:.2e}");
    assert!(ev < 1e-11, "{ev}");
    assert!(ea < 1e-9, "{ea}");
}
