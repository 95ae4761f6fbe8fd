//! Algebraic identities of A, G, L and ā (issue 2): orthogonality, A = G Lᵀ, G p = L p = 0,
//! G Gᵀ = L Lᵀ = I, Ġ ṗ = L̇ ṗ = 0, over random and curated p, normalized and not.
//!
//! Tolerance: [`common::EXACT`] (a few ulps on O(1) data), scaled by |p|² for unnormalized p
//! through the comparison's max(1, |want|) scale.

mod common;

use cardan_eulerparam::{a, bar, g, g_dot, l, l_dot, skew, unskew, EulerParams};
use common::*;
use nalgebra::{Matrix3, Matrix4, Vector3, Vector4};
use proptest::prelude::*;

/// AAᵀ = AᵀA = I, det A = 1 (unit p).
fn check_orthogonal(p: &Vector4<f64>, ctx: &str) -> Result<(), String> {
    let m = a(p);
    close(
        &(m * m.transpose()),
        &Matrix3::identity(),
        EXACT,
        &format!("{ctx}: A Aᵀ = I"),
    )?;
    close(
        &(m.transpose() * m),
        &Matrix3::identity(),
        EXACT,
        &format!("{ctx}: Aᵀ A = I"),
    )?;
    let det = m.determinant();
    if (det - 1.0).abs() > EXACT {
        return Err(format!("{ctx}: det A = {det:e}, want 1"));
    }
    Ok(())
}

/// The identities that hold for every p, normalized or not, with s = pᵀp:
/// G p = L p = 0, G Gᵀ = L Lᵀ = s I, Gᵀ G = Lᵀ L = s I₄ − p pᵀ, G Lᵀ = A + (1 − s) I,
/// A(−p) = A(p), G(−p) = −G(p), L(−p) = −L(p).
fn check_any_p(p: &Vector4<f64>, ctx: &str) -> Result<(), String> {
    let (gm, lm, s) = (g(p), l(p), p.norm_squared());
    let z3 = Vector3::zeros();
    close(&(gm * p), &z3, EXACT, &format!("{ctx}: G p = 0"))?;
    close(&(lm * p), &z3, EXACT, &format!("{ctx}: L p = 0"))?;
    close(
        &(gm * gm.transpose()),
        &(Matrix3::identity() * s),
        EXACT,
        &format!("{ctx}: G Gᵀ = pᵀp I"),
    )?;
    close(
        &(lm * lm.transpose()),
        &(Matrix3::identity() * s),
        EXACT,
        &format!("{ctx}: L Lᵀ = pᵀp I"),
    )?;
    let proj = Matrix4::identity() * s - p * p.transpose();
    close(
        &(gm.transpose() * gm),
        &proj,
        EXACT,
        &format!("{ctx}: Gᵀ G = pᵀp I − p pᵀ"),
    )?;
    close(
        &(lm.transpose() * lm),
        &proj,
        EXACT,
        &format!("{ctx}: Lᵀ L = pᵀp I − p pᵀ"),
    )?;
    let want = a(p) + Matrix3::identity() * (1.0 - s);
    close(
        &(gm * lm.transpose()),
        &want,
        EXACT,
        &format!("{ctx}: G Lᵀ = A + (1 − pᵀp) I"),
    )?;
    close(&a(&-p), &a(p), EXACT, &format!("{ctx}: A(−p) = A(p)"))?;
    close(&g(&-p), &(-gm), EXACT, &format!("{ctx}: G(−p) = −G(p)"))?;
    close(&l(&-p), &(-lm), EXACT, &format!("{ctx}: L(−p) = −L(p)"))?;
    Ok(())
}

/// A written out from its definition (2 e0² − 1) I + 2 (e eᵀ + e0 ẽ) with the test's own skew.
fn a_reference(p: &Vector4<f64>) -> Matrix3<f64> {
    let (e0, e) = (p[0], Vector3::new(p[1], p[2], p[3]));
    let et = Matrix3::new(0.0, -e.z, e.y, e.z, 0.0, -e.x, -e.y, e.x, 0.0);
    Matrix3::identity() * (2.0 * e0 * e0 - 1.0) + (e * e.transpose() + et * e0) * 2.0
}

#[test]
fn a_is_orthogonal_with_unit_determinant_on_curated_p() {
    for (name, p) in curated_unit_p() {
        if let Err(m) = check_orthogonal(&p, &format!("p = {name} {:?}", p.as_slice())) {
            panic!("{m}");
        }
    }
}

