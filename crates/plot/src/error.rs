//! Errors of figure construction and rendering.

/// Why a figure could not be produced.
#[derive(Debug, thiserror::Error)]
pub enum PlotError {
    /// The figure has more panels than grid cells.
    #[error("figure has {panels} panels but its grid has only {rows}×{cols} cells")]
    TooManyPanels {
        /// Number of panels.
        panels: usize,
        /// Grid rows.
        rows: usize,
        /// Grid columns.
        cols: usize,
    },
    /// The figure size or grid is zero or too small to draw in.
    #[error("figure of {width}×{height} px with a {rows}×{cols} grid is too small to draw")]
    BadSize {
        /// Width [px].
        width: u32,
        /// Height [px].
        height: u32,
        /// Grid rows.
        rows: usize,
        /// Grid columns.
        cols: usize,
    },
    /// A series or band has coordinate vectors of different lengths.
    #[error("panel {panel} (\"{title}\"), {what}: {detail}")]
    BadData {
        /// Panel index (0-based, row-major).
        panel: usize,
        /// Panel title.
        title: String,
        /// Which series or band.
        what: String,
        /// What is wrong.
        detail: String,
    },
    /// Fixed axis limits are not finite or not increasing.
    #[error(
        "panel {panel} (\"{title}\"): {axis} limits [{lo}, {hi}] must be finite and increasing"
    )]
    BadLimits {
        /// Panel index (0-based, row-major).
        panel: usize,
        /// Panel title.
        title: String,
        /// `x` or `y`.
        axis: &'static str,
        /// Lower limit.
        lo: f64,
        /// Upper limit.
        hi: f64,
    },
    /// The SVG could not be rasterised.
    #[error("rendering PNG: {0}")]
    Render(String),
}
