//! Derivatives of one tape at several points at once (the collocation points of a
//! transcription all share the node function): every sweep carries `BATCH` lanes, one per
//! point, side by side in each stored entry, so each operation, index set, map and
//! instruction is decoded once for all points and the lanes' arithmetic is one vector
//! operation.

use super::{Locals, Tape};
use crate::error::{check_len, AdError};

/// Number of evaluation points propagated together by [`Tape::jacobian_batch`] and
/// [`Tape::hessian_batch`].
pub const BATCH: usize = 8;

/// Scratch memory for evaluating one [`Tape`] at up to [`BATCH`] points together.
#[derive(Clone, Debug)]
pub struct BatchWorkspace {
    /// Values, local partials and adjoints, one lane per point.
    loc: Locals<BATCH>,
    /// Sparse forward gradients, one lane per point.
    grad: Vec<[f64; BATCH]>,
    /// Partials of folded operations kept by the Jacobian's fused sweep.
    kept: Vec<[[f64; BATCH]; 2]>,
    /// Sparse second-order adjoints, one lane per point.
    adot: Vec<[f64; BATCH]>,
    /// Hessian values of the lanes beyond the last point of a short batch (discarded).
    spare: Vec<f64>,
}

impl Tape {
    /// A fresh batch workspace sized for this tape.
    pub fn batch_workspace(&self) -> BatchWorkspace {
        BatchWorkspace {
            loc: Locals::new(self),
            grad: vec![[0.0; BATCH]; self.sparse.grad_len()],
            kept: vec![[[0.0; BATCH]; 2]; self.sparse.kept_len()],
            adot: vec![[0.0; BATCH]; self.sparse.adot_len()],
            spare: vec![0.0; self.hes_pattern.nnz() * (BATCH - 1)],
        }
    }

    /// Number of points in a batch of `len` inputs (a multiple of `n_inputs`, 1..=BATCH).
    fn batch_points(&self, len: usize, bw: &BatchWorkspace) -> Result<usize, AdError> {
        let n = self.n_in.max(1);
        let points = len / n;
        if !len.is_multiple_of(n) || points == 0 || points > BATCH {
            return Err(AdError::Length {
                what: "batch inputs xs (1 to BATCH points of n_inputs values)",
                expected: self.n_in * BATCH,
                got: len,
            });
        }
        if bw.grad.len() != self.sparse.grad_len()
            || bw.kept.len() != self.sparse.kept_len()
            || bw.adot.len() != self.sparse.adot_len()
            || !bw.loc.fits(self)
        {
            return Err(AdError::Workspace {
                ws_nodes: bw.loc.nodes(),
                tape_nodes: self.n_nodes,
            });
        }
        Ok(points)
    }

    /// Copies the outputs of the first `points` lanes, left in `vals` by a forward sweep,
    /// into `ys`, one block per point.
    fn write_lane_outputs(&self, vals: &[[f64; BATCH]], points: usize, ys: &mut [f64]) {
        let m = self.outputs.len().max(1);
        for (l, y) in ys.chunks_exact_mut(m).take(points).enumerate() {
            self.write_outputs(vals, l, y);
        }
    }

    /// Value sweeps of every lane at `xs`, all lanes in one sweep (lanes beyond the last
    /// point repeat it), writing the outputs of the real points into `ys`; with `lambdas`,
    /// also each lane's adjoint sweep with its point's multipliers.
    fn batch_values<const ORD: u8>(
        &self,
        xs: &[f64],
        lambdas: Option<&[f64]>,
        points: usize,
        bw: &mut BatchWorkspace,
        ys: &mut [f64],
    ) {
        let inputs = lane_blocks(xs, self.n_in, points);
        super::sparse::with_wide_vectors(
            #[inline(always)]
            || self.forward_lanes::<ORD, BATCH>(inputs, &mut bw.loc),
        );
        self.write_lane_outputs(&bw.loc.vals, points, ys);
        if let Some(lambdas) = lambdas {
            let w = lane_blocks(lambdas, self.outputs.len(), points);
            self.adjoint_lanes(&mut bw.loc, w);
        }
    }

    /// Evaluates `y = f(x)` at 1 to [`BATCH`] points: `xs` holds the points one after the
    /// other, `ys` receives the outputs point after point. Same numbers as [`Tape::eval`]
    /// at each point.
    pub fn eval_batch(
        &self,
        xs: &[f64],
        bw: &mut BatchWorkspace,
        ys: &mut [f64],
    ) -> Result<(), AdError> {
        let points = self.batch_points(xs.len(), bw)?;
        check_len("outputs ys", self.outputs.len() * points, ys.len())?;
        self.batch_values::<0>(xs, None, points, bw, ys);
        Ok(())
    }

