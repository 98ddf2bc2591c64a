//! The figure description: a grid of panels holding lines and shaded bands.

use crate::color::Color;
use crate::error::PlotError;

/// A line through points (x, y); non-finite points break the line.
#[derive(Clone, Debug, PartialEq)]
pub struct Series {
    /// Abscissae (data units).
    pub x: Vec<f64>,
    /// Ordinates (data units), same length as `x`.
    pub y: Vec<f64>,
    /// Line colour.
    pub color: Color,
    /// Line width [px].
    pub width: f64,
    /// Dash pattern (on, off, … lengths in px); `None` = solid.
    pub dash: Option<Vec<f64>>,
    /// Legend text; `None` = not in the legend.
    pub label: Option<String>,
}

impl Series {
    /// Solid line of width 1.5 px in `color`, without a legend entry.
    pub fn new(x: Vec<f64>, y: Vec<f64>, color: Color) -> Self {
        Self {
            x,
            y,
            color,
            width: 1.5,
            dash: None,
            label: None,
        }
    }
    /// Set the line width [px].
    pub fn width(mut self, width: f64) -> Self {
        self.width = width;
        self
    }
    /// Set a dash pattern (lengths in px).
    pub fn dash(mut self, pattern: Vec<f64>) -> Self {
        self.dash = Some(pattern);
        self
    }
    /// Set the legend text.
    pub fn label(mut self, label: impl Into<String>) -> Self {
        self.label = Some(label.into());
        self
    }
}

/// A shaded region between `lower` and `upper` over `x`, drawn under the lines; non-finite
/// samples split the band.
#[derive(Clone, Debug, PartialEq)]
pub struct Band {
    /// Abscissae (data units).
    pub x: Vec<f64>,
    /// Lower bound (data units), same length as `x`.
    pub lower: Vec<f64>,
    /// Upper bound (data units), same length as `x`.
    pub upper: Vec<f64>,
    /// Fill colour; its `alpha` is the fill opacity.
    pub color: Color,
    /// Legend text; `None` = not in the legend.
    pub label: Option<String>,
}

impl Band {
    /// Band between `lower` and `upper` filled with `color`.
    pub fn new(x: Vec<f64>, lower: Vec<f64>, upper: Vec<f64>, color: Color) -> Self {
        Self {
            x,
            lower,
            upper,
            color,
            label: None,
        }
    }
    /// Band of `mean ± k·sd`.
    pub fn mean_sd(x: Vec<f64>, mean: &[f64], sd: &[f64], k: f64, color: Color) -> Self {
        let lower = mean.iter().zip(sd).map(|(m, s)| m - k * s).collect();
        let upper = mean.iter().zip(sd).map(|(m, s)| m + k * s).collect();
        Self::new(x, lower, upper, color)
    }
    /// Set the legend text.
    pub fn label(mut self, label: impl Into<String>) -> Self {
        self.label = Some(label.into());
        self
    }
}

/// One axis of a panel: label, and optional fixed limits and ticks.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Axis {
    /// Axis label, with its unit.
    pub label: String,
    /// Fixed limits (data units); `None` = nice limits around the data.
    pub limits: Option<(f64, f64)>,
    /// Fixed tick positions (data units); `None` = nice ticks.
    pub ticks: Option<Vec<f64>>,
}

impl Axis {
    /// Automatic axis with `label`.
    pub fn new(label: impl Into<String>) -> Self {
        Self {
            label: label.into(),
            limits: None,
            ticks: None,
        }
    }
    /// Fix the limits (data units).
    pub fn limits(mut self, lo: f64, hi: f64) -> Self {
        self.limits = Some((lo, hi));
        self
    }
    /// Fix the tick positions (data units).
    pub fn ticks(mut self, ticks: Vec<f64>) -> Self {
        self.ticks = Some(ticks);
        self
    }
}

/// A data range (min, max), `None` when there is no finite value.
pub type Range = Option<(f64, f64)>;

