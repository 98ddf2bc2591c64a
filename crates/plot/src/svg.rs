//! SVG text of a figure.

use crate::color::Color;
use crate::error::PlotError;
use crate::figure::LegendKey;
use crate::figure::{Figure, Panel};
use crate::layout::{
    legend_entry_widths, legend_font_size, legend_height, legend_key_and_gap, legend_row_height,
    legend_rows, plot_area, title_height, PlotArea, CHAR_WIDTH, TICK_LENGTH,
};
use crate::ticks::format_tick;
use std::fmt::Write as _;

/// Font family written in the SVG: the embedded DejaVu Sans first, common fallbacks after.
pub const FONT_FAMILY: &str = "DejaVu Sans, Verdana, Arial, Helvetica, sans-serif";

/// Text with the XML special characters escaped.
pub fn escape(text: &str) -> String {
    let mut s = String::with_capacity(text.len());
    for c in text.chars() {
        match c {
            '&' => s.push_str("&amp;"),
            '<' => s.push_str("&lt;"),
            '>' => s.push_str("&gt;"),
            '"' => s.push_str("&quot;"),
            '\'' => s.push_str("&apos;"),
            c if (c as u32) < 0x20 && c != '\t' && c != '\n' => {}
            c => s.push(c),
        }
    }
    s
}

/// `fill`/`stroke` attribute value and opacity attribute of a colour.
fn paint(attr: &str, c: Color) -> String {
    if c.alpha < 1.0 {
        format!("{attr}=\"{}\" {attr}-opacity=\"{:.3}\"", c.hex(), c.alpha)
    } else {
        format!("{attr}=\"{}\"", c.hex())
    }
}

/// Path data of the finite runs of a polyline.
fn line_path(area: &PlotArea, x: &[f64], y: &[f64]) -> String {
    let mut d = String::new();
    let mut pen_down = false;
    for (&xv, &yv) in x.iter().zip(y) {
        if xv.is_finite() && yv.is_finite() {
            let (px, py) = area.map(xv, yv);
            let _ = write!(d, "{}{px:.2},{py:.2}", if pen_down { 'L' } else { 'M' });
            pen_down = true;
        } else {
            pen_down = false;
        }
    }
    d
}

/// Path data of the closed polygons of the finite runs of a band.
fn band_path(area: &PlotArea, x: &[f64], lo: &[f64], hi: &[f64]) -> String {
    let mut d = String::new();
    let n = x.len().min(lo.len()).min(hi.len());
    let ok = |i: usize| x[i].is_finite() && lo[i].is_finite() && hi[i].is_finite();
    let mut i = 0;
    while i < n {
        if !ok(i) {
            i += 1;
            continue;
        }
        let start = i;
        while i < n && ok(i) {
            i += 1;
        }
        for k in start..i {
            let (px, py) = area.map(x[k], hi[k]);
            let _ = write!(d, "{}{px:.2},{py:.2}", if k == start { 'M' } else { 'L' });
        }
        for k in (start..i).rev() {
            let (px, py) = area.map(x[k], lo[k]);
            let _ = write!(d, "L{px:.2},{py:.2}");
        }
        d.push('Z');
    }
    d
}

fn text(out: &mut String, x: f64, y: f64, size: f64, anchor: &str, rotate: bool, content: &str) {
    let transform = if rotate {
        format!(" transform=\"rotate(-90 {x:.2} {y:.2})\"")
    } else {
        String::new()
    };
    let _ = writeln!(
        out,
        "<text x=\"{x:.2}\" y=\"{y:.2}\" font-size=\"{size}\" text-anchor=\"{anchor}\"{transform}>{}</text>",
        escape(content)
    );
}

