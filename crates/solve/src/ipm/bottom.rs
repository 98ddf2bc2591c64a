//! Elimination of the small supernodes at the bottom of a KKT factor's elimination tree
//! before faer factorises the rest.
//!
//! On the 50-interval gait KKT, 55 k of faer's 82 k supernodes are single constraint rows
//! with no children (a row and the two to six variables it touches), and most of the rest
//! of the small ones sit just above them; each costs faer a few dense-kernel calls of one
//! column plus one small update call per ancestor it touches (~240 k calls of at most four
//! columns per factorisation). [`Bottom`] eliminates every supernode of at most
//! [`BOTTOM_WIDTH`] columns whose descendants are all eliminated too (a subtree closed
//! downwards, so nothing faer factorises ever updates it) with plain loops over dense
//! fronts, and hands faer the Schur complement on the remaining columns, in the same order.
//! The arithmetic is that of a supernodal LDLᵀ without pivoting, so the factor is the same
//! up to rounding; the inertia is the sum of the two parts' (Haynsworth).

/// Widest supernode eliminated here (columns). `stride bench kkt` on the 50-interval gait
/// KKT: see decision 0002 ("Small supernodes eliminated before faer").
pub const BOTTOM_WIDTH: usize = 8;

/// One eliminated supernode: its columns `begin..begin + width` and its dense front, the
/// `(width + below) × width` column-major block of L (unit diagonal implied, D on the
/// diagonal) whose rows are its own columns and then its pattern rows.
#[derive(Clone, Copy, Debug)]
struct Node {
    begin: usize,
    width: usize,
    /// Rows below the supernode's own columns (pattern length).
    below: usize,
    /// Offset of the front in the value array.
    front: usize,
    /// Offset of the pattern rows in `Bottom::rows`.
    rows: usize,
    /// Offset of the update destinations in `Bottom::upd`.
    upd: usize,
}

/// The eliminated bottom of an elimination tree: fronts, where their updates go, and the
/// pattern of the remaining (reduced) matrix.
pub(super) struct Bottom {
    nodes: Vec<Node>,
    /// Pattern rows of every front, concatenated (permuted indices).
    rows: Vec<usize>,
    /// Destination in `vals` of every update entry: per node, for each pattern row j and
    /// each pattern row i ≥ j, the entry (i, j) of the ancestor column that receives it.
    upd: Vec<u32>,
    /// Where each input entry goes in `vals` (`u32::MAX`: ignored, above the diagonal).
    dest: Vec<u32>,
    /// `kept[k]`: permuted column of the reduced matrix's column `k`.
    pub(super) kept: Vec<usize>,
    /// Lower-triangular pattern of the reduced matrix (CSC, `kept.len()` columns).
    pub(super) col_ptr: Vec<usize>,
    pub(super) row_idx: Vec<usize>,
    /// Fronts (`front_len` values) followed by the reduced matrix's values.
    vals: Vec<f64>,
    front_len: usize,
    /// Scratch: D times one row of L21, for the update sums.
    scratch: Vec<f64>,
}

/// Which supernodes are eliminated before faer: a supernode qualifies when it is narrow
/// (at most `max_width` columns), not a root (so faer always has a matrix left), and all its
/// children qualify (children precede their parent, the owner of the first pattern row).
fn qualifying(
    supernodes: &[(usize, usize, Vec<usize>)],
    owner: &[usize],
    max_width: usize,
) -> Vec<bool> {
    let mut elim: Vec<bool> = supernodes
        .iter()
        .map(|s| s.1 - s.0 <= max_width && !s.2.is_empty())
        .collect();
    for (k, s) in supernodes.iter().enumerate() {
        if !elim[k] {
            if let Some(&r) = s.2.first() {
                elim[owner[r]] = false;
            }
        }
    }
    elim
}

