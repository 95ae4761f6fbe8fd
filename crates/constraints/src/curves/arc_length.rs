//! The arc length along a cubic spline, S(u) = ∫₀ᵘ |c'_u(τ)| dτ, for a path driver that moves a
//! point at a prescribed speed along a spline (whose own parameter is the cumulative chord
//! length, not the arc length).
//!
//! ```text
//! S(u)    = S(b_m) + ∫_{b_m}^u |c'_u| dτ      (b_m the breakpoint at or below u)
//! S_u     = |c'_u(u)|
//! S_uu    = c'_uᵀ c'_uu / |c'_u|
//! ```
//!
//! Each segment of the spline is split by bisection until 8-point Gauss–Legendre on the
//! interval agrees with the sum over its two halves to 1e-15 of the curve's length (|c'_u|
//! is the root of a quartic in u, smooth but sharply varying where the spline turns tightly);
//! the breakpoints b_m and the arc length S(b_m) at each are kept. Evaluation is one 8-point
//! rule on [b_m, u], inside an interval the bisection resolved. A closed spline's S runs on over
//! its turns, S(u + L) = S(u) + Λ (Λ its length); an open one's continues beyond its ends along
//! the curve's continuation (straight at the end speed for a cubic, the quadratic Taylor
//! polynomial for a quintic), by the same rule from the end.

use super::cubic::CubicCurve;

/// 8-point Gauss–Legendre nodes on [−1, 1] (positive half; the rule is symmetric).
const NODES: [f64; 4] = [
    0.183_434_642_495_649_8,
    0.525_532_409_916_329,
    0.796_666_477_413_626_7,
    0.960_289_856_497_536_3,
];
/// Their weights.
const WEIGHTS: [f64; 4] = [
    0.362_683_783_378_362,
    0.313_706_645_877_887_3,
    0.222_381_034_453_374_5,
    0.101_228_536_290_376_3,
];

/// S(u) of a cubic spline (module docs).
#[derive(Debug, Clone, PartialEq)]
pub struct ArcLength {
    curve: CubicCurve,
    /// Breakpoints b_m in u, increasing, from u_0 to u_n.
    breaks: Vec<f64>,
    /// S(b_m).
    lengths: Vec<f64>,
}

impl ArcLength {
    /// The arc length table of `curve`.
    pub fn new(curve: &CubicCurve) -> Self {
        let knots = curve.knots();
        let mut breaks = vec![knots[0]];
        let mut lengths = vec![0.0];
        // The tolerance: 1e-15 of the chord length, a lower bound of the curve's length.
        let tol = 1e-15 * (knots[knots.len() - 1] - knots[0]);
        for k in 0..knots.len() - 1 {
            split(
                curve,
                (knots[k], knots[k + 1]),
                tol,
                0,
                &mut breaks,
                &mut lengths,
            );
        }
        Self {
            curve: curve.clone(),
            breaks,
            lengths,
        }
    }

    /// Whether the spline is closed (S runs on over its turns).
    pub fn is_closed(&self) -> bool {
        self.curve.is_closed()
    }

    /// Λ, the length of the curve's data (of one turn of a closed curve).
    pub fn total(&self) -> f64 {
        self.lengths[self.lengths.len() - 1]
    }

    /// (S, S_u, S_uu) at u.
    pub fn eval(&self, u: f64) -> (f64, f64, f64) {
        let n = self.breaks.len() - 1;
        let (a, end) = (self.breaks[0], self.breaks[n]);
        let (turns, w) = if self.curve.is_closed() {
            let turns = ((u - a) / (end - a)).floor();
            (turns, u - (end - a) * turns)
        } else {
            (0.0, u)
        };
        let jet = self.curve.jet(w);
        let speed = jet.c_u.norm();
        let rate = jet.c_u.dot(&jet.c_uu) / speed;
        // Beyond an open curve's ends its continuation (straight for a cubic, the quadratic
        // Taylor polynomial for a quintic) by the 8-point rule from the end.
        let s = if !self.curve.is_closed() && w < a {
            -gauss(&self.curve, w, a)
        } else if !self.curve.is_closed() && w > end {
            self.total() + gauss(&self.curve, end, w)
        } else {
            let m = self.breaks.partition_point(|&b| b <= w).clamp(1, n) - 1;
            self.lengths[m] + gauss(&self.curve, self.breaks[m], w)
        };
        (s + turns * self.total(), speed, rate)
    }
}

/// ∫ₐᵇ |c'_u| by the 8-point rule.
fn gauss(curve: &CubicCurve, a: f64, b: f64) -> f64 {
    let (mid, half) = ((a + b) / 2.0, (b - a) / 2.0);
    let speed = |u: f64| curve.jet(u).c_u.norm();
    (NODES.iter().zip(WEIGHTS))
        .map(|(x, w)| w * (speed(mid - half * x) + speed(mid + half * x)))
        .sum::<f64>()
        * half
}

/// Appends the breakpoints inside (a, b] and their arc lengths, bisecting until the rule on an
/// interval agrees with its halves to `tol` (at most 40 levels deep).
fn split(
    curve: &CubicCurve,
    (a, b): (f64, f64),
    tol: f64,
    depth: usize,
    breaks: &mut Vec<f64>,
    lengths: &mut Vec<f64>,
) {
    let m = (a + b) / 2.0;
    let whole = gauss(curve, a, b);
    let halves = gauss(curve, a, m) + gauss(curve, m, b);
    if (whole - halves).abs() > tol && depth < 40 {
        split(curve, (a, m), tol, depth + 1, breaks, lengths);
        split(curve, (m, b), tol, depth + 1, breaks, lengths);
    } else {
        let s = lengths[lengths.len() - 1] + halves;
        breaks.push(b);
        lengths.push(s);
    }
}
