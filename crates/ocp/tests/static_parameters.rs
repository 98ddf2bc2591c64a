//! Static parameters (FORMULATION 12.6): the contact calibration's 18 sphere parameters in
//! the tracking NLP, differentiated like the other variables. The objective gradient, the
//! constraint Jacobian and the Lagrangian Hessian with respect to the static parameters
//! (and their cross terms with some states and controls) are checked against central
//! finite differences on a 2-interval mesh; and the NLP with calibration at the generic
//! values equals the NLP without it.

use stride_ocp::tracking::{TrackSettings, TrackingProblem};
use stride_solve::nlp::{check_derivatives, DerivativeCheckOptions, EvalError, Nlp, Sparsity};

/// The NLP `inner` as a function of the variables `vars` only, the others fixed at `base`.
struct Restricted<'a, N: Nlp> {
    inner: &'a N,
    base: Vec<f64>,
    vars: Vec<usize>,
    /// Position in `vars` of every inner variable (None: fixed).
    pos: Vec<Option<usize>>,
    jac: Vec<(usize, usize, usize)>,
    hess: Vec<(usize, usize, usize)>,
}

impl<'a, N: Nlp> Restricted<'a, N> {
    fn new(inner: &'a N, base: Vec<f64>, vars: Vec<usize>) -> Self {
        let mut pos = vec![None; inner.n()];
        for (k, &v) in vars.iter().enumerate() {
            pos[v] = Some(k);
        }
        let js = inner.jacobian_structure();
        let jac = (0..js.nnz())
            .filter_map(|e| pos[js.cols[e]].map(|c| (e, js.rows[e], c)))
            .collect();
        let hs = inner.hessian_structure();
        let hess = (0..hs.nnz())
            .filter_map(|e| match (pos[hs.rows[e]], pos[hs.cols[e]]) {
                (Some(r), Some(c)) => Some((e, r.max(c), r.min(c))),
                _ => None,
            })
            .collect();
        Self {
            inner,
            base,
            vars,
            pos,
            jac,
            hess,
        }
    }

    fn full(&self, x: &[f64]) -> Vec<f64> {
        let mut f = self.base.clone();
        for (k, &v) in self.vars.iter().enumerate() {
            f[v] = x[k];
        }
        f
    }
}

impl<N: Nlp> Nlp for Restricted<'_, N> {
    fn n(&self) -> usize {
        self.vars.len()
    }
    fn m(&self) -> usize {
        self.inner.m()
    }
    fn bounds(&self, x_l: &mut [f64], x_u: &mut [f64], g_l: &mut [f64], g_u: &mut [f64]) {
        let n = self.inner.n();
        let (mut l, mut u) = (vec![0.0; n], vec![0.0; n]);
        self.inner.bounds(&mut l, &mut u, g_l, g_u);
        for (k, &v) in self.vars.iter().enumerate() {
            (x_l[k], x_u[k]) = (l[v], u[v]);
        }
    }
    fn initial_point(&self, x: &mut [f64]) {
        for (k, &v) in self.vars.iter().enumerate() {
            x[k] = self.base[v];
        }
    }
    fn objective(&self, x: &[f64]) -> Result<f64, EvalError> {
        self.inner.objective(&self.full(x))
    }
    fn gradient(&self, x: &[f64], grad: &mut [f64]) -> Result<(), EvalError> {
        let mut g = vec![0.0; self.inner.n()];
        self.inner.gradient(&self.full(x), &mut g)?;
        for (i, p) in self.pos.iter().enumerate() {
            if let Some(k) = p {
                grad[*k] = g[i];
            }
        }
        Ok(())
    }
    fn constraints(&self, x: &[f64], c: &mut [f64]) -> Result<(), EvalError> {
        self.inner.constraints(&self.full(x), c)
    }
    fn jacobian_structure(&self) -> Sparsity {
        let mut s = Sparsity::default();
        for &(_, r, c) in &self.jac {
            s.push(r, c);
        }
        s
    }
    fn jacobian_values(&self, x: &[f64], vals: &mut [f64]) -> Result<(), EvalError> {
        let mut v = vec![0.0; self.inner.jacobian_structure().nnz()];
        self.inner.jacobian_values(&self.full(x), &mut v)?;
        for (k, &(e, _, _)) in self.jac.iter().enumerate() {
            vals[k] = v[e];
        }
        Ok(())
    }
    fn hessian_structure(&self) -> Sparsity {
        let mut s = Sparsity::default();
        for &(_, r, c) in &self.hess {
            s.push(r, c);
        }
        s
    }
    fn hessian_values(
        &self,
        x: &[f64],
        obj_factor: f64,
        lambda: &[f64],
        vals: &mut [f64],
    ) -> Result<(), EvalError> {
        let mut v = vec![0.0; self.inner.hessian_structure().nnz()];
        self.inner
            .hessian_values(&self.full(x), obj_factor, lambda, &mut v)?;
        for (k, &(e, _, _)) in self.hess.iter().enumerate() {
            vals[k] = v[e];
        }
        Ok(())
    }
}

