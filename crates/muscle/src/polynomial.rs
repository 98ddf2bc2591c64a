//! Polynomial muscle–tendon geometry (FORMULATION 4): `l_MT(q)` as a polynomial in the
//! spanned coordinates, moment arms `r_j = −∂l_MT/∂q_j` from the analytic derivative of the
//! monomials, and lengthening velocity `v_MT = −Σ_j r_j q̇_j`.
//!
//! Evaluation uses power tables held in a preallocated [`PathWorkspace`]; nothing is
//! allocated per call.

use stride_ad::Scalar;
use stride_model::{CoordId, Model, PathPolynomial};

use crate::MuscleError;

/// A validated path polynomial in evaluation-friendly (flat) layout: the length polynomial
/// and, for each spanned coordinate, the polynomial of its moment arm, both stored as
/// offsets into a power table so that evaluation is a sum of products.
#[derive(Clone, Debug, PartialEq)]
pub struct PathPolynomialEval {
    coordinates: Vec<CoordId>,
    order: usize,
    n_terms: usize,
    /// Monomials of `l_MT`.
    length: Monomials,
    /// Monomials of `r_j = −∂l_MT/∂x_j`, one set per spanned coordinate.
    moment_arms: Vec<Monomials>,
}

/// A sum `Σ_k c_k Π_j pow[offsets[k n + j]]` over a power table laid out as
/// `pow[j (order + 1) + e] = x_j^e`.
#[derive(Clone, Debug, Default, PartialEq)]
struct Monomials {
    offsets: Vec<u16>,
    coefficients: Vec<f64>,
}

impl Monomials {
    /// Evaluates the sum for `N` factors per term (`N` = number of spanned coordinates).
    #[inline(always)]
    fn eval<T: Scalar, const N: usize>(&self, pow: &[T]) -> T {
        let mut sum = T::zero();
        for (off, &c) in self.offsets.chunks_exact(N).zip(&self.coefficients) {
            let mut prod = pow[off[0] as usize];
            for &o in &off[1..N] {
                prod *= pow[o as usize];
            }
            sum += prod * c;
        }
        sum
    }

    /// Evaluates the sum for a run-time number `n` of factors per term.
    fn eval_dyn<T: Scalar>(&self, pow: &[T], n: usize) -> T {
        let mut sum = T::zero();
        for (off, &c) in self.offsets.chunks_exact(n).zip(&self.coefficients) {
            let mut prod = pow[off[0] as usize];
            for &o in &off[1..] {
                prod *= pow[o as usize];
            }
            sum += prod * c;
        }
        sum
    }
}

impl PathPolynomialEval {
    /// Validates `poly` (of muscle index `muscle`, used in error messages) and flattens it.
    pub fn new(muscle: usize, poly: &PathPolynomial) -> Result<Self, MuscleError> {
        let err = |reason: String| MuscleError::InvalidPolynomial { muscle, reason };
        let n = poly.coordinates.len();
        if n == 0 {
            return Err(err("spans no coordinate".into()));
        }
        if poly.exponents.len() != poly.coefficients.len() {
            return Err(err(format!(
                "{} exponent tuples but {} coefficients",
                poly.exponents.len(),
                poly.coefficients.len()
            )));
        }
        for (i, c) in poly.coordinates.iter().enumerate() {
            if poly.coordinates[..i].contains(c) {
                return Err(err(format!("coordinate {c} listed twice")));
            }
        }
        let order = poly.order as usize;
        let stride = order + 1;
        if n * stride > u16::MAX as usize {
            return Err(err(format!(
                "{n} coordinates of order {order} exceed the supported power-table size"
            )));
        }
        for (k, e) in poly.exponents.iter().enumerate() {
            if e.len() != n {
                return Err(err(format!(
                    "exponent tuple {k} has {} entries for {n} coordinates",
                    e.len()
                )));
            }
            let total: usize = e.iter().map(|&x| x as usize).sum();
            if total > order {
                return Err(err(format!(
                    "exponent tuple {k} {e:?} has total degree {total} > order {order}"
                )));
            }
        }
        if let Some((k, c)) = poly
            .coefficients
            .iter()
            .enumerate()
            .find(|(_, c)| !c.is_finite())
        {
            return Err(err(format!("coefficient {k} is not finite ({c})")));
        }
        let offset = |j: usize, e: u8| (j * stride + e as usize) as u16;
        let mut length = Monomials::default();
        let mut moment_arms = vec![Monomials::default(); n];
        for (e, &c) in poly.exponents.iter().zip(&poly.coefficients) {
            length
                .offsets
                .extend(e.iter().enumerate().map(|(j, &ej)| offset(j, ej)));
            length.coefficients.push(c);
            // ∂/∂x_j of c Π x_i^{e_i} is c e_j x_j^{e_j − 1} Π_{i≠j} x_i^{e_i}; terms with
            // e_j = 0 contribute nothing and are left out.
            for (j, arm) in moment_arms.iter_mut().enumerate() {
                if e[j] == 0 {
                    continue;
                }
                arm.offsets.extend(e.iter().enumerate().map(|(i, &ei)| {
                    if i == j {
                        offset(i, ei - 1)
                    } else {
                        offset(i, ei)
                    }
                }));
                arm.coefficients.push(-c * e[j] as f64);
            }
        }
        Ok(Self {
            coordinates: poly.coordinates.clone(),
            order,
            n_terms: poly.coefficients.len(),
            length,
            moment_arms,
        })
    }

