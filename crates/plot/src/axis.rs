//! Axis ranges, ticks and tick labels: 1-2-5 steps on linear axes, decades on log axes.
//! Degenerate data (no finite value, a constant series) get a padded range, never a panic.

use crate::Scale;

/// A value range mapped onto a pixel interval, with its ticks.
#[derive(Debug, Clone, PartialEq)]
pub struct Axis {
    scale: Scale,
    /// Range ends in axis space (log10 of the value on a log axis).
    lo: f64,
    hi: f64,
    /// Tick positions (values) and their labels.
    pub ticks: Vec<(f64, String)>,
}

impl Axis {
    /// An axis covering the finite values of `values` (non-positive ones ignored on a log axis),
    /// with about `n` ticks.
    pub fn fit(values: impl Iterator<Item = f64>, scale: Scale, n: usize) -> Self {
        let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
        for v in values.filter(|v| usable(*v, scale)) {
            lo = lo.min(v);
            hi = hi.max(v);
        }
        match scale {
            Scale::Linear => linear(lo, hi, n),
            Scale::Log => log(lo, hi, n),
        }
    }

    /// Position in [0, 1] of `v` along the axis (may fall outside for values outside the
    /// range); `None` for a value this axis cannot show.
    pub fn frac(&self, v: f64) -> Option<f64> {
        if !usable(v, self.scale) {
            return None;
        }
        let a = match self.scale {
            Scale::Linear => v,
            Scale::Log => v.log10(),
        };
        Some((a - self.lo) / (self.hi - self.lo))
    }
}

/// Whether the axis can show `v`.
fn usable(v: f64, scale: Scale) -> bool {
    v.is_finite() && (scale == Scale::Linear || v > 0.0)
}

/// A linear axis with a 1-2-5 step, the range widened to whole steps.
fn linear(lo: f64, hi: f64, n: usize) -> Axis {
    let (lo, hi) = padded(lo, hi);
    let raw = (hi - lo) / n.max(1) as f64;
    let mag = 10f64.powf(raw.log10().floor());
    let step = [1.0, 2.0, 5.0, 10.0]
        .iter()
        .map(|m| m * mag)
        .find(|s| *s >= raw)
        .unwrap_or(10.0 * mag);
    let start = (lo / step).floor() * step;
    let end = (hi / step).ceil() * step;
    let count = ((end - start) / step).round().clamp(1.0, 100.0) as usize;
    let ticks = (0..=count)
        .map(|k| start + k as f64 * step)
        .map(|v| (v, linear_label(v, step)))
        .collect();
    Axis {
        scale: Scale::Linear,
        lo: start,
        hi: start + count as f64 * step,
        ticks,
    }
}

/// A finite, non-empty range: (0, 1) without data, ±10 % (or ±1 at zero) around a constant.
fn padded(lo: f64, hi: f64) -> (f64, f64) {
    if lo > hi {
        return (0.0, 1.0);
    }
    let size = lo.abs().max(hi.abs());
    if hi - lo <= 1e-12 * size || !(hi - lo).is_finite() {
        let pad = if size == 0.0 { 1.0 } else { 0.1 * size };
        let mid = 0.5 * lo + 0.5 * hi;
        return (mid - pad, mid + pad);
    }
    (lo, hi)
}

/// A log axis over whole decades, with at most about `n` labelled decades.
fn log(lo: f64, hi: f64, n: usize) -> Axis {
    let (a, mut b) = if lo > hi {
        (0.0, 1.0)
    } else {
        (lo.log10().floor(), hi.log10().ceil())
    };
    if b <= a {
        b = a + 1.0;
    }
    let every = ((b - a) / n.max(1) as f64).ceil().max(1.0) as usize;
    let ticks = (a as i32..=b as i32)
        .step_by(every)
        .map(|d| (10f64.powi(d), format!("1e{d}")))
        .collect();
    Axis {
        scale: Scale::Log,
        lo: a,
        hi: b,
        ticks,
    }
}

/// A tick label with as many decimals as the step needs; scientific outside [1e-3, 1e5).
fn linear_label(v: f64, step: f64) -> String {
    if v.abs() < step * 1e-9 {
        return "0".into();
    }
    let a = v.abs();
    if !(1e-3..1e5).contains(&a) {
        return format!("{v:.2e}");
    }
    let decimals = (-step.log10().floor()).clamp(0.0, 12.0) as usize;
    format!("{v:.decimals$}")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn linear_ticks_cover_the_data() {
        let ax = Axis::fit([0.13, 0.97].into_iter(), Scale::Linear, 5);
        assert!(ax.lo <= 0.13 && ax.hi >= 0.97);
        assert!((4..=12).contains(&ax.ticks.len()), "{:?}", ax.ticks);
    }

    #[test]
    fn degenerate_data_get_a_range() {
        for data in [
            vec![],
            vec![2.0, 2.0],
            vec![0.0],
            vec![f64::NAN, f64::INFINITY],
        ] {
            let ax = Axis::fit(data.into_iter(), Scale::Linear, 5);
            assert!(ax.hi > ax.lo && ax.lo.is_finite() && ax.hi.is_finite());
        }
        let ax = Axis::fit([f64::MAX, -f64::MAX].into_iter(), Scale::Linear, 5);
        assert!(ax.ticks.len() <= 101);
        let ax = Axis::fit([-1.0, 0.0].into_iter(), Scale::Log, 5);
        assert!(ax.hi > ax.lo);
    }

    #[test]
    fn log_ticks_are_decades() {
        let ax = Axis::fit([3e-9, 2e-2].into_iter(), Scale::Log, 8);
        assert_eq!(ax.ticks.first().map(|t| t.1.as_str()), Some("1e-9"));
        assert_eq!(ax.frac(1e-9), Some(0.0));
        assert_eq!(ax.frac(-1.0), None);
    }
}