fn write_panel(out: &mut String, fig: &Figure, index: usize, p: &Panel) {
    let a = plot_area(fig, index);
    let fs = fig.font_size;
    let clip = format!("clip{index}");
    let _ = writeln!(
        out,
        "<g id=\"panel{index}\">\n<clipPath id=\"{clip}\"><rect x=\"{:.2}\" y=\"{:.2}\" width=\"{:.2}\" height=\"{:.2}\"/></clipPath>",
        a.left, a.top, a.width, a.height
    );
    // Bands under everything else.
    for b in &p.bands {
        let d = band_path(&a, &b.x, &b.lower, &b.upper);
        if !d.is_empty() {
            let _ = writeln!(
                out,
                "<path d=\"{d}\" {} stroke=\"none\" clip-path=\"url(#{clip})\"/>",
                paint("fill", b.color)
            );
        }
    }
    if p.zero_line && a.y.min < 0.0 && a.y.max > 0.0 {
        let (_, y0) = a.map(0.0, 0.0);
        let _ = writeln!(
            out,
            "<line x1=\"{:.2}\" y1=\"{y0:.2}\" x2=\"{:.2}\" y2=\"{y0:.2}\" stroke=\"#999999\" stroke-width=\"0.8\"/>",
            a.left,
            a.left + a.width
        );
    }
    for s in &p.series {
        let d = line_path(&a, &s.x, &s.y);
        if d.is_empty() {
            continue;
        }
        let dash = match &s.dash {
            Some(v) if !v.is_empty() && v.iter().all(|x| x.is_finite() && *x >= 0.0) => {
                let parts: Vec<String> = v.iter().map(|x| format!("{x:.2}")).collect();
                format!(" stroke-dasharray=\"{}\"", parts.join(","))
            }
            _ => String::new(),
        };
        let _ = writeln!(
            out,
            "<path d=\"{d}\" fill=\"none\" {} stroke-width=\"{:.2}\" stroke-linejoin=\"round\" stroke-linecap=\"round\"{dash} clip-path=\"url(#{clip})\"/>",
            paint("stroke", s.color),
            s.width
        );
    }
    // Axes: left and bottom spines with outward ticks.
    let (x0, y0) = (a.left, a.top + a.height);
    let _ = writeln!(
        out,
        "<path d=\"M{:.2},{:.2}L{x0:.2},{y0:.2}L{:.2},{y0:.2}\" fill=\"none\" stroke=\"#000000\" stroke-width=\"1\"/>",
        a.left,
        a.top,
        a.left + a.width
    );
    for &v in &a.x.values {
        let (px, _) = a.map(v, 0.0);
        let _ = writeln!(
            out,
            "<line x1=\"{px:.2}\" y1=\"{y0:.2}\" x2=\"{px:.2}\" y2=\"{:.2}\" stroke=\"#000000\" stroke-width=\"1\"/>",
            y0 + TICK_LENGTH
        );
        text(
            out,
            px,
            y0 + TICK_LENGTH + fs,
            fs,
            "middle",
            false,
            &format_tick(v, a.x.step),
        );
    }
    for &v in &a.y.values {
        let (_, py) = a.map(0.0, v);
        let _ = writeln!(
            out,
            "<line x1=\"{x0:.2}\" y1=\"{py:.2}\" x2=\"{:.2}\" y2=\"{py:.2}\" stroke=\"#000000\" stroke-width=\"1\"/>",
            x0 - TICK_LENGTH
        );
        text(
            out,
            x0 - TICK_LENGTH - 2.0,
            py + 0.35 * fs,
            fs,
            "end",
            false,
            &format_tick(v, a.y.step),
        );
    }
    let ls = fs + 1.0;
    if !p.title.is_empty() {
        text(
            out,
            a.left + 0.5 * a.width,
            a.top - 0.6 * ls,
            ls,
            "middle",
            false,
            &p.title,
        );
    }
    if !p.x.label.is_empty() {
        text(
            out,
            a.left + 0.5 * a.width,
            y0 + TICK_LENGTH + 1.3 * fs + 1.1 * ls,
            ls,
            "middle",
            false,
            &p.x.label,
        );
    }
    if !p.y.label.is_empty() {
        let x = a.cell_left + 4.0 + ls;
        text(
            out,
            x,
            a.top + 0.5 * a.height,
            ls,
            "middle",
            true,
            &p.y.label,
        );
    }
    if p.legend {
        write_legend(out, &a, p, fs);
    }
    out.push_str("</g>\n");
}

