//! End-to-end tests of the interior-point method against published optima and bad input.

use std::ops::ControlFlow;

use crate::ipm::InteriorPoint;
use crate::nlp::{EvalError, Nlp, NlpError, NlpFunction, Sparsity};
use crate::observer::{Diagnostic, Observer};
use crate::problems::{
    Hs006, Hs021, Hs035, Hs071, InfeasibleDisk, PendulumChain, RosenbrockDisk, WaechterBiegler,
};
use crate::solver::{
    HessianMode, IterationRecord, KktOrdering, MuGlobalisation, MuOracle, MuStrategy, SolveError,
    SolveResult, SolveStatus, Solver, SolverOptions,
};

fn run(nlp: &dyn Nlp, opts: &SolverOptions) -> SolveResult {
    InteriorPoint::new()
        .solve(nlp, opts, &mut |_: &IterationRecord| {
            ControlFlow::Continue(())
        })
        .expect("solve returned an error")
}

/// `r` converged to the published optimum `f_opt` at `x_opt`.
fn assert_published_optimum(name: &str, r: &SolveResult, f_opt: f64, x_opt: &[f64]) {
    assert!(
        r.status.is_success(),
        "{name}: status {:?} after {} iterations (f = {})",
        r.status,
        r.iterations,
        r.objective
    );
    assert!(
        (r.objective - f_opt).abs() <= 1e-6 * f_opt.abs().max(1.0),
        "{name}: f = {} vs published {f_opt}",
        r.objective
    );
    for (i, (a, b)) in r.x.iter().zip(x_opt).enumerate() {
        assert!(
            (a - b).abs() <= 1e-4 * b.abs().max(1.0),
            "{name}: x[{i}] = {a} vs {b}"
        );
    }
}

fn check(name: &str, nlp: &dyn Nlp, opts: &SolverOptions, f_opt: f64, x_opt: &[f64]) {
    let r = run(nlp, opts);
    assert_published_optimum(name, &r, f_opt, x_opt);
    assert!(
        r.constraint_violation <= 1e-6,
        "{name}: violation {}",
        r.constraint_violation
    );
    // Every iteration factorises the KKT matrix at least once; the log's per-iteration
    // counts add up to at most the total (which also has the multiplier initialisation).
    let logged: usize = r.log.iter().map(|l| l.factorisations).sum();
    assert!(
        r.log[1..].iter().all(|l| l.factorisations >= 1) && logged < r.factorizations,
        "{name}: logged factorisations {logged}, total {}",
        r.factorizations
    );
    // every iteration solves with its factor at least once; the solves' time is part of
    // the linear-algebra time, beside the factorisations'
    assert!(
        r.solves >= r.iterations && r.time_solves + r.time_factorisation <= r.time_linear_solver,
        "{name}: {} solves in {:?}, factorisations {:?}, linear algebra {:?}",
        r.solves,
        r.time_solves,
        r.time_factorisation,
        r.time_linear_solver
    );
}

