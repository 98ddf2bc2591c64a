//! Radau transcription of the gait problem into a sparse NLP (FORMULATION 8.2–8.6, v2).
//!
//! The model enters through a [`NodeFunction`]: one function of the variables of a
//! collocation point returning the path constraints and the cost integrand, with exact
//! sparse derivatives; it is evaluated independently (in parallel) at the 3N collocation
//! points. Collocation, continuity, symmetry/periodicity and speed constraints and the
//! distance normalisation of the cost are bilinear or rational in few variables and are
//! differentiated here by hand.

use crate::jacobian_fill::JacobianFill;
use crate::layout::{Layout, Point};
use crate::linear_rows::{LinearRow, Term};
use crate::problem::{GaitProblem, TAU_ARM};
use crate::radau;
use rayon::prelude::*;
use std::collections::HashMap;
use std::sync::Mutex;
use stride_solve::nlp::{BlockStructure, EvalError, Nlp, NlpFunction, Sparsity};

/// The model function of one collocation point and its sparse derivatives.
///
/// Inputs, in this order (NLP variables, scaled): activations (nm), tendon forces (nm),
/// tendon-force derivatives (nm), activation derivatives (nm, interval control),
/// coordinates (nq), speeds (nq), accelerations (nq), arm activations (na), arm
/// excitations (na, interval control). Outputs: the path constraints (bounds from
/// [`NodeFunction::constraint_bounds`]) followed by the cost integrand L (last output).
pub trait NodeFunction: Sync {
    /// Number of inputs.
    fn n_inputs(&self) -> usize;
    /// Number of outputs (path constraints + 1).
    fn n_outputs(&self) -> usize;
    /// Bounds `(lower, upper)` of the path-constraint outputs (all but the last output).
    fn constraint_bounds(&self) -> Vec<(f64, f64)>;
    /// Jacobian nonzeros as `(output, input)`.
    fn jacobian_pattern(&self) -> Vec<(usize, usize)>;
    /// Lower-triangle nonzeros `(input_row, input_col)`, row ≥ col, of Σ w_i ∇² y_i.
    fn hessian_pattern(&self) -> Vec<(usize, usize)>;
    /// Output values.
    fn eval(&self, x: &[f64], y: &mut [f64]);
    /// Jacobian values in pattern order (and output values).
    fn jacobian(&self, x: &[f64], y: &mut [f64], jac: &mut [f64]);
    /// Hessian values of Σ w_i y_i in pattern order.
    fn hessian(&self, x: &[f64], w: &[f64], hess: &mut [f64]);
    /// Most points the batch methods evaluate together (1: no batch form).
    fn batch(&self) -> usize {
        1
    }
    /// [`NodeFunction::eval`] at 1 to [`NodeFunction::batch`] points: `xs` and `ys` hold
    /// one block per point, one after the other.
    fn eval_batch(&self, xs: &[f64], ys: &mut [f64]) {
        let (nin, nout) = (self.n_inputs(), self.n_outputs());
        for (x, y) in xs
            .chunks_exact(nin.max(1))
            .zip(ys.chunks_exact_mut(nout.max(1)))
        {
            self.eval(x, y);
        }
    }
    /// [`NodeFunction::jacobian`] at 1 to [`NodeFunction::batch`] points: `xs`, `ys` and
    /// `jacs` hold one block per point, one after the other.
    fn jacobian_batch(&self, xs: &[f64], ys: &mut [f64], jacs: &mut [f64]) {
        let points = xs.len() / self.n_inputs().max(1);
        let (nin, nout) = (self.n_inputs(), self.n_outputs());
        let nj = jacs.len() / points.max(1);
        for p in 0..points {
            self.jacobian(
                &xs[p * nin..(p + 1) * nin],
                &mut ys[p * nout..(p + 1) * nout],
                &mut jacs[p * nj..(p + 1) * nj],
            );
        }
    }
    /// [`NodeFunction::hessian`] at 1 to [`NodeFunction::batch`] points, each with its own
    /// weights: `xs`, `ws` and `hess` hold one block per point.
    fn hessian_batch(&self, xs: &[f64], ws: &[f64], hess: &mut [f64]) {
        let points = xs.len() / self.n_inputs().max(1);
        let (nin, nout) = (self.n_inputs(), self.n_outputs());
        let nh = hess.len() / points.max(1);
        for p in 0..points {
            self.hessian(
                &xs[p * nin..(p + 1) * nin],
                &ws[p * nout..(p + 1) * nout],
                &mut hess[p * nh..(p + 1) * nh],
            );
        }
    }
    /// Output values, Jacobians and Hessians of Σ w_i y_i at 1 to
    /// [`NodeFunction::batch`] points together (one block per point in each slice): the
    /// same numbers as [`NodeFunction::jacobian_batch`] and [`NodeFunction::hessian_batch`],
    /// for node functions that get the Jacobian from the Hessian's sweeps.
    fn jacobian_hessian_batch(
        &self,
        xs: &[f64],
        ws: &[f64],
        ys: &mut [f64],
        jacs: &mut [f64],
        hess: &mut [f64],
    ) {
        self.jacobian_batch(xs, ys, jacs);
        self.hessian_batch(xs, ws, hess);
    }
}

