//! Evaluation of OpenSim coordinate functions generic over the scalar.
//!
//! A [`Function`] is compiled once per model into a [`CompiledFunction`], which caches the
//! spline coefficients and the `Arc<dyn UnaryFn>` handles needed to evaluate piecewise
//! functions inside recorded tapes (the segment is re-chosen at every evaluation).

use std::sync::Arc;

use stride_ad::{Scalar, UnaryFn};
use thiserror::Error;

use crate::model::Function;

/// Invalid function data found while compiling a [`Function`].
#[derive(Debug, Error, Clone, PartialEq)]
pub enum FunctionError {
    /// A spline has abscissae and ordinates of different lengths.
    #[error("SimmSpline: {nx} abscissae but {ny} ordinates")]
    LengthMismatch {
        /// Number of abscissae.
        nx: usize,
        /// Number of ordinates.
        ny: usize,
    },
    /// A spline has fewer than two knots.
    #[error("SimmSpline: needs at least 2 knots, got {0}")]
    TooFewKnots(usize),
    /// Spline abscissae are not strictly increasing or not finite.
    #[error("SimmSpline: abscissae must be finite and strictly increasing (knot {index}: {prev} then {next})")]
    NotIncreasing {
        /// Index of the offending knot.
        index: usize,
        /// Previous abscissa.
        prev: f64,
        /// Offending abscissa.
        next: f64,
    },
    /// A coefficient, knot ordinate or scale is NaN or infinite.
    #[error("function contains a non-finite number ({0})")]
    NotFinite(&'static str),
    /// A polynomial has no coefficients.
    #[error("PolynomialFunction without coefficients")]
    EmptyPolynomial,
}

/// Piecewise-cubic spline data: on `[x_i, x_{i+1}]`,
/// `s(x) = y_i + b_i h + c_i h² + d_i h³` with `h = x − x_i`; linear extrapolation outside.
#[derive(Clone, Debug, PartialEq)]
pub struct CubicSegments {
    /// Knot abscissae (strictly increasing).
    pub x: Vec<f64>,
    /// Knot ordinates.
    pub y: Vec<f64>,
    /// First-derivative coefficient of each knot.
    pub b: Vec<f64>,
    /// Half second-derivative coefficient of each knot.
    pub c: Vec<f64>,
    /// One-sixth third-derivative coefficient of each knot.
    pub d: Vec<f64>,
}

impl CubicSegments {
    /// Segments from knots and second derivatives `m` at the knots (C² cubic spline).
    pub fn from_second_derivatives(x: &[f64], y: &[f64], m: &[f64]) -> Self {
        let n = x.len();
        let mut b = vec![0.0; n];
        let mut c = vec![0.0; n];
        let mut d = vec![0.0; n];
        for i in 0..n.saturating_sub(1) {
            let h = x[i + 1] - x[i];
            b[i] = (y[i + 1] - y[i]) / h - h * (2.0 * m[i] + m[i + 1]) / 6.0;
            c[i] = 0.5 * m[i];
            d[i] = (m[i + 1] - m[i]) / (6.0 * h);
        }
        if n >= 2 {
            let h = x[n - 1] - x[n - 2];
            b[n - 1] = b[n - 2] + 2.0 * c[n - 2] * h + 3.0 * d[n - 2] * h * h;
            c[n - 1] = 0.5 * m[n - 1];
        }
        Self {
            x: x.to_vec(),
            y: y.to_vec(),
            b,
            c,
            d,
        }
    }

    /// Value, first, second and third derivative at `t`; linear extrapolation (with
    /// the end slope) outside the knot range, as OpenSim's `SimmSpline` does.
    pub fn eval4(&self, t: f64) -> [f64; 4] {
        let n = self.x.len();
        if t < self.x[0] {
            let h = t - self.x[0];
            return [self.y[0] + self.b[0] * h, self.b[0], 0.0, 0.0];
        }
        if t > self.x[n - 1] {
            let h = t - self.x[n - 1];
            return [self.y[n - 1] + self.b[n - 1] * h, self.b[n - 1], 0.0, 0.0];
        }
        let i = self.segment(t);
        let h = t - self.x[i];
        let (b, c, d) = (self.b[i], self.c[i], self.d[i]);
        [
            self.y[i] + h * (b + h * (c + h * d)),
            b + h * (2.0 * c + 3.0 * d * h),
            2.0 * c + 6.0 * d * h,
            6.0 * d,
        ]
    }

