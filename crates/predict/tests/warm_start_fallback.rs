//! A presolved guess whose fine solve breaks down from the coarse optimum is solved again
//! from the guess itself; a fine solve that stops at a limit is not. Checked with a
//! scripted solver that answers each solve by the kind of start it gets (warm or cold), on
//! gait1018 with 3 and 5 mesh intervals.

mod common;

use std::sync::Mutex;
use stride_model::Model;
use stride_ocp::guess::GuessKind;
use stride_ocp::problem::GaitProblem;
use stride_ocp::settings::ProblemSettings;
use stride_predict::predict::{guess_point, record_tape, solve_presolved, Solved, Stage};
use stride_solve::nlp::Nlp;
use stride_solve::observer::Observer;
use stride_solve::solver::{
    HessianMode, SolveError, SolveResult, SolveStatus, Solver, SolverOptions,
};

/// Answers the coarse solve with `MuFloor` at its starting point, a warm fine solve with
/// `warm`, a cold fine solve with `Optimal` at its starting point; records every start.
struct Scripted {
    warm: SolveStatus,
    starts: Mutex<Vec<(bool, Vec<f64>)>>,
}

impl Solver for Scripted {
    fn name(&self) -> &str {
        "scripted"
    }
    fn solve(
        &self,
        nlp: &dyn Nlp,
        options: &SolverOptions,
        _observer: &mut dyn Observer,
    ) -> Result<SolveResult, SolveError> {
        let mut x = vec![0.0; nlp.n()];
        nlp.initial_point(&mut x);
        self.starts
            .lock()
            .unwrap()
            .push((options.warm_start, x.clone()));
        let status = if options.stop_at_mu_floor {
            SolveStatus::MuFloor
        } else if options.warm_start {
            self.warm.clone()
        } else {
            SolveStatus::Optimal
        };
        let zero = std::time::Duration::ZERO;
        Ok(SolveResult {
            status,
            iterations: 7,
            objective: 1.0,
            constraint_violation: 0.0,
            dual_infeasibility: 0.0,
            lambda: vec![0.0; nlp.m()],
            z_l: vec![0.0; x.len()],
            z_u: vec![0.0; x.len()],
            x,
            time_total: zero,
            time_evaluations: zero,
            time_linear_solver: zero,
            time_symbolic: zero,
            factorizations: 0,
            time_factorisation: zero,
            solves: 0,
            time_solves: zero,
            objective_evaluations: 0,
            exact_hessian_from: None,
            log: Vec::new(),
        })
    }
}

/// Each solve's start: whether it was warm, and its starting point.
type Starts = Vec<(bool, Vec<f64>)>;

fn problem(model: &Model, mesh_intervals: usize) -> GaitProblem {
    let s = ProblemSettings {
        mesh_intervals,
        ..Default::default()
    };
    GaitProblem::new(model, &s, &stride_ocp::bounds::bounds_data(&s)).unwrap()
}

/// Runs a presolved quasi-random guess with the scripted solver; returns the guess of
/// the fine mesh, the solver's starts and the solve.
fn run(warm: SolveStatus) -> (Vec<f64>, Starts, Solved) {
    let m = common::shipped_model("gait1018");
    let (coarse, fine) = (problem(&m, 3), problem(&m, 5));
    let g = GuessKind::QuasiRandom;
    let (xc, xf) = (
        guess_point(&coarse, g).unwrap(),
        guess_point(&fine, g).unwrap(),
    );
    let solver = Scripted {
        warm,
        starts: Mutex::new(Vec::new()),
    };
    let options = SolverOptions {
        hessian: HessianMode::Hybrid { history: 6 },
        ..Default::default()
    };
    let solved = solve_presolved(
        Stage {
            problem: &coarse,
            tape: record_tape(&coarse, &xc).unwrap(),
            x0: xc,
        },
        Stage {
            problem: &fine,
            tape: record_tape(&fine, &xf).unwrap(),
            x0: xf.clone(),
        },
        g.into(),
        &solver,
        &options,
        &|_, _| {},
    )
    .unwrap();
    (xf, solver.starts.into_inner().unwrap(), solved)
}

#[test]
fn a_fine_solve_that_breaks_down_from_the_coarse_optimum_restarts_from_the_guess() {
    let (guess, starts, solved) = run(SolveStatus::Failed("KKT".into()));
    let warm: Vec<bool> = starts.iter().map(|s| s.0).collect();
    assert_eq!(warm, [false, true, false], "coarse, warm fine, cold fine");
    assert_ne!(
        starts[1].1, guess,
        "the warm start is the resampled coarse optimum"
    );
    assert_eq!(starts[2].1, guess, "the retry starts from the fine guess");
    assert_eq!(solved.result.status, SolveStatus::Optimal);
    let p = solved.report.presolve.unwrap();
    assert!(!p.used);
    let failure = p.warm_start_failure.unwrap();
    assert!(
        failure.contains("KKT") && failure.contains("7 iterations"),
        "{failure}"
    );
}

#[test]
fn a_fine_solve_stopped_at_a_limit_is_not_repeated() {
    let (_, starts, solved) = run(SolveStatus::TimeLimit);
    assert_eq!(starts.len(), 2);
    assert_eq!(solved.result.status, SolveStatus::TimeLimit);
    let p = solved.report.presolve.unwrap();
    assert!(p.used && p.warm_start_failure.is_none());
}