/// Lower-triangular CSC pattern of the reduced matrix (`n_kept` columns, kept index `kidx`
/// of each permuted column): the kept part of the input (`col_ptr`, `row_idx`) and every
/// update of an eliminated front (`nodes`, their pattern `rows`) into a kept column.
fn reduced_pattern(
    (col_ptr, row_idx): (&[usize], &[usize]),
    kidx: &[usize],
    nodes: &[Node],
    rows: &[usize],
    n_kept: usize,
) -> (Vec<usize>, Vec<usize>) {
    let mut s_cols: Vec<Vec<usize>> = vec![Vec::new(); n_kept];
    for c in 0..col_ptr.len() - 1 {
        if kidx[c] != usize::MAX {
            for &r in &row_idx[col_ptr[c]..col_ptr[c + 1]] {
                s_cols[kidx[c]].push(kidx[r]);
            }
        }
    }
    for n in nodes {
        let p = &rows[n.rows..n.rows + n.below];
        for (j, &g) in p.iter().enumerate() {
            if kidx[g] != usize::MAX {
                s_cols[kidx[g]].extend(p[j..].iter().map(|&r| kidx[r]));
            }
        }
    }
    let mut s_col_ptr = vec![0usize];
    let mut s_row_idx = Vec::new();
    for col in &mut s_cols {
        col.sort_unstable();
        col.dedup();
        s_row_idx.extend_from_slice(col);
        s_col_ptr.push(s_row_idx.len());
    }
    (s_col_ptr, s_row_idx)
}

impl Bottom {
    /// The bottom of the factor of the permuted lower triangle (`col_ptr`, `row_idx`,
    /// dimension `dim`) whose supernodes are `(first column, end column, pattern rows)` in
    /// elimination order; None when no supernode qualifies. `place[e]` is the permuted
    /// entry of input entry `e` (`usize::MAX`: ignored).
    pub(super) fn new(
        col_ptr: &[usize],
        row_idx: &[usize],
        place: &[usize],
        supernodes: &[(usize, usize, Vec<usize>)],
        max_width: usize,
    ) -> Option<Self> {
        let dim = col_ptr.len() - 1;
        let mut owner = vec![0usize; dim];
        for (k, s) in supernodes.iter().enumerate() {
            owner[s.0..s.1].iter_mut().for_each(|o| *o = k);
        }
        let elim = qualifying(supernodes, &owner, max_width);
        if !elim.iter().any(|&e| e) {
            return None;
        }
        // fronts in elimination order, then the reduced matrix
        let mut nodes = Vec::new();
        let mut rows = Vec::new();
        let mut node_of = vec![usize::MAX; supernodes.len()];
        let mut front = 0;
        for (k, s) in supernodes.iter().enumerate() {
            if elim[k] {
                let mut pattern = s.2.clone();
                pattern.sort_unstable();
                let (width, below) = (s.1 - s.0, pattern.len());
                node_of[k] = nodes.len();
                nodes.push(Node {
                    begin: s.0,
                    width,
                    below,
                    front,
                    rows: rows.len(),
                    upd: 0,
                });
                rows.extend_from_slice(&pattern);
                front += (width + below) * width;
            }
        }
        let front_len = front;
        let mut kidx = vec![usize::MAX; dim];
        let kept: Vec<usize> = (0..dim).filter(|&c| !elim[owner[c]]).collect();
        for (k, &c) in kept.iter().enumerate() {
            kidx[c] = k;
        }
        // local row of global row r in node n's front
        let local = |n: &Node, r: usize| -> usize {
            if r >= n.begin && r < n.begin + n.width {
                r - n.begin
            } else {
                let p = &rows[n.rows..n.rows + n.below];
                n.width
                    + p.binary_search(&r)
                        .expect("a row of an eliminated column lies in its front")
            }
        };
        let (s_col_ptr, s_row_idx) =
            reduced_pattern((col_ptr, row_idx), &kidx, &nodes, &rows, kept.len());
        let s_pos = |r: usize, c: usize| -> usize {
            let (kr, kc) = (kidx[r], kidx[c]);
            let col = &s_row_idx[s_col_ptr[kc]..s_col_ptr[kc + 1]];
            front_len
                + s_col_ptr[kc]
                + col
                    .binary_search(&kr)
                    .expect("a kept entry lies in the reduced pattern")
        };
        let to_index = |d: usize| u32::try_from(d).expect("KKT factor values fit 32-bit indices");
        let permuted_dest: Vec<usize> = (0..dim)
            .flat_map(|c| {
                row_idx[col_ptr[c]..col_ptr[c + 1]]
                    .iter()
                    .map(move |&r| (r, c))
            })
            .map(|(r, c)| {
                let k = owner[c];
                if elim[k] {
                    let n = &nodes[node_of[k]];
                    n.front + (c - n.begin) * (n.width + n.below) + local(n, r)
                } else {
                    s_pos(r, c)
                }
            })
            .collect();
        let dest = place
            .iter()
            .map(|&p| match p {
                usize::MAX => u32::MAX,
                p => to_index(permuted_dest[p]),
            })
            .collect();
        drop(permuted_dest);
        let mut upd = Vec::new();
        let mut starts = Vec::with_capacity(nodes.len());
        for n in &nodes {
            starts.push(upd.len());
            let p = &rows[n.rows..n.rows + n.below];
            for (j, &g) in p.iter().enumerate() {
                let k = owner[g];
                for &r in &p[j..] {
                    let d = if elim[k] {
                        let t = &nodes[node_of[k]];
                        t.front + (g - t.begin) * (t.width + t.below) + local(t, r)
                    } else {
                        s_pos(r, g)
                    };
                    upd.push(to_index(d));
                }
            }
        }
        for (n, s) in nodes.iter_mut().zip(starts) {
            n.upd = s;
        }
        let vals = vec![0.0; front_len + s_row_idx.len()];
        Some(Bottom {
            nodes,
            rows,
            upd,
            dest,
            kept,
            col_ptr: s_col_ptr,
            row_idx: s_row_idx,
            vals,
            front_len,
            scratch: Vec::new(),
        })
    }

