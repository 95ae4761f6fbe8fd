//! How a [`Table`] is drawn ([`Table::to_svg`]): small multiples built from its column headers.
//!
//! Each panel holds one unit and the columns of one or a few elements (`panels`: reactions
//! one joint per panel, forces apart from torques; at most 8 series). The colour follows the
//! element (for reactions: the body the reaction acts on) through all panels of the table, the
//! dash the vector component (x solid, y dashed, z dotted). Long tables are reduced per column
//! to [`PRE_COLUMNS`] min/max buckets while the series are collected, so the figure never holds
//! a copy of every sample; `cardan-plot` then decimates to the panel's pixel width. The CSV keeps
//! every sample.

mod header;
mod panels;

use cardan_plot::{decimate, Figure, Panel, Series, Style};

use crate::table::Table;
use header::{y_label, Header};
use panels::{panels, PanelSpec};
use std::collections::HashMap;

/// Buckets of the first reduction of a long column (more than any panel is wide).
pub const PRE_COLUMNS: usize = 2048;

/// The most panels one figure draws. A table of a large model (10⁴ bodies: 10⁴ panels) shows the
/// panels whose series change most; the title says how many there are, the CSV keeps them all.
pub const MAX_PANELS: usize = 24;

impl Table {
    /// The SVG plot of the table: small multiples, one unit per panel ([`figure`]).
    pub fn to_svg(&self) -> String {
        cardan_plot::render_svg(&figure(self))
    }
}

/// The figure of a table: one panel per group of columns, two panels per row.
pub fn figure(table: &Table) -> Figure {
    let headers: Vec<Header> = table.columns.iter().map(|c| Header::parse(c)).collect();
    let keys = colour_keys(&headers);
    let (t0, t1) = time_range(table);
    let mut specs = panels(&headers);
    let mut title = table.title.clone();
    if specs.len() > MAX_PANELS {
        let total = specs.len();
        specs = most_changing(table, specs, MAX_PANELS);
        title.push_str(&format!(
            " ({MAX_PANELS} of {total} panels: those that change most; the CSV has every column)"
        ));
    }
    let mut fig = Figure::new(&title, "t [s]");
    fig.columns = if specs.len() > 1 { 2 } else { 1 };
    fig.panels = specs
        .iter()
        .map(|spec| panel(table, &headers, &keys, spec, (t0, t1)))
        .collect();
    flatten_round_off(&mut fig.panels);
    fig
}

/// The `keep` panels of `specs` whose largest peak-to-peak change, relative to the largest of
/// their unit, is greatest (ties: the earlier), in their original order.
fn most_changing(table: &Table, specs: Vec<PanelSpec>, keep: usize) -> Vec<PanelSpec> {
    let width = table.columns.len();
    let (mut lo, mut hi) = (vec![f64::INFINITY; width], vec![f64::NEG_INFINITY; width]);
    for row in &table.rows {
        for (c, v) in row.iter().skip(1).enumerate().take(width) {
            if v.is_finite() {
                lo[c] = lo[c].min(*v);
                hi[c] = hi[c].max(*v);
            }
        }
    }
    let change = |s: &PanelSpec| {
        s.columns
            .iter()
            .map(|&c| hi[c] - lo[c])
            .filter(|d| d.is_finite())
            .fold(0.0, f64::max)
    };
    let changes: Vec<f64> = specs.iter().map(change).collect();
    let mut unit_max: HashMap<&str, f64> = HashMap::new();
    for (s, &d) in specs.iter().zip(&changes) {
        let m = unit_max.entry(s.unit.as_str()).or_insert(0.0);
        *m = m.max(d);
    }
    let score: Vec<f64> = specs
        .iter()
        .zip(&changes)
        .map(|(s, &d)| match unit_max[s.unit.as_str()] {
            m if m > 0.0 => d / m,
            _ => 0.0,
        })
        .collect();
    let mut order: Vec<usize> = (0..specs.len()).collect();
    order.sort_by(|&a, &b| score[b].total_cmp(&score[a]).then(a.cmp(&b)));
    let mut chosen = vec![false; specs.len()];
    for &k in order.iter().take(keep) {
        chosen[k] = true;
    }
    specs
        .into_iter()
        .zip(chosen)
        .filter_map(|(s, c)| c.then_some(s))
        .collect()
}

/// Below this fraction of the largest value of its unit in the figure, a panel shows round-off.
const ROUND_OFF: f64 = 1e-10;

