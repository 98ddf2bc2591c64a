//! The filter line search with second-order correction and watchdog (Wächter & Biegler
//! 2006, Algorithm A, steps; IPOPT's watchdog).
//!
//! Backtracking from α_max (fraction to the boundary, τ) halves α until the filter
//! ([`super::filter`]) accepts w + α d or α < α_min. If the first trial is rejected with
//! θ not reduced, up to [`MAX_SOC`] second-order corrections solve again with the residual
//! α r + r(w + α d) accumulated (section 2.4) and are accepted on the filter at α_max.
//! After `watchdog_trigger` shortened steps in a row the watchdog takes full steps, each
//! accepted if the filter accepts it against the references of the watchdog's starting
//! point, else taken anyway up to [`WATCHDOG_TRIAL_MAX`] times; it then returns to the
//! starting point and backtracks along its direction from α_max / 2.
// Index loops over several parallel arrays are clearer than zipped iterators here.
#![allow(clippy::needless_range_loop)]

use crate::ipm::direction::{Out, Residual, Targets};
use crate::ipm::filter::{Filter, LsReference};
use crate::ipm::iterate::{
    barrier_directional_derivative, evaluate_trial, fraction_to_boundary, inf_norm, one_norm,
};
use crate::ipm::workspace::{Ipm, LineSearch, Watchdog};
use crate::observer::Diagnostic;
use crate::solver::SolveError;

/// Second-order correction: at most this many corrections, each reducing θ by κ_soc.
const MAX_SOC: usize = 4;
const KAPPA_SOC: f64 = 0.99;
/// Full steps the watchdog takes before it returns to its starting point (IPOPT
/// `watchdog_trial_iter_max`).
const WATCHDOG_TRIAL_MAX: usize = 3;
/// Trial points of one backtracking at most.
const MAX_TRIALS: usize = 60;

impl LineSearch {
    /// State and buffers for `big_n` variables and `m` constraints, with room for a filter
    /// entry per iteration up to `capacity`.
    pub fn new(big_n: usize, m: usize, capacity: usize) -> Self {
        LineSearch {
            filter: Filter::with_capacity(capacity),
            theta_max: f64::INFINITY,
            theta_min: 0.0,
            watchdog: None,
            shortened_steps: 0,
            watchdog_starts: 0,
            watchdog_returns: 0,
            failures: 0,
            tiny_step: false,
            wt: vec![0.0; big_n],
            ct: vec![0.0; m],
            rt: vec![0.0; m],
            soc_rhs_r: vec![0.0; m],
            gl_trial: vec![0.0; big_n],
        }
    }
}

/// The outcome of one line search.
pub(super) struct Trial {
    /// Primal (and constraint-multiplier) step size.
    pub alpha: f64,
    /// Fraction-to-boundary step size of the direction.
    pub alpha_max: f64,
    /// Smallest step size of the backtracking.
    pub alpha_min: f64,
    /// Objective at the accepted trial point (in `ls.wt`, `ls.ct`).
    pub f_t: f64,
    /// Trial points evaluated.
    pub trials: usize,
    /// Whether a step was accepted.
    pub accepted: bool,
    /// Whether it passed the Armijo test of the switching condition.
    pub armijo_step: bool,
    /// Whether it is a watchdog step taken without acceptance.
    pub watchdog_step: bool,
    /// References the step was judged against.
    pub reference: LsReference,
    /// Max-norm of the direction.
    pub dnorm: f64,
}

