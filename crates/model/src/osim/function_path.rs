//! OpenSim's `FunctionBasedPath`: a muscle–tendon length given as a function of
//! coordinates. A `MultivariatePolynomialFunction` length is read as the muscle's own
//! [`PathPolynomial`] (lengths and moment arms −∂l/∂q as OpenSim computes them, no fit).

use super::xml::{child, elements, last_component, name_of, report, tag, text, Ctx, El};
use super::OsimError;
use crate::model::{Model, PathPolynomial};

/// The length polynomial of the `FunctionBasedPath` `fbp` of the muscle `owner`.
pub(crate) fn function_based_path(
    ctx: &Ctx,
    owner: El,
    fbp: El,
    model: &mut Model,
) -> Result<PathPolynomial, OsimError> {
    let who = format!("FunctionBasedPath of `{}`", name_of(owner));
    let cel = ctx.req(fbp, "coordinate_paths")?;
    let coordinates = text(cel)
        .split_whitespace()
        .map(|p| {
            model
                .coordinate_index(last_component(p))
                .ok_or_else(|| ctx.err(cel, format!("{who}: unknown coordinate `{p}`")))
        })
        .collect::<Result<Vec<_>, _>>()?;
    let lf = ctx.req(fbp, "length_function")?;
    let f = elements(lf)
        .next()
        .ok_or_else(|| ctx.err(lf, format!("{who}: length_function holds no function")))?;
    if tag(f) != "MultivariatePolynomialFunction" {
        return Err(ctx.err(
            f,
            format!(
                "{who}: a length function of type `{}` is not supported (supported: \
                 MultivariatePolynomialFunction)",
                tag(f)
            ),
        ));
    }
    let dimension = count(ctx, f, "dimension")?;
    let order = count(ctx, f, "order")?;
    if dimension != coordinates.len() {
        return Err(ctx.err(
            f,
            format!(
                "{who}: the polynomial has {dimension} coordinates (dimension) but the path \
                 names {} (coordinate_paths)",
                coordinates.len()
            ),
        ));
    }
    let exponents = opensim_exponents(dimension, order);
    let cel = ctx.req(f, "coefficients")?;
    let coefficients = ctx.vec_of(cel)?;
    if coefficients.len() != exponents.len() {
        return Err(ctx.err(
            cel,
            format!(
                "{who}: a polynomial of dimension {dimension} and order {order} has {} \
                 coefficients, found {}",
                exponents.len(),
                coefficients.len()
            ),
        ));
    }
    for t in ["moment_arm_functions", "lengthening_speed_function"] {
        if child(fbp, t).is_some_and(|e| elements(e).next().is_some()) {
            report(
                ctx,
                model,
                owner,
                format!("{t} of the FunctionBasedPath is not used: stride differentiates the length function"),
            );
        }
    }
    Ok(PathPolynomial {
        coordinates,
        order: order as u32,
        exponents,
        coefficients,
        rmse_length: None,
        rmse_moment_arm: None,
    })
}

/// A small non-negative integer child (dimension, order).
fn count(ctx: &Ctx, f: El, t: &str) -> Result<usize, OsimError> {
    let el = ctx.req(f, t)?;
    text(el)
        .parse::<usize>()
        .ok()
        .filter(|n| *n <= 12)
        .ok_or_else(|| {
            ctx.err(
                el,
                format!("expected an integer from 0 to 12, found `{}`", text(el)),
            )
        })
}

/// The exponent tuples of a `MultivariatePolynomialFunction` of `dimension` variables and
/// total `order`, in OpenSim's coefficient order: every tuple with sum ≤ order, in
/// lexicographic order of (e₀, e₁, …) (the first variable's exponent changes slowest).
pub(crate) fn opensim_exponents(dimension: usize, order: usize) -> Vec<Vec<u8>> {
    let mut out = Vec::new();
    let mut e = vec![0u8; dimension];
    fill(&mut e, 0, order, &mut out);
    out
}

/// Append every completion of `e[..k]` (with `left` order to spend) in lexicographic order.
fn fill(e: &mut Vec<u8>, k: usize, left: usize, out: &mut Vec<Vec<u8>>) {
    if k == e.len() {
        out.push(e.clone());
        return;
    }
    for p in 0..=left {
        e[k] = p as u8;
        fill(e, k + 1, left - p, out);
    }
    e[k] = 0;
}

#[cfg(test)]
mod tests {
    use super::opensim_exponents;

    /// The orders OpenSim 4.6 gives (`getTermValues` at prime arguments, factored).
    #[test]
    fn exponent_order_is_opensims() {
        let v = |x: &[&[u8]]| x.iter().map(|t| t.to_vec()).collect::<Vec<_>>();
        assert_eq!(opensim_exponents(1, 3), v(&[&[0], &[1], &[2], &[3]]));
        assert_eq!(
            opensim_exponents(2, 2),
            v(&[&[0, 0], &[0, 1], &[0, 2], &[1, 0], &[1, 1], &[2, 0]])
        );
        assert_eq!(
            opensim_exponents(3, 2),
            v(&[
                &[0, 0, 0],
                &[0, 0, 1],
                &[0, 0, 2],
                &[0, 1, 0],
                &[0, 1, 1],
                &[0, 2, 0],
                &[1, 0, 0],
                &[1, 0, 1],
                &[1, 1, 0],
                &[2, 0, 0]
            ])
        );
        assert_eq!(opensim_exponents(2, 3).len(), 10);
        assert_eq!(opensim_exponents(2, 3)[6], vec![1, 2]);
    }
}
