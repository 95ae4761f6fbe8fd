//! Power and work of the drivers and the non-conservative forces, and the energy balance.
//!
//! ## The work-energy theorem in the 6-coordinate form
//! With E = T + V, T = ½ vᵀ M v and V the potential of gravity and the springs (the energy
//! [`crate::Energy`] holds), the equations of motion M v̇ = h − Φ_vᵀ λ give
//!
//! ```text
//! dE/dt = vᵀ M v̇ + dV/dt = vᵀ h_nc − λᵀ Φ_v v
//! ```
//!
//! because the gyroscopic term does no work (ω'ᵀ (ω̃' J' ω') = 0) and the conservative forces'
//! power is −dV/dt (Haug 1989 §11.5; Nikravesh 1988 §11.6). What is left is the power of
//!
//! - the **non-conservative forces** h_nc: dampers −c ℓ̇² and −c θ̇², actuators −f_a ℓ̇ (tension
//!   positive, pulling the points together), point forces F · v_P, torques T · ω, the user
//!   callback vᵀ h_user ([`crate::Force`]);
//! - the **constraint forces** −Φ_vᵀλ, row by row −λ_r (Φ_v v)_r. On the motion Φ_v v = ν with
//!   ν = −Φ_t: joints and couplers do not depend on time (ν = 0), so **ideal joints do no work**
//!   (their power is recorded as a check, [`EnergyHistory::constraint_power`]); a driver's row
//!   has ν ≠ 0 and its power −λ (Φ_v v) = effort × rate of the driven coordinate
//!   ([`crate::DriverEfforts`]) is the energy the driver puts into the mechanism.
//!
//! Positive power is energy put **into** the mechanism. The work W(t) = ∫_{t₀}^{t} P dt of each
//! element, W_nc its sum, and then
//!
//! ```text
//! drift(t) = E(t) − E(t₀)            (physics plus integration error)
//! balance(t) = E(t) − E(t₀) − W_nc(t)  (integration error alone; 0 for the exact motion)
//! ```
//!
//! ## The quadratures
//! Output times may be far apart compared with the integration steps (and a damper's power
//! changes within an oscillation), so W is not a quadrature over the outputs:
//!
//! - **DOPRI5** carries W with the state: the same Runge–Kutta weights are applied to the power
//!   at the seven stage values, W₁ = W₀ + h Σ b_j P(t + c_j h, Y_j), and the outputs between
//!   steps use the same 4th-order continuous extension. This is exactly what DOPRI5 computes for
//!   the augmented system [y; W] with Ẇ = P(t, y): W is as accurate as the state (5th order per
//!   step), and E(y₁) − E(y₀) − ΔW is of the order of the step's local error. W is left out of
//!   the error estimate (so the steps, and every other output, are the same as without it); its
//!   accuracy follows from the state's, since P is a smooth function of the stage values. The
//!   projection after each step moves the state (and E) but not W: the balance includes its
//!   effect, which is of the order of the local error.
//! - **Generalized-α** (second order): the trapezoidal rule on each step,
//!   W_{n+1} = W_n + ½ h (P_n + P_{n+1}), with P at the step's end states: second order like
//!   the scheme, so the balance falls like h². The drivers' λ there is the one of the augmented
//!   system solved at the step's end (index 1), not the scheme's own index-3 λ_{n+1}, which is
//!   off by O(h) and made the balance of a driven model fall like h only (one more
//!   factorization per step, for models with drivers).
//! - **Inverse dynamics** (the motion is prescribed on the output grid, there are no steps):
//!   the trapezoidal rule on the output grid with Gregory's end corrections (`SampledWork`),
//!   fourth order in the output step; the balance measures that quadrature error (and the
//!   kinematic tolerance).
//!
//! [`EnergyHistory::constraint_power`]: crate::EnergyHistory::constraint_power

use crate::forces::AppliedForces;
use crate::kkt::Element;
use crate::results::ElementWork;
use crate::system::Dynamics;
use cardan_mechanism::BodyId;

