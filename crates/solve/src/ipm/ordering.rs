//! Fill-reducing orderings of the KKT matrix.
//!
//! [`chain_dissection`] orders a KKT matrix whose variables form a chain of blocks (the mesh
//! intervals of a collocation problem) by nested dissection along the chain: the middle
//! block boundary (a mesh point's states or the continuity rows that reach it) is ordered
//! last, the two halves recursively before it, and each leaf (a few blocks) by approximate
//! minimum degree on its own subgraph. Global variables and constraints (final time,
//! periodicity) come at the very end. On chains, minimum degree alone makes choices whose fill
//! depends on tie-breaking; the dissection bounds every front by the boundary size.

use faer::dyn_stack::{MemBuffer, MemStack};
use faer::sparse::linalg::amd;
use faer::sparse::SymbolicSparseColMatRef;

use crate::ipm::kkt::KktPattern;
use crate::nlp::{BlockStructure, Nlp, Sparsity};
use crate::solver::KktOrdering;

/// Block of a vertex that belongs to no block (ordered last).
pub const GLOBAL: usize = usize::MAX;

/// The symmetric adjacency (no diagonal) of a lower-triangular CSC pattern.
struct Graph {
    start: Vec<usize>,
    adj: Vec<usize>,
}

impl Graph {
    fn from_lower(dim: usize, col_ptr: &[usize], row_idx: &[usize]) -> Self {
        let mut deg = vec![0usize; dim];
        for c in 0..dim {
            for &r in &row_idx[col_ptr[c]..col_ptr[c + 1]] {
                if r != c {
                    deg[r] += 1;
                    deg[c] += 1;
                }
            }
        }
        let mut start = vec![0usize; dim + 1];
        for v in 0..dim {
            start[v + 1] = start[v] + deg[v];
        }
        let mut fill = start.clone();
        let mut adj = vec![0usize; start[dim]];
        for c in 0..dim {
            for &r in &row_idx[col_ptr[c]..col_ptr[c + 1]] {
                if r != c {
                    adj[fill[r]] = c;
                    fill[r] += 1;
                    adj[fill[c]] = r;
                    fill[c] += 1;
                }
            }
        }
        Graph { start, adj }
    }

    fn neighbours(&self, v: usize) -> &[usize] {
        &self.adj[self.start[v]..self.start[v + 1]]
    }
}

/// Block of every KKT vertex: variables from `var_block` (`GLOBAL` for none), constraints
/// (vertices `n..dim`) from the blocks of the variables they touch: the lowest one when
/// those blocks are equal or adjacent, `GLOBAL` otherwise (e.g. periodicity rows that join
/// the first and the last block) or when they touch only global variables.
fn vertex_blocks(graph: &Graph, n: usize, dim: usize, var_block: &[usize]) -> Vec<usize> {
    let mut block = vec![GLOBAL; dim];
    block[..n].copy_from_slice(var_block);
    for (c, b) in block.iter_mut().enumerate().skip(n) {
        let (mut lo, mut hi) = (GLOBAL, 0usize);
        for &v in graph.neighbours(c) {
            if v < n && var_block[v] != GLOBAL {
                lo = lo.min(var_block[v]);
                hi = hi.max(var_block[v]);
            }
        }
        if lo != GLOBAL && hi - lo <= 1 {
            *b = lo;
        }
    }
    block
}

