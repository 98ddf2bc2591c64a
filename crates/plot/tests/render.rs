//! Rendering checks: SVG well-formed and parseable, PNG decodes at the right size, data
//! coordinates land on the expected pixels, text is drawn.

use resvg::tiny_skia::Pixmap;
use stride_plot::{png::parse_svg, Band, Color, Figure, Panel, PlotError, Series};

/// Balanced tags: every `<name ...>` is closed by `</name>` in order (self-closing and
/// `<?...?>` skipped).
fn balanced(svg: &str) -> bool {
    let mut stack: Vec<String> = Vec::new();
    let mut rest = svg;
    while let Some(i) = rest.find('<') {
        let j = match rest[i..].find('>') {
            Some(j) => i + j,
            None => return false,
        };
        let tag = &rest[i + 1..j];
        if tag.starts_with('?') || tag.starts_with('!') || tag.ends_with('/') {
        } else if let Some(name) = tag.strip_prefix('/') {
            if stack.pop().as_deref() != Some(name.trim()) {
                return false;
            }
        } else {
            let name = tag.split_whitespace().next().unwrap_or("");
            stack.push(name.to_string());
        }
        rest = &rest[j + 1..];
    }
    stack.is_empty()
}

fn sample_figure() -> Figure {
    let x: Vec<f64> = (0..=100).map(|i| i as f64).collect();
    let y: Vec<f64> = x
        .iter()
        .map(|v| (v / 100.0 * std::f64::consts::TAU).sin() * 30.0)
        .collect();
    let sd = vec![5.0; x.len()];
    Figure::new(600, 300, 1, 2)
        .title("Test figure <&>")
        .panel(
            Panel::new("Sine", "gait cycle [%]", "angle [deg]")
                .band(
                    Band::mean_sd(x.clone(), &y, &sd, 2.0, Color::GREY.with_alpha(0.35))
                        .label("experiment"),
                )
                .line(Series::new(x.clone(), y.clone(), Color::BLUE).label("prediction"))
                .legend(true)
                .zero_line(true),
        )
        .panel(
            Panel::new("Dashed", "x", "y").line(
                Series::new(
                    vec![0.0, 1.0, f64::NAN, 2.0, 3.0],
                    vec![0.0, 1.0, 5.0, 0.5, 2.0],
                    Color::RED,
                )
                .dash(vec![4.0, 2.0]),
            ),
        )
}

#[test]
fn svg_is_well_formed_and_parses() {
    let svg = sample_figure().to_svg().unwrap();
    assert!(balanced(&svg), "unbalanced tags");
    assert!(svg.contains("Test figure &lt;&amp;&gt;"));
    let tree = parse_svg(&svg).unwrap();
    assert_eq!(tree.size().width(), 600.0);
    assert_eq!(tree.size().height(), 300.0);
}

#[test]
fn png_decodes_with_the_right_size() {
    let png = sample_figure().to_png(2.0).unwrap();
    assert_eq!(&png[1..4], b"PNG");
    let img = Pixmap::decode_png(&png).unwrap();
    assert_eq!((img.width(), img.height()), (1200, 600));
    if let Ok(dir) = std::env::var("STRIDE_PLOT_SAMPLE_DIR") {
        std::fs::write(format!("{dir}/sample.png"), &png).unwrap();
    }
}

fn pixel(img: &Pixmap, x: f64, y: f64) -> [u8; 3] {
    let p = img.pixel(x.round() as u32, y.round() as u32).unwrap();
    [p.red(), p.green(), p.blue()]
}

