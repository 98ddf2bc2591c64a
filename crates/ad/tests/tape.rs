//! The tape against independent references: f64 evaluation of the same generic code
//! (bit-identical values), central finite differences (Jacobians, gradients, Hessians)
//! and hyper-dual numbers (exact second derivatives, symmetry, pattern completeness).
#![allow(clippy::needless_range_loop)]

use std::sync::Arc;
use stride_ad::{AdError, Dual, HyperDual, Scalar, Tape, UnaryFn, Var, BATCH};

/// `x ↦ x sin x` with analytic derivatives, registered as a tabulated-curve stand-in.
#[derive(Debug)]
struct XSinX;
impl UnaryFn for XSinX {
    fn eval(&self, x: f64) -> [f64; 3] {
        let (s, c) = x.sin_cos();
        [x * s, s + x * c, 2.0 * c - x * s]
    }
}

/// Deterministic uniform numbers in [lo, hi) (64-bit LCG).
struct Rng(u64);
impl Rng {
    fn uniform(&mut self, lo: f64, hi: f64) -> f64 {
        self.0 = self
            .0
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        lo + (hi - lo) * ((self.0 >> 11) as f64 / (1u64 << 53) as f64)
    }
    fn point(&mut self, n: usize, lo: f64, hi: f64) -> Vec<f64> {
        (0..n).map(|_| self.uniform(lo, hi)).collect()
    }
}

/// A test function: name, input count, domain, and the generic body for each scalar type.
struct Case {
    name: &'static str,
    n: usize,
    lo: f64,
    hi: f64,
    f64f: fn(&[f64]) -> Vec<f64>,
    var: fn(&[Var]) -> Vec<Var>,
    dual: fn(&[Dual]) -> Vec<Dual>,
    hyper: fn(&[HyperDual]) -> Vec<HyperDual>,
}

macro_rules! case {
    ($name:expr, $n:expr, $lo:expr, $hi:expr, $f:ident) => {
        Case {
            name: $name,
            n: $n,
            lo: $lo,
            hi: $hi,
            f64f: |x| $f::<f64>(x),
            var: |x| $f::<Var>(x),
            dual: |x| $f::<Dual>(x),
            hyper: |x| $f::<HyperDual>(x),
        }
    };
}

/// Extended Rosenbrock, one scalar output.
fn rosenbrock<T: Scalar>(x: &[T]) -> Vec<T> {
    let mut s = T::zero();
    for i in 0..x.len() - 1 {
        s += (x[i + 1] - x[i].sq()).sq() * 100.0 + (x[i].rsub(1.0)).sq();
    }
    vec![s]
}

/// Uses every `Scalar` method, several outputs with different dependencies.
fn every_method<T: Scalar>(x: &[T]) -> Vec<T> {
    let f: Arc<dyn UnaryFn> = Arc::new(XSinX);
    let (a, b, c, d, e) = (x[0], x[1], x[2], x[3], x[4]);
    let mut acc = a * b;
    acc += c;
    acc -= d * 0.5;
    acc *= e;
    acc /= b + 3.0;
    acc += 1.5;
    acc -= 0.25;
    acc *= 2.0;
    acc /= 3.0;
    vec![
        acc,
        a.sin() * b.cos() + c.exp() - d.ln() + e.sqrt(),
        (a * c).tanh() + b.powf(1.7) + d.powi(3) + e.powi(-2) + a.tan(),
        a.fmin(b * c) + d.fmax(e) + T::select_pos(a - b, c.sq(), d * e),
        (a / b).apply(&f) + c.recip() + d.rsub(2.0) * e.rdiv(3.0) - (-a),
        T::cst(2.0) * a - T::one() + T::zero() * b + smooth(c - d),
        T::cst(4.0) / a + T::cst(1.0) - b,
        e.fmax(T::cst(0.9)).fmin(T::cst(1.8)),
        T::select_pos(c - 1.0, T::cst(3.0), T::cst(-1.0)) * a,
        T::cst(7.0),
        b,
    ]
}

