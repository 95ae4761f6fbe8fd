//! The plots of a sweep: each output against each swept parameter, a line per combination of
//! the other parameters' values (at most [`MAX_LINES`]; a listed sweep's cases are dots).

use super::grid::Cases;
use super::{Row, Sweep};
use cardan_plot::{Figure, Panel, Series, Style};

/// Most lines of one plot: beyond, the first ones are drawn and the title says how many.
pub const MAX_LINES: usize = 10;

/// The SVG files: `(file name, contents)`, `OUTPUT_vs_PARAMETER.svg`.
pub fn plots(sweep: &Sweep, rows: &[Row]) -> Vec<(String, String)> {
    let names = sweep.cases.names();
    let grid = matches!(sweep.cases, Cases::Grid(_));
    let mut out = Vec::new();
    for (oi, o) in sweep.outputs.iter().enumerate() {
        for (pi, p) in names.iter().enumerate() {
            // The lines: rows grouped by the values of the other parameters.
            let mut lines: Vec<(String, Vec<(f64, f64)>)> = Vec::new();
            for r in rows {
                let key: Vec<String> = (r.set.iter().enumerate())
                    .filter(|&(k, _)| k != pi && grid)
                    .map(|(_, (n, v))| format!("{n}={v}"))
                    .collect();
                let key = key.join(", ");
                let point = (r.parameters[pi], r.outputs[oi]);
                match lines.iter_mut().find(|(k, _)| *k == key) {
                    Some((_, pts)) => pts.push(point),
                    None => lines.push((key, vec![point])),
                }
            }
            let total = lines.len();
            let shown = total.min(MAX_LINES);
            let title = if total > shown {
                format!("{} against {p} ({shown} of {total} lines)", o.name)
            } else {
                format!("{} against {p}", o.name)
            };
            let series = (lines.into_iter().take(shown).enumerate())
                .map(|(k, (label, mut points))| {
                    points.sort_by(|a, b| a.0.total_cmp(&b.0));
                    Series {
                        label: if label.is_empty() {
                            o.name.clone()
                        } else {
                            label
                        },
                        style: Style {
                            colour: k,
                            dash: 0,
                            markers: true,
                        },
                        points,
                    }
                })
                .collect();
            let mut fig = Figure::new(&title, p);
            fig.panels.push(Panel {
                title: o.text.clone(),
                y_label: o.name.clone(),
                series,
                y_extent: None,
            });
            out.push((
                format!("{}_vs_{p}.svg", o.name),
                cardan_plot::render_svg(&fig),
            ));
        }
    }
    out
}
