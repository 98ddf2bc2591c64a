//! The operations a tape records, with their value and local derivatives.

use crate::elementary::{cos3, exp3, ln3, recip3, sin3, sqrt3, tanh3};

/// A one-argument elementary function recorded on a tape.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Elem {
    /// Sine.
    Sin,
    /// Cosine.
    Cos,
    /// Exponential.
    Exp,
    /// Natural logarithm.
    Ln,
    /// Square root.
    Sqrt,
    /// Hyperbolic tangent.
    Tanh,
    /// Reciprocal `1/x`.
    Recip,
}

impl Elem {
    /// The value alone, computed exactly as `f64` model code computes it.
    #[inline]
    pub fn value(self, x: f64) -> f64 {
        match self {
            Elem::Sin => x.sin(),
            Elem::Cos => x.cos(),
            Elem::Exp => x.exp(),
            Elem::Ln => x.ln(),
            Elem::Sqrt => x.sqrt(),
            Elem::Tanh => x.tanh(),
            Elem::Recip => 1.0 / x,
        }
    }
    /// Value, first and second derivative.
    #[inline]
    pub fn eval3(self, x: f64) -> [f64; 3] {
        match self {
            Elem::Sin => sin3(x),
            Elem::Cos => cos3(x),
            Elem::Exp => exp3(x),
            Elem::Ln => ln3(x),
            Elem::Sqrt => sqrt3(x),
            Elem::Tanh => tanh3(x),
            Elem::Recip => recip3(x),
        }
    }
}

/// One recorded operation; operands are node indices (inputs are nodes `0..n_inputs`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Op {
    /// Independent variable number `.0`.
    Input(u32),
    /// A constant.
    Const(f64),
    /// `a + b`.
    Add(u32, u32),
    /// `a - b`.
    Sub(u32, u32),
    /// `a * b`.
    Mul(u32, u32),
    /// `a / b`.
    Div(u32, u32),
    /// `-a`.
    Neg(u32),
    /// `a + c`.
    AddC(u32, f64),
    /// `a * c`.
    MulC(u32, f64),
    /// `a / c`.
    DivC(u32, f64),
    /// `c / a`.
    CDiv(f64, u32),
    /// An elementary function of `a`.
    Unary(u32, Elem),
    /// `a^p`, constant real `p`.
    Powf(u32, f64),
    /// `a^n`, integer `n`.
    Powi(u32, i32),
    /// Registered unary function number `.1` applied to `a`.
    Apply(u32, u32),
    /// `min(a, b)`.
    Min(u32, u32),
    /// `max(a, b)`.
    Max(u32, u32),
    /// `if c > 0 { p } else { n }`.
    Select(u32, u32, u32),
}

/// Which kind of second-order interaction an operation creates between its operands.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Curvature {
    /// Linear or piecewise linear: no second derivative.
    Linear,
    /// Nonlinear in its single operand.
    Unary,
    /// Bilinear `a * b`: only the mixed term.
    Bilinear,
    /// `a / b`: mixed term and curvature in `b`.
    Quotient,
}

impl Op {
    /// The operands through which derivatives flow, `[a, b]` (`b = a` when unary).
    /// `None` for inputs and constants.
    #[inline]
    pub fn diff_args(&self) -> Option<[u32; 2]> {
        Some(match *self {
            Op::Input(_) | Op::Const(_) => return None,
            Op::Add(a, b) | Op::Sub(a, b) | Op::Mul(a, b) | Op::Div(a, b) => [a, b],
            Op::Min(a, b) | Op::Max(a, b) => [a, b],
            Op::Select(_, p, n) => [p, n],
            Op::Neg(a)
            | Op::AddC(a, _)
            | Op::MulC(a, _)
            | Op::DivC(a, _)
            | Op::CDiv(_, a)
            | Op::Unary(a, _)
            | Op::Powf(a, _)
            | Op::Powi(a, _)
            | Op::Apply(a, _) => [a, a],
        })
    }

    /// All operands read to compute the value (including the condition of a select).
    pub fn value_args(&self, out: &mut Vec<u32>) {
        out.clear();
        if let Op::Select(c, p, n) = *self {
            out.extend_from_slice(&[c, p, n]);
        } else if let Some([a, b]) = self.diff_args() {
            out.push(a);
            if b != a || matches!(self, Op::Add(..) | Op::Sub(..) | Op::Mul(..) | Op::Div(..)) {
                out.push(b);
            }
        }
    }

    /// Remaps operand indices through `map`.
    pub fn remap(self, map: &[u32]) -> Op {
        let m = |i: u32| map[i as usize];
        match self {
            Op::Input(k) => Op::Input(k),
            Op::Const(c) => Op::Const(c),
            Op::Add(a, b) => Op::Add(m(a), m(b)),
            Op::Sub(a, b) => Op::Sub(m(a), m(b)),
            Op::Mul(a, b) => Op::Mul(m(a), m(b)),
            Op::Div(a, b) => Op::Div(m(a), m(b)),
            Op::Neg(a) => Op::Neg(m(a)),
            Op::AddC(a, c) => Op::AddC(m(a), c),
            Op::MulC(a, c) => Op::MulC(m(a), c),
            Op::DivC(a, c) => Op::DivC(m(a), c),
            Op::CDiv(c, a) => Op::CDiv(c, m(a)),
            Op::Unary(a, e) => Op::Unary(m(a), e),
            Op::Powf(a, p) => Op::Powf(m(a), p),
            Op::Powi(a, n) => Op::Powi(m(a), n),
            Op::Apply(a, f) => Op::Apply(m(a), f),
            Op::Min(a, b) => Op::Min(m(a), m(b)),
            Op::Max(a, b) => Op::Max(m(a), m(b)),
            Op::Select(c, p, n) => Op::Select(m(c), m(p), m(n)),
        }
    }

    /// The partials `[∂/∂a, ∂/∂b]` when they are constants independent of the operand
    /// values (sums, differences, negation, scaling, shifts); `None` otherwise.
    /// They equal the partials the value sweep computes.
    pub fn constant_partials(&self) -> Option<[f64; 2]> {
        match *self {
            Op::Add(..) => Some([1.0, 1.0]),
            Op::Sub(..) => Some([1.0, -1.0]),
            Op::Neg(_) => Some([-1.0, 0.0]),
            Op::AddC(..) => Some([1.0, 0.0]),
            Op::MulC(_, c) => Some([c, 0.0]),
            Op::DivC(_, c) => Some([1.0 / c, 0.0]),
            _ => None,
        }
    }

    /// The second-order structure of the operation.
    pub fn curvature(&self) -> Curvature {
        match *self {
            Op::Mul(..) => Curvature::Bilinear,
            Op::Div(..) => Curvature::Quotient,
            Op::CDiv(..) | Op::Unary(..) | Op::Apply(..) => Curvature::Unary,
            Op::Powf(_, p) if p != 1.0 && p != 0.0 => Curvature::Unary,
            Op::Powi(_, n) if n != 1 && n != 0 => Curvature::Unary,
            _ => Curvature::Linear,
        }
    }
}

/// Value, first and second derivative of `x^n` for integer `n`, value as `f64::powi`.
#[inline]
pub fn powi3(x: f64, n: i32) -> [f64; 3] {
    let nf = n as f64;
    [
        x.powi(n),
        nf * x.powi(n - 1),
        nf * (nf - 1.0) * x.powi(n - 2),
    ]
}
