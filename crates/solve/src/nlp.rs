//! The nonlinear-program abstraction.
//!
//! An [`Nlp`] describes
//!
//! ```text
//!     minimise f(x)   subject to   x_l <= x <= x_u,   g_l <= c(x) <= g_u
//! ```
//!
//! with `n` variables and `m` constraints (equality where `g_l == g_u`, ±∞ allowed for
//! absent bounds). Derivatives are sparse with a fixed pattern declared once: the constraint
//! Jacobian in coordinate (COO) form and the Hessian of the Lagrangian
//! `L = obj_factor * f(x) + Σ_i lambda_i c_i(x)` as its lower triangle (row >= col).
//!
//! The module also provides validation helpers ([`validate_bounds`], [`validate_sparsity`],
//! [`check_finite`]) that turn malformed problems into clear errors, and a finite-difference
//! derivative checker ([`check_derivatives`]) usable with any [`Nlp`].
// Index loops over several parallel arrays are clearer than zipped iterators here.
#![allow(clippy::needless_range_loop)]

use thiserror::Error;

/// Which problem function an evaluation error or check refers to.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum NlpFunction {
    /// The objective f(x).
    Objective,
    /// The objective gradient ∇f(x).
    Gradient,
    /// The constraint values c(x).
    Constraints,
    /// The nonzero values of the constraint Jacobian.
    Jacobian,
    /// The nonzero values of the Lagrangian Hessian (lower triangle).
    Hessian,
}

impl std::fmt::Display for NlpFunction {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let s = match self {
            NlpFunction::Objective => "objective",
            NlpFunction::Gradient => "objective gradient",
            NlpFunction::Constraints => "constraints",
            NlpFunction::Jacobian => "constraint Jacobian",
            NlpFunction::Hessian => "Lagrangian Hessian",
        };
        f.write_str(s)
    }
}

/// An error raised while evaluating a problem function at a given point.
#[derive(Debug, Clone, Error, PartialEq)]
pub enum EvalError {
    /// A function produced NaN or ±∞ at entry `index` (for the objective, index 0).
    #[error("{function} is not finite at entry {index} (value {value})")]
    NonFinite {
        /// The function that produced the value.
        function: NlpFunction,
        /// Index of the offending entry (constraint row, variable, or nonzero position).
        index: usize,
        /// The offending value.
        value: f64,
    },
    /// The problem could not evaluate a function at this point (free-form reason).
    #[error("{function} could not be evaluated: {reason}")]
    Failed {
        /// The function that failed.
        function: NlpFunction,
        /// Why it failed.
        reason: String,
    },
}

/// A fixed sparsity pattern in coordinate form: entry `k` sits at `(rows[k], cols[k])`.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct Sparsity {
    /// Row index of each nonzero.
    pub rows: Vec<usize>,
    /// Column index of each nonzero.
    pub cols: Vec<usize>,
}

impl Sparsity {
    /// A pattern from row and column index lists (same length).
    pub fn new(rows: Vec<usize>, cols: Vec<usize>) -> Self {
        Sparsity { rows, cols }
    }

    /// Number of structural nonzeros.
    pub fn nnz(&self) -> usize {
        self.rows.len()
    }

    /// Appends one nonzero at `(row, col)` and returns its position in the value array.
    pub fn push(&mut self, row: usize, col: usize) -> usize {
        self.rows.push(row);
        self.cols.push(col);
        self.rows.len() - 1
    }
}

/// The chain (collocation) structure of a problem's variables, for fill-reducing orderings
/// of the KKT matrix.
///
/// The variables of block `k` (e.g. one mesh interval's states and controls) appear in
/// constraints and Hessian entries together with those of blocks `k-1`, `k`, `k+1` and with
/// the `global_variables` (e.g. the final time) only; constraints joining distant blocks
/// (periodicity) are allowed and are recognised from the Jacobian. Variables in no list are
/// treated as global.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct BlockStructure {
    /// Variable indices of each block, in chain order.
    pub blocks: Vec<Vec<usize>>,
    /// Variables coupling to every block (e.g. final time).
    pub global_variables: Vec<usize>,
}

