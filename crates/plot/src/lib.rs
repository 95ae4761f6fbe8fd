//! Line plots as small multiples, written as SVG by hand (no dependencies).
//!
//! A [`Figure`] holds [`Panel`]s that share the x axis range; each panel has its own y axis (one
//! unit per panel: the caller groups series so that quantities of different units never share an
//! axis), at most a handful of [`Series`] and its legend inside the panel. Panels are laid out in
//! a grid of [`Figure::columns`] columns.
//!
//! Long series are decimated for drawing only ([`decimate()`]): per pixel column of the plot area
//! the first, smallest, largest and last sample are kept in their order, so peaks survive and a
//! plot's size is bounded by its pixel width, not by the number of samples.
//!
//! Colours and dash patterns are given by the caller as indices into a fixed palette
//! ([`Style`]), so one element can keep its colour across panels.

mod axis;
mod decimate;
mod path;
#[cfg(feature = "png")]
pub mod png;
mod svg;
mod text;

pub use decimate::decimate;
pub use svg::render_svg;

/// How an axis maps values to positions.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Scale {
    /// Linear, with 1-2-5 ticks.
    #[default]
    Linear,
    /// Base-10 logarithmic, with decade ticks; values ≤ 0 are not drawn.
    Log,
}

/// How one series is drawn: indices into the palette and the dash patterns (taken modulo their
/// lengths), and whether each sample gets a marker.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Style {
    /// Colour index (the same index is the same colour in every panel).
    pub colour: usize,
    /// Dash index: 0 solid, 1 dashed, 2 dotted, 3 dash-dot.
    pub dash: usize,
    /// A dot at every drawn point (for short series such as measurements).
    pub markers: bool,
}

/// One curve: a legend label, its style and its points in drawing order.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Series {
    /// Legend label.
    pub label: String,
    /// Colour, dash and markers.
    pub style: Style,
    /// (x, y) samples; non-finite ones are skipped (they break the line).
    pub points: Vec<(f64, f64)>,
}

/// One axis pair with its series and legend.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Panel {
    /// Title above the panel.
    pub title: String,
    /// The y axis label, with its unit, e.g. `force [N]`.
    pub y_label: String,
    /// The curves.
    pub series: Vec<Series>,
    /// A y extent the axis covers at least (±this value), e.g. the scale of sibling panels of
    /// the same unit, so a series of round-off noise is drawn flat instead of magnified.
    pub y_extent: Option<f64>,
}

/// A figure: a title, a shared x axis and a grid of panels.
#[derive(Debug, Clone, PartialEq)]
pub struct Figure {
    /// Title at the top.
    pub title: String,
    /// The x axis label, with its unit, e.g. `t [s]`.
    pub x_label: String,
    /// Scale of the x axis (shared by all panels).
    pub x_scale: Scale,
    /// Scale of the y axes.
    pub y_scale: Scale,
    /// Panels per row (at least 1).
    pub columns: usize,
    /// The panels, row by row.
    pub panels: Vec<Panel>,
}

impl Figure {
    /// An empty figure with linear axes and one column of panels.
    pub fn new(title: &str, x_label: &str) -> Self {
        Self {
            title: title.into(),
            x_label: x_label.into(),
            x_scale: Scale::Linear,
            y_scale: Scale::Linear,
            columns: 1,
            panels: Vec::new(),
        }
    }
}

/// The colour palette (colour-blind friendly first entries), indexed by [`Style::colour`].
pub const PALETTE: [&str; 10] = [
    "#0072b2", "#d55e00", "#009e73", "#cc79a7", "#e69f00", "#56b4e9", "#000000", "#8c564b",
    "#7f7f7f", "#bcbd22",
];

/// The dash patterns, indexed by [`Style::dash`] (`None` is solid).
pub const DASHES: [Option<&str>; 4] = [None, Some("6 3"), Some("1.5 2.5"), Some("7 3 1.5 3")];
