//! The problem as the interior-point method sees it: gradient-based scaling (IPOPT's default
//! `nlp_scaling_method = gradient-based`), inequality rows with slacks, evaluation timing.

use std::time::{Duration, Instant};

use crate::nlp::{check_finite, EvalError, Nlp, NlpFunction, Sparsity};

/// A scaled view of an [`Nlp`]: f̃ = s_f f, c̃_i = s_i c_i, with evaluation time accounting.
pub struct ScaledNlp<'a> {
    /// The original problem.
    pub nlp: &'a dyn Nlp,
    /// Objective scale factor s_f.
    pub obj_scale: f64,
    /// Constraint scale factors s_i.
    pub con_scale: Vec<f64>,
    /// Jacobian pattern.
    pub jac: Sparsity,
    /// Hessian pattern (lower triangle).
    pub hess: Sparsity,
    /// Accumulated time in problem evaluations.
    pub eval_time: Duration,
    /// Objective evaluations.
    pub n_obj: usize,
    lambda_buf: Vec<f64>,
}

impl<'a> ScaledNlp<'a> {
    /// Wraps `nlp` with unit scaling.
    pub fn new(nlp: &'a dyn Nlp, jac: Sparsity, hess: Sparsity) -> Self {
        let m = nlp.m();
        ScaledNlp {
            nlp,
            obj_scale: 1.0,
            con_scale: vec![1.0; m],
            jac,
            hess,
            eval_time: Duration::ZERO,
            n_obj: 0,
            lambda_buf: vec![0.0; m],
        }
    }

    /// Sets s_f = min(1, g_max/‖∇f(x₀)‖∞) and s_i = min(1, g_max/‖∇c_i(x₀)‖∞).
    pub fn compute_gradient_scaling(
        &mut self,
        x0: &[f64],
        max_gradient: f64,
    ) -> Result<(), EvalError> {
        let mut g = vec![0.0; self.nlp.n()];
        let mut jv = vec![0.0; self.jac.nnz()];
        let t = Instant::now();
        self.nlp.gradient(x0, &mut g)?;
        self.nlp.jacobian_values(x0, &mut jv)?;
        self.eval_time += t.elapsed();
        check_finite(NlpFunction::Gradient, &g)?;
        check_finite(NlpFunction::Jacobian, &jv)?;
        let gmax = g.iter().fold(0.0f64, |a, v| a.max(v.abs()));
        self.obj_scale = if gmax > max_gradient {
            max_gradient / gmax
        } else {
            1.0
        };
        let mut rmax = vec![0.0f64; self.nlp.m()];
        for (k, v) in jv.iter().enumerate() {
            let r = self.jac.rows[k];
            rmax[r] = rmax[r].max(v.abs());
        }
        for (s, r) in self.con_scale.iter_mut().zip(&rmax) {
            *s = if *r > max_gradient {
                max_gradient / r
            } else {
                1.0
            };
        }
        Ok(())
    }

    fn timed<R>(&mut self, f: impl FnOnce(&dyn Nlp) -> R) -> R {
        let t = Instant::now();
        let r = f(self.nlp);
        self.eval_time += t.elapsed();
        r
    }

    /// Scaled objective.
    pub fn objective(&mut self, x: &[f64]) -> Result<f64, EvalError> {
        self.n_obj += 1;
        let f = self.timed(|p| p.objective(x))?;
        check_finite(NlpFunction::Objective, &[f])?;
        Ok(f * self.obj_scale)
    }

    /// Scaled gradient.
    pub fn gradient(&mut self, x: &[f64], g: &mut [f64]) -> Result<(), EvalError> {
        self.timed(|p| p.gradient(x, g))?;
        check_finite(NlpFunction::Gradient, g)?;
        let s = self.obj_scale;
        g.iter_mut().for_each(|v| *v *= s);
        Ok(())
    }

    /// Scaled constraint values.
    pub fn constraints(&mut self, x: &[f64], c: &mut [f64]) -> Result<(), EvalError> {
        self.timed(|p| p.constraints(x, c))?;
        check_finite(NlpFunction::Constraints, c)?;
        for (v, s) in c.iter_mut().zip(&self.con_scale) {
            *v *= s;
        }
        Ok(())
    }

    /// Scaled Jacobian values.
    pub fn jacobian(&mut self, x: &[f64], vals: &mut [f64]) -> Result<(), EvalError> {
        self.timed(|p| p.jacobian_values(x, vals))?;
        check_finite(NlpFunction::Jacobian, vals)?;
        for (k, v) in vals.iter_mut().enumerate() {
            *v *= self.con_scale[self.jac.rows[k]];
        }
        Ok(())
    }

    /// Hessian of the scaled Lagrangian obj_factor·f̃ + Σ λ̃_i c̃_i.
    pub fn hessian(
        &mut self,
        x: &[f64],
        obj_factor: f64,
        lambda: &[f64],
        vals: &mut [f64],
    ) -> Result<(), EvalError> {
        for ((b, l), s) in self.lambda_buf.iter_mut().zip(lambda).zip(&self.con_scale) {
            *b = l * s;
        }
        let of = obj_factor * self.obj_scale;
        let lb = std::mem::take(&mut self.lambda_buf);
        let r = self.timed(|p| p.hessian_values(x, of, &lb, vals));
        self.lambda_buf = lb;
        r?;
        check_finite(NlpFunction::Hessian, vals)
    }
}