    /// Index of the segment `[x_i, x_{i+1}]` containing `t` (clamped to valid segments).
    fn segment(&self, t: f64) -> usize {
        let n = self.x.len();
        if n < 2 {
            return 0;
        }
        // partition_point: first index with x > t.
        let k = self.x.partition_point(|&xi| xi <= t);
        k.saturating_sub(1).min(n - 2)
    }
}

/// The `order`-th derivative (0, 1 or 2) of a spline as a tape-safe one-dimensional function.
#[derive(Debug)]
struct SplineDerivative {
    segments: Arc<CubicSegments>,
    order: usize,
}

impl UnaryFn for SplineDerivative {
    fn eval(&self, x: f64) -> [f64; 3] {
        let v = self.segments.eval4(x);
        match self.order {
            0 => [v[0], v[1], v[2]],
            1 => [v[1], v[2], v[3]],
            // Fourth derivative of a cubic is zero.
            _ => [v[2], v[3], 0.0],
        }
    }
}

/// A coordinate function prepared for fast, tape-safe evaluation (built once per model).
#[derive(Clone, Debug)]
pub enum CompiledFunction {
    /// `f(x) = c`.
    Constant(f64),
    /// `f(x) = slope x + intercept`.
    Linear {
        /// Slope.
        slope: f64,
        /// Value at x = 0.
        intercept: f64,
    },
    /// Polynomial, coefficients highest power first.
    Polynomial(Vec<f64>),
    /// Cubic spline: value, first and second derivative as registered functions.
    Spline {
        /// Coefficients (for f64 evaluation).
        segments: Arc<CubicSegments>,
        /// `[f, f', f'']` as tape-safe functions (each with its own two derivatives).
        fns: [Arc<dyn UnaryFn>; 3],
    },
}

impl CompiledFunction {
    /// `[f(x), f'(x), f''(x)]` for a scalar argument (rad or m in, rad or m out).
    pub fn eval<T: Scalar>(&self, x: T) -> [T; 3] {
        match self {
            Self::Constant(c) => [T::cst(*c), T::zero(), T::zero()],
            Self::Linear { slope, intercept } => {
                [x * *slope + *intercept, T::cst(*slope), T::zero()]
            }
            Self::Polynomial(coefs) => {
                // Horner for the value and both derivatives at once.
                let mut p = T::zero();
                let mut dp = T::zero();
                let mut ddp = T::zero();
                for &a in coefs {
                    ddp = ddp * x + dp * 2.0;
                    dp = dp * x + p;
                    p = p * x + a;
                }
                [p, dp, ddp]
            }
            Self::Spline { fns, .. } => [x.apply(&fns[0]), x.apply(&fns[1]), x.apply(&fns[2])],
        }
    }

    /// `[f(x), f'(x), f''(x)]` in plain floating point.
    pub fn eval_f64(&self, x: f64) -> [f64; 3] {
        match self {
            Self::Spline { segments, .. } => {
                let v = segments.eval4(x);
                [v[0], v[1], v[2]]
            }
            _ => self.eval::<f64>(x),
        }
    }

    /// True when the function does not depend on its argument.
    pub fn is_constant(&self) -> bool {
        match self {
            Self::Constant(_) => true,
            Self::Linear { slope, .. } => *slope == 0.0,
            Self::Polynomial(c) => c.len() <= 1,
            Self::Spline { segments, .. } => segments.y.len() == 1,
        }
    }

    fn scaled(self, s: f64) -> Self {
        match self {
            Self::Constant(c) => Self::Constant(c * s),
            Self::Linear { slope, intercept } => Self::Linear {
                slope: slope * s,
                intercept: intercept * s,
            },
            Self::Polynomial(c) => Self::Polynomial(c.into_iter().map(|a| a * s).collect()),
            Self::Spline { segments, .. } => {
                let seg = CubicSegments {
                    x: segments.x.clone(),
                    y: segments.y.iter().map(|v| v * s).collect(),
                    b: segments.b.iter().map(|v| v * s).collect(),
                    c: segments.c.iter().map(|v| v * s).collect(),
                    d: segments.d.iter().map(|v| v * s).collect(),
                };
                Self::spline(seg)
            }
        }
    }

