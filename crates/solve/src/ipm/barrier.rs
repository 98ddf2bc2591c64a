//! The barrier parameter μ: its floor, the monotone (Fiacco–McCormick) decrease and the
//! globalisation of the adaptive strategy, which switches between a free mode (μ chosen
//! every iteration by an oracle, see [`super::direction`]) and a fixed mode (monotone).
//!
//! Monotone rule (Wächter & Biegler 2006, eq. 7): once the barrier problem is solved to
//! E_μ ≤ κ_ε μ, μ ← max(μ_floor, min(κ_μ μ, μ^θ_μ)). The adaptive globalisations follow
//! IPOPT (Nocedal, Wächter & Waltz 2009): `kkt-error` needs the optimality error to fall
//! below 0.9999 × the largest of the last four free-mode references; `obj-constr-filter`
//! needs (f, θ) not dominated by a filter of the earlier free-mode iterates.

use crate::ipm::iterate::{one_norm, Iterate};
use crate::ipm::workspace::{iteration_capacity, Barrier, Ipm};
use crate::solver::{MuGlobalisation, MuStrategy, SolverOptions};

/// Barrier-subproblem tolerance factor κ_ε.
pub(super) const KAPPA_EPS: f64 = 10.0;
/// Linear μ decrease factor κ_μ.
const KAPPA_MU: f64 = 0.2;
/// Adaptive μ: reference KKT errors kept in free mode, and the reduction required.
const FREE_MODE_REFS: usize = 4;
const FREE_MODE_RED: f64 = 0.9999;
/// Adaptive μ: fixed-mode μ as a fraction of the average complementarity.
const FIXED_MU_FACTOR: f64 = 0.8;
/// Margin factor of the obj-constr-filter μ globalisation (IPOPT `filter_margin_fact`).
const MU_FILTER_MARGIN: f64 = 1e-5;
/// Largest barrier parameter of the adaptive strategy.
pub(super) const MU_MAX: f64 = 1e5;

/// Fiacco–McCormick decrease of μ: min(κ_μ μ, μ^θ_μ) with θ_μ = `power`, not below
/// `floor`.
pub(super) fn monotone_decrease(mu: f64, floor: f64, power: f64) -> f64 {
    floor.max((KAPPA_MU * mu).min(mu.powf(power)))
}

/// μ on entering the fixed mode of the adaptive strategy: a fraction of the average
/// complementarity (IPOPT `adaptive_mu_monotone_init_factor`).
pub(super) fn fixed_mode_mu(st: &Iterate, floor: f64) -> f64 {
    (FIXED_MU_FACTOR * st.average_complementarity()).clamp(floor, MU_MAX)
}

impl Barrier {
    /// The barrier state at the start of a solve with `o`.
    pub fn new(o: &SolverOptions) -> Self {
        let want_adaptive = matches!(o.mu_strategy, MuStrategy::Adaptive);
        Barrier {
            mu: o.mu_init,
            tau: 0.99,
            want_adaptive,
            adaptive: want_adaptive,
            globalisation: o.mu_globalisation_in_effect(),
            oracle: o.mu_oracle,
            free_refs: Vec::with_capacity(FREE_MODE_REFS + 1),
            mu_filter: Vec::with_capacity(iteration_capacity(o)),
            floor_iters: 0,
        }
    }

    /// Appends a free-mode reference error, keeping the last [`FREE_MODE_REFS`].
    fn push_reference(&mut self, error: f64) {
        self.free_refs.push(error);
        if self.free_refs.len() > FREE_MODE_REFS {
            self.free_refs.remove(0);
        }
    }
}