/// A smooth nonlinear program with sparse first and second derivatives.
///
/// All slice arguments have the natural lengths: `x`, `x_l`, `x_u`, gradient: `n()`;
/// `c`, `g_l`, `g_u`, `lambda`: `m()`; Jacobian/Hessian values: the `nnz()` of the
/// corresponding structure. Structures must not change between calls.
pub trait Nlp: Sync {
    /// Number of variables.
    fn n(&self) -> usize;
    /// Number of constraints.
    fn m(&self) -> usize;
    /// Writes the variable bounds and the constraint bounds (±∞ for absent; equality where
    /// `g_l[i] == g_u[i]`).
    fn bounds(&self, x_l: &mut [f64], x_u: &mut [f64], g_l: &mut [f64], g_u: &mut [f64]);
    /// Writes the initial guess.
    fn initial_point(&self, x: &mut [f64]);
    /// The objective value f(x).
    fn objective(&self, x: &[f64]) -> Result<f64, EvalError>;
    /// Writes the objective gradient ∇f(x) (dense, length n).
    fn gradient(&self, x: &[f64], grad: &mut [f64]) -> Result<(), EvalError>;
    /// Writes the constraint values c(x) (length m).
    fn constraints(&self, x: &[f64], c: &mut [f64]) -> Result<(), EvalError>;
    /// The fixed nonzero pattern of the constraint Jacobian ∂c/∂x (m × n).
    fn jacobian_structure(&self) -> Sparsity;
    /// Writes the Jacobian nonzeros in the order of [`Nlp::jacobian_structure`].
    fn jacobian_values(&self, x: &[f64], vals: &mut [f64]) -> Result<(), EvalError>;
    /// The fixed nonzero pattern of the lower triangle (row >= col) of the Lagrangian Hessian.
    fn hessian_structure(&self) -> Sparsity;
    /// Writes the nonzeros of ∇²(obj_factor·f + Σ lambda_i c_i) in the order of
    /// [`Nlp::hessian_structure`].
    fn hessian_values(
        &self,
        x: &[f64],
        obj_factor: f64,
        lambda: &[f64],
        vals: &mut [f64],
    ) -> Result<(), EvalError>;
    /// The collocation block structure, if the problem has one.
    fn blocks(&self) -> Option<BlockStructure> {
        None
    }
}

/// A malformed problem definition (bounds or derivative patterns), with where it is wrong.
#[derive(Debug, Clone, Error, PartialEq)]
pub enum NlpError {
    /// A lower bound exceeds its upper bound (or a bound is NaN).
    #[error("{kind} {index}: lower bound {lower} > upper bound {upper}")]
    InvertedBounds {
        /// "variable" or "constraint".
        kind: &'static str,
        /// Index of the variable or constraint.
        index: usize,
        /// The lower bound.
        lower: f64,
        /// The upper bound.
        upper: f64,
    },
    /// A bound is NaN, or a lower bound is +∞ / an upper bound is −∞.
    #[error("{kind} {index}: invalid bounds [{lower}, {upper}]")]
    InvalidBound {
        /// "variable" or "constraint".
        kind: &'static str,
        /// Index of the variable or constraint.
        index: usize,
        /// The lower bound.
        lower: f64,
        /// The upper bound.
        upper: f64,
    },
    /// Row and column lists of a pattern have different lengths.
    #[error("{matrix} structure: {rows} row indices but {cols} column indices")]
    LengthMismatch {
        /// Which matrix.
        matrix: NlpFunction,
        /// Number of row indices.
        rows: usize,
        /// Number of column indices.
        cols: usize,
    },
    /// A nonzero lies outside the matrix.
    #[error(
        "{matrix} structure: entry {entry} at ({row}, {col}) is outside the {nrows}×{ncols} matrix"
    )]
    OutOfRange {
        /// Which matrix.
        matrix: NlpFunction,
        /// Position of the nonzero in the value array.
        entry: usize,
        /// Its row.
        row: usize,
        /// Its column.
        col: usize,
        /// Number of rows of the matrix.
        nrows: usize,
        /// Number of columns of the matrix.
        ncols: usize,
    },
    /// The same (row, col) appears twice.
    #[error("{matrix} structure: entries {first} and {second} both at ({row}, {col})")]
    Duplicate {
        /// Which matrix.
        matrix: NlpFunction,
        /// First position.
        first: usize,
        /// Second position.
        second: usize,
        /// Row.
        row: usize,
        /// Column.
        col: usize,
    },
    /// A Hessian nonzero lies in the strict upper triangle.
    #[error("Lagrangian Hessian structure: entry {entry} at ({row}, {col}) is above the diagonal (need row >= col)")]
    UpperTriangle {
        /// Position of the nonzero.
        entry: usize,
        /// Its row.
        row: usize,
        /// Its column.
        col: usize,
    },
    /// A block lists a variable outside the problem or a variable twice.
    #[error("block structure: {0}")]
    InvalidBlocks(String),
}

