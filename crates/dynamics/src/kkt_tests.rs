//! The two factorizations of [`Kkt`] (Schur complement and LU of the full matrix) give the same
//! trajectories, and the Schur path falls back to the LU near singular configurations.

use super::{elements, Factored, Kkt, KktSolve, SchurRefinement};
use crate::{
    Dopri5Options, Dynamics, Force, GeneralizedAlphaOptions, Integrator, IterationMatrix,
    SimulationOptions, State,
};
use cardan_constraints::JointKind;
use cardan_mechanism::{Body, JointSpec, MechanismBuilder, Model, GROUND};
use cardan_solver::SolverError;
use nalgebra::Vector3;

/// `n` unit rods along +x joined by spherical joints, the first to the ground at the origin;
/// with `tip = Some(ε)`, a distance joint from the far end of the last rod to the ground point
/// (n + 1, ε, 0): at ε = 0 it is aligned with the straight chain, whose tip cannot move along x,
/// so its Φ_v row depends on the spherical rows (a dead-centre position); for small ε it almost
/// does (relative pivot of S ≈ ε²).
fn chain(n: usize, tip: Option<f64>) -> Model {
    chain_with(n, tip, 0.1)
}

/// [`chain`] with link k of mass 1 + `growth` k.
fn chain_with(n: usize, tip: Option<f64>, growth: f64) -> Model {
    let mut b = MechanismBuilder::new();
    b.point(GROUND, "O", Vector3::zeros());
    for k in 0..n {
        let name = format!("b{k}");
        b.body(
            Body::new(&name)
                .mass(1.0 + growth * k as f64)
                .inertia_diagonal(0.001, 1.0 / 12.0, 1.0 / 12.0)
                .position(Vector3::new(k as f64 + 0.5, 0.0, 0.0)),
        );
        b.point(&name, "a", Vector3::new(-0.5, 0.0, 0.0)).point(
            &name,
            "b",
            Vector3::new(0.5, 0.0, 0.0),
        );
        let (pb, pp) = if k == 0 {
            (GROUND.to_string(), "O")
        } else {
            (format!("b{}", k - 1), "b")
        };
        b.joint(JointSpec::new(
            format!("s{k}"),
            JointKind::Spherical,
            (&pb, pp),
            (&name, "a"),
        ));
    }
    if let Some(eps) = tip {
        b.point(GROUND, "G", Vector3::new(n as f64 + 1.0, eps, 0.0));
        b.joint(JointSpec::new(
            "tip",
            JointKind::SphericalSpherical,
            (GROUND, "G"),
            (&format!("b{}", n - 1), "b"),
        ));
    }
    b.build().unwrap()
}

fn dynamics(model: &Model) -> Dynamics<'_> {
    let mut d = Dynamics::new(model).unwrap();
    d.add_force(Force::gravity(Vector3::new(0.0, 2.0, -9.81)))
        .unwrap();
    d
}

/// Body positions, Euler parameters, velocities and angular velocities at every output time.
fn trajectory(model: &Model, integ: Integrator, path: KktSolve) -> (Vec<f64>, usize) {
    let mut d = dynamics(model);
    let s = State::initial(model, 0.0);
    d.prepare(&s).unwrap();
    d.kkt.as_mut().unwrap().set_solve_path(path);
    let opts = SimulationOptions::new(0.2, 10).integrator(integ);
    let r = d.simulate_consistent(s, &opts).unwrap();
    let kkt = d.kkt.as_ref().unwrap();
    let want = if path == KktSolve::Lu {
        Factored::Lu
    } else {
        Factored::Schur
    };
    assert_eq!(kkt.factored(), Some(want), "{path:?}");
    assert_eq!(kkt.fallbacks, 0);
    let mut out = Vec::new();
    for b in &r.kinematics.bodies {
        for k in 0..b.r.len() {
            out.extend(b.r[k].iter());
            out.extend(b.p[k].iter());
            out.extend(b.r_dot[k].iter());
            out.extend(b.omega[k].iter());
        }
    }
    (out, r.stats.factorizations)
}