#[test]
fn data_coordinates_map_to_the_expected_pixels() {
    // Fixed limits: x ∈ [0, 10], y ∈ [-1, 1]; a horizontal line at y = 0.5 from x = 2 to 8.
    let fig = Figure::new(400, 300, 1, 1).panel(
        Panel::new("", "", "")
            .x_limits(0.0, 10.0)
            .y_limits(-1.0, 1.0)
            .line(Series::new(vec![2.0, 8.0], vec![0.5, 0.5], Color::rgb(255, 0, 0)).width(3.0)),
    );
    let a = &fig.plot_areas()[0];
    // Linear map: corners of the limits are the corners of the plot area.
    assert_eq!(a.map(0.0, -1.0), (a.left, a.top + a.height));
    assert_eq!(a.map(10.0, 1.0), (a.left + a.width, a.top));
    let (px, py) = a.map(5.0, 0.5);
    assert!((px - (a.left + 0.5 * a.width)).abs() < 1e-9);
    assert!((py - (a.top + 0.25 * a.height)).abs() < 1e-9);
    // The SVG path goes through the mapped end points.
    let svg = fig.to_svg().unwrap();
    let (x2, y2) = a.map(2.0, 0.5);
    let (x8, _) = a.map(8.0, 0.5);
    assert!(
        svg.contains(&format!("M{x2:.2},{y2:.2}L{x8:.2},{y2:.2}")),
        "{svg}"
    );
    // The PNG is red there and white away from the line.
    let img = Pixmap::decode_png(&fig.to_png(1.0).unwrap()).unwrap();
    assert_eq!(pixel(&img, px, py), [255, 0, 0]);
    let (qx, qy) = a.map(5.0, -0.5);
    assert_eq!(pixel(&img, qx, qy), [255, 255, 255]);
    // Outside the x range of the line: white.
    let (rx, ry) = a.map(9.0, 0.5);
    assert_eq!(pixel(&img, rx, ry), [255, 255, 255]);
}

#[test]
fn text_is_drawn_with_the_embedded_font() {
    // A big title in an otherwise empty figure: dark pixels appear in the title band only
    // if glyphs were rendered.
    let fig = Figure::new(300, 200, 1, 1).title("MMMM");
    let mut fig2 = fig.clone();
    fig2.font_size = 20.0;
    let img = Pixmap::decode_png(&fig2.to_png(1.0).unwrap()).unwrap();
    let band = (2.4 * 23.0) as u32;
    let dark = (0..band)
        .flat_map(|y| (0..300).map(move |x| (x, y)))
        .filter(|&(x, y)| img.pixel(x, y).map(|p| p.red() < 100).unwrap_or(false))
        .count();
    assert!(dark > 100, "only {dark} dark pixels in the title band");
}

#[test]
fn bands_are_drawn_under_lines() {
    let fig = Figure::new(300, 200, 1, 1).panel(
        Panel::new("", "", "")
            .x_limits(0.0, 1.0)
            .y_limits(0.0, 1.0)
            .line(Series::new(vec![0.0, 1.0], vec![0.5, 0.5], Color::rgb(0, 0, 255)).width(4.0))
            .band(Band::new(
                vec![0.0, 1.0],
                vec![0.25, 0.25],
                vec![0.75, 0.75],
                Color::rgb(0, 200, 0),
            )),
    );
    let a = &fig.plot_areas()[0];
    let img = Pixmap::decode_png(&fig.to_png(1.0).unwrap()).unwrap();
    let (x, y) = a.map(0.5, 0.5);
    assert_eq!(pixel(&img, x, y), [0, 0, 255]);
    let (x, y) = a.map(0.5, 0.4);
    assert_eq!(pixel(&img, x, y), [0, 200, 0]);
}

#[test]
fn bad_input_gives_clear_errors() {
    let fig = Figure::new(300, 200, 1, 1).panel(Panel::new("a", "", "").line(Series::new(
        vec![0.0, 1.0],
        vec![0.0],
        Color::BLACK,
    )));
    let e = fig.to_svg().unwrap_err();
    assert!(matches!(e, PlotError::BadData { panel: 0, .. }), "{e}");
    assert!(e.to_string().contains("2 x values but 1 y values"), "{e}");
    let fig = Figure::new(300, 200, 1, 1)
        .panel(Panel::default())
        .panel(Panel::default());
    assert!(matches!(fig.to_svg(), Err(PlotError::TooManyPanels { .. })));
    let fig = Figure::new(300, 200, 1, 1).panel(Panel::default().y_limits(1.0, 1.0));
    assert!(matches!(
        fig.to_svg(),
        Err(PlotError::BadLimits { axis: "y", .. })
    ));
    let fig = Figure::new(0, 200, 1, 1);
    assert!(matches!(fig.to_png(1.0), Err(PlotError::BadSize { .. })));
}

