//! Sampled time series of a trial: linear interpolation at any time.

/// Linear interpolation of `rows` (one per time of `time`, at least two, increasing) at
/// `t` [s] (clamped at the ends).
pub fn interp<const N: usize>(time: &[f64], t: f64, row: impl Fn(usize) -> [f64; N]) -> [f64; N] {
    let n = time.len();
    let s = time.partition_point(|&x| x <= t).clamp(1, n - 1) - 1;
    let w = ((t - time[s]) / (time[s + 1] - time[s])).clamp(0.0, 1.0);
    let (a, b) = (row(s), row(s + 1));
    std::array::from_fn(|i| a[i] + w * (b[i] - a[i]))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn interpolation_is_linear_between_samples_and_clamped_outside() {
        let time = [0.0, 1.0, 3.0];
        let rows = [[0.0, 10.0], [2.0, 10.0], [6.0, 4.0]];
        let at = |t: f64| interp::<2>(&time, t, |s| rows[s]);
        assert_eq!(at(0.5), [1.0, 10.0]);
        assert_eq!(at(2.0), [4.0, 7.0]);
        assert_eq!(at(1.0), [2.0, 10.0]);
        assert_eq!(at(-1.0), [0.0, 10.0]);
        assert_eq!(at(5.0), [6.0, 4.0]);
    }
}
