//! The primal-dual barrier method after Wächter & Biegler 2006 as a type with one method per
//! stage; see docs/decisions/0002-solver.md.
//!
//! [`Ipm`] ([`super::workspace`], below every stage) holds the whole workspace of a solve,
//! allocated here before the first iteration: the iterate ([`super::iterate`]), the KKT
//! system and its factorisation ([`super::inertia`]), the Newton steps
//! ([`super::direction`]), the centrality correctors ([`super::correctors`]), the barrier
//! parameter ([`super::barrier`]) and the line-search state ([`super::line_search`],
//! [`super::filter`]). Each stage adds its methods to `Ipm` in its own module; this one
//! builds it and runs the iteration. One iteration:
//!
//! 1. optimality error and termination test ([`super::convergence`]);
//! 2. barrier update ([`super::barrier`]), the switch of a hybrid solve to the exact
//!    Hessian;
//! 3. factorisation with inertia correction ([`super::inertia`]);
//! 4. search direction and μ oracle ([`super::direction`]), centrality correctors;
//! 5. filter line search with second-order correction and watchdog
//!    ([`super::line_search`]), else soft or feasibility restoration
//!    ([`super::restoration`]);
//! 6. the step accepted, derivatives and the L-BFGS update ([`super::accept`]).

use std::time::Instant;

use crate::ipm::direction::{bound_multiplier_steps, usable_step};
use crate::ipm::inertia::{KktStructure, KktSystem, StepCheck};
use crate::ipm::iterate::{dual_fraction_to_boundary, Iterate};
use crate::ipm::lbfgs::Lbfgs;
use crate::ipm::line_search::Trial;
use crate::ipm::linsys::{Counted, KktSolver};
use crate::ipm::ordering::ordering_blocks;
use crate::ipm::scaled::ScaledNlp;
use crate::ipm::setup::{initial_iterate, initial_point, least_squares_multipliers, StartingPoint};
use crate::ipm::workspace::{
    iteration_capacity, Barrier, Correctors, Ipm, LineSearch, Newton, Optimality, Quasi, Stats,
};
use crate::nlp::{validate_bounds, validate_structures, Nlp};
use crate::observer::{Diagnostic, Emitter, Observer};
use crate::solver::{
    HessianMode, IterationRecord, SolveError, SolveResult, SolveStatus, SolverOptions,
};

/// Iterations with μ at its floor before the exact Hessian takes over a hybrid solve (or a
/// limited-memory solve stops, `SolverOptions::stop_at_mu_floor`).
const EXACT_TAIL_AFTER: usize = 3;
/// A warm-started solve starts the inertia correction from δ_w_last/3 after a regularised
/// iteration only while its scaled optimality error is above this: far from a solution (a
/// long descent from a poor coarse optimum) the trial with 0 fails again; near one, the
/// unregularised Newton step is what converges fast (decision 0005).
const WARM_SKIP_ZERO_ERROR: f64 = 1e-2;

/// Runs the interior-point method on `nlp` with the given KKT linear solver.
pub fn solve(
    nlp: &dyn Nlp,
    options: &SolverOptions,
    observer: &mut dyn Observer,
    linear: &mut dyn KktSolver,
) -> Result<SolveResult, SolveError> {
    let mut ipm = Ipm::new(nlp, options, observer, linear)?;
    let status = ipm.run()?;
    Ok(ipm.result(status))
}