    /// Number of eliminated columns.
    pub(super) fn eliminated(&self) -> usize {
        self.nodes.iter().map(|n| n.width).sum()
    }

    /// Loads the input matrix's values (order of the input pattern) and eliminates the
    /// bottom. Returns the counts of positive and negative pivots, or None when a pivot is
    /// zero or not finite. The reduced matrix's values are then [`Bottom::reduced_values`].
    pub(super) fn eliminate(&mut self, values: &[f64]) -> Option<(usize, usize)> {
        self.vals.iter_mut().for_each(|v| *v = 0.0);
        for (&p, &v) in self.dest.iter().zip(values) {
            if p != u32::MAX {
                self.vals[p as usize] += v;
            }
        }
        let (mut pos, mut neg) = (0, 0);
        for n in &self.nodes {
            let (w, p) = (n.width, n.below);
            let ld = w + p;
            let (head, tail) = self.vals.split_at_mut(n.front + ld * w);
            let f = &mut head[n.front..];
            let split = n.front + ld * w;
            // dense LDLᵀ of the front's columns, right-looking, no pivoting
            for c in 0..w {
                let d = f[c * ld + c];
                if d == 0.0 || !d.is_finite() {
                    return None;
                }
                if d > 0.0 {
                    pos += 1;
                } else {
                    neg += 1;
                }
                for i in c + 1..ld {
                    f[c * ld + i] /= d;
                }
                for j in c + 1..w {
                    let ljd = f[c * ld + j] * d;
                    for i in j..ld {
                        f[j * ld + i] -= f[c * ld + i] * ljd;
                    }
                }
            }
            // rank-w update of the ancestors: (i, j) -= Σ_c L_ic D_c L_jc over pattern rows,
            // with the rows of L21 (and of L21 D) laid out contiguously
            self.scratch.resize(2 * p * w, 0.0);
            let (lt, ldt) = self.scratch.split_at_mut(p * w);
            for c in 0..w {
                let d = f[c * ld + c];
                for i in 0..p {
                    lt[i * w + c] = f[c * ld + w + i];
                    ldt[i * w + c] = d * f[c * ld + w + i];
                }
            }
            let upd = &self.upd[n.upd..n.upd + p * (p + 1) / 2];
            let mut k = 0;
            for j in 0..p {
                let tj = &ldt[j * w..(j + 1) * w];
                for i in j..p {
                    let li = &lt[i * w..(i + 1) * w];
                    let s: f64 = li.iter().zip(tj).map(|(a, b)| a * b).sum();
                    tail[upd[k] as usize - split] -= s;
                    k += 1;
                }
            }
        }
        Some((pos, neg))
    }

    /// Values of the reduced matrix (pattern `col_ptr`, `row_idx`) after [`Bottom::eliminate`].
    pub(super) fn reduced_values(&self) -> &[f64] {
        &self.vals[self.front_len..]
    }

    /// Column `c` of node `n`'s front: its pivot, its entries in the node's later columns,
    /// its entries in the pattern rows, and those rows.
    #[inline]
    fn column(&self, n: &Node, c: usize) -> (f64, &[f64], &[f64], &[usize]) {
        let ld = n.width + n.below;
        let lc = &self.vals[n.front + c * ld..n.front + (c + 1) * ld];
        let (l_own, l_pattern) = lc[c + 1..].split_at(n.width - c - 1);
        let pattern = &self.rows[n.rows..n.rows + n.below];
        (lc[c], l_own, l_pattern, pattern)
    }