/// Variable and constraint bounds of a problem.
#[derive(Debug, Clone, PartialEq)]
pub struct Bounds {
    /// Variable lower bounds.
    pub x_l: Vec<f64>,
    /// Variable upper bounds.
    pub x_u: Vec<f64>,
    /// Constraint lower bounds.
    pub g_l: Vec<f64>,
    /// Constraint upper bounds.
    pub g_u: Vec<f64>,
}

fn check_bound_pairs(kind: &'static str, lo: &[f64], up: &[f64]) -> Result<(), NlpError> {
    for (index, (&lower, &upper)) in lo.iter().zip(up).enumerate() {
        if lower.is_nan() || upper.is_nan() || lower == f64::INFINITY || upper == f64::NEG_INFINITY
        {
            return Err(NlpError::InvalidBound {
                kind,
                index,
                lower,
                upper,
            });
        }
        if lower > upper {
            return Err(NlpError::InvertedBounds {
                kind,
                index,
                lower,
                upper,
            });
        }
    }
    Ok(())
}

/// Reads the bounds of `nlp` and checks that every lower bound is <= its upper bound.
pub fn validate_bounds(nlp: &dyn Nlp) -> Result<Bounds, NlpError> {
    let (n, m) = (nlp.n(), nlp.m());
    let mut b = Bounds {
        x_l: vec![f64::NEG_INFINITY; n],
        x_u: vec![f64::INFINITY; n],
        g_l: vec![f64::NEG_INFINITY; m],
        g_u: vec![f64::INFINITY; m],
    };
    nlp.bounds(&mut b.x_l, &mut b.x_u, &mut b.g_l, &mut b.g_u);
    check_bound_pairs("variable", &b.x_l, &b.x_u)?;
    check_bound_pairs("constraint", &b.g_l, &b.g_u)?;
    Ok(b)
}

/// Checks a pattern against an `nrows × ncols` matrix: equal lengths, indices in range, no
/// duplicates, and (when `lower_triangle`) row >= col.
pub fn validate_sparsity(
    matrix: NlpFunction,
    s: &Sparsity,
    nrows: usize,
    ncols: usize,
    lower_triangle: bool,
) -> Result<(), NlpError> {
    if s.rows.len() != s.cols.len() {
        return Err(NlpError::LengthMismatch {
            matrix,
            rows: s.rows.len(),
            cols: s.cols.len(),
        });
    }
    for (entry, (&row, &col)) in s.rows.iter().zip(&s.cols).enumerate() {
        if row >= nrows || col >= ncols {
            return Err(NlpError::OutOfRange {
                matrix,
                entry,
                row,
                col,
                nrows,
                ncols,
            });
        }
        if lower_triangle && row < col {
            return Err(NlpError::UpperTriangle { entry, row, col });
        }
    }
    let mut order: Vec<usize> = (0..s.rows.len()).collect();
    order.sort_unstable_by_key(|&k| (s.rows[k], s.cols[k], k));
    for w in order.windows(2) {
        let (a, b) = (w[0], w[1]);
        if s.rows[a] == s.rows[b] && s.cols[a] == s.cols[b] {
            return Err(NlpError::Duplicate {
                matrix,
                first: a,
                second: b,
                row: s.rows[a],
                col: s.cols[a],
            });
        }
    }
    Ok(())
}

