//! The `Scalar` trait: the number type every model function is generic over.
//!
//! Model code (kinematics, contact, muscles, metabolics, cost terms) is written once,
//! generic over `T: Scalar`, and runs on `f64` for plain evaluation and on the
//! derivative types of this crate for Jacobians and Hessians.
//!
//! Rules for code written against this trait (they make record-once tapes valid):
//! - never branch on [`Scalar::value`]; use [`Scalar::fmin`], [`Scalar::fmax`],
//!   [`Scalar::select_pos`] or a [`UnaryFn`] so the branch is re-taken at every evaluation;
//! - constants enter through [`Scalar::cst`] or the mixed `T op f64` operators.

use std::fmt::Debug;
use std::ops::{Add, AddAssign, Div, DivAssign, Mul, MulAssign, Neg, Sub, SubAssign};
use std::sync::Arc;

/// A scalar function of one variable with its first two derivatives, usable inside
/// recorded tapes (coordinate functions such as splines, tabulated curves).
pub trait UnaryFn: Send + Sync + Debug {
    /// Value, first and second derivative at `x`: `[f(x), f'(x), f''(x)]`.
    fn eval(&self, x: f64) -> [f64; 3];
}

/// The number type of model functions: `f64`, or an automatic-differentiation type.
pub trait Scalar:
    Copy
    + Debug
    + Send
    + Sync
    + 'static
    + Add<Output = Self>
    + Sub<Output = Self>
    + Mul<Output = Self>
    + Div<Output = Self>
    + Neg<Output = Self>
    + Add<f64, Output = Self>
    + Sub<f64, Output = Self>
    + Mul<f64, Output = Self>
    + Div<f64, Output = Self>
    + AddAssign
    + SubAssign
    + MulAssign
    + DivAssign
    + AddAssign<f64>
    + SubAssign<f64>
    + MulAssign<f64>
    + DivAssign<f64>
{
    /// A constant (carries no derivative).
    fn cst(x: f64) -> Self;
    /// The primal value; for reporting only, never for control flow.
    fn value(self) -> f64;
    /// Sine (argument in rad).
    fn sin(self) -> Self;
    /// Cosine (argument in rad).
    fn cos(self) -> Self;
    /// Natural exponential.
    fn exp(self) -> Self;
    /// Natural logarithm.
    fn ln(self) -> Self;
    /// Square root.
    fn sqrt(self) -> Self;
    /// Hyperbolic tangent.
    fn tanh(self) -> Self;
    /// Power with a constant real exponent (`self > 0` unless `p` is an integer).
    fn powf(self, p: f64) -> Self;
    /// Smaller of two values (derivative taken from the selected branch).
    fn fmin(self, other: Self) -> Self;
    /// Larger of two values (derivative taken from the selected branch).
    fn fmax(self, other: Self) -> Self;
    /// `if cond > 0 { pos } else { nonpos }`, re-decided at every evaluation.
    fn select_pos(cond: Self, pos: Self, nonpos: Self) -> Self;
    /// Apply a registered one-dimensional function (spline, tabulated curve).
    fn apply(self, f: &Arc<dyn UnaryFn>) -> Self;

    /// Zero.
    #[inline]
    fn zero() -> Self {
        Self::cst(0.0)
    }
    /// One.
    #[inline]
    fn one() -> Self {
        Self::cst(1.0)
    }
    /// Square, `self * self`.
    #[inline]
    fn sq(self) -> Self {
        self * self
    }
    /// Tangent.
    #[inline]
    fn tan(self) -> Self {
        self.sin() / self.cos()
    }
    /// Reciprocal `1 / self`.
    #[inline]
    fn recip(self) -> Self {
        Self::one() / self
    }
    /// Integer power by repeated multiplication (exact for AD types).
    #[inline]
    fn powi(self, n: i32) -> Self {
        match n {
            0 => Self::one(),
            1 => self,
            2 => self * self,
            n if n < 0 => self.powi(-n).recip(),
            n => {
                let half = self.powi(n / 2);
                if n % 2 == 0 {
                    half * half
                } else {
                    half * half * self
                }
            }
        }
    }
    /// `c - self` for a constant `c`.
    #[inline]
    fn rsub(self, c: f64) -> Self {
        -self + c
    }
    /// `c / self` for a constant `c`.
    #[inline]
    fn rdiv(self, c: f64) -> Self {
        self.recip() * c
    }
}

impl Scalar for f64 {
    #[inline]
    fn cst(x: f64) -> Self {
        x
    }
    #[inline]
    fn value(self) -> f64 {
        self
    }
    #[inline]
    fn sin(self) -> Self {
        f64::sin(self)
    }
    #[inline]
    fn cos(self) -> Self {
        f64::cos(self)
    }
    #[inline]
    fn exp(self) -> Self {
        f64::exp(self)
    }
    #[inline]
    fn ln(self) -> Self {
        f64::ln(self)
    }
    #[inline]
    fn sqrt(self) -> Self {
        f64::sqrt(self)
    }
    #[inline]
    fn tanh(self) -> Self {
        f64::tanh(self)
    }
    #[inline]
    fn powf(self, p: f64) -> Self {
        f64::powf(self, p)
    }
    #[inline]
    fn fmin(self, other: Self) -> Self {
        f64::min(self, other)
    }
    #[inline]
    fn fmax(self, other: Self) -> Self {
        f64::max(self, other)
    }
    #[inline]
    fn select_pos(cond: Self, pos: Self, nonpos: Self) -> Self {
        if cond > 0.0 {
            pos
        } else {
            nonpos
        }
    }
    #[inline]
    fn apply(self, f: &Arc<dyn UnaryFn>) -> Self {
        f.eval(self)[0]
    }
    #[inline]
    fn powi(self, n: i32) -> Self {
        f64::powi(self, n)
    }
}

/// Smooth step `σ_b(x) = ½ + ½ tanh(b x)` used by the contact and metabolic models.
#[inline]
pub fn smooth_step<T: Scalar>(x: T, b: f64) -> T {
    (x * b).tanh() * 0.5 + 0.5
}
