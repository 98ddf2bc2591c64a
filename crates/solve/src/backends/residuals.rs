//! Final optimality residuals recomputed from the unscaled problem, identical for every
//! backend: constraint violation (bounds and constraints) and dual infeasibility
//! ‖∇f + Jᵀλ − z_l + z_u‖∞ (IPOPT sign convention).

use crate::nlp::{Bounds, EvalError, Nlp, Sparsity};

/// Unscaled primal and dual residuals at a point, in the problem's own units.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Residuals {
    /// Max-norm violation of the variable bounds and of the constraint bounds.
    pub constraint_violation: f64,
    /// Max-norm of the Lagrangian gradient ∇f + Jᵀλ − z_l + z_u.
    pub dual_infeasibility: f64,
}

/// Max-norm by which `v` leaves the interval `[lo, up]` componentwise (0 if inside).
pub fn bound_violation(v: &[f64], lo: &[f64], up: &[f64]) -> f64 {
    v.iter()
        .zip(lo.iter().zip(up))
        .map(|(&v, (&l, &u))| (l - v).max(v - u).max(0.0))
        .fold(0.0, f64::max)
}

/// Computes the [`Residuals`] of `nlp` at `x` with multipliers `lambda`, `z_l`, `z_u`.
#[allow(clippy::too_many_arguments)]
pub fn residuals(
    nlp: &dyn Nlp,
    bounds: &Bounds,
    jacobian: &Sparsity,
    x: &[f64],
    lambda: &[f64],
    z_l: &[f64],
    z_u: &[f64],
) -> Result<Residuals, EvalError> {
    let (n, m) = (nlp.n(), nlp.m());
    let mut c = vec![0.0; m];
    nlp.constraints(x, &mut c)?;
    let constraint_violation = bound_violation(x, &bounds.x_l, &bounds.x_u).max(bound_violation(
        &c,
        &bounds.g_l,
        &bounds.g_u,
    ));
    let mut grad = vec![0.0; n];
    nlp.gradient(x, &mut grad)?;
    let mut jv = vec![0.0; jacobian.nnz()];
    nlp.jacobian_values(x, &mut jv)?;
    for ((&r, &col), &v) in jacobian.rows.iter().zip(&jacobian.cols).zip(&jv) {
        grad[col] += v * lambda[r];
    }
    let dual_infeasibility = (0..n)
        .map(|i| (grad[i] - z_l[i] + z_u[i]).abs())
        .fold(0.0, f64::max);
    Ok(Residuals {
        constraint_violation,
        dual_infeasibility,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bound_violation_is_the_largest_excursion() {
        let v = [0.5, 3.0, -2.0];
        let lo = [0.0, 0.0, -1.0];
        let up = [1.0, 2.5, f64::INFINITY];
        assert_eq!(bound_violation(&v, &lo, &up), 1.0);
        assert_eq!(bound_violation(&[0.5], &[0.0], &[1.0]), 0.0);
    }
}
