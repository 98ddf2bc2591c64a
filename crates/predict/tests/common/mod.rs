//! The data-informed walking guess as the kept "solution" of a prediction: a physically
//! meaningful walking cycle whose result files can be checked without a solve.

use std::time::Duration;
use stride_ocp::{
    data, experimental::Kinematics, guess::GuessKind, layout::Point, problem::GaitProblem,
    settings::ProblemSettings,
};
use stride_predict::predict;
use stride_solve::solver::{SolveResult, SolveStatus};

/// The built-in model, its problem on `mesh` intervals and the data-informed walking guess
/// reported as an optimal solve.
pub fn guess_solved(mesh: usize) -> (stride_model::Model, GaitProblem, Vec<predict::Solved>) {
    let model = stride_model::default_model::default_model();
    let settings = ProblemSettings {
        mesh_intervals: mesh,
        ..Default::default()
    };
    let walking = data::walking_half_cycle();
    let problem = GaitProblem::new(&model, &settings, &walking).unwrap();
    let kin = Kinematics::from_storage(&walking, &problem.gait, "walking").unwrap();
    let x = problem
        .initial_guess(GuessKind::DataInformedWalking, Some(&kin))
        .unwrap();
    let result = SolveResult {
        status: SolveStatus::Optimal,
        iterations: 0,
        objective: 0.0,
        constraint_violation: 0.0,
        dual_infeasibility: 0.0,
        x,
        lambda: Vec::new(),
        z_l: Vec::new(),
        z_u: Vec::new(),
        time_total: Duration::ZERO,
        time_evaluations: Duration::ZERO,
        time_linear_solver: Duration::ZERO,
        time_symbolic: Duration::ZERO,
        time_factorisation: Duration::ZERO,
        solves: 0,
        time_solves: Duration::ZERO,
        factorizations: 0,
        objective_evaluations: 0,
        exact_hessian_from: None,
        log: Vec::new(),
    };
    let solved = vec![predict::Solved {
        report: predict::GuessReport::new(GuessKind::DataInformedWalking, &result),
        result,
    }];
    (model, problem, solved)
}

/// `x` with the states at the last collocation point of each interval set to those of the
/// next mesh point (the same instant), as in any solution: the guess holds each interval's
/// states constant, so its forces at the end of an interval would act where the feet were
/// at its start.
#[allow(dead_code)]
pub fn continuous(problem: &GaitProblem, x: &mut [f64]) {
    let l = &problem.layout;
    for k in 0..l.n {
        let (c, m) = (Point::Col(k, 3), Point::Mesh(k + 1));
        for i in 0..l.nq {
            x[l.q(c, i)] = x[l.q(m, i)];
            x[l.v(c, i)] = x[l.v(m, i)];
        }
        for i in 0..l.nm {
            x[l.a(c, i)] = x[l.a(m, i)];
            x[l.f(c, i)] = x[l.f(m, i)];
        }
        for i in 0..l.na {
            x[l.arm(c, i)] = x[l.arm(m, i)];
        }
    }
}
