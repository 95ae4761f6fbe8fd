//! Derivatives checked against central finite differences (issue 2): ∂(A a')/∂p (normalized and
//! unnormalized p), ∂(A a')/∂π', Ȧ, the ω / ω' maps, ṗ ↔ ω', and p̈ from (ω', ω̇').
//!
//! Step sizes and tolerances are explained in `common/mod.rs`: A(p) is quadratic in p, so
//! differences of A along straight lines in p are exact up to round-off (h = 1e-4, tol 1e-10);
//! differences along curved trajectories use h = 1e-5 / tol 1e-8 (first) and h = 1e-4 / tol
//! 1e-6 (second).

mod common;

use cardan_eulerparam::{
    a, a_dot, da_dp, da_dpi_local, g, g_dot, l, l_dot, omega_global, omega_local,
    p_ddot_from_local, p_dot_from_global, p_dot_from_local, skew,
};
use common::*;
use nalgebra::{Vector3, Vector4};
use proptest::prelude::*;

// ---------------------------------------------------------------------------------------------
// ∂(A a')/∂p
// ---------------------------------------------------------------------------------------------

fn check_da_dp(p: &Vector4<f64>, v: &Vector3<f64>, ctx: &str) -> Result<(), String> {
    let fd = jacobian_p(|q| a(q) * v, p, H_QUADRATIC);
    close(
        &da_dp(p, v),
        &fd,
        FD_QUADRATIC,
        &format!("{ctx}: ∂(A a')/∂p vs central differences"),
    )?;
    // Linear in p: the second derivative of A a' along ṗ is ∂(A a')/∂p evaluated at ṗ, times ṗ.
    // A second central difference of a quadratic is exact up to round-off 4 ε |A| / h²; h = 1e-2
    // keeps that below 1e-11.
    let pd = Vector4::new(0.7, -0.2, 0.5, -1.1);
    let fd2 = central_second(|t| a(&(p + pd * t)) * v, 1e-2);
    close(
        &(da_dp(&pd, v) * pd),
        &fd2,
        FD_QUADRATIC,
        &format!("{ctx}: d²(A a')/dτ² = (∂(A a')/∂p)(ṗ) ṗ"),
    )
}

#[test]
fn da_dp_matches_finite_differences_on_curated_p() {
    for (name, p) in curated_unit_p().into_iter().chain(curated_unnormalized_p()) {
        for v in curated_vectors() {
            let ctx = format!("p = {name} {:?}, a' = {:?}", p.as_slice(), v.as_slice());
            if let Err(m) = check_da_dp(&p, &v, &ctx) {
                panic!("{m}");
            }
        }
    }
}

#[test]
fn da_dp_at_identity_is_known() {
    // At p = [1, 0, 0, 0]: ∂(A a')/∂e0 = 4 a' (from the (2 e0² − 1) I term), ∂(A a')/∂e = −2 ã'.
    let v = Vector3::new(0.4, -1.3, 2.2);
    let d = da_dp(&Vector4::new(1.0, 0.0, 0.0, 0.0), &v);
    assert_close(&d.column(0).into_owned(), &(v * 4.0), EXACT, "column e0");
    assert_close(
        &d.fixed_columns::<3>(1).into_owned(),
        &(skew(&v) * -2.0),
        EXACT,
        "columns e",
    );
}

// ---------------------------------------------------------------------------------------------
// ∂(A a')/∂π'
// ---------------------------------------------------------------------------------------------

fn check_da_dpi(p: &Vector4<f64>, v: &Vector3<f64>, ctx: &str) -> Result<(), String> {
    let want = da_dpi_local(p, v);
    // δp = [1, π'/2], as in the oracle contract: A(p ⊗ δp) is quadratic in π'.
    let fd = jacobian_3(
        |pi| {
            let dp = Vector4::new(1.0, 0.5 * pi.x, 0.5 * pi.y, 0.5 * pi.z);
            a(&qmul(p, &dp)) * v
        },
        H_QUADRATIC,
    );
    close(
        &want,
        &fd,
        FD_QUADRATIC,
        &format!("{ctx}: −A ã' vs differences of A(p ⊗ [1, π'/2]) a'"),
    )?;
    // δp = exp(π'/2), a unit rotation: same first derivative.
    let fd_exp = jacobian_3(
        |pi| {
            let n = pi.norm();
            let dp = if n == 0.0 {
                Vector4::new(1.0, 0.0, 0.0, 0.0)
            } else {
                qexp(&(pi / n), n)
            };
            a(&qmul(p, &dp)) * v
        },
        H_SMOOTH,
    );
    close(
        &want,
        &fd_exp,
        FD_SMOOTH,
        &format!("{ctx}: −A ã' vs differences of A(p ⊗ exp(π'/2)) a'"),
    )?;
    // Φ_π' = ½ Φ_p Lᵀ.
    let chain = da_dp(p, v) * l(p).transpose() * 0.5;
    close(&want, &chain, EXACT, &format!("{ctx}: ∂/∂π' = ½ (∂/∂p) Lᵀ"))
}