/// Appends the vertices `set` to `order` in approximate-minimum-degree order of the
/// subgraph they induce.
fn append_amd(graph: &Graph, set: &[usize], local: &mut [usize], order: &mut Vec<usize>) {
    let k = set.len();
    if k <= 2 {
        order.extend_from_slice(set);
        return;
    }
    for (i, &v) in set.iter().enumerate() {
        local[v] = i;
    }
    // full symmetric pattern of the induced subgraph, rows sorted, diagonal included
    let mut col_ptr = vec![0usize; k + 1];
    let mut rows = Vec::new();
    for (i, &v) in set.iter().enumerate() {
        let begin = rows.len();
        rows.push(i);
        for &u in graph.neighbours(v) {
            if local[u] != GLOBAL {
                rows.push(local[u]);
            }
        }
        rows[begin..].sort_unstable();
        let mut kept = begin;
        for r in begin..rows.len() {
            if r == begin || rows[r] != rows[kept - 1] {
                rows[kept] = rows[r];
                kept += 1;
            }
        }
        rows.truncate(kept);
        col_ptr[i + 1] = rows.len();
    }
    let pattern = SymbolicSparseColMatRef::new_checked(k, k, &col_ptr, None, &rows);
    let mut perm = vec![0usize; k];
    let mut perm_inv = vec![0usize; k];
    let mut mem = MemBuffer::new(amd::order_scratch::<usize>(k, rows.len()));
    let ok = amd::order(
        &mut perm,
        &mut perm_inv,
        pattern,
        amd::Control::default(),
        MemStack::new(&mut mem),
    )
    .is_ok();
    for &v in set {
        local[v] = GLOBAL;
    }
    if ok {
        order.extend(perm.iter().map(|&i| set[i]));
    } else {
        order.extend_from_slice(set);
    }
}

struct Dissection<'a> {
    graph: &'a Graph,
    block: Vec<usize>,
    /// Marks vertices already placed as separators.
    separated: Vec<bool>,
    local: Vec<usize>,
    leaf_blocks: usize,
    order: Vec<usize>,
}

impl Dissection<'_> {
    /// Orders the not yet separated vertices of blocks `lo..hi` (`members`).
    fn dissect(&mut self, lo: usize, hi: usize, members: Vec<usize>) {
        if hi - lo <= self.leaf_blocks {
            let mut local = std::mem::take(&mut self.local);
            append_amd(self.graph, &members, &mut local, &mut self.order);
            self.local = local;
            return;
        }
        let mid = lo + (hi - lo) / 2;
        let is_left = |b: usize| b < mid;
        // boundary vertices on each side of the cut
        let (mut left_edge, mut right_edge) = (Vec::new(), Vec::new());
        for &v in &members {
            let side = is_left(self.block[v]);
            let crosses = self.graph.neighbours(v).iter().any(|&u| {
                let b = self.block[u];
                b != GLOBAL && b >= lo && b < hi && !self.separated[u] && is_left(b) != side
            });
            if crosses {
                if side {
                    left_edge.push(v)
                } else {
                    right_edge.push(v)
                }
            }
        }
        let sep = if left_edge.len() < right_edge.len() {
            left_edge
        } else {
            right_edge
        };
        for &v in &sep {
            self.separated[v] = true;
        }
        let (left, right): (Vec<usize>, Vec<usize>) = members
            .into_iter()
            .filter(|&v| !self.separated[v])
            .partition(|&v| is_left(self.block[v]));
        self.dissect(lo, mid, left);
        self.dissect(mid, hi, right);
        let mut local = std::mem::take(&mut self.local);
        append_amd(self.graph, &sep, &mut local, &mut self.order);
        self.local = local;
    }
}

/// Leaf size (in blocks) of [`chain_dissection`]: on the 50-interval gait KKT, leaves of 1,
/// 2 and 4 intervals gave factors of 16.8, 14.7 and 15.0 million entries (minimum degree
/// alone: 25.5 million with the Hessian pattern, 51.2 million without).
pub const LEAF_BLOCKS: usize = 2;

/// Chain position of every variable from `blocks` (`GLOBAL` for unlisted and global ones),
/// with variables whose Hessian neighbours lie in more than three distinct blocks, or in
/// blocks more than one apart from their own, made global: e.g. a cost normalised by the
/// distance travelled couples the first and last positions to every interval.
pub fn variable_blocks(n: usize, blocks: &BlockStructure, hessian: &Sparsity) -> Vec<usize> {
    let mut var_block = vec![GLOBAL; n];
    for (k, vars) in blocks.blocks.iter().enumerate() {
        for &v in vars {
            var_block[v] = k;
        }
    }
    let mut reach: Vec<Vec<usize>> = vec![Vec::new(); n];
    for (&r, &c) in hessian.rows.iter().zip(&hessian.cols) {
        if var_block[c] != GLOBAL {
            reach[r].push(var_block[c]);
        }
        if var_block[r] != GLOBAL {
            reach[c].push(var_block[r]);
        }
    }
    // first the hubs (many blocks), then whichever end of a remaining long edge
    let mut hub = vec![false; n];
    for (v, r) in reach.iter_mut().enumerate() {
        r.sort_unstable();
        r.dedup();
        hub[v] = r.len() > 3;
    }
    for v in 0..n {
        if hub[v] {
            var_block[v] = GLOBAL;
        }
    }
    for (&r, &c) in hessian.rows.iter().zip(&hessian.cols) {
        let (br, bc) = (var_block[r], var_block[c]);
        if br != GLOBAL && bc != GLOBAL && br.abs_diff(bc) > 1 {
            var_block[r] = GLOBAL;
        }
    }
    var_block
}

