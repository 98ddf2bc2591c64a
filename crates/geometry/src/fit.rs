//! Least-squares fit of a polynomial muscle–tendon length to sampled lengths and moment
//! arms, with order selection (FORMULATION 4.4 steps 2–3).

use crate::basis::MonomialBasis;
use crate::error::GeometryError;
use crate::lsq::solve_least_squares;
use faer::Mat;
use stride_model::{CoordId, PathPolynomial};

/// Sampled path geometry of one muscle over the coordinates it spans.
#[derive(Clone, Debug, Default)]
pub struct MuscleSamples {
    /// Spanned coordinates (model indices), in polynomial order.
    pub coords: Vec<CoordId>,
    /// Coordinate values, row-major `n_samples × coords.len()` [rad or m].
    pub x: Vec<f64>,
    /// Muscle–tendon length at each sample [m].
    pub length: Vec<f64>,
    /// Moment arms `−∂l/∂q` about each spanned coordinate, row-major
    /// `n_samples × coords.len()` [m].
    pub moment_arms: Vec<f64>,
}

impl MuscleSamples {
    /// Number of samples (poses).
    pub fn n_samples(&self) -> usize {
        self.length.len()
    }
}

/// Settings of the order selection.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FitOptions {
    /// First polynomial order tried (3 in the paper).
    pub min_order: u32,
    /// Largest polynomial order (9 in the paper); accepted whatever its accuracy.
    pub max_order: u32,
    /// Accuracy target for the RMS length error and each RMS moment-arm error [m] (3 mm).
    pub tolerance: f64,
}

impl Default for FitOptions {
    /// The settings of the paper: orders 3 to 9, 3 mm.
    fn default() -> Self {
        Self {
            min_order: 3,
            max_order: 9,
            tolerance: 3e-3,
        }
    }
}

/// The polynomial retained for one muscle and its accuracy on the fitting samples.
#[derive(Clone, Debug, PartialEq)]
pub struct PolynomialFit {
    /// The fitted polynomial (RMS errors filled in).
    pub polynomial: PathPolynomial,
    /// RMS error of the length [m].
    pub rms_length: f64,
    /// RMS error of the moment arm about each spanned coordinate [m].
    pub rms_moment_arms: Vec<f64>,
    /// Both RMS criteria are within the tolerance.
    pub meets_tolerance: bool,
}

impl PolynomialFit {
    /// Largest RMS moment-arm error over the spanned coordinates [m] (0 if none).
    pub fn max_rms_moment_arm(&self) -> f64 {
        self.rms_moment_arms.iter().fold(0.0, |a, &b| a.max(b))
    }
}

/// Fits the polynomial of one fixed `order` to the samples: one ordinary least-squares
/// system stacking the length rows and the moment-arm rows of every spanned coordinate.
pub fn fit_order(samples: &MuscleSamples, order: u32) -> Result<PolynomialFit, GeometryError> {
    let n = samples.coords.len();
    let s = samples.n_samples();
    if samples.x.len() != s * n || samples.moment_arms.len() != s * n {
        return Err(GeometryError::SampleShape {
            what: format!(
                "{} samples over {} coordinates but {} coordinate values and {} moment arms",
                s,
                n,
                samples.x.len(),
                samples.moment_arms.len()
            ),
        });
    }
    let basis = MonomialBasis::new(n, order);
    let k = basis.len();
    if s * (n + 1) < k {
        return Err(GeometryError::TooFewSamples {
            samples: s,
            unknowns: k,
            order,
        });
    }
    let rows = s * (n + 1);
    let mut a = Mat::<f64>::zeros(rows, k);
    let mut b = vec![0.0; rows];
    let mut phi = vec![0.0; k];
    for i in 0..s {
        let x = &samples.x[i * n..(i + 1) * n];
        basis.eval_into(x, &mut phi);
        for (c, v) in phi.iter().enumerate() {
            a[(i, c)] = *v;
        }
        b[i] = samples.length[i];
        for j in 0..n {
            basis.deriv_into(x, j, &mut phi);
            let r = s * (j + 1) + i;
            for (c, v) in phi.iter().enumerate() {
                a[(r, c)] = -*v;
            }
            b[r] = samples.moment_arms[i * n + j];
        }
    }
    let coefficients = solve_least_squares(&mut a, &b);
    let (rms_length, rms_moment_arms) = rms_errors(&basis, &coefficients, samples);
    let max_r = rms_moment_arms.iter().fold(0.0f64, |a, &b| a.max(b));
    Ok(PolynomialFit {
        polynomial: PathPolynomial {
            coordinates: samples.coords.clone(),
            order,
            exponents: basis.exponents.clone(),
            coefficients,
            rmse_length: Some(rms_length),
            rmse_moment_arm: Some(max_r),
        },
        rms_length,
        rms_moment_arms,
        meets_tolerance: false,
    })
}

/// RMS errors of a polynomial against samples: (length [m], moment arm per coordinate [m]).
pub fn rms_errors(basis: &MonomialBasis, c: &[f64], samples: &MuscleSamples) -> (f64, Vec<f64>) {
    let n = samples.coords.len();
    let s = samples.n_samples().max(1);
    let mut el = 0.0;
    let mut er = vec![0.0; n];
    for i in 0..samples.n_samples() {
        let x = &samples.x[i * n..(i + 1) * n];
        el += (basis.value(c, x) - samples.length[i]).powi(2);
        for (j, e) in er.iter_mut().enumerate() {
            *e += (basis.moment_arm(c, x, j) - samples.moment_arms[i * n + j]).powi(2);
        }
    }
    (
        (el / s as f64).sqrt(),
        er.into_iter().map(|e| (e / s as f64).sqrt()).collect(),
    )
}

/// Fits orders `min_order..=max_order` in turn and returns the first whose RMS length
/// error and largest RMS moment-arm error are both within the tolerance, or the
/// `max_order` fit (flagged `meets_tolerance = false`) when none is.
pub fn fit_polynomial(
    samples: &MuscleSamples,
    options: &FitOptions,
) -> Result<PolynomialFit, GeometryError> {
    if options.min_order > options.max_order {
        return Err(GeometryError::Options {
            what: format!(
                "minimum order {} exceeds maximum order {}",
                options.min_order, options.max_order
            ),
        });
    }
    let mut order = options.min_order;
    loop {
        let mut fit = fit_order(samples, order)?;
        fit.meets_tolerance =
            fit.rms_length <= options.tolerance && fit.max_rms_moment_arm() <= options.tolerance;
        if fit.meets_tolerance || order >= options.max_order {
            return Ok(fit);
        }
        order += 1;
    }
}
