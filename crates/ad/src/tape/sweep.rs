//! The evaluation sweeps: forward values with local derivatives, scalar reverse,
//! compressed vector reverse (Jacobian) and forward-over-reverse (Hessian).

use super::op::{powi3, Op};
use super::{Locals, Tape, Workspace, LANES};
use crate::elementary::powf3;

/// One node's value, partials and second partials at `L` points.
pub(super) struct Local<const L: usize> {
    pub val: [f64; L],
    pub part: [[f64; L]; 2],
    pub sec: [[f64; L]; 3],
}

impl Tape {
    /// Forward sweep: values; with `ORD >= 1` the local partials `part`, with `ORD >= 2`
    /// the local second partials `sec` (`[∂²/∂a², ∂²/∂a∂b, ∂²/∂b²]`).
    pub(super) fn forward<const ORD: u8>(&self, x: &[f64], ws: &mut Workspace) {
        self.forward_lanes::<ORD, 1>([x], &mut ws.loc);
    }

    /// [`Tape::forward`] at `L` points at once, point `l` into lane `l` of `loc`: each
    /// operation is decoded once and applied to every lane, and the lanes of one node are
    /// adjacent in memory, so the arithmetic of the lanes is one vector operation (same
    /// numbers as `L` single sweeps). Values go to their places ([`super::registers`]),
    /// which are reused once a value has no reader left: only the partials are kept for
    /// every operation.
    #[inline(always)]
    pub(super) fn forward_lanes<const ORD: u8, const L: usize>(
        &self,
        xs: [&[f64]; L],
        loc: &mut Locals<L>,
    ) {
        let n = self.ops.len();
        let regs = &self.registers;
        // The stores as plain slices of the sweep's length (bounds checked once).
        let vals = &mut loc.vals[..regs.len as usize];
        let part = &mut loc.part[..if ORD >= 1 { n } else { 0 }];
        let sec = &mut loc.sec[..if ORD >= 2 { n } else { 0 }];
        self.seed_inputs(xs, vals);
        for (t, (op, &dst)) in regs.ops.iter().zip(&regs.dst).enumerate() {
            let local = self.local::<ORD, L>(*op, vals, xs);
            vals[dst as usize] = local.val;
            if ORD >= 1 {
                part[t] = local.part;
            }
            if ORD >= 2 {
                sec[t] = local.sec;
            }
        }
    }

    /// Writes the `L` points `xs` into the inputs' values (places `0..n_in`).
    #[inline(always)]
    pub(super) fn seed_inputs<const L: usize>(&self, xs: [&[f64]; L], vals: &mut [[f64; L]]) {
        for (i, v) in vals[..self.n_in].iter_mut().enumerate() {
            *v = std::array::from_fn(|l| xs[l][i]);
        }
    }