#[test]
fn da_dpi_local_matches_finite_differences_on_curated_p() {
    for (name, p) in curated_unit_p() {
        for v in curated_vectors() {
            let ctx = format!("p = {name} {:?}, a' = {:?}", p.as_slice(), v.as_slice());
            if let Err(m) = check_da_dpi(&p, &v, &ctx) {
                panic!("{m}");
            }
        }
    }
}

// ---------------------------------------------------------------------------------------------
// Ȧ
// ---------------------------------------------------------------------------------------------

fn check_a_dot(p: &Vector4<f64>, pd: &Vector4<f64>, ctx: &str) -> Result<(), String> {
    let fd = central(|t| a(&(p + pd * t)), H_QUADRATIC);
    close(
        &a_dot(p, pd),
        &fd,
        FD_QUADRATIC,
        &format!("{ctx}: Ȧ vs differences of A(p + ṗ t)"),
    )?;
    let v = Vector3::new(0.4, -1.3, 2.2);
    close(
        &(a_dot(p, pd) * v),
        &(da_dp(p, &v) * pd),
        EXACT,
        &format!("{ctx}: Ȧ a' = (∂(A a')/∂p) ṗ"),
    )
}

#[test]
fn a_dot_matches_finite_differences_on_curated_p() {
    let rates = [
        Vector4::new(0.7, -0.2, 0.5, -1.1),
        Vector4::new(1.0, 0.0, 0.0, 0.0),
        Vector4::new(0.0, 0.0, 0.0, 0.0),
    ];
    for (name, p) in curated_unit_p().into_iter().chain(curated_unnormalized_p()) {
        for pd in rates.iter().copied().chain([p, -p * 0.3]) {
            let ctx = format!("p = {name} {:?}, ṗ = {:?}", p.as_slice(), pd.as_slice());
            if let Err(m) = check_a_dot(&p, &pd, &ctx) {
                panic!("{m}");
            }
            // Tangent rate on the unit sphere: Ȧ = ω̃ A = A ω̃'.
            if (p.norm_squared() - 1.0).abs() < 1e-15 {
                let pt = pd - p * p.dot(&pd);
                let ad = a_dot(&p, &pt);
                let (w, wl) = (omega_global(&p, &pt), omega_local(&p, &pt));
                assert_close(&ad, &(skew(&w) * a(&p)), EXACT, &format!("{ctx}: Ȧ = ω̃ A"));
                assert_close(
                    &ad,
                    &(a(&p) * skew(&wl)),
                    EXACT,
                    &format!("{ctx}: Ȧ = A ω̃'"),
                );
                let (gl, lt) = (g(&p) * l(&pt).transpose(), g(&pt) * l(&p).transpose());
                assert_close(&ad, &(gl * 2.0), EXACT, &format!("{ctx}: Ȧ = 2 G L̇ᵀ"));
                assert_close(&ad, &(lt * 2.0), EXACT, &format!("{ctx}: Ȧ = 2 Ġ Lᵀ"));
            }
        }
    }
}

// ---------------------------------------------------------------------------------------------
// ω and ω' along trajectories.
// ---------------------------------------------------------------------------------------------

/// A unit-p trajectory through p0 with a known rate: p(t) = (p0 + t v) / |p0 + t v|,
/// ṗ(0) = v − p0 (p0ᵀ v) for unit p0. Checks ω̃ = Ȧ Aᵀ and ω̃' = Aᵀ Ȧ with Ȧ by differences.
fn check_omega_on_line(p0: &Vector4<f64>, v: &Vector4<f64>, ctx: &str) -> Result<(), String> {
    let traj = |t: f64| (p0 + v * t).normalize();
    let pd = v - p0 * p0.dot(v);
    close(
        &central(traj, H_SMOOTH),
        &pd,
        FD_SMOOTH,
        &format!("{ctx}: ṗ of the trajectory"),
    )?;
    let ad = central(|t| a(&traj(t)), H_SMOOTH);
    let am = a(p0);
    close(
        &skew(&omega_global(p0, &pd)),
        &(ad * am.transpose()),
        FD_SMOOTH,
        &format!("{ctx}: ω̃ = Ȧ Aᵀ"),
    )?;
    close(
        &skew(&omega_local(p0, &pd)),
        &(am.transpose() * ad),
        FD_SMOOTH,
        &format!("{ctx}: ω̃' = Aᵀ Ȧ"),
    )
}

