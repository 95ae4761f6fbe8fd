//! The SVG path of one series in a plot rectangle: runs of drawable samples mapped to pixels,
//! decimated per pixel column, written with relative moves of 0.1 px resolution (short text).

use crate::axis::Axis;
use crate::decimate::decimate;
use std::fmt::Write as _;

/// A plot area in pixels.
#[derive(Debug, Clone, Copy)]
pub struct Rect {
    /// Left edge.
    pub x: f64,
    /// Top edge.
    pub y: f64,
    /// Width.
    pub w: f64,
    /// Height.
    pub h: f64,
}

/// Pixel positions of the drawable samples, in runs broken at samples an axis cannot show.
/// Positions are clamped to a margin around the rectangle (the clip path hides the rest).
fn runs(points: &[(f64, f64)], xa: &Axis, ya: &Axis, r: Rect) -> Vec<Vec<(f64, f64)>> {
    let mut out = vec![Vec::new()];
    for &(x, y) in points {
        match (xa.frac(x), ya.frac(y)) {
            (Some(fx), Some(fy)) => {
                let px = r.x + fx.clamp(-1.0, 2.0) * r.w;
                let py = r.y + (1.0 - fy.clamp(-1.0, 2.0)) * r.h;
                if let Some(run) = out.last_mut() {
                    run.push((px, py));
                }
            }
            _ => {
                if out.last().is_some_and(|run| !run.is_empty()) {
                    out.push(Vec::new());
                }
            }
        }
    }
    out.retain(|run| !run.is_empty());
    out
}

/// The path data (`d` attribute) of the series and its drawn pixel points; empty when nothing
/// is drawable.
pub fn path(points: &[(f64, f64)], xa: &Axis, ya: &Axis, r: Rect) -> (String, Vec<(f64, f64)>) {
    let mut d = String::new();
    let mut drawn = Vec::new();
    let columns = r.w.max(1.0) as usize;
    for run in runs(points, xa, ya, r) {
        let kept = decimate(run, r.x, r.x + r.w, columns);
        write_run(&mut d, &kept);
        drawn.extend(kept);
    }
    (d, drawn)
}

/// Appends `M x,y` and relative line segments, rounding to tenths of a pixel without drift.
fn write_run(d: &mut String, pts: &[(f64, f64)]) {
    let tenth = |v: f64| (v * 10.0).round() as i64;
    let Some(&(x0, y0)) = pts.first() else {
        return;
    };
    let (mut px, mut py) = (tenth(x0), tenth(y0));
    d.push('M');
    push_tenths(d, px);
    d.push(',');
    push_tenths(d, py);
    if pts.len() == 1 {
        d.push_str("h0.1");
    }
    for &(x, y) in &pts[1..] {
        let (qx, qy) = (tenth(x), tenth(y));
        if (qx, qy) != (px, py) {
            d.push('l');
            push_tenths(d, qx - px);
            d.push(',');
            push_tenths(d, qy - py);
        }
        (px, py) = (qx, qy);
    }
}

/// Appends a number of tenths as a short decimal ("12.3", "-0.4", "7"). Written digit by
/// digit: a plot's path holds thousands of them, and `write!` costs several times more.
fn push_tenths(d: &mut String, v: i64) {
    write_tenths(v, |c| d.push(c));
}

/// Gives `push` the characters of `v` tenths as [`push_tenths`] writes them.
fn write_tenths(v: i64, mut push: impl FnMut(char)) {
    if v < 0 {
        push('-');
    }
    let a = v.unsigned_abs();
    let mut digits = [0u8; 20];
    let mut k = digits.len();
    let mut w = a / 10;
    loop {
        k -= 1;
        digits[k] = b'0' + (w % 10) as u8;
        w /= 10;
        if w == 0 {
            break;
        }
    }
    digits[k..].iter().for_each(|&c| push(char::from(c)));
    let r = (a % 10) as u8;
    if r != 0 {
        push('.');
        push(char::from(b'0' + r));
    }
}

/// A pixel coordinate, shown rounded to a tenth of a pixel as [`push_tenths`] writes it: the
/// frame, grid, labels and markers of a plot, a few thousand numbers per run, which `{:.1}`
/// formats several times slower (exact decimal rounding, often through big-number arithmetic).
#[derive(Debug, Clone, Copy)]
pub struct Px(pub f64);

impl std::fmt::Display for Px {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let mut done = Ok(());
        write_tenths((self.0 * 10.0).round() as i64, |c| {
            done = done.and_then(|()| f.write_char(c));
        });
        done
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tenths_are_short() {
        let s: Vec<String> = [123, -4, 70, 0, -15, i64::MIN, 1_000_000]
            .map(|v| {
                let mut d = String::new();
                push_tenths(&mut d, v);
                d
            })
            .into();
        assert_eq!(
            s,
            [
                "12.3",
                "-0.4",
                "7",
                "0",
                "-1.5",
                "-922337203685477580.8",
                "100000"
            ]
        );
    }

    #[test]
    fn pixels_are_tenths() {
        let s: Vec<String> = [12.25, -0.04, 7.0, 540.0 / 3.0, -1.55]
            .map(|v| Px(v).to_string())
            .into();
        assert_eq!(s, ["12.3", "0", "7", "180", "-1.6"]);
    }

    #[test]
    fn gaps_break_the_line() {
        let mut d = String::new();
        write_run(&mut d, &[(1.0, 2.0), (1.04, 2.0), (3.0, 1.0)]);
        assert_eq!(d, "M1,2l2,-1");
        let ax = Axis::fit([0.0, 1.0].into_iter(), crate::Scale::Linear, 4);
        let r = Rect {
            x: 0.0,
            y: 0.0,
            w: 100.0,
            h: 100.0,
        };
        let pts = [(0.0, 0.0), (0.5, f64::NAN), (1.0, 1.0)];
        let (d, drawn) = path(&pts, &ax, &ax, r);
        assert_eq!(d.matches('M').count(), 2, "{d}");
        assert_eq!(drawn.len(), 2);
    }
}
