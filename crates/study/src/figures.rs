//! Figures of a speed series (paper Fig. 2 style): cost of transport versus speed with the
//! walking (quadratic) and running (linear) fits, and stride frequency versus speed with
//! its walking fit and the literature line, and the vertical GRF per speed; written as SVG
//! and PNG. Also the helpers every study figure uses: reading a column of a case's cycle
//! table (`cycle_column`) and writing a figure's files ([`write_figure`]).

use crate::analysis::{literature_stride_frequency, Fit, SpeedSeries};
use crate::store::{io_err, StoreError};
use std::path::Path;
use stride_files::write_atomic;
use stride_plot::{Color, Figure, LegendEntry, Panel, Series};

/// Resolution factor of the PNG relative to the SVG size.
const PNG_SCALE: f32 = 2.0;

/// Sampled curve of a fit between two speeds [m s⁻¹].
fn fit_curve(f: &Fit, lo: f64, hi: f64) -> (Vec<f64>, Vec<f64>) {
    let x: Vec<f64> = (0..=40).map(|k| lo + (hi - lo) * k as f64 / 40.0).collect();
    let y = x.iter().map(|&v| f.eval(v)).collect();
    (x, y)
}

/// A column of a case's CSV table over the gait cycle: (% cycle, values). `column` is the
/// name without the unit the header gives it (`knee_angle_r` for `knee_angle_r [deg]`).
pub(crate) fn cycle_column(path: &Path, column: &str) -> Option<(Vec<f64>, Vec<f64>)> {
    let text = std::fs::read_to_string(path).ok()?;
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next()?.split(',').collect();
    let c = header
        .iter()
        .position(|h| stride_predict::outputs::column_name(h) == column)?;
    let (mut t, mut y) = (Vec::new(), Vec::new());
    for l in lines.filter(|l| !l.trim().is_empty()) {
        let f: Vec<&str> = l.split(',').collect();
        t.push(f.first()?.parse::<f64>().ok()?);
        y.push(f.get(c)?.parse::<f64>().ok()?);
    }
    let (t0, t1) = (*t.first()?, *t.last()?);
    if t1 <= t0 {
        return None;
    }
    // The table holds the open cycle (last sample one step before the end): scale time so
    // that the sample spacing maps to 100 % over the whole cycle.
    let dt = (t1 - t0) / (t.len() - 1) as f64;
    let span = t1 - t0 + dt;
    Some((t.iter().map(|x| 100.0 * (x - t0) / span).collect(), y))
}

/// Colour of a speed on a blue (slowest) to red (fastest) scale.
fn speed_colour(v: f64, lo: f64, hi: f64) -> Color {
    let t = if hi > lo {
        ((v - lo) / (hi - lo)).clamp(0.0, 1.0)
    } else {
        0.0
    };
    let mix = |a: u8, b: u8| (a as f64 + t * (b as f64 - a as f64)).round() as u8;
    Color::rgb(mix(0, 200), mix(90, 30), mix(181, 45))
}

/// Panel of the right vertical ground reaction force [% body weight] over the gait cycle,
/// one line per speed, read from the kept cases' `grf.csv` under `folder/cases`.
fn vertical_grf_panel(s: &SpeedSeries, folder: &Path) -> Option<Panel> {
    let (lo, hi) = (s.points.first()?.speed, s.points.last()?.speed);
    let mut panel = Panel::new(
        "Vertical GRF (right), blue slow → red fast",
        "gait cycle [%]",
        "upward + [% BW]",
    )
    .legend(true);
    let mut any = false;
    let last = s.points.len() - 1;
    for (i, p) in s.points.iter().enumerate() {
        let file = folder.join("cases").join(&p.case).join("grf.csv");
        // tables written before the headers carried units name the column `right_y_pct_bw`
        let column =
            cycle_column(&file, "right_y").or_else(|| cycle_column(&file, "right_y_pct_bw"));
        if let Some((x, y)) = column {
            let mut line = Series::new(x, y, speed_colour(p.speed, lo, hi)).width(1.5);
            // the legend names the ends of the colour scale
            if i == 0 || i == last {
                line = line.label(format!("{:.2} m/s", p.speed));
            }
            panel = panel.line(line);
            any = true;
        }
    }
    let top = panel.data_range().1.map_or(1.0, |(_, hi)| hi.max(1e-9));
    any.then(|| panel.y_limits(0.0, 1.05 * top))
}

