//! How the transcription's constraint Jacobian values are written from the node
//! Jacobians and the linear rows, laid out once so that an evaluation is a few parallel
//! streaming passes instead of a scatter through a position per entry.
//!
//! The transcription pushes the constraint entries of every node's Jacobian first, node
//! after node in the node pattern's order, then the entries of the linear rows, row after
//! row. So the node part of the NLP values is, node after node, the same selection of
//! that node's Jacobian entries (all but the cost row's), and each value of the linear
//! part is a constant plus a coefficient times h = t_f / N, except the ∂/∂t_f entry of each row with h-terms (the sum of those
//! terms' coefficients times their variables over N).

use crate::linear_rows::{LinearRow, Term};
use rayon::prelude::*;

/// Entries written per parallel task of the streaming passes.
const CHUNK: usize = 1 << 14;

/// The layout of the constraint Jacobian values for [`JacobianFill::fill`].
#[derive(Clone, Debug)]
pub(crate) struct JacobianFill {
    /// Entries of each node's Jacobian pattern.
    node_entries: usize,
    /// The entries of a node's Jacobian that are constraint values, in value order.
    node_constraints: Vec<u32>,
    /// First NLP value of the node entries (node `i`'s from `node_start + i · block` on,
    /// `block` the number of its constraint entries).
    node_start: usize,
    /// First NLP value of the linear rows (they fill `linear_start..` up to `linear_end`).
    linear_start: usize,
    /// Per linear-row value: the sum of its constant coefficients.
    linear_const: Vec<f64>,
    /// Per linear-row value: the sum of the coefficients of its h-terms (times t_f / N).
    linear_h: Vec<f64>,
    /// (value position, `(var, coef)` range in `dtf_terms`) of each ∂/∂t_f entry.
    dtf: Vec<(usize, std::ops::Range<usize>)>,
    /// `(var, coef)` of the h-terms of every row with a ∂/∂t_f entry.
    dtf_terms: Vec<(usize, f64)>,
}

impl JacobianFill {
    /// The layout for nodes with `node_entries` Jacobian entries each, of which those
    /// listed in `node_constraints` are constraint values written from the NLP value
    /// `node_start` on, node after node, and for `rows` whose terms go to `row_pos` (one
    /// position per term, then the ∂/∂t_f position of a row with h-terms).
    pub(crate) fn new(
        node_entries: usize,
        node_constraints: &[usize],
        node_start: usize,
        rows: &[LinearRow],
        row_pos: &[Vec<usize>],
    ) -> Self {
        let all = row_pos.iter().flatten().copied();
        let linear_start = all.clone().min().unwrap_or(0);
        let linear_end = all.max().map_or(linear_start, |p| p + 1);
        let len = linear_end - linear_start;
        let mut linear_const = vec![0.0; len];
        let mut linear_h = vec![0.0; len];
        let mut dtf = Vec::new();
        let mut dtf_terms = Vec::new();
        for (lr, pos) in rows.iter().zip(row_pos) {
            for (t, &p) in lr.terms.iter().zip(pos) {
                let sum = if t.times_h {
                    &mut linear_h
                } else {
                    &mut linear_const
                };
                sum[p - linear_start] += t.coef;
            }
            if pos.len() > lr.terms.len() {
                let start = dtf_terms.len();
                let h_terms = lr.terms.iter().filter(|t| t.times_h);
                dtf_terms.extend(h_terms.map(|&Term { var, coef, .. }| (var, coef)));
                dtf.push((pos[lr.terms.len()], start..dtf_terms.len()));
            }
        }
        Self {
            node_entries,
            node_constraints: node_constraints.iter().map(|&e| e as u32).collect(),
            node_start,
            linear_start,
            linear_const,
            linear_h,
            dtf,
            dtf_terms,
        }
    }

    /// Writes the constraint Jacobian values of the node Jacobians `node_jac` (node after
    /// node) and of the linear rows at the point `x` with h = t_f / N (`tf`, `n` the mesh
    /// intervals) into `vals`; the speed row's entries are left to the caller.
    pub(crate) fn fill(&self, node_jac: &[f64], x: &[f64], tf: f64, n: f64, vals: &mut [f64]) {
        let block = self.node_constraints.len();
        if block > 0 {
            let nodes = node_jac.len() / self.node_entries;
            vals[self.node_start..][..nodes * block]
                .par_chunks_mut(block)
                .zip(node_jac.par_chunks(self.node_entries))
                .for_each(|(v, jac)| {
                    for (v, &e) in v.iter_mut().zip(&self.node_constraints) {
                        *v = jac[e as usize];
                    }
                });
        }
        let linear = &mut vals[self.linear_start..][..self.linear_const.len()];
        linear
            .par_chunks_mut(CHUNK)
            .zip(self.linear_const.par_chunks(CHUNK))
            .zip(self.linear_h.par_chunks(CHUNK))
            .for_each(|((v, c), h)| {
                for ((v, &c), &h) in v.iter_mut().zip(c).zip(h) {
                    *v = c + h * tf / n;
                }
            });
        for (p, range) in &self.dtf {
            let terms = &self.dtf_terms[range.clone()];
            vals[*p] = terms
                .iter()
                .fold(0.0, |s, &(var, coef)| s + coef * x[var] / n);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn term(var: usize, coef: f64, times_h: bool) -> Term {
        Term { var, coef, times_h }
    }

    /// Two nodes of three Jacobian entries (the cost row's last, then first), one row with a
    /// constant and two h-terms (one on a variable also in a constant term), one row with
    /// constants only: every value against its formula.
    #[test]
    fn values_equal_the_rows_formulas_with_blocks_and_with_a_scatter() {
        let rows = vec![
            LinearRow {
                row: 0,
                terms: vec![
                    term(0, -2.0, false),
                    term(1, 0.5, false),
                    term(1, 3.0, true),
                    term(2, -4.0, true),
                ],
            },
            LinearRow {
                row: 1,
                terms: vec![term(3, 1.0, false), term(0, -1.0, false)],
            },
        ];
        let (x, tf, n) = ([0.3, -1.1, 2.5, 0.7], 1.2, 5.0);
        let h = tf / n;
        // Row 0: var 0, var 1 (shared by two terms), var 2, ∂/∂t_f; row 1: var 3, var 0.
        let linear = [
            -2.0,
            0.5 + 3.0 * h,
            -4.0 * h,
            (3.0 * -1.1 - 4.0 * 2.5) / n,
            1.0,
            -1.0,
        ];
        for (node_jac, constraints, node_vals) in [
            (
                [10.0, 11.0, 99.0, 12.0, 13.0, 98.0],
                [0, 1],
                [10.0, 11.0, 12.0, 13.0],
            ),
            (
                [99.0, 11.0, 13.0, 98.0, 10.0, 12.0],
                [1, 2],
                [11.0, 13.0, 10.0, 12.0],
            ),
        ] {
            let row_pos = vec![vec![4, 5, 5, 6, 7], vec![8, 9]];
            let fill = JacobianFill::new(3, &constraints, 0, &rows, &row_pos);
            let mut vals = vec![f64::NAN; 10];
            fill.fill(&node_jac, &x, tf, n, &mut vals);
            assert_eq!(vals[..4], node_vals);
            for (v, want) in vals[4..].iter().zip(linear) {
                assert!((v - want).abs() < 1e-14, "{v} against {want}");
            }
        }
    }
}
