//! Signal processing of experimental data: zero-lag Butterworth filtering and not-a-knot cubic splines.
//!
//! The filter reproduces MATLAB `filtfilt(b, a, x)` with `[b, a] = butter(2, fc/(fs/2))`:
//! odd reflection padding of 6 samples at each end and steady-state initial conditions.
//! The spline reproduces MATLAB `spline(t, y)` (not-a-knot end conditions).

use thiserror::Error;

use crate::function::{check_knots, second_derivatives, CubicSegments, EndRule, FunctionError};

/// Invalid input to the filter or the spline.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum SignalError {
    /// Cut-off must lie strictly between 0 and the Nyquist frequency.
    #[error(
        "Butterworth cut-off {cutoff} Hz must lie in (0, {nyquist}) Hz (Nyquist of fs = {fs} Hz)"
    )]
    BadCutoff {
        /// Requested cut-off [Hz].
        cutoff: f64,
        /// Sampling rate [Hz].
        fs: f64,
        /// Nyquist frequency [Hz].
        nyquist: f64,
    },
    /// The signal is shorter than filtfilt needs (more than 6 samples).
    #[error("filtfilt needs more than {needed} samples, got {got}")]
    TooShort {
        /// Minimum exclusive length.
        needed: usize,
        /// Actual length.
        got: usize,
    },
    /// Non-finite sample in the signal.
    #[error("signal sample {0} is not finite")]
    NotFinite(usize),
    /// Invalid spline knots.
    #[error("spline: {0}")]
    Knots(#[from] FunctionError),
}

/// Digital IIR filter coefficients `b` (numerator) and `a` (denominator, `a[0] = 1`) of order 2.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Biquad {
    /// Numerator coefficients.
    pub b: [f64; 3],
    /// Denominator coefficients, `a[0] = 1`.
    pub a: [f64; 3],
}

impl Biquad {
    /// Second-order low-pass Butterworth with cut-off `cutoff` [Hz] at sampling rate `fs`
    /// [Hz]: bilinear transform with frequency pre-warping (MATLAB `butter(2, fc/(fs/2))`).
    pub fn butterworth_lowpass(cutoff: f64, fs: f64) -> Result<Self, SignalError> {
        let nyquist = fs / 2.0;
        let valid = cutoff > 0.0 && cutoff < nyquist && fs.is_finite();
        if !valid {
            return Err(SignalError::BadCutoff {
                cutoff,
                fs,
                nyquist,
            });
        }
        // Pre-warped analogue cut-off (normalised so that the bilinear constant is 1).
        let k = (std::f64::consts::PI * cutoff / fs).tan();
        let s2 = std::f64::consts::SQRT_2;
        let norm = 1.0 / (1.0 + s2 * k + k * k);
        let b0 = k * k * norm;
        Ok(Self {
            b: [b0, 2.0 * b0, b0],
            a: [
                1.0,
                2.0 * (k * k - 1.0) * norm,
                (1.0 - s2 * k + k * k) * norm,
            ],
        })
    }

    /// Steady-state internal state (transposed direct form II) for a unit step input,
    /// as MATLAB `filtfilt` computes it.
    pub fn steady_state(&self) -> [f64; 2] {
        let [b0, b1, b2] = self.b;
        let [_, a1, a2] = self.a;
        // [[1 + a1, -1], [a2, 1]] z = [b1 - b0 a1, b2 - b0 a2]
        let r0 = b1 - b0 * a1;
        let r1 = b2 - b0 * a2;
        let det = (1.0 + a1) + a2;
        let z0 = (r0 + r1) / det;
        let z1 = r1 - a2 * z0;
        [z0, z1]
    }

