//! Record-once tapes: a generic function is run once on [`Var`]s, the operations are
//! stored, and the tape then evaluates values, sparse Jacobians, gradients and exact
//! sparse Lagrangian Hessians in `f64` into a reusable [`Workspace`], allocating nothing.
//!
//! Algorithms (see `docs/decisions/0001-derivatives.md`); the default ones propagate
//! sparse vectors over statically known per-node index sets (module `sparse`); the
//! coloured ones (`*_coloured`) are kept for comparison:
//! - Jacobian: reverse vector mode, rows compressed by colouring (rows sharing no input
//!   share a lane), `LANES` colours per sweep, each sweep restricted to the union of
//!   the dependency cones of its rows.
//! - Hessian of `Σ λᵢ yᵢ`: one scalar reverse sweep for the adjoints, then
//!   forward-over-reverse in `LANES`-wide chunks of a distance-2 colouring of the
//!   Hessian columns, each chunk restricted to the nodes its seeds can reach.

mod batch;
mod build;
pub mod op;
mod registers;
mod slots;
mod sparse;
mod sweep;
mod var;

pub use batch::{BatchWorkspace, BATCH};
pub use op::{Elem, Op};
pub use var::Var;

use crate::error::{check_len, AdError};
use crate::scalar::UnaryFn;
use crate::sparsity::Pattern;
use std::sync::Arc;

/// Number of derivative directions propagated together in one vector sweep.
pub const LANES: usize = 8;

/// One reverse sweep of the Jacobian: seeded output nodes, nodes to visit, entries to read.
#[derive(Clone, Debug, Default)]
struct JacChunk {
    /// `(node, lane)` adjoint seeds (one per row in the chunk).
    seeds: Vec<(u32, u32)>,
    /// Non-input nodes to sweep, descending.
    nodes: Vec<u32>,
    /// `(pattern entry, input, lane)` to read after the sweep.
    extract: Vec<(u32, u32, u32)>,
}

/// One forward-over-reverse chunk of the Hessian.
#[derive(Clone, Debug, Default)]
struct HesChunk {
    /// `(input, lane)` tangent seeds.
    seeds: Vec<(u32, u32)>,
    /// Nodes whose tangent may be nonzero, ascending.
    fwd: Vec<u32>,
    /// Nodes whose second-order adjoint may be nonzero, descending.
    rev: Vec<u32>,
    /// `(pattern entry, input row, lane)` to read after the sweep.
    extract: Vec<(u32, u32, u32)>,
}

/// A recorded function `y = f(x)`, `x ∈ ℝⁿ`, `y ∈ ℝᵐ`, immutable and shareable between
/// threads (`Send + Sync`); evaluate with a per-thread [`Workspace`].
#[derive(Debug)]
pub struct Tape {
    n_in: usize,
    /// Nodes `0..n_in` are inputs; node `n_in + t` is `ops[t]`. Node `n_nodes` is a sink.
    n_nodes: usize,
    ops: Vec<Op>,
    args: Vec<[u32; 2]>,
    active: Vec<bool>,
    /// Active non-input nodes, descending (full reverse sweep).
    active_desc: Vec<u32>,
    fns: Vec<Arc<dyn UnaryFn>>,
    outputs: Vec<u32>,
    /// Values at the recording point (inputs included).
    rec_vals: Vec<f64>,
    jac_pattern: Pattern,
    jac_colours: usize,
    jac_chunks: Vec<JacChunk>,
    hes_pattern: Pattern,
    hes_colours: usize,
    hes_chunks: Vec<HesChunk>,
    sparse: sparse::SparsePlan,
    /// Places of the node values in the forward sweeps (reused by liveness).
    registers: registers::Registers,
}

/// Per-thread scratch memory for evaluating one [`Tape`]; reuse it across calls.
#[derive(Clone, Debug)]
pub struct Workspace {
    /// Values, local derivatives and adjoints of the nodes (one point).
    loc: Locals<1>,
    lane_a: Vec<[f64; LANES]>,
    lane_b: Vec<[f64; LANES]>,
    /// Sparse forward gradients (one lane).
    grad: Vec<[f64; 1]>,
    /// Partials of folded operations kept for the Jacobian's fused sweep (one lane).
    kept: Vec<[[f64; 1]; 2]>,
    /// Sparse second-order adjoints (one lane).
    adot: Vec<[f64; 1]>,
}

/// Values, local partials, second partials and adjoints of every node at `L` evaluation
/// points, the `L` lanes of a node side by side (one vector operation per node).
#[derive(Clone, Debug)]
pub(super) struct Locals<const L: usize> {
    /// Node values in their places ([`registers::Registers`]: reused by liveness).
    vals: Vec<[f64; L]>,
    /// `[∂/∂a, ∂/∂b]` of each operation.
    part: Vec<[[f64; L]; 2]>,
    /// `[∂²/∂a², ∂²/∂a∂b, ∂²/∂b²]` of each operation.
    sec: Vec<[[f64; L]; 3]>,
    /// Adjoints of the nodes (the sink last).
    abar: Vec<[f64; L]>,
}