#[test]
fn chain_trajectories_agree_with_schur_and_lu() {
    let model = chain(30, None);
    // Generalized-α stops its Newton iterations at 1e-10 (scaled), and between outputs its
    // velocity projection at 1e-3 of the correction; the two paths may take different
    // iteration counts (roundoff decides a contraction test now and then): the trajectories
    // agree to about that times a step's drift (2.3e-10 of the largest value, measured; a
    // wrong solve on either path is far above). DOPRI5 solves the same systems at the same
    // states.
    for (integ, tol) in [
        (
            Integrator::GeneralizedAlpha(GeneralizedAlphaOptions {
                iteration_matrix: IterationMatrix::MassOnly,
                ..GeneralizedAlphaOptions::with_step(1e-3)
            }),
            1e-9,
        ),
        (Integrator::Dopri5(Dopri5Options::fixed(1e-3)), 1e-13),
    ] {
        let (lu, f_lu) = trajectory(&model, integ, KktSolve::Lu);
        let (schur, f_schur) = trajectory(&model, integ, KktSolve::Schur);
        let (auto, _) = trajectory(&model, integ, KktSolve::Auto);
        assert_eq!(lu.len(), schur.len());
        let diff = lu
            .iter()
            .zip(&schur)
            .fold(0.0f64, |m, (a, b)| m.max((a - b).abs()));
        let size = lu.iter().fold(0.0f64, |m, a| m.max(a.abs()));
        assert!(size > 1.0);
        assert!(
            diff <= tol * size,
            "{integ:?}: trajectories differ by {diff:.2e} (largest value {size:.2e}); \
             factorizations LU {f_lu}, Schur {f_schur}"
        );
        assert_eq!(schur, auto, "Auto is the Schur path here");
    }
}

/// The KKT system of `chain(n, Some(eps))` at its initial (straight) pose, all rows active.
fn tip_kkt(model: &Model) -> (Kkt, Dynamics<'_>) {
    let mut d = dynamics(model);
    let s = State::initial(model, 0.0);
    d.sync(&s);
    let els = elements(model);
    let m = model.num_equations();
    let mut kkt = Kkt::new(model, &els, (0..m).collect(), &[]).unwrap();
    kkt.eval_jacobian(model, &els, &d.bodies, &d.curves, 0.0);
    kkt.set_mass(&d.mass, &d.inertia);
    (kkt, d)
}

/// A right-hand side [h; γ] with γ = Φ_v y in the range of Φ_v (as the true γ# is near a dead
/// centre, where the motion stays compatible), h and y smooth pseudo-random.
fn consistent_rhs(kkt: &mut Kkt) {
    let n = kkt.n;
    let y: Vec<f64> = (0..n).map(|i| ((i as f64) * 1.3).cos()).collect();
    let mut g = vec![0.0; kkt.active.len()];
    kkt.phi_v_mul(&y, &mut g);
    for i in 0..n {
        kkt.rhs[i] = ((i as f64) * 0.7).sin();
    }
    kkt.rhs[n..].copy_from_slice(&g);
}

/// Relative residual of the full KKT system at `kkt.sol` for `kkt.rhs`.
fn kkt_residual(kkt: &Kkt, d: &Dynamics) -> f64 {
    let n = kkt.n;
    let (x, lambda) = kkt.sol.split_at(n);
    let mut top = vec![0.0; n];
    for (k, (xk, yk)) in x.chunks(6).zip(top.chunks_mut(6)).enumerate() {
        let w = d.inertia[k] * Vector3::new(xk[3], xk[4], xk[5]);
        for c in 0..3 {
            yk[c] = d.mass[k] * xk[c];
            yk[3 + c] = w[c];
        }
    }
    kkt.phi_v_t_mul_add(lambda, &mut top);
    let mut bottom = vec![0.0; kkt.active.len()];
    kkt.phi_v_mul(x, &mut bottom);
    let mut r = 0.0f64;
    let mut size = 0.0f64;
    for (i, v) in top.iter().chain(&bottom).enumerate() {
        r = r.max((v - kkt.rhs[i]).abs());
        size = size.max(kkt.rhs[i].abs());
    }
    r / size
}

