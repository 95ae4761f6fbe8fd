//! The contact law of one touching pair: a Hunt–Crossley normal force whose hysteresis gives
//! the material's coefficient of restitution exactly, and regularized Coulomb friction with a
//! static and a dynamic coefficient.
//!
//! ## Normal force
//! With the penetration δ > 0, its rate δ̇ (positive while approaching) and the approach speed
//! v₀ at the onset of the contact (Hunt & Crossley 1975; Lankarani & Nikravesh 1990):
//!
//! ```text
//! F_n = max(0, K δⁿ (1 + (a / v₀) δ̇))
//! ```
//!
//! For a normal impact of a mass m, m δ̈ = −F_n has the first integral
//! (m/α²)(α δ̇ − ln(1 + α δ̇)) + K δⁿ⁺¹/(n + 1) = const with α = a/v₀. Equating it at the
//! onset (δ = 0, δ̇ = v₀) and at the separation (δ = 0, δ̇ = −e v₀) gives the exact relation
//! between a and the coefficient of restitution e, independent of m, K and n:
//!
//! ```text
//! a − ln(1 + a) = −a e − ln(1 − a e)          (a > 0, a e < 1)
//! ```
//!
//! ([`hysteresis`] solves it; e = 1 gives a = 0, e → 0 gives a ≈ 1/e). So the rebound speed
//! of a normal impact is e v₀ to the accuracy of the integration, whatever the masses and the
//! stiffness: the approximations of Lankarani–Nikravesh (a = 3(1 − e²)/4) or Flores
//! (a = 8(1 − e)/(5e)) are not needed. During the rebound α δ̇ ≥ −a e > −1, so F_n stays
//! positive (no sticking force) for a normal impact; the max(0, ·) guards oblique cases.
//! A contact that starts slower than [`ONSET_SPEED_FLOOR`] (a body set down, a resting stack)
//! takes v₀ at the floor: its damping stays finite and it bounces less than e would say.
//!
//! ## Stiffness
//! K and n from the two materials ([`cardan_mechanism::Stiffness`]): Hertz's
//! K = 4/3 E* √R* with n = 3/2 for two elastic materials (Johnson 1985, §4.2), springs in
//! K = K₁K₂/(K₁ + K₂) for two direct stiffnesses (compliances add, as the
//! 1/E of Hertz's E* do: two equal materials of K give K/2).
//!
//! ## Friction
//! With the slip velocity v_t (the tangential part of the relative velocity of the contact
//! point) and s = |v_t|:
//!
//! ```text
//! f_t = −μ(s) F_n v_t / √(s² + v_s²),     μ(s) = μ_d + (μ_s − μ_d) e^(−(s/v_s)²)
//! ```
//!
//! Coulomb's law regularized over v_s (the stiction model of the joints' friction): below v_s it
//! acts as a steep viscous law, so a contact "sticks" by creeping at a speed of the order of
//! v_s times the ratio of the tangential load to μ F_n; above a few v_s the coefficient is μ_d.

use cardan_mechanism::{Geometry, MaterialInfo, Stiffness};

/// The smallest approach speed v₀ (m/s) the damping of a contact is scaled by (module docs).
pub const ONSET_SPEED_FLOOR: f64 = 1e-3;

/// The law of one pair of touching shapes (module docs).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PairLaw {
    /// K (N/m^n).
    pub k: f64,
    /// n.
    pub n: f64,
    /// The hysteresis a of the restitution e ([`hysteresis`]).
    pub a: f64,
    /// e.
    pub e: f64,
    /// μ_s.
    pub mu_s: f64,
    /// μ_d.
    pub mu_d: f64,
    /// v_s (m/s).
    pub vs: f64,
}

