//! SVG output of a [`Figure`]: a title, then the panels in a grid. Each panel has its title, a
//! framed plot area with grid lines and tick labels, the y label (with its unit) on the left,
//! the x label below, and its legend on the right, inside the image.

use std::fmt::Write as _;

use crate::axis::Axis;
use crate::path::{path, Px, Rect};
use crate::text::{esc, fit, wrap_two};
use crate::{Figure, Panel, Series, DASHES, PALETTE};

/// Size of one panel cell, in pixels.
const CELL_W: f64 = 540.0;
const CELL_H: f64 = 270.0;
/// Margins of the plot area inside its cell; the legend takes the right margin.
const LEFT: f64 = 74.0;
const RIGHT: f64 = 170.0;
const TOP: f64 = 28.0;
const BOTTOM: f64 = 44.0;
/// Height of the figure title band, and the font sizes.
const HEAD: f64 = 34.0;
const FONT: f64 = 11.0;
/// Height of one legend row.
const ROW: f64 = 15.0;

/// The SVG document of `fig`. Never fails: empty panels and odd data give empty axes.
pub fn render_svg(fig: &Figure) -> String {
    let columns = fig.columns.max(1).min(fig.panels.len().max(1));
    let rows = fig.panels.len().div_ceil(columns).max(1);
    let (w, h) = (columns as f64 * CELL_W, HEAD + rows as f64 * CELL_H);
    let xa = Axis::fit(all(fig.panels.iter(), |p| p.0), fig.x_scale, 6);
    let mut s = String::new();
    let _ = writeln!(
        s,
        r#"<svg xmlns="http://www.w3.org/2000/svg" width="{w}" height="{h}" viewBox="0 0 {w} {h}" font-family="sans-serif" font-size="{FONT}">"#
    );
    let _ = writeln!(s, r#"<rect width="100%" height="100%" fill="white"/>"#);
    let _ = writeln!(
        s,
        r#"<text x="{}" y="22" text-anchor="middle" font-size="15">{}</text>"#,
        Px(w / 2.0),
        esc(&fit(&fig.title, w - 20.0, 15.0))
    );
    for (k, panel) in fig.panels.iter().enumerate() {
        let (col, row) = (k % columns, k / columns);
        let (cx, cy) = (col as f64 * CELL_W, HEAD + row as f64 * CELL_H);
        write_panel(&mut s, k, fig, panel, &xa, cx, cy);
    }
    s.push_str("</svg>\n");
    s
}

/// Every finite coordinate chosen by `pick` of the panels' samples.
fn all<'a>(
    panels: impl Iterator<Item = &'a Panel> + 'a,
    pick: fn(&(f64, f64)) -> f64,
) -> impl Iterator<Item = f64> + 'a {
    panels.flat_map(|p| p.series.iter()).flat_map(move |s| {
        s.points
            .iter()
            .filter(|p| p.0.is_finite() && p.1.is_finite())
            .map(pick)
    })
}

/// One panel with its cell's top left corner at (cx, cy).
fn write_panel(s: &mut String, k: usize, fig: &Figure, panel: &Panel, xa: &Axis, cx: f64, cy: f64) {
    let r = Rect {
        x: cx + LEFT,
        y: cy + TOP,
        w: CELL_W - LEFT - RIGHT,
        h: CELL_H - TOP - BOTTOM,
    };
    let extent = panel.y_extent.into_iter().flat_map(|e| [-e, e]);
    let ya = Axis::fit(
        all(std::iter::once(panel), |p| p.1).chain(extent),
        fig.y_scale,
        5,
    );
    write_panel_title(s, &panel.title, r, cy);
    write_grid(s, xa, &ya, r);
    write_labels(s, &fig.x_label, &panel.y_label, r, cx);
    let _ = writeln!(
        s,
        r#"<clipPath id="c{k}"><rect x="{}" y="{}" width="{}" height="{}"/></clipPath>"#,
        Px(r.x),
        Px(r.y),
        Px(r.w),
        Px(r.h)
    );
    let _ = writeln!(
        s,
        r#"<g clip-path="url(#c{k})" fill="none" stroke-width="1.4">"#
    );
    for series in &panel.series {
        write_series(s, series, xa, &ya, r);
    }
    s.push_str("</g>\n");
    write_legend(s, &panel.series, r);
}

