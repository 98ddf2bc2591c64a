//! Radau IIA collocation of degree 3 (FORMULATION section 8.2), computed from the
//! collocation points rather than tabulated.

/// Collocation points τ_0 = 0 and the three Radau points in [0, 1].
pub fn points() -> [f64; 4] {
    let s6 = 6f64.sqrt();
    [0.0, (4.0 - s6) / 10.0, (4.0 + s6) / 10.0, 1.0]
}

/// The Lagrange basis polynomial ℓ_r through the nodes `nodes` evaluated at `t`.
fn basis(nodes: &[f64], r: usize, t: f64) -> f64 {
    (0..nodes.len())
        .filter(|&k| k != r)
        .map(|k| (t - nodes[k]) / (nodes[r] - nodes[k]))
        .product()
}

/// The Lagrange basis polynomial ℓ_r through `points()` evaluated at `t`.
fn lagrange(r: usize, t: f64) -> f64 {
    basis(&points(), r, t)
}

/// Derivative of ℓ_r at `t`.
fn lagrange_derivative(r: usize, t: f64) -> f64 {
    let p = points();
    let mut sum = 0.0;
    for k in 0..4 {
        if k == r {
            continue;
        }
        let mut term = 1.0 / (p[r] - p[k]);
        for l in 0..4 {
            if l != r && l != k {
                term *= (t - p[l]) / (p[r] - p[l]);
            }
        }
        sum += term;
    }
    sum
}

/// Collocation matrix `C[r][j] = ℓ_r'(τ_j)` for r = 0..3 and j = 1..3 (stored at j − 1).
pub fn collocation_matrix() -> [[f64; 3]; 4] {
    let p = points();
    let mut c = [[0.0; 3]; 4];
    for (r, row) in c.iter_mut().enumerate() {
        for j in 1..4 {
            row[j - 1] = lagrange_derivative(r, p[j]);
        }
    }
    c
}

/// Weights of the four state samples of an interval (at `points()`) in the value of its
/// cubic state polynomial at local time `t` (0 at the interval's start, 1 at its end).
pub fn state_weights(t: f64) -> [f64; 4] {
    [0, 1, 2, 3].map(|r| lagrange(r, t))
}

/// Weights of the three collocation-point samples of an interval (at `points()[1..]`) in the
/// value at local time `t` of the quadratic through them (the derivative of a cubic state
/// polynomial is such a quadratic).
pub fn collocation_weights(t: f64) -> [f64; 3] {
    let p = points();
    [0, 1, 2].map(|r| basis(&p[1..], r, t))
}

/// Quadrature weights `B_j = ∫₀¹ ℓ_j` for j = 1..3 (B_0 = 0 for Radau).
pub fn quadrature_weights() -> [f64; 3] {
    // Gauss–Legendre with 3 nodes integrates the cubic ℓ_j exactly.
    let g = [
        (-(0.6f64).sqrt(), 5.0 / 9.0),
        (0.0, 8.0 / 9.0),
        ((0.6f64).sqrt(), 5.0 / 9.0),
    ];
    let mut b = [0.0; 3];
    for (j, bj) in b.iter_mut().enumerate() {
        *bj = g
            .iter()
            .map(|&(x, w)| 0.5 * w * lagrange(j + 1, 0.5 * (x + 1.0)))
            .sum();
    }
    b
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn coefficients_match_the_published_values() {
        let c = collocation_matrix();
        let expected = [
            [-4.139387691339811, 1.739387691339813, -3.0],
            [3.224744871391587, -3.567840084690404, 5.531972647421812],
            [1.167840084690406, 0.775255128608411, -7.531972647421811],
            [-0.253197264742181, 1.053197264742181, 5.0],
        ];
        for r in 0..4 {
            for j in 0..3 {
                assert!((c[r][j] - expected[r][j]).abs() < 1e-12, "C[{r}][{j}]");
            }
        }
        let b = quadrature_weights();
        let eb = [0.376403062700467, 0.512485826188421, 0.111111111111111];
        for j in 0..3 {
            assert!((b[j] - eb[j]).abs() < 1e-14);
        }
        let p = points();
        assert!((p[1] - 0.155051025721682).abs() < 1e-15);
        assert!((p[2] - 0.644948974278318).abs() < 1e-15);
    }

    #[test]
    fn collocation_differentiates_cubics_exactly() {
        // x(τ) = τ³ − 2τ + 1 sampled at the points: Σ_r C[r][j] x_r = x'(τ_j).
        let p = points();
        let c = collocation_matrix();
        for j in 1..4 {
            let d: f64 = (0..4)
                .map(|r| c[r][j - 1] * (p[r].powi(3) - 2.0 * p[r] + 1.0))
                .sum();
            assert!((d - (3.0 * p[j] * p[j] - 2.0)).abs() < 1e-12);
        }
    }
}
