//! Forward-mode dual numbers: [`Dual`] (one directional derivative) and [`HyperDual`]
//! (two directional derivatives and their mixed second derivative).

use crate::elementary::{cos3, exp3, ln3, powf3, recip3, sin3, sqrt3, tanh3};
use crate::scalar::{Scalar, UnaryFn};
use std::sync::Arc;

/// Implements the arithmetic operator traits of a derivative type from its inherent
/// `add_`, `sub_`, `mul_`, `div_`, `neg_`, `shift` and `scale` methods.
macro_rules! impl_dual_ops {
    ([$($gen:tt)*] $t:ty) => {
        impl<$($gen)*> std::ops::Add for $t {
            type Output = Self;
            #[inline]
            fn add(self, o: Self) -> Self { self.add_(o) }
        }
        impl<$($gen)*> std::ops::Sub for $t {
            type Output = Self;
            #[inline]
            fn sub(self, o: Self) -> Self { self.sub_(o) }
        }
        impl<$($gen)*> std::ops::Mul for $t {
            type Output = Self;
            #[inline]
            fn mul(self, o: Self) -> Self { self.mul_(o) }
        }
        impl<$($gen)*> std::ops::Div for $t {
            type Output = Self;
            #[inline]
            fn div(self, o: Self) -> Self { self.div_(o) }
        }
        impl<$($gen)*> std::ops::Neg for $t {
            type Output = Self;
            #[inline]
            fn neg(self) -> Self { self.neg_() }
        }
        impl<$($gen)*> std::ops::Add<f64> for $t {
            type Output = Self;
            #[inline]
            fn add(self, c: f64) -> Self { self.shift(c) }
        }
        impl<$($gen)*> std::ops::Sub<f64> for $t {
            type Output = Self;
            #[inline]
            fn sub(self, c: f64) -> Self { self.shift(-c) }
        }
        impl<$($gen)*> std::ops::Mul<f64> for $t {
            type Output = Self;
            #[inline]
            fn mul(self, c: f64) -> Self { self.scale(c) }
        }
        impl<$($gen)*> std::ops::Div<f64> for $t {
            type Output = Self;
            #[inline]
            fn div(self, c: f64) -> Self { self.scale(1.0 / c) }
        }
        impl<$($gen)*> std::ops::AddAssign for $t {
            #[inline]
            fn add_assign(&mut self, o: Self) { *self = self.add_(o) }
        }
        impl<$($gen)*> std::ops::SubAssign for $t {
            #[inline]
            fn sub_assign(&mut self, o: Self) { *self = self.sub_(o) }
        }
        impl<$($gen)*> std::ops::MulAssign for $t {
            #[inline]
            fn mul_assign(&mut self, o: Self) { *self = self.mul_(o) }
        }
        impl<$($gen)*> std::ops::DivAssign for $t {
            #[inline]
            fn div_assign(&mut self, o: Self) { *self = self.div_(o) }
        }
        impl<$($gen)*> std::ops::AddAssign<f64> for $t {
            #[inline]
            fn add_assign(&mut self, c: f64) { *self = self.shift(c) }
        }
        impl<$($gen)*> std::ops::SubAssign<f64> for $t {
            #[inline]
            fn sub_assign(&mut self, c: f64) { *self = self.shift(-c) }
        }
        impl<$($gen)*> std::ops::MulAssign<f64> for $t {
            #[inline]
            fn mul_assign(&mut self, c: f64) { *self = self.scale(c) }
        }
        impl<$($gen)*> std::ops::DivAssign<f64> for $t {
            #[inline]
            fn div_assign(&mut self, c: f64) { *self = self.scale(1.0 / c) }
        }
        impl<$($gen)*> Scalar for $t {
            #[inline]
            fn cst(x: f64) -> Self { Self::constant(x) }
            #[inline]
            fn value(self) -> f64 { self.re() }
            #[inline]
            fn sin(self) -> Self { self.chain(sin3(self.re())) }
            #[inline]
            fn cos(self) -> Self { self.chain(cos3(self.re())) }
            #[inline]
            fn exp(self) -> Self { self.chain(exp3(self.re())) }
            #[inline]
            fn ln(self) -> Self { self.chain(ln3(self.re())) }
            #[inline]
            fn sqrt(self) -> Self { self.chain(sqrt3(self.re())) }
            #[inline]
            fn tanh(self) -> Self { self.chain(tanh3(self.re())) }
            #[inline]
            fn powf(self, p: f64) -> Self { self.chain(powf3(self.re(), p)) }
            #[inline]
            fn recip(self) -> Self { self.chain(recip3(self.re())) }
            #[inline]
            fn fmin(self, other: Self) -> Self {
                if self.re() <= other.re() { self } else { other }
            }
            #[inline]
            fn fmax(self, other: Self) -> Self {
                if self.re() >= other.re() { self } else { other }
            }
            #[inline]
            fn select_pos(cond: Self, pos: Self, nonpos: Self) -> Self {
                if cond.re() > 0.0 { pos } else { nonpos }
            }
            #[inline]
            fn apply(self, f: &Arc<dyn UnaryFn>) -> Self { self.chain(f.eval(self.re())) }
        }
    };
}
pub(crate) use impl_dual_ops;

