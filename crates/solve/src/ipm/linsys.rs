//! Sparse symmetric (quasi-definite) KKT linear solvers behind a small trait.
//!
//! The KKT matrix is given by its lower triangle in compressed sparse column form with a
//! fixed pattern: symbolic analysis (fill-reducing ordering, elimination tree, supernodes)
//! happens once in [`KktSolver::analyse`], numeric factorisation every iteration in
//! [`KktSolver::factor`], which also reports the inertia (signs of the pivots of LDLᵀ).
// Index loops over several parallel arrays are clearer than zipped iterators here.
#![allow(clippy::needless_range_loop)]

use faer::dyn_stack::{MemBuffer, MemStack, StackReq};
use faer::linalg::cholesky::lblt::factor::LbltParams;
use faer::linalg::cholesky::ldlt::factor::{LdltParams, LdltRegularization};
use faer::perm::PermRef;
use faer::sparse::linalg::cholesky::{
    factorize_symbolic_cholesky,
    supernodal::{SupernodalIntranodeLbltRef, SupernodalLdltRef},
    CholeskySymbolicParams, IntranodeLbltRef, LdltRef, SymbolicCholesky, SymbolicCholeskyRaw,
    SymmetricOrdering,
};
use faer::sparse::linalg::SupernodalThreshold;

use super::bottom::{Bottom, BOTTOM_WIDTH};
use crate::pivots::Inertia;
use faer::sparse::{SparseColMatRef, SymbolicSparseColMatRef};
use faer::{Conj, MatMut, Par, Side, Spec};
use thiserror::Error;

/// Errors of a KKT linear solver.
#[derive(Debug, Clone, Error, PartialEq)]
pub enum LinearSolverError {
    /// The pattern was rejected by the symbolic analysis.
    #[error("symbolic analysis of the KKT matrix failed: {0}")]
    Symbolic(String),
    /// `factor` or `solve` called before `analyse` / `factor`.
    #[error("KKT solver used before {0}")]
    NotReady(&'static str),
}

/// A sparse symmetric linear solver for the KKT system (lower triangle, CSC).
pub trait KktSolver: Send {
    /// Short name for logs and benchmarks.
    fn name(&self) -> &str;
    /// Symbolic analysis of the fixed lower-triangular pattern (dimension `dim`), with the
    /// elimination order `ordering` (`ordering[k]` = row eliminated `k`-th) or, if None, the
    /// solver's own fill-reducing ordering.
    fn analyse(
        &mut self,
        dim: usize,
        col_ptr: &[usize],
        row_idx: &[usize],
        ordering: Option<&[usize]>,
    ) -> Result<(), LinearSolverError>;
    /// Numeric factorisation with the given values (same order as `row_idx`); returns the
    /// inertia of the matrix.
    fn factor(&mut self, values: &[f64]) -> Result<Inertia, LinearSolverError>;
    /// Solves in place with the last factorisation.
    fn solve(&mut self, rhs: &mut [f64]) -> Result<(), LinearSolverError>;
    /// Solves in place for `ncols` right-hand sides stored one after another (column-major,
    /// `rhs.len() = ncols × dim`); solvers that can do better than one solve per column
    /// override it.
    fn solve_many(&mut self, rhs: &mut [f64], ncols: usize) -> Result<(), LinearSolverError> {
        if ncols == 0 {
            return Ok(());
        }
        let dim = rhs.len() / ncols;
        for col in rhs.chunks_mut(dim) {
            self.solve(col)?;
        }
        Ok(())
    }
    /// Number of nonzeros in the factor L (0 if unknown).
    fn factor_nnz(&self) -> usize {
        0
    }
}

/// `perm` inverted, after checking it is a permutation.
fn inverse_permutation(perm: &[usize]) -> Result<Vec<usize>, LinearSolverError> {
    let mut inv = vec![usize::MAX; perm.len()];
    for (k, &v) in perm.iter().enumerate() {
        if v >= perm.len() || inv[v] != usize::MAX {
            return Err(LinearSolverError::Symbolic(format!(
                "the ordering is not a permutation of 0..{} (entry {k} = {v})",
                perm.len()
            )));
        }
        inv[v] = k;
    }
    Ok(inv)
}

/// faer's ordering choice: the given permutation (with its inverse) or AMD.
fn symmetric_ordering<'a>(
    perm: Option<&'a [usize]>,
    inverse: Option<&'a [usize]>,
) -> SymmetricOrdering<'a, usize> {
    match (perm, inverse) {
        (Some(p), Some(i)) => SymmetricOrdering::Custom(PermRef::new_checked(p, i, p.len())),
        _ => SymmetricOrdering::Amd,
    }
}

/// The pattern of the transpose of a square CSC pattern (`col_ptr`, `row_idx`): the upper
/// triangle of a symmetric matrix given by its lower one.
fn transpose_pattern(col_ptr: &[usize], row_idx: &[usize]) -> (Vec<usize>, Vec<usize>) {
    let dim = col_ptr.len() - 1;
    let mut t_ptr = vec![0usize; dim + 1];
    for &r in row_idx {
        t_ptr[r + 1] += 1;
    }
    for k in 0..dim {
        t_ptr[k + 1] += t_ptr[k];
    }
    let mut next = t_ptr.clone();
    let mut t_idx = vec![0usize; row_idx.len()];
    for c in 0..dim {
        for &r in &row_idx[col_ptr[c]..col_ptr[c + 1]] {
            t_idx[next[r]] = c;
            next[r] += 1;
        }
    }
    (t_ptr, t_idx)
}