    /// Global indices of the spanned coordinates, in the order of the moment arms.
    pub fn coordinates(&self) -> &[CoordId] {
        &self.coordinates
    }
    /// Number of spanned coordinates.
    pub fn n_coordinates(&self) -> usize {
        self.coordinates.len()
    }
    /// Total polynomial order p.
    pub fn order(&self) -> usize {
        self.order
    }
    /// Number of monomials.
    pub fn n_terms(&self) -> usize {
        self.n_terms
    }

    /// Evaluates `l_MT` [m] and writes `r_j = −∂l_MT/∂x_j` [m] into `moment_arms` for the
    /// local coordinate values `x` [rad], using `pow` as the power table (length at least
    /// `n (order + 1)`). Slice lengths are the caller's responsibility.
    #[inline]
    fn eval_local<T: Scalar>(&self, x: &[T], pow: &mut [T], moment_arms: &mut [T]) -> T {
        let n = self.coordinates.len();
        let stride = self.order + 1;
        debug_assert!(x.len() == n && moment_arms.len() == n && pow.len() >= n * stride);
        for (j, &xj) in x.iter().enumerate() {
            let row = &mut pow[j * stride..(j + 1) * stride];
            row[0] = T::one();
            for e in 1..stride {
                row[e] = row[e - 1] * xj;
            }
        }
        match n {
            1 => self.eval_n::<T, 1>(pow, moment_arms),
            2 => self.eval_n::<T, 2>(pow, moment_arms),
            3 => self.eval_n::<T, 3>(pow, moment_arms),
            4 => self.eval_n::<T, 4>(pow, moment_arms),
            _ => {
                for (r, m) in moment_arms.iter_mut().zip(&self.moment_arms) {
                    *r = m.eval_dyn(pow, n);
                }
                self.length.eval_dyn(pow, n)
            }
        }
    }

    #[inline]
    fn eval_n<T: Scalar, const N: usize>(&self, pow: &[T], moment_arms: &mut [T]) -> T {
        for (r, m) in moment_arms.iter_mut().zip(&self.moment_arms) {
            *r = m.eval::<T, N>(pow);
        }
        self.length.eval::<T, N>(pow)
    }

    /// Evaluates `l_MT` [m] and `v_MT` [m s⁻¹] from the full coordinate and speed vectors
    /// `q` [rad], `q̇` [rad s⁻¹], writing the moment arms [m] of the spanned coordinates.
    pub fn evaluate<T: Scalar>(
        &self,
        q: &[T],
        qdot: &[T],
        ws: &mut PathWorkspace<T>,
        moment_arms: &mut [T],
    ) -> Result<(T, T), MuscleError> {
        let n = self.n_coordinates();
        check_len("moment arms", n, moment_arms.len())?;
        let needed = self.coordinates.iter().max().map_or(0, |c| c + 1);
        check_min("q", needed, q.len())?;
        check_min("qdot", needed, qdot.len())?;
        ws.ensure(n, self.order)?;
        for (x, &c) in ws.x.iter_mut().zip(&self.coordinates) {
            *x = q[c];
        }
        let PathWorkspace { x, pow } = ws;
        let l = self.eval_local(&x[..n], pow, moment_arms);
        let mut v = T::zero();
        for (r, &c) in moment_arms.iter().zip(&self.coordinates) {
            v -= *r * qdot[c];
        }
        Ok((l, v))
    }
}

fn check_len(what: &'static str, expected: usize, actual: usize) -> Result<(), MuscleError> {
    if expected == actual {
        Ok(())
    } else {
        Err(MuscleError::LengthMismatch {
            what,
            expected,
            actual,
        })
    }
}

fn check_min(what: &'static str, expected: usize, actual: usize) -> Result<(), MuscleError> {
    if actual >= expected {
        Ok(())
    } else {
        Err(MuscleError::LengthMismatch {
            what,
            expected,
            actual,
        })
    }
}

/// Preallocated scratch space (power tables) for polynomial evaluation on scalar type `T`.
#[derive(Clone, Debug)]
pub struct PathWorkspace<T> {
    x: Vec<T>,
    pow: Vec<T>,
}

impl<T: Scalar> PathWorkspace<T> {
    /// Workspace for polynomials spanning up to `max_coordinates` coordinates of order up to
    /// `max_order`.
    pub fn new(max_coordinates: usize, max_order: usize) -> Self {
        Self {
            x: vec![T::zero(); max_coordinates],
            pow: vec![T::zero(); max_coordinates * (max_order + 1)],
        }
    }
    /// Workspace sized for one polynomial.
    pub fn for_polynomial(p: &PathPolynomialEval) -> Self {
        Self::new(p.n_coordinates(), p.order())
    }
    /// Workspace sized for every polynomial of `paths`.
    pub fn for_paths(paths: &MusclePaths) -> Self {
        Self::new(paths.max_coordinates, paths.max_order)
    }
    fn ensure(&self, n: usize, order: usize) -> Result<(), MuscleError> {
        check_min("path workspace coordinates", n, self.x.len())?;
        check_min(
            "path workspace power table",
            n * (order + 1),
            self.pow.len(),
        )
    }
}