impl Ipm<'_> {
    /// The floor of μ: tol/10 in the scaled problem while the iterate is not yet primal and
    /// dual feasible (a lower μ that early makes iterates hug their bounds); once it is, low
    /// enough that the unscaled complementarity test (compl_inf_tol) can be met. With the
    /// obj-constr-filter globalisation IPOPT's fixed-mode floor min(tol,
    /// compl_inf_tol)/(κ_ε + 1), in free mode too: IPOPT lets free-mode μ fall to
    /// mu_min ≈ 1e-11, which on the gait problem made the tail alternate between free-mode
    /// steps with iterates pushed to their bounds and fixed-mode steps at the floor pulling
    /// them back (decision 0002).
    pub(super) fn mu_floor(&self) -> f64 {
        let o = self.o;
        let compl = o.tol.min(o.compl_inf_tol * self.prob.obj_scale);
        if self.barrier.globalisation == MuGlobalisation::ObjConstrFilter {
            compl / (KAPPA_EPS + 1.0)
        } else if self.opt.feasible {
            compl / 10.0
        } else {
            o.tol / 10.0
        }
    }

    /// Scaled optimality error E_μ of the barrier problem at `mu` at the current iterate.
    pub(super) fn barrier_error(&self, mu: f64) -> f64 {
        let e = &self.opt;
        (e.inf_du / e.s_d)
            .max(e.inf_pr)
            .max(self.st.complementarity(mu) / e.s_c)
    }

    /// The barrier update of one iteration: the adaptive globalisation's choice of mode,
    /// and in fixed mode the monotone decrease while the barrier problem is solved.
    pub(super) fn update_barrier(&mut self, floor: f64) {
        let b = &self.barrier;
        if b.want_adaptive && b.globalisation == MuGlobalisation::ObjConstrFilter {
            self.obj_constr_filter_update(floor);
        } else {
            self.kkt_error_update(floor);
            if !self.barrier.adaptive {
                self.monotone_update(floor);
            }
        }
    }

    /// IPOPT's default globalisation `obj-constr-filter`: an iterate makes sufficient
    /// progress when (f + margin, θ + margin) is not dominated by any (f, θ) of the earlier
    /// accepted free-mode iterates; without it the fixed mode takes over, where μ decreases
    /// once each barrier problem is solved.
    fn obj_constr_filter_update(&mut self, floor: f64) {
        let theta = one_norm(&self.opt.r);
        let margin = MU_FILTER_MARGIN * self.opt.err0.min(1.0);
        let f = self.st.f;
        let tiny_step = self.ls.tiny_step;
        let sufficient = !tiny_step
            && self
                .barrier
                .mu_filter
                .iter()
                .all(|&(fe, te)| f + margin < fe || theta + margin < te);
        let mu = self.barrier.mu;
        if sufficient {
            // stay in (or return to) free mode
            self.barrier.adaptive = true;
            self.barrier.mu_filter.push((f, theta));
        } else if self.barrier.adaptive {
            self.barrier.adaptive = false;
            self.barrier.mu = fixed_mode_mu(&self.st, floor);
        } else if self.barrier_error(mu) <= KAPPA_EPS * mu || tiny_step {
            self.barrier.mu = monotone_decrease(mu, floor, self.o.mu_superlinear_power);
        }
    }

    /// IPOPT's `kkt-error` globalisation (and the `ScaledError` variant): progress is the
    /// error (mean squared primal-dual error, IPOPT's `quality_function_pd_system`, or the
    /// scaled max-norm error) falling below 0.9999 × the largest of the last four reference
    /// errors. Free mode is left without such progress; with `kkt-error` fixed mode is left
    /// as soon as it is made again (the references are kept across the switch).
    fn kkt_error_update(&mut self, floor: f64) {
        let pd = self.barrier.globalisation == MuGlobalisation::KktError;
        let want_adaptive = self.barrier.want_adaptive;
        let pd_error = if want_adaptive && pd {
            self.st.pd_barrier_error(&self.opt.gl, &self.opt.r, 0.0)
        } else {
            self.opt.err0
        };
        let b = &mut self.barrier;
        let progress = b.free_refs.len() >= FREE_MODE_REFS
            && b.free_refs.iter().any(|&r| pd_error <= FREE_MODE_RED * r);
        if b.adaptive {
            if b.free_refs.len() >= FREE_MODE_REFS && !progress {
                b.adaptive = false;
                if !pd {
                    b.free_refs.clear();
                }
                b.mu = fixed_mode_mu(&self.st, floor);
            } else {
                b.push_reference(pd_error);
            }
        } else if pd && want_adaptive && progress && !self.opt.feasible && !self.ls.tiny_step {
            b.adaptive = true;
            b.push_reference(pd_error);
        }
    }

    /// Fixed mode: decrease μ monotonically while the barrier problem is solved to κ_ε μ
    /// (at most 20 times), or go back to free mode once it is solved (before the iterate is
    /// feasible: once primal and dual feasible, μ only decreases monotonically, as a
    /// free-mode probe there can leave the feasible region and cycle back).
    fn monotone_update(&mut self, floor: f64) {
        for _ in 0..20 {
            let mu = self.barrier.mu;
            if self.barrier_error(mu) > KAPPA_EPS * mu || mu <= floor {
                break;
            }
            if self.barrier.want_adaptive && self.ls.failures == 0 && !self.opt.feasible {
                self.barrier.adaptive = true;
                break;
            }
            self.barrier.mu = monotone_decrease(mu, floor, self.o.mu_superlinear_power);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn monotone_decrease_is_linear_then_superlinear_and_stops_at_the_floor() {
        // κ_μ μ = 0.02 < μ^1.5 = 0.0316 at μ = 0.1
        assert_eq!(monotone_decrease(0.1, 0.0, 1.5), 0.2 * 0.1);
        // μ^1.5 = 1e-6 < κ_μ μ = 2e-5 at μ = 1e-4
        assert!((monotone_decrease(1e-4, 0.0, 1.5) - 1e-6).abs() < 1e-20);
        assert_eq!(monotone_decrease(1e-4, 1e-5, 1.5), 1e-5);
        // the crossover κ_μ μ = μ^1.5 lies at μ = κ_μ² = 0.04
        let mu = 0.04;
        assert!((monotone_decrease(mu, 0.0, 1.5) - 0.2 * mu).abs() < 1e-15);
        // θ_μ = 1: min(κ_μ μ, μ) = κ_μ μ, linear at every μ
        assert!((monotone_decrease(1e-5, 0.0, 1.0) - 2e-6).abs() < 1e-20);
        assert!((monotone_decrease(1e-5, 1e-7, 1.0) - 2e-6).abs() < 1e-20);
        assert_eq!(monotone_decrease(2e-7, 1e-7, 1.0), 1e-7);
    }
}
