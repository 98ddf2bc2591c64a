//! The evaluation sweeps: forward values with local derivatives, scalar reverse,
//! compressed vector reverse (Jacobian) and forward-over-reverse (Hessian).

use super::op::{powi3, Op};
use super::{Tape, Workspace, LANES};
use crate::elementary::powf3;

impl Tape {
    /// Forward sweep: values; with `ORD >= 1` the local partials `part`, with `ORD >= 2`
    /// the local second partials `sec` (`[∂²/∂a², ∂²/∂a∂b, ∂²/∂b²]`).
    pub(super) fn forward<const ORD: u8>(&self, x: &[f64], ws: &mut Workspace) {
        let n_in = self.n_in;
        let (vals, part, sec) = (&mut ws.vals, &mut ws.part, &mut ws.sec);
        vals[..n_in].copy_from_slice(x);
        for (t, op) in self.ops.iter().enumerate() {
            let v = |i: u32| vals[i as usize];
            let (val, p, s): (f64, [f64; 2], [f64; 3]) = match *op {
                Op::Input(i) => (x[i as usize], [0.0; 2], [0.0; 3]),
                Op::Const(c) => (c, [0.0; 2], [0.0; 3]),
                Op::Add(a, b) => (v(a) + v(b), [1.0, 1.0], [0.0; 3]),
                Op::Sub(a, b) => (v(a) - v(b), [1.0, -1.0], [0.0; 3]),
                Op::Mul(a, b) => {
                    let (va, vb) = (v(a), v(b));
                    (va * vb, [vb, va], [0.0, 1.0, 0.0])
                }
                Op::Div(a, b) => {
                    let q = v(a) / v(b);
                    if ORD == 0 {
                        (q, [0.0; 2], [0.0; 3])
                    } else {
                        let r = 1.0 / v(b);
                        (q, [r, -q * r], [0.0, -r * r, 2.0 * q * r * r])
                    }
                }
                Op::Neg(a) => (-v(a), [-1.0, 0.0], [0.0; 3]),
                Op::AddC(a, c) => (v(a) + c, [1.0, 0.0], [0.0; 3]),
                Op::MulC(a, c) => (v(a) * c, [c, 0.0], [0.0; 3]),
                Op::DivC(a, c) => (v(a) / c, [1.0 / c, 0.0], [0.0; 3]),
                Op::CDiv(c, a) => {
                    let q = c / v(a);
                    if ORD == 0 {
                        (q, [0.0; 2], [0.0; 3])
                    } else {
                        let r = 1.0 / v(a);
                        (q, [-q * r, 0.0], [2.0 * q * r * r, 0.0, 0.0])
                    }
                }
                Op::Unary(a, e) => {
                    if ORD == 0 {
                        (e.value(v(a)), [0.0; 2], [0.0; 3])
                    } else {
                        let f = e.eval3(v(a));
                        (f[0], [f[1], 0.0], [f[2], 0.0, 0.0])
                    }
                }
                Op::Powf(a, pw) => {
                    if ORD == 0 {
                        (v(a).powf(pw), [0.0; 2], [0.0; 3])
                    } else {
                        let f = powf3(v(a), pw);
                        (f[0], [f[1], 0.0], [f[2], 0.0, 0.0])
                    }
                }
                Op::Powi(a, n) => {
                    if ORD == 0 {
                        (v(a).powi(n), [0.0; 2], [0.0; 3])
                    } else {
                        let f = powi3(v(a), n);
                        (f[0], [f[1], 0.0], [f[2], 0.0, 0.0])
                    }
                }
                Op::Apply(a, k) => {
                    let f = self.fns[k as usize].eval(v(a));
                    (f[0], [f[1], 0.0], [f[2], 0.0, 0.0])
                }
                Op::Min(a, b) => {
                    let (va, vb) = (v(a), v(b));
                    let pick = if va <= vb { [1.0, 0.0] } else { [0.0, 1.0] };
                    (f64::min(va, vb), pick, [0.0; 3])
                }
                Op::Max(a, b) => {
                    let (va, vb) = (v(a), v(b));
                    let pick = if va >= vb { [1.0, 0.0] } else { [0.0, 1.0] };
                    (f64::max(va, vb), pick, [0.0; 3])
                }
                Op::Select(c, p, n) => {
                    if v(c) > 0.0 {
                        (v(p), [1.0, 0.0], [0.0; 3])
                    } else {
                        (v(n), [0.0, 1.0], [0.0; 3])
                    }
                }
            };
            vals[n_in + t] = val;
            if ORD >= 1 {
                part[t] = p;
            }
            if ORD >= 2 {
                sec[t] = s;
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