#[test]
fn near_dead_centre_falls_back_to_lu_with_a_correct_solution() {
    // ε = 1e-5: relative pivot of S ≈ 1e-10 < 1e-4, the LU pivot ≈ 1e-5 is fine.
    // 340 links: n + m_a = 3061, beyond LU_EAGER_MAX_SIZE: the LU is analyzed at the fallback.
    let big = chain(340, Some(1e-5));
    let (mut kkt, d) = tip_kkt(&big);
    assert!(kkt.rhs.len() > super::LU_EAGER_MAX_SIZE && !kkt.lu.analyzed());
    consistent_rhs(&mut kkt);
    kkt.factor().unwrap();
    assert_eq!(kkt.factored(), Some(Factored::Lu));
    kkt.solve(SchurRefinement::ONE_SHOT).unwrap();
    let r = kkt_residual(&kkt, &d);
    assert!(
        r < 1e-10,
        "LU fallback (deferred analysis): relative residual {r:.2e}"
    );

    let model = chain(20, Some(1e-5));
    let (mut kkt, d) = tip_kkt(&model);
    assert!(kkt.lu.analyzed());
    consistent_rhs(&mut kkt);
    kkt.factor().unwrap();
    assert_eq!(kkt.factored(), Some(Factored::Lu));
    assert_eq!(kkt.fallbacks, 1);
    kkt.solve(SchurRefinement::ONE_SHOT).unwrap();
    let r = kkt_residual(&kkt, &d);
    assert!(r < 1e-10, "LU fallback: relative residual {r:.2e}");
    let fallback = kkt.sol.clone();

    // The Schur path alone refuses this matrix, naming the tip row (KKT row n + m − 1).
    kkt.set_solve_path(KktSolve::Schur);
    match kkt.factor() {
        Err(SolverError::Singular {
            dependent_equations,
        }) => assert!(
            dependent_equations.iter().all(|&r| r >= kkt.n),
            "{dependent_equations:?}"
        ),
        other => panic!("expected Singular, got {other:?}"),
    }
    assert_eq!(kkt.factored(), None);
    assert!(matches!(
        kkt.solve(SchurRefinement::ONE_SHOT),
        Err(SolverError::NotReady { .. })
    ));

    // The forced LU gives the same solution as the fallback.
    kkt.set_solve_path(KktSolve::Lu);
    kkt.factor().unwrap();
    kkt.solve(SchurRefinement::ONE_SHOT).unwrap();
    assert_eq!(kkt.sol, fallback);

    // Away from the dead centre (ε = 0.3) Auto keeps the Schur path, with the same result.
    let model = chain(20, Some(0.3));
    let (mut kkt, d) = tip_kkt(&model);
    consistent_rhs(&mut kkt);
    kkt.factor().unwrap();
    assert_eq!(kkt.factored(), Some(Factored::Schur));
    kkt.solve(SchurRefinement::ONE_SHOT).unwrap();
    let schur = kkt.sol.clone();
    assert!(kkt_residual(&kkt, &d) < 1e-12);
    kkt.set_solve_path(KktSolve::Lu);
    kkt.factor().unwrap();
    kkt.solve(SchurRefinement::ONE_SHOT).unwrap();
    let diff = schur
        .iter()
        .zip(&kkt.sol)
        .fold(0.0f64, |m, (a, b)| m.max((a - b).abs()));
    let scale = kkt.sol.iter().fold(0.0f64, |m, a| m.max(a.abs()));
    assert!(diff <= 1e-12 * scale, "Schur vs LU: {diff:.2e}");
}

