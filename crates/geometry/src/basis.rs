//! Monomial basis of the polynomial muscle–tendon geometry (FORMULATION 4.2).
//!
//! For `n` spanned coordinates `(x_1..x_n)` [rad or m] and total order `p`, the basis holds
//! every monomial `x_1^e_1 … x_n^e_n` with `e_1 + … + e_n ≤ p`, enumerated
//! lexicographically with `e_1` outermost (slowest varying). This is the coefficient
//! order of the reference polynomial files.

/// The monomials of total degree ≤ `order` over `n_coords` coordinates, in file order.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct MonomialBasis {
    /// Number of coordinates the monomials are functions of.
    pub n_coords: usize,
    /// Largest total degree.
    pub order: u32,
    /// Exponent tuple of each monomial (one exponent per coordinate), in coefficient order.
    pub exponents: Vec<Vec<u8>>,
}

/// Number of monomials of total degree ≤ `order` in `n` variables: binomial(n + order, n).
pub fn basis_size(n: usize, order: u32) -> usize {
    let p = order as usize;
    // binomial(n + p, n) computed incrementally (exact in integers).
    let mut c: usize = 1;
    for k in 1..=n {
        c = c * (p + k) / k;
    }
    c
}

impl MonomialBasis {
    /// Builds the basis of `n_coords` coordinates and total order `order`.
    pub fn new(n_coords: usize, order: u32) -> Self {
        let mut exponents = Vec::with_capacity(basis_size(n_coords, order));
        let mut current = vec![0u8; n_coords];
        enumerate(0, order, &mut current, &mut exponents);
        Self {
            n_coords,
            order,
            exponents,
        }
    }

    /// Builds a basis from an explicit exponent list (e.g. read from a file).
    pub fn from_exponents(n_coords: usize, exponents: Vec<Vec<u8>>) -> Self {
        let order = exponents
            .iter()
            .map(|e| e.iter().map(|&x| x as u32).sum::<u32>())
            .max()
            .unwrap_or(0);
        Self {
            n_coords,
            order,
            exponents,
        }
    }

    /// Number of monomials (= number of coefficients).
    pub fn len(&self) -> usize {
        self.exponents.len()
    }

    /// True when the basis has no monomial.
    pub fn is_empty(&self) -> bool {
        self.exponents.is_empty()
    }

    /// Values of all monomials at `x` (length `n_coords`) written into `out` (length `len()`).
    pub fn eval_into(&self, x: &[f64], out: &mut [f64]) {
        for (o, e) in out.iter_mut().zip(&self.exponents) {
            let mut v = 1.0;
            for (xi, &ei) in x.iter().zip(e) {
                v *= xi.powi(ei as i32);
            }
            *o = v;
        }
    }

    /// Partial derivatives `∂φ_k/∂x_j` of all monomials at `x` written into `out`
    /// (length `len()`); terms with `e_j = 0` are exactly 0.
    pub fn deriv_into(&self, x: &[f64], j: usize, out: &mut [f64]) {
        for (o, e) in out.iter_mut().zip(&self.exponents) {
            if e[j] == 0 {
                *o = 0.0;
                continue;
            }
            let mut v = e[j] as f64;
            for (i, (xi, &ei)) in x.iter().zip(e).enumerate() {
                let p = if i == j { ei as i32 - 1 } else { ei as i32 };
                v *= xi.powi(p);
            }
            *o = v;
        }
    }

    /// Polynomial value `Σ_k c_k φ_k(x)` [m] for coefficients `c`.
    pub fn value(&self, c: &[f64], x: &[f64]) -> f64 {
        self.exponents
            .iter()
            .zip(c)
            .map(|(e, ck)| {
                ck * x
                    .iter()
                    .zip(e)
                    .map(|(xi, &ei)| xi.powi(ei as i32))
                    .product::<f64>()
            })
            .sum()
    }

    /// Moment arm `−∂l/∂x_j` [m] of the polynomial with coefficients `c` at `x`.
    pub fn moment_arm(&self, c: &[f64], x: &[f64], j: usize) -> f64 {
        let mut s = 0.0;
        for (e, ck) in self.exponents.iter().zip(c) {
            if e[j] == 0 {
                continue;
            }
            let mut v = e[j] as f64;
            for (i, (xi, &ei)) in x.iter().zip(e).enumerate() {
                let p = if i == j { ei as i32 - 1 } else { ei as i32 };
                v *= xi.powi(p);
            }
            s += ck * v;
        }
        -s
    }
}

/// Appends all exponent tuples of coordinates `k..` with total degree ≤ `budget`.
fn enumerate(k: usize, budget: u32, current: &mut Vec<u8>, out: &mut Vec<Vec<u8>>) {
    if k == current.len() {
        out.push(current.clone());
        return;
    }
    for e in 0..=budget {
        current[k] = e as u8;
        enumerate(k + 1, budget - e, current, out);
    }
    current[k] = 0;
}
