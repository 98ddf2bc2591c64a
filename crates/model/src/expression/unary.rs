//! The one-argument functions of OpenSim's Lepton parser: those the scalar type provides,
//! compositions of them, and the others with their first two derivatives.

use super::{Native, Op};
use std::sync::Arc;
use stride_ad::UnaryFn;

/// A one-argument Lepton function.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Lepton {
    Native(Native),
    Sec,
    Csc,
    Cot,
    Square,
    Cube,
    Special(Special),
}

/// Functions evaluated with their derivatives as a [`UnaryFn`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Special {
    Asin,
    Acos,
    Atan,
    Sinh,
    Cosh,
    Erf,
    Erfc,
    /// 1 for x ≥ 0, else 0.
    Step,
    /// 1 at x = 0, else 0.
    Delta,
    Abs,
}

/// The Lepton function named `f`, if there is one.
pub(super) fn lepton_unary(f: &str) -> Option<Lepton> {
    use Lepton as L;
    Some(match f {
        "sqrt" => L::Native(Native::Sqrt),
        "exp" => L::Native(Native::Exp),
        "log" => L::Native(Native::Log),
        "sin" => L::Native(Native::Sin),
        "cos" => L::Native(Native::Cos),
        "tan" => L::Native(Native::Tan),
        "tanh" => L::Native(Native::Tanh),
        "recip" => L::Native(Native::Recip),
        "sec" => L::Sec,
        "csc" => L::Csc,
        "cot" => L::Cot,
        "square" => L::Square,
        "cube" => L::Cube,
        "asin" => L::Special(Special::Asin),
        "acos" => L::Special(Special::Acos),
        "atan" => L::Special(Special::Atan),
        "sinh" => L::Special(Special::Sinh),
        "cosh" => L::Special(Special::Cosh),
        "erf" => L::Special(Special::Erf),
        "erfc" => L::Special(Special::Erfc),
        "step" => L::Special(Special::Step),
        "delta" => L::Special(Special::Delta),
        "abs" => L::Special(Special::Abs),
        _ => return None,
    })
}

impl Lepton {
    /// The instructions applying the function to the top of the stack.
    pub(super) fn ops(self) -> Vec<Op> {
        let recip_of = |n: Native| vec![Op::Native(n), Op::Native(Native::Recip)];
        match self {
            Lepton::Native(n) => vec![Op::Native(n)],
            Lepton::Sec => recip_of(Native::Cos),
            Lepton::Csc => recip_of(Native::Sin),
            Lepton::Cot => recip_of(Native::Tan),
            Lepton::Square => vec![Op::PowConst(2.0)],
            Lepton::Cube => vec![Op::PowConst(3.0)],
            Lepton::Special(s) => vec![Op::Unary(Arc::new(s))],
        }
    }
}

/// 2/√π.
const TWO_OVER_SQRT_PI: f64 = std::f64::consts::FRAC_2_SQRT_PI;

impl UnaryFn for Special {
    fn eval(&self, x: f64) -> [f64; 3] {
        let one_minus_sq = 1.0 - x * x;
        match self {
            Special::Asin | Special::Acos => {
                let s = if *self == Special::Asin { 1.0 } else { -1.0 };
                let d = one_minus_sq.sqrt().recip();
                let v = if s > 0.0 { x.asin() } else { x.acos() };
                [v, s * d, s * x * d * d * d]
            }
            Special::Atan => {
                let d = 1.0 / (1.0 + x * x);
                [x.atan(), d, -2.0 * x * d * d]
            }
            Special::Sinh => [x.sinh(), x.cosh(), x.sinh()],
            Special::Cosh => [x.cosh(), x.sinh(), x.cosh()],
            Special::Erf | Special::Erfc => {
                let s = if *self == Special::Erf { 1.0 } else { -1.0 };
                let d = TWO_OVER_SQRT_PI * (-x * x).exp();
                let v = if s > 0.0 { erf(x) } else { erfc(x) };
                [v, s * d, -2.0 * x * s * d]
            }
            Special::Step => [if x >= 0.0 { 1.0 } else { 0.0 }, 0.0, 0.0],
            Special::Delta => [if x == 0.0 { 1.0 } else { 0.0 }, 0.0, 0.0],
            Special::Abs => [x.abs(), if x >= 0.0 { 1.0 } else { -1.0 }, 0.0],
        }
    }
}

/// The error function: its Maclaurin series below |x| = 2.5, 1 − erfc(x) above.
pub(super) fn erf(x: f64) -> f64 {
    if x.abs() >= 2.5 {
        return x.signum() * (1.0 - erfc_tail(x.abs()));
    }
    // erf(x) = 2/√π Σ (−1)ⁿ x^(2n+1) / (n! (2n+1))
    let (mut term, mut sum) = (x, x);
    for n in 1..200 {
        term *= -x * x / n as f64;
        let add = term / (2 * n + 1) as f64;
        sum += add;
        if add.abs() <= 1e-17 * sum.abs() {
            break;
        }
    }
    TWO_OVER_SQRT_PI * sum
}

/// The complementary error function 1 − erf(x).
pub(super) fn erfc(x: f64) -> f64 {
    if x >= 2.5 {
        erfc_tail(x)
    } else {
        1.0 - erf(x)
    }
}

/// erfc(x) for x ≥ 2.5 from its continued fraction
/// `e^(−x²)/√π · 1/(x + (1/2)/(x + 1/(x + (3/2)/(x + …))))`, evaluated from the back.
fn erfc_tail(x: f64) -> f64 {
    let mut t = x;
    for k in (1..=120).rev() {
        t = x + (k as f64 / 2.0) / t;
    }
    (-x * x).exp() / (std::f64::consts::PI.sqrt() * t)
}