/// Checks a block structure: indices inside the problem, none listed twice.
pub fn validate_blocks(b: &BlockStructure, n: usize) -> Result<(), NlpError> {
    let mut owner: Vec<Option<String>> = vec![None; n];
    let lists = b
        .blocks
        .iter()
        .enumerate()
        .map(|(k, vars)| (format!("block {k}"), vars))
        .chain(std::iter::once((
            "the global variables".to_string(),
            &b.global_variables,
        )));
    for (name, vars) in lists {
        for &v in vars {
            if v >= n {
                return Err(NlpError::InvalidBlocks(format!(
                    "{name} lists variable {v}, outside 0..{n}"
                )));
            }
            if let Some(first) = &owner[v] {
                return Err(NlpError::InvalidBlocks(format!(
                    "variable {v} is listed in {first} and in {name}"
                )));
            }
            owner[v] = Some(name.clone());
        }
    }
    Ok(())
}

/// The validated fixed derivative structures of a problem.
#[derive(Debug, Clone, PartialEq)]
pub struct Structures {
    /// Constraint Jacobian pattern (m × n).
    pub jacobian: Sparsity,
    /// Lagrangian Hessian lower-triangle pattern (n × n).
    pub hessian: Sparsity,
}

/// Reads and validates the Jacobian and Hessian patterns (and block structure) of `nlp`.
pub fn validate_structures(nlp: &dyn Nlp) -> Result<Structures, NlpError> {
    let (n, m) = (nlp.n(), nlp.m());
    let jacobian = nlp.jacobian_structure();
    validate_sparsity(NlpFunction::Jacobian, &jacobian, m, n, false)?;
    let hessian = nlp.hessian_structure();
    validate_sparsity(NlpFunction::Hessian, &hessian, n, n, true)?;
    if let Some(b) = nlp.blocks() {
        validate_blocks(&b, n)?;
    }
    Ok(Structures { jacobian, hessian })
}

/// Returns an error naming the first non-finite entry of `values` produced by `function`.
pub fn check_finite(function: NlpFunction, values: &[f64]) -> Result<(), EvalError> {
    match values.iter().position(|v| !v.is_finite()) {
        None => Ok(()),
        Some(index) => Err(EvalError::NonFinite {
            function,
            index,
            value: values[index],
        }),
    }
}

/// Settings for [`check_derivatives`].
#[derive(Debug, Clone)]
pub struct DerivativeCheckOptions {
    /// Relative finite-difference step (step = h · max(1, |x_j|)).
    pub step: f64,
    /// Check at most this many variables (columns), spread evenly over 0..n.
    pub max_columns: usize,
    /// Also check the Lagrangian Hessian with these multipliers (None: skip the Hessian).
    pub lambda: Option<Vec<f64>>,
    /// Objective factor used for the Hessian check.
    pub obj_factor: f64,
    /// An entry is reported bad when |analytic − fd| > tol · max(1, |fd|).
    pub tol: f64,
}

impl Default for DerivativeCheckOptions {
    fn default() -> Self {
        DerivativeCheckOptions {
            step: 1e-6,
            max_columns: 200,
            lambda: None,
            obj_factor: 1.0,
            tol: 1e-5,
        }
    }
}