fn all_options() -> Vec<(&'static str, SolverOptions)> {
    let exact = SolverOptions::default();
    let adaptive = SolverOptions {
        mu_strategy: MuStrategy::Adaptive,
        ..SolverOptions::default()
    };
    let lbfgs = SolverOptions {
        hessian: HessianMode::LimitedMemory { history: 6 },
        max_iter: 500,
        ..SolverOptions::default()
    };
    let adaptive_pd = SolverOptions {
        mu_strategy: MuStrategy::Adaptive,
        mu_globalisation: Some(MuGlobalisation::KktError),
        ..SolverOptions::default()
    };
    let lbfgs_pd = SolverOptions {
        hessian: HessianMode::LimitedMemory { history: 6 },
        max_iter: 500,
        mu_strategy: MuStrategy::Adaptive,
        mu_globalisation: Some(MuGlobalisation::KktError),
        ..SolverOptions::default()
    };
    // the watchdog after every shortened step, to exercise its full steps and returns
    let watchdog = SolverOptions {
        watchdog_trigger: 1,
        ..SolverOptions::default()
    };
    let lbfgs_watchdog = SolverOptions {
        hessian: HessianMode::LimitedMemory { history: 6 },
        max_iter: 500,
        watchdog_trigger: 1,
        ..SolverOptions::default()
    };
    let adaptive_filter = SolverOptions {
        mu_strategy: MuStrategy::Adaptive,
        mu_globalisation: Some(MuGlobalisation::ObjConstrFilter),
        ..SolverOptions::default()
    };
    let adaptive_quality = SolverOptions {
        mu_strategy: MuStrategy::Adaptive,
        mu_globalisation: Some(MuGlobalisation::ObjConstrFilter),
        mu_oracle: MuOracle::QualityFunction,
        ..SolverOptions::default()
    };
    let lbfgs_adaptive = SolverOptions {
        hessian: HessianMode::LimitedMemory { history: 6 },
        max_iter: 500,
        mu_strategy: MuStrategy::Adaptive,
        ..SolverOptions::default()
    };
    // centrality correctors on every iteration whose step is cut
    let correctors = SolverOptions {
        mu_strategy: MuStrategy::Adaptive,
        centrality_correctors: 3,
        ..SolverOptions::default()
    };
    let lbfgs_correctors = SolverOptions {
        hessian: HessianMode::LimitedMemory { history: 6 },
        max_iter: 500,
        mu_strategy: MuStrategy::Adaptive,
        centrality_correctors: 3,
        ..SolverOptions::default()
    };
    vec![
        ("exact", exact),
        ("adaptive-correctors-3", correctors),
        ("l-bfgs-correctors-3", lbfgs_correctors),
        ("l-bfgs-adaptive", lbfgs_adaptive),
        ("adaptive-quality-function", adaptive_quality),
        ("adaptive-filter", adaptive_filter),
        ("exact-watchdog-1", watchdog),
        ("l-bfgs-watchdog-1", lbfgs_watchdog),
        ("adaptive", adaptive),
        ("adaptive-pd", adaptive_pd),
        ("l-bfgs", lbfgs),
        ("l-bfgs-adaptive-pd", lbfgs_pd),
    ]
}

#[test]
fn solves_hs071_to_published_optimum() {
    for (mode, o) in all_options() {
        check(
            &format!("HS071/{mode}"),
            &Hs071,
            &o,
            Hs071::F_OPT,
            &Hs071::X_OPT,
        );
    }
}

#[test]
fn solves_rosenbrock_on_disk() {
    for (mode, o) in all_options() {
        check(
            &format!("Rosenbrock/{mode}"),
            &RosenbrockDisk,
            &o,
            RosenbrockDisk::F_OPT,
            &RosenbrockDisk::X_OPT,
        );
    }
}

#[test]
fn solves_hs035_hs021_hs006() {
    for (mode, o) in all_options() {
        check(
            &format!("HS035/{mode}"),
            &Hs035,
            &o,
            Hs035::F_OPT,
            &Hs035::X_OPT,
        );
        check(
            &format!("HS021/{mode}"),
            &Hs021,
            &o,
            Hs021::F_OPT,
            &Hs021::X_OPT,
        );
        check(
            &format!("HS006/{mode}"),
            &Hs006,
            &o,
            Hs006::F_OPT,
            &Hs006::X_OPT,
        );
    }
}

#[test]
fn restoration_solves_the_waechter_biegler_counterexample() {
    // From x₀ = (−2, 3, 1) the linearised constraints and the bounds x₂, x₃ ≥ 0 become
    // inconsistent and the filter line search fails near x₁ ≈ −1.1 (IPOPT 3.11.9 stops
    // there with "local infeasibility"); the elastic restoration steps carry the iterate on
    // to the optimum (1, 0, 0.5), f* = 1.
    for (mode, o) in all_options() {
        check(
            &format!("WB/{mode}"),
            &WaechterBiegler,
            &o,
            1.0,
            &[1.0, 0.0, 0.5],
        );
    }
}

#[test]
fn reports_infeasible_problem() {
    let r = run(&InfeasibleDisk, &SolverOptions::default());
    assert_eq!(
        r.status,
        SolveStatus::Infeasible,
        "after {} iterations",
        r.iterations
    );
    // Every point violates one of the two constraints by a clear margin.
    assert!(
        r.constraint_violation > 0.1,
        "violation {}",
        r.constraint_violation
    );
}

#[test]
fn collocation_problem_converges_and_satisfies_dynamics() {
    let p = PendulumChain::new(3, 40);
    for (mode, o) in all_options() {
        let o = SolverOptions {
            max_iter: 1000,
            ..o
        };
        let r = run(&p, &o);
        assert!(
            r.status.is_success(),
            "{mode}: {:?} after {}",
            r.status,
            r.iterations
        );
        assert!(
            r.constraint_violation < 1e-6,
            "{mode}: {}",
            r.constraint_violation
        );
        assert!(r.objective > 0.0);
    }
}