/// Geometry of all muscles of a model: one polynomial per muscle, evaluated at once.
#[derive(Clone, Debug, PartialEq)]
pub struct MusclePaths {
    polys: Vec<PathPolynomialEval>,
    /// `offsets[m]..offsets[m+1]` is muscle m's block in the flat moment-arm vector.
    offsets: Vec<usize>,
    n_coordinates: usize,
    max_coordinates: usize,
    max_order: usize,
}

impl MusclePaths {
    /// Builds the evaluator from a model; every muscle needs a path polynomial whose
    /// coordinates exist in the model.
    pub fn from_model(model: &Model) -> Result<Self, MuscleError> {
        if model.path_polynomials.len() != model.muscles.len() {
            return Err(MuscleError::LengthMismatch {
                what: "model.path_polynomials (one per muscle)",
                expected: model.muscles.len(),
                actual: model.path_polynomials.len(),
            });
        }
        let mut polys = Vec::with_capacity(model.muscles.len());
        for (m, p) in model.path_polynomials.iter().enumerate() {
            let p = p.as_ref().ok_or_else(|| MuscleError::InvalidPolynomial {
                muscle: m,
                reason: format!("muscle `{}` has no path polynomial", model.muscles[m].name),
            })?;
            polys.push(PathPolynomialEval::new(m, p)?);
        }
        Self::new(polys, model.coordinates.len())
    }

    /// Builds the evaluator from validated polynomials over `n_coordinates` model coordinates.
    pub fn new(polys: Vec<PathPolynomialEval>, n_coordinates: usize) -> Result<Self, MuscleError> {
        let mut offsets = Vec::with_capacity(polys.len() + 1);
        offsets.push(0);
        for (m, p) in polys.iter().enumerate() {
            if let Some(&c) = p.coordinates().iter().find(|&&c| c >= n_coordinates) {
                return Err(MuscleError::InvalidPolynomial {
                    muscle: m,
                    reason: format!("coordinate index {c} ≥ number of coordinates {n_coordinates}"),
                });
            }
            offsets.push(offsets[m] + p.n_coordinates());
        }
        let max_coordinates = polys.iter().map(|p| p.n_coordinates()).max().unwrap_or(0);
        let max_order = polys.iter().map(|p| p.order()).max().unwrap_or(0);
        Ok(Self {
            polys,
            offsets,
            n_coordinates,
            max_coordinates,
            max_order,
        })
    }

    /// Number of muscles.
    pub fn n_muscles(&self) -> usize {
        self.polys.len()
    }
    /// Length of the flat moment-arm vector (sum of spanned coordinates over muscles).
    pub fn n_moment_arms(&self) -> usize {
        *self.offsets.last().unwrap_or(&0)
    }
    /// Range of muscle `m`'s moment arms in the flat moment-arm vector.
    pub fn moment_arm_range(&self, m: usize) -> std::ops::Range<usize> {
        self.offsets[m]..self.offsets[m + 1]
    }
    /// Polynomial of muscle `m`.
    pub fn polynomial(&self, m: usize) -> &PathPolynomialEval {
        &self.polys[m]
    }

    /// Fills `lengths` (`l_MT` [m]), `velocities` (`v_MT` [m s⁻¹]) per muscle and the flat
    /// `moment_arms` [m] (muscle m's block: [`Self::moment_arm_range`], in the order of its
    /// polynomial's coordinates) from coordinates `q` [rad] and speeds `q̇` [rad s⁻¹].
    pub fn evaluate<T: Scalar>(
        &self,
        q: &[T],
        qdot: &[T],
        ws: &mut PathWorkspace<T>,
        lengths: &mut [T],
        velocities: &mut [T],
        moment_arms: &mut [T],
    ) -> Result<(), MuscleError> {
        check_min("q", self.n_coordinates, q.len())?;
        check_min("qdot", self.n_coordinates, qdot.len())?;
        check_len("muscle lengths", self.polys.len(), lengths.len())?;
        check_len("muscle velocities", self.polys.len(), velocities.len())?;
        check_len("moment arms", self.n_moment_arms(), moment_arms.len())?;
        ws.ensure(self.max_coordinates, self.max_order)?;
        let PathWorkspace { x, pow } = ws;
        for (m, p) in self.polys.iter().enumerate() {
            let n = p.n_coordinates();
            let arms = &mut moment_arms[self.offsets[m]..self.offsets[m + 1]];
            for (xj, &c) in x.iter_mut().zip(p.coordinates()) {
                *xj = q[c];
            }
            lengths[m] = p.eval_local(&x[..n], pow, arms);
            let mut v = T::zero();
            for (r, &c) in arms.iter().zip(p.coordinates()) {
                v -= *r * qdot[c];
            }
            velocities[m] = v;
        }
        Ok(())
    }
}