    /// Evaluates `y = f(x)` and the Jacobian values at 1 to [`BATCH`] points: `xs` holds the
    /// points one after the other, `ys` and `jacs` receive the outputs and the Jacobian
    /// values (order of [`Tape::jacobian_pattern`]) point after point. Same numbers as
    /// [`Tape::jacobian`] at each point.
    pub fn jacobian_batch(
        &self,
        xs: &[f64],
        bw: &mut BatchWorkspace,
        ys: &mut [f64],
        jacs: &mut [f64],
    ) -> Result<(), AdError> {
        let points = self.batch_points(xs.len(), bw)?;
        let nnz = self.jac_pattern.nnz();
        check_len("outputs ys", self.outputs.len() * points, ys.len())?;
        check_len("Jacobian values jacs", nnz * points, jacs.len())?;
        let inputs = lane_blocks(xs, self.n_in, points);
        self.value_gradient_batch(inputs, &mut bw.loc.vals, &mut bw.kept, &mut bw.grad);
        self.write_lane_outputs(&bw.loc.vals, points, ys);
        self.sparse_jacobian_extract(self.sparse.compact(), &bw.grad, jacs);
        Ok(())
    }

    /// Evaluates `y = f(x)` and the lower triangle of the Hessian of `Σ λᵢ yᵢ` at 1 to
    /// [`BATCH`] points, each with its own multipliers: `xs`, `lambdas`, `ys` and `hes`
    /// hold one block per point. Same numbers as [`Tape::hessian`] at each point.
    pub fn hessian_batch(
        &self,
        xs: &[f64],
        lambdas: &[f64],
        bw: &mut BatchWorkspace,
        ys: &mut [f64],
        hes: &mut [f64],
    ) -> Result<(), AdError> {
        self.second_order_batch(xs, lambdas, bw, ys, None, hes)
    }

    /// [`Tape::hessian_batch`] that also writes the Jacobian values of each point into
    /// `jacs` (one block per point, order of [`Tape::jacobian_pattern`]): the Hessian's
    /// forward sweep already holds them, so this costs little more than the Hessian alone.
    /// Same numbers as [`Tape::jacobian_batch`] and [`Tape::hessian_batch`].
    pub fn jacobian_hessian_batch(
        &self,
        xs: &[f64],
        lambdas: &[f64],
        bw: &mut BatchWorkspace,
        ys: &mut [f64],
        jacs: &mut [f64],
        hes: &mut [f64],
    ) -> Result<(), AdError> {
        self.second_order_batch(xs, lambdas, bw, ys, Some(jacs), hes)
    }

    /// Values, optionally Jacobians, and Lagrangian Hessians at 1 to [`BATCH`] points.
    fn second_order_batch(
        &self,
        xs: &[f64],
        lambdas: &[f64],
        bw: &mut BatchWorkspace,
        ys: &mut [f64],
        jacs: Option<&mut [f64]>,
        hes: &mut [f64],
    ) -> Result<(), AdError> {
        let points = self.batch_points(xs.len(), bw)?;
        let (m, nnz) = (self.outputs.len(), self.hes_pattern.nnz());
        let nnz_j = self.jac_pattern.nnz();
        check_len("multipliers lambdas", m * points, lambdas.len())?;
        check_len("outputs ys", m * points, ys.len())?;
        check_len("Hessian values hes", nnz * points, hes.len())?;
        if let Some(jacs) = &jacs {
            check_len("Jacobian values jacs", nnz_j * points, jacs.len())?;
        }
        self.batch_values::<2>(xs, Some(lambdas), points, bw, ys);
        let plan = self.sparse.full();
        self.sparse_forward_batch(plan, &bw.loc.part, &mut bw.grad);
        if let Some(jacs) = jacs {
            self.sparse_jacobian_extract(plan, &bw.grad, jacs);
        }
        if nnz == 0 {
            return Ok(());
        }
        // Lanes beyond the last point write into scratch.
        let mut real = hes.chunks_exact_mut(nnz);
        let mut spare = bw.spare.chunks_exact_mut(nnz);
        let outs: [&mut [f64]; BATCH] = std::array::from_fn(|l| {
            let next = if l < points {
                real.next()
            } else {
                spare.next()
            };
            next.expect("one block of nnz values per lane (lengths checked above)")
        });
        self.sparse_hessian_batch(&bw.loc, &bw.grad, &mut bw.adot, outs);
        Ok(())
    }
}

/// The block of `len` values of each lane in `v` (blocks one after another): block `l`,
/// lanes beyond the last of the `points` blocks repeating it.
fn lane_blocks(v: &[f64], len: usize, points: usize) -> [&[f64]; BATCH] {
    std::array::from_fn(|l| &v[l.min(points - 1) * len..][..len])
}