/// The figure of one speed series (`None` with fewer than two points with outcomes); with
/// `folder`, a third panel shows the vertical ground reaction force per speed.
pub fn speed_series_figure(s: &SpeedSeries, title: &str, folder: Option<&Path>) -> Option<Figure> {
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
    let grf = folder.and_then(|f| vertical_grf_panel(s, f));
    let columns = if grf.is_some() { 3 } else { 2 };
    let mut fig = Figure::new(600 * columns as u32, 500, 1, columns)
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
    let fig = fig.panel(cot).panel(sf);
    Some(match grf {
        Some(g) => fig.panel(g),
        None => fig,
    })
}

/// Write `figure_speed_series_<i>.svg` and `.png` for every series of a report; `mesh`:
/// the cases' mesh as the caption states it.
pub fn write_speed_figures(
    folder: &Path,
    series: &[SpeedSeries],
    mesh: &str,
) -> Result<(), StoreError> {
    for (i, s) in series.iter().enumerate() {
        let mut caption: Vec<String> = s.key.iter().map(|(k, v)| format!("{k} = {v}")).collect();
        caption.extend((!mesh.is_empty()).then(|| mesh.to_string()));
        let title = if caption.is_empty() {
            "Speed dependence".to_string()
        } else {
            format!("Speed dependence ({})", caption.join(", "))
        };
        let Some(fig) = speed_series_figure(s, &title, Some(folder)) else {
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::analysis::{speed_series_of, Selected};
    use std::collections::BTreeMap;

    fn point(speed: f64, case: &str) -> Selected {
        Selected {
            group: case.into(),
            axes: BTreeMap::new(),
            case: case.into(),
            guess: "quasi-random".into(),
            objective: Some(1.0),
            speed,
            cost_of_transport: Some(3.0 + speed),
            stride_frequency: Some(0.6 + 0.2 * speed),
            stride_length: Some(1.4),
            gait: None,
        }
    }

    /// The vertical GRF panel appears when the kept cases have their `grf.csv`, with one
    /// line per speed coloured from blue (slowest) to red (fastest).
    #[test]
    fn speed_figure_draws_the_vertical_grf_of_each_speed() {
        let root = std::env::temp_dir().join(format!("stride-speed-fig-{}", std::process::id()));
        let s = speed_series_of(BTreeMap::new(), vec![point(1.0, "a"), point(2.0, "b")]);
        assert_eq!(
            speed_series_figure(&s, "t", Some(&root))
                .unwrap()
                .panels
                .len(),
            2
        );
        for case in ["a", "b"] {
            let dir = root.join("cases").join(case);
            std::fs::create_dir_all(&dir).unwrap();
            let rows: String = (0..5)
                .map(|k| format!("{},0,{},0\n", 0.1 * k as f64, 20 * k))
                .collect();
            std::fs::write(
                dir.join("grf.csv"),
                format!("time [s],right_x [% BW],right_y [% BW],right_z [% BW]\n{rows}"),
            )
            .unwrap();
        }
        let fig = speed_series_figure(&s, "t", Some(&root)).unwrap();
        assert_eq!(fig.panels.len(), 3);
        // the legend names the speeds, the title the mesh
        let labels: Vec<_> = fig.panels[2]
            .series
            .iter()
            .filter_map(|l| l.label.as_deref())
            .collect();
        assert_eq!(labels, ["1.00 m/s", "2.00 m/s"]);
        write_speed_figures(&root, &[s], "10 mesh intervals per half cycle").unwrap();
        let svg = std::fs::read_to_string(root.join("figure_speed_series_0.svg")).unwrap();
        assert!(svg.contains("Speed dependence (10 mesh intervals per half cycle)"));
        assert_eq!(speed_colour(1.0, 1.0, 2.0), Color::rgb(0, 90, 181));
        assert_eq!(speed_colour(2.0, 1.0, 2.0), Color::rgb(200, 30, 45));
        std::fs::remove_dir_all(&root).unwrap();
    }
}