impl<'a> Ipm<'a> {
    /// Validates the problem and options, builds the starting point, the KKT system with
    /// its symbolic analysis and every buffer of the iteration.
    pub(super) fn new(
        nlp: &'a dyn Nlp,
        o: &'a SolverOptions,
        observer: &'a mut dyn Observer,
        linear: &'a mut dyn KktSolver,
    ) -> Result<Self, SolveError> {
        let start = Instant::now();
        check_options(o)?;
        let (n, m) = (nlp.n(), nlp.m());
        let bounds = validate_bounds(nlp)?;
        let structures = validate_structures(nlp)?;
        let exact = o.hessian.starts_exact();
        let mut prob = ScaledNlp::new(nlp, structures.jacobian, structures.hessian);
        let StartingPoint {
            x0,
            xl,
            xu,
            fixed_x,
        } = initial_point(&prob, &bounds, o)?;
        if o.nlp_scaling {
            prob.compute_gradient_scaling(&x0, o.nlp_scaling_max_gradient)
                .map_err(SolveError::InitialEvaluation)?;
        }
        let mut st = initial_iterate(&mut prob, &bounds, (&x0, xl, xu), o)?;
        if exact {
            prob.hessian(&st.w[..n], 1.0, &st.lam, &mut st.hv)
                .map_err(SolveError::InitialEvaluation)?;
        }
        let structure = KktStructure {
            fixed_x,
            nonlinear: nonlinear_variables(&prob),
            jac_rows: prob.jac.rows.clone(),
            jac_cols: prob.jac.cols.clone(),
        };
        let blocks = ordering_blocks(nlp, o.kkt_ordering);
        let mut kkt = KktSystem::new(Counted::new(linear), structure, &prob, blocks, exact)?;
        least_squares_multipliers(&mut kkt, &mut st)?;
        if exact && st.lam.iter().any(|&v| v != 0.0) {
            prob.hessian(&st.w[..n], 1.0, &st.lam, &mut st.hv)
                .map_err(SolveError::InitialEvaluation)?;
        }
        let big_n = st.big_n;
        let ni = st.row_of_slack.len();
        let lbfgs = o.hessian.history().map(|h| Quasi {
            lbfgs: Lbfgs::new(h),
            prev_x: vec![0.0; n],
            prev_grad_lag: vec![0.0; n],
            tmp_n: vec![0.0; n],
            s_pair: vec![0.0; n],
            y_pair: vec![0.0; n],
        });
        let stats = Stats {
            factorizations_before: kkt.factorizations,
            ..Stats::default()
        };
        Ok(Ipm {
            o,
            start,
            prob,
            bounds,
            emitter: Emitter::new(observer, o.print_level),
            st,
            kkt,
            newton: Newton::new(big_n, m, ni),
            corr: Correctors::new(o.centrality_correctors > 0, big_n, m),
            barrier: Barrier::new(o),
            ls: LineSearch::new(big_n, m, iteration_capacity(o)),
            opt: Optimality {
                r: vec![0.0; m],
                gl: vec![0.0; big_n],
                ..Optimality::default()
            },
            lbfgs,
            exact,
            x_new: vec![0.0; n],
            stats,
            iter: 0,
            log: Vec::with_capacity(iteration_capacity(o)),
            last_rec: IterationRecord::default(),
            acceptable_count: 0,
        })
    }

    /// Iterates until a termination test holds; returns how the solve ended.
    fn run(&mut self) -> Result<SolveStatus, SolveError> {
        loop {
            if let Some(status) = self.iteration()? {
                return Ok(status);
            }
        }
    }

    /// One iteration (module docs); Some(status) when the solve ends here.
    fn iteration(&mut self) -> Result<Option<SolveStatus>, SolveError> {
        self.measure_residuals();
        self.measure_optimality();
        if let Some(status) = self.record_and_test() {
            return Ok(Some(status));
        }
        let floor = self.mu_floor();
        self.update_barrier(floor);
        if let Some(status) = self.hessian_switch(floor)? {
            return Ok(Some(status));
        }
        let Some(delta_w) = self.factorise()? else {
            let reason = "KKT matrix could not be regularised";
            return Ok(Some(SolveStatus::Failed(reason.into())));
        };
        let avg = self.st.average_complementarity();
        self.early_steps(avg)?;
        self.search_direction(floor, avg)?;
        self.centrality_correctors()?;
        let mut trial = self.line_search()?;
        let alpha_z = match self.step_or_restoration(&mut trial) {
            Ok(alpha_z) => alpha_z,
            Err(status) => return Ok(Some(status)),
        };
        if let Some(status) = self.accept_step(&trial, alpha_z) {
            return Ok(Some(status));
        }
        self.iter += 1;
        self.last_rec = IterationRecord {
            step_norm: trial.alpha * trial.dnorm,
            alpha_pr: trial.alpha,
            alpha_du: alpha_z,
            regularisation: delta_w,
            ls_trials: trial.trials,
            factorisations: self.kkt.factorizations - self.stats.factorizations_before,
            ..Default::default()
        };
        self.stats.factorizations_before = self.kkt.factorizations;
        Ok(None)
    }