    /// The value of operation `op` at `L` points from its operands' values in `vals`, with
    /// `ORD >= 1` its partials, with `ORD >= 2` its second partials (zero otherwise: they
    /// are only evaluated when asked for).
    // The partials of some operations do not depend on the operands' values.
    #[allow(unused_variables)]
    #[inline(always)]
    pub(super) fn local<const ORD: u8, const L: usize>(
        &self,
        op: Op,
        vals: &[[f64; L]],
        xs: [&[f64]; L],
    ) -> Local<L> {
        const ZERO: f64 = 0.0;
        let zero2 = [[ZERO; L]; 2];
        let zero3 = [[ZERO; L]; 3];
        // The node's value of every lane, its partials and second partials.
        macro_rules! set {
            ($val:expr, $p:expr, $s:expr) => {
                Local {
                    val: $val,
                    part: if ORD >= 1 { $p } else { zero2 },
                    sec: if ORD >= 2 { $s } else { zero3 },
                }
            };
        }
        // A function of one operand, `f` its `[value, first, second]` derivatives at
        // `x`, lane by lane: the value alone without partials.
        macro_rules! unary {
            ($a:expr, |$x:ident| $value:expr, $f:expr) => {{
                let va = vals[$a as usize];
                if ORD == 0 {
                    let v = each(|l| {
                        let $x = va[l];
                        $value
                    });
                    set!(v, zero2, zero3)
                } else {
                    let f: [[f64; 3]; L] = std::array::from_fn(|l| {
                        let $x = va[l];
                        $f
                    });
                    set!(
                        each(|l| f[l][0]),
                        [each(|l| f[l][1]), [ZERO; L]],
                        [each(|l| f[l][2]), [ZERO; L], [ZERO; L]]
                    )
                }
            }};
        }
        // An operation of two operands with the same formulas in every lane: `$val`,
        // `$p`, `$s` are lane expressions of `$x`, `$y` (the operands' values).
        macro_rules! binary {
            ($a:expr, $b:expr, |$x:ident, $y:ident| $val:expr, [$pa:expr, $pb:expr], [$saa:expr, $sab:expr, $sbb:expr]) => {{
                let (va, vb) = (vals[$a as usize], vals[$b as usize]);
                set!(
                    pairwise(va, vb, |$x, $y| $val),
                    [
                        pairwise(va, vb, |$x, $y| $pa),
                        pairwise(va, vb, |$x, $y| $pb)
                    ],
                    [
                        pairwise(va, vb, |$x, $y| $saa),
                        pairwise(va, vb, |$x, $y| $sab),
                        pairwise(va, vb, |$x, $y| $sbb)
                    ]
                )
            }};
        }
        match op {
            Op::Input(i) => set!(each(|l| xs[l][i as usize]), zero2, zero3),
            Op::Const(c) => set!([c; L], zero2, zero3),
            Op::Add(a, b) => binary!(a, b, |x, y| x + y, [1.0, 1.0], [0.0, 0.0, 0.0]),
            Op::Sub(a, b) => binary!(a, b, |x, y| x - y, [1.0, -1.0], [0.0, 0.0, 0.0]),
            Op::Mul(a, b) => binary!(a, b, |x, y| x * y, [y, x], [0.0, 1.0, 0.0]),
            Op::Div(a, b) => {
                let (va, vb) = (vals[a as usize], vals[b as usize]);
                let q: [f64; L] = each(|l| va[l] / vb[l]);
                if ORD == 0 {
                    set!(q, zero2, zero3)
                } else {
                    let r: [f64; L] = each(|l| 1.0 / vb[l]);
                    set!(
                        q,
                        [r, each(|l| -q[l] * r[l])],
                        [
                            [ZERO; L],
                            each(|l| -r[l] * r[l]),
                            each(|l| 2.0 * q[l] * r[l] * r[l])
                        ]
                    )
                }
            }
            Op::Neg(a) => {
                let va = vals[a as usize];
                set!(each(|l| -va[l]), [[-1.0; L], [ZERO; L]], zero3)
            }
            Op::AddC(a, c) => {
                let va = vals[a as usize];
                set!(each(|l| va[l] + c), [[1.0; L], [ZERO; L]], zero3)
            }
            Op::MulC(a, c) => {
                let va = vals[a as usize];
                set!(each(|l| va[l] * c), [[c; L], [ZERO; L]], zero3)
            }
            Op::DivC(a, c) => {
                let va = vals[a as usize];
                set!(each(|l| va[l] / c), [[1.0 / c; L], [ZERO; L]], zero3)
            }
            Op::CDiv(c, a) => {
                let va = vals[a as usize];
                let q: [f64; L] = each(|l| c / va[l]);
                if ORD == 0 {
                    set!(q, zero2, zero3)
                } else {
                    let r: [f64; L] = each(|l| 1.0 / va[l]);
                    set!(
                        q,
                        [each(|l| -q[l] * r[l]), [ZERO; L]],
                        [each(|l| 2.0 * q[l] * r[l] * r[l]), [ZERO; L], [ZERO; L]]
                    )
                }
            }
            Op::Unary(a, e) => unary!(a, |x| e.value(x), e.eval3(x)),
            Op::Powf(a, pw) => unary!(a, |x| x.powf(pw), powf3(x, pw)),
            Op::Powi(a, n) => unary!(a, |x| x.powi(n), powi3(x, n)),
            Op::Apply(a, i) => {
                let func = &self.fns[i as usize];
                unary!(a, |x| func.eval(x)[0], func.eval(x))
            }
            Op::Min(a, b) => {
                let (va, vb) = (vals[a as usize], vals[b as usize]);
                let first: [f64; L] = each(|l| if va[l] <= vb[l] { 1.0 } else { 0.0 });
                set!(
                    each(|l| f64::min(va[l], vb[l])),
                    [first, each(|l| 1.0 - first[l])],
                    zero3
                )
            }
            Op::Max(a, b) => {
                let (va, vb) = (vals[a as usize], vals[b as usize]);
                let first: [f64; L] = each(|l| if va[l] >= vb[l] { 1.0 } else { 0.0 });
                set!(
                    each(|l| f64::max(va[l], vb[l])),
                    [first, each(|l| 1.0 - first[l])],
                    zero3
                )
            }
            Op::Select(c, p, n) => {
                let (vc, vp, vn) = (vals[c as usize], vals[p as usize], vals[n as usize]);
                let pick: [f64; L] = each(|l| if vc[l] > 0.0 { 1.0 } else { 0.0 });
                set!(
                    each(|l| if vc[l] > 0.0 { vp[l] } else { vn[l] }),
                    [pick, each(|l| 1.0 - pick[l])],
                    zero3
                )
            }
        }
    }

