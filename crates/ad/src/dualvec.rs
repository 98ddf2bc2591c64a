//! [`DualVec`]: forward vector mode, a value with `N` directional derivatives, used for
//! compressed (column-coloured) Jacobians evaluated directly on generic code.

use crate::dual::impl_dual_ops;
use crate::elementary::{cos3, exp3, ln3, powf3, recip3, sin3, sqrt3, tanh3};
use crate::scalar::{Scalar, UnaryFn};
use std::sync::Arc;

/// A value and its derivatives along `N` seeded directions.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DualVec<const N: usize> {
    /// The value.
    pub re: f64,
    /// The derivatives along the seeded directions.
    pub eps: [f64; N],
}

impl<const N: usize> DualVec<N> {
    /// A constant: value `re`, all derivatives 0.
    #[inline]
    pub const fn constant(re: f64) -> Self {
        Self { re, eps: [0.0; N] }
    }
    /// An independent variable with derivative 1 along direction `dir` (if `< N`).
    #[inline]
    pub fn var(re: f64, dir: usize) -> Self {
        let mut eps = [0.0; N];
        if dir < N {
            eps[dir] = 1.0;
        }
        Self { re, eps }
    }
    #[inline]
    fn re(self) -> f64 {
        self.re
    }
    #[inline]
    fn map(self, re: f64, f: impl Fn(f64) -> f64) -> Self {
        let mut eps = self.eps;
        eps.iter_mut().for_each(|e| *e = f(*e));
        Self { re, eps }
    }
    #[inline]
    fn zip(self, o: Self, re: f64, f: impl Fn(f64, f64) -> f64) -> Self {
        let mut eps = self.eps;
        eps.iter_mut().zip(o.eps).for_each(|(e, d)| *e = f(*e, d));
        Self { re, eps }
    }
    #[inline]
    fn chain(self, f: [f64; 3]) -> Self {
        self.map(f[0], |e| f[1] * e)
    }
    #[inline]
    fn add_(self, o: Self) -> Self {
        self.zip(o, self.re + o.re, |a, b| a + b)
    }
    #[inline]
    fn sub_(self, o: Self) -> Self {
        self.zip(o, self.re - o.re, |a, b| a - b)
    }
    #[inline]
    fn mul_(self, o: Self) -> Self {
        let (x, y) = (self.re, o.re);
        self.zip(o, x * y, |a, b| a * y + x * b)
    }
    #[inline]
    fn div_(self, o: Self) -> Self {
        let r = 1.0 / o.re;
        let q = self.re / o.re;
        self.zip(o, q, |a, b| (a - q * b) * r)
    }
    #[inline]
    fn neg_(self) -> Self {
        self.map(-self.re, |e| -e)
    }
    #[inline]
    fn shift(self, c: f64) -> Self {
        Self {
            re: self.re + c,
            eps: self.eps,
        }
    }
    #[inline]
    fn scale(self, c: f64) -> Self {
        self.map(self.re * c, |e| e * c)
    }
}

impl_dual_ops!([const N: usize] DualVec<N>);