/// faer's symbolic analysis of a lower-triangular CSC pattern already in elimination order
/// (supernodal whatever its size when `supernodal`, else as faer's flop heuristic chooses).
fn symbolic_in_order(
    col_ptr: &[usize],
    row_idx: &[usize],
    supernodal: bool,
) -> Result<SymbolicCholesky<usize>, LinearSolverError> {
    let dim = col_ptr.len() - 1;
    let (up_ptr, up_idx) = transpose_pattern(col_ptr, row_idx);
    let upper = SymbolicSparseColMatRef::new_unsorted_checked(dim, dim, &up_ptr, None, &up_idx);
    let mut params = CholeskySymbolicParams::default();
    if supernodal {
        params.supernodal_flop_ratio_threshold = SupernodalThreshold::FORCE_SUPERNODAL;
    }
    factorize_symbolic_cholesky(upper, Side::Upper, SymmetricOrdering::Identity, params)
        .map_err(|e| LinearSolverError::Symbolic(format!("{e:?}")))
}

/// Supernodes of a supernodal symbolic factor as (first column, end column, pattern rows);
/// empty for a simplicial one.
fn supernode_list(sym: &SymbolicCholesky<usize>) -> Vec<(usize, usize, Vec<usize>)> {
    match sym.raw() {
        SymbolicCholeskyRaw::Supernodal(s) => (0..s.n_supernodes())
            .map(|k| {
                let (b, e) = (s.supernode_begin()[k], s.supernode_end()[k]);
                (b, e, s.supernode(k).pattern().to_vec())
            })
            .collect(),
        SymbolicCholeskyRaw::Simplicial(_) => Vec::new(),
    }
}

/// A lower-triangular CSC matrix symmetrically permuted once, in the symbolic analysis: the
/// pattern of P A Pᵀ, where each input entry goes, and room for its values. faer permutes
/// its input on every numeric factorisation when it holds the ordering (~4 % of a
/// factorisation of the 50-interval gait KKT, `stride bench kkt`); with the map that
/// becomes one scatter of the values.
struct Permuted {
    /// `order[k]`: the input row and column eliminated `k`-th.
    order: Vec<usize>,
    /// Pattern of the permuted lower triangle.
    col_ptr: Vec<usize>,
    row_idx: Vec<usize>,
    /// Position in the permuted pattern of each input entry; `usize::MAX` for entries above
    /// the diagonal, which a lower-triangle factorisation ignores.
    place: Vec<usize>,
    /// Values of the permuted lower triangle.
    values: Vec<f64>,
    /// Right-hand sides in elimination order.
    rhs: Vec<f64>,
}

/// Where entry `k` (elimination order) of right-hand side `col` sits in `Permuted::rhs`:
/// `k * row_stride + col * col_stride`. Column after column for faer's solve; interleaved
/// row by row for the bottom's substitutions, which read scattered rows, all columns at once.
#[derive(Clone, Copy)]
struct RhsLayout {
    row_stride: usize,
    col_stride: usize,
}

impl Permuted {
    /// The permuted pattern of the lower triangle (`col_ptr`, `row_idx`) under `order`
    /// (`inverse[v]` = position of row `v` in `order`).
    fn new(col_ptr: &[usize], row_idx: &[usize], order: &[usize], inverse: &[usize]) -> Self {
        let dim = order.len();
        let target = |c: usize, r: usize| {
            let (pr, pc) = (inverse[r], inverse[c]);
            (pr.max(pc), pr.min(pc))
        };
        let mut counts = vec![0usize; dim + 1];
        for c in 0..dim {
            for &r in &row_idx[col_ptr[c]..col_ptr[c + 1]] {
                if r >= c {
                    counts[target(c, r).1 + 1] += 1;
                }
            }
        }
        for k in 0..dim {
            counts[k + 1] += counts[k];
        }
        let p_col_ptr = counts.clone();
        let mut next = counts;
        let mut p_row_idx = vec![0usize; p_col_ptr[dim]];
        let mut place = vec![usize::MAX; row_idx.len()];
        for c in 0..dim {
            for e in col_ptr[c]..col_ptr[c + 1] {
                let r = row_idx[e];
                if r >= c {
                    let (pr, pc) = target(c, r);
                    place[e] = next[pc];
                    p_row_idx[next[pc]] = pr;
                    next[pc] += 1;
                }
            }
        }
        let values = vec![0.0; p_row_idx.len()];
        Permuted {
            order: order.to_vec(),
            col_ptr: p_col_ptr,
            row_idx: p_row_idx,
            place,
            values,
            rhs: Vec::new(),
        }
    }

    /// Copies the right-hand sides `rhs` (column after column, input order) into `self.rhs`
    /// in elimination order with `layout`.
    fn permute_rhs(&mut self, rhs: &[f64], ncols: usize, layout: RhsLayout) {
        let dim = self.order.len();
        self.rhs.resize(dim * ncols, 0.0);
        for (col, src) in rhs.chunks(dim).enumerate() {
            for (k, &v) in self.order.iter().enumerate() {
                self.rhs[k * layout.row_stride + col * layout.col_stride] = src[v];
            }
        }
    }

    /// Copies `self.rhs` (elimination order, `layout`) back into `rhs` in input order.
    fn unpermute_rhs(&self, rhs: &mut [f64], layout: RhsLayout) {
        for (col, dst) in rhs.chunks_mut(self.order.len()).enumerate() {
            for (k, &v) in self.order.iter().enumerate() {
                dst[v] = self.rhs[k * layout.row_stride + col * layout.col_stride];
            }
        }
    }