/// Close to a dead centre, but not so close that S is refused (pivot ratio between τ = 1e-4
/// and [`super::SCHUR_REFINE_RATIO`]): the Schur solve is refined once against K, which brings
/// its residual down to the LU's; `solve_unrefined` leaves it (as a refinement below 0 does).
#[test]
fn ill_conditioned_schur_solves_are_refined() {
    for eps in [0.03, 0.015] {
        let model = chain(60, Some(eps));
        let (mut kkt, d) = tip_kkt(&model);
        consistent_rhs(&mut kkt);
        kkt.factor().unwrap();
        assert_eq!(kkt.factored(), Some(Factored::Schur));
        let ratio = kkt.schur.min_pivot_ratio();
        assert!(ratio < super::SCHUR_REFINE_RATIO, "ratio {ratio:e}");
        kkt.solve_unrefined().unwrap();
        let plain = kkt_residual(&kkt, &d);
        kkt.solve(SchurRefinement { below: 0.0 }).unwrap();
        assert_eq!(kkt_residual(&kkt, &d), plain);
        kkt.solve(SchurRefinement::ONE_SHOT).unwrap();
        let refined = kkt_residual(&kkt, &d);
        kkt.set_solve_path(KktSolve::Lu);
        kkt.factor().unwrap();
        kkt.solve(SchurRefinement::ONE_SHOT).unwrap();
        let lu = kkt_residual(&kkt, &d);
        eprintln!("ε = {eps}: ratio {ratio:.1e}, residual plain {plain:.1e}, refined {refined:.1e}, LU {lu:.1e}");
        assert!(
            refined < plain && refined <= 10.0 * lu.max(1e-16),
            "{refined:e} vs {plain:e}, LU {lu:e}"
        );
    }
}

#[test]
fn exact_dead_centre_is_a_clean_error() {
    let model = chain(20, Some(0.0));
    let (mut kkt, _) = tip_kkt(&model);
    match kkt.factor() {
        Err(SolverError::Singular { .. }) => {}
        other => panic!("expected Singular, got {other:?}"),
    }
    assert_eq!(kkt.fallbacks, 1);
    assert!(matches!(
        kkt.solve(SchurRefinement::ONE_SHOT),
        Err(SolverError::NotReady { .. })
    ));
}

#[test]
fn tangent_terms_on_coupled_layouts_take_the_lu() {
    // Coupling blocks laid out (a force element between b0 and b1) and tangent terms added:
    // the top-left is no longer block diagonal.
    let model = chain(20, None);
    let d = dynamics(&model);
    let mut s = State::initial(&model, 0.0);
    s.v[4] = 0.3;
    let els = elements(&model);
    let m = model.num_equations();
    let mut kkt = Kkt::new(&model, &els, (0..m).collect(), &[(0, 1)]).unwrap();
    let mut d = d;
    d.sync(&s);
    kkt.eval_jacobian(&model, &els, &d.bodies, &d.curves, 0.0);
    kkt.set_mass(&d.mass, &d.inertia);
    kkt.factor().unwrap();
    assert_eq!(kkt.factored(), Some(Factored::Schur));
    // A symmetric coupling term: LU (the blocks are not diagonal any more).
    kkt.add_top(|r, c| {
        if r / 6 != c / 6 && r % 6 == c % 6 {
            0.1
        } else {
            0.0
        }
    });
    kkt.factor().unwrap();
    assert_eq!(kkt.factored(), Some(Factored::Lu));
    // Back to the mass only: Schur again.
    kkt.set_mass(&d.mass, &d.inertia);
    kkt.factor().unwrap();
    assert_eq!(kkt.factored(), Some(Factored::Schur));

    // Without coupling blocks: a symmetric block-diagonal term keeps the Schur path, a
    // non-symmetric one (gyroscopic-like) takes the LU; both solve the same system as the LU.
    let mut kkt = Kkt::new(&model, &els, (0..m).collect(), &[]).unwrap();
    kkt.eval_jacobian(&model, &els, &d.bodies, &d.curves, 0.0);
    for (i, v) in kkt.rhs.iter_mut().enumerate() {
        *v = ((i as f64) * 0.3).cos();
    }
    for (skew, want) in [(0.0, Factored::Schur), (0.05, Factored::Lu)] {
        let term = |r: usize, c: usize| {
            if r / 6 != c / 6 {
                0.0
            } else if r == c {
                0.2
            } else if r % 6 == 3 && c % 6 == 4 {
                0.01 + skew
            } else if r % 6 == 4 && c % 6 == 3 {
                0.01 - skew
            } else {
                0.0
            }
        };
        kkt.set_solve_path(KktSolve::Auto);
        kkt.set_mass(&d.mass, &d.inertia);
        kkt.add_top(term);
        kkt.factor().unwrap();
        assert_eq!(kkt.factored(), Some(want), "skew {skew}");
        kkt.solve(SchurRefinement::ONE_SHOT).unwrap();
        let got = kkt.sol.clone();
        kkt.set_solve_path(KktSolve::Lu);
        kkt.set_mass(&d.mass, &d.inertia);
        kkt.add_top(term);
        kkt.factor().unwrap();
        kkt.solve(SchurRefinement::ONE_SHOT).unwrap();
        let diff = got
            .iter()
            .zip(&kkt.sol)
            .fold(0.0f64, |m, (a, b)| m.max((a - b).abs()));
        let scale = kkt.sol.iter().fold(0.0f64, |m, a| m.max(a.abs()));
        assert!(diff <= 1e-12 * scale, "skew {skew}: {diff:.2e}");
    }
}