/// Where the multipliers of the driver rows are read.
#[derive(Clone, Copy)]
pub(crate) enum Multipliers<'a> {
    /// One per model equation (redundant rows 0).
    Full(&'a [f64]),
    /// The last solution of the augmented system (active rows only; dropped rows 0).
    Solution,
}

impl Dynamics<'_> {
    /// The elements whose power and work are recorded, with empty histories: every driver in
    /// model order, every non-conservative force element, the user callback.
    pub(crate) fn work_channels(&self, capacity: usize) -> Vec<ElementWork> {
        let channel = |name: &str, kind| ElementWork {
            name: name.to_string(),
            kind,
            power: Vec::with_capacity(capacity),
            work: Vec::with_capacity(capacity),
        };
        let mut out: Vec<ElementWork> = self
            .model
            .drivers()
            .iter()
            .map(|d| channel(&d.name, "driver"))
            .collect();
        for (f, name) in self.forces.iter().zip(&self.force_names) {
            if f.is_non_conservative() {
                out.push(channel(name, "force"));
            }
        }
        if self.user.is_some() {
            out.push(channel("user", "user"));
        }
        for f in self.model.frictions() {
            out.push(channel(&f.name, "friction"));
        }
        if self.collisions.is_some() {
            out.push(channel("contact", "contact"));
        }
        for l in self.model.limits() {
            out.push(channel(&l.name, "limit"));
        }
        out
    }

    /// Adds each limit's impact work (the kinetic energy its impacts took) to its channel, the
    /// last ones of `work` ([`work_channels`](Self::work_channels)). Held stops do no work
    /// (ġ = 0), so the channel's power is 0 between impacts.
    pub(crate) fn add_impact_work(&self, work: &mut [f64]) {
        let nl = self.contacts.impact_work.len();
        let start = work.len() - nl;
        for (w, i) in work[start..].iter_mut().zip(&self.contacts.impact_work) {
            *w += i;
        }
    }

    /// The number of [`work_channels`](Self::work_channels).
    pub(crate) fn num_work_channels(&self) -> usize {
        self.model.drivers().len()
            + self
                .forces
                .iter()
                .filter(|f| f.is_non_conservative())
                .count()
            + usize::from(self.user.is_some())
            + self.model.frictions().len()
            + usize::from(self.collisions.is_some())
            + self.model.limits().len()
    }

    /// The power of each work channel at the synced bodies and time `t` into `out` (W, positive
    /// into the mechanism), the drivers' from the multipliers `lambda`. No allocation (unless
    /// the user callback allocates).
    pub(crate) fn powers(&mut self, t: f64, lambda: Multipliers<'_>, out: &mut [f64]) {
        if out.is_empty() {
            return;
        }
        let nj = self.model.joints().len();
        let nd = self.model.drivers().len();
        for (di, o) in out.iter_mut().enumerate().take(nd) {
            *o = self.element_power(&self.elements[nj + di], t, lambda);
        }
        let mut k = nd;
        for f in &self.forces {
            if f.is_non_conservative() {
                out[k] = f.non_conservative_power(self.model, t, &self.bodies);
                k += 1;
            }
        }
        if let Some(u) = &mut self.user {
            self.h_user.fill(0.0);
            let mut acc = AppliedForces {
                h: &mut self.h_user,
                bodies: &self.bodies,
            };
            u(t, &mut acc);
            let mut p = 0.0;
            for (b, h) in self.bodies.iter().zip(self.h_user.chunks_exact(6)) {
                for c in 0..3 {
                    p += h[c] * b.r_dot[c] + h[3 + c] * b.omega_local[c];
                }
            }
            out[k] = p;
            k += 1;
        }
        let nf = self.friction.power.len();
        out[k..k + nf].copy_from_slice(&self.friction.power);
        k += nf;
        if let Some(c) = &self.collisions {
            out[k] = c.power_at(&self.bodies);
            k += 1;
        }
        out[k..].copy_from_slice(&self.contacts.compliant_power);
    }

    /// The power of the joints' and couplers' reactions, −Σ λ_r (Φ_v v)_r over their rows, at
    /// the synced bodies (0 up to the velocity drift: ideal constraints do no work).
    pub(crate) fn constraint_power(&self, t: f64, lambda: &[f64]) -> f64 {
        let nj = self.model.joints().len();
        let nd = self.model.drivers().len();
        self.elements
            .iter()
            .enumerate()
            .filter(|(k, _)| *k < nj || *k >= nj + nd)
            .map(|(_, e)| self.element_power(e, t, Multipliers::Full(lambda)))
            .sum()
    }

    /// −Σ λ_r (Φ_v v)_r over the rows of element `e` at the synced bodies: the power of its
    /// reaction −Φ_vᵀλ on its two bodies.
    fn element_power(&self, e: &Element, t: f64, lambda: Multipliers<'_>) -> f64 {
        let mut bi = [[0.0; 6]; 6];
        let mut bj = [[0.0; 6]; 6];
        self.element_blocks(e, t, &mut bi, &mut bj);
        let mut p = 0.0;
        for (lr, r) in e.rows.clone().enumerate() {
            let l = match lambda {
                Multipliers::Full(l) => l[r],
                Multipliers::Solution => {
                    let kkt = self.kkt.as_ref().expect("prepared");
                    kkt.active
                        .binary_search(&r)
                        .map_or(0.0, |a| kkt.sol[kkt.n + a])
                }
            };
            let mut rate = 0.0;
            for (id, blk) in [(e.bi, &bi), (e.bj, &bj)] {
                if let BodyId::Moving(k) = id {
                    let b = &self.bodies[k];
                    for c in 0..3 {
                        rate += blk[lr][c] * b.r_dot[c] + blk[lr][3 + c] * b.omega_local[c];
                    }
                }
            }
            p -= l * rate;
        }
        p
    }
}

