//! "Nice" axis ticks: steps of 1, 2, 2.5 or 5 times a power of ten that cover the data.

/// Ticks of one axis and the axis limits they define.
#[derive(Clone, Debug, PartialEq)]
pub struct Ticks {
    /// Lower axis limit (data units).
    pub min: f64,
    /// Upper axis limit (data units).
    pub max: f64,
    /// Tick positions (data units), increasing, within [min, max].
    pub values: Vec<f64>,
    /// Spacing between ticks (data units).
    pub step: f64,
}

/// Nice ticks covering [lo, hi] with about `target` intervals: the step is the smallest of
/// {1, 2, 2.5, 5, 10}·10ᵏ not below (hi − lo)/target, and the limits are the multiples of the
/// step just outside the data. Degenerate or non-finite ranges are widened to a unit range.
pub fn nice_ticks(lo: f64, hi: f64, target: usize) -> Ticks {
    let (mut lo, mut hi) = match (lo.is_finite(), hi.is_finite()) {
        (true, true) if lo <= hi => (lo, hi),
        (true, true) => (hi, lo),
        (true, false) => (lo, lo),
        (false, true) => (hi, hi),
        (false, false) => (0.0, 1.0),
    };
    if hi - lo <= 1e-12 * hi.abs().max(lo.abs()).max(1e-300) {
        let pad = if lo == 0.0 { 1.0 } else { 0.1 * lo.abs() };
        lo -= pad;
        hi += pad;
    }
    let raw = (hi - lo) / target.max(1) as f64;
    let mag = 10f64.powf(raw.log10().floor());
    let step = [1.0, 2.0, 2.5, 5.0, 10.0]
        .iter()
        .map(|m| m * mag)
        .find(|s| *s >= raw * (1.0 - 1e-9))
        .unwrap_or(10.0 * mag);
    // Tolerance so that data exactly on a multiple is not pushed one step out.
    let eps = 1e-9 * step;
    let k0 = ((lo + eps) / step).floor();
    let k1 = ((hi - eps) / step).ceil();
    let n = (k1 - k0).round() as i64;
    let values: Vec<f64> = (0..=n)
        .map(|i| {
            let v = (k0 + i as f64) * step;
            // Snap values that are zero up to rounding.
            if v.abs() < eps {
                0.0
            } else {
                v
            }
        })
        .collect();
    Ticks {
        min: k0 * step,
        max: k1 * step,
        values,
        step,
    }
}

/// Ticks inside fixed limits [lo, hi] (limits kept as given).
pub fn ticks_within(lo: f64, hi: f64, target: usize) -> Ticks {
    let t = nice_ticks(lo, hi, target);
    let eps = 1e-9 * t.step;
    Ticks {
        min: lo,
        max: hi,
        values: t
            .values
            .into_iter()
            .filter(|v| *v >= lo - eps && *v <= hi + eps)
            .collect(),
        step: t.step,
    }
}

/// Tick label of `v` with as many decimals as the tick `step` needs (no "-0").
pub fn format_tick(v: f64, step: f64) -> String {
    let mut decimals = 0usize;
    if step.is_finite() && step > 0.0 {
        let mut s = step;
        while decimals < 10 && (s - s.round()).abs() > 1e-6 * s.max(1e-300) {
            s *= 10.0;
            decimals += 1;
        }
    }
    let text = format!("{v:.decimals$}");
    if text
        .trim_start_matches('-')
        .chars()
        .all(|c| c == '0' || c == '.')
    {
        text.trim_start_matches('-').to_string()
    } else {
        text
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn close(a: &[f64], b: &[f64]) -> bool {
        a.len() == b.len() && a.iter().zip(b).all(|(x, y)| (x - y).abs() < 1e-9)
    }

    #[test]
    fn zero_to_97_gives_steps_of_20_up_to_100() {
        let t = nice_ticks(0.0, 97.0, 5);
        assert!(
            close(&t.values, &[0.0, 20.0, 40.0, 60.0, 80.0, 100.0]),
            "{t:?}"
        );
        assert_eq!((t.min, t.max, t.step), (0.0, 100.0, 20.0));
    }

    #[test]
    fn negative_fractional_range() {
        // Range 1.05 / 5 = 0.21 → step 0.25; limits −0.75 and 0.5.
        let t = nice_ticks(-0.73, 0.32, 5);
        assert!(
            close(&t.values, &[-0.75, -0.5, -0.25, 0.0, 0.25, 0.5]),
            "{t:?}"
        );
        assert_eq!(format_tick(-0.75, t.step), "-0.75");
        assert_eq!(format_tick(0.0, t.step), "0.00");
    }

    #[test]
    fn data_on_multiples_are_not_padded() {
        let t = nice_ticks(0.0, 100.0, 5);
        assert!(close(&t.values, &[0.0, 20.0, 40.0, 60.0, 80.0, 100.0]));
        let t = nice_ticks(-60.0, 10.0, 5);
        assert!(close(&t.values, &[-60.0, -40.0, -20.0, 0.0, 20.0]), "{t:?}");
    }

    #[test]
    fn degenerate_and_non_finite_ranges() {
        let t = nice_ticks(3.0, 3.0, 5);
        assert!(t.min < 3.0 && t.max > 3.0);
        let t = nice_ticks(0.0, 0.0, 5);
        assert_eq!((t.min, t.max), (-1.0, 1.0));
        let t = nice_ticks(f64::NAN, f64::INFINITY, 5);
        assert_eq!((t.min, t.max), (0.0, 1.0));
    }

    #[test]
    fn fixed_limits_keep_ticks_inside() {
        let t = ticks_within(0.0, 97.0, 5);
        assert!(close(&t.values, &[0.0, 20.0, 40.0, 60.0, 80.0]));
        assert_eq!((t.min, t.max), (0.0, 97.0));
    }

    #[test]
    fn tick_labels() {
        assert_eq!(format_tick(20.0, 20.0), "20");
        assert_eq!(format_tick(2.5, 2.5), "2.5");
        assert_eq!(format_tick(0.02, 0.01), "0.02");
        assert_eq!(format_tick(-1e-17, 0.1), "0.0");
    }
}