#[test]
fn a_g_l_identities_hold_on_curated_p_normalized_or_not() {
    for (name, p) in curated_unit_p().into_iter().chain(curated_unnormalized_p()) {
        let ctx = format!("p = {name} {:?}", p.as_slice());
        if let Err(m) = check_any_p(&p, &ctx) {
            panic!("{m}");
        }
        assert_close(
            &a(&p),
            &a_reference(&p),
            EXACT,
            &format!("{ctx}: A matches its definition"),
        );
    }
}

#[test]
fn a_equals_g_l_transpose_for_unit_p() {
    for (name, p) in curated_unit_p() {
        let ctx = format!("p = {name} {:?}", p.as_slice());
        assert_close(
            &(g(&p) * l(&p).transpose()),
            &a(&p),
            EXACT,
            &format!("{ctx}: A = G Lᵀ"),
        );
        assert_close(
            &(g(&p) * g(&p).transpose()),
            &Matrix3::identity(),
            EXACT,
            &format!("{ctx}: G Gᵀ = I"),
        );
        assert_close(
            &(l(&p) * l(&p).transpose()),
            &Matrix3::identity(),
            EXACT,
            &format!("{ctx}: L Lᵀ = I"),
        );
    }
}

#[test]
fn known_rotations_have_known_matrices() {
    // Independent of the crate's formulas: Rodrigues' formula at the same axis and angle.
    let axes = [
        Vector3::x(),
        Vector3::y(),
        Vector3::z(),
        Vector3::new(1.0, -2.0, 3.0).normalize(),
    ];
    for u in axes {
        for chi in [
            0.0,
            0.3,
            std::f64::consts::FRAC_PI_2,
            2.0,
            std::f64::consts::PI,
            4.0,
            6.0,
        ] {
            let p = qexp(&u, chi);
            let ctx = format!("u = {:?}, χ = {chi}", u.as_slice());
            assert_close(&a(&p), &rodrigues(&u, chi), EXACT, &ctx);
        }
    }
}

#[test]
fn g_and_l_rows_are_the_quaternion_products() {
    // G ṗ = vector part of ṗ ⊗ p*, L ṗ = vector part of p* ⊗ ṗ: an independent check of every
    // entry's sign (a planted sign error in G or L breaks this even where GLᵀ might not show it).
    let p = Vector4::new(0.3, -0.5, 0.2, 0.7);
    let pc = Vector4::new(p[0], -p[1], -p[2], -p[3]);
    for k in 0..4 {
        let mut v = Vector4::zeros();
        v[k] = 1.0;
        let gq = qmul(&v, &pc);
        let lq = qmul(&pc, &v);
        let ctx = format!("column {k}");
        assert_close(
            &(g(&p) * v),
            &Vector3::new(gq[1], gq[2], gq[3]),
            EXACT,
            &format!("G {ctx}"),
        );
        assert_close(
            &(l(&p) * v),
            &Vector3::new(lq[1], lq[2], lq[3]),
            EXACT,
            &format!("L {ctx}"),
        );
    }
}

#[test]
fn bar_is_skew_and_is_the_right_product_with_a_pure_quaternion() {
    for v in curated_vectors() {
        let b = bar(&v);
        let ctx = format!("a = {:?}", v.as_slice());
        assert_close(
            &(b + b.transpose()),
            &Matrix4::zeros(),
            0.0,
            &format!("{ctx}: ā is skew"),
        );
        // ā q = q ⊗ [0, a] (right product with the pure quaternion a).
        let q = Vector4::new(0.3, -0.5, 0.2, 0.7);
        assert_close(
            &(b * q),
            &qmul(&q, &Vector4::new(0.0, v.x, v.y, v.z)),
            EXACT,
            &ctx,
        );
    }
}

#[test]
fn skew_and_unskew() {
    for v in curated_vectors() {
        let w = Vector3::new(-0.7, 0.1, 0.4);
        let ctx = format!("a = {:?}", v.as_slice());
        assert_close(&(skew(&v) * w), &v.cross(&w), EXACT, &ctx);
        assert_close(&unskew(&skew(&v)), &v, 0.0, &ctx);
    }
}

#[test]
fn g_dot_and_l_dot_annihilate_p_dot() {
    for (name, p) in curated_unit_p() {
        // Any ṗ: Ġ ṗ = G(ṗ) ṗ = 0 for every ṗ, tangent or not.
        let pd = Vector4::new(0.4, -1.1, 0.3, 0.9) + p;
        let ctx = format!("p = {name}, ṗ = {:?}", pd.as_slice());
        assert_close(&(g_dot(&pd) * pd), &Vector3::zeros(), EXACT, &ctx);
        assert_close(&(l_dot(&pd) * pd), &Vector3::zeros(), EXACT, &ctx);
    }
}