    /// Residual r and Lagrangian gradient ∇L at the current iterate.
    pub(super) fn measure_residuals(&mut self) {
        let (st, s) = (&self.st, &self.kkt.structure);
        st.residual(&st.w, &st.c, &mut self.opt.r);
        st.grad_lag(&s.jac_rows, &s.jac_cols, &s.fixed_x, &mut self.opt.gl);
    }

    /// Once μ has sat at its floor for a few iterations only the quasi-Newton model is left
    /// to converge, which takes hundreds of iterations on the gait problem: a hybrid solve
    /// switches to the exact Hessian there (the KKT matrix gets the Hessian pattern and a
    /// new symbolic analysis), and with `stop_at_mu_floor` the solve ends there.
    fn hessian_switch(&mut self, floor: f64) -> Result<Option<SolveStatus>, SolveError> {
        let hybrid = matches!(self.o.hessian, HessianMode::Hybrid { .. });
        if !(hybrid || self.o.stop_at_mu_floor) || self.exact {
            return Ok(None);
        }
        let b = &mut self.barrier;
        b.floor_iters = if b.mu <= floor { b.floor_iters + 1 } else { 0 };
        if b.floor_iters < EXACT_TAIL_AFTER {
            return Ok(None);
        }
        if self.o.stop_at_mu_floor {
            return Ok(Some(SolveStatus::MuFloor));
        }
        self.exact = true;
        self.lbfgs = None;
        self.newton.drop_correction();
        self.kkt.switch_to_exact(&self.prob)?;
        let st = &mut self.st;
        if let Err(e) = self.prob.hessian(&st.w[..st.n], 1.0, &st.lam, &mut st.hv) {
            let reason = format!("Hessian evaluation failed: {e}");
            return Ok(Some(SolveStatus::Failed(reason)));
        }
        self.stats.exact_from = Some(self.iter);
        self.stats.counts_at_switch = self.kkt.linear.counts;
        self.emitter.emit(Diagnostic::ExactHessianFrom {
            iteration: self.iter,
            factor_entries: self.kkt.linear.factor_nnz(),
        });
        Ok(None)
    }

    /// Σ, D_c and the factorisation with inertia correction. The first δ_w trial is 0, as
    /// IPOPT, except after a regularised iteration in the exact-Hessian tail of a hybrid
    /// solve, and in a warm-started solve while it is far from a solution: there the trial
    /// with 0 almost always fails again, and δ_w_last/3 is tried first (decisions 0002,
    /// 0005). Not from the start of an exact-Hessian solve: at 10 intervals that led to a
    /// higher local optimum. A warm-started exact solve also keeps a factor of the wrong
    /// inertia when its Newton step has positive curvature and can be taken at least
    /// half-way (the inertia-free test of Chiang & Zavala, decision 0005). Returns δ_w, or
    /// None when the matrix cannot be regularised.
    fn factorise(&mut self) -> Result<Option<f64>, SolveError> {
        self.kkt.set_barrier_terms(&self.st);
        let b0 = self.lbfgs.as_ref().map_or(0.0, |q| q.lbfgs.sigma);
        let inertia_free = self.o.warm_start && self.exact;
        let skip_zero = self.stats.exact_from.is_some()
            || (self.o.warm_start && self.opt.err0 > WARM_SKIP_ZERO_ERROR);
        let delta_w = self.kkt.first_delta_w(skip_zero);
        let mu = if self.barrier.adaptive {
            0.0
        } else {
            self.barrier.mu
        };
        let (r, newton) = (&self.opt.r, &mut self.newton);
        let mut usable = |kkt: &mut KktSystem, st: &Iterate| usable_step(kkt, st, mu, r, newton);
        let check: Option<StepCheck> = if inertia_free {
            Some(&mut usable)
        } else {
            None
        };
        let (st, em) = (&self.st, &mut self.emitter);
        self.kkt
            .factor_with_inertia_correction(st, b0, delta_w, check, em)
    }

