//! Placement of the panels in the figure and the data → pixel maps of their plot areas.

use crate::figure::{Axis, Figure, Panel};
use crate::ticks::{format_tick, nice_ticks, ticks_within, Ticks};

/// Approximate advance width of one character of DejaVu Sans, as a fraction of the font size.
pub const CHAR_WIDTH: f64 = 0.62;
/// Number of tick intervals aimed at on each axis.
pub const TARGET_TICKS: usize = 5;
/// Length of the tick marks [px].
pub const TICK_LENGTH: f64 = 4.0;

/// The plot area of one panel in figure pixels, with the axis limits and ticks it shows.
#[derive(Clone, Debug, PartialEq)]
pub struct PlotArea {
    /// Left edge [px from the figure's left].
    pub left: f64,
    /// Top edge [px from the figure's top].
    pub top: f64,
    /// Width [px].
    pub width: f64,
    /// Height [px].
    pub height: f64,
    /// Horizontal limits and ticks (data units).
    pub x: Ticks,
    /// Vertical limits and ticks (data units).
    pub y: Ticks,
    /// Left edge of the panel's grid cell [px].
    pub cell_left: f64,
    /// Top edge of the panel's grid cell [px].
    pub cell_top: f64,
}

impl PlotArea {
    /// Pixel position (from the figure's top-left corner) of the data point (x, y).
    pub fn map(&self, x: f64, y: f64) -> (f64, f64) {
        (
            self.left + (x - self.x.min) / (self.x.max - self.x.min) * self.width,
            self.top + self.height - (y - self.y.min) / (self.y.max - self.y.min) * self.height,
        )
    }
}

/// Limits and ticks of one axis from its settings and the data range.
fn axis_ticks(a: &Axis, data: Option<(f64, f64)>) -> Ticks {
    let mut t = match (a.limits, data) {
        (Some((lo, hi)), _) => ticks_within(lo, hi, TARGET_TICKS),
        (None, Some((lo, hi))) => nice_ticks(lo, hi, TARGET_TICKS),
        (None, None) => nice_ticks(0.0, 1.0, TARGET_TICKS),
    };
    if let Some(v) = &a.ticks {
        let (lo, hi) = (t.min.min(t.max), t.max.max(t.min));
        t.values = v
            .iter()
            .copied()
            .filter(|x| x.is_finite() && *x >= lo && *x <= hi)
            .collect();
    }
    t
}

/// Height of the figure title band [px].
pub fn title_height(fig: &Figure) -> f64 {
    let title = if fig.title.is_some() {
        2.4 * (fig.font_size + 3.0)
    } else {
        0.0
    };
    title + legend_height(fig)
}

/// Font size of the figure-level legend [px].
pub fn legend_font_size(fig: &Figure) -> f64 {
    fig.font_size + 1.0
}

/// Length of a figure-level legend key [px] and the gap between entries [px].
pub fn legend_key_and_gap(fig: &Figure) -> (f64, f64) {
    let fs = legend_font_size(fig);
    (2.2 * fs, 2.0 * fs)
}

/// Width [px] of each figure-level legend entry: key, space and label.
pub fn legend_entry_widths(fig: &Figure) -> Vec<f64> {
    let fs = legend_font_size(fig);
    let (key, _) = legend_key_and_gap(fig);
    fig.legend
        .iter()
        .map(|e| key + 0.4 * fs + CHAR_WIDTH * fs * e.label.chars().count() as f64)
        .collect()
}

/// The figure-level legend's entries in rows that each fit the figure's width (with a
/// 4 px margin on both sides), as index ranges; an entry wider than the figure gets a row
/// of its own.
pub fn legend_rows(fig: &Figure) -> Vec<std::ops::Range<usize>> {
    let (_, gap) = legend_key_and_gap(fig);
    let room = fig.width as f64 - 8.0;
    let mut rows = Vec::new();
    let (mut start, mut used) = (0, 0.0);
    for (i, w) in legend_entry_widths(fig).into_iter().enumerate() {
        if i > start && used + gap + w > room {
            rows.push(start..i);
            (start, used) = (i, w);
        } else {
            used += if i > start { gap + w } else { w };
        }
    }
    if start < fig.legend.len() {
        rows.push(start..fig.legend.len());
    }
    rows
}

/// Height of one figure-level legend row [px].
pub fn legend_row_height(fig: &Figure) -> f64 {
    2.0 * legend_font_size(fig)
}

/// Height of the figure-level legend [px] (0 without entries).
pub fn legend_height(fig: &Figure) -> f64 {
    legend_rows(fig).len() as f64 * legend_row_height(fig)
}

/// Limits and ticks of a panel's axes.
pub fn panel_ticks(p: &Panel) -> (Ticks, Ticks) {
    let (xr, yr) = p.data_range();
    (axis_ticks(&p.x, xr), axis_ticks(&p.y, yr))
}

/// Plot area of panel `index` (row-major) of `fig`.
pub fn plot_area(fig: &Figure, index: usize) -> PlotArea {
    let fs = fig.font_size;
    let (row, col) = (index / fig.cols, index % fig.cols);
    let cell_w = fig.width as f64 / fig.cols as f64;
    let top0 = title_height(fig);
    let cell_h = (fig.height as f64 - top0) / fig.rows as f64;
    let cell_left = col as f64 * cell_w;
    let cell_top = top0 + row as f64 * cell_h;
    let empty = Panel::default();
    let p = fig.panels.get(index).unwrap_or(&empty);
    let (x, y) = panel_ticks(p);
    let label_chars = y
        .values
        .iter()
        .map(|v| format_tick(*v, y.step).chars().count())
        .max()
        .unwrap_or(1) as f64;
    let y_label = if p.y.label.is_empty() {
        0.0
    } else {
        1.3 * (fs + 1.0)
    };
    let x_label = if p.x.label.is_empty() {
        0.0
    } else {
        1.3 * (fs + 1.0)
    };
    let title = if p.title.is_empty() {
        0.4 * fs
    } else {
        1.6 * (fs + 1.0)
    };
    let left = 6.0 + y_label + CHAR_WIDTH * fs * label_chars + TICK_LENGTH + 4.0;
    let bottom = TICK_LENGTH + 1.5 * fs + x_label + 6.0;
    let right = 0.6 * fs * 0.5 * (format_tick(x.max, x.step).chars().count() as f64) + 6.0;
    PlotArea {
        left: cell_left + left,
        top: cell_top + title + 4.0,
        width: (cell_w - left - right).max(10.0),
        height: (cell_h - title - 4.0 - bottom).max(10.0),
        x,
        y,
        cell_left,
        cell_top,
    }
}

impl Figure {
    /// Plot areas of every panel, in panel order.
    pub fn plot_areas(&self) -> Vec<PlotArea> {
        (0..self.panels.len()).map(|i| plot_area(self, i)).collect()
    }
}