/// The hysteresis a > 0 with a − ln(1 + a) = −a e − ln(1 − a e) for e ∈ (0, 1) (module docs);
/// 0 for e = 1. Bisection on a e ∈ (0, 1), then Newton: to roundoff.
pub fn hysteresis(e: f64) -> f64 {
    if e >= 1.0 {
        return 0.0;
    }
    // In b = a e ∈ (0, 1): f(b) = (b/e − ln(1 + b/e)) + (b + ln(1 − b)) is b²(1/e² − 1)/2 > 0
    // near 0 and → −∞ as b → 1, with one root between.
    let f = |b: f64| (b / e - (b / e).ln_1p()) + (b + (-b).ln_1p());
    let (mut lo, mut hi) = (0.0_f64, 1.0_f64);
    for _ in 0..1100 {
        let mid = 0.5 * (lo + hi);
        if mid <= lo || mid >= hi {
            break;
        }
        if f(mid) > 0.0 {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    0.5 * (lo + hi) / e
}

impl PairLaw {
    /// The law between materials `m1` on a shape of `g1` and `m2` on one of `g2`. Two elastic
    /// materials need a curved shape on one side (checked when the model is built); two direct
    /// stiffnesses of different exponents take the softer one's exponent; an elastic and a
    /// direct one take the direct stiffness.
    pub fn new(m1: &MaterialInfo, g1: &Geometry, m2: &MaterialInfo, g2: &Geometry) -> PairLaw {
        let (k, n) = match (m1.stiffness, m2.stiffness) {
            (
                Stiffness::Elastic {
                    youngs_modulus: e1,
                    poisson_ratio: nu1,
                },
                Stiffness::Elastic {
                    youngs_modulus: e2,
                    poisson_ratio: nu2,
                },
            ) => {
                let e_star = 1.0 / ((1.0 - nu1 * nu1) / e1 + (1.0 - nu2 * nu2) / e2);
                let r_star = 1.0 / (1.0 / g1.curvature_radius() + 1.0 / g2.curvature_radius());
                (4.0 / 3.0 * e_star * r_star.sqrt(), 1.5)
            }
            (
                Stiffness::Direct {
                    k: k1,
                    exponent: n1,
                },
                Stiffness::Direct {
                    k: k2,
                    exponent: n2,
                },
            ) => {
                let n = if k1 <= k2 { n1 } else { n2 };
                (k1 * k2 / (k1 + k2), n)
            }
            // One elastic, one direct: the direct one is taken as the pair's.
            (Stiffness::Direct { k, exponent }, _) | (_, Stiffness::Direct { k, exponent }) => {
                (k, exponent)
            }
        };
        let e = m1.restitution.min(m2.restitution);
        PairLaw {
            k,
            n,
            a: hysteresis(e),
            e,
            mu_s: m1.friction_static.min(m2.friction_static),
            mu_d: m1.friction_dynamic.min(m2.friction_dynamic),
            vs: m1.slip_velocity.min(m2.slip_velocity),
        }
    }

    /// The law a pair material declares ([`cardan_mechanism::MaterialSpec::between`]): its
    /// stiffness, exponent, restitution and friction as they are, not combined.
    pub fn of_pair(m: &MaterialInfo) -> PairLaw {
        let (k, n) = match m.stiffness {
            Stiffness::Direct { k, exponent } => (k, exponent),
            // Refused when the model is built.
            Stiffness::Elastic { .. } => (f64::NAN, 1.5),
        };
        PairLaw {
            k,
            n,
            a: hysteresis(m.restitution),
            e: m.restitution,
            mu_s: m.friction_static,
            mu_d: m.friction_dynamic,
            vs: m.slip_velocity,
        }
    }

    /// F_n at penetration δ ≥ 0, rate δ̇ and onset speed v₀ (module docs).
    pub fn normal_force(&self, delta: f64, delta_dot: f64, v0: f64) -> f64 {
        if delta <= 0.0 {
            return 0.0;
        }
        let v0 = v0.max(ONSET_SPEED_FLOOR);
        (self.k * delta.powf(self.n) * (1.0 + self.a / v0 * delta_dot)).max(0.0)
    }

    /// (∂F_n/∂δ, ∂F_n/∂δ̇) at penetration δ, rate δ̇ and onset speed v₀ (0 where F_n is 0).
    pub fn normal_slopes(&self, delta: f64, delta_dot: f64, v0: f64) -> (f64, f64) {
        if self.normal_force(delta, delta_dot, v0) <= 0.0 {
            return (0.0, 0.0);
        }
        let v0 = v0.max(ONSET_SPEED_FLOOR);
        let dn = delta.powf(self.n);
        let k = self.k * self.n * delta.powf(self.n - 1.0) * (1.0 + self.a / v0 * delta_dot);
        (k, self.k * dn * self.a / v0)
    }

    /// The slope of the friction's magnitude per unit normal force, ψ(s) = φ(s) s:
    /// dψ/ds = μ'(s) s / √(s² + v_s²) + μ(s) v_s² / (s² + v_s²)^(3/2), at least 0 (past a
    /// Stribeck drop it is negative; the implicit tangent takes no negative slope).
    pub fn friction_slope(&self, slip: f64) -> f64 {
        if self.mu_s == 0.0 {
            return 0.0;
        }
        let x = slip / self.vs;
        let g = (-x * x).exp();
        let mu = self.mu_d + (self.mu_s - self.mu_d) * g;
        let dmu = (self.mu_s - self.mu_d) * g * (-2.0 * x / self.vs);
        let r2 = slip * slip + self.vs * self.vs;
        let r = r2.sqrt();
        (dmu * slip / r + mu * self.vs * self.vs / (r2 * r)).max(0.0)
    }

    /// The factor φ(s) = μ(s) / √(s² + v_s²) with f_t = −φ F_n v_t (module docs).
    pub fn friction_factor(&self, slip: f64) -> f64 {
        if self.mu_s == 0.0 {
            return 0.0;
        }
        let x = slip / self.vs;
        let mu = self.mu_d + (self.mu_s - self.mu_d) * (-x * x).exp();
        mu / (slip * slip + self.vs * self.vs).sqrt()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The rebound speed of a normal impact of mass m at speed v₀ under the law (RK4 with
    /// steps of 1e-4 of the contact time's scale), as a ratio to v₀.
    fn rebound_ratio(law: &PairLaw, m: f64, v0: f64) -> f64 {
        let t_scale = (m / (law.k * v0.powf(law.n - 1.0))).powf(1.0 / (law.n + 1.0));
        let dt = 1e-4 * t_scale;
        let acc = |d: f64, dd: f64| -law.normal_force(d, dd, v0) / m;
        let (mut d, mut dd) = (0.0, v0);
        loop {
            let (k1x, k1v) = (dd, acc(d, dd));
            let (k2x, k2v) = (
                dd + 0.5 * dt * k1v,
                acc(d + 0.5 * dt * k1x, dd + 0.5 * dt * k1v),
            );
            let (k3x, k3v) = (
                dd + 0.5 * dt * k2v,
                acc(d + 0.5 * dt * k2x, dd + 0.5 * dt * k2v),
            );
            let (k4x, k4v) = (dd + dt * k3v, acc(d + dt * k3x, dd + dt * k3v));
            let d1 = d + dt / 6.0 * (k1x + 2.0 * k2x + 2.0 * k3x + k4x);
            let dd1 = dd + dt / 6.0 * (k1v + 2.0 * k2v + 2.0 * k3v + k4v);
            if d1 <= 0.0 {
                // Linear interpolation of the speed to δ = 0.
                let s = d / (d - d1);
                return -(dd + s * (dd1 - dd)) / v0;
            }
            (d, dd) = (d1, dd1);
        }
    }

    #[test]
    fn the_hysteresis_gives_the_restitution_whatever_the_mass_stiffness_and_speed() {
        for e in [0.05, 0.2, 0.5, 0.8, 0.99] {
            for (m, k, n, v0) in [
                (1.0, 1e8, 1.5, 2.0),
                (0.01, 1e5, 1.0, 0.1),
                (50.0, 1e10, 1.5, 7.0),
            ] {
                let law = PairLaw {
                    k,
                    n,
                    a: hysteresis(e),
                    e,
                    mu_s: 0.0,
                    mu_d: 0.0,
                    vs: 1e-3,
                };
                let ratio = rebound_ratio(&law, m, v0);
                assert!((ratio - e).abs() < 1e-6, "e = {e}, m = {m}: {ratio}");
            }
        }
        assert_eq!(hysteresis(1.0), 0.0);
    }

    #[test]
    fn the_friction_slope_is_the_derivative_of_its_magnitude() {
        // With a Stribeck drop (μ_s > μ_d) ψ' turns negative past the drop: clamped to 0.
        for (mu_s, mu_d) in [(0.3, 0.3), (0.5, 0.3)] {
            let law = PairLaw {
                k: 1e7,
                n: 1.5,
                a: 0.0,
                e: 1.0,
                mu_s,
                mu_d,
                vs: 1e-3,
            };
            let psi = |s: f64| law.friction_factor(s) * s;
            for s in [0.0, 2e-4, 1e-3, 1.7e-3, 5e-3, 0.1] {
                let h = 1e-7;
                let numeric = (psi(s + h) - psi((s - h).max(0.0))) / (s + h - (s - h).max(0.0));
                let want = numeric.max(0.0);
                let got = law.friction_slope(s);
                assert!(
                    (got - want).abs() <= 1e-6 * (1.0 + want.abs()),
                    "μ_s {mu_s}, s = {s}: {got} against {want}"
                );
            }
        }
    }

    #[test]
    fn hysteresis_solves_its_equation_to_roundoff() {
        for e in [0.1, 0.5, 0.9, 0.999] {
            let a = hysteresis(e);
            let lhs = a - a.ln_1p();
            let rhs = -a * e - (-a * e).ln_1p();
            assert!((lhs - rhs).abs() <= 1e-12 * lhs, "e = {e}: {lhs} vs {rhs}");
        }
    }
}
