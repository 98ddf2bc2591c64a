//! Derivative back-ends on a node function of the gait problem's shape.
//!
//! The node function has the inputs of one collocation point (92 activations, 92
//! normalised tendon forces and their derivatives, 92 activation derivatives, 29 q, 29 q̇,
//! 29 q̈, 8 arm activations, 8 arm excitations = 471) and 126 outputs: 29 skeleton
//! residuals (inverse dynamics of a 29-DOF tree with 12 smooth contact spheres minus muscle,
//! passive and arm torques), 92 Hill residuals (real `stride_muscle::hill_equilibrium` on
//! path polynomials through `stride_muscle::PathPolynomialEval`), 4 distances and a cost
//! integrand (real Bhargava 2004 metabolic rates squared, activations cubed, ...).
//!
//! Two node functions are measured: the REAL one (`stride_multibody::skeleton_dynamics` and
//! `stride_muscle` on the built-in model, 31 coordinates, 92 muscles) and a STAND-IN
//! (a Newton–Euler tree written here, synthetic order-5 path polynomials) that was used
//! before the real functions existed and is kept as a second workload.
//!
//! Run: `cargo bench -p stride-ocp --bench derivatives` (prints a table).

use std::time::Instant;
use stride_ad::{DualVec, Scalar, Tape, Var, Workspace};
use stride_model::{Model, PathPolynomial};
use stride_multibody::{skeleton_dynamics, Data, SkeletonOutput};
use stride_muscle::{
    hill_equilibrium, HillParams, MetabolicModel, MusclePaths, PathPolynomialEval, PathWorkspace,
};

/// Number of coordinates.
const NQ: usize = 29;
/// Number of muscles.
const NM: usize = 92;
/// Number of arm actuators.
const NARM: usize = 8;
/// Collocation points per problem (50 intervals × 3 Radau points).
const NODES: usize = 150;

/// Input layout offsets.
const A: usize = 0;
const FT: usize = NM;
const DFT: usize = 2 * NM;
const DA: usize = 3 * NM;
const Q: usize = 4 * NM;
const V: usize = Q + NQ;
const QDD: usize = V + NQ;
const AA: usize = QDD + NQ;
const AE: usize = AA + NARM;
const NX: usize = AE + NARM;

/// One single-DOF joint and the body it moves (stand-in skeleton).
struct Joint {
    parent: Option<usize>,
    axis: [f64; 3],
    prismatic: bool,
    offset: [f64; 3],
    mass: f64,
    com: [f64; 3],
    inertia: [f64; 3],
}

/// A contact sphere: body, centre in the body frame [m], radius [m].
struct Sphere {
    body: usize,
    centre: [f64; 3],
    radius: f64,
}

/// Everything the node function needs.
struct NodeModel {
    joints: Vec<Joint>,
    spheres: Vec<Sphere>,
    paths: Vec<PathPolynomialEval>,
    hill: Vec<HillParams>,
}

type V3<T> = [T; 3];
type M3<T> = [[T; 3]; 3];

