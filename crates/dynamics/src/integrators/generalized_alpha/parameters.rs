//! The parameters of generalized-α from the spectral radius at infinite frequency ρ∞ (Chung &
//! Hulbert 1993; Arnold & Brüls 2007, §3), and the scalings of the iteration matrix for a step.

/// α_m, α_f, γ and β of generalized-α:
///
/// ```text
/// α_m = (2ρ∞ − 1)/(ρ∞ + 1),   α_f = ρ∞/(ρ∞ + 1),   γ = ½ + α_f − α_m,   β = ¼(γ + ½)²
/// ```
///
/// Second order for every ρ∞ ∈ [0, 1]; ρ∞ = 1 has no numerical damping.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Parameters {
    /// α_m.
    pub alpha_m: f64,
    /// α_f.
    pub alpha_f: f64,
    /// γ.
    pub gamma: f64,
    /// β.
    pub beta: f64,
}

impl Parameters {
    /// The parameters for ρ∞.
    pub fn from_rho_inf(rho_inf: f64) -> Self {
        let alpha_m = (2.0 * rho_inf - 1.0) / (rho_inf + 1.0);
        let alpha_f = rho_inf / (rho_inf + 1.0);
        let gamma = 0.5 + alpha_f - alpha_m;
        let beta = 0.25 * (gamma + 0.5) * (gamma + 0.5);
        Self {
            alpha_m,
            alpha_f,
            gamma,
            beta,
        }
    }

    /// β' = h²β(1 − α_f)/(1 − α_m): ∂q_{n+1}/∂v̇_{n+1} for a step of size `h` (the scaling of
    /// the stiffness in the iteration matrix, and of the position constraint).
    pub fn beta_prime(&self, h: f64) -> f64 {
        h * h * self.beta * (1.0 - self.alpha_f) / (1.0 - self.alpha_m)
    }

    /// γ' = hγ(1 − α_f)/(1 − α_m): ∂v_{n+1}/∂v̇_{n+1} for a step of size `h` (the scaling of
    /// the damping in the iteration matrix).
    pub fn gamma_prime(&self, h: f64) -> f64 {
        h * self.gamma * (1.0 - self.alpha_f) / (1.0 - self.alpha_m)
    }
}

#[cfg(test)]
mod tests {
    use super::Parameters;

    /// ρ∞ = 1: the trapezoidal rule (α_m = α_f = ½, γ = ½, β = ¼); ρ∞ = 0: the most damping.
    #[test]
    fn the_limits_of_rho_inf() {
        let p = Parameters::from_rho_inf(1.0);
        assert_eq!(
            (p.alpha_m, p.alpha_f, p.gamma, p.beta),
            (0.5, 0.5, 0.5, 0.25)
        );
        let p = Parameters::from_rho_inf(0.0);
        assert_eq!(
            (p.alpha_m, p.alpha_f, p.gamma, p.beta),
            (-1.0, 0.0, 1.5, 1.0)
        );
    }
}