#[test]
fn auto_limits_use_nice_ticks_around_the_data() {
    let fig = Figure::new(300, 200, 1, 1).panel(Panel::new("", "", "").line(Series::new(
        vec![0.0, 97.0],
        vec![-3.0, 12.0],
        Color::BLACK,
    )));
    let a = &fig.plot_areas()[0];
    assert_eq!(a.x.values, vec![0.0, 20.0, 40.0, 60.0, 80.0, 100.0]);
    assert_eq!((a.y.min, a.y.max), (-5.0, 15.0));
}

#[test]
fn legend_goes_to_the_emptiest_corner() {
    use stride_plot::svg::legend_corner;
    // Data fill the top half of the plot area: the legend moves to the bottom.
    let x: Vec<f64> = (0..=100).map(|i| i as f64 / 100.0).collect();
    let fig = Figure::new(400, 300, 1, 1).panel(
        Panel::new("", "", "")
            .x_limits(0.0, 1.0)
            .y_limits(0.0, 1.0)
            .band(Band::new(
                x.clone(),
                vec![0.6; 101],
                vec![1.0; 101],
                Color::GREY,
            ))
            .line(Series::new(x, vec![0.8; 101], Color::BLUE).label("line"))
            .legend(true),
    );
    let a = &fig.plot_areas()[0];
    let (_, y) = legend_corner(a, &fig.panels[0], 80.0, 20.0);
    assert!(y > a.top + 0.5 * a.height, "legend at y = {y}");
}

#[test]
fn figure_legend_sits_under_the_title_and_above_the_panels() {
    use stride_plot::LegendEntry;
    let s = Series::new(vec![0.0, 1.0], vec![0.0, 1.0], Color::BLUE);
    let fig = Figure::new(400, 300, 1, 1)
        .title("T")
        .legend_entry(LegendEntry::for_series(&s, "prediction"))
        .legend_entry(LegendEntry::fill(Color::GREY, "experiment"))
        .panel(Panel::new("p", "x", "y").line(s));
    let svg = fig.to_svg().unwrap();
    assert!(svg.contains(">prediction</text>") && svg.contains(">experiment</text>"));
    parse_svg(&svg).unwrap();
    let with = fig.plot_areas()[0].top;
    let mut plain = fig.clone();
    plain.legend.clear();
    assert!(with > plain.plot_areas()[0].top + 10.0);
}

#[test]
fn a_wide_figure_legend_wraps_into_rows_inside_the_figure() {
    use stride_plot::LegendEntry;
    let s = Series::new(vec![0.0, 1.0], vec![0.0, 1.0], Color::BLUE);
    let labels = [
        "unaffected (left)",
        "affected (right, prosthesis)",
        "amputees, affected side (Quesada et al. 2016, mean ± 2 SD)",
    ];
    let mut fig = Figure::new(500, 400, 1, 1).panel(Panel::new("p", "x", "y").line(s.clone()));
    for l in labels {
        fig = fig.legend_entry(LegendEntry::for_series(&s, l));
    }
    let svg = fig.to_svg().unwrap();
    parse_svg(&svg).unwrap();
    // Each label starts inside the figure and, at the font's advance width, ends inside it.
    let fs = fig.font_size + 1.0;
    let mut ys = Vec::new();
    for l in labels {
        let end = format!(">{l}</text>");
        let at = svg
            .find(&end)
            .unwrap_or_else(|| panic!("label {l} missing"));
        let tag = &svg[svg[..at].rfind("<text").unwrap()..at];
        let attr = |name: &str| -> f64 {
            let i = tag.find(&format!(" {name}=\"")).unwrap() + name.len() + 3;
            tag[i..i + tag[i..].find('"').unwrap()].parse().unwrap()
        };
        let (x, y) = (attr("x"), attr("y"));
        assert!(x >= 0.0, "{l} starts at {x}");
        let right = x + 0.62 * fs * l.chars().count() as f64;
        assert!(right <= 500.0, "{l} ends at {right} px of 500");
        ys.push(y);
    }
    // The long label needs its own row below the first two, which share one.
    assert_eq!(ys[0], ys[1]);
    assert!(ys[2] > ys[1] + fs, "rows at {ys:?}");
    // The panel moves down by the second row.
    let mut one_row = fig.clone();
    one_row.legend.truncate(2);
    assert!(fig.plot_areas()[0].top >= one_row.plot_areas()[0].top + 2.0 * fs - 1e-9);
}