impl<N: NodeFunction + Send> NodeFunction for std::sync::Arc<N> {
    fn n_inputs(&self) -> usize {
        (**self).n_inputs()
    }
    fn n_outputs(&self) -> usize {
        (**self).n_outputs()
    }
    fn constraint_bounds(&self) -> Vec<(f64, f64)> {
        (**self).constraint_bounds()
    }
    fn jacobian_pattern(&self) -> Vec<(usize, usize)> {
        (**self).jacobian_pattern()
    }
    fn hessian_pattern(&self) -> Vec<(usize, usize)> {
        (**self).hessian_pattern()
    }
    fn eval(&self, x: &[f64], y: &mut [f64]) {
        (**self).eval(x, y)
    }
    fn jacobian(&self, x: &[f64], y: &mut [f64], jac: &mut [f64]) {
        (**self).jacobian(x, y, jac)
    }
    fn hessian(&self, x: &[f64], w: &[f64], hess: &mut [f64]) {
        (**self).hessian(x, w, hess)
    }
    fn batch(&self) -> usize {
        (**self).batch()
    }
    fn eval_batch(&self, xs: &[f64], ys: &mut [f64]) {
        (**self).eval_batch(xs, ys)
    }
    fn jacobian_batch(&self, xs: &[f64], ys: &mut [f64], jacs: &mut [f64]) {
        (**self).jacobian_batch(xs, ys, jacs)
    }
    fn hessian_batch(&self, xs: &[f64], ws: &[f64], hess: &mut [f64]) {
        (**self).hessian_batch(xs, ws, hess)
    }
    fn jacobian_hessian_batch(
        &self,
        xs: &[f64],
        ws: &[f64],
        ys: &mut [f64],
        jacs: &mut [f64],
        hess: &mut [f64],
    ) {
        (**self).jacobian_hessian_batch(xs, ws, ys, jacs, hess)
    }
}

/// Node input block offsets for a layout.
#[derive(Clone, Copy, Debug)]
pub struct NodeInputs {
    /// Muscles.
    pub nm: usize,
    /// Coordinates.
    pub nq: usize,
    /// Arm actuators.
    pub na: usize,
}

impl NodeInputs {
    /// Offset of the activations.
    pub fn a(&self) -> usize {
        0
    }
    /// Offset of the scaled tendon forces.
    pub fn f(&self) -> usize {
        self.nm
    }
    /// Offset of the scaled tendon-force derivatives.
    pub fn df(&self) -> usize {
        2 * self.nm
    }
    /// Offset of the scaled activation derivatives.
    pub fn da(&self) -> usize {
        3 * self.nm
    }
    /// Offset of the scaled coordinates.
    pub fn q(&self) -> usize {
        4 * self.nm
    }
    /// Offset of the scaled speeds.
    pub fn v(&self) -> usize {
        4 * self.nm + self.nq
    }
    /// Offset of the scaled accelerations.
    pub fn qdd(&self) -> usize {
        4 * self.nm + 2 * self.nq
    }
    /// Offset of the arm activations.
    pub fn arm(&self) -> usize {
        4 * self.nm + 3 * self.nq
    }
    /// Offset of the arm excitations.
    pub fn e_arm(&self) -> usize {
        4 * self.nm + 3 * self.nq + self.na
    }
    /// Number of inputs.
    pub fn len(&self) -> usize {
        4 * self.nm + 3 * self.nq + 2 * self.na
    }
    /// Whether there are no inputs.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }
    /// Global NLP index of every node input at collocation point (k, j).
    pub fn global_indices(&self, l: &Layout, k: usize, j: usize) -> Vec<usize> {
        let p = Point::Col(k, j);
        let mut g = Vec::with_capacity(self.len());
        g.extend((0..self.nm).map(|m| l.a(p, m)));
        g.extend((0..self.nm).map(|m| l.f(p, m)));
        g.extend((0..self.nm).map(|m| l.u_df(k, j, m)));
        g.extend((0..self.nm).map(|m| l.u_da(k, m)));
        g.extend((0..self.nq).map(|i| l.q(p, i)));
        g.extend((0..self.nq).map(|i| l.v(p, i)));
        g.extend((0..self.nq).map(|i| l.u_dv(k, j, i)));
        g.extend((0..self.na).map(|i| l.arm(p, i)));
        g.extend((0..self.na).map(|i| l.e_arm(k, i)));
        g
    }
}

/// Accumulates a symmetric lower-triangle pattern with merged duplicates.
#[derive(Default)]
struct HessianBuilder {
    pattern: Sparsity,
    index: HashMap<(usize, usize), usize>,
}

impl HessianBuilder {
    fn slot(&mut self, r: usize, c: usize) -> usize {
        let key = if r >= c { (r, c) } else { (c, r) };
        if let Some(&p) = self.index.get(&key) {
            return p;
        }
        let p = self.pattern.push(key.0, key.1);
        self.index.insert(key, p);
        p
    }
}

/// Cached node evaluations at the last point.
#[derive(Default)]
struct Cache {
    x: Vec<f64>,
    values: Vec<f64>,
    jac: Vec<f64>,
    valid_values: bool,
    valid_jac: bool,
}

impl Cache {
    /// Makes the cache belong to `x`, invalidating what it held for another point.
    fn move_to(&mut self, x: &[f64]) {
        if self.x.as_slice() != x {
            self.x.clear();
            self.x.extend_from_slice(x);
            self.valid_values = false;
            self.valid_jac = false;
        }
    }
}