#[test]
fn point_mass_with_negligible_inertia_takes_the_lu_once_and_for_all() {
    // The A01 pendulum's body: m = 1, J' = 1e-13 I (block condition 1e13).
    let mut b = MechanismBuilder::new();
    b.point(GROUND, "O", Vector3::zeros());
    b.body(
        Body::new("mass")
            .mass(1.0)
            .inertia_diagonal(1e-13, 1e-13, 1e-13)
            .position(Vector3::new(1.0, 0.0, 0.0)),
    );
    b.point("mass", "O", Vector3::new(-1.0, 0.0, 0.0));
    b.joint(JointSpec::new(
        "ball",
        JointKind::Spherical,
        (GROUND, "O"),
        ("mass", "O"),
    ));
    let model = b.build().unwrap();
    let mut d = dynamics(&model);
    d.sync(&State::initial(&model, 0.0));
    let els = elements(&model);
    let mut kkt = Kkt::new(&model, &els, vec![0, 1, 2], &[]).unwrap();
    kkt.eval_jacobian(&model, &els, &d.bodies, &d.curves, 0.0);
    for _ in 0..3 {
        kkt.set_mass(&d.mass, &d.inertia);
        kkt.factor().unwrap();
        assert_eq!(kkt.factored(), Some(Factored::Lu));
    }
    assert_eq!(kkt.fallbacks, 1, "the Schur path is tried once");
    kkt.set_solve_path(KktSolve::Schur);
    kkt.set_mass(&d.mass, &d.inertia);
    assert!(matches!(
        kkt.factor(),
        Err(SolverError::Singular { dependent_equations }) if dependent_equations.is_empty()
    ));
}

#[test]
fn a_matrix_refused_again_and_again_is_tried_once_in_sixteen() {
    // Near the dead centre every factorization is refused by the Schur solver.
    let model = chain(20, Some(1e-5));
    let (mut kkt, _) = tip_kkt(&model);
    for _ in 0..35 {
        // A new matrix each time (one ulp apart), so that each one is factored.
        kkt.jac[0] = f64::from_bits(kkt.jac[0].to_bits() ^ 1);
        kkt.factor().unwrap();
        assert_eq!(kkt.factored(), Some(Factored::Lu));
    }
    // Tries 1, 2, 3 refused; 4–18 skipped; 19 refused, 20–34 skipped; 35 refused.
    assert_eq!(kkt.fallbacks, 5);
}

#[test]
fn an_unchanged_mass_only_matrix_is_not_factored_again() {
    let model = chain(5, None);
    let (mut kkt, d) = tip_kkt(&model);
    kkt.factor().unwrap();
    consistent_rhs(&mut kkt);
    kkt.solve(SchurRefinement::ONE_SHOT).unwrap();
    let first = kkt.sol.clone();
    // Same Φ_v, same masses: the factorization is kept, and solves the same.
    kkt.set_mass(&d.mass, &d.inertia);
    kkt.factor().unwrap();
    kkt.solve(SchurRefinement::ONE_SHOT).unwrap();
    assert_eq!(kkt.factorizations, 1);
    assert_eq!(kkt.sol, first);
    // A changed Φ_v value, other masses, or tangent terms: factored again.
    let k = kkt.jac.iter().position(|v| *v != 0.0).unwrap();
    kkt.jac[k] *= 1.0 + 1e-12;
    kkt.factor().unwrap();
    assert_eq!(kkt.factorizations, 2);
    let heavier: Vec<f64> = d.mass.iter().map(|m| 2.0 * m).collect();
    kkt.set_mass(&heavier, &d.inertia);
    kkt.factor().unwrap();
    assert_eq!(kkt.factorizations, 3);
    kkt.add_top(|r, c| if r == c { 1e-3 } else { 0.0 });
    kkt.factor().unwrap();
    kkt.factor().unwrap();
    assert_eq!(kkt.factorizations, 5, "a tangent matrix is always factored");
    // Back to the mass matrix: different from the tangent one just factored.
    kkt.set_mass(&heavier, &d.inertia);
    kkt.factor().unwrap();
    assert_eq!(kkt.factorizations, 6);
}