    /// Copies the input values into the permuted pattern.
    fn scatter(&mut self, values: &[f64]) {
        for (&p, &v) in self.place.iter().zip(values) {
            if p != usize::MAX {
                self.values[p] = v;
            }
        }
    }
}

/// Supernodes (columns, for a simplicial factor), floating-point operations of one numeric
/// factorisation (Σ over columns of the squared count of entries below the diagonal, the
/// usual Cholesky count) and entries of L of a symbolic factor.
fn symbolic_stats(sym: &SymbolicCholesky<usize>) -> (usize, f64, usize) {
    let mut flops = 0.0;
    let units = match sym.raw() {
        SymbolicCholeskyRaw::Supernodal(s) => {
            for k in 0..s.n_supernodes() {
                let below = s.supernode(k).pattern().len();
                let ncols = s.supernode_end()[k] - s.supernode_begin()[k];
                // the supernode's columns have below + ncols − 1, …, below entries below
                // their diagonals
                for c in below..below + ncols {
                    flops += (c * c) as f64;
                }
            }
            s.n_supernodes()
        }
        SymbolicCholeskyRaw::Simplicial(s) => {
            let cp = s.col_ptr();
            for j in 0..s.ncols() {
                let c = (cp[j + 1] - cp[j]).saturating_sub(1) as f64;
                flops += c * c;
            }
            s.ncols()
        }
    };
    (units, flops, sym.len_val())
}

/// faer's sparse LDLᵀ (AMD or a given ordering, supernodal or simplicial by faer's flop heuristic),
/// without pivoting: meant for quasi-definite (regularised) KKT matrices.
pub struct FaerLdlt {
    dim: usize,
    col_ptr: Vec<usize>,
    row_idx: Vec<usize>,
    /// The matrix in the given elimination order, when there is one (faer then factorises
    /// it as is, without permuting the input on every factorisation).
    permuted: Option<Permuted>,
    /// The small supernodes at the bottom of the elimination tree, eliminated before faer
    /// factorises the rest (with a given ordering only).
    bottom: Option<Bottom>,
    /// Supernodes, floating-point operations and L entries of the whole factor.
    stats: Option<(usize, f64, usize)>,
    /// One row of interleaved right-hand sides (scratch of the bottom's substitutions).
    row_scratch: Vec<f64>,
    /// Right-hand sides of the reduced matrix (after the bottom's forward substitution).
    reduced_rhs: Vec<f64>,
    /// faer's symbolic factor of what it factorises (the reduced matrix with a bottom).
    symbolic: Option<SymbolicCholesky<usize>>,
    l_values: Vec<f64>,
    /// Scratch for the numeric factorisation.
    buffer: MemBuffer,
    /// Scratch for solves, and the column count it was sized for.
    solve_buffer: (MemBuffer, usize),
    factored: bool,
}

impl Default for FaerLdlt {
    fn default() -> Self {
        FaerLdlt {
            dim: 0,
            col_ptr: Vec::new(),
            row_idx: Vec::new(),
            permuted: None,
            bottom: None,
            stats: None,
            row_scratch: Vec::new(),
            reduced_rhs: Vec::new(),
            symbolic: None,
            l_values: Vec::new(),
            buffer: MemBuffer::new(StackReq::empty()),
            solve_buffer: (MemBuffer::new(StackReq::empty()), 0),
            factored: false,
        }
    }
}

impl FaerLdlt {
    /// A solver with no analysed pattern yet.
    pub fn new() -> Self {
        Self::default()
    }

    /// Supernodes (columns, for a simplicial factor) and floating-point operations of one
    /// numeric factorisation (Σ over columns of the squared count of entries below the
    /// diagonal, the usual Cholesky count), or None before `analyse`.
    pub fn factor_stats(&self) -> Option<(usize, f64)> {
        self.stats.map(|(units, flops, _)| (units, flops))
    }

    /// Columns eliminated before faer (the bottom of the elimination tree), 0 without.
    pub fn bottom_columns(&self) -> usize {
        self.bottom.as_ref().map_or(0, Bottom::eliminated)
    }

    /// Inertia from the signs of D, or None when a pivot is not finite. A non-finite entry
    /// L_ij of the factor reaches the pivot D_i through the update L_ij² D_j (or is itself
    /// a quotient by a zero pivot), so checking D finds a non-finite factor without reading
    /// all of L (14.7 M entries on the 50-interval gait KKT).
    fn inertia_of_d(&self) -> Option<Inertia> {
        let mut inertia = Inertia::default();
        let mut finite = true;
        let mut count = |d: f64| {
            finite &= d.is_finite();
            if d > 0.0 {
                inertia.positive += 1
            } else if d < 0.0 {
                inertia.negative += 1
            } else {
                inertia.zero += 1
            }
        };
        let sym = self.symbolic.as_ref()?;
        match sym.raw() {
            SymbolicCholeskyRaw::Supernodal(s) => {
                let l = SupernodalLdltRef::new(s, &self.l_values);
                for k in 0..s.n_supernodes() {
                    let node = l.supernode(k);
                    let v = node.val();
                    for j in 0..v.ncols() {
                        count(v[(j, j)]);
                    }
                }
            }
            SymbolicCholeskyRaw::Simplicial(s) => {
                let cp = s.col_ptr();
                let ri = s.row_idx();
                for j in 0..s.ncols() {
                    for p in cp[j]..cp[j + 1] {
                        if ri[p] == j {
                            count(self.l_values[p]);
                        }
                    }
                }
            }
        }
        finite.then_some(inertia)
    }
}

