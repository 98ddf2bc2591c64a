//! Assembly of the condensed primal-dual KKT matrix
//!
//! ```text
//!     [ H + Σ_x + δ_w I     Jᵀ  ]
//!     [ J                  −D   ]
//! ```
//!
//! (n + m rows; slack variables of inequality constraints are eliminated into the diagonal
//! D) as a lower triangle in compressed sparse column form with a fixed pattern. The pattern
//! and the scatter maps from the problem's COO derivative values are built once.

use crate::nlp::Sparsity;

/// The fixed lower-triangular CSC pattern of the KKT matrix and where each derivative
/// nonzero lands in its value array.
#[derive(Debug, Clone)]
pub struct KktPattern {
    /// Matrix dimension n + m.
    pub dim: usize,
    /// Number of primal variables n (the first block).
    pub n: usize,
    /// Column pointers (dim + 1).
    pub col_ptr: Vec<usize>,
    /// Row indices of the nonzeros.
    pub row_idx: Vec<usize>,
    /// Position of each diagonal entry (dim).
    pub diag_pos: Vec<usize>,
    /// Position of each Hessian nonzero.
    pub hess_pos: Vec<usize>,
    /// Position of each Jacobian nonzero.
    pub jac_pos: Vec<usize>,
}

impl KktPattern {
    /// Builds the pattern for `n` variables and `m` constraints from the Jacobian pattern and
    /// the lower-triangular Hessian pattern (kept in limited-memory mode too, for the ordering).
    pub fn new(n: usize, m: usize, jac: &Sparsity, hess: &Sparsity) -> Self {
        let dim = n + m;
        // (col, row, source) with source: 0..dim diagonal, then Hessian, then Jacobian.
        let nh = hess.nnz();
        let mut entries: Vec<(usize, usize, usize)> = Vec::with_capacity(dim + nh + jac.nnz());
        for i in 0..dim {
            entries.push((i, i, i));
        }
        for k in 0..nh {
            entries.push((hess.cols[k], hess.rows[k], dim + k));
        }
        for k in 0..jac.nnz() {
            entries.push((jac.cols[k], n + jac.rows[k], dim + nh + k));
        }
        entries.sort_unstable();
        let mut col_ptr = vec![0usize; dim + 1];
        let mut row_idx = Vec::with_capacity(entries.len());
        let mut diag_pos = vec![0usize; dim];
        let mut hess_pos = vec![0usize; nh];
        let mut jac_pos = vec![0usize; jac.nnz()];
        let mut last: Option<(usize, usize)> = None;
        for &(c, r, src) in &entries {
            if last != Some((c, r)) {
                row_idx.push(r);
                col_ptr[c + 1] += 1;
                last = Some((c, r));
            }
            let pos = row_idx.len() - 1;
            if src < dim {
                diag_pos[src] = pos;
            } else if src < dim + nh {
                hess_pos[src - dim] = pos;
            } else {
                jac_pos[src - dim - nh] = pos;
            }
        }
        for c in 0..dim {
            col_ptr[c + 1] += col_ptr[c];
        }
        KktPattern {
            dim,
            n,
            col_ptr,
            row_idx,
            diag_pos,
            hess_pos,
            jac_pos,
        }
    }

    /// Number of stored nonzeros.
    pub fn nnz(&self) -> usize {
        self.row_idx.len()
    }

    /// Fills `vals` with H (scaled Hessian values, may be empty), J, and the diagonals
    /// `diag_x` (added to the first block) and `−d_c` (second block).
    pub fn assemble(
        &self,
        vals: &mut [f64],
        hess: &[f64],
        jac: &[f64],
        diag_x: &[f64],
        d_c: &[f64],
    ) {
        vals.iter_mut().for_each(|v| *v = 0.0);
        for (k, &p) in self.hess_pos.iter().enumerate() {
            vals[p] += hess[k];
        }
        for (k, &p) in self.jac_pos.iter().enumerate() {
            vals[p] += jac[k];
        }
        for i in 0..self.n {
            vals[self.diag_pos[i]] += diag_x[i];
        }
        for (i, &d) in d_c.iter().enumerate() {
            vals[self.diag_pos[self.n + i]] -= d;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pattern_merges_hessian_diagonal_and_places_jacobian_below() {
        let jac = Sparsity::new(vec![0, 0], vec![0, 1]);
        let hess = Sparsity::new(vec![0, 1, 1], vec![0, 0, 1]);
        let p = KktPattern::new(2, 1, &jac, &hess);
        assert_eq!(p.dim, 3);
        // column 0: rows 0, 1, 2; column 1: rows 1, 2; column 2: row 2.
        assert_eq!(p.col_ptr, vec![0, 3, 5, 6]);
        assert_eq!(p.row_idx, vec![0, 1, 2, 1, 2, 2]);
        let mut vals = vec![0.0; p.nnz()];
        p.assemble(
            &mut vals,
            &[1.0, 2.0, 3.0],
            &[4.0, 5.0],
            &[10.0, 20.0],
            &[0.5],
        );
        assert_eq!(vals, vec![11.0, 2.0, 4.0, 23.0, 5.0, -0.5]);
    }
}