/// A forward-mode dual number `re + eps·ε` (ε² = 0): value and one directional derivative.
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub struct Dual {
    /// The value.
    pub re: f64,
    /// The derivative along the seeded direction.
    pub eps: f64,
}

impl Dual {
    /// A dual number with value `re` and derivative `eps`.
    #[inline]
    pub const fn new(re: f64, eps: f64) -> Self {
        Self { re, eps }
    }
    /// An independent variable: value `re`, derivative 1.
    #[inline]
    pub const fn var(re: f64) -> Self {
        Self { re, eps: 1.0 }
    }
    /// A constant: value `re`, derivative 0.
    #[inline]
    pub const fn constant(re: f64) -> Self {
        Self { re, eps: 0.0 }
    }
    #[inline]
    fn re(self) -> f64 {
        self.re
    }
    #[inline]
    fn chain(self, f: [f64; 3]) -> Self {
        Self::new(f[0], f[1] * self.eps)
    }
    #[inline]
    fn add_(self, o: Self) -> Self {
        Self::new(self.re + o.re, self.eps + o.eps)
    }
    #[inline]
    fn sub_(self, o: Self) -> Self {
        Self::new(self.re - o.re, self.eps - o.eps)
    }
    #[inline]
    fn mul_(self, o: Self) -> Self {
        Self::new(self.re * o.re, self.eps * o.re + self.re * o.eps)
    }
    #[inline]
    fn div_(self, o: Self) -> Self {
        let r = 1.0 / o.re;
        let q = self.re * r;
        Self::new(q, (self.eps - q * o.eps) * r)
    }
    #[inline]
    fn neg_(self) -> Self {
        Self::new(-self.re, -self.eps)
    }
    #[inline]
    fn shift(self, c: f64) -> Self {
        Self::new(self.re + c, self.eps)
    }
    #[inline]
    fn scale(self, c: f64) -> Self {
        Self::new(self.re * c, self.eps * c)
    }
}

impl_dual_ops!([] Dual);

/// A hyper-dual number `re + e1·ε₁ + e2·ε₂ + e12·ε₁ε₂` (ε₁² = ε₂² = 0): value, two
/// directional derivatives and the mixed second derivative along both directions.
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub struct HyperDual {
    /// The value.
    pub re: f64,
    /// The derivative along the first direction.
    pub e1: f64,
    /// The derivative along the second direction.
    pub e2: f64,
    /// The mixed second derivative along both directions.
    pub e12: f64,
}

impl HyperDual {
    /// A hyper-dual number from its four parts.
    #[inline]
    pub const fn new(re: f64, e1: f64, e2: f64, e12: f64) -> Self {
        Self { re, e1, e2, e12 }
    }
    /// A constant: value `re`, all derivatives 0.
    #[inline]
    pub const fn constant(re: f64) -> Self {
        Self::new(re, 0.0, 0.0, 0.0)
    }
    /// An independent variable seeded in both directions (for a pure second derivative).
    #[inline]
    pub const fn var(re: f64) -> Self {
        Self::new(re, 1.0, 1.0, 0.0)
    }
    #[inline]
    fn re(self) -> f64 {
        self.re
    }
    #[inline]
    fn chain(self, f: [f64; 3]) -> Self {
        Self::new(
            f[0],
            f[1] * self.e1,
            f[1] * self.e2,
            f[1] * self.e12 + f[2] * self.e1 * self.e2,
        )
    }
    #[inline]
    fn add_(self, o: Self) -> Self {
        Self::new(
            self.re + o.re,
            self.e1 + o.e1,
            self.e2 + o.e2,
            self.e12 + o.e12,
        )
    }
    #[inline]
    fn sub_(self, o: Self) -> Self {
        Self::new(
            self.re - o.re,
            self.e1 - o.e1,
            self.e2 - o.e2,
            self.e12 - o.e12,
        )
    }
    #[inline]
    fn mul_(self, o: Self) -> Self {
        Self::new(
            self.re * o.re,
            self.e1 * o.re + self.re * o.e1,
            self.e2 * o.re + self.re * o.e2,
            self.e12 * o.re + self.e1 * o.e2 + self.e2 * o.e1 + self.re * o.e12,
        )
    }
    #[inline]
    fn div_(self, o: Self) -> Self {
        self.mul_(o.chain(recip3(o.re)))
    }
    #[inline]
    fn neg_(self) -> Self {
        Self::new(-self.re, -self.e1, -self.e2, -self.e12)
    }
    #[inline]
    fn shift(self, c: f64) -> Self {
        Self::new(self.re + c, self.e1, self.e2, self.e12)
    }
    #[inline]
    fn scale(self, c: f64) -> Self {
        Self::new(self.re * c, self.e1 * c, self.e2 * c, self.e12 * c)
    }
}

impl_dual_ops!([] HyperDual);