/// One trapezoidal step of the work: W += ½ h (P₀ + P₁).
pub(crate) fn trapezoid(work: &mut [f64], p0: &[f64], p1: &[f64], h: f64) {
    for ((w, a), b) in work.iter_mut().zip(p0).zip(p1) {
        *w += 0.5 * h * (a + b);
    }
}

/// The work W(t_n) = ∫_{t₀}^{t_n} P dt of each channel from its power sampled on a uniform grid
/// of step h, fourth order: the trapezoidal sum T_n with Gregory's end corrections
/// (Euler–Maclaurin, T_n − ∫ = h²/12 (Ṗ(t_n) − Ṗ(t₀)) + O(h⁴)):
///
/// ```text
/// W_n = T_n − h²/12 (Ṗ_n − Ṗ₀),   Ṗ₀ = (−3P₀ + 4P₁ − P₂)/(2h),   Ṗ_n = (3P_n − 4P_{n−1} + P_{n−2})/(2h)
/// ```
///
/// Causal, so the work streams with the frames: from n = 2 the corrections use the first three
/// and the last three samples; W₁ is Simpson's rule h/6 (P₀ + 4P_½ + P₁) when the power at the
/// first interval's midpoint is given ([`SampledWork::set_first_midpoint`]), else the trapezoid
/// (its O(h³) error, the only one above fourth order, is then the balance's largest). For inverse dynamics, whose motion is given at the output times only; the
/// trapezoidal rule left the energy balance of the bundled slider-crank (200 steps) at 5e-5 of
/// its energy scale. Grids that are not uniform (to 1e-9 relative) fall back to the trapezoid.
/// No allocation after construction.
#[derive(Debug, Clone)]
pub(crate) struct SampledWork {
    /// The trapezoidal sums T_n.
    trapezoid: Vec<f64>,
    /// P₀, P₁, P₂ (the start's derivative).
    first: [Vec<f64>; 3],
    /// P_{n−2}, P_{n−1} (the end's derivative, with P_n).
    last: [Vec<f64>; 2],
    /// The power at the first interval's midpoint, when known.
    midpoint: Option<Vec<f64>>,
    /// Samples so far, the step and whether every step had it.
    count: usize,
    h: f64,
    uniform: bool,
}