impl KktSolver for FaerLdlt {
    fn name(&self) -> &str {
        "faer-ldlt"
    }

    fn analyse(
        &mut self,
        dim: usize,
        col_ptr: &[usize],
        row_idx: &[usize],
        ordering: Option<&[usize]>,
    ) -> Result<(), LinearSolverError> {
        self.dim = dim;
        self.col_ptr = col_ptr.to_vec();
        self.row_idx = row_idx.to_vec();
        let a = SymbolicSparseColMatRef::new_unsorted_checked(
            dim,
            dim,
            &self.col_ptr,
            None,
            &self.row_idx,
        );
        let sym = match ordering {
            Some(order) => {
                let inverse = inverse_permutation(order)?;
                let permuted = Permuted::new(col_ptr, row_idx, order, &inverse);
                // supernodal for the bottom's partition even where faer would factorise a
                // small matrix column by column
                let full = symbolic_in_order(&permuted.col_ptr, &permuted.row_idx, true)?;
                self.stats = Some(symbolic_stats(&full));
                self.bottom = Bottom::new(
                    &permuted.col_ptr,
                    &permuted.row_idx,
                    &permuted.place,
                    &supernode_list(&full),
                    BOTTOM_WIDTH,
                );
                self.permuted = Some(permuted);
                match &self.bottom {
                    Some(b) => symbolic_in_order(&b.col_ptr, &b.row_idx, false)?,
                    None => full,
                }
            }
            None => {
                self.permuted = None;
                self.bottom = None;
                let sym = factorize_symbolic_cholesky(
                    a,
                    Side::Lower,
                    SymmetricOrdering::Amd,
                    CholeskySymbolicParams::default(),
                )
                .map_err(|e| LinearSolverError::Symbolic(format!("{e:?}")))?;
                self.stats = Some(symbolic_stats(&sym));
                sym
            }
        };
        self.l_values = vec![0.0; sym.len_val()];
        self.buffer = MemBuffer::new(
            sym.factorize_numeric_ldlt_scratch::<f64>(Par::Seq, Spec::<LdltParams, f64>::default()),
        );
        // solve scratch depends on the pattern: sized again on the next solve
        self.solve_buffer = (MemBuffer::new(StackReq::empty()), 0);
        self.symbolic = Some(sym);
        self.factored = false;
        Ok(())
    }

    fn factor(&mut self, values: &[f64]) -> Result<Inertia, LinearSolverError> {
        let sym = self
            .symbolic
            .as_ref()
            .ok_or(LinearSolverError::NotReady("analyse"))?;
        // the pivots of the bottom's columns, when there is a bottom
        let mut bottom_pivots = (0, 0);
        let (fdim, col_ptr, row_idx, values) = match (self.permuted.as_mut(), self.bottom.as_mut())
        {
            (Some(p), bottom) => {
                assert_eq!(
                    values.len(),
                    p.place.len(),
                    "KKT values do not match the pattern"
                );
                match bottom {
                    Some(b) => match b.eliminate(values) {
                        Some(pivots) => {
                            bottom_pivots = pivots;
                            let (col_ptr, row_idx) = (&b.col_ptr, &b.row_idx);
                            (b.kept.len(), col_ptr, row_idx, b.reduced_values())
                        }
                        None => {
                            self.factored = false;
                            return Ok(Inertia::singular(self.dim));
                        }
                    },
                    None => {
                        p.scatter(values);
                        (self.dim, &p.col_ptr, &p.row_idx, &p.values[..])
                    }
                }
            }
            (None, _) => (self.dim, &self.col_ptr, &self.row_idx, values),
        };
        let a_sym =
            SymbolicSparseColMatRef::new_unsorted_checked(fdim, fdim, col_ptr, None, row_idx);
        let a = SparseColMatRef::new(a_sym, values);
        let stack = MemStack::new(&mut self.buffer);
        let res = sym.factorize_numeric_ldlt(
            &mut self.l_values,
            a,
            Side::Lower,
            LdltRegularization::default(),
            Par::Seq,
            stack,
            Spec::<LdltParams, f64>::default(),
        );
        // a failed factorisation or a non-finite pivot: singular, no solves
        let inertia = if res.is_ok() {
            self.inertia_of_d().map(|i| Inertia {
                positive: i.positive + bottom_pivots.0,
                negative: i.negative + bottom_pivots.1,
                zero: i.zero,
            })
        } else {
            None
        };
        self.factored = inertia.is_some();
        Ok(inertia.unwrap_or(Inertia::singular(self.dim)))
    }

    fn solve(&mut self, rhs: &mut [f64]) -> Result<(), LinearSolverError> {
        self.solve_many(rhs, 1)
    }

