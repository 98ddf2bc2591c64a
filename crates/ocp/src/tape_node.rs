//! The node function recorded once on a derivative tape: values, sparse Jacobian and
//! exact sparse Hessian for the transcription.

use crate::node::NodeModel;
use crate::problem::ProblemError;
use crate::transcription::NodeFunction;
use std::sync::Mutex;
use stride_ad::{BatchWorkspace, Scalar, Tape, Var, Workspace, BATCH};

/// A [`NodeModel`] recorded on a tape.
pub struct TapeNode {
    tape: Tape,
    bounds: Vec<(f64, f64)>,
    pool: Mutex<Vec<(Workspace, Vec<f64>)>>,
    batch_pool: Mutex<Vec<(BatchWorkspace, Vec<f64>)>>,
}

impl TapeNode {
    /// Record the node function at the input point `x0` (any point: the tape has no
    /// value-dependent branches).
    pub fn record(node: &NodeModel, x0: &[f64]) -> Result<Self, ProblemError> {
        let mut ws = node.workspace::<Var>()?;
        let n_out = node.n_outputs();
        let tape = Tape::record(x0, |x| {
            let mut y = vec![<Var as Scalar>::cst(0.0); n_out];
            node.eval(&mut ws, x, &mut y);
            y
        })
        .map_err(|e| ProblemError::Model(format!("recording the node function: {e}")))?;
        Ok(Self {
            tape,
            bounds: node.constraint_bounds(),
            pool: Mutex::new(Vec::new()),
            batch_pool: Mutex::new(Vec::new()),
        })
    }

    /// Record the node function of `problem` at the inputs of its first collocation point
    /// in the NLP vector `x`.
    pub fn for_problem(
        problem: &crate::problem::GaitProblem,
        node: &NodeModel,
        x: &[f64],
    ) -> Result<Self, ProblemError> {
        let l = &problem.layout;
        let io = crate::transcription::NodeInputs {
            nm: l.nm,
            nq: l.nq,
            na: l.na,
        };
        let xin: Vec<f64> = io.global_indices(l, 0, 1).iter().map(|&g| x[g]).collect();
        Self::record(node, &xin)
    }

    /// The underlying tape.
    pub fn tape(&self) -> &Tape {
        &self.tape
    }

    /// Run `f` with a workspace and an output buffer taken from the pool (allocated only
    /// the first time a thread needs one).
    fn with_ws<R>(&self, f: impl FnOnce(&mut Workspace, &mut Vec<f64>) -> R) -> R {
        with_pooled(
            &self.pool,
            || (self.tape.workspace(), vec![0.0; self.tape.n_outputs()]),
            f,
        )
    }

    /// Run `f` with a batch workspace and a batch output buffer from the pool.
    fn with_batch_ws<R>(&self, f: impl FnOnce(&mut BatchWorkspace, &mut Vec<f64>) -> R) -> R {
        with_pooled(
            &self.batch_pool,
            || {
                let m = self.tape.n_outputs() * BATCH;
                (self.tape.batch_workspace(), vec![0.0; m])
            },
            f,
        )
    }
}

/// Runs `f` on an entry taken from `pool` (made by `make` when the pool is empty) and
/// returns the entry to the pool.
fn with_pooled<W, R>(
    pool: &Mutex<Vec<(W, Vec<f64>)>>,
    make: impl FnOnce() -> (W, Vec<f64>),
    f: impl FnOnce(&mut W, &mut Vec<f64>) -> R,
) -> R {
    let mut entry = pool
        .lock()
        .unwrap_or_else(|e| e.into_inner())
        .pop()
        .unwrap_or_else(make);
    let r = f(&mut entry.0, &mut entry.1);
    pool.lock().unwrap_or_else(|e| e.into_inner()).push(entry);
    r
}

impl NodeFunction for TapeNode {
    fn n_inputs(&self) -> usize {
        self.tape.n_inputs()
    }
    fn n_outputs(&self) -> usize {
        self.tape.n_outputs()
    }
    fn constraint_bounds(&self) -> Vec<(f64, f64)> {
        self.bounds.clone()
    }
    fn jacobian_pattern(&self) -> Vec<(usize, usize)> {
        self.tape.jacobian_pattern().iter().collect()
    }
    fn hessian_pattern(&self) -> Vec<(usize, usize)> {
        self.tape.hessian_pattern().iter().collect()
    }
    fn eval(&self, x: &[f64], y: &mut [f64]) {
        self.with_ws(|ws, _| self.tape.eval(x, ws, y))
            .expect("tape sizes fixed at recording");
    }
    fn jacobian(&self, x: &[f64], y: &mut [f64], jac: &mut [f64]) {
        self.with_ws(|ws, _| self.tape.jacobian(x, ws, y, jac))
            .expect("tape sizes fixed at recording");
    }
    fn hessian(&self, x: &[f64], w: &[f64], hess: &mut [f64]) {
        self.with_ws(|ws, y| self.tape.hessian(x, w, ws, y, hess))
            .expect("tape sizes fixed at recording");
    }
    fn batch(&self) -> usize {
        BATCH
    }
    fn eval_batch(&self, xs: &[f64], ys: &mut [f64]) {
        self.with_batch_ws(|bw, _| self.tape.eval_batch(xs, bw, ys))
            .expect("tape sizes fixed at recording");
    }
    fn jacobian_batch(&self, xs: &[f64], ys: &mut [f64], jacs: &mut [f64]) {
        self.with_batch_ws(|bw, _| self.tape.jacobian_batch(xs, bw, ys, jacs))
            .expect("tape sizes fixed at recording");
    }
    fn hessian_batch(&self, xs: &[f64], ws: &[f64], hess: &mut [f64]) {
        let m = self.tape.n_outputs();
        self.with_batch_ws(|bw, y| {
            let points = xs.len() / self.tape.n_inputs().max(1);
            self.tape
                .hessian_batch(xs, ws, bw, &mut y[..points * m], hess)
        })
        .expect("tape sizes fixed at recording");
    }
    fn jacobian_hessian_batch(
        &self,
        xs: &[f64],
        ws: &[f64],
        ys: &mut [f64],
        jacs: &mut [f64],
        hess: &mut [f64],
    ) {
        self.with_batch_ws(|bw, _| self.tape.jacobian_hessian_batch(xs, ws, bw, ys, jacs, hess))
            .expect("tape sizes fixed at recording");
    }
}
