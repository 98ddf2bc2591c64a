//! PNG rendering of the figure's SVG with resvg and the embedded DejaVu Sans.

use crate::error::PlotError;
use crate::figure::Figure;
use resvg::{tiny_skia, usvg};
use std::sync::OnceLock;

/// Family name of the embedded font.
pub const EMBEDDED_FAMILY: &str = "DejaVu Sans";

/// Parse options with only the embedded font (no system font lookup), shared by all renders.
fn options() -> &'static usvg::Options<'static> {
    static OPTIONS: OnceLock<usvg::Options<'static>> = OnceLock::new();
    OPTIONS.get_or_init(|| {
        let mut opt = usvg::Options {
            font_family: EMBEDDED_FAMILY.to_string(),
            ..Default::default()
        };
        let db = opt.fontdb_mut();
        db.load_font_data(dejavu::sans::regular().to_vec());
        db.set_sans_serif_family(EMBEDDED_FAMILY);
        opt
    })
}

/// Parse SVG text with the embedded font (also a well-formedness check).
pub fn parse_svg(svg: &str) -> Result<usvg::Tree, PlotError> {
    usvg::Tree::from_str(svg, options()).map_err(|e| PlotError::Render(e.to_string()))
}

/// Render SVG text to PNG bytes at `scale` output pixels per SVG unit.
pub fn svg_to_png(svg: &str, scale: f32) -> Result<Vec<u8>, PlotError> {
    if !(scale.is_finite() && scale > 0.0) {
        return Err(PlotError::Render(format!("scale {scale} must be positive")));
    }
    let tree = parse_svg(svg)?;
    let size = tree.size();
    let w = (size.width() * scale).ceil() as u32;
    let h = (size.height() * scale).ceil() as u32;
    let mut pixmap = tiny_skia::Pixmap::new(w, h)
        .ok_or_else(|| PlotError::Render(format!("cannot allocate a {w}×{h} image")))?;
    pixmap.fill(tiny_skia::Color::WHITE);
    resvg::render(
        &tree,
        tiny_skia::Transform::from_scale(scale, scale),
        &mut pixmap.as_mut(),
    );
    pixmap
        .encode_png()
        .map_err(|e| PlotError::Render(e.to_string()))
}

impl Figure {
    /// The figure as PNG bytes, `scale` pixels per figure px (e.g. 2 for print quality).
    pub fn to_png(&self, scale: f32) -> Result<Vec<u8>, PlotError> {
        svg_to_png(&self.to_svg()?, scale)
    }
}
