//! Iterative refinement of KKT solves against the unregularised matrix.
//!
//! The factorised KKT matrix K_reg carries a small constant regularisation −δ_c I on its
//! constraint block (quasi-definiteness, [`super::inertia::DELTA_C`]); the system the
//! Newton step needs is K_true = K_reg + diag(0, δ_c I). Refinement corrects a solution x
//! of K_reg x = b by x ← x + K_reg⁻¹ (b − K_true x) until the residual is below
//! [`REFINE_TOL`] relative to b or stops shrinking (IPOPT's iterative refinement).

// Index loops over several parallel arrays are clearer than zipped iterators here.
#![allow(clippy::needless_range_loop)]

use crate::ipm::iterate::inf_norm;
use crate::ipm::kkt::KktPattern;
use crate::ipm::linsys::{KktSolver, LinearSolverError};
use crate::observer::{Diagnostic, Emitter};

/// Iterative refinement: at most this many steps, down to this relative residual.
const MAX_REFINE: usize = 10;
pub(super) const REFINE_TOL: f64 = 1e-10;

/// Scratch of [`refine_solutions`], kept between solves so that refinement does not allocate
/// once it has seen its largest block.
#[derive(Default)]
pub(super) struct RefineScratch {
    /// Residual columns, packed.
    res: Vec<f64>,
    /// Max-norm of each right-hand side (at least 1).
    bnorm: Vec<f64>,
    /// Last residual norm of each column.
    last: Vec<f64>,
    /// Columns still refining.
    active: Vec<usize>,
}

/// res = b − K_true x for the KKT matrix K_reg (lower CSC values `vals`) whose constraint
/// block carries the extra regularisation −diag(`d_c_reg`): K_true = K_reg + diag(0, d_c_reg).
/// Several systems at once, in one pass over the matrix: slot s of `res` (column-major,
/// `pattern.dim` rows) gets column `cols[s]` of `b` and `x`.
pub(super) fn kkt_residual(
    pattern: &KktPattern,
    vals: &[f64],
    d_c_reg: &[f64],
    cols: &[usize],
    b: &[f64],
    x: &[f64],
    res: &mut [f64],
) {
    let dim = pattern.dim;
    for (s, &c) in cols.iter().enumerate() {
        res[s * dim..(s + 1) * dim].copy_from_slice(&b[c * dim..(c + 1) * dim]);
    }
    for j in 0..dim {
        for p in pattern.col_ptr[j]..pattern.col_ptr[j + 1] {
            let i = pattern.row_idx[p];
            let v = vals[p];
            for (s, &c) in cols.iter().enumerate() {
                let (rs, xc) = (s * dim, c * dim);
                res[rs + i] -= v * x[xc + j];
                if i != j {
                    res[rs + j] -= v * x[xc + i];
                }
            }
        }
    }
    for (s, &c) in cols.iter().enumerate() {
        let (rs, xc) = (s * dim + pattern.n, c * dim + pattern.n);
        for (k, d) in d_c_reg.iter().enumerate() {
            res[rs + k] -= d * x[xc + k];
        }
    }
}

/// The systems K_true x = b (column-major, `ncols` columns of `pattern.dim` rows) and the
/// factorisation of K_reg they are refined with (see [`kkt_residual`]).
pub(super) struct RegularisedSystem<'k> {
    /// Factorisation of K_reg.
    pub linear: &'k mut dyn KktSolver,
    /// Pattern of K.
    pub pattern: &'k KktPattern,
    /// Lower CSC values of K_reg.
    pub vals: &'k [f64],
    /// Constraint-block regularisation that K_reg has and K_true has not.
    pub d_c_reg: &'k [f64],
}

