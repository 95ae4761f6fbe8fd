//! PNG output (feature `png`): the SVG document rendered by resvg, a pure-Rust renderer. Text
//! is drawn in the system's sans-serif font; on a machine without fonts the curves, axes and
//! legend lines are still drawn, without their labels.

use resvg::{tiny_skia, usvg};

/// A rendered image: RGBA pixels, row by row (premultiplied alpha, opaque here: the plots have a
/// white background).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Raster {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// RGBA bytes, 4 per pixel.
    pub rgba: Vec<u8>,
}

/// Why an SVG document could not be rendered.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct RenderError(pub String);

impl std::fmt::Display for RenderError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "cannot render the plot: {}", self.0)
    }
}

impl std::error::Error for RenderError {}

/// Renders an SVG document at its own size.
pub fn rasterize(svg: &str) -> Result<Raster, RenderError> {
    let mut opt = usvg::Options::default();
    load_fonts(opt.fontdb_mut());
    let tree = usvg::Tree::from_str(svg, &opt).map_err(|e| RenderError(e.to_string()))?;
    let size = tree.size().to_int_size();
    let mut pixmap = tiny_skia::Pixmap::new(size.width(), size.height())
        .ok_or_else(|| RenderError(format!("bad size {}×{}", size.width(), size.height())))?;
    resvg::render(&tree, tiny_skia::Transform::default(), &mut pixmap.as_mut());
    Ok(Raster {
        width: pixmap.width(),
        height: pixmap.height(),
        rgba: pixmap.take(),
    })
}

/// Loads the system fonts and makes the first of the usual sans-serif families found (or any
/// family with "Sans" in its name) the one `sans-serif` means.
fn load_fonts(db: &mut usvg::fontdb::Database) {
    db.load_system_fonts();
    const PREFERRED: [&str; 5] = [
        "DejaVu Sans",
        "Liberation Sans",
        "Noto Sans",
        "Arial",
        "Helvetica",
    ];
    let families: Vec<String> = db
        .faces()
        .flat_map(|f| f.families.iter().map(|(name, _)| name.clone()))
        .collect();
    let chosen = PREFERRED
        .iter()
        .find(|p| families.iter().any(|f| f == *p))
        .map(|p| p.to_string())
        .or_else(|| {
            families
                .iter()
                .find(|f| f.contains("Sans") && !f.contains("Mono"))
                .cloned()
        })
        .or_else(|| families.first().cloned());
    if let Some(family) = chosen {
        db.set_sans_serif_family(family);
    }
}

/// Renders an SVG document to PNG bytes.
pub fn svg_to_png(svg: &str) -> Result<Vec<u8>, RenderError> {
    let r = rasterize(svg)?;
    let pixmap = tiny_skia::Pixmap::from_vec(
        r.rgba,
        tiny_skia::IntSize::from_wh(r.width, r.height)
            .ok_or_else(|| RenderError("empty image".into()))?,
    )
    .ok_or_else(|| RenderError("bad pixel buffer".into()))?;
    pixmap.encode_png().map_err(|e| RenderError(e.to_string()))
}

impl Raster {
    /// The variance of the pixels' grey levels (0 for a blank image).
    pub fn grey_variance(&self) -> f64 {
        let greys: Vec<f64> = self
            .rgba
            .chunks_exact(4)
            .map(|p| (f64::from(p[0]) + f64::from(p[1]) + f64::from(p[2])) / 3.0)
            .collect();
        let n = greys.len().max(1) as f64;
        let mean = greys.iter().sum::<f64>() / n;
        greys.iter().map(|g| (g - mean).powi(2)).sum::<f64>() / n
    }

    /// How many pixels have this colour (opaque RGB).
    pub fn count(&self, rgb: [u8; 3]) -> usize {
        self.rgba
            .chunks_exact(4)
            .filter(|p| p[..3] == rgb && p[3] == 255)
            .count()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{render_svg, Figure, Panel, Series, Style};

    #[test]
    fn a_rendered_plot_is_not_blank() {
        let points = (0..500)
            .map(|k| (k as f64, (k as f64 / 40.0).sin()))
            .collect();
        let fig = Figure {
            panels: vec![Panel {
                title: "sine".into(),
                y_label: "[m]".into(),
                series: vec![Series {
                    label: "s".into(),
                    style: Style::default(),
                    points,
                }],
                y_extent: None,
            }],
            ..Figure::new("f", "t [s]")
        };
        let raster = rasterize(&render_svg(&fig)).expect("renders");
        assert!(raster.grey_variance() > 10.0, "{}", raster.grey_variance());
        assert!(
            raster.count([0, 0x72, 0xb2]) > 200,
            "the curve's colour is drawn"
        );
        let png = svg_to_png(&render_svg(&fig)).expect("encodes");
        assert_eq!(&png[1..4], b"PNG");
        let blank = rasterize(&render_svg(&Figure::new("", ""))).expect("renders");
        assert!(blank.grey_variance() < 1.0);
    }

    #[test]
    fn bad_svg_is_an_error() {
        assert!(rasterize("<svg").is_err());
    }
}
