//! Minimal SVG line plots on log-log (or lin-log) axes, for the report.

use std::fmt::Write as _;

/// One series: a label and its points.
pub struct Series {
    /// Legend label.
    pub label: String,
    /// (x, y) points, drawn in order.
    pub points: Vec<(f64, f64)>,
}

const COLORS: [&str; 6] = [
    "#1f77b4", "#d62728", "#2ca02c", "#ff7f0e", "#9467bd", "#8c564b",
];

fn decades(lo: f64, hi: f64) -> (f64, f64) {
    let a = lo.log10().floor();
    let mut b = hi.log10().ceil();
    if b <= a {
        b = a + 1.0;
    }
    (a, b)
}

/// A log-log plot with decade grid lines.
pub fn loglog(title: &str, xlabel: &str, ylabel: &str, series: &[Series]) -> String {
    let (w, h, ml, mr, mt, mb) = (640.0, 420.0, 70.0, 170.0, 40.0, 50.0);
    let all: Vec<(f64, f64)> = series
        .iter()
        .flat_map(|s| s.points.iter().copied())
        .filter(|(x, y)| *x > 0.0 && *y > 0.0 && x.is_finite() && y.is_finite())
        .collect();
    let mut out = String::new();
    let _ = writeln!(
        out,
        r#"<svg xmlns="http://www.w3.org/2000/svg" width="{w}" height="{h}" font-family="sans-serif" font-size="12">"#
    );
    let _ = writeln!(out, r#"<rect width="{w}" height="{h}" fill="white"/>"#);
    let _ = writeln!(
        out,
        r#"<text x="{}" y="22" text-anchor="middle" font-size="14">{}</text>"#,
        (ml + w - mr) / 2.0,
        esc(title)
    );
    if all.is_empty() {
        out.push_str("</svg>\n");
        return out;
    }
    let (x0, x1) = decades(
        all.iter().map(|p| p.0).fold(f64::INFINITY, f64::min),
        all.iter().map(|p| p.0).fold(0.0, f64::max),
    );
    let (y0, y1) = decades(
        all.iter().map(|p| p.1).fold(f64::INFINITY, f64::min),
        all.iter().map(|p| p.1).fold(0.0, f64::max),
    );
    let pw = w - ml - mr;
    let ph = h - mt - mb;
    let px = |x: f64| ml + (x.log10() - x0) / (x1 - x0) * pw;
    let py = |y: f64| mt + ph - (y.log10() - y0) / (y1 - y0) * ph;
    let step = |a: f64, b: f64| ((b - a) / 8.0).ceil().max(1.0) as usize;
    for d in (x0 as i32..=x1 as i32).step_by(step(x0, x1)) {
        let x = ml + (d as f64 - x0) / (x1 - x0) * pw;
        let _ = writeln!(
            out,
            r##"<line x1="{x:.1}" y1="{mt}" x2="{x:.1}" y2="{}" stroke="#ddd"/><text x="{x:.1}" y="{}" text-anchor="middle">1e{d}</text>"##,
            mt + ph,
            mt + ph + 16.0
        );
    }
    for d in (y0 as i32..=y1 as i32).step_by(step(y0, y1)) {
        let y = mt + ph - (d as f64 - y0) / (y1 - y0) * ph;
        let _ = writeln!(
            out,
            r##"<line x1="{ml}" y1="{y:.1}" x2="{}" y2="{y:.1}" stroke="#ddd"/><text x="{}" y="{:.1}" text-anchor="end">1e{d}</text>"##,
            ml + pw,
            ml - 6.0,
            y + 4.0
        );
    }
    let _ = writeln!(
        out,
        r##"<rect x="{ml}" y="{mt}" width="{pw}" height="{ph}" fill="none" stroke="#333"/>"##
    );
    let _ = writeln!(
        out,
        r#"<text x="{}" y="{}" text-anchor="middle">{}</text>"#,
        ml + pw / 2.0,
        h - 12.0,
        esc(xlabel)
    );
    let _ = writeln!(
        out,
        r#"<text x="16" y="{}" text-anchor="middle" transform="rotate(-90 16 {})">{}</text>"#,
        mt + ph / 2.0,
        mt + ph / 2.0,
        esc(ylabel)
    );
    for (i, s) in series.iter().enumerate() {
        let c = COLORS[i % COLORS.len()];
        let pts: Vec<String> = s
            .points
            .iter()
            .filter(|(x, y)| *x > 0.0 && *y > 0.0 && x.is_finite() && y.is_finite())
            .map(|&(x, y)| format!("{:.1},{:.1}", px(x), py(y)))
            .collect();
        if pts.is_empty() {
            continue;
        }
        let _ = writeln!(
            out,
            r#"<polyline points="{}" fill="none" stroke="{c}" stroke-width="1.8"/>"#,
            pts.join(" ")
        );
        for p in &pts {
            let (a, b) = p.split_once(',').unwrap_or(("0", "0"));
            let _ = writeln!(out, r#"<circle cx="{a}" cy="{b}" r="3" fill="{c}"/>"#);
        }
        let ly = mt + 10.0 + 18.0 * i as f64;
        let _ = writeln!(
            out,
            r#"<line x1="{}" y1="{ly}" x2="{}" y2="{ly}" stroke="{c}" stroke-width="2"/><text x="{}" y="{}">{}</text>"#,
            ml + pw + 10.0,
            ml + pw + 30.0,
            ml + pw + 35.0,
            ly + 4.0,
            esc(&s.label)
        );
    }
    out.push_str("</svg>\n");
    out
}

fn esc(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
}