fn smooth<T: Scalar>(x: T) -> T {
    stride_ad::smooth_step(x, 5.0)
}

/// A banded function (chained, like collocation residuals): `yᵢ` uses `xᵢ₋₁, xᵢ, xᵢ₊₁`.
fn banded<T: Scalar>(x: &[T]) -> Vec<T> {
    let n = x.len();
    (0..n)
        .map(|i| {
            let l = if i > 0 { x[i - 1] } else { T::cst(0.3) };
            let r = if i + 1 < n { x[i + 1] } else { T::cst(-0.2) };
            (x[i] * 3.0 - x[i].sq() * 2.0) - l * r.exp() + (l - r).sin() * x[i] + 1.0
        })
        .collect()
}

/// Long sums and scalings (like joint torques summed over muscles): chains of operations
/// with constant partials, some intermediate sums also used elsewhere or returned,
/// `x - x`, negation, shifts and division by constants between nonlinear terms.
#[allow(clippy::eq_op)] // `half - half` is the `x - x` case
fn linear_chains<T: Scalar>(x: &[T]) -> Vec<T> {
    let n = x.len();
    let mut total = T::zero();
    let mut half = T::zero();
    for i in 0..n {
        let term = x[i] * x[(i + 3) % n] * (0.5 + i as f64);
        total = total + term - x[i] * 0.25;
        if i == n / 2 {
            half = total;
        }
    }
    let shifted = -(total / 3.0 + 2.0) * 1.5 - x[0];
    let zero = half - half;
    vec![
        shifted.sin() + zero,
        half,
        half.sq() + total,
        (x[1] + x[2]) * 2.0 - (x[3] + x[4] - x[5]),
    ]
}

/// A deep chain of nonlinear steps on one running value that depends on every input
/// (like a kinematic chain): each step's gradient set is read by the next step only, so
/// the Jacobian-only sweep can reuse its place.
fn deep_chain<T: Scalar>(x: &[T]) -> Vec<T> {
    let n = x.len();
    let mut s = T::zero();
    for (i, &xi) in x.iter().enumerate() {
        s += xi * (0.3 + 0.1 * i as f64);
    }
    let mut outs = Vec::new();
    for k in 0..24 {
        s = s.sin() * 1.1 + x[k % n] * s;
        if k % 8 == 7 {
            outs.push(s.sq());
        }
    }
    outs
}

fn cases() -> Vec<Case> {
    vec![
        case!("rosenbrock", 8, -1.5, 1.5, rosenbrock),
        case!("every_method", 5, 0.5, 1.4, every_method),
        case!("banded", 40, -1.0, 1.0, banded),
        case!("linear_chains", 12, -1.0, 1.0, linear_chains),
        case!("deep_chain", 10, -0.5, 0.5, deep_chain),
    ]
}

fn close(a: f64, b: f64, tol: f64) -> bool {
    (a - b).abs() <= tol * (1.0 + a.abs().max(b.abs()))
}

/// Dense Jacobian by central differences of the f64 function.
fn fd_jacobian(f: fn(&[f64]) -> Vec<f64>, x: &[f64]) -> Vec<Vec<f64>> {
    let m = f(x).len();
    let mut jac = vec![vec![0.0; x.len()]; m];
    for j in 0..x.len() {
        let h = 1e-6 * (1.0 + x[j].abs());
        let (mut xp, mut xm) = (x.to_vec(), x.to_vec());
        xp[j] += h;
        xm[j] -= h;
        let (yp, ym) = (f(&xp), f(&xm));
        for i in 0..m {
            jac[i][j] = (yp[i] - ym[i]) / (2.0 * h);
        }
    }
    jac
}

/// Gradient of `Σ λᵢ yᵢ` with forward-mode duals (independent of the tape).
fn dual_lagrangian_gradient(c: &Case, x: &[f64], lambda: &[f64]) -> Vec<f64> {
    (0..x.len())
        .map(|j| {
            let xd: Vec<Dual> = x
                .iter()
                .enumerate()
                .map(|(k, &v)| Dual::new(v, if k == j { 1.0 } else { 0.0 }))
                .collect();
            (c.dual)(&xd)
                .iter()
                .zip(lambda)
                .map(|(y, l)| y.eps * l)
                .sum()
        })
        .collect()
}