/// What makes a transcription a tracking problem (FORMULATION 12.6): the node function
/// takes `n_data` constant inputs after its variable inputs (the measured quantities at that
/// collocation point), the duration is fixed, there is neither a symmetry, periodicity nor
/// speed constraint, and the cost is the quadrature of L over time (not divided by the
/// distance walked).
#[derive(Clone, Debug)]
pub struct TrackingData {
    /// Constant node inputs of every collocation point (point-major, `n_data` each).
    pub node_data: Vec<f64>,
    /// Constant inputs per collocation point.
    pub n_data: usize,
    /// Fixed duration t_f [s].
    pub duration: f64,
    /// Boundary states tracked by the cost besides the collocation points (the first
    /// mesh point is none of them, the last only with the quadrature's smallest weight).
    pub boundary: Vec<BoundaryTarget>,
}

/// A boundary state tracked by the cost: the term `weight (x[var] − target)²` joins the
/// quadrature sum `S = Σ B_j L` of the cost `t_f / N · S` (scaled variables).
#[derive(Clone, Debug, PartialEq)]
pub struct BoundaryTarget {
    /// Index of the NLP variable.
    pub var: usize,
    /// Its measured value (scaled).
    pub target: f64,
    /// Weight, in units of one collocation point's cost.
    pub weight: f64,
}

/// The static parameters of a transcription (constant over time): NLP variables after the
/// layout's, read by every node as inputs after its variable inputs.
#[derive(Clone, Debug, Default)]
pub struct StaticBlock {
    /// Lower bounds of the scaled parameters.
    pub lower: Vec<f64>,
    /// Upper bounds of the scaled parameters.
    pub upper: Vec<f64>,
}

impl StaticBlock {
    /// The block of `statics`: every parameter bounded to [−0.5, 0.5] by its scaling.
    pub fn of(statics: &crate::statics::StaticParameters) -> Self {
        Self {
            lower: vec![-0.5; statics.len()],
            upper: vec![0.5; statics.len()],
        }
    }

    /// Number of static parameters.
    pub fn len(&self) -> usize {
        self.lower.len()
    }

    /// Whether there are none.
    pub fn is_empty(&self) -> bool {
        self.lower.is_empty()
    }
}

/// Marks a node Hessian entry that involves a constant input (not scattered).
const NO_SLOT: usize = usize::MAX;

/// The transcribed problem: implements [`Nlp`].
pub struct Transcription<F: NodeFunction> {
    /// The problem.
    pub problem: GaitProblem,
    node: F,
    n_nodes: usize,
    n_out: usize,
    n_path: usize,
    /// Global variable index of each node input, per node (node-major).
    node_globals: Vec<usize>,
    node_jac_pattern: Vec<(usize, usize)>,
    node_hess_pattern: Vec<(usize, usize)>,
    /// Hessian position of each node Hessian entry per node.
    node_hess_pos: Vec<usize>,
    /// Hessian positions of (t_f, u), (x_N, u), (x_0, u) for each cost-gradient entry, per node.
    cost_cross_pos: Vec<[usize; 3]>,
    /// For each node Jacobian entry of the cost row: the entry index in the node pattern.
    cost_entries: Vec<usize>,
    linear_rows: Vec<LinearRow>,
    /// How the constraint Jacobian values are written from the node Jacobians and the
    /// linear rows.
    jac_fill: JacobianFill,
    /// Hessian position of (t_f, var) per h-term of each linear row.
    linear_hess_pos: Vec<Vec<usize>>,
    speed_row: usize,
    speed_pos: [usize; 3],
    hess_speed_pos: [usize; 3],
    hess_cost_pos: [usize; 5],
    /// Hessian positions (var, var) and (t_f, var) of each tracked boundary state.
    hess_boundary_pos: Vec<[usize; 2]>,
    jacobian: Sparsity,
    hessian: Sparsity,
    n_constraints: usize,
    constraint_lo: Vec<f64>,
    constraint_hi: Vec<f64>,
    x0: Vec<f64>,
    tx0: usize,
    txn: usize,
    cache: Mutex<Cache>,
    /// Node Hessian values of the last Hessian evaluation (reused, not reallocated).
    node_hessians: Mutex<Vec<f64>>,
    /// Tracking problem data (`None`: the predictive problem).
    tracking: Option<TrackingData>,
    /// Static parameters (NLP variables from `problem.layout.len()` on).
    statics: StaticBlock,
    /// Variable inputs per node: the point's variables and the static parameters.
    n_var: usize,
}

impl<F: NodeFunction> Transcription<F> {
    /// Transcribe `problem` with the node function `node`, starting from `x0`.
    pub fn new(problem: GaitProblem, node: F, x0: Vec<f64>) -> Self {
        Self::with_statics(problem, node, x0, None, StaticBlock::default())
    }

    /// Transcribe the tracking problem `problem` with the node function `node` (whose
    /// inputs end with `tracking.n_data` constants), starting from `x0`.
    pub fn tracking(problem: GaitProblem, node: F, x0: Vec<f64>, tracking: TrackingData) -> Self {
        Self::with_statics(problem, node, x0, Some(tracking), StaticBlock::default())
    }