impl<const L: usize> Locals<L> {
    /// Zeroed stores for `tape`.
    fn new(tape: &Tape) -> Self {
        let n_ops = tape.ops.len();
        Locals {
            vals: vec![[0.0; L]; tape.registers.len as usize],
            part: vec![[[0.0; L]; 2]; n_ops],
            sec: vec![[[0.0; L]; 3]; n_ops],
            abar: vec![[0.0; L]; tape.n_nodes + 1],
        }
    }

    /// Nodes of the tape the stores were sized for (the adjoints hold one more: the sink).
    fn nodes(&self) -> usize {
        self.abar.len().saturating_sub(1)
    }

    /// Whether the stores were sized for `tape`.
    fn fits(&self, tape: &Tape) -> bool {
        self.nodes() == tape.n_nodes
            && self.part.len() == tape.ops.len()
            && self.vals.len() == tape.registers.len as usize
    }
}

/// Size statistics of a tape (for reports and benchmarks).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct TapeStats {
    /// Number of inputs.
    pub n_inputs: usize,
    /// Number of outputs.
    pub n_outputs: usize,
    /// Recorded operations after constant folding and dead-code elimination.
    pub n_ops: usize,
    /// Structural nonzeros of the Jacobian.
    pub jac_nnz: usize,
    /// Colours (compressed reverse directions) of the Jacobian rows.
    pub jac_colours: usize,
    /// Structural nonzeros of the Hessian lower triangle.
    pub hes_nnz: usize,
    /// Colours (forward directions) of the Hessian columns.
    pub hes_colours: usize,
    /// Stored entries of the per-node sparse gradients of the forward sweep that keeps
    /// them all for the Hessian's second-order sweep.
    pub grad_entries: usize,
    /// Length of the gradient store of the Jacobian-only forward sweep: the inputs' and
    /// outputs' sets plus the most other sets live at once (places reused by liveness).
    pub jacobian_grad_entries: usize,
    /// Length of the store of the per-node second-order adjoints (Hessian sweep): the
    /// inputs' sets plus the most other sets live at once (places reused by liveness).
    pub adot_entries: usize,
    /// Value places of the forward sweeps: the inputs plus the most other values live at
    /// once (places reused by liveness).
    pub value_places: usize,
    /// Partials of folded operations the Jacobian-only sweep keeps at once.
    pub jacobian_kept_partials: usize,
    /// Stored scatter positions of both sparse sweeps.
    pub map_entries: usize,
}

