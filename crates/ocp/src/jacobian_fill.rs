//! How the transcription's constraint Jacobian values are written from the node
//! Jacobians and the linear rows, laid out once so that an evaluation is a few parallel
//! streaming passes instead of a scatter through a position per entry.
//!
//! The transcription pushes the constraint entries of every node's Jacobian first, node
//! after node in the node pattern's order (row-major, the cost row last and left out),
//! then the entries of the linear rows, row after row. So the node part of the NLP values
//! is each node's leading block copied as it is, and the linear part is, entry by entry,
//! a constant plus a coefficient times h = t_f / N, except the ∂/∂t_f entry of each row
//! with h-terms (the sum of those terms' coefficients times their variables over N).

use crate::transcription::{LinearRow, Term};
use rayon::prelude::*;

/// Entries written per parallel task of the streaming passes.
const CHUNK: usize = 1 << 14;

/// The layout of the constraint Jacobian values for [`JacobianFill::fill`].
#[derive(Clone, Debug)]
pub(crate) struct JacobianFill {
    /// Entries of each node's Jacobian pattern per node.
    node_entries: usize,
    /// How the node entries are written: the leading `block` entries of each node's
    /// Jacobian copied to `i · block` (the layout the transcription builds), or through
    /// one position per entry (`usize::MAX`: the cost row, not a constraint).
    node_copy: NodeCopy,
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

/// How node Jacobian entries reach the NLP values.
#[derive(Clone, Debug)]
enum NodeCopy {
    /// Node `i`'s first `block` entries go to `i · block ..`, in order.
    Blocks { block: usize },
    /// Entry `e` of the node Jacobians goes to `pos[e]` (`usize::MAX`: dropped).
    Scatter { pos: Vec<usize> },
}

impl JacobianFill {
    /// The layout for nodes with `node_entries` Jacobian entries each whose entry `e`
    /// (node-major) goes to `node_pos[e]`, and for `rows` whose terms go to `row_pos`
    /// (one position per term, then the ∂/∂t_f position of a row with h-terms).
    pub(crate) fn new(
        node_entries: usize,
        node_pos: &[usize],
        rows: &[LinearRow],
        row_pos: &[Vec<usize>],
    ) -> Self {
        let node_copy = match leading_blocks(node_entries, node_pos) {
            Some(block) => NodeCopy::Blocks { block },
            None => NodeCopy::Scatter {
                pos: node_pos.to_vec(),
            },
        };
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
            node_copy,
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
        match &self.node_copy {
            NodeCopy::Blocks { block } if *block > 0 => {
                let nodes = node_jac.len() / self.node_entries.max(1);
                vals[..nodes * block]
                    .par_chunks_mut(*block)
                    .zip(node_jac.par_chunks(self.node_entries))
                    .for_each(|(v, j)| v.copy_from_slice(&j[..*block]));
            }
            NodeCopy::Blocks { .. } => {}
            NodeCopy::Scatter { pos } => {
                for (&p, &v) in pos.iter().zip(node_jac) {
                    if p != usize::MAX {
                        vals[p] = v;
                    }
                }
            }
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

/// `Some(block)` when entry `e` of node `i` (of `per_node` entries) goes to
/// `i · block + e` for `e < block` and nowhere for `e ≥ block`.
fn leading_blocks(per_node: usize, pos: &[usize]) -> Option<usize> {
    if per_node == 0 || !pos.len().is_multiple_of(per_node) {
        return None;
    }
    let block = pos[..per_node]
        .iter()
        .take_while(|&&p| p != usize::MAX)
        .count();
    let fits = pos.chunks(per_node).enumerate().all(|(i, node)| {
        node.iter().enumerate().all(|(e, &p)| {
            if e < block {
                p == i * block + e
            } else {
                p == usize::MAX
            }
        })
    });
    fits.then_some(block)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn term(var: usize, coef: f64, times_h: bool) -> Term {
        Term { var, coef, times_h }
    }

    #[test]
    fn node_blocks_are_found_only_in_the_transcription_s_layout() {
        let m = usize::MAX;
        assert_eq!(leading_blocks(3, &[0, 1, m, 2, 3, m]), Some(2));
        assert_eq!(leading_blocks(3, &[0, 1, 2, 3, 4, 5]), Some(3));
        assert_eq!(leading_blocks(3, &[0, m, 1, 2, m, 3]), None);
        assert_eq!(leading_blocks(3, &[2, 3, m, 0, 1, m]), None);
        assert_eq!(leading_blocks(3, &[0, 1]), None);
    }

    /// Two nodes of three Jacobian entries (the last one the cost row), one row with a
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
        let node_jac = [10.0, 11.0, 99.0, 12.0, 13.0, 98.0];
        let m = usize::MAX;
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
        for (node_pos, node_vals) in [
            (vec![0, 1, m, 2, 3, m], [10.0, 11.0, 12.0, 13.0]),
            (vec![3, 0, m, 2, 1, m], [11.0, 13.0, 12.0, 10.0]),
        ] {
            let row_pos = vec![vec![4, 5, 5, 6, 7], vec![8, 9]];
            let fill = JacobianFill::new(3, &node_pos, &rows, &row_pos);
            let mut vals = vec![f64::NAN; 10];
            fill.fill(&node_jac, &x, tf, n, &mut vals);
            assert_eq!(vals[..4], node_vals);
            for (v, want) in vals[4..].iter().zip(linear) {
                assert!((v - want).abs() < 1e-14, "{v} against {want}");
            }
        }
    }
}