impl SampledWork {
    /// For `channels` channels.
    pub(crate) fn new(channels: usize) -> Self {
        let z = || vec![0.0; channels];
        Self {
            trapezoid: z(),
            first: [z(), z(), z()],
            last: [z(), z()],
            midpoint: None,
            count: 0,
            h: 0.0,
            uniform: true,
        }
    }

    /// The power at t₀ + h/2, for Simpson's rule on the first interval.
    pub(crate) fn set_first_midpoint(&mut self, power: Vec<f64>) {
        self.midpoint = Some(power);
    }

    /// Adds the sample `power` taken `h` after the previous one (ignored for the first) and
    /// writes each channel's work at its time into `work`.
    pub(crate) fn add(&mut self, h: f64, power: &[f64], work: &mut [f64]) {
        let n = self.count;
        if n > 0 {
            trapezoid(&mut self.trapezoid, &self.last[1], power, h);
            if n == 1 {
                self.h = h;
            } else if (h - self.h).abs() > 1e-9 * self.h.abs() {
                self.uniform = false;
            }
        }
        if n < 3 {
            self.first[n].copy_from_slice(power);
        }
        work.copy_from_slice(&self.trapezoid);
        if let (1, Some(mid)) = (n, &self.midpoint) {
            for ((w, (p0, p1)), pm) in work
                .iter_mut()
                .zip(self.first[0].iter().zip(power))
                .zip(mid)
            {
                *w = h / 6.0 * (p0 + 4.0 * pm + p1);
            }
        }
        if n >= 2 && self.uniform && self.h != 0.0 {
            let c = self.h / 24.0; // h²/12 · 1/(2h)
            for (k, w) in work.iter_mut().enumerate() {
                let [p0, p1, p2] = [self.first[0][k], self.first[1][k], self.first[2][k]];
                let start = -3.0 * p0 + 4.0 * p1 - p2;
                let end = 3.0 * power[k] - 4.0 * self.last[1][k] + self.last[0][k];
                *w -= c * (end - start);
            }
        }
        let [older, newer] = &mut self.last;
        std::mem::swap(older, newer);
        newer.copy_from_slice(power);
        self.count += 1;
    }
}

#[cfg(test)]
mod sampled_work_tests {
    use super::SampledWork;

    /// ∫₀ᵗ P for P = sin(3t) + t², on n steps to t = 2: the worst error over the grid, with or
    /// without the first midpoint.
    fn worst_error(n: usize, midpoint: bool) -> f64 {
        let p = |t: f64| (3.0 * t).sin() + t * t;
        let exact = |t: f64| (1.0 - (3.0 * t).cos()) / 3.0 + t * t * t / 3.0;
        let h = 2.0 / n as f64;
        let mut q = SampledWork::new(1);
        if midpoint {
            q.set_first_midpoint(vec![p(0.5 * h)]);
        }
        let mut w = [0.0];
        let mut worst = 0.0f64;
        for k in 0..=n {
            let t = k as f64 * h;
            q.add(if k == 0 { 0.0 } else { h }, &[p(t)], &mut w);
            worst = worst.max((w[0] - exact(t)).abs());
        }
        worst
    }

    /// Fourth order with the midpoint (halving h divides the worst error by about 16); the
    /// trapezoid's first interval alone is third order.
    #[test]
    fn gregory_with_a_simpson_start_is_fourth_order() {
        let (e1, e2) = (worst_error(100, true), worst_error(200, true));
        assert!(e1 / e2 > 14.0 && e1 < 1e-6, "{e1:e} {e2:e}");
        let (t1, t2) = (worst_error(100, false), worst_error(200, false));
        assert!(t1 / t2 > 7.0 && t1 / t2 < 9.0, "{t1:e} {t2:e}");
        assert!(t1 > 3.0 * e1, "{t1:e} {e1:e}");
    }
}