/// Iterative refinement of the `ncols` solutions `x` of K_true x = b (column-major) from
/// the factorisation of K_reg (see [`kkt_residual`]): each column until its residual is
/// below `REFINE_TOL` relative to its right-hand side or stops shrinking, the columns still
/// refining corrected together in one block solve per step. Emits each residual.
pub(super) fn refine_solutions(
    sys: RegularisedSystem,
    b: &[f64],
    x: &mut [f64],
    ncols: usize,
    scratch: &mut RefineScratch,
    emitter: &mut Emitter,
) -> Result<(), LinearSolverError> {
    let dim = sys.pattern.dim;
    let RefineScratch {
        res,
        bnorm,
        last,
        active,
    } = scratch;
    res.resize(ncols * dim, 0.0);
    bnorm.clear();
    bnorm.extend(b.chunks(dim).map(|c| inf_norm(c).max(1.0)));
    last.clear();
    last.resize(ncols, f64::INFINITY);
    active.clear();
    active.extend(0..ncols);
    let debug = emitter.wants(3);
    for _ in 0..MAX_REFINE {
        kkt_residual(sys.pattern, sys.vals, sys.d_c_reg, active, b, x, res);
        // keep the columns that still improve, their residuals packed to the front
        let mut kept = 0;
        for s in 0..active.len() {
            let c = active[s];
            let rn = inf_norm(&res[s * dim..(s + 1) * dim]);
            if debug {
                emitter.emit(Diagnostic::Refinement {
                    column: c,
                    residual: rn,
                    rhs_norm: bnorm[c],
                });
            }
            if rn <= REFINE_TOL * bnorm[c] || rn >= 0.9 * last[c] {
                continue;
            }
            last[c] = rn;
            if kept != s {
                res.copy_within(s * dim..(s + 1) * dim, kept * dim);
            }
            active[kept] = c;
            kept += 1;
        }
        active.truncate(kept);
        if kept == 0 {
            break;
        }
        sys.linear.solve_many(&mut res[..kept * dim], kept)?;
        for (s, &c) in active.iter().enumerate() {
            let xc = &mut x[c * dim..(c + 1) * dim];
            for (xi, d) in xc.iter_mut().zip(&res[s * dim..(s + 1) * dim]) {
                *xi += d;
            }
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::ipm::linsys::FaerLdlt;
    use crate::nlp::Sparsity;
    use crate::solver::{ControlFlow, IterationRecord};

    /// KKT matrix [[H, Jᵀ], [J, −δ_c I]] with H = diag(4, 3, 5), J = [[1, 1, 0], [0, 2, 1]],
    /// factorised with the constraint block regularised by δ_c = 0.01 (far larger than the
    /// solver's, so that refinement has something to remove); the unregularised matrix is
    /// the one refinement solves.
    fn regularised_system() -> (KktPattern, Vec<f64>, FaerLdlt) {
        let jac = Sparsity::new(vec![0, 0, 1, 1], vec![0, 1, 1, 2]);
        let hess = Sparsity::new(vec![], vec![]);
        let pattern = KktPattern::new(3, 2, &jac, &hess);
        let mut vals = vec![0.0; pattern.nnz()];
        pattern.assemble(
            &mut vals,
            &[],
            &[1.0, 1.0, 2.0, 1.0],
            &[4.0, 3.0, 5.0],
            &[0.01, 0.01],
        );
        let mut solver = FaerLdlt::new();
        solver
            .analyse(pattern.dim, &pattern.col_ptr, &pattern.row_idx, None)
            .unwrap();
        solver.factor(&vals).unwrap();
        (pattern, vals, solver)
    }

    /// K_true x for the system above (constraint block zero).
    fn true_product(x: &[f64]) -> Vec<f64> {
        vec![
            4.0 * x[0] + x[3],
            3.0 * x[1] + x[3] + 2.0 * x[4],
            5.0 * x[2] + x[4],
            x[0] + x[1],
            2.0 * x[1] + x[2],
        ]
    }

    #[test]
    fn block_refinement_solves_the_unregularised_system_column_by_column() {
        let (pattern, vals, mut solver) = regularised_system();
        let xs = [
            [1.0, -2.0, 0.5, 3.0, -1.0],
            [0.0, 1.0, 1.0, -2.0, 4.0],
            [2.0, 0.0, -1.0, 0.5, 0.25],
        ];
        let b: Vec<f64> = xs.iter().flat_map(|x| true_product(x)).collect();
        let mut x = b.clone();
        solver.solve_many(&mut x, 3).unwrap();
        // without refinement the regularisation leaves an error of order δ_c
        let before = (0..15)
            .map(|k| (x[k] - xs[k / 5][k % 5]).abs())
            .fold(0.0, f64::max);
        assert!(before > 1e-4, "unrefined error {before}");
        let mut res = RefineScratch::default();
        let d_c_reg = [0.01, 0.01];
        let mut quiet = |_: &IterationRecord| ControlFlow::Continue(());
        let mut emitter = Emitter::new(&mut quiet, 0);
        let sys = RegularisedSystem {
            linear: &mut solver,
            pattern: &pattern,
            vals: &vals,
            d_c_reg: &d_c_reg,
        };
        refine_solutions(sys, &b, &mut x, 3, &mut res, &mut emitter).unwrap();
        // refinement stops at a residual of REFINE_TOL relative to the right-hand side
        for (c, want) in xs.iter().enumerate() {
            let col = &x[c * 5..(c + 1) * 5];
            let kx = true_product(col);
            let bnorm = inf_norm(&b[c * 5..(c + 1) * 5]).max(1.0);
            let res = (0..5)
                .map(|i| (b[c * 5 + i] - kx[i]).abs())
                .fold(0.0, f64::max);
            assert!(res <= REFINE_TOL * bnorm, "column {c}: residual {res:e}");
            for (got, w) in col.iter().zip(want) {
                assert!((got - w).abs() < 1e-7, "column {c}: {got} vs {w}");
            }
        }
        // the same column refined alone gives the same solution
        let mut x1 = b[5..10].to_vec();
        solver.solve(&mut x1).unwrap();
        let sys = RegularisedSystem {
            linear: &mut solver,
            pattern: &pattern,
            vals: &vals,
            d_c_reg: &d_c_reg,
        };
        refine_solutions(sys, &b[5..10], &mut x1, 1, &mut res, &mut emitter).unwrap();
        for (a, c) in x1.iter().zip(&x[5..10]) {
            assert!((a - c).abs() < 1e-12, "{a} vs {c}");
        }
    }
}