/// The panel's title above its plot area: one line at 12 px, or two at 11 px when it is too
/// long for one ([`wrap_two`]; the plot area starts `TOP` = 28 px below the cell's top).
fn write_panel_title(s: &mut String, title: &str, r: Rect, cy: f64) {
    let width = r.w + RIGHT - 10.0;
    let lines = wrap_two(title, width, 12.0);
    let (font, first, step) = if lines.len() == 1 {
        (12.0, 18.0, 0.0)
    } else {
        (11.0, 12.0, 12.0)
    };
    let lines = if lines.len() == 1 {
        lines
    } else {
        wrap_two(title, width, font)
    };
    for (k, line) in lines.iter().enumerate() {
        let _ = writeln!(
            s,
            r#"<text x="{}" y="{}" text-anchor="middle" font-size="{font}" font-weight="bold">{}</text>"#,
            Px(r.x + r.w / 2.0),
            Px(cy + first + step * k as f64),
            esc(line)
        );
    }
}

/// Grid lines, tick labels and the frame of the plot area.
fn write_grid(s: &mut String, xa: &Axis, ya: &Axis, r: Rect) {
    for (v, label) in &xa.ticks {
        let Some(f) = xa.frac(*v) else { continue };
        let x = Px(r.x + f * r.w);
        let _ = writeln!(
            s,
            r##"<line x1="{x}" y1="{}" x2="{x}" y2="{}" stroke="#e4e4e4"/><text x="{x}" y="{}" text-anchor="middle">{}</text>"##,
            Px(r.y),
            Px(r.y + r.h),
            Px(r.y + r.h + 14.0),
            esc(label)
        );
    }
    for (v, label) in &ya.ticks {
        let Some(f) = ya.frac(*v) else { continue };
        let y = r.y + (1.0 - f) * r.h;
        let _ = writeln!(
            s,
            r##"<line x1="{}" y1="{}" x2="{}" y2="{}" stroke="#e4e4e4"/><text x="{}" y="{}" text-anchor="end">{}</text>"##,
            Px(r.x),
            Px(y),
            Px(r.x + r.w),
            Px(y),
            Px(r.x - 5.0),
            Px(y + 4.0),
            esc(label)
        );
    }
    let _ = writeln!(
        s,
        r##"<rect x="{}" y="{}" width="{}" height="{}" fill="none" stroke="#333"/>"##,
        Px(r.x),
        Px(r.y),
        Px(r.w),
        Px(r.h)
    );
}

/// The x label under the plot area and the y label turned along the left edge of the cell.
fn write_labels(s: &mut String, x_label: &str, y_label: &str, r: Rect, cx: f64) {
    let _ = writeln!(
        s,
        r#"<text x="{}" y="{}" text-anchor="middle">{}</text>"#,
        Px(r.x + r.w / 2.0),
        Px(r.y + r.h + 32.0),
        esc(&fit(x_label, r.w, FONT))
    );
    let (lx, ly) = (Px(cx + 14.0), Px(r.y + r.h / 2.0));
    let _ = writeln!(
        s,
        r#"<text x="{lx}" y="{ly}" text-anchor="middle" transform="rotate(-90 {lx} {ly})">{}</text>"#,
        esc(&fit(y_label, r.h, FONT))
    );
}