    /// Scalar reverse sweep over all active nodes, accumulating into the adjoints of
    /// `ws` (which the caller has seeded).
    pub(super) fn reverse_scalar(&self, ws: &mut Workspace) {
        self.reverse_lanes(&mut ws.loc);
    }

    /// Reverse sweeps of `L` points at once, each lane accumulating into its own adjoints
    /// (seeded by the caller) with its own partials: every instruction is decoded once for
    /// all lanes, and the lanes' updates are one vector operation. Same operations in the
    /// same order as one sweep per lane.
    pub(super) fn reverse_lanes<const L: usize>(&self, loc: &mut Locals<L>) {
        let n_in = self.n_in;
        let Locals { abar, part, .. } = loc;
        for &k in &self.active_desc {
            let k = k as usize;
            let [a, b] = self.args[k - n_in];
            let ak = abar[k];
            let [pa, pb] = part[k - n_in];
            let da = &mut abar[a as usize];
            for l in 0..L {
                da[l] += pa[l] * ak[l];
            }
            let db = &mut abar[b as usize];
            for l in 0..L {
                db[l] += pb[l] * ak[l];
            }
        }
    }

    /// Adjoints `ā = ∂(Σ wᵢ yᵢ)/∂node` of every node.
    pub(super) fn adjoint_sweep(&self, ws: &mut Workspace, w: &[f64]) {
        self.adjoint_lanes(&mut ws.loc, [w]);
    }

    /// [`Tape::adjoint_sweep`] of `L` points at once, lane `l` with the weights `w[l]`.
    pub(super) fn adjoint_lanes<const L: usize>(&self, loc: &mut Locals<L>, w: [&[f64]; L]) {
        loc.abar.iter_mut().for_each(|a| *a = [0.0; L]);
        for (i, &o) in self.outputs.iter().enumerate() {
            let a = &mut loc.abar[o as usize];
            for l in 0..L {
                a[l] += w[l][i];
            }
        }
        self.reverse_lanes(loc);
    }

