//! Turning a recording into an evaluation-ready tape: dead-code elimination, index-set
//! sparsity of the Jacobian and of the Lagrangian Hessian, colouring, and the per-chunk
//! node lists the sweeps walk.

use super::op::Op;
use super::var::Recorder;
use super::{HesChunk, JacChunk, Tape, LANES};
use crate::sparsity::{bits, greedy_colouring, BitSets, Pattern};

/// Identity of an operation for common-subexpression elimination: kind, operands (sorted
/// for the commutative `+` and `*`) and the bits of its constant. `None` for inputs.
fn cse_key(op: &Op) -> Option<(u8, u32, u32, u32, u64)> {
    let sorted = |a: u32, b: u32| if a <= b { (a, b) } else { (b, a) };
    Some(match *op {
        Op::Input(_) => return None,
        Op::Const(c) => (0, 0, 0, 0, c.to_bits()),
        Op::Add(a, b) => {
            let (a, b) = sorted(a, b);
            (1, a, b, 0, 0)
        }
        Op::Sub(a, b) => (2, a, b, 0, 0),
        Op::Mul(a, b) => {
            let (a, b) = sorted(a, b);
            (3, a, b, 0, 0)
        }
        Op::Div(a, b) => (4, a, b, 0, 0),
        Op::Neg(a) => (5, a, 0, 0, 0),
        Op::AddC(a, c) => (6, a, 0, 0, c.to_bits()),
        Op::MulC(a, c) => (7, a, 0, 0, c.to_bits()),
        Op::DivC(a, c) => (8, a, 0, 0, c.to_bits()),
        Op::CDiv(c, a) => (9, a, 0, 0, c.to_bits()),
        Op::Unary(a, e) => (10, a, e as u32, 0, 0),
        Op::Powf(a, p) => (11, a, 0, 0, p.to_bits()),
        Op::Powi(a, n) => (12, a, 0, 0, n as u32 as u64),
        Op::Apply(a, f) => (13, a, f, 0, 0),
        // Not reordered: which operand wins a tie decides the derivative.
        Op::Min(a, b) => (14, a, b, 0, 0),
        Op::Max(a, b) => (15, a, b, 0, 0),
        Op::Select(c, p, n) => (16, c, p, n, 0),
    })
}

/// Common-subexpression elimination: the operations with every operand replaced by the
/// first recorded node that computes the same operation of the same operands, and that
/// representative for every node (an operation repeated in the model code, such as a
/// monomial shared by a muscle's length and moment-arm polynomials, is then evaluated
/// and differentiated once).
fn merge_common(rec: &Recorder) -> (Vec<Op>, Vec<u32>) {
    let n = rec.ops.len();
    let mut canon: Vec<u32> = Vec::with_capacity(n);
    let mut ops = Vec::with_capacity(n);
    let mut seen = std::collections::HashMap::with_capacity(n);
    for (k, (op, _)) in rec.ops.iter().enumerate() {
        let op = op.remap(&canon);
        let rep = match cse_key(&op) {
            Some(key) => *seen.entry(key).or_insert(k as u32),
            None => k as u32,
        };
        canon.push(rep);
        ops.push(op);
    }
    (ops, canon)
}

/// Common-subexpression and dead-code elimination: keeps the inputs and every distinct
/// node an output depends on. Returns the kept operations (remapped), their values at the
/// recording point, and the new index of each output.
pub(super) fn compact(
    n_in: usize,
    rec: &Recorder,
    outputs: &[u32],
) -> (Vec<Op>, Vec<f64>, Vec<u32>) {
    let n = rec.ops.len();
    let (merged, canon) = merge_common(rec);
    let outputs: Vec<u32> = outputs.iter().map(|&o| canon[o as usize]).collect();
    let mut live = vec![false; n];
    live[..n_in].iter_mut().for_each(|l| *l = true);
    for &o in &outputs {
        live[o as usize] = true;
    }
    let mut args = Vec::with_capacity(3);
    for k in (n_in..n).rev() {
        if live[k] {
            merged[k].value_args(&mut args);
            for &a in &args {
                live[a as usize] = true;
            }
        }
    }
    let mut map = vec![u32::MAX; n];
    let mut ops = Vec::new();
    let mut vals = Vec::new();
    let mut next = 0u32;
    for k in 0..n {
        if live[k] {
            map[k] = next;
            next += 1;
            if k >= n_in {
                ops.push(merged[k].remap(&map));
            }
            vals.push(rec.ops[k].1);
        }
    }
    let outs = outputs.iter().map(|&o| map[o as usize]).collect();
    (ops, vals, outs)
}

/// Forward propagation of the input index sets `J(k)` of every node.
pub(super) fn index_sets(n_in: usize, ops: &[Op]) -> BitSets {
    let n = n_in + ops.len();
    let mut j = BitSets::new(n, n_in);
    for i in 0..n_in {
        j.insert(i, i);
    }
    for (t, op) in ops.iter().enumerate() {
        let k = n_in + t;
        if let Some([a, b]) = op.diff_args() {
            j.union_rows(k, a as usize);
            j.union_rows(k, b as usize);
        }
    }
    j
}

/// Neighbour lists of a conflict graph given, for each vertex, the groups it belongs to
/// (two vertices conflict when they share a group).
fn conflicts(members_of: &[Vec<u32>], groups: &[Vec<u32>]) -> Vec<Vec<u32>> {
    let n = members_of.len();
    let mut seen = vec![usize::MAX; n];
    (0..n)
        .map(|v| {
            let mut out = Vec::new();
            seen[v] = v;
            for &g in &members_of[v] {
                for &u in &groups[g as usize] {
                    if seen[u as usize] != v {
                        seen[u as usize] = v;
                        out.push(u);
                    }
                }
            }
            out
        })
        .collect()
}