    /// Forward substitution with the fronts' unit lower triangle, for `nc` right-hand
    /// sides interleaved row by row (`y[r * nc + col]`, permuted order): the `nc` values of
    /// a row share cache lines, so the scattered rows of the fronts are read once for all
    /// columns. `yc` is scratch.
    pub(super) fn forward(&self, y: &mut [f64], nc: usize, yc: &mut Vec<f64>) {
        if nc == 1 {
            return self.forward_one(y);
        }
        yc.resize(nc, 0.0);
        for n in &self.nodes {
            for c in 0..n.width {
                let (_, l_own, l_pattern, pattern) = self.column(n, c);
                let own = (n.begin + c) * nc;
                yc.copy_from_slice(&y[own..own + nc]);
                for (&l, r) in l_own.iter().zip(n.begin + c + 1..) {
                    sub_scaled(&mut y[r * nc..(r + 1) * nc], l, yc);
                }
                for (&l, &r) in l_pattern.iter().zip(pattern) {
                    sub_scaled(&mut y[r * nc..(r + 1) * nc], l, yc);
                }
            }
        }
    }

    /// Division by the fronts' pivots and backward substitution with their transposed unit
    /// lower triangle (after the reduced matrix's solve has set the kept entries), on
    /// right-hand sides interleaved as for [`Bottom::forward`]. `x` is scratch.
    pub(super) fn backward(&self, y: &mut [f64], nc: usize, x: &mut Vec<f64>) {
        if nc == 1 {
            return self.backward_one(y);
        }
        x.resize(nc, 0.0);
        for n in self.nodes.iter().rev() {
            for c in (0..n.width).rev() {
                let (d, l_own, l_pattern, pattern) = self.column(n, c);
                let own = (n.begin + c) * nc;
                for (xv, &t) in x.iter_mut().zip(&y[own..own + nc]) {
                    *xv = t / d;
                }
                for (&l, r) in l_own.iter().zip(n.begin + c + 1..) {
                    sub_scaled(x, l, &y[r * nc..(r + 1) * nc]);
                }
                for (&l, &r) in l_pattern.iter().zip(pattern) {
                    sub_scaled(x, l, &y[r * nc..(r + 1) * nc]);
                }
                y[own..own + nc].copy_from_slice(x);
            }
        }
    }

    /// [`Bottom::forward`] for one right-hand side.
    fn forward_one(&self, y: &mut [f64]) {
        for n in &self.nodes {
            for c in 0..n.width {
                let yc = y[n.begin + c];
                if yc == 0.0 {
                    continue;
                }
                let (_, l_own, l_pattern, pattern) = self.column(n, c);
                for (&l, r) in l_own.iter().zip(n.begin + c + 1..) {
                    y[r] -= l * yc;
                }
                for (&l, &r) in l_pattern.iter().zip(pattern) {
                    y[r] -= l * yc;
                }
            }
        }
    }

    /// [`Bottom::backward`] for one right-hand side.
    fn backward_one(&self, y: &mut [f64]) {
        for n in self.nodes.iter().rev() {
            for c in (0..n.width).rev() {
                let (d, l_own, l_pattern, pattern) = self.column(n, c);
                let mut x = y[n.begin + c] / d;
                for (&l, r) in l_own.iter().zip(n.begin + c + 1..) {
                    x -= l * y[r];
                }
                for (&l, &r) in l_pattern.iter().zip(pattern) {
                    x -= l * y[r];
                }
                y[n.begin + c] = x;
            }
        }
    }
}