    /// Transcribe `problem` (a prediction, or a tracking problem with `tracking`) with
    /// static parameters: `x0` ends with their scaled initial values, and the node
    /// function's inputs are its variable inputs, then the static parameters, then the
    /// tracking constants.
    pub fn with_statics(
        problem: GaitProblem,
        node: F,
        x0: Vec<f64>,
        tracking: Option<TrackingData>,
        statics: StaticBlock,
    ) -> Self {
        let l = problem.layout.clone();
        let inputs = NodeInputs {
            nm: l.nm,
            nq: l.nq,
            na: l.na,
        };
        let n_data = tracking.as_ref().map_or(0, |t| t.n_data);
        let n_var = inputs.len() + statics.len();
        assert_eq!(node.n_inputs(), n_var + n_data, "node function inputs");
        assert_eq!(x0.len(), l.len() + statics.len(), "initial point length");
        let n_out = node.n_outputs();
        let n_path = n_out - 1;
        let n_nodes = 3 * l.n;
        let ns = l.n_states();
        let per_point = ns + n_path;
        let static_globals: Vec<usize> = (l.len()..l.len() + statics.len()).collect();
        let node_globals: Vec<usize> = (0..l.n)
            .flat_map(|k| (1..=3).map(move |j| (k, j)))
            .flat_map(|(k, j)| {
                let mut g = inputs.global_indices(&l, k, j);
                g.extend_from_slice(&static_globals);
                g
            })
            .collect();
        let node_jac_pattern = node.jacobian_pattern();
        let node_hess_pattern = node.hessian_pattern();
        let tf = l.tf();
        let tx = problem.gait.forward_translation;
        let tx0 = l.q(Point::Mesh(0), tx);
        let txn = l.q(Point::Mesh(l.n), tx);

        let mut jacobian = Sparsity::default();
        let mut hb = HessianBuilder::default();
        let mut node_hess_pos = Vec::with_capacity(n_nodes * node_hess_pattern.len());
        let mut cost_cross_pos = Vec::new();
        let cost_entries: Vec<usize> = node_jac_pattern
            .iter()
            .enumerate()
            .filter(|(_, &(o, i))| o == n_path && i < n_var)
            .map(|(e, _)| e)
            .collect();
        // The node entries that are constraint values (all but the cost row's), written
        // node after node from the first Jacobian position on.
        let node_constraints: Vec<usize> = (0..node_jac_pattern.len())
            .filter(|&e| node_jac_pattern[e].0 < n_path && node_jac_pattern[e].1 < n_var)
            .collect();
        let node_jac_start = jacobian.nnz();
        let mut linear_rows = Vec::new();
        let c = radau::collocation_matrix();
        let s = &problem.scaling;
        for node_i in 0..n_nodes {
            let (k, j) = (node_i / 3, node_i % 3 + 1);
            let g = &node_globals[node_i * n_var..(node_i + 1) * n_var];
            let base = node_i * per_point;
            // Collocation equations of every state component.
            for st in 0..ns {
                let row = base + st;
                let mut terms = Vec::new();
                let arm_i = st.checked_sub(2 * l.nm + 2 * l.nq);
                for (r, cr) in c.iter().enumerate() {
                    let p = if r == 0 {
                        Point::Mesh(k)
                    } else {
                        Point::Col(k, r)
                    };
                    terms.push(Term {
                        var: l.state(p, st),
                        coef: -cr[j - 1],
                        times_h: false,
                    });
                }
                let (var, coef) = if st < l.nm {
                    (l.u_da(k, st), s.activation_rate)
                } else if st < 2 * l.nm {
                    (
                        l.u_df(k, j, st - l.nm),
                        s.tendon_force_rate / s.tendon_force,
                    )
                } else if st < 2 * l.nm + l.nq {
                    let i = st - 2 * l.nm;
                    (l.v(Point::Col(k, j), i), s.v[i] / s.q[i])
                } else if st < 2 * l.nm + 2 * l.nq {
                    let i = st - 2 * l.nm - l.nq;
                    (l.u_dv(k, j, i), s.a[i] / s.v[i])
                } else {
                    let i = arm_i.unwrap();
                    terms.push(Term {
                        var: l.arm(Point::Col(k, j), i),
                        coef: -1.0 / TAU_ARM,
                        times_h: true,
                    });
                    (l.e_arm(k, i), 1.0 / TAU_ARM)
                };
                terms.push(Term {
                    var,
                    coef,
                    times_h: true,
                });
                linear_rows.push(LinearRow { row, terms });
            }
            // Path constraints from the node function.
            for &e in &node_constraints {
                let (o, inp) = node_jac_pattern[e];
                jacobian.push(base + ns + o, g[inp]);
            }
            for &(r, cc) in &node_hess_pattern {
                node_hess_pos.push(if r < n_var && cc < n_var {
                    hb.slot(g[r], g[cc])
                } else {
                    NO_SLOT
                });
            }
            for &e in &cost_entries {
                let u = g[node_jac_pattern[e].1];
                cost_cross_pos.push([hb.slot(tf, u), hb.slot(txn, u), hb.slot(tx0, u)]);
            }
        }
        // Continuity.
        let mut row = n_nodes * per_point;
        for k in 0..l.n {
            for st in 0..ns {
                linear_rows.push(LinearRow {
                    row,
                    terms: vec![
                        Term {
                            var: l.state(Point::Mesh(k + 1), st),
                            coef: 1.0,
                            times_h: false,
                        },
                        Term {
                            var: l.state(Point::Col(k, 3), st),
                            coef: -1.0,
                            times_h: false,
                        },
                    ],
                });
                row += 1;
            }
        }
        // Symmetry (half cycle) or periodicity (full cycle); none when tracking.
        let half = problem.is_half_cycle();
        let boundary = tracking.is_none();
        let last = Point::Mesh(l.n);
        let first = Point::Mesh(0);
        let mut pair = |a: usize, b: usize, sign: f64, row: &mut usize| {
            linear_rows.push(LinearRow {
                row: *row,
                terms: vec![
                    Term {
                        var: a,
                        coef: 1.0,
                        times_h: false,
                    },
                    Term {
                        var: b,
                        coef: -sign,
                        times_h: false,
                    },
                ],
            });
            *row += 1;
        };
        let gait = &problem.gait;
        let arm_coords = gait.actuator_driven();
        for (i, gc) in gait.coordinates.iter().enumerate() {
            if i == tx || !boundary {
                continue;
            }
            let (m, sg) = if half {
                (gc.mirror, gc.mirror_sign)
            } else {
                (i, 1.0)
            };
            pair(l.q(last, i), l.q(first, m), sg, &mut row);
        }
        for (i, gc) in gait.coordinates.iter().enumerate().filter(|_| boundary) {
            let (m, sg) = if half {
                (gc.mirror, gc.mirror_sign)
            } else {
                (i, 1.0)
            };
            pair(l.v(last, i), l.v(first, m), sg, &mut row);
        }
        for m in (0..l.nm).filter(|_| boundary) {
            let pm = if half { gait.muscle_mirror[m] } else { m };
            pair(l.a(last, m), l.a(first, pm), 1.0, &mut row);
        }
        for m in (0..l.nm).filter(|_| boundary) {
            let pm = if half { gait.muscle_mirror[m] } else { m };
            pair(l.f(last, m), l.f(first, pm), 1.0, &mut row);
        }
        for (ai, &ci) in arm_coords.iter().enumerate().filter(|_| boundary) {
            let pm = if half {
                let mc = gait.coordinates[ci].mirror;
                arm_coords.iter().position(|&x| x == mc).unwrap_or(ai)
            } else {
                ai
            };
            pair(l.arm(last, ai), l.arm(first, pm), 1.0, &mut row);
        }
        // (a tracking problem has no speed row: its index is one past the last constraint)
        let speed_row = row;
        let n_constraints = if boundary { row + 1 } else { row };
        // Jacobian entries of linear rows.
        let mut linear_jac_pos = Vec::with_capacity(linear_rows.len());
        let mut linear_hess_pos = Vec::with_capacity(linear_rows.len());
        for lr in &linear_rows {
            let mut pos: Vec<usize> = Vec::with_capacity(lr.terms.len() + 1);
            let mut hpos = Vec::new();
            for (ti, t) in lr.terms.iter().enumerate() {
                // A variable appearing in two terms of a row shares one Jacobian entry.
                let shared = lr.terms[..ti].iter().position(|u| u.var == t.var);
                pos.push(match shared {
                    Some(first) => pos[first],
                    None => jacobian.push(lr.row, t.var),
                });
                if t.times_h {
                    hpos.push(hb.slot(t.var, tf));
                }
            }
            if lr.terms.iter().any(|t| t.times_h) {
                pos.push(jacobian.push(lr.row, tf));
            }
            linear_jac_pos.push(pos);
            linear_hess_pos.push(hpos);
        }
        let speed_pos = if boundary {
            [
                jacobian.push(speed_row, txn),
                jacobian.push(speed_row, tx0),
                jacobian.push(speed_row, tf),
            ]
        } else {
            [NO_SLOT; 3]
        };
        let hess_speed_pos = [hb.slot(txn, tf), hb.slot(tx0, tf), hb.slot(tf, tf)];
        let hess_boundary_pos = (tracking.iter().flat_map(|t| &t.boundary))
            .map(|b| [hb.slot(b.var, b.var), hb.slot(tf, b.var)])
            .collect();
        let hess_cost_pos = [
            hb.slot(tf, txn),
            hb.slot(tf, tx0),
            hb.slot(txn, txn),
            hb.slot(tx0, tx0),
            hb.slot(txn, tx0),
        ];
        // Constraint bounds.
        let mut constraint_lo = vec![0.0; n_constraints];
        let mut constraint_hi = vec![0.0; n_constraints];
        let path_bounds = node.constraint_bounds();
        for node_i in 0..n_nodes {
            let base = node_i * per_point + ns;
            for (o, &(lo, hi)) in path_bounds.iter().enumerate() {
                constraint_lo[base + o] = lo;
                constraint_hi[base + o] = hi;
            }
        }
        if boundary {
            constraint_lo[speed_row] = problem.settings.speed;
            constraint_hi[speed_row] = problem.settings.speed;
        }
        let jac_fill = JacobianFill::new(
            node_jac_pattern.len(),
            &node_constraints,
            node_jac_start,
            &linear_rows,
            &linear_jac_pos,
        );
        Self {
            problem,
            node,
            n_nodes,
            n_out,
            n_path,
            node_globals,
            node_jac_pattern,
            node_hess_pattern,
            jac_fill,
            node_hess_pos,
            cost_cross_pos,
            cost_entries,
            linear_rows,
            linear_hess_pos,
            speed_row,
            speed_pos,
            hess_speed_pos,
            hess_cost_pos,
            hess_boundary_pos,
            jacobian,
            hessian: hb.pattern,
            n_constraints,
            constraint_lo,
            constraint_hi,
            x0,
            tx0,
            txn,
            cache: Mutex::new(Cache::default()),
            node_hessians: Mutex::new(Vec::new()),
            tracking,
            statics,
            n_var,
        }
    }