fn v3<T: Scalar>(a: [f64; 3]) -> V3<T> {
    [T::cst(a[0]), T::cst(a[1]), T::cst(a[2])]
}
fn add<T: Scalar>(a: V3<T>, b: V3<T>) -> V3<T> {
    [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
}
fn sub<T: Scalar>(a: V3<T>, b: V3<T>) -> V3<T> {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}
fn scl<T: Scalar>(a: V3<T>, s: T) -> V3<T> {
    [a[0] * s, a[1] * s, a[2] * s]
}
fn cross<T: Scalar>(a: V3<T>, b: V3<T>) -> V3<T> {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}
fn dot<T: Scalar>(a: V3<T>, b: V3<T>) -> T {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}
fn mv<T: Scalar>(m: &M3<T>, v: V3<T>) -> V3<T> {
    [dot(m[0], v), dot(m[1], v), dot(m[2], v)]
}
fn mtv<T: Scalar>(m: &M3<T>, v: V3<T>) -> V3<T> {
    [
        m[0][0] * v[0] + m[1][0] * v[1] + m[2][0] * v[2],
        m[0][1] * v[0] + m[1][1] * v[1] + m[2][1] * v[2],
        m[0][2] * v[0] + m[1][2] * v[1] + m[2][2] * v[2],
    ]
}
fn mm<T: Scalar>(a: &M3<T>, b: &M3<T>) -> M3<T> {
    let mut r = [[T::zero(); 3]; 3];
    for i in 0..3 {
        for j in 0..3 {
            r[i][j] = a[i][0] * b[0][j] + a[i][1] * b[1][j] + a[i][2] * b[2][j];
        }
    }
    r
}
/// Rotation by `theta` about the unit axis `k` (Rodrigues).
fn rot<T: Scalar>(k: [f64; 3], theta: T) -> M3<T> {
    let (s, c) = (theta.sin(), theta.cos());
    let t = c.rsub(1.0);
    let mut r = [[T::zero(); 3]; 3];
    for i in 0..3 {
        for j in 0..3 {
            let mut e = t * (k[i] * k[j]);
            if i == j {
                e += c;
            }
            r[i][j] = e;
        }
    }
    r[0][1] -= s * k[2];
    r[1][0] += s * k[2];
    r[0][2] += s * k[1];
    r[2][0] -= s * k[1];
    r[1][2] -= s * k[0];
    r[2][1] += s * k[0];
    r
}

/// Joint torques [N m] / forces [N] of the stand-in tree by world-frame Newton–Euler with
/// smooth contact forces, and 4 foot/leg distances [m].
fn inverse_dynamics<T: Scalar>(m: &NodeModel, q: &[T], v: &[T], qdd: &[T]) -> (Vec<T>, [T; 4]) {
    let n = m.joints.len();
    let id: M3<T> = [
        v3([1.0, 0.0, 0.0]),
        v3([0.0, 1.0, 0.0]),
        v3([0.0, 0.0, 1.0]),
    ];
    let zero = v3::<T>([0.0; 3]);
    let mut r = vec![id; n];
    let mut p = vec![zero; n];
    let mut w = vec![zero; n];
    let mut wd = vec![zero; n];
    let mut vel = vec![zero; n];
    let mut acc = vec![zero; n];
    let mut axis = vec![zero; n];
    for (i, j) in m.joints.iter().enumerate() {
        let (rp, pp, wp, wdp, vp, ap) = match j.parent {
            Some(k) => (r[k], p[k], w[k], wd[k], vel[k], acc[k]),
            None => (id, zero, zero, zero, zero, v3([0.0, 9.81, 0.0])),
        };
        let d = mv(&rp, v3(j.offset));
        let z = mv(&rp, v3(j.axis));
        axis[i] = z;
        let mut pi = add(pp, d);
        let mut vi = add(vp, cross(wp, d));
        let mut ai = add(add(ap, cross(wdp, d)), cross(wp, cross(wp, d)));
        if j.prismatic {
            pi = add(pi, scl(z, q[i]));
            vi = add(vi, scl(z, v[i]));
            ai = add(ai, add(scl(z, qdd[i]), scl(cross(wp, z), v[i] * 2.0)));
            r[i] = rp;
            w[i] = wp;
            wd[i] = wdp;
        } else {
            r[i] = mm(&rp, &rot(j.axis, q[i]));
            w[i] = add(wp, scl(z, v[i]));
            wd[i] = add(add(wdp, scl(z, qdd[i])), scl(cross(wp, z), v[i]));
        }
        p[i] = pi;
        vel[i] = vi;
        acc[i] = ai;
    }
    // External contact forces and moments about each body's joint point.
    let mut fext = vec![zero; n];
    let mut mext = vec![zero; n];
    for s in &m.spheres {
        let b = s.body;
        let d = mv(&r[b], v3(s.centre));
        let c = add(p[b], d);
        let vc = add(vel[b], cross(w[b], d));
        let pen = (c[1] - s.radius).rsub(0.0);
        let pos = ((pen.sq() + 1e-10).sqrt() + pen) * 0.5;
        let fn_ = pos.powf(1.5) * 1.0e6 * (vc[1] * -2.0 + 1.0).fmax(T::zero());
        let slip = (vc[0].sq() + vc[2].sq() + 1e-6).sqrt();
        let mu = (slip * 100.0).tanh() * 0.8 / slip;
        let f = [-(fn_ * mu * vc[0]), fn_, -(fn_ * mu * vc[2])];
        fext[b] = add(fext[b], f);
        mext[b] = add(mext[b], cross(d, f));
    }
    // Backward pass: net force and moment about the joint point of each subtree.
    let mut f = vec![zero; n];
    let mut mo = vec![zero; n];
    for (i, j) in m.joints.iter().enumerate() {
        if j.mass == 0.0 {
            f[i] = scl(fext[i], T::cst(-1.0));
            mo[i] = scl(mext[i], T::cst(-1.0));
            continue;
        }
        let c = mv(&r[i], v3(j.com));
        let ac = add(add(acc[i], cross(wd[i], c)), cross(w[i], cross(w[i], c)));
        let fi = scl(ac, T::cst(j.mass));
        let iw_local = |x: V3<T>| -> V3<T> {
            let l = mtv(&r[i], x);
            mv(
                &r[i],
                [
                    l[0] * j.inertia[0],
                    l[1] * j.inertia[1],
                    l[2] * j.inertia[2],
                ],
            )
        };
        let ni = add(iw_local(wd[i]), cross(w[i], iw_local(w[i])));
        f[i] = sub(fi, fext[i]);
        mo[i] = sub(add(ni, cross(c, fi)), mext[i]);
    }
    let mut tau = vec![T::zero(); n];
    for i in (0..n).rev() {
        tau[i] = if m.joints[i].prismatic {
            dot(axis[i], f[i])
        } else {
            dot(axis[i], mo[i])
        };
        if let Some(k) = m.joints[i].parent {
            let d = sub(p[i], p[k]);
            let (fi, mi) = (f[i], mo[i]);
            f[k] = add(f[k], fi);
            mo[k] = add(add(mo[k], mi), cross(d, fi));
        }
    }
    let dist = |a: usize, b: usize| {
        let d = sub(p[a], p[b]);
        (d[0].sq() + d[2].sq()).sqrt()
    };
    (tau, [dist(11, 17), dist(12, 18), dist(9, 15), dist(25, 28)])
}

/// The node function: 126 outputs from the 471 inputs of one collocation point.
fn node_function<T: Scalar>(m: &NodeModel, x: &[T], pw: &mut PathWorkspace<T>) -> Vec<T> {
    let (q, v, qdd) = (&x[Q..Q + NQ], &x[V..V + NQ], &x[QDD..QDD + NQ]);
    let (mut tau, dist) = inverse_dynamics(m, q, v, qdd);
    let mut out = Vec::with_capacity(NQ + NM + 5);
    let mut hill_res = Vec::with_capacity(NM);
    let mut cost = T::zero();
    let mut arms = [T::zero(); 4];
    for (k, (path, hp)) in m.paths.iter().zip(&m.hill).enumerate() {
        let nc = path.n_coordinates();
        let (l, lv) = path
            .evaluate(q, v, pw, &mut arms[..nc])
            .expect("benchmark polynomial sizes are consistent");
        let h = hill_equilibrium(hp, x[A + k], x[FT + k], x[DFT + k], l, lv);
        let force = x[FT + k] * hp.max_isometric_force();
        for (r, &c) in arms[..nc].iter().zip(path.coordinates()) {
            tau[c] -= *r * force;
        }
        hill_res.push(h.residual);
        let e = MetabolicModel::Bhargava2004.rate(hp, x[A + k], &h).total;
        cost += (e * 0.01).sq() + x[A + k].powi(3) + x[DA + k].sq() * 1e-3 + x[DFT + k].sq() * 1e-2;
    }
    for c in 0..NQ {
        // Linear passive stand-in and arm actuators on the last 8 coordinates.
        let mut t = tau[c] + q[c] * 5.0 + v[c] * 0.1;
        if c >= NQ - NARM {
            t -= x[AA + c - (NQ - NARM)] * 150.0;
        }
        out.push(t);
        cost += qdd[c].sq() * 0.01;
    }
    out.extend(hill_res);
    out.extend(dist);
    for k in 0..NARM {
        cost += x[AE + k].sq() + (x[AE + k] - x[AA + k]).sq() * 0.1;
    }
    out.push(cost);
    out
}

/// Per-scalar-type scratch of a node function (preallocated, reused across calls).
struct Scratch<T: Scalar> {
    pw: PathWorkspace<T>,
    skel: Option<(Data<T>, SkeletonOutput<T>)>,
    lengths: Vec<T>,
    velocities: Vec<T>,
    arms: Vec<T>,
}

/// A node function of the gait problem that the benchmark can record and evaluate.
trait NodeFn: Sync {
    /// Number of inputs.
    fn n_inputs(&self) -> usize;
    /// A random evaluation point.
    fn point(&self, rng: &mut Rng) -> Vec<f64>;
    /// Fresh scratch for scalar type `T`.
    fn scratch<T: Scalar>(&self) -> Scratch<T>;
    /// The outputs at `x`.
    fn eval<T: Scalar>(&self, x: &[T], s: &mut Scratch<T>) -> Vec<T>;
}

impl NodeFn for NodeModel {
    fn n_inputs(&self) -> usize {
        NX
    }
    fn point(&self, rng: &mut Rng) -> Vec<f64> {
        random_point(rng)
    }
    fn scratch<T: Scalar>(&self) -> Scratch<T> {
        Scratch {
            pw: PathWorkspace::new(4, 5),
            skel: None,
            lengths: Vec::new(),
            velocities: Vec::new(),
            arms: Vec::new(),
        }
    }
    fn eval<T: Scalar>(&self, x: &[T], s: &mut Scratch<T>) -> Vec<T> {
        node_function(self, x, &mut s.pw)
    }
}

/// The real node function: `stride_multibody::skeleton_dynamics` (31 coordinates, 12
/// contact spheres) and `stride_muscle` geometry/Hill/metabolics on the built-in model.
struct RealModel {
    model: Model,
    paths: MusclePaths,
    hill: Vec<HillParams>,
    /// Body indices for the 4 distance constraints (calcn, toes, tibia, hand pairs).
    pairs: [(usize, usize); 4],
}

impl RealModel {
    fn new() -> Option<Self> {
        let model = stride_model::default_model::default_model().clone();
        let paths = MusclePaths::from_model(&model).ok()?;
        let hill = model
            .muscles
            .iter()
            .map(HillParams::from_muscle)
            .collect::<Result<Vec<_>, _>>()
            .ok()?;
        let body = |n: &str| model.bodies.iter().position(|b| b.name == n);
        let pair = |a: &str, b: &str| Some((body(a)?, body(b)?));
        let pairs = [
            pair("calcn_r", "calcn_l")?,
            pair("toes_r", "toes_l")?,
            pair("tibia_r", "tibia_l")?,
            pair("hand_r", "femur_r")?,
        ];
        Data::<f64>::new(&model).ok()?;
        Some(Self {
            model,
            paths,
            hill,
            pairs,
        })
    }
    fn nq(&self) -> usize {
        self.model.coordinates.len()
    }
    fn nm(&self) -> usize {
        self.model.muscles.len()
    }
}

impl NodeFn for RealModel {
    fn n_inputs(&self) -> usize {
        4 * self.nm() + 3 * self.nq() + 2 * NARM
    }
    fn point(&self, rng: &mut Rng) -> Vec<f64> {
        let (nm, nq) = (self.nm(), self.nq());
        let mut x = vec![0.0; self.n_inputs()];
        for k in 0..nm {
            x[k] = rng.uniform(0.05, 0.9);
            x[nm + k] = rng.uniform(0.05, 0.8);
            x[2 * nm + k] = rng.uniform(-1.0, 1.0);
            x[3 * nm + k] = rng.uniform(-1.0, 1.0);
        }
        let q0 = 4 * nm;
        for c in 0..nq {
            x[q0 + c] = rng.uniform(-0.3, 0.3);
            x[q0 + nq + c] = rng.uniform(-1.0, 1.0);
            x[q0 + 2 * nq + c] = rng.uniform(-5.0, 5.0);
        }
        // pelvis_ty: feet near the ground so that some spheres are in contact.
        x[q0 + 4] = rng.uniform(0.9, 0.95);
        for k in 0..2 * NARM {
            x[q0 + 3 * nq + k] = rng.uniform(-0.5, 0.5);
        }
        x
    }
    fn scratch<T: Scalar>(&self) -> Scratch<T> {
        let data = Data::<T>::new(&self.model).expect("checked in RealModel::new");
        let out = SkeletonOutput::new(&self.model, &data);
        Scratch {
            pw: PathWorkspace::for_paths(&self.paths),
            skel: Some((data, out)),
            lengths: vec![T::zero(); self.nm()],
            velocities: vec![T::zero(); self.nm()],
            arms: vec![T::zero(); self.paths.n_moment_arms()],
        }
    }
    fn eval<T: Scalar>(&self, x: &[T], s: &mut Scratch<T>) -> Vec<T> {
        let (nm, nq) = (self.nm(), self.nq());
        let q0 = 4 * nm;
        let (q, v, qdd) = (
            &x[q0..q0 + nq],
            &x[q0 + nq..q0 + 2 * nq],
            &x[q0 + 2 * nq..q0 + 3 * nq],
        );
        let (data, out) = s.skel.as_mut().expect("real scratch has a skeleton");
        skeleton_dynamics(&self.model, data, q, v, qdd, out).expect("skeleton dynamics");
        self.paths
            .evaluate(
                q,
                v,
                &mut s.pw,
                &mut s.lengths,
                &mut s.velocities,
                &mut s.arms,
            )
            .expect("muscle paths");
        let mut tau = out.tau.clone();
        let mut res = Vec::with_capacity(nq + nm + 5);
        let mut hill_res = Vec::with_capacity(nm);
        let mut cost = T::zero();
        for (k, hp) in self.hill.iter().enumerate() {
            let (a, ft, dft, da) = (x[k], x[nm + k], x[2 * nm + k], x[3 * nm + k]);
            let h = hill_equilibrium(hp, a, ft, dft, s.lengths[k], s.velocities[k]);
            let force = ft * hp.max_isometric_force();
            let range = self.paths.moment_arm_range(k);
            for (r, &c) in s.arms[range]
                .iter()
                .zip(self.paths.polynomial(k).coordinates())
            {
                tau[c] -= *r * force;
            }
            hill_res.push(h.residual);
            let e = MetabolicModel::Bhargava2004.rate(hp, a, &h).total;
            cost += (e * 0.01).sq() + a.powi(3) + da.sq() * 1e-3 + dft.sq() * 1e-2;
        }
        for (c, t) in tau.iter().enumerate() {
            res.push(*t + q[c] * 5.0 + v[c] * 0.1);
            cost += qdd[c].sq() * 0.01;
        }
        res.extend(hill_res);
        for &(a, b) in &self.pairs {
            let (pa, pb) = (out.body_origins[a], out.body_origins[b]);
            res.push(((pa[0] - pb[0]).sq() + (pa[2] - pb[2]).sq()).sqrt());
        }
        let arm = q0 + 3 * nq;
        for k in 0..NARM {
            cost += x[arm + NARM + k].sq() + (x[arm + NARM + k] - x[arm + k]).sq() * 0.1;
        }
        res.push(cost);
        res
    }
}

/// Deterministic uniform numbers (64-bit LCG).
struct Rng(u64);
impl Rng {
    fn uniform(&mut self, lo: f64, hi: f64) -> f64 {
        self.0 = self
            .0
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        lo + (hi - lo) * ((self.0 >> 11) as f64 / (1u64 << 53) as f64)
    }
}

fn build_model() -> NodeModel {
    let z = [0.0, 0.0, 1.0];
    let xa = [1.0, 0.0, 0.0];
    let ya = [0.0, 1.0, 0.0];
    let mut joints = Vec::new();
    let mut j = |parent: Option<usize>,
                 axis: [f64; 3],
                 prismatic: bool,
                 offset: [f64; 3],
                 mass: f64,
                 com: [f64; 3]| {
        let i = mass * 0.02;
        joints.push(Joint {
            parent,
            axis,
            prismatic,
            offset,
            mass,
            com,
            inertia: [i, i * 0.5, i],
        });
        joints.len() - 1
    };
    let t0 = j(None, xa, true, [0.0; 3], 0.0, [0.0; 3]);
    let t1 = j(Some(t0), ya, true, [0.0; 3], 0.0, [0.0; 3]);
    let t2 = j(Some(t1), z, true, [0.0; 3], 0.0, [0.0; 3]);
    let r0 = j(Some(t2), z, false, [0.0; 3], 0.0, [0.0; 3]);
    let r1 = j(Some(r0), xa, false, [0.0; 3], 0.0, [0.0; 3]);
    let pelvis = j(Some(r1), ya, false, [0.0; 3], 11.8, [-0.07, 0.0, 0.0]);
    let sub_axis = [0.787, 0.605, -0.118];
    let norm =
        (sub_axis[0] * sub_axis[0] + sub_axis[1] * sub_axis[1] + sub_axis[2] * sub_axis[2]).sqrt();
    let sub_axis = [sub_axis[0] / norm, sub_axis[1] / norm, sub_axis[2] / norm];
    for side in [1.0, -1.0] {
        let h0 = j(
            Some(pelvis),
            z,
            false,
            [-0.07, -0.07, 0.08 * side],
            0.0,
            [0.0; 3],
        );
        let h1 = j(Some(h0), xa, false, [0.0; 3], 0.0, [0.0; 3]);
        let femur = j(Some(h1), ya, false, [0.0; 3], 9.3, [0.0, -0.17, 0.0]);
        let tibia = j(
            Some(femur),
            z,
            false,
            [0.0, -0.4, 0.0],
            3.7,
            [0.0, -0.19, 0.0],
        );
        let talus = j(Some(tibia), z, false, [0.0, -0.43, 0.0], 0.1, [0.0; 3]);
        let calcn = j(
            Some(talus),
            sub_axis,
            false,
            [-0.05, -0.04, 0.008 * side],
            1.25,
            [0.1, 0.03, 0.0],
        );
        j(
            Some(calcn),
            z,
            false,
            [0.18, -0.002, 0.001 * side],
            0.22,
            [0.035, 0.006, 0.0],
        );
    }
    let l0 = j(Some(pelvis), z, false, [-0.1, 0.08, 0.0], 0.0, [0.0; 3]);
    let l1 = j(Some(l0), xa, false, [0.0; 3], 0.0, [0.0; 3]);
    let torso = j(Some(l1), ya, false, [0.0; 3], 26.8, [-0.03, 0.32, 0.0]);
    for side in [1.0, -1.0] {
        let s0 = j(
            Some(torso),
            z,
            false,
            [0.003, 0.37, 0.17 * side],
            0.0,
            [0.0; 3],
        );
        let hum = j(Some(s0), xa, false, [0.0; 3], 2.0, [0.0, -0.16, 0.0]);
        j(
            Some(hum),
            z,
            false,
            [0.013, -0.29, -0.01 * side],
            1.5,
            [0.0, -0.18, 0.0],
        );
    }
    assert_eq!(joints.len(), NQ);
    // Spheres: 4 on each calcaneus (bodies 11, 18), 2 on each toes body (12, 19).
    let mut spheres = Vec::new();
    for (calcn, toes, side) in [(11, 12, 1.0), (18, 19, -1.0)] {
        for (b, c) in [
            (calcn, [0.0019, -0.01, -0.0038 * side]),
            (calcn, [0.148, -0.01, -0.028 * side]),
            (calcn, [0.133, -0.01, 0.051 * side]),
            (calcn, [0.066, -0.01, 0.026 * side]),
            (toes, [0.06, -0.01, -0.0187 * side]),
            (toes, [0.045, -0.01, 0.06 * side]),
        ] {
            spheres.push(Sphere {
                body: b,
                centre: c,
                radius: 0.032,
            });
        }
    }
    // Muscles: 43 per leg spanning subsets of (hip ×3, knee, ankle, subtalar), 6 trunk.
    let spans: [&[usize]; 6] = [&[0, 1, 2], &[0, 1, 2, 3], &[3], &[3, 4], &[4, 5], &[0, 3]];
    let mut rng = Rng(7);
    let mut paths = Vec::new();
    let mut hill = Vec::new();
    for k in 0..NM {
        let coords: Vec<usize> = if k < 86 {
            let base = if k < 43 { 6 } else { 13 };
            let leg = [base, base + 1, base + 2, base + 3, base + 4, base + 5];
            spans[k % spans.len()].iter().map(|&c| leg[c]).collect()
        } else {
            vec![20, 21, 22]
        };
        let order = 5u32;
        let mut exponents = Vec::new();
        monomials(
            coords.len(),
            order as usize,
            &mut vec![0; coords.len()],
            0,
            &mut exponents,
        );
        let coefficients = exponents
            .iter()
            .map(|e: &Vec<u8>| {
                let deg: u8 = e.iter().sum();
                if deg == 0 {
                    0.3
                } else {
                    rng.uniform(-0.02, 0.02) / f64::from(deg)
                }
            })
            .collect();
        let poly = PathPolynomial {
            coordinates: coords,
            order,
            exponents,
            coefficients,
            rmse_length: None,
            rmse_moment_arm: None,
        };
        paths.push(PathPolynomialEval::new(k, &poly).expect("valid synthetic polynomial"));
        hill.push(
            HillParams::new(&format!("m{k}"), 1000.0, 0.1, 0.2, 0.1, 10.0, 0.25e6, 0.5)
                .expect("valid synthetic muscle"),
        );
    }
    NodeModel {
        joints,
        spheres,
        paths,
        hill,
    }
}

/// All exponent tuples of `n` variables with total degree ≤ `order`.
fn monomials(n: usize, order: usize, cur: &mut Vec<u8>, i: usize, out: &mut Vec<Vec<u8>>) {
    if i == n {
        out.push(cur.clone());
        return;
    }
    let used: usize = cur[..i].iter().map(|&e| e as usize).sum();
    for e in 0..=(order - used) {
        cur[i] = e as u8;
        monomials(n, order, cur, i + 1, out);
    }
    cur[i] = 0;
}

fn random_point(rng: &mut Rng) -> Vec<f64> {
    let mut x = vec![0.0; NX];
    for k in 0..NM {
        x[A + k] = rng.uniform(0.05, 0.9);
        x[FT + k] = rng.uniform(0.05, 0.8);
        x[DFT + k] = rng.uniform(-1.0, 1.0);
        x[DA + k] = rng.uniform(-1.0, 1.0);
    }
    for c in 0..NQ {
        x[Q + c] = rng.uniform(-0.3, 0.3);
        x[V + c] = rng.uniform(-1.0, 1.0);
        x[QDD + c] = rng.uniform(-5.0, 5.0);
    }
    x[Q + 1] = 0.95;
    for k in 0..NARM {
        x[AA + k] = rng.uniform(-0.5, 0.5);
        x[AE + k] = rng.uniform(-0.5, 0.5);
    }
    x
}

/// CPU time of the calling thread [s] (robust to other processes sharing the cores).
fn thread_cpu_s() -> f64 {
    let mut ts = libc::timespec {
        tv_sec: 0,
        tv_nsec: 0,
    };
    // SAFETY: clock_gettime writes into the valid, exclusively borrowed timespec.
    unsafe { libc::clock_gettime(libc::CLOCK_THREAD_CPUTIME_ID, &mut ts) };
    ts.tv_sec as f64 + ts.tv_nsec as f64 * 1e-9
}

/// Best-of-5 mean thread-CPU time per call [µs] of `f`, repetitions chosen for ~50 ms.
fn time_us(mut f: impl FnMut()) -> f64 {
    let t = thread_cpu_s();
    f();
    let once = thread_cpu_s() - t;
    let reps = ((0.05 / once.max(1e-9)) as usize).clamp(1, 100_000);
    (0..5)
        .map(|_| {
            let t = thread_cpu_s();
            for _ in 0..reps {
                f();
            }
            (thread_cpu_s() - t) / reps as f64
        })
        .fold(f64::INFINITY, f64::min)
        * 1e6
}

/// Column-coloured forward vector mode: a compressed Jacobian from `passes` evaluations on
/// `DualVec<8>`, written in the tape's pattern order.
struct ForwardColoured {
    colour: Vec<usize>,
    n_colours: usize,
}

impl ForwardColoured {
    fn new(pattern: &stride_ad::Pattern) -> Self {
        let n = pattern.n_cols;
        let mut rows_of_col = vec![Vec::new(); n];
        let mut cols_of_row = vec![Vec::new(); pattern.n_rows];
        for (r, c) in pattern.iter() {
            rows_of_col[c].push(r);
            cols_of_row[r].push(c);
        }
        let mut colour = vec![usize::MAX; n];
        let mut mark = Vec::new();
        let mut n_colours = 0;
        for c in 0..n {
            mark.clear();
            for &r in &rows_of_col[c] {
                for &o in &cols_of_row[r] {
                    if colour[o] != usize::MAX {
                        mark.push(colour[o]);
                    }
                }
            }
            let k = (0..).find(|k| !mark.contains(k)).unwrap_or(0);
            colour[c] = k;
            n_colours = n_colours.max(k + 1);
        }
        Self { colour, n_colours }
    }
    fn jacobian<M: NodeFn>(
        &self,
        m: &M,
        pat: &stride_ad::Pattern,
        x: &[f64],
        ws: &mut Scratch<DualVec<8>>,
        jac: &mut [f64],
    ) {
        for pass in 0..self.n_colours.div_ceil(8) {
            let xd: Vec<DualVec<8>> = x
                .iter()
                .zip(&self.colour)
                .map(|(&v, &c)| DualVec::var(v, if c / 8 == pass { c % 8 } else { 8 }))
                .collect();
            let y = m.eval(&xd, ws);
            for (e, (r, c)) in pat.iter().enumerate() {
                if self.colour[c] / 8 == pass {
                    jac[e] = y[r].eps[self.colour[c] % 8];
                }
            }
        }
    }
}

fn main() {
    match RealModel::new() {
        Some(real) => {
            breakdown(&real);
            run(
            "REAL node function: stride_multibody skeleton_dynamics (31 coordinates, 12 spheres) \
             + stride_muscle paths/Hill/metabolics on the built-in model",
            &real,
            )
        }
        None => println!("(built-in model unavailable: real node function skipped)"),
    }
    println!();
    run(
        "STAND-IN node function: Newton-Euler tree written in this bench + stride_muscle \
         Hill/metabolics on synthetic order-5 polynomials",
        &build_model(),
    );
}

/// Tape sizes of the parts of the real node function (where the operations come from).
fn breakdown(m: &RealModel) {
    let mut rng = Rng(42);
    let x0 = m.point(&mut rng);
    let (nm, nq) = (m.nm(), m.nq());
    let q0 = 4 * nm;
    let count =
        |f: &dyn Fn(&[Var]) -> Vec<Var>| Tape::record(&x0, f).map_or(0, |t| t.stats().n_ops);
    let skeleton = count(&|x| {
        let mut sc = m.scratch::<Var>();
        let (data, out) = sc.skel.as_mut().expect("skeleton");
        let (q, v, a) = (
            &x[q0..q0 + nq],
            &x[q0 + nq..q0 + 2 * nq],
            &x[q0 + 2 * nq..q0 + 3 * nq],
        );
        skeleton_dynamics(&m.model, data, q, v, a, out).expect("skeleton");
        out.tau.clone()
    });
    let paths = count(&|x| {
        let mut sc = m.scratch::<Var>();
        let (q, v) = (&x[q0..q0 + nq], &x[q0 + nq..q0 + 2 * nq]);
        m.paths
            .evaluate(
                q,
                v,
                &mut sc.pw,
                &mut sc.lengths,
                &mut sc.velocities,
                &mut sc.arms,
            )
            .expect("paths");
        let mut o = sc.lengths.clone();
        o.extend(sc.velocities.iter().copied());
        o.extend(sc.arms.iter().copied());
        o
    });
    let total = count(&|x| {
        let mut sc = m.scratch::<Var>();
        m.eval(x, &mut sc)
    });
    println!(
        "# Real node function: tape operations by part: skeleton_dynamics {skeleton}, \
         muscle paths (lengths, velocities, moment arms) {paths}, \
         Hill + metabolics + assembly {}, total {total}",
        total.saturating_sub(skeleton + paths)
    );
}

/// Records `m`, checks the back-ends against each other and prints the timing table.
fn run<M: NodeFn>(title: &str, m: &M) {
    let mut rng = Rng(42);
    let x0 = m.point(&mut rng);
    let t = Instant::now();
    let tape = Tape::record(&x0, |x: &[Var]| {
        let mut sc = m.scratch::<Var>();
        m.eval(x, &mut sc)
    })
    .expect("recording the node function");
    let record_ms = t.elapsed().as_secs_f64() * 1e3;
    let s = tape.stats();
    println!("# {title}");
    println!(
        "inputs {}  outputs {}  tape ops {}  record {:.1} ms",
        s.n_inputs, s.n_outputs, s.n_ops, record_ms
    );
    println!(
        "Jacobian nnz {}  row colours {}   Hessian (lower) nnz {}  column colours {}",
        s.jac_nnz, s.jac_colours, s.hes_nnz, s.hes_colours
    );
    println!(
        "sparse sweeps: gradient entries {} (Jacobian-only sweep {})  second-order adjoint \
         entries {}  map entries {}",
        s.grad_entries, s.jacobian_grad_entries, s.adot_entries, s.map_entries
    );

    let xs: Vec<Vec<f64>> = (0..NODES).map(|_| m.point(&mut rng)).collect();
    let lambda: Vec<f64> = (0..s.n_outputs).map(|_| rng.uniform(-1.0, 1.0)).collect();
    let mut ws = tape.workspace();
    let mut y = vec![0.0; s.n_outputs];
    let mut jac = vec![0.0; s.jac_nnz];
    let mut hes = vec![0.0; s.hes_nnz];
    let mut g = vec![0.0; s.n_inputs];
    let x = &xs[0];

    // Consistency: tape values == f64 values; forward-coloured Jacobian == tape Jacobian.
    let mut pw64 = m.scratch::<f64>();
    let yf = m.eval(x, &mut pw64);
    tape.eval(x, &mut ws, &mut y).expect("eval");
    let max_val_diff = y
        .iter()
        .zip(&yf)
        .map(|(a, b)| (a - b).abs())
        .fold(0.0, f64::max);
    let fwd = ForwardColoured::new(tape.jacobian_pattern());
    let mut pwd = m.scratch::<DualVec<8>>();
    let mut jac_fwd = vec![0.0; s.jac_nnz];
    fwd.jacobian(m, tape.jacobian_pattern(), x, &mut pwd, &mut jac_fwd);
    tape.jacobian(x, &mut ws, &mut y, &mut jac)
        .expect("jacobian");
    let max_jac_rel = jac
        .iter()
        .zip(&jac_fwd)
        .map(|(a, b)| (a - b).abs() / (1.0 + a.abs()))
        .fold(0.0, f64::max);
    println!(
        "check: |tape - f64| values max {:.1e}; |tape J - forward J| / (1+|J|) max {:.1e}; forward colours {}",
        max_val_diff, max_jac_rel, fwd.n_colours
    );

    let t_f64 = time_us(|| {
        std::hint::black_box(m.eval(std::hint::black_box(x), &mut pw64));
    });
    let t_eval = time_us(|| tape.eval(x, &mut ws, &mut y).expect("eval"));
    let t_jac = time_us(|| tape.jacobian(x, &mut ws, &mut y, &mut jac).expect("jac"));
    let t_jac_col = time_us(|| {
        tape.jacobian_coloured(x, &mut ws, &mut y, &mut jac)
            .expect("jac")
    });
    let t_grad = time_us(|| {
        tape.gradient(x, s.n_outputs - 1, &mut ws, &mut g)
            .expect("grad");
    });
    let t_hes = time_us(|| {
        tape.hessian(x, &lambda, &mut ws, &mut y, &mut hes)
            .expect("hes")
    });
    let mut hes_col = vec![0.0; s.hes_nnz];
    tape.hessian_coloured(x, &lambda, &mut ws, &mut y, &mut hes_col)
        .expect("hes");
    let max_hes_rel = hes
        .iter()
        .zip(&hes_col)
        .map(|(a, b)| (a - b).abs() / (1.0 + a.abs()))
        .fold(0.0, f64::max);
    println!("check: |sparse H - coloured H| / (1+|H|) max {max_hes_rel:.1e}");
    let t_hes_col = time_us(|| {
        tape.hessian_coloured(x, &lambda, &mut ws, &mut y, &mut hes_col)
            .expect("hes")
    });
    let t_fwd = time_us(|| fwd.jacobian(m, tape.jacobian_pattern(), x, &mut pwd, &mut jac_fwd));

    // All 150 nodes on 2 threads: tape shared, one preallocated workspace and output
    // buffers per thread.
    struct Buffers {
        ws: Workspace,
        y: Vec<f64>,
        jac: Vec<f64>,
        hes: Vec<f64>,
    }
    let mut bufs: Vec<Buffers> = (0..2)
        .map(|_| Buffers {
            ws: tape.workspace(),
            y: vec![0.0; s.n_outputs],
            jac: vec![0.0; s.jac_nnz],
            hes: vec![0.0; s.hes_nnz],
        })
        .collect();
    // Each thread reports its own CPU time; the slower thread is what an idle 2-core
    // machine would show as wall time (the shared machine's load inflates real wall time).
    let mut par = |hessian: bool| {
        (0..3)
            .map(|_| {
                std::thread::scope(|sc| {
                    let handles: Vec<_> = xs
                        .chunks(NODES / 2)
                        .zip(bufs.iter_mut())
                        .map(|(half, b)| {
                            let (tape, lambda) = (&tape, &lambda);
                            sc.spawn(move || {
                                let t = thread_cpu_s();
                                for x in half {
                                    if hessian {
                                        tape.hessian(x, lambda, &mut b.ws, &mut b.y, &mut b.hes)
                                            .expect("hes");
                                    } else {
                                        tape.jacobian(x, &mut b.ws, &mut b.y, &mut b.jac)
                                            .expect("jac");
                                    }
                                }
                                thread_cpu_s() - t
                            })
                        })
                        .collect();
                    handles
                        .into_iter()
                        .map(|h| h.join().expect("bench thread"))
                        .fold(0.0, f64::max)
                })
            })
            .fold(f64::INFINITY, f64::min)
            * 1e6
    };
    let p_jac = par(false);
    let p_hes = par(true);

    println!();
    println!(
        "| quantity | method | per node [µs] | 150 nodes serial [ms] | 150 nodes 2 threads [ms] |"
    );
    println!("|---|---|---:|---:|---:|");
    let row = |q: &str, meth: &str, us: f64, par: Option<f64>| {
        let p = par.map_or("–".to_string(), |p| format!("{:.2}", p / 1e3));
        println!(
            "| {q} | {meth} | {us:.1} | {:.2} | {p} |",
            us * NODES as f64 / 1e3
        );
    };
    row("value", "generic code on f64", t_f64, None);
    row("value", "tape forward", t_eval, None);
    row("gradient (cost)", "tape scalar reverse", t_grad, None);
    row(
        "Jacobian",
        "tape sparse forward (static index sets)",
        t_jac,
        Some(p_jac),
    );
    row(
        "Jacobian",
        "tape coloured reverse, 8 lanes",
        t_jac_col,
        None,
    );
    row(
        "Jacobian",
        "DualVec<8> forward, coloured columns",
        t_fwd,
        None,
    );
    row(
        "Lagrangian Hessian",
        "tape sparse second-order adjoint",
        t_hes,
        Some(p_hes),
    );
    row(
        "Lagrangian Hessian",
        "tape coloured forward-over-reverse, 8 lanes",
        t_hes_col,
        None,
    );
    println!();
    println!("(per-node: thread CPU time, best of 5; 2 threads: CPU time of the slower thread,");
    println!(" best of 3, i.e. the wall time of an otherwise idle 2-core machine)");
}