#[test]
fn chain_dissection_and_minimum_degree_reach_the_same_collocation_optimum() {
    // The ordering changes only the pivot order of the KKT factorisation.
    let p = PendulumChain::new(3, 40);
    for hessian in [
        HessianMode::Exact,
        HessianMode::LimitedMemory { history: 6 },
    ] {
        let solve = |kkt_ordering| {
            run(
                &p,
                &SolverOptions {
                    hessian,
                    kkt_ordering,
                    max_iter: 1000,
                    ..SolverOptions::default()
                },
            )
        };
        let (a, b) = (solve(KktOrdering::Auto), solve(KktOrdering::MinimumDegree));
        assert!(a.status.is_success() && b.status.is_success());
        let rel = (a.objective - b.objective).abs() / b.objective;
        assert!(
            rel < 1e-6,
            "{hessian:?}: {} vs {}",
            a.objective,
            b.objective
        );
    }
}

/// Adaptive μ, tolerance 1e-8: the options of the hybrid-Hessian tests on the pendulum chain.
fn adaptive_tight() -> SolverOptions {
    SolverOptions {
        tol: 1e-8,
        max_iter: 1000,
        mu_strategy: MuStrategy::Adaptive,
        ..SolverOptions::default()
    }
}

#[test]
fn hybrid_hessian_reaches_the_exact_hessian_optimum_in_fewer_iterations() {
    // L-BFGS until μ sits at its floor, then Newton steps with the exact Hessian.
    let p = PendulumChain::new(3, 40);
    let base = adaptive_tight();
    let exact = run(&p, &base);
    let lbfgs = SolverOptions {
        hessian: HessianMode::LimitedMemory { history: 6 },
        ..base.clone()
    };
    let plain = run(&p, &lbfgs);
    let hybrid = run(
        &p,
        &SolverOptions {
            hessian: HessianMode::Hybrid { history: 6 },
            ..lbfgs
        },
    );
    assert!(exact.status.is_success() && hybrid.status.is_success());
    let rel = (hybrid.objective - exact.objective).abs() / exact.objective;
    assert!(rel < 1e-6, "{} vs {}", hybrid.objective, exact.objective);
    assert!(
        hybrid.iterations < plain.iterations,
        "hybrid {} vs limited-memory {} iterations",
        hybrid.iterations,
        plain.iterations
    );
    // The switch is recorded: after the first iteration, before the last; never without the
    // option.
    let k = hybrid
        .exact_hessian_from
        .expect("switch iteration recorded");
    assert!(k > 0 && k < hybrid.iterations, "switched at {k}");
    assert_eq!(plain.exact_hessian_from, None);
    assert_eq!(exact.exact_hessian_from, None);
}

#[test]
fn stop_at_mu_floor_ends_where_the_exact_tail_would_start() {
    // The stop comes at the iteration where the hybrid switches to the exact Hessian, at
    // the same point, near the optimum but before converging.
    let p = PendulumChain::new(3, 40);
    let hybrid = SolverOptions {
        hessian: HessianMode::Hybrid { history: 6 },
        ..adaptive_tight()
    };
    let full = run(&p, &hybrid);
    let k = full.exact_hessian_from.expect("hybrid switches");
    for hessian in [
        HessianMode::Hybrid { history: 6 },
        HessianMode::LimitedMemory { history: 6 },
    ] {
        let stopped = run(
            &p,
            &SolverOptions {
                stop_at_mu_floor: true,
                hessian,
                ..hybrid.clone()
            },
        );
        assert_eq!(stopped.status, SolveStatus::MuFloor);
        assert!(stopped.status.is_usable_start() && !stopped.status.is_success());
        assert_eq!(stopped.iterations, k, "stopped at the switch");
        assert_eq!(stopped.exact_hessian_from, None);
        assert!(stopped.log.last().unwrap().mu <= 1e-8);
        let rel = (stopped.objective - full.objective).abs() / full.objective;
        assert!(rel < 1e-2, "{} vs {}", stopped.objective, full.objective);
    }
    // an exact-Hessian solve ignores it
    let exact = SolverOptions {
        hessian: HessianMode::Exact,
        stop_at_mu_floor: true,
        ..hybrid
    };
    assert_eq!(run(&p, &exact).status, SolveStatus::Optimal);
}