/// One derivative entry whose analytic value disagrees with the finite difference.
#[derive(Debug, Clone, PartialEq)]
pub struct DerivativeMismatch {
    /// Which derivative.
    pub function: NlpFunction,
    /// Row (constraint for the Jacobian, 0 for the gradient, variable for the Hessian).
    pub row: usize,
    /// Column (variable).
    pub col: usize,
    /// The value the problem returned (0 if the entry is not in the declared pattern).
    pub analytic: f64,
    /// The central finite-difference estimate.
    pub finite_difference: f64,
}

/// The outcome of a derivative check.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct DerivativeReport {
    /// Largest scaled error |analytic − fd| / max(1, |fd|) over all checked entries.
    pub max_error: f64,
    /// Number of columns checked.
    pub columns_checked: usize,
    /// Entries beyond the tolerance (at most 50 kept).
    pub mismatches: Vec<DerivativeMismatch>,
}

impl DerivativeReport {
    fn record(&mut self, tol: f64, mm: DerivativeMismatch) {
        let err = (mm.analytic - mm.finite_difference).abs() / mm.finite_difference.abs().max(1.0);
        if err.is_nan() || err > self.max_error {
            self.max_error = if err.is_nan() { f64::INFINITY } else { err };
        }
        if (err > tol || err.is_nan()) && self.mismatches.len() < 50 {
            self.mismatches.push(mm);
        }
    }
}