#[test]
fn omega_maps_match_finite_differences_on_curated_p() {
    for (name, p) in curated_unit_p() {
        for v in [
            Vector4::new(0.7, -0.2, 0.5, -1.1),
            Vector4::new(0.0, 1.0, -1.0, 0.5),
        ] {
            let ctx = format!(
                "p = {name} {:?}, direction {:?}",
                p.as_slice(),
                v.as_slice()
            );
            if let Err(m) = check_omega_on_line(&p, &v, &ctx) {
                panic!("{m}");
            }
        }
    }
}

#[test]
fn constant_body_rate_trajectory_has_that_rate() {
    // p(t) = p0 ⊗ exp(t ω'/2) turns with the constant body angular velocity ω'.
    let w = Vector3::new(0.3, -1.2, 2.0);
    for (name, p0) in curated_unit_p() {
        let traj = |t: f64| qmul(&p0, &qexp(&w.normalize(), t * w.norm()));
        let pd = central(traj, H_SMOOTH);
        let ctx = format!("p0 = {name}");
        assert_close(
            &omega_local(&p0, &pd),
            &w,
            FD_SMOOTH,
            &format!("{ctx}: ω' = 2 L ṗ"),
        );
        assert_close(
            &omega_global(&p0, &pd),
            &(a(&p0) * w),
            FD_SMOOTH,
            &format!("{ctx}: ω = A ω'"),
        );
        assert_close(
            &p_dot_from_local(&p0, &w),
            &pd,
            FD_SMOOTH,
            &format!("{ctx}: ṗ = ½ Lᵀ ω'"),
        );
        // Constant ω' ⇒ ω̇' = 0 ⇒ p̈ = −¼ |ω'|² p.
        let pdd = central_second(traj, H_SECOND);
        let want = p_ddot_from_local(&p0, &w, &Vector3::zeros());
        assert_close(&want, &pdd, FD_SECOND, &format!("{ctx}: p̈ with ω̇' = 0"));
    }
}

// ---------------------------------------------------------------------------------------------
// ṗ ↔ ω' and p̈.
// ---------------------------------------------------------------------------------------------

fn check_rate_maps(p: &Vector4<f64>, w: &Vector3<f64>, ctx: &str) -> Result<(), String> {
    let pd = p_dot_from_local(p, w);
    close(
        &omega_local(p, &pd),
        w,
        EXACT,
        &format!("{ctx}: ω' → ṗ → ω'"),
    )?;
    if p.dot(&pd).abs() > EXACT {
        return Err(format!("{ctx}: pᵀṗ = {:e}, want 0", p.dot(&pd)));
    }
    // Independent: ṗ = ½ p ⊗ [0, ω'].
    let quat = qmul(p, &Vector4::new(0.0, w.x, w.y, w.z)) * 0.5;
    close(&pd, &quat, EXACT, &format!("{ctx}: ṗ = ½ p ⊗ [0, ω']"))?;
    let wg = a(p) * w;
    close(
        &omega_global(p, &pd),
        &wg,
        EXACT,
        &format!("{ctx}: ω = A ω'"),
    )?;
    close(
        &p_dot_from_global(p, &wg),
        &pd,
        EXACT,
        &format!("{ctx}: ṗ = ½ Gᵀ ω"),
    )?;
    // Back from a tangent ṗ.
    close(
        &p_dot_from_local(p, &omega_local(p, &pd)),
        &pd,
        EXACT,
        &format!("{ctx}: ṗ → ω' → ṗ"),
    )?;
    close(
        &p_dot_from_global(p, &omega_global(p, &pd)),
        &pd,
        EXACT,
        &format!("{ctx}: ṗ → ω → ṗ"),
    )
}