#[test]
fn collocation_cost_converges_with_mesh_refinement() {
    // Radau IIA (order 5) cost must agree closely between N = 40 and N = 80.
    let a = run(&PendulumChain::new(2, 40), &SolverOptions::default());
    let b = run(&PendulumChain::new(2, 80), &SolverOptions::default());
    assert!(a.status.is_success() && b.status.is_success());
    let rel = (a.objective - b.objective).abs() / b.objective;
    assert!(rel < 1e-3, "{} vs {} (rel {rel})", a.objective, b.objective);
}

#[test]
fn observer_can_interrupt_and_log_is_kept() {
    let mut calls = 0;
    let r = InteriorPoint::new()
        .solve(
            &Hs071,
            &SolverOptions::default(),
            &mut |rec: &IterationRecord| {
                calls += 1;
                if rec.iter >= 2 {
                    ControlFlow::Break(())
                } else {
                    ControlFlow::Continue(())
                }
            },
        )
        .unwrap();
    assert_eq!(r.status, SolveStatus::Interrupted);
    assert_eq!(calls, 3);
    assert_eq!(r.log.len(), 3);
}

#[test]
fn max_iterations_is_reported() {
    let o = SolverOptions {
        max_iter: 2,
        ..SolverOptions::default()
    };
    assert_eq!(run(&Hs071, &o).status, SolveStatus::MaxIterations);
}

/// A problem started from a given point instead of its own initial guess.
struct StartAt<'a> {
    nlp: &'a dyn Nlp,
    x0: Vec<f64>,
}

impl Nlp for StartAt<'_> {
    fn n(&self) -> usize {
        self.nlp.n()
    }
    fn m(&self) -> usize {
        self.nlp.m()
    }
    fn bounds(&self, x_l: &mut [f64], x_u: &mut [f64], g_l: &mut [f64], g_u: &mut [f64]) {
        self.nlp.bounds(x_l, x_u, g_l, g_u)
    }
    fn initial_point(&self, x: &mut [f64]) {
        x.copy_from_slice(&self.x0)
    }
    fn objective(&self, x: &[f64]) -> Result<f64, EvalError> {
        self.nlp.objective(x)
    }
    fn gradient(&self, x: &[f64], g: &mut [f64]) -> Result<(), EvalError> {
        self.nlp.gradient(x, g)
    }
    fn constraints(&self, x: &[f64], c: &mut [f64]) -> Result<(), EvalError> {
        self.nlp.constraints(x, c)
    }
    fn jacobian_structure(&self) -> Sparsity {
        self.nlp.jacobian_structure()
    }
    fn jacobian_values(&self, x: &[f64], v: &mut [f64]) -> Result<(), EvalError> {
        self.nlp.jacobian_values(x, v)
    }
    fn hessian_structure(&self) -> Sparsity {
        self.nlp.hessian_structure()
    }
    fn hessian_values(
        &self,
        x: &[f64],
        obj_factor: f64,
        lambda: &[f64],
        v: &mut [f64],
    ) -> Result<(), EvalError> {
        self.nlp.hessian_values(x, obj_factor, lambda, v)
    }
    fn blocks(&self) -> Option<crate::nlp::BlockStructure> {
        self.nlp.blocks()
    }
}

/// `opts` with a warm start from a point near the optimum.
fn warm(opts: &SolverOptions) -> SolverOptions {
    SolverOptions {
        warm_start: true,
        mu_init: 1e-6,
        bound_push: 1e-8,
        ..opts.clone()
    }
}