/// An error from the derivative checker: the problem is malformed or failed to evaluate.
#[derive(Debug, Clone, Error, PartialEq)]
pub enum CheckError {
    /// The declared structure is invalid.
    #[error(transparent)]
    Structure(#[from] NlpError),
    /// A function could not be evaluated.
    #[error(transparent)]
    Eval(#[from] EvalError),
    /// The point has the wrong length.
    #[error("point has {got} entries, the problem has {expected} variables")]
    WrongLength {
        /// Length of the given point.
        got: usize,
        /// Number of variables.
        expected: usize,
    },
}

fn lagrangian_gradient(
    nlp: &dyn Nlp,
    jac: &Sparsity,
    x: &[f64],
    obj_factor: f64,
    lambda: &[f64],
    jv: &mut [f64],
    out: &mut [f64],
) -> Result<(), EvalError> {
    nlp.gradient(x, out)?;
    out.iter_mut().for_each(|v| *v *= obj_factor);
    nlp.jacobian_values(x, jv)?;
    for k in 0..jac.nnz() {
        out[jac.cols[k]] += lambda[jac.rows[k]] * jv[k];
    }
    Ok(())
}

/// Compares the gradient, the Jacobian and (optionally) the Lagrangian Hessian of `nlp` at
/// `x` with central finite differences, column by column (cost: 2 evaluations per checked
/// column). Entries outside the declared patterns are compared against zero, so a missing
/// nonzero is reported too.
pub fn check_derivatives(
    nlp: &dyn Nlp,
    x: &[f64],
    opts: &DerivativeCheckOptions,
) -> Result<DerivativeReport, CheckError> {
    let (n, m) = (nlp.n(), nlp.m());
    if x.len() != n {
        return Err(CheckError::WrongLength {
            got: x.len(),
            expected: n,
        });
    }
    let st = validate_structures(nlp)?;
    let mut grad = vec![0.0; n];
    nlp.gradient(x, &mut grad)?;
    let mut jv = vec![0.0; st.jacobian.nnz()];
    nlp.jacobian_values(x, &mut jv)?;
    // Column-wise views of the analytic derivatives.
    let mut jac_cols: Vec<Vec<(usize, f64)>> = vec![Vec::new(); n];
    for k in 0..st.jacobian.nnz() {
        jac_cols[st.jacobian.cols[k]].push((st.jacobian.rows[k], jv[k]));
    }
    let mut hess_cols: Vec<Vec<(usize, f64)>> = vec![Vec::new(); n];
    if let Some(lambda) = &opts.lambda {
        let mut hv = vec![0.0; st.hessian.nnz()];
        nlp.hessian_values(x, opts.obj_factor, lambda, &mut hv)?;
        for k in 0..st.hessian.nnz() {
            let (r, c) = (st.hessian.rows[k], st.hessian.cols[k]);
            hess_cols[c].push((r, hv[k]));
            if r != c {
                hess_cols[r].push((c, hv[k]));
            }
        }
    }
    let cols: Vec<usize> = if n <= opts.max_columns {
        (0..n).collect()
    } else {
        let stride = n as f64 / opts.max_columns as f64;
        (0..opts.max_columns)
            .map(|i| ((i as f64 * stride) as usize).min(n - 1))
            .collect()
    };
    let mut report = DerivativeReport::default();
    let mut xp = x.to_vec();
    let (mut cp, mut cm) = (vec![0.0; m], vec![0.0; m]);
    let (mut lp, mut lm) = (vec![0.0; n], vec![0.0; n]);
    let mut jtmp = vec![0.0; st.jacobian.nnz()];
    let mut dense = vec![0.0; m.max(n)];
    for &j in &cols {
        let h = opts.step * x[j].abs().max(1.0);
        xp[j] = x[j] + h;
        let fp = nlp.objective(&xp)?;
        nlp.constraints(&xp, &mut cp)?;
        xp[j] = x[j] - h;
        let fm = nlp.objective(&xp)?;
        nlp.constraints(&xp, &mut cm)?;
        report.record(
            opts.tol,
            DerivativeMismatch {
                function: NlpFunction::Gradient,
                row: 0,
                col: j,
                analytic: grad[j],
                finite_difference: (fp - fm) / (2.0 * h),
            },
        );
        dense[..m].iter_mut().for_each(|v| *v = 0.0);
        for &(r, v) in &jac_cols[j] {
            dense[r] += v;
        }
        for i in 0..m {
            report.record(
                opts.tol,
                DerivativeMismatch {
                    function: NlpFunction::Jacobian,
                    row: i,
                    col: j,
                    analytic: dense[i],
                    finite_difference: (cp[i] - cm[i]) / (2.0 * h),
                },
            );
        }
        if let Some(lambda) = &opts.lambda {
            xp[j] = x[j] + h;
            lagrangian_gradient(
                nlp,
                &st.jacobian,
                &xp,
                opts.obj_factor,
                lambda,
                &mut jtmp,
                &mut lp,
            )?;
            xp[j] = x[j] - h;
            lagrangian_gradient(
                nlp,
                &st.jacobian,
                &xp,
                opts.obj_factor,
                lambda,
                &mut jtmp,
                &mut lm,
            )?;
            dense[..n].iter_mut().for_each(|v| *v = 0.0);
            for &(r, v) in &hess_cols[j] {
                dense[r] += v;
            }
            for i in 0..n {
                report.record(
                    opts.tol,
                    DerivativeMismatch {
                        function: NlpFunction::Hessian,
                        row: i,
                        col: j,
                        analytic: dense[i],
                        finite_difference: (lp[i] - lm[i]) / (2.0 * h),
                    },
                );
            }
        }
        xp[j] = x[j];
        report.columns_checked += 1;
    }
    Ok(report)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn block_lists_must_stay_inside_the_problem_and_not_repeat() {
        let ok = BlockStructure {
            blocks: vec![vec![0, 1], vec![2, 3]],
            global_variables: vec![4],
        };
        assert_eq!(validate_blocks(&ok, 5), Ok(()));
        let outside = BlockStructure {
            blocks: vec![vec![0, 7]],
            global_variables: vec![],
        };
        let e = validate_blocks(&outside, 5).unwrap_err().to_string();
        assert!(e.contains("block 0 lists variable 7"), "{e}");
        let twice = BlockStructure {
            blocks: vec![vec![0, 1], vec![1, 2]],
            global_variables: vec![],
        };
        let e = validate_blocks(&twice, 5).unwrap_err().to_string();
        assert!(
            e.contains("variable 1 is listed in block 0 and in block 1"),
            "{e}"
        );
    }
}