fn calibration(mesh: usize) -> TrackingProblem {
    let model = stride_model::default_model::default_model();
    TrackingProblem::new(
        &model,
        &TrackSettings {
            mesh_intervals: mesh,
            window: [3.45, 3.6],
            calibrate_contact: true,
            ..Default::default()
        },
    )
    .unwrap()
}

#[test]
fn derivatives_with_respect_to_the_static_parameters_match_finite_differences() {
    let mut tp = calibration(2);
    for (i, xi) in tp.x0.iter_mut().enumerate() {
        *xi += 1e-3 * ((i as f64 * 0.7548776662).fract() - 0.5);
    }
    let tr = tp.transcription().unwrap();
    let n_layout = tp.problem.layout.len();
    assert_eq!(tr.n(), n_layout + 18);
    // the 18 parameters, and every 97th other variable (states and controls of every
    // point, for the cross terms)
    let mut vars: Vec<usize> = (0..n_layout).step_by(97).collect();
    vars.extend(n_layout..n_layout + 18);
    let r = Restricted::new(&tr, tp.x0.clone(), vars);
    let x: Vec<f64> = r.vars.iter().map(|&v| tp.x0[v]).collect();
    let lambda: Vec<f64> = (0..tr.m())
        .map(|i| ((i as f64 * 0.5698402910).fract() - 0.5) * 2.0)
        .collect();
    for (lambda, tol) in [(None, 1e-6), (Some(lambda), 1e-4)] {
        let report = check_derivatives(
            &r,
            &x,
            &DerivativeCheckOptions {
                max_columns: x.len(),
                lambda,
                obj_factor: 0.7,
                tol,
                step: 1e-5,
            },
        )
        .unwrap();
        assert!(
            report.mismatches.is_empty(),
            "{:?}",
            &report.mismatches[..report.mismatches.len().min(5)]
        );
    }
    // the parameters enter the contact forces: the gradient is not zero
    let mut g = vec![0.0; tr.n()];
    tr.gradient(&tp.x0, &mut g).unwrap();
    assert!(
        g[n_layout..].iter().any(|v| v.abs() > 1e-3),
        "{:?}",
        &g[n_layout..]
    );
}

#[test]
fn calibration_at_the_generic_values_gives_the_problem_without_calibration() {
    let tp = calibration(2);
    let model = stride_model::default_model::default_model();
    let plain = TrackingProblem::new(
        &model,
        &TrackSettings {
            mesh_intervals: 2,
            window: [3.45, 3.6],
            ..Default::default()
        },
    )
    .unwrap();
    let (a, b) = (tp.transcription().unwrap(), plain.transcription().unwrap());
    let n = plain.problem.layout.len();
    assert_eq!(tp.x0[..n], plain.x0[..]);
    let (fa, fb) = (
        a.objective(&tp.x0).unwrap(),
        b.objective(&plain.x0).unwrap(),
    );
    assert!((fa - fb).abs() <= 1e-10 * fb.abs(), "{fa} {fb}");
    let (mut ca, mut cb) = (vec![0.0; a.m()], vec![0.0; b.m()]);
    a.constraints(&tp.x0, &mut ca).unwrap();
    b.constraints(&plain.x0, &mut cb).unwrap();
    for (i, (u, v)) in ca.iter().zip(&cb).enumerate() {
        assert!(
            (u - v).abs() <= 1e-10 * v.abs().max(1.0),
            "row {i}: {u} {v}"
        );
    }
    // bounds of the scaled parameters: [−0.5, 0.5], the generic value in the middle
    let (mut xl, mut xu) = (vec![0.0; a.n()], vec![0.0; a.n()]);
    let (mut gl, mut gu) = (vec![0.0; a.m()], vec![0.0; a.m()]);
    a.bounds(&mut xl, &mut xu, &mut gl, &mut gu);
    assert!(xl[n..].iter().all(|&v| v == -0.5) && xu[n..].iter().all(|&v| v == 0.5));
    assert!(tp.x0[n..].iter().all(|v| v.abs() < 1e-12));
}