/// Colours grouped `LANES` at a time, as lists of member vertices.
fn chunks_of(colour: &[u32], n_colours: usize) -> Vec<Vec<u32>> {
    let n_chunks = n_colours.div_ceil(LANES);
    let mut chunks = vec![Vec::new(); n_chunks];
    for (v, &c) in colour.iter().enumerate() {
        chunks[c as usize / LANES].push(v as u32);
    }
    chunks
}

/// Derivative operands of each operation, with inactive operands sent to the sink node.
pub(super) fn diff_args(n_in: usize, ops: &[Op], active: &[bool], sink: u32) -> Vec<[u32; 2]> {
    let _ = n_in;
    ops.iter()
        .map(|op| match op.diff_args() {
            Some([a, b]) => {
                let f = |i: u32| if active[i as usize] { i } else { sink };
                [f(a), f(b)]
            }
            None => [sink, sink],
        })
        .collect()
}

impl Tape {
    /// Builds the Jacobian pattern, row colouring and reverse-sweep chunks.
    pub(super) fn plan_jacobian(&mut self, jset: &BitSets) {
        let n_in = self.n_in;
        let m = self.outputs.len();
        let mut pattern = Pattern {
            n_rows: m,
            n_cols: n_in,
            ..Pattern::default()
        };
        let mut row_cols: Vec<Vec<u32>> = Vec::with_capacity(m);
        for (r, &o) in self.outputs.iter().enumerate() {
            let cols: Vec<u32> = bits(jset.row(o as usize)).map(|c| c as u32).collect();
            for &c in &cols {
                pattern.rows.push(r as u32);
                pattern.cols.push(c);
            }
            row_cols.push(cols);
        }
        let mut col_rows: Vec<Vec<u32>> = vec![Vec::new(); n_in];
        for (r, cols) in row_cols.iter().enumerate() {
            for &c in cols {
                col_rows[c as usize].push(r as u32);
            }
        }
        let (colour, n_colours) = greedy_colouring(&conflicts(&row_cols, &col_rows));
        let mut row_start = vec![0usize; m + 1];
        for r in 0..m {
            row_start[r + 1] = row_start[r] + row_cols[r].len();
        }
        let mut mark = vec![false; self.n_nodes];
        for rows in chunks_of(&colour, n_colours) {
            let mut chunk = JacChunk::default();
            mark.iter_mut().for_each(|x| *x = false);
            for &r in &rows {
                let r = r as usize;
                if row_cols[r].is_empty() {
                    continue;
                }
                let lane = colour[r] % LANES as u32;
                let node = self.outputs[r];
                chunk.seeds.push((node, lane));
                mark[node as usize] = true;
                for (e, &c) in row_cols[r].iter().enumerate() {
                    chunk.extract.push(((row_start[r] + e) as u32, c, lane));
                }
            }
            for k in (n_in..self.n_nodes).rev() {
                if mark[k] && self.active[k] {
                    chunk.nodes.push(k as u32);
                    for a in self.args[k - n_in] {
                        if (a as usize) < self.n_nodes {
                            mark[a as usize] = true;
                        }
                    }
                }
            }
            self.jac_chunks.push(chunk);
        }
        self.jac_pattern = pattern;
        self.jac_colours = n_colours;
    }

    /// Builds the Lagrangian Hessian pattern (lower triangle), the distance-2 column
    /// colouring and the forward-over-reverse chunks.
    pub(super) fn plan_hessian(&mut self, pattern: Pattern) {
        let n_in = self.n_in;
        let mut adj: Vec<Vec<u32>> = vec![Vec::new(); n_in];
        for (i, j) in pattern.iter() {
            adj[i].push(j as u32);
            if i != j {
                adj[j].push(i as u32);
            }
        }
        adj.iter_mut().for_each(|a| a.sort_unstable());
        // Columns i, j conflict when some row k has H[k,i] and H[k,j] nonzero.
        let (colour, n_colours) = greedy_colouring(&conflicts(&adj, &adj));
        let mut fwd = vec![false; self.n_nodes];
        let mut anc = vec![false; self.n_nodes];
        for cols in chunks_of(&colour, n_colours) {
            let mut chunk = HesChunk::default();
            fwd.iter_mut().for_each(|x| *x = false);
            anc.iter_mut().for_each(|x| *x = false);
            for &j in &cols {
                if adj[j as usize].is_empty() {
                    continue;
                }
                chunk.seeds.push((j, colour[j as usize] % LANES as u32));
                fwd[j as usize] = true;
            }
            for k in n_in..self.n_nodes {
                let [a, b] = self.args[k - n_in];
                let hit = |i: u32| (i as usize) < self.n_nodes && fwd[i as usize];
                if self.active[k] && (hit(a) || hit(b)) {
                    fwd[k] = true;
                    chunk.fwd.push(k as u32);
                }
            }
            for k in (n_in..self.n_nodes).rev() {
                if self.active[k] && (fwd[k] || anc[k]) {
                    chunk.rev.push(k as u32);
                    for a in self.args[k - n_in] {
                        if (a as usize) < self.n_nodes {
                            anc[a as usize] = true;
                        }
                    }
                }
            }
            self.hes_chunks.push(chunk);
        }
        // Extraction: entry (i, j), i >= j, read from input i in the lane of colour(j).
        for (e, (i, j)) in pattern.iter().enumerate() {
            let c = colour[j] as usize;
            self.hes_chunks[c / LANES]
                .extract
                .push((e as u32, i as u32, (c % LANES) as u32));
        }
        self.hes_pattern = pattern;
        self.hes_colours = n_colours;
    }
}
