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
#[allow(dead_code)]
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

/// `x` with mesh point N linked to mesh point 0 as the symmetry (half cycle) or
/// periodicity (full cycle) constraints link them (forward position excepted), and every
/// interval's last collocation state equal to the next mesh point's (continuity).
#[allow(dead_code)]
pub fn consistent(p: &GaitProblem, mut x: Vec<f64>) -> Vec<f64> {
    let l = &p.layout;
    let (s, g) = (&p.scaling, &p.gait);
    let half = p.is_half_cycle();
    let (first, last) = (Point::Mesh(0), Point::Mesh(l.n));
    for (i, c) in g.coordinates.iter().enumerate() {
        let (m, sign) = if half {
            (c.mirror, c.mirror_sign)
        } else {
            (i, 1.0)
        };
        if i != g.forward_translation {
            x[l.q(last, i)] = sign * x[l.q(first, m)] * s.q[m] / s.q[i];
        }
        x[l.v(last, i)] = sign * x[l.v(first, m)] * s.v[m] / s.v[i];
    }
    for m in 0..l.nm {
        let pm = if half { g.muscle_mirror[m] } else { m };
        x[l.a(last, m)] = x[l.a(first, pm)];
        x[l.f(last, m)] = x[l.f(first, pm)];
    }
    let arms = g.actuator_driven();
    for (ai, &ci) in arms.iter().enumerate() {
        let mc = if half { g.coordinates[ci].mirror } else { ci };
        let pm = arms.iter().position(|&c| c == mc).unwrap();
        x[l.arm(last, ai)] = x[l.arm(first, pm)];
    }
    for k in 0..l.n {
        for st in 0..l.n_states() {
            x[l.state(Point::Col(k, 3), st)] = x[l.state(Point::Mesh(k + 1), st)];
        }
    }
    x
}

/// The shipped model `name` with its settings file and fitted geometry applied.
#[allow(dead_code)]
pub fn shipped_model(name: &str) -> stride_model::Model {
    use stride_model::model_settings::ModelSettings;
    let s = stride_model::shipped::shipped(name).unwrap();
    let mut m = stride_model::osim::parse_osim(s.osim, s.file_name).unwrap();
    ModelSettings::parse(s.settings, name)
        .unwrap()
        .apply(&mut m, name)
        .unwrap();
    stride_geometry::GeometryFile::parse(s.geometry, name)
        .unwrap()
        .apply(&mut m)
        .unwrap();
    m
}