    /// Compressed vector reverse sweeps writing the Jacobian values.
    pub(super) fn jacobian_sweeps(&self, ws: &mut Workspace, jac: &mut [f64]) {
        let n_in = self.n_in;
        let sink = self.n_nodes;
        let adj = &mut ws.lane_a;
        for chunk in &self.jac_chunks {
            for &(node, lane) in &chunk.seeds {
                adj[node as usize][lane as usize] += 1.0;
            }
            for &k in &chunk.nodes {
                let k = k as usize;
                let ak = std::mem::replace(&mut adj[k], [0.0; LANES]);
                let [a, b] = self.args[k - n_in];
                let [[pa], [pb]] = ws.loc.part[k - n_in];
                let da = &mut adj[a as usize];
                for l in 0..LANES {
                    da[l] += pa * ak[l];
                }
                let db = &mut adj[b as usize];
                for l in 0..LANES {
                    db[l] += pb * ak[l];
                }
            }
            for &(e, i, lane) in &chunk.extract {
                let slot = &mut adj[i as usize][lane as usize];
                jac[e as usize] = *slot;
                *slot = 0.0;
            }
            adj[sink] = [0.0; LANES];
        }
    }

    /// Forward-over-reverse sweeps writing the lower-triangle Hessian values; needs
    /// `forward::<2>` and `adjoint_sweep` first.
    pub(super) fn hessian_sweeps(&self, ws: &mut Workspace, hes: &mut [f64]) {
        let n_in = self.n_in;
        let sink = self.n_nodes;
        let (tan, adot) = (&mut ws.lane_a, &mut ws.lane_b);
        for chunk in &self.hes_chunks {
            for &(i, lane) in &chunk.seeds {
                tan[i as usize][lane as usize] = 1.0;
            }
            for &k in &chunk.fwd {
                let k = k as usize;
                let [a, b] = self.args[k - n_in];
                let [[pa], [pb]] = ws.loc.part[k - n_in];
                let (ta, tb) = (tan[a as usize], tan[b as usize]);
                let tk = &mut tan[k];
                for l in 0..LANES {
                    tk[l] = pa * ta[l] + pb * tb[l];
                }
            }
            for &k in &chunk.rev {
                let k = k as usize;
                let dk = std::mem::replace(&mut adot[k], [0.0; LANES]);
                let [ak] = ws.loc.abar[k];
                let [a, b] = self.args[k - n_in];
                let [[pa], [pb]] = ws.loc.part[k - n_in];
                let [[saa], [sab], [sbb]] = ws.loc.sec[k - n_in];
                let (ta, tb) = (tan[a as usize], tan[b as usize]);
                let (ca, cb) = (ak * saa, ak * sab);
                let cc = ak * sbb;
                let da = &mut adot[a as usize];
                for l in 0..LANES {
                    da[l] += pa * dk[l] + ca * ta[l] + cb * tb[l];
                }
                let db = &mut adot[b as usize];
                for l in 0..LANES {
                    db[l] += pb * dk[l] + cb * ta[l] + cc * tb[l];
                }
            }
            for &(e, i, lane) in &chunk.extract {
                hes[e as usize] = adot[i as usize][lane as usize];
            }
            for &k in &chunk.fwd {
                tan[k as usize] = [0.0; LANES];
            }
            for &(i, _) in &chunk.seeds {
                tan[i as usize] = [0.0; LANES];
            }
            adot[..n_in].iter_mut().for_each(|d| *d = [0.0; LANES]);
            adot[sink] = [0.0; LANES];
        }
    }
}

/// `[f(0), …, f(L − 1)]`: one value per lane.
#[inline(always)]
fn each<const L: usize>(f: impl Fn(usize) -> f64) -> [f64; L] {
    std::array::from_fn(f)
}

/// `f` of the two operands' values lane by lane.
#[inline(always)]
fn pairwise<const L: usize>(a: [f64; L], b: [f64; L], f: impl Fn(f64, f64) -> f64) -> [f64; L] {
    std::array::from_fn(|l| f(a[l], b[l]))
}