    fn solve_many(&mut self, rhs: &mut [f64], ncols: usize) -> Result<(), LinearSolverError> {
        if ncols == 0 {
            return Ok(());
        }
        if !self.factored {
            return Err(LinearSolverError::NotReady("a successful factorisation"));
        }
        let sym = self
            .symbolic
            .as_ref()
            .ok_or(LinearSolverError::NotReady("analyse"))?;
        if self.solve_buffer.1 < ncols {
            self.solve_buffer = (
                MemBuffer::new(sym.solve_in_place_scratch::<f64>(ncols, Par::Seq)),
                ncols,
            );
        }
        // One pass over the factor for all columns (blocked triangular solves) instead of one
        // pass per column; the factor of the 50-interval gait KKT is 14.7 M entries.
        let l = LdltRef::new(sym, &self.l_values);
        let stack = MemStack::new(&mut self.solve_buffer.0);
        let dim = self.dim;
        match self.permuted.as_mut() {
            Some(p) => {
                let layout = match self.bottom {
                    Some(_) => RhsLayout {
                        row_stride: ncols,
                        col_stride: 1,
                    },
                    None => RhsLayout {
                        row_stride: 1,
                        col_stride: dim,
                    },
                };
                p.permute_rhs(rhs, ncols, layout);
                match &self.bottom {
                    Some(b) => {
                        // bottom forward, the reduced matrix's solve on the kept entries
                        // (gathered column after column for faer), bottom pivots and backward
                        b.forward(&mut p.rhs, ncols, &mut self.row_scratch);
                        let m = b.kept.len();
                        self.reduced_rhs.resize(m * ncols, 0.0);
                        for (col, z) in self.reduced_rhs.chunks_mut(m).enumerate() {
                            for (zk, &c) in z.iter_mut().zip(&b.kept) {
                                *zk = p.rhs[c * ncols + col];
                            }
                        }
                        let mat = MatMut::from_column_major_slice_mut(
                            &mut self.reduced_rhs[..],
                            m,
                            ncols,
                        );
                        l.solve_in_place_with_conj(Conj::No, mat, Par::Seq, stack);
                        for (col, z) in self.reduced_rhs.chunks(m).enumerate() {
                            for (&zk, &c) in z.iter().zip(&b.kept) {
                                p.rhs[c * ncols + col] = zk;
                            }
                        }
                        b.backward(&mut p.rhs, ncols, &mut self.row_scratch);
                    }
                    None => {
                        let mat = MatMut::from_column_major_slice_mut(&mut p.rhs[..], dim, ncols);
                        l.solve_in_place_with_conj(Conj::No, mat, Par::Seq, stack);
                    }
                }
                p.unpermute_rhs(rhs, layout);
            }
            None => {
                let mat = MatMut::from_column_major_slice_mut(rhs, dim, ncols);
                l.solve_in_place_with_conj(Conj::No, mat, Par::Seq, stack);
            }
        }
        Ok(())
    }

    fn factor_nnz(&self) -> usize {
        self.stats.map_or(0, |(_, _, nnz)| nnz)
    }
}

/// faer's sparse LBLᵀ with Bunch–Kaufman pivoting inside each supernode (forced
/// supernodal, AMD ordering): 1×1 and 2×2 pivots keep the factorisation stable on
/// indefinite KKT matrices, so the inertia it reports does not depend on a tiny δ_c making
/// the matrix quasi-definite. Pivots are not delayed across supernodes.
pub struct FaerLblt {
    dim: usize,
    col_ptr: Vec<usize>,
    row_idx: Vec<usize>,
    symbolic: Option<SymbolicCholesky<usize>>,
    l_values: Vec<f64>,
    subdiag: Vec<f64>,
    perm_fwd: Vec<usize>,
    perm_inv: Vec<usize>,
    buffer: MemBuffer,
    factored: bool,
}

impl Default for FaerLblt {
    fn default() -> Self {
        FaerLblt {
            dim: 0,
            col_ptr: Vec::new(),
            row_idx: Vec::new(),
            symbolic: None,
            l_values: Vec::new(),
            subdiag: Vec::new(),
            perm_fwd: Vec::new(),
            perm_inv: Vec::new(),
            buffer: MemBuffer::new(StackReq::empty()),
            factored: false,
        }
    }
}

impl FaerLblt {
    /// A solver with no analysed pattern yet.
    pub fn new() -> Self {
        Self::default()
    }

    fn lblt_params() -> Spec<LbltParams, f64> {
        // faer's default: Bunch–Kaufman partial pivoting with a diagonal search
        Spec::default()
    }

    /// Inertia of the block-diagonal B (1×1 and 2×2 blocks) of the last factorisation.
    fn inertia_of_b(&self) -> Inertia {
        let mut inertia = Inertia::default();
        let Some(sym) = &self.symbolic else {
            return inertia;
        };
        let SymbolicCholeskyRaw::Supernodal(s) = sym.raw() else {
            return inertia;
        };
        let perm = PermRef::new_checked(&self.perm_fwd, &self.perm_inv, self.dim);
        let l = SupernodalIntranodeLbltRef::new(s, &self.l_values, &self.subdiag, perm);
        for k in 0..s.n_supernodes() {
            let node = l.supernode(k);
            let v = node.val();
            let start = node.start();
            let mut j = 0;
            while j < v.ncols() {
                let off = self.subdiag[start + j];
                if off == 0.0 {
                    let d = v[(j, j)];
                    if d > 0.0 {
                        inertia.positive += 1
                    } else if d < 0.0 {
                        inertia.negative += 1
                    } else {
                        inertia.zero += 1
                    }
                    j += 1;
                } else {
                    let (a, c) = (v[(j, j)], v[(j + 1, j + 1)]);
                    let det = a * c - off * off;
                    if det < 0.0 {
                        inertia.positive += 1;
                        inertia.negative += 1;
                    } else if det > 0.0 {
                        if a + c > 0.0 {
                            inertia.positive += 2
                        } else {
                            inertia.negative += 2
                        }
                    } else {
                        inertia.zero += 2;
                    }
                    j += 2;
                }
            }
        }
        inertia
    }
}

impl KktSolver for FaerLblt {
    fn name(&self) -> &str {
        "faer-lblt"
    }

