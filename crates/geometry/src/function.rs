//! Evaluation of OpenSim coordinate functions (path-point and joint functions) generic
//! over the scalar.
//!
//! Local stand-in for `stride_model::function`, which did not exist when this crate was
//! written. The spline interval is chosen from the argument's primal value, so a recorded
//! tape is valid only within the interval it was recorded in (the path geometry is a
//! fitting tool, not meant for tapes).

use stride_ad::Scalar;
use stride_model::Function;

/// Cubic coefficients of an OpenSim `SimmSpline` on each knot interval:
/// `y = y_i + b_i dx + c_i dx² + d_i dx³`, `dx = x − x_i`.
#[derive(Clone, Debug, PartialEq)]
pub struct SplineCoefficients {
    /// Knot abscissae.
    pub x: Vec<f64>,
    /// Knot ordinates.
    pub y: Vec<f64>,
    /// First-order coefficients.
    pub b: Vec<f64>,
    /// Second-order coefficients.
    pub c: Vec<f64>,
    /// Third-order coefficients.
    pub d: Vec<f64>,
}

impl SplineCoefficients {
    /// Interpolating cubic spline through `(x, y)` with the end conditions of OpenSim's
    /// `SimmSpline` (Forsythe–Malcolm–Moler: the third derivative at each end equals that
    /// of the cubic through the four nearest knots); fewer than 4 knots give linear
    /// interpolation.
    pub fn new(x: &[f64], y: &[f64]) -> Self {
        let n = x.len().min(y.len());
        let (x, y) = (x[..n].to_vec(), y[..n].to_vec());
        let mut b = vec![0.0; n];
        let mut c = vec![0.0; n];
        let mut d = vec![0.0; n];
        if n < 2 {
            return Self { x, y, b, c, d };
        }
        if n < 4 {
            for i in 0..n - 1 {
                b[i] = (y[i + 1] - y[i]) / (x[i + 1] - x[i]);
            }
            b[n - 1] = b[n - 2];
            return Self { x, y, b, c, d };
        }
        let nm1 = n - 1;
        // Tridiagonal system: b diagonal, d off-diagonal, c right-hand side.
        d[0] = x[1] - x[0];
        c[1] = (y[1] - y[0]) / d[0];
        for i in 1..nm1 {
            d[i] = x[i + 1] - x[i];
            b[i] = 2.0 * (d[i - 1] + d[i]);
            c[i + 1] = (y[i + 1] - y[i]) / d[i];
            c[i] = c[i + 1] - c[i];
        }
        // End conditions from third divided differences.
        b[0] = -d[0];
        b[nm1] = -d[n - 2];
        let c0 = c[2] / (x[3] - x[1]) - c[1] / (x[2] - x[0]);
        let cn = c[n - 2] / (x[nm1] - x[n - 3]) - c[n - 3] / (x[n - 2] - x[n - 4]);
        c[0] = c0 * d[0] * d[0] / (x[3] - x[0]);
        c[nm1] = -cn * d[n - 2] * d[n - 2] / (x[nm1] - x[n - 4]);
        // Forward elimination.
        for i in 1..n {
            let t = d[i - 1] / b[i - 1];
            b[i] -= t * d[i - 1];
            c[i] -= t * c[i - 1];
        }
        // Back substitution.
        c[nm1] /= b[nm1];
        for i in (0..nm1).rev() {
            c[i] = (c[i] - d[i] * c[i + 1]) / b[i];
        }
        // Polynomial coefficients.
        b[nm1] = (y[nm1] - y[n - 2]) / d[n - 2] + d[n - 2] * (c[n - 2] + 2.0 * c[nm1]);
        for i in 0..nm1 {
            b[i] = (y[i + 1] - y[i]) / d[i] - d[i] * (c[i + 1] + 2.0 * c[i]);
            d[i] = (c[i + 1] - c[i]) / d[i];
            c[i] *= 3.0;
        }
        c[nm1] *= 3.0;
        d[nm1] = d[n - 2];
        Self { x, y, b, c, d }
    }

    /// Coefficients of a model `PiecewiseLinear` function as the model computes them;
    /// empty when its knots are invalid (the importer rejects those).
    pub fn from_model(f: &Function) -> Self {
        let seg = match f {
            Function::PiecewiseLinear { x, y } => stride_model::function::piecewise_linear(x, y),
            _ => Err(stride_model::function::FunctionError::TooFewKnots(0)),
        };
        match seg {
            Ok(s) => Self {
                x: s.x,
                y: s.y,
                b: s.b,
                c: s.c,
                d: s.d,
            },
            Err(_) => Self::new(&[], &[]),
        }
    }

    /// Spline value at `x`; linear extrapolation with the end slopes outside the knots.
    pub fn eval<T: Scalar>(&self, x: T) -> T {
        let n = self.x.len();
        if n == 0 {
            return T::zero();
        }
        if n == 1 {
            return T::cst(self.y[0]);
        }
        let xv = x.value();
        if xv <= self.x[0] {
            return (x - self.x[0]) * self.b[0] + self.y[0];
        }
        if xv >= self.x[n - 1] {
            return (x - self.x[n - 1]) * self.b[n - 1] + self.y[n - 1];
        }
        // Interval containing xv (discrete choice from the primal value).
        let i = match self.x.partition_point(|&k| k <= xv) {
            0 => 0,
            p => (p - 1).min(n - 2),
        };
        let dx = x - self.x[i];
        ((dx * self.d[i] + self.c[i]) * dx + self.b[i]) * dx + self.y[i]
    }
}

/// Value of a coordinate function at `x` [rad or m]. Splines are rebuilt on every call;
/// use [`PreparedFunction`] in loops.
pub fn eval_function<T: Scalar>(f: &Function, x: T) -> T {
    PreparedFunction::new(f).eval(x)
}

/// A coordinate function with its spline coefficients precomputed.
#[derive(Clone, Debug, PartialEq)]
pub enum PreparedFunction {
    /// `f(x) = value`.
    Constant(f64),
    /// `f(x) = slope x + intercept`.
    Linear(f64, f64),
    /// Cubic spline.
    Spline(SplineCoefficients),
    /// Polynomial, highest power first.
    Polynomial(Vec<f64>),
    /// `scale · g(x)`.
    Multiplier(f64, Box<PreparedFunction>),
}

impl PreparedFunction {
    /// Precomputes a model function.
    pub fn new(f: &Function) -> Self {
        match f {
            Function::Constant(v) => Self::Constant(*v),
            Function::Linear { slope, intercept } => Self::Linear(*slope, *intercept),
            Function::SimmSpline { x, y } => Self::Spline(SplineCoefficients::new(x, y)),
            Function::PiecewiseLinear { .. } => Self::Spline(SplineCoefficients::from_model(f)),
            Function::Polynomial { coefficients } => Self::Polynomial(coefficients.clone()),
            Function::Multiplier { scale, function } => {
                Self::Multiplier(*scale, Box::new(Self::new(function)))
            }
        }
    }

    /// Value at `x` [rad or m].
    pub fn eval<T: Scalar>(&self, x: T) -> T {
        match self {
            Self::Constant(v) => T::cst(*v),
            Self::Linear(s, i) => x * *s + *i,
            Self::Spline(s) => s.eval(x),
            Self::Polynomial(c) => c.iter().fold(T::zero(), |acc, &ck| acc * x + ck),
            Self::Multiplier(s, g) => g.eval(x) * *s,
        }
    }
}
