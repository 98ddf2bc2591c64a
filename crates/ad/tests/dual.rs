//! Dual and HyperDual derivatives of every `Scalar` method against analytic derivatives.

use std::sync::Arc;
use stride_ad::{Dual, HyperDual, Scalar, UnaryFn};

/// `x³` with its analytic derivatives, as a registered unary function.
#[derive(Debug)]
struct Cube;
impl UnaryFn for Cube {
    fn eval(&self, x: f64) -> [f64; 3] {
        [x * x * x, 3.0 * x * x, 6.0 * x]
    }
}

fn close(a: f64, b: f64) -> bool {
    (a - b).abs() <= 1e-12 * (1.0 + a.abs().max(b.abs()))
}

/// (name, f on Dual, f on HyperDual, analytic [f, f', f''] at x).
type Case = (
    &'static str,
    fn(Dual) -> Dual,
    fn(HyperDual) -> HyperDual,
    fn(f64) -> [f64; 3],
);

fn cases() -> Vec<Case> {
    vec![
        (
            "sin",
            |x| x.sin(),
            |x| x.sin(),
            |x| [x.sin(), x.cos(), -x.sin()],
        ),
        (
            "cos",
            |x| x.cos(),
            |x| x.cos(),
            |x| [x.cos(), -x.sin(), -x.cos()],
        ),
        (
            "exp",
            |x| x.exp(),
            |x| x.exp(),
            |x| [x.exp(), x.exp(), x.exp()],
        ),
        (
            "ln",
            |x| x.ln(),
            |x| x.ln(),
            |x| [x.ln(), 1.0 / x, -1.0 / (x * x)],
        ),
        (
            "sqrt",
            |x| x.sqrt(),
            |x| x.sqrt(),
            |x| [x.sqrt(), 0.5 / x.sqrt(), -0.25 * x.powf(-1.5)],
        ),
        (
            "tanh",
            |x| x.tanh(),
            |x| x.tanh(),
            |x| {
                let t = x.tanh();
                [t, 1.0 - t * t, -2.0 * t * (1.0 - t * t)]
            },
        ),
        (
            "powf",
            |x| x.powf(2.7),
            |x| x.powf(2.7),
            |x| [x.powf(2.7), 2.7 * x.powf(1.7), 2.7 * 1.7 * x.powf(0.7)],
        ),
        (
            "powi",
            |x| x.powi(-3),
            |x| x.powi(-3),
            |x| [x.powi(-3), -3.0 * x.powi(-4), 12.0 * x.powi(-5)],
        ),
        (
            "recip",
            |x| x.recip(),
            |x| x.recip(),
            |x| [1.0 / x, -1.0 / (x * x), 2.0 / (x * x * x)],
        ),
        (
            "tan",
            |x| x.tan(),
            |x| x.tan(),
            |x| {
                let c = x.cos();
                [x.tan(), 1.0 / (c * c), 2.0 * x.tan() / (c * c)]
            },
        ),
        ("sq", |x| x.sq(), |x| x.sq(), |x| [x * x, 2.0 * x, 2.0]),
        (
            "rsub",
            |x| x.rsub(3.0),
            |x| x.rsub(3.0),
            |x| [3.0 - x, -1.0, 0.0],
        ),
        (
            "rdiv",
            |x| x.rdiv(3.0),
            |x| x.rdiv(3.0),
            |x| [3.0 / x, -3.0 / (x * x), 6.0 / (x * x * x)],
        ),
        (
            "mul/div mixed",
            |x| (x * 2.0 + 1.0) / (x - 0.25) * x,
            |x| (x * 2.0 + 1.0) / (x - 0.25) * x,
            |x| {
                // f = (2x² + x) / (x - 1/4); f = 2x + 3/2 + (3/8)/(x - 1/4)
                let d = x - 0.25;
                [
                    (2.0 * x * x + x) / d,
                    2.0 - 0.375 / (d * d),
                    0.75 / (d * d * d),
                ]
            },
        ),
        (
            "assign ops",
            |x| {
                let mut y = x;
                y += 1.0;
                y *= x;
                y -= 0.5;
                y /= 2.0;
                y += x;
                y -= x * 0.5;
                y *= 3.0;
                y /= x;
                y
            },
            |x| {
                let mut y = x;
                y += 1.0;
                y *= x;
                y -= 0.5;
                y /= 2.0;
                y += x;
                y -= x * 0.5;
                y *= 3.0;
                y /= x;
                y
            },
            |x| {
                // y = 3 ((x² + x - 0.5)/2 + x/2) / x = 1.5 x + 3 - 0.75/x
                [
                    1.5 * x + 3.0 - 0.75 / x,
                    1.5 + 0.75 / (x * x),
                    -1.5 / (x * x * x),
                ]
            },
        ),
        (
            "neg-sub",
            |x| -(x - x.sq()),
            |x| -(x - x.sq()),
            |x| [x * x - x, 2.0 * x - 1.0, 2.0],
        ),
        (
            "apply",
            |x| x.apply(&(Arc::new(Cube) as Arc<dyn UnaryFn>)),
            |x| x.apply(&(Arc::new(Cube) as Arc<dyn UnaryFn>)),
            |x| [x * x * x, 3.0 * x * x, 6.0 * x],
        ),
        (
            "fmin lower",
            |x| x.fmin(Dual::cst(5.0)),
            |x| x.fmin(HyperDual::cst(5.0)),
            |x| [x, 1.0, 0.0],
        ),
        (
            "fmin upper",
            |x| x.fmin(Dual::cst(0.1)),
            |x| x.fmin(HyperDual::cst(0.1)),
            |_| [0.1, 0.0, 0.0],
        ),
        (
            "fmax",
            |x| x.sq().fmax(x),
            |x| x.sq().fmax(x),
            |x| {
                if x * x >= x {
                    [x * x, 2.0 * x, 2.0]
                } else {
                    [x, 1.0, 0.0]
                }
            },
        ),
        (
            "fmax other",
            |x| Dual::cst(9.0).fmax(x),
            |x| HyperDual::cst(9.0).fmax(x),
            |_| [9.0, 0.0, 0.0],
        ),
        (
            "select_pos +",
            |x| Dual::select_pos(x - 1.0, x.sq(), x.exp()),
            |x| HyperDual::select_pos(x - 1.0, x.sq(), x.exp()),
            |x| {
                if x > 1.0 {
                    [x * x, 2.0 * x, 2.0]
                } else {
                    [x.exp(), x.exp(), x.exp()]
                }
            },
        ),
        (
            "zero/one",
            |x| x * Dual::zero() + Dual::one(),
            |x| x * HyperDual::zero() + HyperDual::one(),
            |_| [1.0, 0.0, 0.0],
        ),
    ]
}

