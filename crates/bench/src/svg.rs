//! The report's log-log plots, drawn by `cardan-plot` (the plotting module of the command line
//! too): one panel, decade ticks, a marker at every measurement.

use cardan_plot::{render_svg, Figure, Panel, Scale, Style};

/// One series: a label and its points.
pub struct Series {
    /// Legend label.
    pub label: String,
    /// (x, y) points, drawn in order.
    pub points: Vec<(f64, f64)>,
}

/// A log-log plot with decade grid lines; values ≤ 0 are not drawn.
pub fn loglog(title: &str, xlabel: &str, ylabel: &str, series: &[Series]) -> String {
    let series = series
        .iter()
        .enumerate()
        .map(|(k, s)| cardan_plot::Series {
            label: s.label.clone(),
            style: Style {
                colour: k,
                dash: 0,
                markers: true,
            },
            points: s.points.clone(),
        })
        .collect();
    let fig = Figure {
        x_scale: Scale::Log,
        y_scale: Scale::Log,
        panels: vec![Panel {
            title: String::new(),
            y_label: ylabel.into(),
            series,
            y_extent: None,
        }],
        ..Figure::new(title, xlabel)
    };
    render_svg(&fig)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn loglog_draws_positive_points_only() {
        let s = Series {
            label: "a".into(),
            points: vec![(1.0, 1e-3), (10.0, 1e-2), (0.0, 5.0)],
        };
        let svg = loglog("t", "x", "y [s]", &[s]);
        assert_eq!(svg.matches("<circle").count(), 2);
        assert!(svg.contains(">1e-3<") && svg.contains("y [s]"));
    }
}
