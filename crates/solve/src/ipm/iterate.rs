//! The iterate of the interior point and the measures taken on it.
//!
//! The iteration works on the scaled problem (see [`super::scaled::ScaledNlp`]) with
//! variables w = (x, s): slacks s for the inequality rows, bounds L ≤ w ≤ U, and equality
//! residuals r(w) = c(x) − (g for equality rows, s for inequality rows) = 0. The barrier
//! problem at μ is min φ_μ(w) = f(x) − μ Σ ln(w − L) − μ Σ ln(U − w) subject to r(w) = 0
//! (Wächter & Biegler 2006, section 2.1); z_L, z_U are the bound multipliers and λ the
//! constraint multipliers (∇f + Jᵀλ − z_L + z_U = 0 at a solution).
// Index loops over several parallel arrays are clearer than zipped iterators here.
#![allow(clippy::needless_range_loop)]

use crate::ipm::lbfgs::dot;
use crate::ipm::scaled::ScaledNlp;
use crate::nlp::EvalError;

/// `slack_of_row` entry of an equality row.
pub(super) const NO_SLACK: usize = usize::MAX;

/// The primal-dual iterate with the values and derivatives of the problem functions at it,
/// and the bound and slack layout of the problem they belong to.
#[derive(Clone)]
pub(super) struct Iterate {
    pub(super) n: usize,
    pub(super) m: usize,
    pub(super) big_n: usize,
    pub(super) slack_of_row: Vec<usize>,
    pub(super) row_of_slack: Vec<usize>,
    pub(super) g_eq: Vec<f64>,
    pub(super) wl: Vec<f64>,
    pub(super) wu: Vec<f64>,
    pub(super) has_l: Vec<bool>,
    pub(super) has_u: Vec<bool>,
    pub(super) w: Vec<f64>,
    pub(super) lam: Vec<f64>,
    pub(super) zl: Vec<f64>,
    pub(super) zu: Vec<f64>,
    pub(super) f: f64,
    pub(super) grad: Vec<f64>,
    pub(super) c: Vec<f64>,
    pub(super) jv: Vec<f64>,
    pub(super) hv: Vec<f64>,
}

impl Iterate {
    /// Equality residuals r(w) = c − (g or s) of the point `w` with constraint values `c`.
    pub(super) fn residual(&self, w: &[f64], c: &[f64], r: &mut [f64]) {
        for i in 0..self.m {
            let k = self.slack_of_row[i];
            r[i] = if k == NO_SLACK {
                c[i] - self.g_eq[i]
            } else {
                c[i] - w[self.n + k]
            };
        }
    }

    /// ∇f + Aᵀλ over w (without the bound multipliers).
    pub(super) fn grad_lag_no_z(&self, jac_rows: &[usize], jac_cols: &[usize], out: &mut [f64]) {
        out[..self.n].copy_from_slice(&self.grad);
        out[self.n..].iter_mut().for_each(|v| *v = 0.0);
        for k in 0..self.jv.len() {
            out[jac_cols[k]] += self.jv[k] * self.lam[jac_rows[k]];
        }
        for (k, &i) in self.row_of_slack.iter().enumerate() {
            out[self.n + k] -= self.lam[i];
        }
    }

    /// f + barrier terms at (f, w).
    pub(super) fn barrier(&self, f: f64, w: &[f64], mu: f64) -> f64 {
        let mut b = f;
        for j in 0..self.big_n {
            if self.has_l[j] {
                b -= mu * (w[j] - self.wl[j]).ln();
            }
            if self.has_u[j] {
                b -= mu * (self.wu[j] - w[j]).ln();
            }
        }
        b
    }

    /// Max-norm of the shifted complementarity z (w − bound) − μ over all bounds.
    pub(super) fn complementarity(&self, mu: f64) -> f64 {
        let mut e = 0.0f64;
        for j in 0..self.big_n {
            if self.has_l[j] {
                e = e.max(((self.w[j] - self.wl[j]) * self.zl[j] - mu).abs());
            }
            if self.has_u[j] {
                e = e.max(((self.wu[j] - self.w[j]) * self.zu[j] - mu).abs());
            }
        }
        e
    }

    /// Primal-dual error of the barrier problem at μ (IPOPT's `curr_primal_dual_system_error`
    /// in the mean-squared form): ‖r‖²/m + ‖∇L‖²/N + mean of (z (w − bound) − μ)², with the
    /// Lagrangian gradient `gl` (bound multipliers included) and residual `r` given.
    pub(super) fn pd_barrier_error(&self, gl: &[f64], r: &[f64], mu: f64) -> f64 {
        let (pr, du) = self.mean_squared_infeasibilities(gl, r);
        pr + du + self.mean_squared_complementarity(mu)
    }

    /// Mean squared primal infeasibility ‖r‖²/m and dual infeasibility ‖∇L‖²/N.
    pub(super) fn mean_squared_infeasibilities(&self, gl: &[f64], r: &[f64]) -> (f64, f64) {
        (
            r.iter().map(|v| v * v).sum::<f64>() / self.m.max(1) as f64,
            gl.iter().map(|v| v * v).sum::<f64>() / self.big_n.max(1) as f64,
        )
    }