fn check_p_ddot_algebra(
    p: &Vector4<f64>,
    w: &Vector3<f64>,
    wd: &Vector3<f64>,
    ctx: &str,
) -> Result<(), String> {
    let pd = p_dot_from_local(p, w);
    let pdd = p_ddot_from_local(p, w, wd);
    close(
        &(l(p) * pdd * 2.0),
        wd,
        EXACT,
        &format!("{ctx}: 2 L p̈ = ω̇'"),
    )?;
    let (lhs, rhs) = (p.dot(&pdd), -pd.dot(&pd));
    if (lhs - rhs).abs() > EXACT * (1.0 + rhs.abs()) {
        return Err(format!("{ctx}: pᵀp̈ = {lhs:e}, want −ṗᵀṗ = {rhs:e}"));
    }
    // Global form: 2 G p̈ = ω̇ = A ω̇' (since Ġṗ = 0 and ω̇ = A ω̇' + Ȧ ω' = A ω̇' + A ω̃' ω').
    close(
        &(g(p) * pdd * 2.0),
        &(a(p) * wd),
        EXACT,
        &format!("{ctx}: 2 G p̈ = A ω̇'"),
    )
}

/// The two-rotation trajectory A(t) = A0 R(u1, α(t)) R(u2, β(t)) with quadratic α, β, whose body
/// angular velocity and acceleration are known in closed form (no crate code involved):
/// ω' = α̇ R2ᵀ u1 + β̇ u2,  ω̇' = α̈ R2ᵀ u1 − α̇ β̇ ũ2 R2ᵀ u1 + β̈ u2.
struct TwoRotations {
    p0: Vector4<f64>,
    u1: Vector3<f64>,
    u2: Vector3<f64>,
    al: [f64; 3],
    be: [f64; 3],
}

impl TwoRotations {
    fn angles(&self, t: f64) -> (f64, f64, f64, f64, f64, f64) {
        let [a0, a1, a2] = self.al;
        let [b0, b1, b2] = self.be;
        (
            a0 + a1 * t + a2 * t * t,
            a1 + 2.0 * a2 * t,
            2.0 * a2,
            b0 + b1 * t + b2 * t * t,
            b1 + 2.0 * b2 * t,
            2.0 * b2,
        )
    }
    fn p(&self, t: f64) -> Vector4<f64> {
        let (al, _, _, be, _, _) = self.angles(t);
        qmul(&qmul(&self.p0, &qexp(&self.u1, al)), &qexp(&self.u2, be))
    }
    fn omega_local(&self, t: f64) -> (Vector3<f64>, Vector3<f64>) {
        let (_, ad, add, be, bd, bdd) = self.angles(t);
        let r2t_u1 = rodrigues(&self.u2, be).transpose() * self.u1;
        let w = r2t_u1 * ad + self.u2 * bd;
        let wd = r2t_u1 * add - self.u2.cross(&r2t_u1) * (ad * bd) + self.u2 * bdd;
        (w, wd)
    }
    fn check(&self, t0: f64, ctx: &str) -> Result<(), String> {
        let p = self.p(t0);
        let (w, wd) = self.omega_local(t0);
        let pd_fd = central(|h| self.p(t0 + h), H_SMOOTH);
        close(
            &p_dot_from_local(&p, &w),
            &pd_fd,
            FD_SMOOTH,
            &format!("{ctx}: ṗ = ½ Lᵀ ω'"),
        )?;
        close(
            &omega_local(&p, &pd_fd),
            &w,
            FD_SMOOTH,
            &format!("{ctx}: ω' = 2 L ṗ"),
        )?;
        let ad_fd = central(|h| a(&self.p(t0 + h)), H_SMOOTH);
        close(
            &skew(&w),
            &(a(&p).transpose() * ad_fd),
            FD_SMOOTH,
            &format!("{ctx}: ω̃' = Aᵀ Ȧ"),
        )?;
        close(
            &skew(&(a(&p) * w)),
            &(ad_fd * a(&p).transpose()),
            FD_SMOOTH,
            &format!("{ctx}: ω̃ = Ȧ Aᵀ"),
        )?;
        let pdd_fd = central_second(|h| self.p(t0 + h), H_SECOND);
        close(
            &p_ddot_from_local(&p, &w, &wd),
            &pdd_fd,
            FD_SECOND,
            &format!("{ctx}: p̈ vs second differences"),
        )?;
        // ω̇' itself against a difference of 2 L ṗ along the trajectory (checks the closed form).
        let wd_fd = central(
            |h| {
                let q = self.p(t0 + h);
                let qd = central(|k| self.p(t0 + h + k), H_SECOND);
                omega_local(&q, &qd)
            },
            H_SECOND,
        );
        close(&wd, &wd_fd, FD_SECOND, &format!("{ctx}: closed-form ω̇'"))
    }
}