#[test]
fn dopri5_refines_schur_solves_only_for_tight_tolerances() {
    // A 1,000-link chain's smallest pivot ratio is about 5e-4.
    assert!(SchurRefinement::for_rtol(1e-10).below > 5e-4);
    assert!(SchurRefinement::for_rtol(1e-8).below < 5e-4);
    assert!(SchurRefinement::for_rtol(1e-14).below <= super::SCHUR_REFINE_RATIO);
}

#[test]
fn the_schur_pivot_tolerance_admits_long_chains_only() {
    use super::schur_pivot_tolerance;
    // Models under 1,000 rows keep the solver's τ (the A02 four-bar passes its singular
    // positions on the LU with it).
    assert_eq!(schur_pivot_tolerance(3), 1e-4);
    assert_eq!(schur_pivot_tolerance(999), 1e-4);
    // A chain of N links (m = 3N rows) has a smallest pivot ratio of about 1/(2N): admitted at
    // every length, with a margin.
    for n in [1_000usize, 10_000, 100_000] {
        let ratio = 1.0 / (2.0 * n as f64);
        assert!(schur_pivot_tolerance(3 * n) < ratio / 10.0, "N = {n}");
    }
}

#[test]
fn a_long_chain_takes_the_schur_path() {
    // 6,000 equal links: smallest pivot ratio ≈ 1/(2N) = 8e-5, which the fixed τ = 1e-4
    // refused. (With masses growing along the chain, 1 + 0.1 k, the ratio falls like 1/N²:
    // 6e-5 at 400 links, 1e-5 at 1,000; such chains still go to the LU.)
    let model = chain_with(6000, None, 0.0);
    let (mut kkt, d) = tip_kkt(&model);
    kkt.factor().unwrap();
    assert_eq!(kkt.factored(), Some(Factored::Schur));
    consistent_rhs(&mut kkt);
    kkt.solve(SchurRefinement::ONE_SHOT).unwrap();
    let r = kkt_residual(&kkt, &d);
    assert!(r < 1e-13, "{r:e}");
}

/// The fused product of the residual (Φ_vᵀλ and the size of its terms) equals Φ_vᵀλ term for
/// term, and |Φ_v|ᵀ|λ|.
#[test]
fn phi_v_t_product_with_size_is_the_product_and_its_term_sizes() {
    let model = chain(12, Some(0.3));
    let (mut kkt, _) = tip_kkt(&model);
    let (n, na) = (kkt.n, kkt.active.len());
    let lambda: Vec<f64> = (0..na).map(|a| (a as f64 * 0.7).sin() - 0.2).collect();
    let base: Vec<f64> = (0..n).map(|i| (i as f64 * 0.3).cos()).collect();
    let mut plain = base.clone();
    kkt.phi_v_t_mul_add(&lambda, &mut plain);
    let mut fused = base.clone();
    let mut size = vec![1.0; n];
    kkt.phi_v_t_mul_add_with_size(&lambda, &mut fused, &mut size);
    assert_eq!(fused, plain);
    for v in kkt.jac.iter_mut() {
        *v = v.abs();
    }
    let abs_lambda: Vec<f64> = lambda.iter().map(|l| l.abs()).collect();
    let mut expected = vec![1.0; n];
    kkt.phi_v_t_mul_add(&abs_lambda, &mut expected);
    assert!(size.iter().any(|&s| s > 1.0));
    for (s, e) in size.iter().zip(&expected) {
        assert!((s - e).abs() <= 1e-15 * e, "{s} vs {e}");
    }
}
