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
        /// Every lane with the same first and second partials.
        fn same<const L: usize>(
            val: [f64; L],
            p: [f64; 2],
        ) -> ([f64; L], [[f64; 2]; L], [[f64; 3]; L]) {
            (val, [p; L], [[0.0; 3]; L])
        }
        /// Lanes of a unary function from its `[value, first, second]` derivatives.
        fn unary<const L: usize>(f: [[f64; 3]; L]) -> ([f64; L], [[f64; 2]; L], [[f64; 3]; L]) {
            (
                std::array::from_fn(|l| f[l][0]),
                std::array::from_fn(|l| [f[l][1], 0.0]),
                std::array::from_fn(|l| [f[l][2], 0.0, 0.0]),
            )
        }
        for (t, op) in self.ops.iter().enumerate() {
            let v = |i: u32| -> [f64; L] { std::array::from_fn(|l| vals[l][i as usize]) };
            let (val, p, s): ([f64; L], [[f64; 2]; L], [[f64; 3]; L]) = match *op {
                Op::Input(i) => same(std::array::from_fn(|l| xs[l][i as usize]), [0.0; 2]),
                Op::Const(c) => same([c; L], [0.0; 2]),
                Op::Add(a, b) => {
                    let (va, vb) = (v(a), v(b));
                    same(std::array::from_fn(|l| va[l] + vb[l]), [1.0, 1.0])
                }
                Op::Sub(a, b) => {
                    let (va, vb) = (v(a), v(b));
                    same(std::array::from_fn(|l| va[l] - vb[l]), [1.0, -1.0])
                }
                Op::Mul(a, b) => {
                    let (va, vb) = (v(a), v(b));
                    (
                        std::array::from_fn(|l| va[l] * vb[l]),
                        std::array::from_fn(|l| [vb[l], va[l]]),
                        [[0.0, 1.0, 0.0]; L],
                    )
                }
                Op::Div(a, b) => {
                    let (va, vb) = (v(a), v(b));
                    let q: [f64; L] = std::array::from_fn(|l| va[l] / vb[l]);
                    if ORD == 0 {
                        same(q, [0.0; 2])
                    } else {
                        let r: [f64; L] = std::array::from_fn(|l| 1.0 / vb[l]);
                        (
                            q,
                            std::array::from_fn(|l| [r[l], -q[l] * r[l]]),
                            std::array::from_fn(|l| [0.0, -r[l] * r[l], 2.0 * q[l] * r[l] * r[l]]),
                        )
                    }
                }
                Op::Neg(a) => same(v(a).map(|x| -x), [-1.0, 0.0]),
                Op::AddC(a, c) => same(v(a).map(|x| x + c), [1.0, 0.0]),
                Op::MulC(a, c) => same(v(a).map(|x| x * c), [c, 0.0]),
                Op::DivC(a, c) => same(v(a).map(|x| x / c), [1.0 / c, 0.0]),
                Op::CDiv(c, a) => {
                    let va = v(a);
                    let q: [f64; L] = std::array::from_fn(|l| c / va[l]);
                    if ORD == 0 {
                        same(q, [0.0; 2])
                    } else {
                        let r: [f64; L] = std::array::from_fn(|l| 1.0 / va[l]);
                        (
                            q,
                            std::array::from_fn(|l| [-q[l] * r[l], 0.0]),
                            std::array::from_fn(|l| [2.0 * q[l] * r[l] * r[l], 0.0, 0.0]),
                        )
                    }
                }
                Op::Unary(a, e) => {
                    if ORD == 0 {
                        same(v(a).map(|x| e.value(x)), [0.0; 2])
                    } else {
                        let va = v(a);
                        unary(std::array::from_fn(|l| e.eval3(va[l])))
                    }
                }
                Op::Powf(a, pw) => {
                    if ORD == 0 {
                        same(v(a).map(|x| x.powf(pw)), [0.0; 2])
                    } else {
                        let va = v(a);
                        unary(std::array::from_fn(|l| powf3(va[l], pw)))
                    }
                }
                Op::Powi(a, n) => {
                    if ORD == 0 {
                        same(v(a).map(|x| x.powi(n)), [0.0; 2])
                    } else {
                        let va = v(a);
                        unary(std::array::from_fn(|l| powi3(va[l], n)))
                    }
                }
                Op::Apply(a, k) => {
                    let va = v(a);
                    let f = &self.fns[k as usize];
                    unary(std::array::from_fn(|l| f.eval(va[l])))
                }
                Op::Min(a, b) => {
                    let (va, vb) = (v(a), v(b));
                    (
                        std::array::from_fn(|l| f64::min(va[l], vb[l])),
                        std::array::from_fn(|l| {
                            if va[l] <= vb[l] {
                                [1.0, 0.0]
                            } else {
                                [0.0, 1.0]
                            }
                        }),
                        [[0.0; 3]; L],
                    )
                }
                Op::Max(a, b) => {
                    let (va, vb) = (v(a), v(b));
                    (
                        std::array::from_fn(|l| f64::max(va[l], vb[l])),
                        std::array::from_fn(|l| {
                            if va[l] >= vb[l] {
                                [1.0, 0.0]
                            } else {
                                [0.0, 1.0]
                            }
                        }),
                        [[0.0; 3]; L],
                    )
                }
                Op::Select(c, p, n) => {
                    let (vc, vp, vn) = (v(c), v(p), v(n));
                    (
                        std::array::from_fn(|l| if vc[l] > 0.0 { vp[l] } else { vn[l] }),
                        std::array::from_fn(|l| if vc[l] > 0.0 { [1.0, 0.0] } else { [0.0, 1.0] }),
                        [[0.0; 3]; L],
                    )
                }
            };
            for l in 0..L {
                vals[l][n_in + t] = val[l];
                if ORD >= 1 {
                    part[l][t] = p[l];
                }
                if ORD >= 2 {
                    sec[l][t] = s[l];
                }
            }
        }
    }

    /// Scalar reverse sweep over all active nodes, accumulating into `ws.abar`
    /// (which the caller has seeded).
    pub(super) fn reverse_scalar(&self, ws: &mut Workspace) {
        let n_in = self.n_in;
        let abar = &mut ws.abar;
        for &k in &self.active_desc {
            let k = k as usize;
            let ak = abar[k];
            let [a, b] = self.args[k - n_in];
            let [pa, pb] = ws.part[k - n_in];
            abar[a as usize] += pa * ak;
            abar[b as usize] += pb * ak;
        }
    }

    /// Adjoints `ā = ∂(Σ wᵢ yᵢ)/∂node` of every node.
    pub(super) fn adjoint_sweep(&self, ws: &mut Workspace, w: &[f64]) {
        ws.abar.iter_mut().for_each(|a| *a = 0.0);
        for (&o, &wi) in self.outputs.iter().zip(w) {
            ws.abar[o as usize] += wi;
        }
        self.reverse_scalar(ws);
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
