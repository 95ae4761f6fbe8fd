//! Continued angles and their jets: the one nonlinear function the couplers add to the dot
//! products of [`crate::jet`].
//!
//! An angle θ = atan2(s, c) of two smooth scalars s, c (a sine and a cosine up to a common
//! positive factor ρ² = s² + c²) is continued over turns from a reference θ_ref (the angle at
//! the last accepted pose):
//!
//! ```text
//! θ  = θ_ref + atan2(s cos θ_ref − c sin θ_ref,  c cos θ_ref + s sin θ_ref)
//!    = the value of atan2(s, c) + 2πk nearest to θ_ref          (smooth while |θ − θ_ref| < π)
//! ∇θ = (c ∇s − s ∇c) / ρ²
//! θ̇  = (c ṡ − s ċ) / ρ²
//! θ̈  = (c s̈ − s c̈) / ρ² − 2 θ̇ (s ṡ + c ċ) / ρ²
//! ```
//!
//! The derivatives do not depend on θ_ref; only Φ does. With s̈, c̈ replaced by their
//! velocity-quadratic parts, the last line is the velocity-quadratic part of θ̈ (what γ# needs).

use crate::jet::{ScalarGrad, ScalarMotion};

/// The value of atan2(s, c) + 2πk nearest to `reference` (k an integer), computed without a
/// jump: `reference` plus the principal angle from `reference` to (c, s).
pub fn continued_angle(reference: f64, s: f64, c: f64) -> f64 {
    let (sr, cr) = reference.sin_cos();
    reference + (s * cr - c * sr).atan2(c * cr + s * sr)
}

/// ∇θ of θ = atan2(s, c) from the gradients of s and c.
pub fn angle_grad<const N: usize>(s: &ScalarGrad<N>, c: &ScalarGrad<N>) -> ScalarGrad<N> {
    let rho2 = s.v * s.v + c.v * c.v;
    ScalarGrad {
        v: s.v.atan2(c.v),
        di: (s.di * c.v - c.di * s.v) / rho2,
        dj: (s.dj * c.v - c.dj * s.v) / rho2,
    }
}

/// θ, θ̇ and the velocity-quadratic part of θ̈ of θ = atan2(s, c) (principal value).
pub fn angle_motion(s: &ScalarMotion, c: &ScalarMotion) -> ScalarMotion {
    let rho2 = s.v * s.v + c.v * c.v;
    let rate = (c.v * s.rate - s.v * c.rate) / rho2;
    let quad =
        (c.v * s.quad - s.v * c.quad) / rho2 - 2.0 * rate * (s.v * s.rate + c.v * c.rate) / rho2;
    ScalarMotion {
        v: s.v.atan2(c.v),
        rate,
        quad,
    }
}

/// ∇θ of θ = asin(s) from the gradient of s (|s| < 1).
pub fn asin_grad<const N: usize>(s: &ScalarGrad<N>) -> ScalarGrad<N> {
    let c = (1.0 - s.v * s.v).sqrt();
    ScalarGrad {
        v: s.v.asin(),
        di: s.di / c,
        dj: s.dj / c,
    }
}

/// θ, θ̇ and the velocity-quadratic part of θ̈ of θ = asin(s) (|s| < 1): θ̇ = ṡ/c,
/// θ̈ = s̈/c + s ṡ²/c³ with c = √(1 − s²).
pub fn asin_motion(s: &ScalarMotion) -> ScalarMotion {
    let c2 = 1.0 - s.v * s.v;
    let c = c2.sqrt();
    ScalarMotion {
        v: s.v.asin(),
        rate: s.rate / c,
        quad: s.quad / c + s.v * s.rate * s.rate / (c2 * c),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    #[test]
    fn continued_angle_is_nearest_to_the_reference() {
        for k in -5..=5 {
            let th = 0.3 + 2.0 * PI * k as f64;
            let v = continued_angle(th + 0.4, th.sin() * 2.0, th.cos() * 2.0);
            assert!((v - th).abs() < 1e-12, "{v} {th}");
        }
        // Across the branch cut of atan2.
        let v = continued_angle(PI - 0.1, (PI + 0.2).sin(), (PI + 0.2).cos());
        assert!((v - (PI + 0.2)).abs() < 1e-12);
    }
}