proptest! {
    #[test]
    fn prop_a_is_a_proper_rotation(p in unit_p()) {
        if let Err(m) = check_orthogonal(&p, "random unit p") {
            return Err(TestCaseError::fail(m));
        }
        prop_close!(g(&p) * l(&p).transpose(), a(&p), EXACT, "A = G Lᵀ");
    }

    #[test]
    fn prop_identities_for_any_p(p in prop_oneof![unit_p(), unnormalized_p()]) {
        if let Err(m) = check_any_p(&p, "random p") {
            return Err(TestCaseError::fail(m));
        }
        prop_close!(a(&p), a_reference(&p), EXACT, "A matches its definition");
    }

    #[test]
    fn prop_g_dot_l_dot_annihilate_p_dot(pd in vec4()) {
        prop_close!(g_dot(&pd) * pd, Vector3::zeros(), EXACT, "Ġ ṗ = 0");
        prop_close!(l_dot(&pd) * pd, Vector3::zeros(), EXACT, "L̇ ṗ = 0");
    }

    #[test]
    fn prop_a_rotates_like_the_quaternion_sandwich(p in unit_p(), v in vec3()) {
        // A a' = vector part of p ⊗ [0, a'] ⊗ p*.
        let pc = Vector4::new(p[0], -p[1], -p[2], -p[3]);
        let r = qmul(&qmul(&p, &Vector4::new(0.0, v.x, v.y, v.z)), &pc);
        prop_close!(a(&p) * v, Vector3::new(r[1], r[2], r[3]), EXACT, "A a' = p a' p*");
    }

    #[test]
    fn prop_compose_and_conjugate(p in unit_p(), q in unit_p()) {
        let (ep, eq) = (EulerParams::from_vector(p), EulerParams::from_vector(q));
        prop_close!(ep.compose(&eq).a(), a(&p) * a(&q), EXACT, "A(p ⊗ q) = A(p) A(q)");
        prop_close!(*ep.compose(&eq).as_vector(), qmul(&p, &q), EXACT, "compose = Hamilton product");
        prop_close!(ep.conjugate().a(), a(&p).transpose(), EXACT, "A(p*) = Aᵀ");
        prop_assert_ne!(-ep, ep);
        prop_close!((-ep).a(), ep.a(), EXACT, "A(−p) = A(p)");
    }

    #[test]
    fn prop_normalized_keeps_the_sign(p in unnormalized_p()) {
        let n = EulerParams::from_vector(p).normalized().unwrap();
        prop_assert!(n.is_normalized(EXACT), "|pᵀp − 1| = {:e}", n.norm_error());
        prop_close!(*n.as_vector(), p / p.norm(), EXACT, "p / |p|");
        prop_assert!(n.as_vector().dot(&p) > 0.0, "normalization flipped the sign");
    }
}

#[test]
fn euler_params_type_basics() {
    assert_eq!(EulerParams::default(), EulerParams::identity());
    let p = EulerParams::new(0.3, -0.5, 0.2, 0.7);
    assert_eq!(Vector4::from(p), Vector4::new(0.3, -0.5, 0.2, 0.7));
    assert_eq!((p.e0(), p.e()), (0.3, Vector3::new(-0.5, 0.2, 0.7)));
    assert!((p.norm_squared() - 0.87).abs() < EXACT);
    assert!((p.norm_error() - 0.13).abs() < EXACT);
    assert!(!p.is_normalized(1e-3) && p.is_normalized(0.2));
    let q = EulerParams::try_new_normalized(0.3, -0.5, 0.2, 0.7).unwrap();
    assert!(q.is_normalized(EXACT), "|pᵀp − 1| = {:e}", q.norm_error());
    assert!(matches!(
        EulerParams::try_new_normalized(0.0, 0.0, 0.0, 0.0),
        Err(cardan_eulerparam::EulerParamError::ZeroNorm { .. })
    ));
    assert!(matches!(
        EulerParams::try_new_normalized(0.0, f64::INFINITY, 0.0, 0.0),
        Err(cardan_eulerparam::EulerParamError::NotFinite { .. })
    ));
    // The accessor matrices agree with the free functions.
    assert_eq!(q.a(), a(q.as_vector()));
    assert_eq!(q.g(), g(q.as_vector()));
    assert_eq!(q.l(), l(q.as_vector()));
}