#[test]
fn p_ddot_matches_second_differences_on_curated_p() {
    for (name, p0) in curated_unit_p() {
        let tr = TwoRotations {
            p0,
            u1: Vector3::new(1.0, -2.0, 3.0).normalize(),
            u2: Vector3::new(-0.5, 0.4, 1.0).normalize(),
            al: [0.2, 1.3, -0.8],
            be: [-0.4, 0.9, 1.5],
        };
        for t0 in [0.0, 0.37] {
            if let Err(m) = tr.check(t0, &format!("p0 = {name} {:?}, t0 = {t0}", p0.as_slice())) {
                panic!("{m}");
            }
        }
    }
}

#[test]
fn rate_maps_and_p_ddot_algebra_on_curated_p() {
    for (name, p) in curated_unit_p() {
        for w in curated_vectors() {
            let wd = Vector3::new(-0.3, 2.0, 0.8);
            let ctx = format!("p = {name} {:?}, ω' = {:?}", p.as_slice(), w.as_slice());
            if let Err(m) =
                check_rate_maps(&p, &w, &ctx).and_then(|_| check_p_ddot_algebra(&p, &w, &wd, &ctx))
            {
                panic!("{m}");
            }
        }
    }
}

#[test]
fn p_dot_from_local_is_tangent_for_unnormalized_p() {
    for (name, p) in curated_unnormalized_p() {
        let pd = p_dot_from_local(&p, &Vector3::new(0.3, -1.2, 2.0));
        assert!(
            p.dot(&pd).abs() <= EXACT,
            "p = {name}: pᵀṗ = {:e}",
            p.dot(&pd)
        );
    }
}

proptest! {
    #[test]
    fn prop_da_dp_matches_finite_differences(p in prop_oneof![unit_p(), unnormalized_p()], v in vec3()) {
        if let Err(m) = check_da_dp(&p, &v, "random p, a'") { return Err(TestCaseError::fail(m)); }
    }

    #[test]
    fn prop_da_dpi_local_matches_finite_differences(p in unit_p(), v in vec3()) {
        if let Err(m) = check_da_dpi(&p, &v, "random p, a'") { return Err(TestCaseError::fail(m)); }
    }

    #[test]
    fn prop_a_dot_matches_finite_differences(p in prop_oneof![unit_p(), unnormalized_p()], pd in vec4()) {
        if let Err(m) = check_a_dot(&p, &pd, "random p, ṗ") { return Err(TestCaseError::fail(m)); }
    }

    #[test]
    fn prop_g_dot_l_dot_are_time_derivatives(p in prop_oneof![unit_p(), unnormalized_p()], pd in vec4()) {
        // G and L are linear in p, so a central difference along p + ṗ t is exact up to round-off.
        prop_close!(g_dot(&pd), central(|t| g(&(p + pd * t)), H_QUADRATIC), FD_QUADRATIC, "Ġ = d G(p + ṗ t)/dt");
        prop_close!(l_dot(&pd), central(|t| l(&(p + pd * t)), H_QUADRATIC), FD_QUADRATIC, "L̇ = d L(p + ṗ t)/dt");
    }

    #[test]
    fn prop_omega_maps_match_finite_differences(p in unit_p(), v in vec4()) {
        if let Err(m) = check_omega_on_line(&p, &v, "random p, direction") { return Err(TestCaseError::fail(m)); }
    }

    #[test]
    fn prop_rate_maps_round_trip(p in unit_p(), w in vec3(), wd in vec3()) {
        if let Err(m) = check_rate_maps(&p, &w, "random p, ω'") { return Err(TestCaseError::fail(m)); }
        if let Err(m) = check_p_ddot_algebra(&p, &w, &wd, "random p, ω', ω̇'") { return Err(TestCaseError::fail(m)); }
    }

    #[test]
    fn prop_p_ddot_matches_second_differences(
        p0 in unit_p(), u1 in unit_axis(), u2 in unit_axis(),
        al in prop::array::uniform3(-1.5f64..1.5), be in prop::array::uniform3(-1.5f64..1.5),
        t0 in -0.5f64..0.5,
    ) {
        let tr = TwoRotations { p0, u1, u2, al, be };
        if let Err(m) = tr.check(t0, "random trajectory") { return Err(TestCaseError::fail(m)); }
    }
}