    /// Filter `x` in place (transposed direct form II) from initial state `z`.
    pub fn filter_in_place(&self, x: &mut [f64], mut z: [f64; 2]) {
        let [b0, b1, b2] = self.b;
        let [_, a1, a2] = self.a;
        for v in x.iter_mut() {
            let xin = *v;
            let y = b0 * xin + z[0];
            z[0] = b1 * xin - a1 * y + z[1];
            z[1] = b2 * xin - a2 * y;
            *v = y;
        }
    }

    /// Zero-phase forward–backward filtering with MATLAB `filtfilt` conventions.
    pub fn filtfilt(&self, x: &[f64]) -> Result<Vec<f64>, SignalError> {
        const NFACT: usize = 6;
        let n = x.len();
        if n <= NFACT {
            return Err(SignalError::TooShort {
                needed: NFACT,
                got: n,
            });
        }
        if let Some(i) = x.iter().position(|v| !v.is_finite()) {
            return Err(SignalError::NotFinite(i));
        }
        let mut ext = Vec::with_capacity(n + 2 * NFACT);
        for i in (1..=NFACT).rev() {
            ext.push(2.0 * x[0] - x[i]);
        }
        ext.extend_from_slice(x);
        for i in 1..=NFACT {
            ext.push(2.0 * x[n - 1] - x[n - 1 - i]);
        }
        let zi = self.steady_state();
        let z = [zi[0] * ext[0], zi[1] * ext[0]];
        self.filter_in_place(&mut ext, z);
        ext.reverse();
        let z = [zi[0] * ext[0], zi[1] * ext[0]];
        self.filter_in_place(&mut ext, z);
        ext.reverse();
        Ok(ext[NFACT..NFACT + n].to_vec())
    }
}

/// Zero-lag low-pass filter: 2nd-order Butterworth at `cutoff` [Hz] applied forward and
/// backward (MATLAB `filtfilt`), for a signal sampled at `fs` [Hz].
pub fn lowpass_filtfilt(x: &[f64], cutoff: f64, fs: f64) -> Result<Vec<f64>, SignalError> {
    Biquad::butterworth_lowpass(cutoff, fs)?.filtfilt(x)
}

/// Cubic spline through samples `(t, y)` with MATLAB `spline` end conditions (not-a-knot
/// for ≥ 4 samples, the parabola for 3, the line for 2); extrapolates with the end pieces.
#[derive(Clone, Debug, PartialEq)]
pub struct NotAKnotSpline {
    segments: CubicSegments,
}

impl NotAKnotSpline {
    /// Fit the spline; `t` strictly increasing, same length as `y`, at least 2 samples.
    pub fn new(t: &[f64], y: &[f64]) -> Result<Self, SignalError> {
        check_knots(t, y)?;
        let n = t.len();
        let m = match n {
            2 => vec![0.0; 2],
            3 => {
                let dd =
                    ((y[2] - y[1]) / (t[2] - t[1]) - (y[1] - y[0]) / (t[1] - t[0])) / (t[2] - t[0]);
                vec![2.0 * dd; 3]
            }
            _ => second_derivatives(t, y, EndRule::NotAKnot),
        };
        Ok(Self {
            segments: CubicSegments::from_second_derivatives(t, y, &m),
        })
    }