#[test]
fn warm_start_from_a_neighbouring_optimum_takes_fewer_iterations_to_the_same_optimum() {
    // Continuation as in a speed sweep: the optimum of one problem starts a neighbouring
    // one (here a stiffer spring between the pendulums). With the default start the
    // interior point re-centres far from that point; with a warm start (bound multipliers
    // on the central path of a small μ, variables barely pushed) it stays near it.
    assert!(InteriorPoint::new().supports_warm_start());
    let base = PendulumChain::new(4, 20);
    let stiffer = PendulumChain {
        stiffness: 0.6,
        ..base.clone()
    };
    for (name, opts) in [
        ("monotone", SolverOptions::default()),
        (
            "adaptive",
            SolverOptions {
                mu_strategy: MuStrategy::Adaptive,
                ..SolverOptions::default()
            },
        ),
    ] {
        let x0 = run(&base, &opts).x;
        let reference = run(&stiffer, &opts);
        assert!(reference.status.is_success(), "{name}");
        let start = StartAt { nlp: &stiffer, x0 };
        let cold = run(&start, &opts);
        let warm = run(&start, &warm(&opts));
        for r in [&cold, &warm] {
            assert!(r.status.is_success(), "{name}: {:?}", r.status);
            assert!(
                (r.objective - reference.objective).abs() <= 1e-6 * reference.objective.abs(),
                "{name}: f = {} vs {}",
                r.objective,
                reference.objective
            );
        }
        assert!(
            warm.iterations < cold.iterations,
            "{name}: reference {} it, from the neighbouring optimum cold {} it, warm {} it",
            reference.iterations,
            cold.iterations,
            warm.iterations
        );
    }
    // With bounds active at the optimum (HS071: x₁ = 1 at its lower bound), started at the
    // published optimum: the default start pushes x₁ into the interior and re-centres.
    let x_opt = [1.0, 4.742_999_64, 3.821_149_98, 1.379_408_29];
    let start = StartAt {
        nlp: &Hs071,
        x0: x_opt.to_vec(),
    };
    let opts = SolverOptions {
        mu_strategy: MuStrategy::Adaptive,
        ..SolverOptions::default()
    };
    let cold = run(&start, &opts);
    let warm = run(&start, &warm(&opts));
    for r in [&cold, &warm] {
        assert!(
            r.status.is_success(),
            "hs071 from its optimum: cold {} it, warm {} it",
            cold.iterations,
            warm.iterations
        );
        assert!(
            (r.objective - 17.014_017_3).abs() < 1e-6,
            "f = {}",
            r.objective
        );
    }
    assert!(warm.iterations < cold.iterations);
}

/// Counts the inertia trials of a solve and those whose factor, of the wrong inertia, was
/// kept because its Newton step was usable.
#[derive(Default)]
struct WrongInertiaKept {
    trials: usize,
    kept: usize,
}

impl Observer for WrongInertiaKept {
    fn iteration(&mut self, _: &IterationRecord) -> ControlFlow<()> {
        ControlFlow::Continue(())
    }
    fn diagnostic(&mut self, event: &Diagnostic) {
        if let Diagnostic::InertiaTrial { step_check, .. } = event {
            self.trials += 1;
            self.kept += usize::from(*step_check == Some(true));
        }
    }
}

#[test]
fn a_warm_started_exact_solve_keeps_a_wrong_inertia_for_a_usable_step() {
    // Started (warm, exact Hessian) in the Rosenbrock valley, where the Hessian is
    // indefinite, some factorisation has the wrong inertia; the inertia-free test keeps it
    // when the Newton step has positive curvature and can be taken at least half-way,
    // instead of refactorising with a larger δ_w, and the solve still reaches the
    // published optimum.
    let opts = SolverOptions {
        hessian: HessianMode::Exact,
        print_level: 3,
        ..SolverOptions::default()
    };
    let start = StartAt {
        nlp: &RosenbrockDisk,
        x0: vec![-0.5, 0.8],
    };
    let mut seen = WrongInertiaKept::default();
    let r = InteriorPoint::new()
        .solve(&start, &warm(&opts), &mut seen)
        .expect("solve returned an error");
    assert_published_optimum(
        "rosenbrock disk, warm",
        &r,
        RosenbrockDisk::F_OPT,
        &RosenbrockDisk::X_OPT,
    );
    assert!(
        seen.kept >= 1,
        "no factor kept for its curvature in {} trials: {:?}",
        seen.trials,
        r.log
            .iter()
            .map(|l| (l.regularisation, l.factorisations))
            .collect::<Vec<_>>()
    );
    // a cold exact solve does not test the curvature
    let mut cold = WrongInertiaKept::default();
    let r = InteriorPoint::new()
        .solve(&start, &opts, &mut cold)
        .expect("solve returned an error");
    assert!(r.status.is_success());
    assert_eq!(cold.kept, 0);
}

/// A wrapper that breaks one aspect of HS071.
struct Broken {
    kind: u8,
}

