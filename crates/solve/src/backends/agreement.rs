//! Cross-backend tests: system IPOPT on every shared test problem against its published
//! optimum, and against the pure-Rust solvers on the scalable collocation problem.

use crate::backends::ipopt::IpoptSolver;
use crate::backends::tests::run;
use crate::nlp::Nlp;
use crate::problems::{Hs006, Hs021, Hs035, Hs071, InfeasibleDisk, PendulumChain, RosenbrockDisk};
use crate::solver::{SolveStatus, SolverOptions};

fn check_optimum(name: &str, nlp: &dyn Nlp, f_opt: f64, x_opt: &[f64]) {
    let r = run(&IpoptSolver::default(), nlp, &SolverOptions::default());
    assert_eq!(r.status, SolveStatus::Optimal, "{name}");
    assert!(
        (r.objective - f_opt).abs() < 1e-6 * f_opt.abs().max(1.0),
        "{name}: f = {} vs {f_opt}",
        r.objective
    );
    for (a, b) in r.x.iter().zip(x_opt) {
        assert!((a - b).abs() < 1e-5, "{name}: x = {:?} vs {x_opt:?}", r.x);
    }
    assert!(r.constraint_violation < 1e-6, "{name}");
    assert!(
        r.dual_infeasibility < 1e-5,
        "{name}: {}",
        r.dual_infeasibility
    );
}

#[test]
fn ipopt_solves_every_classic_problem_to_its_published_optimum() {
    check_optimum("HS071", &Hs071, Hs071::F_OPT, &Hs071::X_OPT);
    check_optimum("HS035", &Hs035, Hs035::F_OPT, &Hs035::X_OPT);
    check_optimum("HS021", &Hs021, Hs021::F_OPT, &Hs021::X_OPT);
    check_optimum("HS006", &Hs006, Hs006::F_OPT, &Hs006::X_OPT);
    check_optimum(
        "RosenbrockDisk",
        &RosenbrockDisk,
        RosenbrockDisk::F_OPT,
        &RosenbrockDisk::X_OPT,
    );
}

#[test]
fn ipopt_detects_the_infeasible_problem() {
    let r = run(
        &IpoptSolver::default(),
        &InfeasibleDisk,
        &SolverOptions::default(),
    );
    assert_eq!(r.status, SolveStatus::Infeasible);
}

#[cfg(feature = "ripopt")]
#[test]
fn ipopt_and_ripopt_agree_on_collocation() {
    use crate::backends::ripopt::RipoptSolver;
    let p = PendulumChain::new(3, 40);
    let o = SolverOptions::default();
    let a = run(&IpoptSolver::default(), &p, &o);
    let b = run(&RipoptSolver::default(), &p, &o);
    assert!(a.status.is_success() && b.status.is_success());
    assert!(
        (a.objective - b.objective).abs() < 1e-6 * a.objective.abs().max(1.0),
        "ipopt {} vs ripopt {}",
        a.objective,
        b.objective
    );
}

#[test]
fn ipopt_and_stride_ipm_agree_on_collocation() {
    use crate::ipm::InteriorPoint;
    let p = PendulumChain::new(3, 40);
    let o = SolverOptions::default();
    let a = run(&IpoptSolver::default(), &p, &o);
    let b = run(&InteriorPoint::new(), &p, &o);
    assert!(a.status.is_success(), "ipopt {:?}", a.status);
    assert!(b.status.is_success(), "stride-ipm {:?}", b.status);
    assert!(
        (a.objective - b.objective).abs() < 1e-6 * a.objective.abs().max(1.0),
        "ipopt {} vs stride-ipm {}",
        a.objective,
        b.objective
    );
}