#[test]
fn dual_first_derivatives_match_analytic() {
    for x in [0.3, 0.77, 1.4, 2.5] {
        for (name, fd, _, exact) in cases() {
            let y = fd(Dual::var(x));
            let e = exact(x);
            assert!(
                close(y.re, e[0]),
                "{name} value at {x}: {} vs {}",
                y.re,
                e[0]
            );
            assert!(
                close(y.eps, e[1]),
                "{name} d/dx at {x}: {} vs {}",
                y.eps,
                e[1]
            );
            assert_eq!(y.value(), y.re);
        }
    }
}

#[test]
fn hyperdual_second_derivatives_match_analytic() {
    for x in [0.3, 0.77, 1.4, 2.5] {
        for (name, _, fh, exact) in cases() {
            let y = fh(HyperDual::var(x));
            let e = exact(x);
            assert!(close(y.re, e[0]), "{name} value at {x}");
            assert!(close(y.e1, e[1]), "{name} e1 at {x}: {} vs {}", y.e1, e[1]);
            assert!(close(y.e2, e[1]), "{name} e2 at {x}");
            assert!(
                close(y.e12, e[2]),
                "{name} e12 at {x}: {} vs {}",
                y.e12,
                e[2]
            );
        }
    }
}

#[test]
fn hyperdual_mixed_partial_of_two_variables() {
    // f(x, y) = sin(x y) + x² / y: ∂²f/∂x∂y = cos(xy) - xy sin(xy) - 2x / y².
    let (x0, y0) = (0.7, 1.3);
    let x = HyperDual::new(x0, 1.0, 0.0, 0.0);
    let y = HyperDual::new(y0, 0.0, 1.0, 0.0);
    let f = (x * y).sin() + x.sq() / y;
    let xy = x0 * y0;
    assert!(close(f.e1, y0 * xy.cos() + 2.0 * x0 / y0));
    assert!(close(f.e2, x0 * xy.cos() - x0 * x0 / (y0 * y0)));
    assert!(close(
        f.e12,
        xy.cos() - xy * xy.sin() - 2.0 * x0 / (y0 * y0)
    ));
}

#[test]
fn dual_product_and_quotient_rules() {
    let a = Dual::new(1.5, 0.25);
    let b = Dual::new(-0.5, 2.0);
    let p = a * b;
    assert!(close(p.eps, 0.25 * -0.5 + 1.5 * 2.0));
    let q = a / b;
    assert!(close(q.eps, (0.25 * -0.5 - 1.5 * 2.0) / 0.25));
    assert!(close((a - b).eps, -1.75));
    assert!(close((-a).eps, -0.25));
}

#[test]
fn dualvec_carries_independent_directions() {
    use stride_ad::DualVec;
    // f(x, y) = x² y + sin(y) / x: ∂f/∂x = 2xy - sin(y)/x², ∂f/∂y = x² + cos(y)/x.
    let (x0, y0) = (1.3, 0.4);
    let x = DualVec::<3>::var(x0, 0);
    let y = DualVec::<3>::var(y0, 1);
    let f = x.sq() * y + y.sin() / x - DualVec::cst(1.0);
    assert!(close(f.re, x0 * x0 * y0 + y0.sin() / x0 - 1.0));
    assert!(close(f.eps[0], 2.0 * x0 * y0 - y0.sin() / (x0 * x0)));
    assert!(close(f.eps[1], x0 * x0 + y0.cos() / x0));
    assert_eq!(f.eps[2], 0.0);
    let g = (x * 2.0 - 1.0).exp().fmax(y.tanh()).powf(1.5);
    let u = (2.0 * x0 - 1.0).exp();
    assert!(close(g.eps[0], 1.5 * u.sqrt() * 2.0 * u));
}