    fn spline(seg: CubicSegments) -> Self {
        let segments = Arc::new(seg);
        let mk = |order| -> Arc<dyn UnaryFn> {
            Arc::new(SplineDerivative {
                segments: segments.clone(),
                order,
            })
        };
        let fns = [mk(0), mk(1), mk(2)];
        Self::Spline { segments, fns }
    }
}

impl Function {
    /// Prepare the function for evaluation (solves spline coefficients, builds the
    /// tape-safe handles); call once per model, not per evaluation.
    pub fn compile(&self) -> Result<CompiledFunction, FunctionError> {
        match self {
            Function::Constant(c) => {
                finite(&[*c], "constant")?;
                Ok(CompiledFunction::Constant(*c))
            }
            Function::Linear { slope, intercept } => {
                finite(&[*slope, *intercept], "linear function")?;
                Ok(CompiledFunction::Linear {
                    slope: *slope,
                    intercept: *intercept,
                })
            }
            Function::Polynomial { coefficients } => {
                if coefficients.is_empty() {
                    return Err(FunctionError::EmptyPolynomial);
                }
                finite(coefficients, "polynomial coefficient")?;
                Ok(CompiledFunction::Polynomial(coefficients.clone()))
            }
            Function::SimmSpline { x, y } => Ok(CompiledFunction::spline(simm_spline(x, y)?)),
            Function::PiecewiseLinear { x, y } => {
                Ok(CompiledFunction::spline(piecewise_linear(x, y)?))
            }
            Function::Multiplier { scale, function } => {
                finite(&[*scale], "multiplier scale")?;
                Ok(function.compile()?.scaled(*scale))
            }
        }
    }