/// One panel: title, axes, bands (under) and lines (over), legend and zero line options.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Panel {
    /// Title above the plot area.
    pub title: String,
    /// Horizontal axis.
    pub x: Axis,
    /// Vertical axis.
    pub y: Axis,
    /// Lines, drawn in order over the bands.
    pub series: Vec<Series>,
    /// Shaded bands, drawn in order under the lines.
    pub bands: Vec<Band>,
    /// Draw a legend of the labelled series and bands.
    pub legend: bool,
    /// Draw a thin horizontal line at y = 0 when 0 is inside the y limits.
    pub zero_line: bool,
}

impl Panel {
    /// Empty panel with a title and axis labels.
    pub fn new(
        title: impl Into<String>,
        x_label: impl Into<String>,
        y_label: impl Into<String>,
    ) -> Self {
        Self {
            title: title.into(),
            x: Axis::new(x_label),
            y: Axis::new(y_label),
            ..Default::default()
        }
    }
    /// Add a line.
    pub fn line(mut self, s: Series) -> Self {
        self.series.push(s);
        self
    }
    /// Add a shaded band.
    pub fn band(mut self, b: Band) -> Self {
        self.bands.push(b);
        self
    }
    /// Show or hide the legend.
    pub fn legend(mut self, on: bool) -> Self {
        self.legend = on;
        self
    }
    /// Show or hide the zero line.
    pub fn zero_line(mut self, on: bool) -> Self {
        self.zero_line = on;
        self
    }
    /// Fix the x limits.
    pub fn x_limits(mut self, lo: f64, hi: f64) -> Self {
        self.x.limits = Some((lo, hi));
        self
    }
    /// Fix the y limits.
    pub fn y_limits(mut self, lo: f64, hi: f64) -> Self {
        self.y.limits = Some((lo, hi));
        self
    }
    /// Whether the panel has at least one finite data point in a line or band.
    pub fn has_data(&self) -> bool {
        self.series.iter().any(|s| {
            s.x.iter()
                .zip(&s.y)
                .any(|(x, y)| x.is_finite() && y.is_finite())
        }) || self.bands.iter().any(|b| {
            b.x.iter()
                .zip(b.lower.iter().zip(&b.upper))
                .any(|(x, (l, u))| x.is_finite() && l.is_finite() && u.is_finite())
        })
    }
    /// Data range (min, max) of the abscissae and of the ordinates, ignoring non-finite
    /// values; `None` where there is no finite value.
    pub fn data_range(&self) -> (Range, Range) {
        let mut xr: Option<(f64, f64)> = None;
        let mut yr: Option<(f64, f64)> = None;
        let add = |r: &mut Option<(f64, f64)>, v: f64| {
            if v.is_finite() {
                *r = Some(match *r {
                    Some((a, b)) => (a.min(v), b.max(v)),
                    None => (v, v),
                });
            }
        };
        for s in &self.series {
            for (&x, &y) in s.x.iter().zip(&s.y) {
                if x.is_finite() && y.is_finite() {
                    add(&mut xr, x);
                    add(&mut yr, y);
                }
            }
        }
        for b in &self.bands {
            for (&x, (&l, &u)) in b.x.iter().zip(b.lower.iter().zip(&b.upper)) {
                if x.is_finite() && l.is_finite() && u.is_finite() {
                    add(&mut xr, x);
                    add(&mut yr, l);
                    add(&mut yr, u);
                }
            }
        }
        (xr, yr)
    }
}

/// A figure: `rows × cols` panels (row-major) in `width × height` px, with an optional
/// title above the grid.
#[derive(Clone, Debug, PartialEq)]
pub struct Figure {
    /// Width [px] (SVG user units; the PNG is `scale` times this).
    pub width: u32,
    /// Height [px].
    pub height: u32,
    /// Grid rows.
    pub rows: usize,
    /// Grid columns.
    pub cols: usize,
    /// Title above the grid; `None` = no title band.
    pub title: Option<String>,
    /// Panels in row-major order (at most rows × cols; missing cells stay empty).
    pub panels: Vec<Panel>,
    /// Font size of tick labels [px]; titles and axis labels are 1 px larger.
    pub font_size: f64,
    /// Figure-level legend, one row under the title; empty = none.
    pub legend: Vec<LegendEntry>,
}