    /// `[s(t), s'(t), s''(t)]` at any `t` (polynomial extrapolation of the end pieces).
    pub fn eval(&self, t: f64) -> [f64; 3] {
        let s = &self.segments;
        let n = s.x.len();
        let i = if t <= s.x[0] {
            0
        } else {
            s.x.partition_point(|&xi| xi <= t)
                .saturating_sub(1)
                .min(n - 2)
        };
        let h = t - s.x[i];
        let (b, c, d) = (s.b[i], s.c[i], s.d[i]);
        [
            s.y[i] + h * (b + h * (c + h * d)),
            b + h * (2.0 * c + 3.0 * d * h),
            2.0 * c + 6.0 * d * h,
        ]
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    fn rms(x: &[f64]) -> f64 {
        (x.iter().map(|v| v * v).sum::<f64>() / x.len() as f64).sqrt()
    }

    #[test]
    fn butterworth_coefficients_match_matlab() {
        // MATLAB: [b, a] = butter(2, 0.2) → b = [0.0675 0.1349 0.0675], a = [1 −1.1430 0.4128].
        let f = Biquad::butterworth_lowpass(10.0, 100.0).unwrap();
        assert!((f.b[0] - 0.067_455_273_889_071_9).abs() < 1e-12);
        assert!((f.a[1] + 1.142_980_502_539_901).abs() < 1e-12);
        assert!((f.a[2] - 0.412_801_598_096_189).abs() < 1e-12);
    }

    #[test]
    fn constant_stays_constant() {
        let x = vec![3.7; 40];
        let y = lowpass_filtfilt(&x, 6.0, 100.0).unwrap();
        for v in y {
            assert!((v - 3.7).abs() < 1e-12);
        }
    }

    #[test]
    fn gain_below_and_above_cutoff() {
        let fs = 100.0;
        let n = 1000;
        let t: Vec<f64> = (0..n).map(|i| i as f64 / fs).collect();
        // Forward–backward gain is |H|² = 1 / (1 + (f/fc)^4) with pre-warping.
        let gain = |f: f64, fc: f64| {
            let r = (PI * f / fs).tan() / (PI * fc / fs).tan();
            1.0 / (1.0 + r.powi(4))
        };
        for &f in &[1.0, 6.0, 20.0] {
            let x: Vec<f64> = t.iter().map(|t| (2.0 * PI * f * t).sin()).collect();
            let y = lowpass_filtfilt(&x, 6.0, fs).unwrap();
            let inner = 200..800;
            let g = rms(&y[inner.clone()]) / rms(&x[inner]);
            assert!(
                (g - gain(f, 6.0)).abs() < 2e-3,
                "f = {f}: {g} vs {}",
                gain(f, 6.0)
            );
        }
    }

    #[test]
    fn short_signal_and_bad_cutoff_are_errors() {
        assert!(matches!(
            lowpass_filtfilt(&[1.0; 6], 6.0, 100.0),
            Err(SignalError::TooShort { .. })
        ));
        assert!(matches!(
            lowpass_filtfilt(&[1.0; 20], 60.0, 100.0),
            Err(SignalError::BadCutoff { .. })
        ));
    }

    #[test]
    fn spline_reproduces_cubics() {
        let f = |t: f64| {
            [
                -0.7 * t * t * t + 1.3 * t * t - 0.2 * t + 4.0,
                -2.1 * t * t + 2.6 * t - 0.2,
                -4.2 * t + 2.6,
            ]
        };
        let t = [0.0, 0.13, 0.3, 0.42, 0.61, 0.8, 1.0];
        let y: Vec<f64> = t.iter().map(|&t| f(t)[0]).collect();
        let s = NotAKnotSpline::new(&t, &y).unwrap();
        for &x in &[0.0, 0.05, 0.35, 0.77, 1.0, 1.1] {
            let v = s.eval(x);
            let e = f(x);
            for k in 0..3 {
                assert!(
                    (v[k] - e[k]).abs() < 1e-10,
                    "t={x} k={k}: {} vs {}",
                    v[k],
                    e[k]
                );
            }
        }
        // Four points: not-a-knot is the single interpolating cubic.
        let y4: Vec<f64> = t[..4].iter().map(|&t| f(t)[0]).collect();
        let s4 = NotAKnotSpline::new(&t[..4], &y4).unwrap();
        let v = s4.eval(0.2);
        assert!((v[2] - f(0.2)[2]).abs() < 1e-9);
    }

    #[test]
    fn spline_bad_input() {
        assert!(NotAKnotSpline::new(&[0.0, 0.0, 1.0], &[1.0, 2.0, 3.0]).is_err());
        assert!(NotAKnotSpline::new(&[0.0], &[1.0]).is_err());
    }
}