/// Exact dense Hessian of `Σ λᵢ yᵢ` with hyper-dual numbers.
fn hyper_hessian(c: &Case, x: &[f64], lambda: &[f64]) -> Vec<Vec<f64>> {
    let n = x.len();
    let mut h = vec![vec![0.0; n]; n];
    for i in 0..n {
        for j in 0..n {
            let xh: Vec<HyperDual> = x
                .iter()
                .enumerate()
                .map(|(k, &v)| HyperDual::new(v, (k == i) as u8 as f64, (k == j) as u8 as f64, 0.0))
                .collect();
            h[i][j] = (c.hyper)(&xh)
                .iter()
                .zip(lambda)
                .map(|(y, l)| y.e12 * l)
                .sum();
        }
    }
    h
}

#[test]
fn tape_values_are_bit_identical_to_f64() {
    let mut rng = Rng(1);
    for c in cases() {
        let x0 = rng.point(c.n, c.lo, c.hi);
        let tape = Tape::record(&x0, c.var).unwrap();
        assert_eq!(tape.recorded_outputs(), (c.f64f)(&x0), "{}", c.name);
        let mut ws = tape.workspace();
        let mut y = vec![0.0; tape.n_outputs()];
        for _ in 0..5 {
            let x = rng.point(c.n, c.lo, c.hi);
            tape.eval(&x, &mut ws, &mut y).unwrap();
            let yf = (c.f64f)(&x);
            for (a, b) in y.iter().zip(&yf) {
                assert_eq!(a.to_bits(), b.to_bits(), "{}: {a} vs {b}", c.name);
            }
        }
    }
}

#[test]
fn jacobian_matches_finite_differences_and_pattern_is_complete() {
    let mut rng = Rng(2);
    for c in cases() {
        let tape = Tape::record(&rng.point(c.n, c.lo, c.hi), c.var).unwrap();
        let pat = tape.jacobian_pattern().clone();
        let mut ws = tape.workspace();
        let mut y = vec![0.0; tape.n_outputs()];
        let mut jac = vec![0.0; pat.nnz()];
        for trial in 0..6 {
            let x = rng.point(c.n, c.lo, c.hi);
            if trial % 2 == 0 {
                tape.jacobian(&x, &mut ws, &mut y, &mut jac).unwrap();
            } else {
                tape.jacobian_coloured(&x, &mut ws, &mut y, &mut jac)
                    .unwrap();
            }
            assert_eq!(y, (c.f64f)(&x));
            let fd = fd_jacobian(c.f64f, &x);
            let mut dense = vec![vec![0.0; c.n]; y.len()];
            for (e, (r, col)) in pat.iter().enumerate() {
                dense[r][col] = jac[e];
            }
            for (r, row) in fd.iter().enumerate() {
                for (col, &d) in row.iter().enumerate() {
                    assert!(
                        close(dense[r][col], d, 1e-6),
                        "{} J[{r}][{col}] = {} vs FD {d} (in pattern: {})",
                        c.name,
                        dense[r][col],
                        pat.find(r, col).is_some()
                    );
                }
            }
        }
    }
}

#[test]
fn gradients_match_finite_differences() {
    let mut rng = Rng(3);
    for c in cases() {
        let tape = Tape::record(&rng.point(c.n, c.lo, c.hi), c.var).unwrap();
        let mut ws = tape.workspace();
        let m = tape.n_outputs();
        let x = rng.point(c.n, c.lo, c.hi);
        let fd = fd_jacobian(c.f64f, &x);
        let mut g = vec![0.0; c.n];
        for k in 0..m {
            let yk = tape.gradient(&x, k, &mut ws, &mut g).unwrap();
            assert_eq!(yk, (c.f64f)(&x)[k]);
            for j in 0..c.n {
                assert!(close(g[j], fd[k][j], 1e-6), "{} ∇y{k}[{j}]", c.name);
            }
        }
        let w = rng.point(m, -1.0, 1.0);
        let mut y = vec![0.0; m];
        tape.vjp(&x, &w, &mut ws, &mut y, &mut g).unwrap();
        for j in 0..c.n {
            let expect: f64 = (0..m).map(|k| w[k] * fd[k][j]).sum();
            assert!(close(g[j], expect, 1e-6), "{} vjp[{j}]", c.name);
        }
    }
}

