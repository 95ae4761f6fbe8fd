//! Min/max decimation: a long series reduced to what a pixel grid can show.
//!
//! The samples are cut into buckets by x (one bucket per pixel column); from each bucket the
//! smallest and the largest sample are kept, in their original order. The drawn line then
//! covers the same vertical extent in every column as the full series (peaks survive), while at
//! most 2 points per column remain.

/// The samples of `points` (x ascending or not; x outside [x0, x1] are clamped into the first or
/// last bucket) kept for drawing on `columns` pixel columns spanning [x0, x1]. Non-finite
/// samples are dropped. Returns every sample when each bucket holds at most 2.
pub fn decimate(points: &[(f64, f64)], x0: f64, x1: f64, columns: usize) -> Vec<(f64, f64)> {
    let finite = |p: &&(f64, f64)| p.0.is_finite() && p.1.is_finite();
    let columns = columns.max(1);
    let width = x1 - x0;
    if !(width > 0.0 && width.is_finite()) {
        return points.iter().filter(finite).copied().collect();
    }
    let bucket =
        |x: f64| (((x - x0) / width * columns as f64).floor().max(0.0) as usize).min(columns - 1);
    let mut out = Vec::new();
    let mut current: Option<Bucket> = None;
    for &p in points.iter().filter(finite) {
        let b = bucket(p.0);
        match &mut current {
            Some(c) if c.index == b => c.add(p),
            _ => {
                if let Some(c) = current.take() {
                    c.emit(&mut out);
                }
                current = Some(Bucket::new(b, p));
            }
        }
    }
    if let Some(c) = current {
        c.emit(&mut out);
    }
    out
}

/// The extremes of one pixel column's run of samples, with their order of arrival.
struct Bucket {
    index: usize,
    count: usize,
    min: (usize, (f64, f64)),
    max: (usize, (f64, f64)),
}

impl Bucket {
    fn new(index: usize, p: (f64, f64)) -> Self {
        Self {
            index,
            count: 1,
            min: (0, p),
            max: (0, p),
        }
    }

    fn add(&mut self, p: (f64, f64)) {
        let k = self.count;
        self.count += 1;
        // With two samples, both are kept (the second as min or max).
        if p.1 < self.min.1 .1 || (k == 1 && self.min.0 == self.max.0 && p.1 == self.min.1 .1) {
            self.min = (k, p);
        }
        if p.1 > self.max.1 .1 {
            self.max = (k, p);
        }
    }

    /// Appends the kept samples in their original order, each once.
    fn emit(self, out: &mut Vec<(f64, f64)>) {
        let (a, b) = if self.min.0 <= self.max.0 {
            (self.min, self.max)
        } else {
            (self.max, self.min)
        };
        out.push(a.1);
        if b.0 != a.0 {
            out.push(b.1);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn short_series_are_kept_whole() {
        let pts: Vec<_> = (0..10).map(|k| (k as f64, (k * k) as f64)).collect();
        assert_eq!(decimate(&pts, 0.0, 9.0, 100), pts);
    }

    #[test]
    fn long_series_keep_peaks_and_stay_bounded() {
        let n = 1_000_000;
        let mut pts: Vec<_> = (0..n)
            .map(|k| {
                let t = k as f64 / n as f64;
                (t, (40.0 * t).sin())
            })
            .collect();
        pts[123_457].1 = 50.0;
        pts[876_543].1 = -70.0;
        let d = decimate(&pts, 0.0, 1.0, 400);
        assert!(d.len() <= 2 * 400, "{}", d.len());
        assert!(d.contains(&pts[123_457]) && d.contains(&pts[876_543]));
        assert!(d.windows(2).all(|w| w[0].0 <= w[1].0), "order kept");
    }

    #[test]
    fn odd_input_does_not_panic() {
        assert!(decimate(&[], 0.0, 1.0, 10).is_empty());
        assert_eq!(decimate(&[(0.5, 1.0)], 0.5, 0.5, 10), [(0.5, 1.0)]);
        let nan = decimate(&[(0.0, f64::NAN), (1.0, 2.0)], 0.0, 1.0, 0);
        assert_eq!(nan, [(1.0, 2.0)]);
        assert_eq!(decimate(&[(-5.0, 1.0), (9.0, 2.0)], 0.0, 1.0, 3).len(), 2);
    }
}
