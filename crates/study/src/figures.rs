//! Figures of a speed series (paper Fig. 2 style): cost of transport versus speed with the
//! walking (quadratic) and running (linear) fits, and stride frequency versus speed with
//! its walking fit and the literature line; written as SVG and PNG.

use crate::analysis::{literature_stride_frequency, Fit, SpeedSeries};
use crate::store::{io_err, StoreError};
use std::path::Path;
use stride_model::storage::write_atomic;
use stride_plot::{Color, Figure, LegendEntry, Panel, Series};

/// Resolution factor of the PNG relative to the SVG size.
const PNG_SCALE: f32 = 2.0;

/// Sampled curve of a fit between two speeds [m s⁻¹].
fn fit_curve(f: &Fit, lo: f64, hi: f64) -> (Vec<f64>, Vec<f64>) {
    let x: Vec<f64> = (0..=40).map(|k| lo + (hi - lo) * k as f64 / 40.0).collect();
    let y = x.iter().map(|&v| f.eval(v)).collect();
    (x, y)
}

/// The figure of one speed series (`None` with fewer than two points with outcomes).
pub fn speed_series_figure(s: &SpeedSeries, title: &str) -> Option<Figure> {
    let (xc, yc): (Vec<f64>, Vec<f64>) = s
        .points
        .iter()
        .filter_map(|p| p.cost_of_transport.map(|c| (p.speed, c)))
        .unzip();
    let (xf, yf): (Vec<f64>, Vec<f64>) = s
        .points
        .iter()
        .filter_map(|p| p.stride_frequency.map(|f| (p.speed, f)))
        .unzip();
    if xc.len() < 2 {
        return None;
    }
    let lo = xc[0];
    let hi = xc[xc.len() - 1];
    let t = s.transition_speed.unwrap_or(hi);
    let data = Series::new(xc, yc, Color::BLACK)
        .width(2.0)
        .label("prediction");
    let mut cot = Panel::new("Cost of transport", "speed [m/s]", "COT [J/kg/m]").line(data.clone());
    let walk_fit = s.cot_walking_fit.as_ref().map(|f| {
        let (x, y) = fit_curve(f, lo, t);
        Series::new(x, y, Color::BLUE)
            .dash(vec![6.0, 4.0])
            .label(format!("walking fit, {}", f.quality(2)))
    });
    let run_fit = s.cot_running_fit.as_ref().map(|f| {
        let (x, y) = fit_curve(f, t, hi);
        Series::new(x, y, Color::RED)
            .dash(vec![6.0, 4.0])
            .label(format!("running fit, {}", f.quality(2)))
    });
    for l in walk_fit.iter().chain(&run_fit) {
        cot = cot.line(l.clone());
    }
    let mut fig = Figure::new(1200, 500, 1, 2)
        .title(title.to_string())
        .legend_entry(LegendEntry::for_series(&data, "prediction"));
    if let (Some(l), Some(f)) = (&walk_fit, &s.cot_walking_fit) {
        let label = format!("walking fit (quadratic), {}", f.quality(2));
        fig = fig.legend_entry(LegendEntry::for_series(l, &label));
    }
    if let (Some(l), Some(f)) = (&run_fit, &s.cot_running_fit) {
        let label = format!("running fit (linear), {}", f.quality(2));
        fig = fig.legend_entry(LegendEntry::for_series(l, &label));
    }
    let mut sf = Panel::new("Stride frequency", "speed [m/s]", "stride frequency [1/s]");
    if xf.len() >= 2 {
        let lit_x = vec![xf[0], xf[xf.len() - 1]];
        let lit_y = lit_x
            .iter()
            .map(|&v| literature_stride_frequency(v))
            .collect();
        let lit = Series::new(lit_x, lit_y, Color::GREY).label("Hansen et al. 2017");
        sf = sf
            .line(Series::new(xf, yf, Color::BLACK).width(2.0))
            .line(lit.clone());
        fig = fig.legend_entry(LegendEntry::for_series(
            &lit,
            "literature (Hansen et al. 2017)",
        ));
        if let Some(f) = &s.stride_frequency_walking_fit {
            let (x, y) = fit_curve(f, lo, t);
            sf = sf.line(Series::new(x, y, Color::BLUE).dash(vec![6.0, 4.0]));
        }
    }
    Some(fig.panel(cot).panel(sf))
}

/// Write `figure_speed_series_<i>.svg` and `.png` for every series of a report.
pub fn write_speed_figures(folder: &Path, series: &[SpeedSeries]) -> Result<(), StoreError> {
    for (i, s) in series.iter().enumerate() {
        let key: Vec<String> = s.key.iter().map(|(k, v)| format!("{k} = {v}")).collect();
        let title = if key.is_empty() {
            "Speed dependence".to_string()
        } else {
            format!("Speed dependence ({})", key.join(", "))
        };
        let Some(fig) = speed_series_figure(s, &title) else {
            continue;
        };
        write_figure(&folder.join(format!("figure_speed_series_{i}")), &fig)?;
    }
    Ok(())
}

/// Write a figure as `<base>.svg` and `<base>.png`.
pub fn write_figure(base: &Path, fig: &Figure) -> Result<(), StoreError> {
    let svg = fig.to_svg().map_err(|e| io_err(base, e))?;
    let png = stride_plot::png::svg_to_png(&svg, PNG_SCALE).map_err(|e| io_err(base, e))?;
    let p = base.with_extension("svg");
    write_atomic(&p, svg.as_bytes()).map_err(|e| io_err(&p, e))?;
    let p = base.with_extension("png");
    write_atomic(&p, &png).map_err(|e| io_err(&p, e))
}