#[test]
fn hessian_matches_hyperduals_and_finite_differences() {
    let mut rng = Rng(4);
    for c in cases() {
        let tape = Tape::record(&rng.point(c.n, c.lo, c.hi), c.var).unwrap();
        let pat = tape.hessian_pattern().clone();
        let mut ws = tape.workspace();
        let m = tape.n_outputs();
        let mut y = vec![0.0; m];
        let mut hv = vec![0.0; pat.nnz()];
        for trial in 0..4 {
            let x = rng.point(c.n, c.lo, c.hi);
            let lambda = rng.point(m, -2.0, 2.0);
            if trial % 2 == 0 {
                tape.hessian(&x, &lambda, &mut ws, &mut y, &mut hv).unwrap();
            } else {
                tape.hessian_coloured(&x, &lambda, &mut ws, &mut y, &mut hv)
                    .unwrap();
            }
            let exact = hyper_hessian(&c, &x, &lambda);
            let mut dense = vec![vec![0.0; c.n]; c.n];
            for (e, (i, j)) in pat.iter().enumerate() {
                assert!(i >= j, "{}: pattern not lower triangular", c.name);
                dense[i][j] = hv[e];
                dense[j][i] = hv[e];
            }
            // Central differences of the (dual-number) gradient of the Lagrangian.
            for j in 0..c.n {
                let h = 1e-5 * (1.0 + x[j].abs());
                let (mut xp, mut xm) = (x.clone(), x.clone());
                xp[j] += h;
                xm[j] -= h;
                let gp = dual_lagrangian_gradient(&c, &xp, &lambda);
                let gm = dual_lagrangian_gradient(&c, &xm, &lambda);
                for i in 0..c.n {
                    let fd = (gp[i] - gm[i]) / (2.0 * h);
                    assert!(
                        close(dense[i][j], exact[i][j], 1e-10),
                        "{} H[{i}][{j}] = {} vs hyper-dual {}",
                        c.name,
                        dense[i][j],
                        exact[i][j]
                    );
                    assert!(
                        close(dense[i][j], fd, 1e-6),
                        "{} H[{i}][{j}] = {} vs FD {fd}",
                        c.name,
                        dense[i][j]
                    );
                    assert!(
                        close(exact[i][j], exact[j][i], 1e-12),
                        "{} reference Hessian not symmetric",
                        c.name
                    );
                    if exact[i][j] != 0.0 {
                        let (r, k) = (i.max(j), i.min(j));
                        assert!(pat.find(r, k).is_some(), "{} H[{r}][{k}] missing", c.name);
                    }
                }
            }
        }
    }
}

#[test]
fn sparsity_is_exploited_on_the_banded_function() {
    let x0: Vec<f64> = (0..40).map(|i| 0.01 * i as f64).collect();
    let tape = Tape::record(&x0, banded).unwrap();
    let s = tape.stats();
    assert_eq!(s.jac_nnz, 3 * 40 - 2);
    // Lower triangle of a pentadiagonal Hessian (l·exp(r) couples i-1 and i+1).
    assert_eq!(s.hes_nnz, 40 + 39 + 38);
    assert!(s.jac_colours <= 5, "row colours {}", s.jac_colours);
    assert!(s.hes_colours <= 9, "Hessian colours {}", s.hes_colours);
}