/// Top-left corner of the legend box of size `w × h`: the corner of the plot area (top
/// right, top left, bottom right, bottom left, in that order of preference) whose box covers
/// the fewest line vertices and band samples.
pub fn legend_corner(a: &PlotArea, p: &Panel, w: f64, h: f64) -> (f64, f64) {
    let m = 4.0;
    let corners = [
        (a.left + a.width - w - m, a.top + m),
        (a.left + m, a.top + m),
        (a.left + a.width - w - m, a.top + a.height - h - m),
        (a.left + m, a.top + a.height - h - m),
    ];
    // A box wider than the plot area starts at its left edge.
    let corners = corners.map(|(x, y)| (x.max(a.left), y));
    let cost = |&(x, y): &(f64, f64)| -> usize {
        let inside_x = |px: f64| px >= x && px <= x + w;
        let mut n = 0;
        for s in &p.series {
            for (&xv, &yv) in s.x.iter().zip(&s.y) {
                let (px, py) = a.map(xv, yv);
                if inside_x(px) && py >= y && py <= y + h {
                    n += 1;
                }
            }
        }
        for b in &p.bands {
            for (&xv, (&lo, &hi)) in b.x.iter().zip(b.lower.iter().zip(&b.upper)) {
                let (px, py_hi) = a.map(xv, hi);
                let (_, py_lo) = a.map(xv, lo);
                if inside_x(px) && py_hi <= y + h && py_lo >= y {
                    n += 1;
                }
            }
        }
        n
    };
    let mut best = corners[0];
    let mut best_cost = usize::MAX;
    for c in &corners {
        let k = cost(c);
        if k < best_cost {
            best = *c;
            best_cost = k;
        }
    }
    best
}

fn write_legend(out: &mut String, a: &PlotArea, p: &Panel, fs: f64) {
    let entries: Vec<(&str, Option<&crate::figure::Series>, Option<Color>)> = p
        .bands
        .iter()
        .filter_map(|b| b.label.as_deref().map(|l| (l, None, Some(b.color))))
        .chain(
            p.series
                .iter()
                .filter_map(|s| s.label.as_deref().map(|l| (l, Some(s), None))),
        )
        .collect();
    if entries.is_empty() {
        return;
    }
    let row = 1.35 * fs;
    let sample = 2.0 * fs;
    let chars = entries
        .iter()
        .map(|e| e.0.chars().count())
        .max()
        .unwrap_or(0) as f64;
    let w = 6.0 + sample + 4.0 + CHAR_WIDTH * fs * chars + 6.0;
    let h = 4.0 + row * entries.len() as f64 + 2.0;
    let (x, y) = legend_corner(a, p, w, h);
    let _ = writeln!(
        out,
        "<rect x=\"{x:.2}\" y=\"{y:.2}\" width=\"{w:.2}\" height=\"{h:.2}\" fill=\"#ffffff\" fill-opacity=\"0.85\" stroke=\"#bbbbbb\" stroke-width=\"0.6\"/>"
    );
    for (k, (label, series, band)) in entries.iter().enumerate() {
        let cy = y + 4.0 + row * (k as f64 + 0.5);
        let sx = x + 6.0;
        if let Some(c) = band {
            let _ = writeln!(
                out,
                "<rect x=\"{sx:.2}\" y=\"{:.2}\" width=\"{sample:.2}\" height=\"{:.2}\" {}/>",
                cy - 0.35 * fs,
                0.7 * fs,
                paint("fill", *c)
            );
        }
        if let Some(s) = series {
            let dash = match &s.dash {
                Some(v) if !v.is_empty() => {
                    let parts: Vec<String> = v.iter().map(|x| format!("{x:.2}")).collect();
                    format!(" stroke-dasharray=\"{}\"", parts.join(","))
                }
                _ => String::new(),
            };
            let _ = writeln!(
                out,
                "<line x1=\"{sx:.2}\" y1=\"{cy:.2}\" x2=\"{:.2}\" y2=\"{cy:.2}\" {} stroke-width=\"{:.2}\"{dash}/>",
                sx + sample,
                paint("stroke", s.color),
                s.width
            );
        }
        text(
            out,
            sx + sample + 4.0,
            cy + 0.35 * fs,
            fs,
            "start",
            false,
            label,
        );
    }
}