impl Tape {
    /// Records `f` at the point `x0` (which fixes the values seen while recording; the
    /// tape is valid everywhere as `f` must not branch on values) and analyses it.
    ///
    /// `f` receives the input variables and returns the outputs. It must build every
    /// [`Var`] it uses from its arguments or [`crate::Scalar::cst`], on this thread.
    pub fn record<F>(x0: &[f64], f: F) -> Result<Tape, AdError>
    where
        F: FnOnce(&[Var]) -> Vec<Var>,
    {
        let n_in = x0.len();
        let (inputs, id) = var::begin(n_in, x0)?;
        let result = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| f(&inputs)));
        let mut rec = var::end().expect("recorder vanished during Tape::record");
        let outs = match result {
            Ok(o) => o,
            Err(p) => std::panic::resume_unwind(p),
        };
        let mut out_nodes = Vec::with_capacity(outs.len());
        for (index, v) in outs.iter().enumerate() {
            if v.is_constant() {
                rec.ops.push((Op::Const(v.val), v.val));
                out_nodes.push((rec.ops.len() - 1) as u32);
            } else if v.rec != id || v.idx as usize >= rec.ops.len() {
                return Err(AdError::ForeignVariable { index });
            } else {
                out_nodes.push(v.idx);
            }
        }
        let (ops, rec_vals, outputs) = build::compact(n_in, &rec, &out_nodes);
        let n_nodes = n_in + ops.len();
        let jset = build::index_sets(n_in, &ops);
        let active: Vec<bool> = (0..n_nodes).map(|k| !jset.is_empty_row(k)).collect();
        let args = build::diff_args(n_in, &ops, &active, n_nodes as u32);
        let active_desc = (n_in..n_nodes)
            .rev()
            .filter(|&k| active[k])
            .map(|k| k as u32)
            .collect();
        let registers = registers::Registers::new(n_in, &ops, &outputs);
        let mut tape = Tape {
            n_in,
            n_nodes,
            ops,
            args,
            active,
            active_desc,
            fns: rec.fns,
            outputs,
            rec_vals,
            jac_pattern: Pattern::default(),
            jac_colours: 0,
            jac_chunks: Vec::new(),
            hes_pattern: Pattern::default(),
            hes_colours: 0,
            hes_chunks: Vec::new(),
            sparse: sparse::SparsePlan::default(),
            registers,
        };
        let (plan, hes_pattern) = sparse::SparsePlan::new(
            n_in,
            &tape.ops,
            &tape.args,
            &tape.active,
            &tape.outputs,
            &jset,
        );
        tape.sparse = plan;
        tape.plan_jacobian(&jset);
        tape.plan_hessian(hes_pattern);
        Ok(tape)
    }

    /// Number of inputs `n`.
    pub fn n_inputs(&self) -> usize {
        self.n_in
    }
    /// Number of outputs `m`.
    pub fn n_outputs(&self) -> usize {
        self.outputs.len()
    }
    /// Size statistics.
    pub fn stats(&self) -> TapeStats {
        TapeStats {
            n_inputs: self.n_in,
            n_outputs: self.outputs.len(),
            n_ops: self.ops.len(),
            jac_nnz: self.jac_pattern.nnz(),
            jac_colours: self.jac_colours,
            hes_nnz: self.hes_pattern.nnz(),
            hes_colours: self.hes_colours,
            grad_entries: self.sparse.grad_len(),
            jacobian_grad_entries: self.sparse.jacobian_grad_len(),
            adot_entries: self.sparse.adot_len(),
            value_places: self.registers.len as usize,
            jacobian_kept_partials: self.sparse.kept_len(),
            map_entries: self.sparse.map_len(),
        }
    }
    /// The recorded operations (node `n_inputs + t` is `ops()[t]`).
    pub fn ops(&self) -> &[Op] {
        &self.ops
    }
    /// Output values at the recording point.
    pub fn recorded_outputs(&self) -> Vec<f64> {
        self.outputs
            .iter()
            .map(|&o| self.rec_vals[o as usize])
            .collect()
    }
    /// Structural nonzeros of the Jacobian `∂y/∂x` (m × n), sorted row-major; the
    /// order of the values written by [`Tape::jacobian`].
    pub fn jacobian_pattern(&self) -> &Pattern {
        &self.jac_pattern
    }
    /// Structural nonzeros of the lower triangle (row ≥ col) of the Hessian of
    /// `Σ λᵢ yᵢ` for any λ (n × n), sorted row-major; the order of [`Tape::hessian`].
    pub fn hessian_pattern(&self) -> &Pattern {
        &self.hes_pattern
    }
    /// A fresh workspace sized for this tape.
    pub fn workspace(&self) -> Workspace {
        let n = self.n_nodes + 1;
        Workspace {
            loc: Locals::new(self),
            lane_a: vec![[0.0; LANES]; n],
            lane_b: vec![[0.0; LANES]; n],
            grad: vec![[0.0]; self.sparse.grad_len()],
            kept: vec![[[0.0]; 2]; self.sparse.kept_len()],
            adot: vec![[0.0]; self.sparse.adot_len()],
        }
    }

    fn check(&self, x: &[f64], ws: &Workspace) -> Result<(), AdError> {
        check_len("inputs x", self.n_in, x.len())?;
        if !ws.loc.fits(self) {
            return Err(AdError::Workspace {
                ws_nodes: ws.loc.nodes(),
                tape_nodes: self.n_nodes,
            });
        }
        Ok(())
    }

    /// Copies lane `lane` of the outputs' values, left in their places in `vals` by a
    /// forward sweep, into `y`.
    fn write_outputs<const L: usize>(&self, vals: &[[f64; L]], lane: usize, y: &mut [f64]) {
        for (yi, &o) in y.iter_mut().zip(&self.registers.outputs) {
            *yi = vals[o as usize][lane];
        }
    }

    /// Evaluates `y = f(x)` (bit-identical to running the generic function on `f64`).
    pub fn eval(&self, x: &[f64], ws: &mut Workspace, y: &mut [f64]) -> Result<(), AdError> {
        self.check(x, ws)?;
        check_len("outputs y", self.outputs.len(), y.len())?;
        self.forward::<0>(x, ws);
        self.write_outputs(&ws.loc.vals, 0, y);
        Ok(())
    }

    /// Evaluates `y = f(x)` and the Jacobian values `jac` in the order of
    /// [`Tape::jacobian_pattern`].
    pub fn jacobian(
        &self,
        x: &[f64],
        ws: &mut Workspace,
        y: &mut [f64],
        jac: &mut [f64],
    ) -> Result<(), AdError> {
        self.check(x, ws)?;
        check_len("outputs y", self.outputs.len(), y.len())?;
        check_len("Jacobian values", self.jac_pattern.nnz(), jac.len())?;
        self.value_gradient_sweep([x], &mut ws.loc.vals, &mut ws.kept, &mut ws.grad);
        self.write_outputs(&ws.loc.vals, 0, y);
        self.sparse_jacobian_extract(self.sparse.compact(), &ws.grad, jac);
        Ok(())
    }

    /// Same result as [`Tape::jacobian`] by the alternative algorithm: reverse vector
    /// sweeps over row colours, `LANES` at a time (kept for comparison and testing).
    pub fn jacobian_coloured(
        &self,
        x: &[f64],
        ws: &mut Workspace,
        y: &mut [f64],
        jac: &mut [f64],
    ) -> Result<(), AdError> {
        self.check(x, ws)?;
        check_len("outputs y", self.outputs.len(), y.len())?;
        check_len("Jacobian values", self.jac_pattern.nnz(), jac.len())?;
        self.forward::<1>(x, ws);
        self.write_outputs(&ws.loc.vals, 0, y);
        self.jacobian_sweeps(ws, jac);
        Ok(())
    }

    /// Evaluates `y = f(x)` and the dense gradient `g = Σ wᵢ ∇yᵢ` (a vector–Jacobian
    /// product; `w = eₖ` gives the gradient of output `k`).
    pub fn vjp(
        &self,
        x: &[f64],
        w: &[f64],
        ws: &mut Workspace,
        y: &mut [f64],
        g: &mut [f64],
    ) -> Result<(), AdError> {
        self.check(x, ws)?;
        check_len("weights w", self.outputs.len(), w.len())?;
        check_len("outputs y", self.outputs.len(), y.len())?;
        check_len("gradient g", self.n_in, g.len())?;
        self.forward::<1>(x, ws);
        self.write_outputs(&ws.loc.vals, 0, y);
        self.adjoint_sweep(ws, w);
        g.iter_mut().zip(&ws.loc.abar).for_each(|(g, [a])| *g = *a);
        Ok(())
    }

    /// Evaluates the dense gradient `g = ∇y_k` of output `k` and returns `y_k`.
    pub fn gradient(
        &self,
        x: &[f64],
        k: usize,
        ws: &mut Workspace,
        g: &mut [f64],
    ) -> Result<f64, AdError> {
        self.check(x, ws)?;
        check_len("gradient g", self.n_in, g.len())?;
        if k >= self.outputs.len() {
            return Err(AdError::OutputIndex {
                index: k,
                n_outputs: self.outputs.len(),
            });
        }
        self.forward::<1>(x, ws);
        ws.loc.abar.iter_mut().for_each(|a| *a = [0.0]);
        ws.loc.abar[self.outputs[k] as usize] = [1.0];
        self.reverse_scalar(ws);
        g.iter_mut().zip(&ws.loc.abar).for_each(|(g, [a])| *g = *a);
        Ok(ws.loc.vals[self.registers.outputs[k] as usize][0])
    }

    /// Evaluates `y = f(x)` and the lower triangle of the exact Hessian of `Σ λᵢ yᵢ`,
    /// in the order of [`Tape::hessian_pattern`].
    pub fn hessian(
        &self,
        x: &[f64],
        lambda: &[f64],
        ws: &mut Workspace,
        y: &mut [f64],
        hes: &mut [f64],
    ) -> Result<(), AdError> {
        self.check(x, ws)?;
        check_len("multipliers lambda", self.outputs.len(), lambda.len())?;
        check_len("outputs y", self.outputs.len(), y.len())?;
        check_len("Hessian values", self.hes_pattern.nnz(), hes.len())?;
        self.forward::<2>(x, ws);
        self.write_outputs(&ws.loc.vals, 0, y);
        self.adjoint_sweep(ws, lambda);
        self.sparse_forward(self.sparse.full(), &ws.loc.part, &mut ws.grad);
        self.sparse_hessian(&ws.loc, &ws.grad, &mut ws.adot, [hes]);
        Ok(())
    }

    /// Same result as [`Tape::hessian`] by the alternative algorithm: forward-over-reverse
    /// over a distance-2 colouring of the columns, `LANES` at a time.
    pub fn hessian_coloured(
        &self,
        x: &[f64],
        lambda: &[f64],
        ws: &mut Workspace,
        y: &mut [f64],
        hes: &mut [f64],
    ) -> Result<(), AdError> {
        self.check(x, ws)?;
        check_len("multipliers lambda", self.outputs.len(), lambda.len())?;
        check_len("outputs y", self.outputs.len(), y.len())?;
        check_len("Hessian values", self.hes_pattern.nnz(), hes.len())?;
        self.forward::<2>(x, ws);
        self.write_outputs(&ws.loc.vals, 0, y);
        self.adjoint_sweep(ws, lambda);
        self.hessian_sweeps(ws, hes);
        Ok(())
    }
}