#[test]
fn linear_combinations_store_only_their_result() {
    // y = Σᵢ xᵢ² + 2 Σᵢ xᵢ: the partial sums are used once, by the next sum, and each
    // square once, by a sum, so only the inputs (1 entry each) and the sum (n entries) are
    // stored; without collapsing, the n − 1 partial sums alone hold Σ (i + 1) more, and
    // without folding the squares hold n more.
    let n = 30;
    let x0: Vec<f64> = (0..n).map(|i| 0.1 * i as f64).collect();
    let tape = Tape::record(&x0, |x: &[Var]| {
        let mut s = Var::zero();
        for &xi in x {
            s = s + xi.sq() + xi * 2.0;
        }
        vec![s]
    })
    .unwrap();
    assert_eq!(tape.stats().grad_entries, n + n);
    let mut ws = tape.workspace();
    let (mut y, mut jac) = (vec![0.0], vec![0.0; n]);
    tape.jacobian(&x0, &mut ws, &mut y, &mut jac).unwrap();
    let cols = &tape.jacobian_pattern().cols;
    for (e, &c) in cols.iter().enumerate() {
        assert_eq!(jac[e], 2.0 * x0[c as usize] + 2.0, "column {c}");
    }
}

#[test]
fn jacobian_sweep_reuses_the_places_of_dead_gradients_and_values() {
    // Every step of the chain stores a gradient over all 10 inputs; the Jacobian-only
    // sweep keeps only the inputs, the outputs and the few sets live at once.
    let n = 10;
    let x0: Vec<f64> = (0..n).map(|i| 0.05 * i as f64 - 0.2).collect();
    let tape = Tape::record(&x0, deep_chain).unwrap();
    let s = tape.stats();
    assert!(s.grad_entries >= 24 * n, "full store {}", s.grad_entries);
    assert!(
        s.jacobian_grad_entries <= n + 3 * n + 3 * n,
        "Jacobian-only store {} (full {})",
        s.jacobian_grad_entries,
        s.grad_entries
    );
    // Values too: the inputs and the three outputs keep their places, every other value
    // lives from its operation to its last reader (a few at once along the chain).
    assert!(s.n_ops > 100, "{} operations", s.n_ops);
    assert!(
        s.value_places <= n + 3 + 6,
        "{} value places for {} inputs and {} operations",
        s.value_places,
        n,
        s.n_ops
    );
    // Same Jacobian from the compact sweep as from the Hessian's full one.
    let mut bw = tape.batch_workspace();
    let m = tape.n_outputs();
    let nnz = tape.jacobian_pattern().nnz();
    let (mut y1, mut j1) = (vec![0.0; m], vec![0.0; nnz]);
    tape.jacobian_batch(&x0, &mut bw, &mut y1, &mut j1).unwrap();
    let (mut y2, mut j2) = (vec![0.0; m], vec![0.0; nnz]);
    let mut h = vec![0.0; tape.hessian_pattern().nnz()];
    let lambda = vec![1.0; m];
    tape.jacobian_hessian_batch(&x0, &lambda, &mut bw, &mut y2, &mut j2, &mut h)
        .unwrap();
    assert_eq!(y1, y2);
    assert_eq!(j1, j2);
}

#[test]
fn bad_input_gives_clear_errors() {
    let tape = Tape::record(&[1.0, 2.0], |x| vec![x[0] * x[1]]).unwrap();
    let mut ws = tape.workspace();
    let mut y = [0.0];
    let err = tape.eval(&[1.0], &mut ws, &mut y).unwrap_err();
    assert_eq!(
        err,
        AdError::Length {
            what: "inputs x",
            expected: 2,
            got: 1
        }
    );
    assert!(err.to_string().contains("inputs x"));
    let mut g = [0.0; 2];
    assert!(matches!(
        tape.gradient(&[1.0, 2.0], 3, &mut ws, &mut g),
        Err(AdError::OutputIndex { index: 3, .. })
    ));
    let other = Tape::record(&[1.0], |x| vec![x[0].sin()]).unwrap();
    let mut ws2 = other.workspace();
    assert!(matches!(
        tape.eval(&[1.0, 2.0], &mut ws2, &mut y),
        Err(AdError::Workspace { .. })
    ));
    let nested = Tape::record(&[1.0], |x| {
        assert_eq!(
            Tape::record(&[1.0], |z| z.to_vec()).unwrap_err(),
            AdError::NestedRecording
        );
        vec![x[0]]
    });
    assert!(nested.is_ok());
}