/// The key drawn next to a legend label.
#[derive(Clone, Debug, PartialEq)]
pub enum LegendKey {
    /// A line sample of a series' colour, width [px] and dash pattern.
    Line {
        /// Line colour.
        color: Color,
        /// Line width [px].
        width: f64,
        /// Dash pattern [px]; `None` = solid.
        dash: Option<Vec<f64>>,
    },
    /// A filled rectangle of a band's colour.
    Fill(Color),
}

/// One entry of a figure-level legend.
#[derive(Clone, Debug, PartialEq)]
pub struct LegendEntry {
    /// Label text.
    pub label: String,
    /// Key drawn before the label.
    pub key: LegendKey,
}

impl LegendEntry {
    /// Entry with the key of series `s` (its own label unless `label` is given).
    pub fn for_series(s: &Series, label: &str) -> Self {
        Self {
            label: label.to_string(),
            key: LegendKey::Line {
                color: s.color,
                width: s.width,
                dash: s.dash.clone(),
            },
        }
    }
    /// Entry with a filled key of `color`.
    pub fn fill(color: Color, label: &str) -> Self {
        Self {
            label: label.to_string(),
            key: LegendKey::Fill(color),
        }
    }
}

impl Figure {
    /// Empty figure of `rows × cols` panels in `width × height` px.
    pub fn new(width: u32, height: u32, rows: usize, cols: usize) -> Self {
        Self {
            width,
            height,
            rows,
            cols,
            title: None,
            panels: Vec::new(),
            font_size: 10.0,
            legend: Vec::new(),
        }
    }
    /// Set the figure title.
    pub fn title(mut self, title: impl Into<String>) -> Self {
        self.title = Some(title.into());
        self
    }
    /// Add an entry to the figure-level legend.
    pub fn legend_entry(mut self, e: LegendEntry) -> Self {
        self.legend.push(e);
        self
    }
    /// Add a panel in the next grid cell.
    pub fn panel(mut self, p: Panel) -> Self {
        self.panels.push(p);
        self
    }

    /// Check sizes, panel count, vector lengths and fixed limits.
    pub fn validate(&self) -> Result<(), PlotError> {
        if self.rows == 0
            || self.cols == 0
            || (self.width as usize) < 60 * self.cols
            || (self.height as usize) < 50 * self.rows
        {
            return Err(PlotError::BadSize {
                width: self.width,
                height: self.height,
                rows: self.rows,
                cols: self.cols,
            });
        }
        if self.panels.len() > self.rows * self.cols {
            return Err(PlotError::TooManyPanels {
                panels: self.panels.len(),
                rows: self.rows,
                cols: self.cols,
            });
        }
        for (i, p) in self.panels.iter().enumerate() {
            let bad = |what: String, detail: String| PlotError::BadData {
                panel: i,
                title: p.title.clone(),
                what,
                detail,
            };
            for (k, s) in p.series.iter().enumerate() {
                if s.x.len() != s.y.len() {
                    return Err(bad(
                        format!("series {k}"),
                        format!("{} x values but {} y values", s.x.len(), s.y.len()),
                    ));
                }
                if !(s.width.is_finite() && s.width > 0.0) {
                    return Err(bad(
                        format!("series {k}"),
                        format!("line width {}", s.width),
                    ));
                }
            }
            for (k, b) in p.bands.iter().enumerate() {
                if b.x.len() != b.lower.len() || b.x.len() != b.upper.len() {
                    return Err(bad(
                        format!("band {k}"),
                        format!(
                            "{} x values, {} lower, {} upper",
                            b.x.len(),
                            b.lower.len(),
                            b.upper.len()
                        ),
                    ));
                }
            }
            for (axis, a) in [("x", &p.x), ("y", &p.y)] {
                if let Some((lo, hi)) = a.limits {
                    if !(lo.is_finite() && hi.is_finite() && lo < hi) {
                        return Err(PlotError::BadLimits {
                            panel: i,
                            title: p.title.clone(),
                            axis,
                            lo,
                            hi,
                        });
                    }
                }
            }
        }
        Ok(())
    }
}