    /// `[f(x), f'(x), f''(x)]` in plain floating point (compiles on every call; for
    /// one-off use only).
    pub fn eval_f64(&self, x: f64) -> Result<[f64; 3], FunctionError> {
        Ok(self.compile()?.eval_f64(x))
    }
}

fn finite(v: &[f64], what: &'static str) -> Result<(), FunctionError> {
    if v.iter().all(|a| a.is_finite()) {
        Ok(())
    } else {
        Err(FunctionError::NotFinite(what))
    }
}

/// Check spline knots: equal lengths, at least two, finite, strictly increasing abscissae.
pub fn check_knots(x: &[f64], y: &[f64]) -> Result<(), FunctionError> {
    if x.len() != y.len() {
        return Err(FunctionError::LengthMismatch {
            nx: x.len(),
            ny: y.len(),
        });
    }
    if x.len() < 2 {
        return Err(FunctionError::TooFewKnots(x.len()));
    }
    finite(y, "spline ordinate")?;
    for i in 1..x.len() {
        let increasing = x[i].is_finite() && x[i - 1].is_finite() && x[i] > x[i - 1];
        if !increasing {
            return Err(FunctionError::NotIncreasing {
                index: i,
                prev: x[i - 1],
                next: x[i],
            });
        }
    }
    Ok(())
}

/// OpenSim `SimmSpline` coefficients (Forsythe–Malcolm–Moler end conditions): with four
/// or more knots, the third derivative in the first (last) interval equals that of the
/// cubic through the first (last) four knots; three knots give one parabola; two knots a line.
pub fn simm_spline(x: &[f64], y: &[f64]) -> Result<CubicSegments, FunctionError> {
    check_knots(x, y)?;
    let n = x.len();
    let m = if n == 2 {
        vec![0.0; 2]
    } else if n == 3 {
        // One parabola: constant second derivative 2·f[x0,x1,x2].
        let dd = ((y[2] - y[1]) / (x[2] - x[1]) - (y[1] - y[0]) / (x[1] - x[0])) / (x[2] - x[0]);
        vec![2.0 * dd; 3]
    } else {
        // Third divided differences of the first and last four knots.
        let d3 = |k: usize| -> f64 {
            let f1 = |i: usize| (y[i + 1] - y[i]) / (x[i + 1] - x[i]);
            let f2 = |i: usize| (f1(i + 1) - f1(i)) / (x[i + 2] - x[i]);
            (f2(k + 1) - f2(k)) / (x[k + 3] - x[k])
        };
        // M1 − M0 = 6 h0 D_first, M_{n-1} − M_{n-2} = 6 h_{n-2} D_last.
        let left = 6.0 * d3(0);
        let right = 6.0 * d3(n - 4);
        second_derivatives(x, y, EndRule::ThirdDerivative(left, right))
    };
    Ok(CubicSegments::from_second_derivatives(x, y, &m))
}

/// OpenSim `PiecewiseLinearFunction` as cubic segments without curvature: the slope of
/// each interval, the first and last slopes continuing outside the knots.
pub fn piecewise_linear(x: &[f64], y: &[f64]) -> Result<CubicSegments, FunctionError> {
    check_knots(x, y)?;
    Ok(CubicSegments::from_second_derivatives(
        x,
        y,
        &vec![0.0; x.len()],
    ))
}

/// End conditions of [`second_derivatives`].
#[derive(Clone, Copy, Debug)]
pub enum EndRule {
    /// Prescribed third derivative in the first and last interval.
    ThirdDerivative(f64, f64),
    /// Not-a-knot: third derivative continuous at the second and second-to-last knots.
    NotAKnot,
}

/// Second derivatives at the knots of a C² cubic spline with the given end rule; the two
/// end unknowns are eliminated so the remaining system is tridiagonal. Needs n ≥ 4 knots
/// with strictly increasing abscissae (callers check; fewer knots return zeros).
pub fn second_derivatives(x: &[f64], y: &[f64], rule: EndRule) -> Vec<f64> {
    let n = x.len();
    if n < 4 || y.len() != n {
        return vec![0.0; n];
    }
    let h: Vec<f64> = (0..n - 1).map(|i| x[i + 1] - x[i]).collect();
    let delta: Vec<f64> = (0..n - 1).map(|i| (y[i + 1] - y[i]) / h[i]).collect();
    // Unknowns M1..M_{n-2}; row i: h_{i-1} M_{i-1} + 2(h_{i-1}+h_i) M_i + h_i M_{i+1} = r_i.
    let k = n - 2;
    let mut lo = vec![0.0; k];
    let mut di = vec![0.0; k];
    let mut up = vec![0.0; k];
    let mut r = vec![0.0; k];
    for j in 0..k {
        let i = j + 1;
        lo[j] = h[i - 1];
        di[j] = 2.0 * (h[i - 1] + h[i]);
        up[j] = h[i];
        r[j] = 6.0 * (delta[i] - delta[i - 1]);
    }
    // Express M0 = α M1 + β M2 + γ and M_{n-1} = α' M_{n-2} + β' M_{n-3} + γ'.
    let (a0, b0, g0, a1, b1, g1) = match rule {
        EndRule::ThirdDerivative(l, rr) => (1.0, 0.0, -h[0] * l, 1.0, 0.0, h[n - 2] * rr),
        EndRule::NotAKnot => {
            let (p, q) = (h[0], h[1]);
            let (pe, qe) = (h[n - 2], h[n - 3]);
            (1.0 + p / q, -p / q, 0.0, 1.0 + pe / qe, -pe / qe, 0.0)
        }
    };
    // Substitute into the first and last rows.
    let first_h = lo[0];
    di[0] += first_h * a0;
    up[0] += first_h * b0;
    r[0] -= first_h * g0;
    let last_h = up[k - 1];
    di[k - 1] += last_h * a1;
    lo[k - 1] += last_h * b1;
    r[k - 1] -= last_h * g1;
    let inner = solve_tridiagonal(&lo, &di, &up, &r);
    let mut m = vec![0.0; n];
    m[1..n - 1].copy_from_slice(&inner);
    m[0] = a0 * inner[0] + b0 * inner[1] + g0;
    m[n - 1] = a1 * inner[k - 1] + b1 * inner[k - 2] + g1;
    m
}

/// Solve a tridiagonal system (Thomas algorithm; `lo[0]` and `up[n-1]` are ignored).
pub fn solve_tridiagonal(lo: &[f64], di: &[f64], up: &[f64], r: &[f64]) -> Vec<f64> {
    let n = di.len();
    let mut c = vec![0.0; n];
    let mut d = vec![0.0; n];
    c[0] = up[0] / di[0];
    d[0] = r[0] / di[0];
    for i in 1..n {
        let den = di[i] - lo[i] * c[i - 1];
        c[i] = if i + 1 < n { up[i] / den } else { 0.0 };
        d[i] = (r[i] - lo[i] * d[i - 1]) / den;
    }
    let mut xs = vec![0.0; n];
    xs[n - 1] = d[n - 1];
    for i in (0..n - 1).rev() {
        xs[i] = d[i] - c[i] * xs[i + 1];
    }
    xs
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn simm_spline_reproduces_cubics() {
        // FMM end conditions are exact for cubics (third derivatives match).
        let f = |x: f64| 0.3 * x * x * x - x * x + 2.0 * x - 0.5;
        let xs = [0.0, 0.4, 1.1, 1.5, 2.3, 3.0];
        let ys: Vec<f64> = xs.iter().map(|&x| f(x)).collect();
        let s = simm_spline(&xs, &ys).unwrap();
        for &t in &[0.1, 0.7, 1.3, 2.0, 2.9] {
            let v = s.eval4(t);
            assert!((v[0] - f(t)).abs() < 1e-12);
            assert!((v[1] - (0.9 * t * t - 2.0 * t + 2.0)).abs() < 1e-11);
            assert!((v[2] - (1.8 * t - 2.0)).abs() < 1e-10);
        }
    }

    #[test]
    fn simm_spline_three_knots_is_parabola() {
        let f = |x: f64| 2.0 * x * x - x + 1.0;
        let xs = [0.0, 1.0, 3.0];
        let ys: Vec<f64> = xs.iter().map(|&x| f(x)).collect();
        let s = simm_spline(&xs, &ys).unwrap();
        let v = s.eval4(2.2);
        assert!((v[0] - f(2.2)).abs() < 1e-12);
        assert!((v[1] - (4.0 * 2.2 - 1.0)).abs() < 1e-12);
        assert!((v[2] - 4.0).abs() < 1e-12);
    }

    #[test]
    fn spline_derivative_handles_match_finite_differences() {
        let func = Function::SimmSpline {
            x: vec![-1.0, -0.3, 0.2, 0.9, 1.4],
            y: vec![0.1, 0.5, -0.2, 0.3, 0.0],
        };
        let c = func.compile().unwrap();
        let CompiledFunction::Spline { fns, .. } = &c else {
            panic!("expected spline")
        };
        let e = 1e-6;
        for &t in &[-0.8, 0.0, 0.5, 1.2] {
            for f in fns.iter() {
                let v = f.eval(t);
                let fd = (f.eval(t + e)[0] - f.eval(t - e)[0]) / (2.0 * e);
                assert!((v[1] - fd).abs() < 1e-6, "{t}: {} vs {fd}", v[1]);
                let fd2 = (f.eval(t + e)[1] - f.eval(t - e)[1]) / (2.0 * e);
                assert!((v[2] - fd2).abs() < 1e-6);
            }
            let [a, b, cc] = c.eval::<f64>(t);
            assert!((a - fns[0].eval(t)[0]).abs() < 1e-15);
            assert!((b - fns[1].eval(t)[0]).abs() < 1e-15);
            assert!((cc - fns[2].eval(t)[0]).abs() < 1e-15);
        }
    }

    #[test]
    fn polynomial_multiplier_and_linear() {
        let p = Function::Multiplier {
            scale: 2.0,
            function: Box::new(Function::Polynomial {
                coefficients: vec![1.0, -2.0, 3.0, 0.5],
            }),
        };
        let [v, d, dd] = p.eval_f64(1.5).unwrap();
        let x: f64 = 1.5;
        assert!((v - 2.0 * (x.powi(3) - 2.0 * x * x + 3.0 * x + 0.5)).abs() < 1e-12);
        assert!((d - 2.0 * (3.0 * x * x - 4.0 * x + 3.0)).abs() < 1e-12);
        assert!((dd - 2.0 * (6.0 * x - 4.0)).abs() < 1e-12);
        let l = Function::Linear {
            slope: -1.5,
            intercept: 0.25,
        };
        assert_eq!(l.eval_f64(2.0).unwrap(), [-2.75, -1.5, 0.0]);
    }

    #[test]
    fn piecewise_linear_interpolates_and_extrapolates_with_end_slopes() {
        let f = Function::PiecewiseLinear {
            x: vec![0.0, 1.0, 3.0],
            y: vec![0.0, 2.0, 1.0],
        };
        assert_eq!(f.eval_f64(0.5).unwrap(), [1.0, 2.0, 0.0]);
        assert_eq!(f.eval_f64(2.0).unwrap(), [1.5, -0.5, 0.0]);
        assert_eq!(f.eval_f64(-1.0).unwrap(), [-2.0, 2.0, 0.0]);
        assert_eq!(f.eval_f64(5.0).unwrap(), [0.0, -0.5, 0.0]);
    }

    #[test]
    fn bad_knots_are_reported() {
        let f = Function::SimmSpline {
            x: vec![0.0, 1.0, 1.0],
            y: vec![0.0, 1.0, 2.0],
        };
        assert!(matches!(
            f.compile(),
            Err(FunctionError::NotIncreasing { index: 2, .. })
        ));
        let f = Function::SimmSpline {
            x: vec![0.0, 1.0],
            y: vec![0.0],
        };
        assert!(matches!(
            f.compile(),
            Err(FunctionError::LengthMismatch { .. })
        ));
    }
}
