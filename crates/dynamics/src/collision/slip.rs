//! The slope of a contact's friction along its slip that the implicit tangent takes
//! ([`along_slope`]), chosen from the slips of the contact point at the pair's last evaluations
//! (the Newton iterates of a generalized-α step).
//!
//! ## Why not the derivative
//! Per unit normal force the friction's magnitude is ψ(s) = φ(s) s = μ(s) s / √(s² + v_s²)
//! ([`super::law`]): odd, increasing, concave for s > 0 and saturated beyond a few v_s. Along the
//! slip, one contact of an implicit step solves about a (s − s_p) + F_n ψ(s) = 0 (a the
//! inertia the iteration matrix gives the slip, s_p the slip without friction). Where the
//! friction outweighs the inertia (F_n ψ' ≫ a: a pile's contacts near the friction limit,
//! creeping at slips of about v_s), the three slopes a Newton step can take behave so:
//!
//! - the derivative ψ'(s): from above the solution it overshoots from one side of the steep
//!   part to the other (from s = v_s it lands at −v_s, then cycles); from below it is
//!   monotone (the tangent of a concave function lies above it);
//! - the secant φ(s) = ψ(s)/s (a lagged viscosity): the chord to s = 0, never crosses the
//!   solution, but contracts only linearly, by about 1 − ψ'/φ per iteration (a half at
//!   s = v_s);
//! - the chord to the solution s*, (ψ(s) − ψ(s*))/(s − s*): one step, were s* known.
//!
//! So: a slip that grew since the last iterate in the same direction approaches from below and
//! takes ψ'; a slip that shrank twice in a row in the same direction takes the chord to the
//! solution estimated by Aitken's Δ² from its last three values (for a linearly converging
//! sequence, s* ≈ s − (s − s₁)² / (s − 2 s₁ + s₂)), kept between ψ'(s) and φ(s); anything else
//! (a new contact, a reversal, a first iterate) the secant. Only the iteration matrix changes:
//! each iterate's forces are the law's, and the step converges on the residual.

use super::law::PairLaw;
use nalgebra::Vector3;

/// The slips v_t of one contact point at its pair's last two evaluations.
#[derive(Debug, Clone, Copy, Default)]
pub(super) struct SlipMemory {
    last: Vector3<f64>,
    before: Vector3<f64>,
}

/// Whether slip a points the same way as slip b (within 60°).
fn same_way(a: &Vector3<f64>, b: &Vector3<f64>) -> bool {
    a.dot(b) > 0.5 * a.norm() * b.norm()
}

/// The slope σ along the slip v_t (per unit F_n) for the tangent at this evaluation (module
/// docs), given the secant `phi` = φ(|v_t|) the force took; `run`: how many evaluations of
/// the pair in a row came just before this one (so `memory` holds that many of this point's
/// slips, up to two). Records v_t in `memory`.
pub(super) fn along_slope(
    law: &PairLaw,
    vt: &Vector3<f64>,
    phi: f64,
    memory: &mut SlipMemory,
    run: u32,
) -> f64 {
    let s = vt.norm();
    let (s1, s2) = (memory.last.norm(), memory.before.norm());
    let along1 = run >= 1 && same_way(vt, &memory.last);
    let along2 = along1 && run >= 2 && same_way(&memory.last, &memory.before);
    let slope = if along1 && s > s1 {
        law.friction_slope(s)
    } else if along2 && s < s1 && s1 < s2 && s - 2.0 * s1 + s2 > 0.0 {
        let root = s - (s - s1) * (s - s1) / (s - 2.0 * s1 + s2);
        if (0.0..s).contains(&root) {
            let psi = |x: f64| law.friction_factor(x) * x;
            let chord = (psi(s) - psi(root)) / (s - root);
            // ψ'(s) ≤ φ(s) but for roundoff near s = 0 (both μ/v_s): no `clamp`, which
            // panics on crossed bounds.
            chord.max(law.friction_slope(s)).min(phi)
        } else {
            phi
        }
    } else {
        phi
    };
    memory.before = memory.last;
    memory.last = *vt;
    slope
}

#[cfg(test)]
mod tests {
    use super::*;

    fn law() -> PairLaw {
        PairLaw {
            k: 1e7,
            n: 1.5,
            a: 0.0,
            e: 1.0,
            mu_s: 0.3,
            mu_d: 0.3,
            vs: 1e-3,
        }
    }

    /// The 1D model of the module docs, a (s − s_p) + F ψ(s) = 0 with the friction dominant
    /// (F ψ'(0) = 300 a), solved by Newton with a slope rule from the frictionless slip s_p:
    /// the iterations to 1e-12 relative, or None after 200.
    fn iterations(
        sp: f64,
        rule: impl Fn(&PairLaw, f64, &mut SlipMemory, u32) -> f64,
    ) -> Option<usize> {
        let law = law();
        let (a, f) = (1.0, 1.0);
        let g = |s: f64| a * (s - sp) + f * law.friction_factor(s.abs()) * s;
        let mut s = sp;
        let mut memory = SlipMemory::default();
        for it in 0..200 {
            if g(s).abs() <= 1e-12 * a * sp {
                return Some(it);
            }
            let sigma = rule(&law, s, &mut memory, it as u32);
            s -= g(s) / (a + f * sigma);
        }
        None
    }

    #[test]
    fn the_chosen_slope_converges_where_the_secant_crawls_and_the_derivative_cycles() {
        let v = |s: f64| Vector3::new(s, 0.0, 0.0);
        // s_p = 0.2125 m/s: the solution creeps at about v_s; s_p = 0.3: at a few v_s.
        for sp in [0.2125, 0.3] {
            let secant = iterations(sp, |law, s, _, _| law.friction_factor(s.abs()));
            let chosen = iterations(sp, |law, s, m, run| {
                along_slope(law, &v(s), law.friction_factor(s.abs()), m, run)
            })
            .expect("the chosen slope converges");
            assert!(
                secant.is_none_or(|k| 2 * chosen <= k),
                "s_p {sp}: chosen {chosen} against the secant's {secant:?} iterations"
            );
        }
        let derivative = iterations(0.2125, |law, s, _, _| law.friction_slope(s.abs()));
        assert!(
            derivative.is_none(),
            "the derivative converged: {derivative:?}"
        );
    }

    #[test]
    fn a_reversed_or_new_slip_takes_the_secant() {
        let law = law();
        let mut m = SlipMemory::default();
        let x = |s: f64| Vector3::new(s, 0.0, 0.0);
        let phi = |s: f64| law.friction_factor(s);
        assert_eq!(along_slope(&law, &x(2e-3), phi(2e-3), &mut m, 0), phi(2e-3));
        // Grown the same way: the derivative.
        assert_eq!(
            along_slope(&law, &x(3e-3), phi(3e-3), &mut m, 1),
            law.friction_slope(3e-3)
        );
        // Reversed: the secant.
        assert_eq!(
            along_slope(&law, &x(-1e-3), phi(1e-3), &mut m, 2),
            phi(1e-3)
        );
        // After a gap in the evaluations: the secant, whatever the memory says.
        assert_eq!(
            along_slope(&law, &x(-2e-3), phi(2e-3), &mut m, 0),
            phi(2e-3)
        );
    }
}