    /// After the line search: the bound-multiplier steps and the dual step size, then, if
    /// no step was accepted, soft restoration, else feasibility restoration, else the
    /// shortest trial step. Returns the dual step size, or the status that ends the solve.
    fn step_or_restoration(&mut self, trial: &mut Trial) -> Result<f64, SolveStatus> {
        let (mu, tau) = (self.barrier.mu, self.barrier.tau);
        let (st, main) = (&self.st, &mut self.newton.main);
        let targets = self.corr.kept_targets();
        bound_multiplier_steps(st, mu, targets, &main.dw, &mut main.dzl, &mut main.dzu);
        let mut alpha_z = dual_fraction_to_boundary(st, &main.dzl, &main.dzu, tau);
        let mut soft_step = false;
        if !trial.accepted && self.o.soft_restoration {
            soft_step = self.soft_restoration(trial, &mut alpha_z);
            self.stats.soft_steps += usize::from(soft_step);
        }
        if soft_step || !trial.accepted {
            // soft or feasibility restoration: the watchdog starts afresh
            self.ls.watchdog = None;
            self.ls.shortened_steps = 0;
        }
        if trial.accepted {
            self.ls.failures = 0;
            return Ok(alpha_z);
        }
        self.ls.failures += 1;
        if self.barrier.adaptive {
            self.barrier.adaptive = false;
            self.barrier.mu = mu.max(self.st.average_complementarity());
        }
        if let Some(restored) = self.feasibility_restoration() {
            self.stats.restorations += 1;
            self.ls.wt.copy_from_slice(&restored.w);
            self.ls.ct.copy_from_slice(&restored.c);
            trial.f_t = restored.f;
            trial.alpha = 0.0;
            return Ok(0.0);
        }
        self.shortest_step(trial)?;
        Ok(alpha_z)
    }

    /// Restoration made no progress either: stop after 3 such failures in a row, else take
    /// the shortest trial step, reset the filter and go on.
    fn shortest_step(&mut self, trial: &mut Trial) -> Result<(), SolveStatus> {
        if self.ls.failures >= 3 {
            return Err(if self.opt.inf_pr_u > self.o.constr_viol_tol {
                SolveStatus::Infeasible
            } else {
                SolveStatus::SmallStep
            });
        }
        self.ls.filter.clear();
        let Ipm {
            st,
            prob,
            ls,
            newton,
            ..
        } = self;
        let dw = &newton.main.dw;
        match crate::ipm::iterate::evaluate_trial(
            prob,
            &st.w,
            trial.alpha,
            dw,
            &mut ls.wt,
            &mut ls.ct,
        ) {
            Ok(f) => {
                trial.f_t = f;
                Ok(())
            }
            Err(_) => Err(SolveStatus::Failed(
                "function evaluation failed along the search direction".into(),
            )),
        }
    }
}

/// Variables that appear nonlinearly (a nonzero Hessian row or column): L-BFGS works in
/// their space, as IPOPT's `hessian_approximation_space = nonlinear-variables` with the
/// list CasADi passes; linear variables get no B₀ = σI curvature.
fn nonlinear_variables(prob: &ScaledNlp) -> Vec<bool> {
    let mut nl = vec![false; prob.nlp.n()];
    for k in 0..prob.hess.nnz() {
        nl[prob.hess.rows[k]] = true;
        nl[prob.hess.cols[k]] = true;
    }
    nl
}

/// Rejects inconsistent options with the option's name.
fn check_options(o: &SolverOptions) -> Result<(), SolveError> {
    let bad = |name: &'static str, reason: &str| {
        Err(SolveError::InvalidOption {
            name,
            reason: reason.to_string(),
        })
    };
    if o.tol.is_nan() || o.tol <= 0.0 {
        return bad("tol", "must be positive");
    }
    if o.mu_init.is_nan() || o.mu_init <= 0.0 {
        return bad("mu_init", "must be positive");
    }
    if !(1.0..=2.0).contains(&o.mu_superlinear_power) {
        return bad("mu_superlinear_power", "must be in [1, 2]");
    }
    if o.mu_safeguard.is_some_and(|f| f.is_nan() || f < 0.0) {
        return bad("mu_safeguard", "must be non-negative");
    }
    if o.bound_push.is_nan() || o.bound_push <= 0.0 || o.bound_push >= 0.5 {
        return bad("bound_push", "must be in (0, 0.5)");
    }
    if o.hessian.history() == Some(0) {
        return bad("hessian", "limited-memory history must be at least 1");
    }
    Ok(())
}