    /// Mean and mean square of the complementarity products (w + α_p dw − bound)(z + α_d dz)
    /// over all bounds after a primal step α_p dw and a bound-multiplier step α_d dz.
    pub(super) fn complementarity_after_step(
        &self,
        dw: &[f64],
        dzl: &[f64],
        dzu: &[f64],
        ap: f64,
        ad: f64,
    ) -> (f64, f64) {
        let (mut s, mut s2, mut cnt) = (0.0, 0.0, 0usize);
        for j in 0..self.big_n {
            if self.has_l[j] {
                let p = (self.w[j] + ap * dw[j] - self.wl[j]) * (self.zl[j] + ad * dzl[j]);
                s += p;
                s2 += p * p;
                cnt += 1;
            }
            if self.has_u[j] {
                let p = (self.wu[j] - self.w[j] - ap * dw[j]) * (self.zu[j] + ad * dzu[j]);
                s += p;
                s2 += p * p;
                cnt += 1;
            }
        }
        let c = cnt.max(1) as f64;
        (s / c, s2 / c)
    }

    /// A copy of the iterate without the Hessian values (the copies kept by soft
    /// restoration and the watchdog never need them: the Hessian is evaluated again at
    /// every accepted point before it is used).
    pub(super) fn clone_without_hessian(&mut self) -> Iterate {
        let hv = std::mem::take(&mut self.hv);
        let copy = self.clone();
        self.hv = hv;
        copy
    }

    /// ∇L over w with the bound multipliers, fixed variables zeroed.
    pub(super) fn grad_lag(
        &self,
        jac_rows: &[usize],
        jac_cols: &[usize],
        fixed_x: &[bool],
        out: &mut [f64],
    ) {
        self.grad_lag_no_z(jac_rows, jac_cols, out);
        for j in 0..self.big_n {
            out[j] += self.zu[j] - self.zl[j];
        }
        for (o, &f) in out[..self.n].iter_mut().zip(fixed_x) {
            if f {
                *o = 0.0;
            }
        }
    }

    /// Mean squared shifted complementarity (z_L (w − w_L) − μ)², (z_U (w_U − w) − μ)² over
    /// all bounds.
    pub(super) fn mean_squared_complementarity(&self, mu: f64) -> f64 {
        let (mut s, mut cnt) = (0.0, 0usize);
        for j in 0..self.big_n {
            if self.has_l[j] {
                s += ((self.w[j] - self.wl[j]) * self.zl[j] - mu).powi(2);
                cnt += 1;
            }
            if self.has_u[j] {
                s += ((self.wu[j] - self.w[j]) * self.zu[j] - mu).powi(2);
                cnt += 1;
            }
        }
        if cnt == 0 {
            0.0
        } else {
            s / cnt as f64
        }
    }

    /// Mean complementarity product z (w − bound) over all bounds (0 without bounds).
    pub(super) fn average_complementarity(&self) -> f64 {
        let (mut s, mut cnt) = (0.0, 0usize);
        for j in 0..self.big_n {
            if self.has_l[j] {
                s += (self.w[j] - self.wl[j]) * self.zl[j];
                cnt += 1;
            }
            if self.has_u[j] {
                s += (self.wu[j] - self.w[j]) * self.zu[j];
                cnt += 1;
            }
        }
        if cnt == 0 {
            0.0
        } else {
            s / cnt as f64
        }
    }
}

/// Max-norm of `v`.
pub(super) fn inf_norm(v: &[f64]) -> f64 {
    v.iter().fold(0.0f64, |a, x| a.max(x.abs()))
}

/// 1-norm of `v`.
pub(super) fn one_norm(v: &[f64]) -> f64 {
    v.iter().map(|x| x.abs()).sum()
}

/// Largest α in (0, 1] keeping v + α dv − lo >= (1 − τ)(v − lo) and hi − v − α dv likewise.
pub(super) fn fraction_to_boundary(st: &Iterate, w: &[f64], dw: &[f64], tau: f64) -> f64 {
    let mut a = 1.0f64;
    for j in 0..st.big_n {
        if st.has_l[j] && dw[j] < 0.0 {
            a = a.min(-tau * (w[j] - st.wl[j]) / dw[j]);
        }
        if st.has_u[j] && dw[j] > 0.0 {
            a = a.min(tau * (st.wu[j] - w[j]) / dw[j]);
        }
    }
    a
}

/// Largest α in (0, 1] keeping z + α dz ≥ (1 − τ) z for both bound multipliers.
pub(super) fn dual_fraction_to_boundary(st: &Iterate, dzl: &[f64], dzu: &[f64], tau: f64) -> f64 {
    let mut a = 1.0f64;
    for j in 0..st.big_n {
        if st.has_l[j] && dzl[j] < 0.0 {
            a = a.min(-tau * st.zl[j] / dzl[j]);
        }
        if st.has_u[j] && dzu[j] < 0.0 {
            a = a.min(-tau * st.zu[j] / dzu[j]);
        }
    }
    a
}

/// Objective at the trial point wt = w + α d (slacks included in `wt`), with the constraint
/// values written into `ct`.
pub(super) fn evaluate_trial(
    prob: &mut ScaledNlp,
    w: &[f64],
    alpha: f64,
    d: &[f64],
    wt: &mut [f64],
    ct: &mut [f64],
) -> Result<f64, EvalError> {
    for ((t, &x), &dx) in wt.iter_mut().zip(w).zip(d) {
        *t = x + alpha * dx;
    }
    let x = &wt[..prob.nlp.n()];
    let f = prob.objective(x)?;
    prob.constraints(x, ct)?;
    Ok(f)
}

/// ∇φ_μ(w)ᵀ dw for the barrier function φ_μ = f − μ Σ ln(slacks to bounds).
pub(super) fn barrier_directional_derivative(st: &Iterate, mu: f64, dw: &[f64]) -> f64 {
    let mut g = dot(&st.grad, &dw[..st.n]);
    for j in 0..st.big_n {
        if st.has_l[j] {
            g -= mu / (st.w[j] - st.wl[j]) * dw[j];
        }
        if st.has_u[j] {
            g += mu / (st.wu[j] - st.w[j]) * dw[j];
        }
    }
    g
}
