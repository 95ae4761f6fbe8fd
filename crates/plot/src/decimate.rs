//! Min/max decimation: a long series reduced to what a pixel grid can show.
//!
//! The samples are cut into buckets by x (one bucket per pixel column); from each bucket the
//! smallest and the largest sample are kept, in their original order. The drawn line then
//! covers the same vertical extent in every column as the full series (peaks survive), while at
//! most 2 points per column remain.

/// The samples of `points` (x ascending or not; x outside [x0, x1] are clamped into the first or
/// last bucket) kept for drawing on `columns` pixel columns spanning [x0, x1]. Samples with a
/// non-finite x are dropped; a run of samples with a non-finite y becomes one break marker
/// `(x, NaN)`, so gaps stay gaps. Returns every sample when each bucket holds at most 2.
pub fn decimate(
    points: impl IntoIterator<Item = (f64, f64)>,
    x0: f64,
    x1: f64,
    columns: usize,
) -> Vec<(f64, f64)> {
    let columns = columns.max(1);
    let width = x1 - x0;
    let spread = width > 0.0 && width.is_finite();
    let bucket = |x: f64| {
        let b = if spread {
            (x - x0) / width * columns as f64
        } else {
            0.0
        };
        // The column left of x (truncation is the floor above 0; NaN and below 0: the first).
        if b > 0.0 {
            (b as usize).min(columns - 1)
        } else {
            0
        }
    };
    let points = points.into_iter();
    let mut out = Vec::with_capacity(points.size_hint().0.min(2 * columns + 2));
    let mut current: Option<Bucket> = None;
    for p in points.filter(|p| p.0.is_finite()) {
        if !p.1.is_finite() {
            if let Some(c) = current.take() {
                c.emit(&mut out);
            }
            if out.last().is_some_and(|q: &(f64, f64)| q.1.is_finite()) {
                out.push((p.0, f64::NAN));
            }
            continue;
        }
        let b = if spread { bucket(p.0) } else { usize::MAX };
        match &mut current {
            Some(c) if c.index == b && spread => c.add(p),
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
        assert_eq!(decimate(pts.clone(), 0.0, 9.0, 100), pts);
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
        let d = decimate(pts.iter().copied(), 0.0, 1.0, 400);
        assert!(d.len() <= 2 * 400, "{}", d.len());
        assert!(d.contains(&pts[123_457]) && d.contains(&pts[876_543]));
        assert!(d.windows(2).all(|w| w[0].0 <= w[1].0), "order kept");
    }

    #[test]
    fn odd_input_does_not_panic() {
        assert!(decimate([], 0.0, 1.0, 10).is_empty());
        assert_eq!(decimate([(0.5, 1.0)], 0.5, 0.5, 10), [(0.5, 1.0)]);
        let nan = decimate([(0.0, f64::NAN), (1.0, 2.0)], 0.0, 1.0, 0);
        assert_eq!(nan, [(1.0, 2.0)]);
        assert_eq!(decimate([(-5.0, 1.0), (9.0, 2.0)], 0.0, 1.0, 3).len(), 2);
        let same_x = decimate([(1.0, 1.0), (1.0, 5.0), (1.0, 2.0)], 1.0, 1.0, 3);
        assert_eq!(same_x.len(), 3, "no spread: nothing merged");
    }

    #[test]
    fn gaps_stay_gaps() {
        let pts = (0..1000).map(|k| {
            (
                k as f64,
                if (400..500).contains(&k) {
                    f64::NAN
                } else {
                    1.0
                },
            )
        });
        let d = decimate(pts, 0.0, 999.0, 10);
        assert_eq!(d.iter().filter(|p| p.1.is_nan()).count(), 1);
    }
}
