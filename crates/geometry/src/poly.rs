//! Evaluating a fitted path polynomial (FORMULATION 4.2) at full model coordinates.

use stride_model::PathPolynomial;

/// Muscle–tendon length [m] of polynomial `p` at model coordinates `q` [rad or m].
pub fn polynomial_length(p: &PathPolynomial, q: &[f64]) -> f64 {
    p.exponents
        .iter()
        .zip(&p.coefficients)
        .map(|(e, c)| {
            c * e
                .iter()
                .zip(&p.coordinates)
                .map(|(k, &ci)| q[ci].powi(i32::from(*k)))
                .product::<f64>()
        })
        .sum()
}

/// Moment arm `−∂l/∂q_j` [m] of polynomial `p` about its `j`-th coordinate at `q`.
pub fn polynomial_moment_arm(p: &PathPolynomial, q: &[f64], j: usize) -> f64 {
    let mut d = 0.0;
    for (e, c) in p.exponents.iter().zip(&p.coefficients) {
        if e[j] == 0 {
            continue;
        }
        let mut term = c * f64::from(e[j]);
        for (i, (k, &ci)) in e.iter().zip(&p.coordinates).enumerate() {
            let k = i32::from(*k) - i32::from(i == j);
            term *= q[ci].powi(k);
        }
        d += term;
    }
    -d
}
