//! The evaluation sweeps: forward values with local derivatives, scalar reverse,
//! compressed vector reverse (Jacobian) and forward-over-reverse (Hessian).

use super::op::{powi3, Op};
use super::{Tape, Workspace, LANES};
use crate::elementary::powf3;

impl Tape {
    /// Forward sweep: values; with `ORD >= 1` the local partials `part`, with `ORD >= 2`
    /// the local second partials `sec` (`[∂²/∂a², ∂²/∂a∂b, ∂²/∂b²]`).
    pub(super) fn forward<const ORD: u8>(&self, x: &[f64], ws: &mut Workspace) {
        self.forward_lanes::<ORD, 1>([x], [ws]);
    }

    /// [`Tape::forward`] at `L` points at once, point `l` into workspace `ws[l]`: each
    /// operation is decoded once and applied to every lane (same numbers as `L` single
    /// sweeps).
    // The lane loops index several per-lane arrays by the same lane.
    #[allow(clippy::needless_range_loop)]
    pub(super) fn forward_lanes<const ORD: u8, const L: usize>(
        &self,
        xs: [&[f64]; L],
        ws: [&mut Workspace; L],
    ) {
        let n_in = self.n_in;
        let n = self.ops.len();
        // Each lane's stores as plain slices of the sweep's length (bounds checked once).
        let mut vals: [&mut [f64]; L] = [(); L].map(|_| &mut [][..]);
        let mut part: [&mut [[f64; 2]]; L] = [(); L].map(|_| &mut [][..]);
        let mut sec: [&mut [[f64; 3]]; L] = [(); L].map(|_| &mut [][..]);
        for (l, w) in ws.into_iter().enumerate() {
            vals[l] = &mut w.vals[..n_in + n];
            vals[l][..n_in].copy_from_slice(xs[l]);
            if ORD >= 1 {
                part[l] = &mut w.part[..n];
            }
            if ORD >= 2 {
                sec[l] = &mut w.sec[..n];
            }
        }
        const Z2: [f64; 2] = [0.0; 2];
        const Z3: [f64; 3] = [0.0; 3];
        for (t, op) in self.ops.iter().enumerate() {
            let k = n_in + t;
            // The operand `i` of every lane.
            macro_rules! v {
                ($i:expr) => {{
                    let i = $i as usize;
                    let lanes: [f64; L] = std::array::from_fn(|l| vals[l][i]);
                    lanes
                }};
            }
            // Store lane `l`'s value, partials and second partials (the partials are only
            // evaluated when stored). Written element by element, straight from registers:
            // building per-lane arrays and copying them compiled to wide loads of narrower
            // stores just made (a store-forwarding stall on every operation).
            macro_rules! put {
                ($l:expr, $val:expr, $p:expr, $s:expr) => {{
                    let l = $l;
                    vals[l][k] = $val;
                    if ORD >= 1 {
                        let p: [f64; 2] = $p;
                        let d = &mut part[l][t];
                        d[0] = p[0];
                        d[1] = p[1];
                    }
                    if ORD >= 2 {
                        let s: [f64; 3] = $s;
                        let d = &mut sec[l][t];
                        d[0] = s[0];
                        d[1] = s[1];
                        d[2] = s[2];
                    }
                }};
            }
            // A function of one operand, `f` its `[value, first, second]` derivatives at
            // `x`: the value alone without partials.
            macro_rules! unary {
                ($a:expr, |$x:ident| $value:expr, $f:expr) => {{
                    let va = v!($a);
                    for l in 0..L {
                        let $x = va[l];
                        if ORD == 0 {
                            put!(l, $value, Z2, Z3);
                        } else {
                            let f: [f64; 3] = $f;
                            put!(l, f[0], [f[1], 0.0], [f[2], 0.0, 0.0]);
                        }
                    }
                }};
            }
            match *op {
                Op::Input(i) => {
                    for l in 0..L {
                        put!(l, xs[l][i as usize], Z2, Z3);
                    }
                }
                Op::Const(c) => {
                    for l in 0..L {
                        put!(l, c, Z2, Z3);
                    }
                }
                Op::Add(a, b) => {
                    let (va, vb) = (v!(a), v!(b));
                    for l in 0..L {
                        put!(l, va[l] + vb[l], [1.0, 1.0], Z3);
                    }
                }
                Op::Sub(a, b) => {
                    let (va, vb) = (v!(a), v!(b));
                    for l in 0..L {
                        put!(l, va[l] - vb[l], [1.0, -1.0], Z3);
                    }
                }
                Op::Mul(a, b) => {
                    let (va, vb) = (v!(a), v!(b));
                    for l in 0..L {
                        put!(l, va[l] * vb[l], [vb[l], va[l]], [0.0, 1.0, 0.0]);
                    }
                }
                Op::Div(a, b) => {
                    let (va, vb) = (v!(a), v!(b));
                    for l in 0..L {
                        let q = va[l] / vb[l];
                        if ORD == 0 {
                            put!(l, q, Z2, Z3);
                        } else {
                            let r = 1.0 / vb[l];
                            put!(l, q, [r, -q * r], [0.0, -r * r, 2.0 * q * r * r]);
                        }
                    }
                }
                Op::Neg(a) => {
                    let va = v!(a);
                    for l in 0..L {
                        put!(l, -va[l], [-1.0, 0.0], Z3);
                    }
                }
                Op::AddC(a, c) => {
                    let va = v!(a);
                    for l in 0..L {
                        put!(l, va[l] + c, [1.0, 0.0], Z3);
                    }
                }
                Op::MulC(a, c) => {
                    let va = v!(a);
                    for l in 0..L {
                        put!(l, va[l] * c, [c, 0.0], Z3);
                    }
                }
                Op::DivC(a, c) => {
                    let va = v!(a);
                    for l in 0..L {
                        put!(l, va[l] / c, [1.0 / c, 0.0], Z3);
                    }
                }
                Op::CDiv(c, a) => {
                    let va = v!(a);
                    for l in 0..L {
                        let q = c / va[l];
                        if ORD == 0 {
                            put!(l, q, Z2, Z3);
                        } else {
                            let r = 1.0 / va[l];
                            put!(l, q, [-q * r, 0.0], [2.0 * q * r * r, 0.0, 0.0]);
                        }
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
                    let (va, vb) = (v!(a), v!(b));
                    for l in 0..L {
                        let pick = if va[l] <= vb[l] {
                            [1.0, 0.0]
                        } else {
                            [0.0, 1.0]
                        };
                        put!(l, f64::min(va[l], vb[l]), pick, Z3);
                    }
                }
                Op::Max(a, b) => {
                    let (va, vb) = (v!(a), v!(b));
                    for l in 0..L {
                        let pick = if va[l] >= vb[l] {
                            [1.0, 0.0]
                        } else {
                            [0.0, 1.0]
                        };
                        put!(l, f64::max(va[l], vb[l]), pick, Z3);
                    }
                }
                Op::Select(c, p, n) => {
                    let (vc, vp, vn) = (v!(c), v!(p), v!(n));
                    for l in 0..L {
                        if vc[l] > 0.0 {
                            put!(l, vp[l], [1.0, 0.0], Z3);
                        } else {
                            put!(l, vn[l], [0.0, 1.0], Z3);
                        }
                    }
                }
            }
        }
    }

    /// Scalar reverse sweep over all active nodes, accumulating into `ws.abar`
    /// (which the caller has seeded).
    pub(super) fn reverse_scalar(&self, ws: &mut Workspace) {
        self.reverse_lanes([ws]);
    }

    /// Scalar reverse sweeps of `L` points at once, each lane accumulating into its own
    /// `abar` (seeded by the caller) with its own partials: every instruction is decoded
    /// once for all lanes, and the lanes' independent updates overlap. Same operations in
    /// the same order as one sweep per lane.
    pub(super) fn reverse_lanes<const L: usize>(&self, lanes: [&mut Workspace; L]) {
        let n_in = self.n_in;
        let mut lanes = lanes.map(|ws| {
            let Workspace { abar, part, .. } = ws;
            (abar.as_mut_slice(), part.as_slice())
        });
        for &k in &self.active_desc {
            let k = k as usize;
            let [a, b] = self.args[k - n_in];
            for (abar, part) in lanes.iter_mut() {
                let ak = abar[k];
                let [pa, pb] = part[k - n_in];
                abar[a as usize] += pa * ak;
                abar[b as usize] += pb * ak;
            }
        }
    }

    /// Adjoints `ā = ∂(Σ wᵢ yᵢ)/∂node` of every node.
    pub(super) fn adjoint_sweep(&self, ws: &mut Workspace, w: &[f64]) {
        self.adjoint_lanes([ws], [w]);
    }

    /// [`Tape::adjoint_sweep`] of `L` points at once, lane `l` with the weights `w[l]`.
    pub(super) fn adjoint_lanes<const L: usize>(
        &self,
        mut lanes: [&mut Workspace; L],
        w: [&[f64]; L],
    ) {
        for (ws, w) in lanes.iter_mut().zip(w) {
            ws.abar.iter_mut().for_each(|a| *a = 0.0);
            for (&o, &wi) in self.outputs.iter().zip(w) {
                ws.abar[o as usize] += wi;
            }
        }
        self.reverse_lanes(lanes);
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
                let [pa, pb] = ws.part[k - n_in];
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
                let [pa, pb] = ws.part[k - n_in];
                let (ta, tb) = (tan[a as usize], tan[b as usize]);
                let tk = &mut tan[k];
                for l in 0..LANES {
                    tk[l] = pa * ta[l] + pb * tb[l];
                }
            }
            for &k in &chunk.rev {
                let k = k as usize;
                let dk = std::mem::replace(&mut adot[k], [0.0; LANES]);
                let ak = ws.abar[k];
                let [a, b] = self.args[k - n_in];
                let [pa, pb] = ws.part[k - n_in];
                let [saa, sab, sbb] = ws.sec[k - n_in];
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