impl Ipm<'_> {
    /// The filter line search of one iteration along `newton.main`.
    pub(super) fn line_search(&mut self) -> Result<Trial, SolveError> {
        let mut trial = self.ls_start();
        self.watchdog(&mut trial);
        trial.dnorm = inf_norm(&self.newton.main.dw);
        self.backtrack(&mut trial)?;
        if trial.accepted && !trial.armijo_step && !trial.watchdog_step {
            self.ls.filter.augment(&trial.reference);
        }
        // a shortened step counts towards the watchdog trigger
        if trial.accepted && !self.ls.tiny_step && trial.alpha < trial.alpha_max {
            self.ls.shortened_steps += 1;
        } else {
            self.ls.shortened_steps = 0;
        }
        Ok(trial)
    }

    /// References of the line search at the current iterate (θ, φ_μ, ∇φ_μᵀd, α_max, α_min).
    fn ls_start(&mut self) -> Trial {
        let (mu, tau) = (self.barrier.mu, self.barrier.tau);
        let st = &self.st;
        let dw = &self.newton.main.dw;
        let alpha_max = fraction_to_boundary(st, &st.w, dw, tau);
        let theta0 = one_norm(&self.opt.r);
        if self.iter == 0 {
            self.ls.theta_max = 1e4 * theta0.max(1.0);
            self.ls.theta_min = 1e-4 * theta0.max(1.0);
        }
        self.ls.filter.set_mu(mu);
        let reference = LsReference {
            theta: theta0,
            phi: st.barrier(st.f, &st.w, mu),
            gphi_d: barrier_directional_derivative(st, mu, dw),
            theta_min: self.ls.theta_min,
            theta_max: self.ls.theta_max,
        };
        self.ls.tiny_step = false;
        Trial {
            alpha: alpha_max,
            alpha_max,
            alpha_min: reference.alpha_min(),
            f_t: st.f,
            trials: 0,
            accepted: false,
            armijo_step: false,
            watchdog_step: false,
            reference,
            dnorm: 0.0,
        }
    }

    /// Starts the watchdog after enough shortened steps, and takes its full step when it
    /// is active (or returns to its starting point).
    fn watchdog(&mut self, trial: &mut Trial) {
        let mu = self.barrier.mu;
        if self.ls.watchdog.as_ref().is_some_and(|wd| wd.mu != mu) {
            // the barrier problem changed: the stored references no longer apply
            self.ls.watchdog = None;
        }
        let trigger = self.o.watchdog_trigger;
        if self.ls.watchdog.is_none() && trigger > 0 && self.ls.shortened_steps >= trigger {
            self.ls.watchdog = Some(Watchdog {
                st: self.st.clone_without_hessian(),
                dw: self.newton.main.dw.clone(),
                dlam: self.newton.main.dlam.clone(),
                reference: trial.reference,
                alpha_max: trial.alpha_max,
                alpha_min: trial.alpha_min,
                mu,
                trials: 0,
            });
            self.ls.shortened_steps = 0;
            self.ls.watchdog_starts += 1;
            self.emitter.emit(Diagnostic::WatchdogStarted);
        }
        if self.ls.watchdog.is_some() {
            self.watchdog_trial(trial);
        }
    }

    /// The watchdog's full step: accepted against the starting point's references (the
    /// watchdog ends), taken anyway while it has trials left, else back to the start.
    fn watchdog_trial(&mut self, trial: &mut Trial) {
        let (mu, alpha_max) = (self.barrier.mu, trial.alpha_max);
        trial.trials = 1;
        let Ipm {
            st,
            prob,
            ls,
            newton,
            ..
        } = self;
        let ev = evaluate_trial(
            prob,
            &st.w,
            alpha_max,
            &newton.main.dw,
            &mut ls.wt,
            &mut ls.ct,
        );
        let wd = ls.watchdog.as_mut().expect("watchdog active");
        let verdict = ev.as_ref().ok().map(|&f| {
            st.residual(&ls.wt, &ls.ct, &mut ls.rt);
            let phi = st.barrier(f, &ls.wt, mu);
            let theta = one_norm(&ls.rt);
            (f, wd.reference.accepts(alpha_max, theta, phi, &ls.filter))
        });
        match verdict {
            Some((f, Some(a))) => {
                // progress against the starting point: the watchdog ends here
                trial.f_t = f;
                trial.accepted = true;
                trial.armijo_step = a;
                trial.reference = wd.reference;
                ls.watchdog = None;
            }
            Some((f, None)) if wd.trials < WATCHDOG_TRIAL_MAX => {
                wd.trials += 1;
                trial.f_t = f;
                trial.accepted = true;
                trial.watchdog_step = true;
            }
            _ => self.watchdog_return(trial),
        }
    }

    /// No acceptable full step: back to the watchdog's starting point and its direction,
    /// backtracking from α_max / 2.
    fn watchdog_return(&mut self, trial: &mut Trial) {
        let wd = self.ls.watchdog.take().expect("watchdog active");
        // keep the Hessian buffer: its values are evaluated again at the next accepted point
        // before the KKT matrix is assembled
        let hv = std::mem::take(&mut self.st.hv);
        self.st = wd.st;
        self.st.hv = hv;
        self.newton.main.dw.copy_from_slice(&wd.dw);
        self.newton.main.dlam.copy_from_slice(&wd.dlam);
        // the stored direction's bound-multiplier steps are taken at μ alone
        self.corr.targets_on = false;
        trial.reference = wd.reference;
        trial.alpha_max = wd.alpha_max;
        trial.alpha_min = wd.alpha_min;
        self.measure_residuals();
        trial.alpha = 0.5 * trial.alpha_max;
        self.ls.watchdog_returns += 1;
        self.emitter.emit(Diagnostic::WatchdogReturned);
    }

    /// Backtracking along `newton.main` until the filter accepts a trial point, with the
    /// second-order correction after a first trial rejected for θ.
    fn backtrack(&mut self, trial: &mut Trial) -> Result<(), SolveError> {
        let mu = self.barrier.mu;
        let wnorm = inf_norm(&self.st.w).max(1.0);
        while !trial.accepted {
            trial.trials += 1;
            let Ipm {
                st,
                prob,
                ls,
                newton,
                ..
            } = self;
            let (alpha, dw) = (trial.alpha, &newton.main.dw);
            let ev = evaluate_trial(prob, &st.w, alpha, dw, &mut ls.wt, &mut ls.ct);
            let mut theta_t = f64::INFINITY;
            if let Ok(f) = ev {
                st.residual(&ls.wt, &ls.ct, &mut ls.rt);
                theta_t = one_norm(&ls.rt);
                let phi = st.barrier(f, &ls.wt, mu);
                if let Some(a) = trial.reference.accepts(alpha, theta_t, phi, &ls.filter) {
                    trial.f_t = f;
                    trial.accepted = true;
                    trial.armijo_step = a;
                    break;
                }
            }
            // only a full step that is already at round-off level is accepted unconditionally
            let tiny = trial.alpha_max * trial.dnorm <= 10.0 * f64::EPSILON * wnorm;
            if tiny && ev.is_ok() {
                trial.f_t = ev.unwrap_or(st.f);
                trial.accepted = true;
                ls.tiny_step = true;
                break;
            }
            if trial.trials == 1
                && theta_t.is_finite()
                && theta_t >= trial.reference.theta
                && self.second_order_correction(trial)?
            {
                trial.accepted = true;
                break;
            }
            trial.alpha *= 0.5;
            if trial.alpha < trial.alpha_min || trial.trials >= MAX_TRIALS {
                break;
            }
        }
        Ok(())
    }

    /// Second-order corrections after the first trial step (α, in `ls.rt` its residual) was
    /// rejected for θ: each solves with the accumulated residual α r + r(trial) and is
    /// judged by the filter at α_max. An accepted one becomes the direction, scaled so that
    /// α = 1 gives the accepted point (already in `ls.wt`).
    fn second_order_correction(&mut self, trial: &mut Trial) -> Result<bool, SolveError> {
        let (mu, tau, alpha) = (self.barrier.mu, self.barrier.tau, trial.alpha);
        let theta0 = trial.reference.theta;
        let mut theta_old = theta0;
        let mut theta_soc = one_norm(&self.ls.rt);
        for i in 0..self.st.m {
            self.ls.soc_rhs_r[i] = alpha * self.opt.r[i] + self.ls.rt[i];
        }
        let targets = if self.corr.targets_on {
            Targets::Kept
        } else {
            Targets::None
        };
        for _ in 0..MAX_SOC {
            if theta_soc > KAPPA_SOC * theta_old && theta_old != theta0 {
                break;
            }
            self.direction(mu, targets, Residual::Soc, Out::Soc)?;
            let Ipm {
                st,
                prob,
                ls,
                newton,
                emitter,
                ..
            } = self;
            let dw_soc = &newton.soc.dw;
            let a_soc = fraction_to_boundary(st, &st.w, dw_soc, tau);
            let ev = evaluate_trial(prob, &st.w, a_soc, dw_soc, &mut ls.wt, &mut ls.ct);
            let Ok(f) = ev else { break };
            st.residual(&ls.wt, &ls.ct, &mut ls.rt);
            theta_old = theta_soc;
            theta_soc = one_norm(&ls.rt);
            let phi = st.barrier(f, &ls.wt, mu);
            let verdict = trial
                .reference
                .accepts(trial.alpha_max, theta_soc, phi, &ls.filter);
            emitter.emit(Diagnostic::SecondOrderCorrection {
                theta: theta_soc,
                accepted: verdict.is_some(),
            });
            if let Some(a) = verdict {
                trial.f_t = f;
                trial.armijo_step = a;
                let main = &mut newton.main;
                main.dw.copy_from_slice(&newton.soc.dw);
                main.dlam.copy_from_slice(&newton.soc.dlam);
                trial.alpha = 1.0;
                // the step w + a_soc dw_soc is already in wt: rescale so that α dw = it
                main.dw.iter_mut().for_each(|v| *v *= a_soc);
                main.dlam.iter_mut().for_each(|v| *v *= a_soc);
                return Ok(true);
            }
            for i in 0..st.m {
                ls.soc_rhs_r[i] = a_soc * ls.soc_rhs_r[i] + ls.rt[i];
            }
        }
        Ok(false)
    }
}