    /// Forget the cached node evaluations, so that the next evaluation at any point
    /// recomputes every collocation point (for timing single evaluations).
    pub fn clear_cache(&self) {
        let mut cache = self.cache.lock().unwrap_or_else(|e| e.into_inner());
        cache.x.clear();
        cache.valid_values = false;
        cache.valid_jac = false;
    }

    /// The node function.
    pub fn node(&self) -> &F {
        &self.node
    }

    /// Inputs of node `i` gathered from the NLP vector (and its constants when tracking).
    fn gather(&self, x: &[f64], i: usize, out: &mut [f64]) {
        let n = self.n_var;
        for (o, &g) in out.iter_mut().zip(&self.node_globals[i * n..(i + 1) * n]) {
            *o = x[g];
        }
        if let Some(t) = &self.tracking {
            let d = t.n_data;
            out[n..n + d].copy_from_slice(&t.node_data[i * d..(i + 1) * d]);
        }
    }

    /// Inputs per node: the variable inputs (with the static parameters) and the tracking
    /// constants.
    fn node_inputs(&self) -> usize {
        self.n_var + self.tracking.as_ref().map_or(0, |t| t.n_data)
    }

    /// Scale of the forward translation in the distance of the cost (0 when the cost is not
    /// divided by the distance).
    /// The tracked boundary states (none for a prediction).
    fn boundary(&self) -> impl Iterator<Item = &BoundaryTarget> {
        self.tracking.iter().flat_map(|t| &t.boundary)
    }