/// A panel whose values are all round-off next to its siblings of the same unit (the reaction
/// torques of a spherical joint, say) is drawn on the siblings' scale, where it lies flat at
/// zero, and its title says so with its largest value; the CSV keeps the values.
fn flatten_round_off(panels: &mut [Panel]) {
    let peak = |p: &Panel| {
        p.series
            .iter()
            .flat_map(|s| s.points.iter().map(|q| q.1.abs()))
            .filter(|v| v.is_finite())
            .fold(0.0, f64::max)
    };
    let peaks: Vec<f64> = panels.iter().map(peak).collect();
    let mut scales: HashMap<String, f64> = HashMap::new();
    for (p, &v) in panels.iter().zip(&peaks) {
        let s = scales.entry(p.y_label.clone()).or_insert(0.0);
        *s = s.max(v);
    }
    for k in 0..panels.len() {
        let scale = scales[&panels[k].y_label];
        if scale > 0.0 && peaks[k] <= ROUND_OFF * scale {
            panels[k].y_extent = Some(scale);
            panels[k]
                .title
                .push_str(&format!(" (round-off only, |max| {:.1e})", peaks[k]));
        }
    }
}

/// The colour of each key of the table: its index in order of first appearance.
fn colour_keys<'a>(headers: &[Header<'a>]) -> HashMap<&'a str, usize> {
    let mut keys: HashMap<&str, usize> = HashMap::new();
    for h in headers {
        let next = keys.len();
        keys.entry(h.colour_key).or_insert(next);
    }
    keys
}

/// The finite time range of the rows ((0, 0) without any).
fn time_range(table: &Table) -> (f64, f64) {
    let times = table.rows.iter().filter_map(|r| r.first().copied());
    let (lo, hi) = times
        .filter(|t| t.is_finite())
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), t| {
            (a.min(t), b.max(t))
        });
    if lo <= hi {
        (lo, hi)
    } else {
        (0.0, 0.0)
    }
}

/// One panel of the figure.
fn panel(
    table: &Table,
    headers: &[Header],
    keys: &HashMap<&str, usize>,
    spec: &PanelSpec,
    t: (f64, f64),
) -> Panel {
    let mut title = spec.elements.join(", ");
    if let Some((k, n)) = spec.part {
        title.push_str(&format!(" ({k}/{n})"));
    }
    let single = (spec.elements.len() == 1).then(|| spec.elements[0].as_str());
    let mut series: Vec<Series> = spec
        .columns
        .iter()
        .map(|&c| {
            let h = &headers[c];
            let colour = keys.get(h.colour_key).copied().unwrap_or(0);
            Series {
                label: legend_label(h.label, single),
                style: Style {
                    colour,
                    dash: h.dash,
                    markers: false,
                },
                points: column(table, c, t),
            }
        })
        .collect();
    separate_clashes(&mut series);
    Panel {
        title,
        y_label: y_label(&spec.unit),
        series,
        y_extent: None,
    }
}

/// The label in the legend: without the panel's element when the panel shows only that one.
fn legend_label(label: &str, element: Option<&str>) -> String {
    element
        .and_then(|e| label.strip_prefix(e))
        .and_then(|rest| rest.strip_prefix('.'))
        .filter(|rest| !rest.is_empty())
        .unwrap_or(label)
        .to_string()
}

/// Column `c` against time, reduced to [`PRE_COLUMNS`] min/max buckets over `t`.
fn column(table: &Table, c: usize, t: (f64, f64)) -> Vec<(f64, f64)> {
    let samples = table.rows.iter().map(|r| {
        let at = |k: usize| r.get(k).copied().unwrap_or(f64::NAN);
        (at(0), at(c + 1))
    });
    decimate(samples, t.0, t.1, PRE_COLUMNS)
}

/// When two series of a panel would look alike (same colour and dash: two points of one body),
/// the panel's series are coloured by their position instead.
fn separate_clashes(series: &mut [Series]) {
    let looks: Vec<(usize, usize)> = series
        .iter()
        .map(|s| (s.style.colour, s.style.dash))
        .collect();
    let clash = looks
        .iter()
        .enumerate()
        .any(|(k, l)| looks[..k].contains(l));
    if clash {
        for (k, s) in series.iter_mut().enumerate() {
            s.style.colour = k;
            s.style.dash = 0;
        }
    }
}

/// The plot files a run writes beside a table's CSV file.
#[derive(Debug, Clone, Copy, Default)]
pub struct PlotFiles {
    /// An SVG per table (the model file's `plots`), except the Newton residual's.
    pub svg: bool,
    /// A PNG beside each SVG (`--png`).
    pub png: bool,
}

impl PlotFiles {
    /// Whether the table `name` is plotted.
    pub fn plots(&self, name: &str) -> bool {
        self.svg && name != "residual"
    }

    /// The plot files of the table `name`.
    pub fn of(&self, name: &str) -> Vec<String> {
        let mut files = Vec::new();
        if self.plots(name) {
            if self.png {
                files.push(format!("{name}.png"));
            }
            files.push(format!("{name}.svg"));
        }
        files
    }
}

#[cfg(test)]
mod tests;