#[test]
fn repeated_subexpressions_are_recorded_once() {
    // y0 = sin(a b) + sin(b a), y1 = 3 (a b)² written with fresh products each time.
    let f = |x: &[Var]| {
        let (a, b) = (x[0], x[1]);
        vec![(a * b).sin() + (b * a).sin(), (a * b) * (b * a) * 3.0]
    };
    let tape = Tape::record(&[0.3, 0.7], f).unwrap();
    // a·b, sin, add, square product, ×3: five operations instead of nine.
    assert_eq!(tape.stats().n_ops, 5, "{:?}", tape.ops());
    let (a, b) = (1.1, -0.4);
    let mut ws = tape.workspace();
    let (mut y, mut jac) = ([0.0; 2], vec![0.0; tape.jacobian_pattern().nnz()]);
    tape.jacobian(&[a, b], &mut ws, &mut y, &mut jac).unwrap();
    let p: f64 = a * b;
    assert!(close(y[0], 2.0 * p.sin(), 1e-15) && close(y[1], 3.0 * p * p, 1e-15));
    let expect = |r: usize, c: usize| {
        let dp = if c == 0 { b } else { a };
        if r == 0 {
            2.0 * p.cos() * dp
        } else {
            6.0 * p * dp
        }
    };
    let pat = tape.jacobian_pattern();
    for (e, (r, c)) in pat.iter().enumerate() {
        assert!(close(jac[e], expect(r, c), 1e-14), "J[{r}][{c}]");
    }
    // Hessian of λ0 y0 + λ1 y1 against the analytic second derivatives.
    let lambda = [0.7, -1.3];
    let mut hes = vec![0.0; tape.hessian_pattern().nnz()];
    tape.hessian(&[a, b], &lambda, &mut ws, &mut y, &mut hes)
        .unwrap();
    let d = [b, a];
    for (e, (i, j)) in tape.hessian_pattern().iter().enumerate() {
        let cross = if i != j { 1.0 } else { 0.0 };
        let h0 = 2.0 * (-p.sin() * d[i] * d[j] + p.cos() * cross);
        let h1 = 6.0 * (d[i] * d[j] + p * cross);
        assert!(
            close(hes[e], lambda[0] * h0 + lambda[1] * h1, 1e-13),
            "H[{i}][{j}]"
        );
    }
}