/// The stroke attributes of a style.
fn stroke(style: crate::Style) -> String {
    let colour = PALETTE[style.colour % PALETTE.len()];
    match DASHES[style.dash % DASHES.len()] {
        Some(d) => format!(r#"stroke="{colour}" stroke-dasharray="{d}""#),
        None => format!(r#"stroke="{colour}""#),
    }
}

/// One series' path (and its markers).
fn write_series(s: &mut String, series: &Series, xa: &Axis, ya: &Axis, r: Rect) {
    let (d, drawn) = path(&series.points, xa, ya, r);
    if d.is_empty() {
        return;
    }
    let _ = writeln!(s, r#"<path {} d="{d}"/>"#, stroke(series.style));
    if series.style.markers {
        let colour = PALETTE[series.style.colour % PALETTE.len()];
        for (x, y) in drawn {
            let (x, y) = (Px(x), Px(y));
            let _ = writeln!(s, r#"<circle cx="{x}" cy="{y}" r="2.5" fill="{colour}"/>"#);
        }
    }
}

/// The legend in the right margin of the cell: a line sample and the label per series, as many
/// rows as fit, then "+ n more".
fn write_legend(s: &mut String, series: &[Series], r: Rect) {
    let x = r.x + r.w + 10.0;
    let fits = ((r.h + 10.0) / ROW).floor() as usize;
    let shown = if series.len() > fits {
        fits.saturating_sub(1)
    } else {
        series.len()
    };
    for (k, item) in series.iter().take(shown).enumerate() {
        let y = r.y + 6.0 + ROW * k as f64;
        let _ = writeln!(
            s,
            r#"<path {} stroke-width="2" d="M{},{}h22"/><text x="{}" y="{}">{}</text>"#,
            stroke(item.style),
            Px(x),
            Px(y),
            Px(x + 27.0),
            Px(y + 4.0),
            esc(&fit(&item.label, RIGHT - 40.0, FONT))
        );
    }
    if shown < series.len() {
        let _ = writeln!(
            s,
            r#"<text x="{}" y="{}">+ {} more</text>"#,
            Px(x),
            Px(r.y + 10.0 + ROW * shown as f64),
            series.len() - shown
        );
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{Scale, Style};

    fn series(label: &str, points: Vec<(f64, f64)>) -> Series {
        Series {
            label: label.into(),
            style: Style::default(),
            points,
        }
    }

    #[test]
    fn odd_figures_render() {
        let mut fig = Figure::new("empty & <odd>", "t [s]");
        assert!(render_svg(&fig).contains("empty &amp; &lt;odd&gt;"));
        fig.panels.push(Panel::default());
        fig.panels.push(Panel {
            title: "p".into(),
            y_label: "[m]".into(),
            series: vec![
                series("nan", vec![(0.0, f64::NAN)]),
                series("one", vec![(1.0, 2.0)]),
                series("flat", vec![(0.0, 3.0), (1.0, 3.0)]),
            ],
            y_extent: None,
        });
        fig.columns = 5;
        fig.y_scale = Scale::Log;
        let svg = render_svg(&fig);
        assert!(svg.ends_with("</svg>\n") && svg.contains("flat"));
    }

    /// A panel title too long for one line (the flyball governor's energy panel: eight
    /// series) is wrapped onto a second line at a comma, not cut with an ellipsis.
    #[test]
    fn long_panel_titles_wrap_onto_two_lines() {
        let title =
            "kinetic, potential_gravity, potential_spring, total, drift, springA, springB, W_nc";
        let fig = Figure {
            panels: vec![Panel {
                title: title.into(),
                y_label: "energy [J]".into(),
                series: vec![series("a", vec![(0.0, 1.0), (1.0, 2.0)])],
                y_extent: None,
            }],
            ..Figure::new("energy", "t [s]")
        };
        let svg = render_svg(&fig);
        assert!(!svg.contains('…'), "{svg}");
        let lines: Vec<&str> = svg
            .lines()
            .filter(|l| l.contains("font-weight=\"bold\""))
            .collect();
        assert_eq!(lines.len(), 2, "{lines:?}");
        let shown: String = lines
            .iter()
            .map(|l| l.split('>').nth(1).unwrap().trim_end_matches("</text"))
            .collect::<Vec<_>>()
            .join(" ");
        assert_eq!(shown, title);
    }

    #[test]
    fn long_legends_stay_inside() {
        let many = (0..40)
            .map(|k| series(&format!("s{k}"), vec![(0.0, k as f64)]))
            .collect();
        let fig = Figure {
            panels: vec![Panel {
                title: "t".into(),
                y_label: "[N]".into(),
                series: many,
                y_extent: None,
            }],
            ..Figure::new("f", "t [s]")
        };
        let svg = render_svg(&fig);
        assert!(svg.contains("more</text>") && !svg.contains(">s39<"));
    }
}