    fn cost_stx(&self) -> f64 {
        match self.tracking {
            Some(_) => 0.0,
            None => self.problem.scaling.q[self.problem.gait.forward_translation],
        }
    }

    /// Gathers the inputs of the `points` nodes from `first` on into `xin`, one block per
    /// node, and returns those blocks.
    fn gather_points<'a>(
        &self,
        x: &[f64],
        first: usize,
        points: usize,
        xin: &'a mut [f64],
    ) -> &'a [f64] {
        let n = self.node_inputs();
        for p in 0..points {
            self.gather(x, first + p, &mut xin[p * n..(p + 1) * n]);
        }
        &xin[..points * n]
    }

    /// Evaluate all nodes (values, and Jacobians if `with_jac`) at `x`, using the cache.
    fn with_nodes<R>(&self, x: &[f64], with_jac: bool, f: impl FnOnce(&Cache) -> R) -> R {
        let mut cache = self.cache.lock().unwrap_or_else(|e| e.into_inner());
        cache.move_to(x);
        let nin = self.node_inputs();
        let nout = self.n_out;
        if with_jac && !cache.valid_jac {
            let nj = self.node_jac_pattern.len();
            let c = &mut *cache;
            c.values.resize(self.n_nodes * nout, 0.0);
            c.jac.resize(self.n_nodes * nj, 0.0);
            // Points in batches that the node function evaluates together.
            let batch = self.node.batch().max(1);
            c.values
                .par_chunks_mut(nout * batch)
                .zip(c.jac.par_chunks_mut(nj * batch))
                .enumerate()
                .for_each_init(
                    || vec![0.0; nin * batch],
                    |xin, (b, (y, jac))| {
                        let xs = self.gather_points(x, b * batch, y.len() / nout, xin);
                        self.node.jacobian_batch(xs, y, jac);
                    },
                );
            c.valid_jac = true;
            c.valid_values = true;
        } else if !cache.valid_values {
            let c = &mut *cache;
            c.values.resize(self.n_nodes * nout, 0.0);
            let batch = self.node.batch().max(1);
            c.values
                .par_chunks_mut(nout * batch)
                .enumerate()
                .for_each_init(
                    || vec![0.0; nin * batch],
                    |xin, (b, y)| {
                        let xs = self.gather_points(x, b * batch, y.len() / nout, xin);
                        self.node.eval_batch(xs, y);
                    },
                );
            c.valid_values = true;
        }
        f(&cache)
    }

    /// Pieces of the cost: (S = Σ B_j L, d, t_f, c = 1/(N d)) at x.
    fn cost_parts(&self, x: &[f64], values: &[f64]) -> (f64, f64, f64, f64) {
        let b = radau::quadrature_weights();
        let s: f64 = (0..self.n_nodes)
            .map(|i| b[i % 3] * values[i * self.n_out + self.n_path])
            .sum::<f64>()
            + self
                .boundary()
                .map(|t| t.weight * (x[t.var] - t.target).powi(2))
                .sum::<f64>();
        let (d, cc) = self.distance_factor(x);
        (s, d, x[self.problem.layout.tf()], cc)
    }

    /// The distance walked d [m] and the cost factor c = 1/(N d) at x (d = 1 when tracking).
    fn distance_factor(&self, x: &[f64]) -> (f64, f64) {
        if self.tracking.is_some() {
            return (1.0, 1.0 / self.problem.layout.n as f64);
        }
        let stx = self.problem.scaling.q[self.problem.gait.forward_translation];
        let d = stx * (x[self.txn] - x[self.tx0]);
        (d, 1.0 / (self.problem.layout.n as f64 * d))
    }

    /// Objective terms at `x` reported separately: (J, distance [m], duration [s]).
    pub fn objective_parts(&self, x: &[f64]) -> (f64, f64, f64) {
        self.with_nodes(x, false, |c| {
            let (s, d, tf, cc) = self.cost_parts(x, &c.values);
            (cc * tf * s, d, tf)
        })
    }

    /// Node output values (path constraints then L) at every collocation point.
    pub fn node_values(&self, x: &[f64]) -> Vec<f64> {
        self.with_nodes(x, false, |c| c.values.clone())
    }
}