/// `dst -= l * src`, element by element (one row of interleaved right-hand sides).
#[inline(always)]
fn sub_scaled(dst: &mut [f64], l: f64, src: &[f64]) {
    for (d, &v) in dst.iter_mut().zip(src) {
        *d -= l * v;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Solution of the dense system `a x = b` (`n × n`, row-major) by Gaussian elimination
    /// with partial pivoting.
    fn dense_solve(mut a: Vec<f64>, mut b: Vec<f64>, n: usize) -> Vec<f64> {
        for k in 0..n {
            let p = (k..n)
                .max_by(|&i, &j| a[i * n + k].abs().total_cmp(&a[j * n + k].abs()))
                .unwrap();
            for c in 0..n {
                a.swap(k * n + c, p * n + c);
            }
            b.swap(k, p);
            for i in k + 1..n {
                let f = a[i * n + k] / a[k * n + k];
                for c in k..n {
                    a[i * n + c] -= f * a[k * n + c];
                }
                b[i] -= f * b[k];
            }
        }
        for k in (0..n).rev() {
            let s: f64 = (k + 1..n).map(|c| a[k * n + c] * b[c]).sum();
            b[k] = (b[k] - s) / a[k * n + k];
        }
        b
    }

    #[test]
    fn fronts_give_the_schur_complement_and_the_solution_of_a_dense_elimination() {
        // A (5 × 5, symmetric, indefinite): a two-column supernode {0, 1} with pattern rows
        // {3, 4} (entry (3, 1) is fill), a one-column supernode {2} with pattern row {3},
        // and the root {3, 4} left to the reduced matrix
        let a = [
            [4.0, 1.0, 0.0, 1.0, 1.0],
            [1.0, 5.0, 0.0, 0.0, 2.0],
            [0.0, 0.0, -3.0, 1.0, 0.0],
            [1.0, 0.0, 1.0, 6.0, 1.0],
            [1.0, 2.0, 0.0, 1.0, 7.0],
        ];
        let col_ptr = [0, 4, 6, 8, 10, 11];
        let row_idx = [0, 1, 3, 4, 1, 4, 2, 3, 3, 4, 4];
        let values: Vec<f64> = (0..5)
            .flat_map(|c| {
                row_idx[col_ptr[c]..col_ptr[c + 1]]
                    .iter()
                    .map(move |&r| (r, c))
            })
            .map(|(r, c)| a[r][c])
            .collect();
        let place: Vec<usize> = (0..values.len()).collect();
        let supernodes = vec![(0, 2, vec![3, 4]), (2, 3, vec![3]), (3, 5, vec![])];
        let mut b = Bottom::new(&col_ptr, &row_idx, &place, &supernodes, 8).unwrap();
        assert_eq!((b.eliminated(), b.kept.clone()), (3, vec![3, 4]));
        // pivots: 4, 5 − 1/4 > 0 and −3 < 0
        assert_eq!(b.eliminate(&values), Some((2, 1)));
        // Schur complement S = A22 − A21 A11⁻¹ A12 on {3, 4}, column by column
        let a11: Vec<f64> = (0..3).flat_map(|r| (0..3).map(move |c| a[r][c])).collect();
        for (k, &c) in [3usize, 4].iter().enumerate() {
            let x = dense_solve(a11.clone(), (0..3).map(|r| a[r][c]).collect(), 3);
            for p in b.col_ptr[k]..b.col_ptr[k + 1] {
                let r = b.kept[b.row_idx[p]];
                let want = a[r][c] - (0..3).map(|i| a[r][i] * x[i]).sum::<f64>();
                let got = b.reduced_values()[p];
                assert!((got - want).abs() < 1e-12, "S({r}, {c}): {got} vs {want}");
            }
        }
        // two right-hand sides, interleaved: fronts forward, the reduced solve, backward
        let rhs = [[1.0, -2.0, 3.0, 0.5, 4.0], [0.0, 1.0, -1.0, 2.0, -3.0]];
        let mut y: Vec<f64> = (0..5).flat_map(|r| [rhs[0][r], rhs[1][r]]).collect();
        let mut scratch = Vec::new();
        b.forward(&mut y, 2, &mut scratch);
        let s: Vec<f64> = {
            let mut s = vec![0.0; 4];
            for k in 0..2 {
                for p in b.col_ptr[k]..b.col_ptr[k + 1] {
                    let r = b.row_idx[p];
                    s[r * 2 + k] = b.reduced_values()[p];
                    s[k * 2 + r] = b.reduced_values()[p];
                }
            }
            s
        };
        for col in 0..2 {
            let z = dense_solve(s.clone(), vec![y[3 * 2 + col], y[4 * 2 + col]], 2);
            y[3 * 2 + col] = z[0];
            y[4 * 2 + col] = z[1];
        }
        b.backward(&mut y, 2, &mut scratch);
        let dense: Vec<f64> = a.iter().flatten().copied().collect();
        for (col, r) in rhs.iter().enumerate() {
            let want = dense_solve(dense.clone(), r.to_vec(), 5);
            for i in 0..5 {
                let got = y[i * 2 + col];
                assert!(
                    (got - want[i]).abs() < 1e-12,
                    "x[{i}] of column {col}: {got} vs {}",
                    want[i]
                );
            }
        }
    }
}