/// Nested-dissection ordering along a chain of blocks for the KKT matrix given by its lower
/// triangle (`dim` = n + m; vertices `0..n` are variables, `n..dim` constraints).
/// `var_block[i]` is the chain position of variable `i` (`GLOBAL` for variables coupled to
/// the whole chain, see [`variable_blocks`]); blocks must couple only with their neighbours
/// in the chain. Returns `perm` with `perm[k]` = the vertex eliminated `k`-th.
pub fn chain_dissection(
    dim: usize,
    col_ptr: &[usize],
    row_idx: &[usize],
    var_block: &[usize],
    leaf_blocks: usize,
) -> Vec<usize> {
    let n = var_block.len();
    let graph = Graph::from_lower(dim, col_ptr, row_idx);
    let block = vertex_blocks(&graph, n, dim, var_block);
    let n_blocks = block
        .iter()
        .filter(|&&b| b != GLOBAL)
        .max()
        .map_or(0, |&b| b + 1);
    let (members, globals): (Vec<usize>, Vec<usize>) = (0..dim).partition(|&v| block[v] != GLOBAL);
    let mut d = Dissection {
        graph: &graph,
        block,
        separated: vec![false; dim],
        local: vec![GLOBAL; dim],
        leaf_blocks: leaf_blocks.max(1),
        order: Vec::with_capacity(dim),
    };
    d.dissect(0, n_blocks, members);
    let mut local = std::mem::take(&mut d.local);
    append_amd(&graph, &globals, &mut local, &mut d.order);
    d.order
}

/// The elimination order of `pattern` (a KKT matrix whose Lagrangian Hessian pattern is
/// `hessian`): chain dissection along `blocks` when given, None (the linear solver's
/// minimum degree) otherwise.
pub fn kkt_ordering(
    blocks: Option<&BlockStructure>,
    hessian: &Sparsity,
    pattern: &KktPattern,
) -> Option<Vec<usize>> {
    let var_block = variable_blocks(pattern.n, blocks?, hessian);
    Some(chain_dissection(
        pattern.dim,
        &pattern.col_ptr,
        &pattern.row_idx,
        &var_block,
        LEAF_BLOCKS,
    ))
}