impl Nlp for Broken {
    fn n(&self) -> usize {
        4
    }
    fn m(&self) -> usize {
        2
    }
    fn bounds(&self, x_l: &mut [f64], x_u: &mut [f64], g_l: &mut [f64], g_u: &mut [f64]) {
        Hs071.bounds(x_l, x_u, g_l, g_u);
        if self.kind == 0 {
            x_l[2] = 6.0;
        }
    }
    fn initial_point(&self, x: &mut [f64]) {
        Hs071.initial_point(x)
    }
    fn objective(&self, x: &[f64]) -> Result<f64, EvalError> {
        if self.kind == 1 {
            return Ok(f64::NAN);
        }
        Hs071.objective(x)
    }
    fn gradient(&self, x: &[f64], g: &mut [f64]) -> Result<(), EvalError> {
        Hs071.gradient(x, g)
    }
    fn constraints(&self, x: &[f64], c: &mut [f64]) -> Result<(), EvalError> {
        Hs071.constraints(x, c)?;
        if self.kind == 4 {
            c[1] = f64::INFINITY;
        }
        Ok(())
    }
    fn jacobian_structure(&self) -> Sparsity {
        let mut s = Hs071.jacobian_structure();
        if self.kind == 2 {
            s.rows[3] = 7;
        }
        if self.kind == 3 {
            s.cols[1] = 0;
        }
        s
    }
    fn jacobian_values(&self, x: &[f64], v: &mut [f64]) -> Result<(), EvalError> {
        Hs071.jacobian_values(x, v)
    }
    fn hessian_structure(&self) -> Sparsity {
        let mut s = Hs071.hessian_structure();
        if self.kind == 5 {
            s.rows[1] = 0;
            s.cols[1] = 1;
        }
        s
    }
    fn hessian_values(
        &self,
        x: &[f64],
        of: f64,
        l: &[f64],
        v: &mut [f64],
    ) -> Result<(), EvalError> {
        Hs071.hessian_values(x, of, l, v)
    }
}

fn solve_err(kind: u8) -> SolveError {
    InteriorPoint::new()
        .solve(
            &Broken { kind },
            &SolverOptions::default(),
            &mut |_: &IterationRecord| ControlFlow::Continue(()),
        )
        .expect_err("expected an error")
}

#[test]
fn bad_problems_give_clear_errors() {
    let e = solve_err(0);
    assert!(
        matches!(
            e,
            SolveError::InvalidProblem(NlpError::InvertedBounds { index: 2, .. })
        ),
        "{e}"
    );
    assert!(e.to_string().contains("variable 2"), "{e}");
    let e = solve_err(1);
    assert!(
        matches!(
            e,
            SolveError::InitialEvaluation(EvalError::NonFinite {
                function: NlpFunction::Objective,
                ..
            })
        ),
        "{e}"
    );
    let e = solve_err(2);
    assert!(
        matches!(
            e,
            SolveError::InvalidProblem(NlpError::OutOfRange {
                entry: 3,
                row: 7,
                ..
            })
        ),
        "{e}"
    );
    let e = solve_err(3);
    assert!(
        matches!(
            e,
            SolveError::InvalidProblem(NlpError::Duplicate {
                first: 0,
                second: 1,
                ..
            })
        ),
        "{e}"
    );
    let e = solve_err(4);
    assert!(
        matches!(
            e,
            SolveError::InitialEvaluation(EvalError::NonFinite {
                function: NlpFunction::Constraints,
                index: 1,
                ..
            })
        ),
        "{e}"
    );
    let e = solve_err(5);
    assert!(
        matches!(
            e,
            SolveError::InvalidProblem(NlpError::UpperTriangle { entry: 1, .. })
        ),
        "{e}"
    );
}

#[test]
fn invalid_options_are_rejected() {
    let rejected = |o: SolverOptions| {
        InteriorPoint::new()
            .solve(&Hs071, &o, &mut |_: &IterationRecord| {
                ControlFlow::Continue(())
            })
            .unwrap_err()
    };
    let e = rejected(SolverOptions {
        tol: -1.0,
        ..SolverOptions::default()
    });
    assert!(matches!(e, SolveError::InvalidOption { name: "tol", .. }));
    for power in [0.5, 2.5, f64::NAN] {
        let e = rejected(SolverOptions {
            mu_superlinear_power: power,
            ..SolverOptions::default()
        });
        assert!(
            matches!(
                e,
                SolveError::InvalidOption {
                    name: "mu_superlinear_power",
                    ..
                }
            ),
            "{e}"
        );
    }
}
