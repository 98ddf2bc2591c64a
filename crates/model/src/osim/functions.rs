//! OpenSim function elements (`LinearFunction`, `Constant`, `SimmSpline`,
//! `NaturalCubicSpline`, `PiecewiseLinearFunction`, `PolynomialFunction`,
//! `MultiplierFunction`) → [`Function`].

use super::xml::{elements, tag, Ctx, El};
use super::OsimError;
use crate::model::Function;

/// Parse the single function element inside a container such as `<function>` or
/// `<x_location>`.
pub(crate) fn parse_function_in(ctx: &Ctx, container: El) -> Result<Function, OsimError> {
    let mut it = elements(container);
    let f = it
        .next()
        .ok_or_else(|| ctx.err(container, "expected a function element inside"))?;
    parse_function(ctx, f)
}

/// Parse one OpenSim function element.
pub(crate) fn parse_function(ctx: &Ctx, f: El) -> Result<Function, OsimError> {
    match tag(f) {
        "Constant" => Ok(Function::Constant(ctx.req_f64(f, "value")?)),
        "LinearFunction" => {
            let c = ctx.req(f, "coefficients")?;
            let v = ctx.vec_of(c)?;
            if v.len() != 2 {
                return Err(ctx.err(
                    c,
                    format!(
                        "expected 2 coefficients (slope, intercept), found {}",
                        v.len()
                    ),
                ));
            }
            Ok(Function::Linear {
                slope: v[0],
                intercept: v[1],
            })
        }
        // OpenSim 4 registers `NaturalCubicSpline` as another name of `SimmSpline` (a
        // file's NaturalCubicSpline evaluates as a SimmSpline there).
        "SimmSpline" | "NaturalCubicSpline" => {
            let (x, y) = knots(ctx, f)?;
            Ok(Function::SimmSpline { x, y })
        }
        "PiecewiseLinearFunction" => {
            let (x, y) = knots(ctx, f)?;
            Ok(Function::PiecewiseLinear { x, y })
        }
        "PolynomialFunction" => {
            let c = ctx.vec_of(ctx.req(f, "coefficients")?)?;
            if c.is_empty() {
                return Err(ctx.missing(f, "coefficients"));
            }
            Ok(Function::Polynomial { coefficients: c })
        }
        "MultiplierFunction" => {
            let scale = ctx.opt_f64(f, "scale", 1.0)?;
            let inner = ctx.req(f, "function")?;
            Ok(Function::Multiplier {
                scale,
                function: Box::new(parse_function_in(ctx, inner)?),
            })
        }
        other => {
            // A function type stride cannot evaluate would silently change the mechanics.
            Err(ctx.err(
                f,
                format!(
                    "unsupported function type `{other}` (supported: Constant, LinearFunction, \
                     SimmSpline, NaturalCubicSpline, PiecewiseLinearFunction, \
                     PolynomialFunction, MultiplierFunction)"
                ),
            ))
        }
    }
}

/// Knots `x`, `y` of a spline or piecewise-linear element: equal counts, at least two,
/// `x` strictly increasing.
fn knots(ctx: &Ctx, f: El) -> Result<(Vec<f64>, Vec<f64>), OsimError> {
    let xn = ctx.req(f, "x")?;
    let x = ctx.vec_of(xn)?;
    let y = ctx.vec_of(ctx.req(f, "y")?)?;
    if x.len() != y.len() || x.len() < 2 {
        return Err(ctx.err(
            f,
            format!(
                "`{}` needs as many y as x values (and at least two): {} x, {} y",
                tag(f),
                x.len(),
                y.len()
            ),
        ));
    }
    if x.windows(2).any(|w| w[1] <= w[0]) {
        return Err(ctx.err(xn, "knots x must be strictly increasing"));
    }
    Ok((x, y))
}

/// Whether an element tag names an OpenSim function type.
pub(crate) fn is_function_tag(t: &str) -> bool {
    t.ends_with("Function") || t.ends_with("Spline") || t == "Constant"
}