    fn analyse(
        &mut self,
        dim: usize,
        col_ptr: &[usize],
        row_idx: &[usize],
        ordering: Option<&[usize]>,
    ) -> Result<(), LinearSolverError> {
        self.dim = dim;
        self.col_ptr = col_ptr.to_vec();
        self.row_idx = row_idx.to_vec();
        let a = SymbolicSparseColMatRef::new_unsorted_checked(
            dim,
            dim,
            &self.col_ptr,
            None,
            &self.row_idx,
        );
        let inverse = ordering.map(inverse_permutation).transpose()?;
        let sym = factorize_symbolic_cholesky(
            a,
            Side::Lower,
            symmetric_ordering(ordering, inverse.as_deref()),
            CholeskySymbolicParams {
                supernodal_flop_ratio_threshold: SupernodalThreshold::FORCE_SUPERNODAL,
                ..Default::default()
            },
        )
        .map_err(|e| LinearSolverError::Symbolic(format!("{e:?}")))?;
        self.l_values = vec![0.0; sym.len_val()];
        self.subdiag = vec![0.0; dim];
        self.perm_fwd = (0..dim).collect();
        self.perm_inv = (0..dim).collect();
        let req = StackReq::any_of(&[
            sym.factorize_numeric_intranode_lblt_scratch::<f64>(Par::Seq, Self::lblt_params()),
            sym.solve_in_place_scratch::<f64>(1, Par::Seq),
        ]);
        self.buffer = MemBuffer::new(req);
        self.symbolic = Some(sym);
        self.factored = false;
        Ok(())
    }

    fn factor(&mut self, values: &[f64]) -> Result<Inertia, LinearSolverError> {
        let sym = self
            .symbolic
            .as_ref()
            .ok_or(LinearSolverError::NotReady("analyse"))?;
        let a_sym = SymbolicSparseColMatRef::new_unsorted_checked(
            self.dim,
            self.dim,
            &self.col_ptr,
            None,
            &self.row_idx,
        );
        let a = SparseColMatRef::new(a_sym, values);
        let stack = MemStack::new(&mut self.buffer);
        sym.factorize_numeric_intranode_lblt(
            &mut self.l_values,
            &mut self.subdiag,
            &mut self.perm_fwd,
            &mut self.perm_inv,
            a,
            Side::Lower,
            Par::Seq,
            stack,
            Self::lblt_params(),
        );
        let finite = self.l_values.iter().all(|v| v.is_finite())
            && self.subdiag.iter().all(|v| v.is_finite());
        self.factored = finite;
        Ok(if finite {
            self.inertia_of_b()
        } else {
            Inertia::singular(self.dim)
        })
    }

    fn solve(&mut self, rhs: &mut [f64]) -> Result<(), LinearSolverError> {
        if !self.factored {
            return Err(LinearSolverError::NotReady("a successful factorisation"));
        }
        let sym = self
            .symbolic
            .as_ref()
            .ok_or(LinearSolverError::NotReady("analyse"))?;
        let perm = PermRef::new_checked(&self.perm_fwd, &self.perm_inv, self.dim);
        let l = IntranodeLbltRef::new(sym, &self.l_values, &self.subdiag, perm);
        let n = rhs.len();
        let mat = MatMut::from_column_major_slice_mut(rhs, n, 1);
        let stack = MemStack::new(&mut self.buffer);
        l.solve_in_place_with_conj(Conj::No, mat, Par::Seq, stack);
        Ok(())
    }

    fn factor_nnz(&self) -> usize {
        self.l_values.len()
    }
}

/// Calls, right-hand-side columns, time and factor size of a KKT solver's solves, for the
/// solver's summary of where the linear-algebra time goes.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct SolveCounts {
    /// Triangular-solve calls (one pass over the factor each).
    pub calls: usize,
    /// Right-hand sides solved for, summed over the calls.
    pub columns: usize,
    /// Wall time in the solves.
    pub time: std::time::Duration,
}

/// A KKT solver that counts the solves of the one it wraps.
pub struct Counted<'a> {
    inner: &'a mut dyn KktSolver,
    /// Solves so far.
    pub counts: SolveCounts,
}

impl<'a> Counted<'a> {
    /// Wraps `inner` with zero counts.
    pub fn new(inner: &'a mut dyn KktSolver) -> Self {
        Counted {
            inner,
            counts: SolveCounts::default(),
        }
    }
}