#[test]
fn batches_give_each_point_the_single_point_numbers() {
    let mut rng = Rng(11);
    for c in cases() {
        let tape = Tape::record(&rng.point(c.n, c.lo, c.hi), c.var).unwrap();
        let (n, m) = (c.n, tape.n_outputs());
        let (nj, nh) = (tape.jacobian_pattern().nnz(), tape.hessian_pattern().nnz());
        let mut ws = tape.workspace();
        let mut bw = tape.batch_workspace();
        for points in [1, BATCH - 1, BATCH] {
            let xs = rng.point(points * n, c.lo, c.hi);
            let lambdas = rng.point(points * m, -2.0, 2.0);
            let (mut ys, mut jacs) = (vec![0.0; points * m], vec![0.0; points * nj]);
            tape.jacobian_batch(&xs, &mut bw, &mut ys, &mut jacs)
                .unwrap();
            let mut hes = vec![0.0; points * nh];
            let mut ys2 = vec![0.0; points * m];
            tape.hessian_batch(&xs, &lambdas, &mut bw, &mut ys2, &mut hes)
                .unwrap();
            let mut ys3 = vec![0.0; points * m];
            tape.eval_batch(&xs, &mut bw, &mut ys3).unwrap();
            assert_eq!(ys3, ys, "{} values of the batch", c.name);
            // Jacobian and Hessian from one set of sweeps: the same numbers as each alone.
            let (mut ys4, mut jacs4) = (vec![0.0; points * m], vec![0.0; points * nj]);
            let mut hes4 = vec![0.0; points * nh];
            tape.jacobian_hessian_batch(&xs, &lambdas, &mut bw, &mut ys4, &mut jacs4, &mut hes4)
                .unwrap();
            assert_eq!(ys4, ys, "{} values with J and H", c.name);
            assert_eq!(jacs4, jacs, "{} J with H", c.name);
            assert_eq!(hes4, hes, "{} H with J", c.name);
            for p in 0..points {
                let x = &xs[p * n..(p + 1) * n];
                let (mut y, mut jac, mut h) = (vec![0.0; m], vec![0.0; nj], vec![0.0; nh]);
                tape.jacobian(x, &mut ws, &mut y, &mut jac).unwrap();
                assert_eq!(&ys[p * m..(p + 1) * m], &y[..], "{} y, point {p}", c.name);
                assert_eq!(
                    &jacs[p * nj..(p + 1) * nj],
                    &jac[..],
                    "{} J, point {p}",
                    c.name
                );
                tape.hessian(x, &lambdas[p * m..(p + 1) * m], &mut ws, &mut y, &mut h)
                    .unwrap();
                assert_eq!(&ys2[p * m..(p + 1) * m], &y[..], "{} y, point {p}", c.name);
                assert_eq!(
                    &hes[p * nh..(p + 1) * nh],
                    &h[..],
                    "{} H, point {p}",
                    c.name
                );
            }
        }
        // A batch of more than BATCH points, or a partial point, is a length error.
        let mut big = vec![0.0; (BATCH + 1) * m];
        let mut jbig = vec![0.0; (BATCH + 1) * nj];
        let xs = vec![0.5; (BATCH + 1) * n];
        let err = tape.jacobian_batch(&xs, &mut bw, &mut big, &mut jbig);
        assert!(matches!(err, Err(AdError::Length { .. })), "{}", c.name);
        let err = tape.jacobian_batch(&xs[..n + 1], &mut bw, &mut big, &mut jbig);
        assert!(matches!(err, Err(AdError::Length { .. })), "{}", c.name);
    }
}

#[test]
fn degenerate_tapes_work() {
    let empty = Tape::record(&[], |_| vec![]).unwrap();
    let mut ws = empty.workspace();
    empty.eval(&[], &mut ws, &mut []).unwrap();
    let constant = Tape::record(&[2.0], |x| vec![Var::cst(3.0), x[0] * 0.0 + 1.0]).unwrap();
    let mut ws = constant.workspace();
    let mut y = [0.0; 2];
    let mut jac = vec![0.0; constant.jacobian_pattern().nnz()];
    constant
        .jacobian(&[5.0], &mut ws, &mut y, &mut jac)
        .unwrap();
    assert_eq!(y, [3.0, 1.0]);
    assert!(jac.iter().all(|&j| j == 0.0));
    let identity = Tape::record(&[1.0, 2.0], |x| vec![x[1], x[0]]).unwrap();
    let mut ws = identity.workspace();
    let mut jac = vec![0.0; 2];
    let mut hes = vec![0.0; identity.hessian_pattern().nnz()];
    identity
        .jacobian(&[4.0, 5.0], &mut ws, &mut y, &mut jac)
        .unwrap();
    assert_eq!((y, jac.as_slice()), ([5.0, 4.0], &[1.0, 1.0][..]));
    identity
        .hessian(&[4.0, 5.0], &[1.0, 1.0], &mut ws, &mut y, &mut hes)
        .unwrap();
    assert!(hes.is_empty());
}

#[test]
fn tape_is_send_and_sync_and_evaluates_in_threads() {
    fn assert_send_sync<T: Send + Sync>() {}
    assert_send_sync::<Tape>();
    let tape = Tape::record(&[0.5; 40], banded).unwrap();
    let x: Vec<f64> = (0..40).map(|i| (i as f64 * 0.37).sin()).collect();
    let expect = banded::<f64>(&x);
    std::thread::scope(|s| {
        for _ in 0..2 {
            s.spawn(|| {
                let mut ws = tape.workspace();
                let mut y = vec![0.0; 40];
                tape.eval(&x, &mut ws, &mut y).unwrap();
                assert_eq!(y, expect);
            });
        }
    });
}