fn dash_attr(dash: &Option<Vec<f64>>) -> String {
    match dash {
        Some(v) if !v.is_empty() && v.iter().all(|x| x.is_finite() && *x >= 0.0) => {
            let parts: Vec<String> = v.iter().map(|x| format!("{x:.2}")).collect();
            format!(" stroke-dasharray=\"{}\"", parts.join(","))
        }
        _ => String::new(),
    }
}

/// The figure-level legend: centred rows of entries (as many as the width needs) from
/// height `top` down.
fn write_figure_legend(out: &mut String, fig: &Figure, top: f64) {
    let fs = legend_font_size(fig);
    let (key, gap) = legend_key_and_gap(fig);
    let widths = legend_entry_widths(fig);
    let row_h = legend_row_height(fig);
    for (r, row) in legend_rows(fig).into_iter().enumerate() {
        let cy = top + (r as f64 + 0.5) * row_h;
        let total = widths[row.clone()].iter().sum::<f64>() + gap * (row.len() - 1) as f64;
        let mut x = (0.5 * (fig.width as f64 - total)).max(4.0);
        for i in row {
            let e = &fig.legend[i];
            match &e.key {
                LegendKey::Fill(c) => {
                    let _ = writeln!(
                        out,
                        "<rect x=\"{x:.2}\" y=\"{:.2}\" width=\"{key:.2}\" height=\"{:.2}\" {}/>",
                        cy - 0.4 * fs,
                        0.8 * fs,
                        paint("fill", *c)
                    );
                }
                LegendKey::Line { color, width, dash } => {
                    let _ = writeln!(
                        out,
                        "<line x1=\"{x:.2}\" y1=\"{cy:.2}\" x2=\"{:.2}\" y2=\"{cy:.2}\" {} stroke-width=\"{width:.2}\"{}/>",
                        x + key,
                        paint("stroke", *color),
                        dash_attr(dash)
                    );
                }
            }
            text(
                out,
                x + key + 0.4 * fs,
                cy + 0.35 * fs,
                fs,
                "start",
                false,
                &e.label,
            );
            x += widths[i] + gap;
        }
    }
}

impl Figure {
    /// The figure as SVG text (width × height user units = px).
    pub fn to_svg(&self) -> Result<String, PlotError> {
        self.validate()?;
        let (w, h) = (self.width, self.height);
        let mut out = String::new();
        let _ = writeln!(
            out,
            "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<svg xmlns=\"http://www.w3.org/2000/svg\" version=\"1.1\" width=\"{w}\" height=\"{h}\" viewBox=\"0 0 {w} {h}\" font-family=\"{FONT_FAMILY}\" fill=\"#000000\">\n<rect x=\"0\" y=\"0\" width=\"{w}\" height=\"{h}\" fill=\"#ffffff\"/>"
        );
        let legend_h = legend_height(self);
        if let Some(t) = &self.title {
            let size = self.font_size + 3.0;
            text(
                &mut out,
                0.5 * w as f64,
                0.5 * (title_height(self) - legend_h) + 0.35 * size,
                size,
                "middle",
                false,
                t,
            );
        }
        if !self.legend.is_empty() {
            write_figure_legend(&mut out, self, title_height(self) - legend_h);
        }
        for (i, p) in self.panels.iter().enumerate() {
            write_panel(&mut out, self, i, p);
        }
        out.push_str("</svg>\n");
        Ok(out)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn escapes_xml_specials() {
        assert_eq!(
            escape("a<b & \"c\" > 'd'"),
            "a&lt;b &amp; &quot;c&quot; &gt; &apos;d&apos;"
        );
    }
}