/// Reports the first non-finite value of `v` as an error of `function`; long vectors are
/// scanned in parallel first (the serial scan then only runs to name the bad entry).
fn check(function: NlpFunction, v: &[f64]) -> Result<(), EvalError> {
    let finite = |c: &[f64]| c.iter().fold(true, |ok, x| ok & x.is_finite());
    if v.par_chunks(1 << 14).all(finite) {
        return Ok(());
    }
    stride_solve::nlp::check_finite(function, v)
}

impl<F: NodeFunction> Nlp for Transcription<F> {
    fn n(&self) -> usize {
        self.problem.layout.len() + self.statics.len()
    }
    fn blocks(&self) -> Option<BlockStructure> {
        let mut b = self.problem.layout.interval_blocks();
        let first = self.problem.layout.len();
        b.global_variables.extend(first..first + self.statics.len());
        Some(b)
    }
    fn m(&self) -> usize {
        self.n_constraints
    }
    fn bounds(&self, x_l: &mut [f64], x_u: &mut [f64], g_l: &mut [f64], g_u: &mut [f64]) {
        let (lo, hi) = self.problem.variable_bounds();
        let n = lo.len();
        x_l[..n].copy_from_slice(&lo);
        x_u[..n].copy_from_slice(&hi);
        x_l[n..].copy_from_slice(&self.statics.lower);
        x_u[n..].copy_from_slice(&self.statics.upper);
        if let Some(t) = &self.tracking {
            let tf = self.problem.layout.tf();
            (x_l[tf], x_u[tf]) = (t.duration, t.duration);
        }
        g_l.copy_from_slice(&self.constraint_lo);
        g_u.copy_from_slice(&self.constraint_hi);
    }
    fn initial_point(&self, x: &mut [f64]) {
        x.copy_from_slice(&self.x0);
    }
    fn objective(&self, x: &[f64]) -> Result<f64, EvalError> {
        let j = self.objective_parts(x).0;
        check(NlpFunction::Objective, &[j])?;
        Ok(j)
    }
    fn gradient(&self, x: &[f64], grad: &mut [f64]) -> Result<(), EvalError> {
        grad.iter_mut().for_each(|g| *g = 0.0);
        let nj = self.node_jac_pattern.len();
        let nin = self.n_var;
        let b = radau::quadrature_weights();
        self.with_nodes(x, true, |c| {
            let (s, d, tf, cc) = self.cost_parts(x, &c.values);
            let stx = self.cost_stx();
            for i in 0..self.n_nodes {
                let w = cc * tf * b[i % 3];
                for &e in &self.cost_entries {
                    let g = self.node_globals[i * nin + self.node_jac_pattern[e].1];
                    grad[g] += w * c.jac[i * nj + e];
                }
            }
            for t in self.boundary() {
                grad[t.var] += cc * tf * 2.0 * t.weight * (x[t.var] - t.target);
            }
            grad[self.problem.layout.tf()] += cc * s;
            grad[self.txn] -= cc * tf * s * stx / d;
            grad[self.tx0] += cc * tf * s * stx / d;
        });
        check(NlpFunction::Gradient, grad)
    }
    fn constraints(&self, x: &[f64], cv: &mut [f64]) -> Result<(), EvalError> {
        let ns = self.problem.layout.n_states();
        let per_point = ns + self.n_path;
        let h = x[self.problem.layout.tf()] / self.problem.layout.n as f64;
        self.with_nodes(x, false, |c| {
            for i in 0..self.n_nodes {
                let base = i * per_point + ns;
                cv[base..base + self.n_path]
                    .copy_from_slice(&c.values[i * self.n_out..i * self.n_out + self.n_path]);
            }
        });
        for lr in &self.linear_rows {
            cv[lr.row] = lr
                .terms
                .iter()
                .map(|t| t.coef * x[t.var] * if t.times_h { h } else { 1.0 })
                .sum();
        }
        if self.tracking.is_none() {
            let stx = self.problem.scaling.q[self.problem.gait.forward_translation];
            cv[self.speed_row] = stx * (x[self.txn] - x[self.tx0]) / x[self.problem.layout.tf()];
        }
        check(NlpFunction::Constraints, cv)
    }
    fn jacobian_structure(&self) -> Sparsity {
        self.jacobian.clone()
    }
    fn jacobian_values(&self, x: &[f64], vals: &mut [f64]) -> Result<(), EvalError> {
        let n = self.problem.layout.n as f64;
        let tf = x[self.problem.layout.tf()];
        self.with_nodes(x, true, |c| self.jac_fill.fill(&c.jac, x, tf, n, vals));
        if self.tracking.is_some() {
            return check(NlpFunction::Jacobian, vals);
        }
        let stx = self.problem.scaling.q[self.problem.gait.forward_translation];
        vals[self.speed_pos[0]] = stx / tf;
        vals[self.speed_pos[1]] = -stx / tf;
        vals[self.speed_pos[2]] = -stx * (x[self.txn] - x[self.tx0]) / (tf * tf);
        check(NlpFunction::Jacobian, vals)
    }
    fn hessian_structure(&self) -> Sparsity {
        self.hessian.clone()
    }
    fn hessian_values(
        &self,
        x: &[f64],
        obj_factor: f64,
        lambda: &[f64],
        vals: &mut [f64],
    ) -> Result<(), EvalError> {
        vals.iter_mut().for_each(|v| *v = 0.0);
        let l = &self.problem.layout;
        let ns = l.n_states();
        let per_point = ns + self.n_path;
        let nin = self.node_inputs();
        let nh = self.node_hess_pattern.len();
        let nj = self.node_jac_pattern.len();
        let n = l.n as f64;
        let b = radau::quadrature_weights();
        let stx = self.cost_stx();
        let tf = x[l.tf()];
        // The cost weight of a node needs only x.
        let (d, cc) = self.distance_factor(x);
        let weights = |i: usize, wp: &mut [f64]| {
            let base = i * per_point + ns;
            wp[..self.n_path].copy_from_slice(&lambda[base..base + self.n_path]);
            wp[self.n_path] = obj_factor * cc * tf * b[i % 3];
        };
        let mut node_h = self.node_hessians.lock().unwrap_or_else(|e| e.into_inner());
        node_h.resize(self.n_nodes * nh, 0.0);
        let batch = self.node.batch().max(1);
        let nout = self.n_out;
        let mut cache = self.cache.lock().unwrap_or_else(|e| e.into_inner());
        cache.move_to(x);
        // Node Hessians in parallel, then scattered (positions may repeat across nodes). The
        // Hessian's sweeps also give the node values and Jacobians: when the cache lacks them
        // at x (an iteration asks for the Hessian first), they are kept there, and the
        // gradient and Jacobian at the same x need no sweeps of their own.
        // (without Hessian entries the loop below runs no chunk: `with_nodes` fills them)
        let fill = !cache.valid_jac && nh > 0;
        let c = &mut *cache;
        c.values.resize(self.n_nodes * nout, 0.0);
        c.jac.resize(self.n_nodes * nj, 0.0);
        node_h
            .par_chunks_mut(nh.max(1) * batch)
            .zip(c.values.par_chunks_mut(nout * batch))
            .zip(c.jac.par_chunks_mut(nj.max(1) * batch))
            .enumerate()
            .for_each_init(
                || (vec![0.0; nin * batch], vec![0.0; nout * batch]),
                |(xin, w), (k, ((hv, y), jac))| {
                    let points = y.len() / nout;
                    let xs = self.gather_points(x, k * batch, points, xin);
                    for p in 0..points {
                        weights(k * batch + p, &mut w[p * nout..(p + 1) * nout]);
                    }
                    let w = &w[..points * nout];
                    if fill {
                        self.node.jacobian_hessian_batch(xs, w, y, jac, hv);
                    } else {
                        self.node.hessian_batch(xs, w, hv);
                    }
                },
            );
        if fill {
            c.valid_values = true;
            c.valid_jac = true;
        }
        drop(cache);
        // Cost pieces need node values and cost gradients (now cached at x).
        let s = self.with_nodes(x, true, |c| self.cost_parts(x, &c.values).0);
        for (p, &pos) in self.node_hess_pos.iter().enumerate() {
            if pos != NO_SLOT {
                vals[pos] += node_h[p];
            }
        }
        // Cost: cross terms of (t_f, x_N, x_0) with the node inputs, and among themselves.
        self.with_nodes(x, true, |c| {
            let ncost = self.cost_entries.len();
            for i in 0..self.n_nodes {
                for (q, &e) in self.cost_entries.iter().enumerate() {
                    let dl = obj_factor * b[i % 3] * c.jac[i * nj + e];
                    let [ptf, pn, p0] = self.cost_cross_pos[i * ncost + q];
                    vals[ptf] += cc * dl;
                    vals[pn] += -cc * tf * stx / d * dl;
                    vals[p0] += cc * tf * stx / d * dl;
                }
            }
        });
        let sc = obj_factor * cc * s;
        vals[self.hess_cost_pos[0]] += -sc * stx / d;
        vals[self.hess_cost_pos[1]] += sc * stx / d;
        vals[self.hess_cost_pos[2]] += 2.0 * sc * tf * stx * stx / (d * d);
        vals[self.hess_cost_pos[3]] += 2.0 * sc * tf * stx * stx / (d * d);
        vals[self.hess_cost_pos[4]] += -2.0 * sc * tf * stx * stx / (d * d);
        for (t, &[pvv, ptv]) in self.boundary().zip(&self.hess_boundary_pos) {
            vals[pvv] += obj_factor * cc * tf * 2.0 * t.weight;
            vals[ptv] += obj_factor * cc * 2.0 * t.weight * (x[t.var] - t.target);
        }
        // Bilinear collocation terms h·u: ∂²/∂t_f∂u = coef/N.
        for (lr, hpos) in self.linear_rows.iter().zip(&self.linear_hess_pos) {
            let lam = lambda[lr.row];
            if lam == 0.0 {
                continue;
            }
            for (t, &p) in lr.terms.iter().filter(|t| t.times_h).zip(hpos) {
                vals[p] += lam * t.coef / n;
            }
        }
        if self.tracking.is_some() {
            return check(NlpFunction::Hessian, vals);
        }
        // Speed: λ (s (x_N − x_0) / t_f).
        let stx = self.problem.scaling.q[self.problem.gait.forward_translation];
        let lam = lambda[self.speed_row];
        let dx = x[self.txn] - x[self.tx0];
        vals[self.hess_speed_pos[0]] += -lam * stx / (tf * tf);
        vals[self.hess_speed_pos[1]] += lam * stx / (tf * tf);
        vals[self.hess_speed_pos[2]] += 2.0 * lam * stx * dx / (tf * tf * tf);
        check(NlpFunction::Hessian, vals)
    }
}