/// The chain of blocks the KKT ordering `choice` uses for `nlp`: its declared blocks under
/// `Auto`, none under `MinimumDegree`.
pub fn ordering_blocks(nlp: &dyn Nlp, choice: KktOrdering) -> Option<BlockStructure> {
    match choice {
        KktOrdering::Auto => nlp.blocks(),
        KktOrdering::MinimumDegree => None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// KKT pattern (lower CSC) of a chain of `nb` blocks of 3 variables with one constraint
    /// per block touching its 3 variables and the first variable of the next block, a
    /// periodicity constraint joining the first and the last block, and a global variable
    /// (last) in every block constraint.
    fn chain(nb: usize) -> (usize, usize, Vec<usize>, Vec<usize>, Vec<usize>) {
        let n = 3 * nb + 1;
        let m = nb + 1;
        let dim = n + m;
        let global = 3 * nb;
        let mut cols: Vec<Vec<usize>> = (0..dim).map(|c| vec![c]).collect();
        for k in 0..nb {
            let row = n + k;
            let mut vars = vec![3 * k, 3 * k + 1, 3 * k + 2, global];
            if k + 1 < nb {
                vars.push(3 * (k + 1));
            }
            for v in vars {
                cols[v].push(row);
            }
        }
        cols[0].push(n + nb);
        cols[3 * (nb - 1) + 2].push(n + nb);
        let mut col_ptr = vec![0];
        let mut row_idx = Vec::new();
        for c in cols {
            row_idx.extend(c);
            col_ptr.push(row_idx.len());
        }
        let mut var_block: Vec<usize> = (0..3 * nb).map(|v| v / 3).collect();
        var_block.push(GLOBAL);
        (n, dim, col_ptr, row_idx, var_block)
    }

    #[test]
    fn dissection_is_a_permutation_with_the_middle_boundary_and_globals_last() {
        let nb = 8;
        let (n, dim, col_ptr, row_idx, var_block) = chain(nb);
        let perm = chain_dissection(dim, &col_ptr, &row_idx, &var_block, 1);
        let mut seen = vec![false; dim];
        for &v in &perm {
            assert!(!seen[v], "vertex {v} twice");
            seen[v] = true;
        }
        assert!(seen.iter().all(|&s| s));
        let pos = |v: usize| perm.iter().position(|&p| p == v).unwrap();
        // the global variable and the periodicity row come last
        let tail: Vec<usize> = perm[dim - 2..].to_vec();
        assert!(
            tail.contains(&(3 * nb)) && tail.contains(&(n + nb)),
            "{perm:?}"
        );
        // the cut between blocks 3 and 4 (the boundary of the top-level dissection) is the
        // first variable of block 4 or the constraint of block 3: ordered after every
        // other block vertex
        let sep = if pos(3 * 4) > pos(n + 3) {
            3 * 4
        } else {
            n + 3
        };
        for v in 0..dim {
            if v != sep && !tail.contains(&v) {
                assert!(
                    pos(v) < pos(sep),
                    "vertex {v} after the separator {sep}: {perm:?}"
                );
            }
        }
    }

    #[test]
    fn dissection_reduces_fill_on_a_long_chain() {
        // elimination in natural order (constraint rows last) fills the constraint block;
        // the dissection keeps the factor linear in the chain length
        let nb = 64;
        let (_, dim, col_ptr, row_idx, var_block) = chain(nb);
        let perm = chain_dissection(dim, &col_ptr, &row_idx, &var_block, 2);
        let fill = |order: &[usize]| -> usize {
            let a =
                SymbolicSparseColMatRef::new_unsorted_checked(dim, dim, &col_ptr, None, &row_idx);
            let mut inv = vec![0; dim];
            for (k, &v) in order.iter().enumerate() {
                inv[v] = k;
            }
            let p = faer::perm::PermRef::new_checked(order, &inv, dim);
            faer::sparse::linalg::cholesky::factorize_symbolic_cholesky(
                a,
                faer::Side::Lower,
                faer::sparse::linalg::cholesky::SymmetricOrdering::Custom(p),
                Default::default(),
            )
            .unwrap()
            .len_val()
        };
        let natural: Vec<usize> = (0..dim).collect();
        let (nd, nat) = (fill(&perm), fill(&natural));
        assert!(nd * 3 < nat, "dissection {nd} vs natural {nat}");
        assert!(nd < 12 * dim, "dissection fill {nd} not linear in {dim}");
    }

    #[test]
    fn hub_variables_and_long_hessian_edges_become_global() {
        // 6 blocks of 2 variables; variable 12 is listed in block 5 but couples (Hessian)
        // to all blocks; variable 1 (block 0) couples to variable 9 (block 4).
        let blocks = BlockStructure {
            blocks: (0..6)
                .map(|k| {
                    let mut v = vec![2 * k, 2 * k + 1];
                    if k == 5 {
                        v.push(12);
                    }
                    v
                })
                .collect(),
            global_variables: vec![],
        };
        let mut rows = Vec::new();
        let mut cols = Vec::new();
        for v in 0..12 {
            rows.push(12);
            cols.push(v);
        }
        rows.push(9);
        cols.push(1);
        rows.push(3);
        cols.push(2);
        let vb = variable_blocks(13, &blocks, &Sparsity::new(rows, cols));
        assert_eq!(vb[12], GLOBAL);
        assert!(vb[1] == GLOBAL || vb[9] == GLOBAL);
        assert_eq!((vb[2], vb[3]), (1, 1));
        assert_eq!(vb[0], 0);
    }
}