impl KktSolver for Counted<'_> {
    fn name(&self) -> &str {
        self.inner.name()
    }

    fn analyse(
        &mut self,
        dim: usize,
        col_ptr: &[usize],
        row_idx: &[usize],
        ordering: Option<&[usize]>,
    ) -> Result<(), LinearSolverError> {
        self.inner.analyse(dim, col_ptr, row_idx, ordering)
    }

    fn factor(&mut self, values: &[f64]) -> Result<Inertia, LinearSolverError> {
        self.inner.factor(values)
    }

    fn solve(&mut self, rhs: &mut [f64]) -> Result<(), LinearSolverError> {
        self.solve_many(rhs, 1)
    }

    fn solve_many(&mut self, rhs: &mut [f64], ncols: usize) -> Result<(), LinearSolverError> {
        let t = std::time::Instant::now();
        let res = self.inner.solve_many(rhs, ncols);
        self.counts.calls += 1;
        self.counts.columns += ncols;
        self.counts.time += t.elapsed();
        res
    }

    fn factor_nnz(&self) -> usize {
        self.inner.factor_nnz()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// K = [[4, 1, 1], [1, 3, 2], [1, 2, -1]] (lower triangle, CSC), inertia (2, 1); K (1, 2,
    /// 3) = (9, 13, 2).
    const K_COL_PTR: [usize; 4] = [0, 3, 5, 6];
    const K_ROW_IDX: [usize; 6] = [0, 1, 2, 1, 2, 2];
    const K_VALS: [f64; 6] = [4.0, 1.0, 1.0, 3.0, 2.0, -1.0];

    #[test]
    fn solves_small_quasi_definite_system_and_counts_inertia() {
        let (col_ptr, row_idx, vals) = (K_COL_PTR, K_ROW_IDX, K_VALS);
        let mut s = FaerLdlt::new();
        s.analyse(3, &col_ptr, &row_idx, None).unwrap();
        let inertia = s.factor(&vals).unwrap();
        assert_eq!((inertia.positive, inertia.negative), (2, 1));
        // x = (1, 2, 3): b = K x = (4+2+3, 1+6+6, 1+4-3) = (9, 13, 2)
        let mut b = [9.0, 13.0, 2.0];
        s.solve(&mut b).unwrap();
        for (got, want) in b.iter().zip([1.0, 2.0, 3.0]) {
            assert!((got - want).abs() < 1e-12, "{got} vs {want}");
        }
    }

    #[test]
    fn non_finite_factor_entry_is_reported_as_singular() {
        // a NaN or an infinity below the diagonal (not on it) must still be caught
        for bad in [f64::NAN, f64::INFINITY] {
            for pos in [1, 2, 4] {
                let mut vals = K_VALS;
                vals[pos] = bad;
                let mut s = FaerLdlt::new();
                s.analyse(3, &K_COL_PTR, &K_ROW_IDX, None).unwrap();
                let inertia = s.factor(&vals).unwrap();
                assert_eq!(
                    (inertia.positive, inertia.negative, inertia.zero),
                    (0, 0, 3),
                    "entry {pos} = {bad}"
                );
                assert!(
                    s.solve(&mut [1.0, 1.0, 1.0]).is_err(),
                    "entry {pos} = {bad}"
                );
            }
        }
    }

    #[test]
    fn multi_column_solve_matches_column_by_column() {
        // Same K as above; columns x₁ = (1, 2, 3), x₂ = (−1, 0, 2), x₃ = (0, 1, −1).
        let (col_ptr, row_idx, vals) = (K_COL_PTR, K_ROW_IDX, K_VALS);
        let k = |x: [f64; 3]| {
            [
                4.0 * x[0] + x[1] + x[2],
                x[0] + 3.0 * x[1] + 2.0 * x[2],
                x[0] + 2.0 * x[1] - x[2],
            ]
        };
        let xs = [[1.0, 2.0, 3.0], [-1.0, 0.0, 2.0], [0.0, 1.0, -1.0]];
        let mut b: Vec<f64> = xs.iter().flat_map(|&x| k(x)).collect();
        let mut s = FaerLdlt::new();
        s.analyse(3, &col_ptr, &row_idx, None).unwrap();
        s.factor(&vals).unwrap();
        s.solve_many(&mut b, 3).unwrap();
        for (got, want) in b.iter().zip(xs.iter().flatten()) {
            assert!((got - want).abs() < 1e-12, "{got} vs {want}");
        }
    }

    #[test]
    fn a_given_ordering_gives_the_same_solution_and_inertia_as_faer_s_own() {
        // Quasi-definite K = [[H, Jᵀ], [J, −δI]]: H (30 × 30) diagonally dominant with sparse
        // off-diagonal entries, J (12 × 30) sparse, δ = 1e-2; inertia (30, 12). Lower
        // triangle in CSC, entries from a fixed linear congruential sequence.
        let (n, m) = (30usize, 12usize);
        let dim = n + m;
        let mut state = 12345u64;
        let mut rand = || {
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            ((state >> 11) as f64 / (1u64 << 53) as f64) * 2.0 - 1.0
        };
        let mut dense = vec![0.0; dim * dim];
        for i in 0..n {
            dense[i * dim + i] = 10.0;
            for j in 0..i {
                if (i * 7 + j * 3) % 5 == 0 {
                    dense[i * dim + j] = rand();
                }
            }
        }
        for r in 0..m {
            dense[(n + r) * dim + n + r] = -1e-2;
            for j in 0..n {
                if (r * 5 + j) % 4 == 0 {
                    dense[(n + r) * dim + j] = rand();
                }
            }
        }
        let (mut col_ptr, mut row_idx, mut vals) = (vec![0usize], Vec::new(), Vec::new());
        for c in 0..dim {
            for r in c..dim {
                if dense[r * dim + c] != 0.0 {
                    row_idx.push(r);
                    vals.push(dense[r * dim + c]);
                }
            }
            col_ptr.push(row_idx.len());
        }
        let at = |r: usize, c: usize| dense[r.max(c) * dim + r.min(c)];
        // three known solutions and their right-hand sides
        let xs: Vec<f64> = (0..3 * dim).map(|_| rand()).collect();
        let mut b = vec![0.0; 3 * dim];
        for k in 0..3 {
            for r in 0..dim {
                b[k * dim + r] = (0..dim).map(|c| at(r, c) * xs[k * dim + c]).sum();
            }
        }
        // an ordering unrelated to the pattern: constraints first, variables interleaved
        let order: Vec<usize> = (n..dim).rev().chain((0..n).map(|i| (i * 7) % n)).collect();
        let mut own = FaerLdlt::new();
        own.analyse(dim, &col_ptr, &row_idx, None).unwrap();
        let mut given = FaerLdlt::new();
        given
            .analyse(dim, &col_ptr, &row_idx, Some(&order))
            .unwrap();
        // the constraints first: some columns are eliminated before faer, not all
        let bottom = given.bottom_columns();
        assert!(
            bottom > 0 && bottom < dim,
            "{bottom} of {dim} columns in the bottom"
        );
        for s in [&mut own, &mut given] {
            let inertia = s.factor(&vals).unwrap();
            assert_eq!(
                (inertia.positive, inertia.negative, inertia.zero),
                (n, m, 0)
            );
            let mut x = b.clone();
            s.solve_many(&mut x, 3).unwrap();
            for (got, want) in x.iter().zip(&xs) {
                assert!((got - want).abs() < 1e-10, "{got} vs {want}");
            }
            let mut x1 = b[dim..2 * dim].to_vec();
            s.solve(&mut x1).unwrap();
            for (got, want) in x1.iter().zip(&xs[dim..2 * dim]) {
                assert!((got - want).abs() < 1e-10, "{got} vs {want}");
            }
        }
        // a non-finite entry anywhere (bottom or reduced part) makes the matrix singular
        for pos in [0, vals.len() / 2, vals.len() - 1] {
            let mut bad = vals.clone();
            bad[pos] = f64::NAN;
            let inertia = given.factor(&bad).unwrap();
            assert_eq!(inertia.zero, dim, "NaN at entry {pos}");
            assert!(given.solve(&mut b[..dim].to_vec()).is_err());
        }
        // a factorisation with other values reuses the permuted pattern
        let scaled: Vec<f64> = vals.iter().map(|v| 2.0 * v).collect();
        given.factor(&scaled).unwrap();
        let mut x = b[..dim].to_vec();
        given.solve(&mut x).unwrap();
        for (got, want) in x.iter().zip(&xs[..dim]) {
            assert!((got - 0.5 * want).abs() < 1e-10, "{got} vs {}", 0.5 * want);
        }
    }

    #[test]
    fn factor_statistics_count_the_cholesky_operations() {
        // dense 3 × 3 pattern: columns of L have 2, 1, 0 entries below the diagonal
        let (col_ptr, row_idx) = (K_COL_PTR, K_ROW_IDX);
        let mut s = FaerLdlt::new();
        assert!(s.factor_stats().is_none());
        s.analyse(3, &col_ptr, &row_idx, None).unwrap();
        let (units, flops) = s.factor_stats().unwrap();
        assert_eq!(flops, 4.0 + 1.0);
        assert!((1..=3).contains(&units));
    }

    #[test]
    fn counted_solver_counts_calls_and_columns_and_solves_the_same() {
        let (col_ptr, row_idx, vals) = (K_COL_PTR, K_ROW_IDX, K_VALS);
        let mut inner = FaerLdlt::new();
        let mut s = Counted::new(&mut inner);
        s.analyse(3, &col_ptr, &row_idx, None).unwrap();
        s.factor(&vals).unwrap();
        let mut b = [9.0, 13.0, 2.0];
        s.solve(&mut b).unwrap();
        let mut bb = [9.0, 13.0, 2.0, 9.0, 13.0, 2.0];
        s.solve_many(&mut bb, 2).unwrap();
        assert_eq!((s.counts.calls, s.counts.columns), (2, 3));
        assert!(s.counts.time.as_secs_f64() >= 0.0);
        assert_eq!(s.factor_nnz(), s.inner.factor_nnz());
        for (got, want) in b.iter().chain(&bb).zip([1.0, 2.0, 3.0].iter().cycle()) {
            assert!((got - want).abs() < 1e-12, "{got} vs {want}");
        }
    }

    #[test]
    fn lblt_pivots_a_zero_diagonal_and_counts_inertia() {
        // K = [[0, 1, 0], [1, 0, 2], [0, 2, 1/2]]: the first pivot is zero, so an unpivoted
        // LDLᵀ fails. det(K − λI) = −λ³ + λ²/2 + 5λ − 1/2 is −1/2 at 0, > 0 at 0.1 and → ∓∞
        // as λ → ±∞: roots in (−∞, 0), (0, 0.1), (0.1, ∞), so the inertia is (2, 1, 0).
        let col_ptr = [0, 2, 4, 5];
        let row_idx = [0, 1, 1, 2, 2];
        let vals = [0.0, 1.0, 0.0, 2.0, 0.5];
        let mut s = FaerLblt::new();
        s.analyse(3, &col_ptr, &row_idx, None).unwrap();
        let inertia = s.factor(&vals).unwrap();
        assert_eq!(
            (inertia.positive, inertia.negative, inertia.zero),
            (2, 1, 0)
        );
        // x = (1, 2, 3): b = K x = (2, 1 + 6, 4 + 1.5)
        let mut b = [2.0, 7.0, 5.5];
        s.solve(&mut b).unwrap();
        for (got, want) in b.iter().zip([1.0, 2.0, 3.0]) {
            assert!((got - want).abs() < 1e-12, "{got} vs {want}");
        }
    }

    #[test]
    fn lblt_and_ldlt_agree_on_a_quasi_definite_system() {
        let (col_ptr, row_idx, vals) = (K_COL_PTR, K_ROW_IDX, K_VALS);
        let mut s = FaerLblt::new();
        s.analyse(3, &col_ptr, &row_idx, None).unwrap();
        let inertia = s.factor(&vals).unwrap();
        assert_eq!((inertia.positive, inertia.negative), (2, 1));
        let mut b = [9.0, 13.0, 2.0];
        s.solve(&mut b).unwrap();
        for (got, want) in b.iter().zip([1.0, 2.0, 3.0]) {
            assert!((got - want).abs() < 1e-12, "{got} vs {want}");
        }
    }
}
