//! Development driver: solve the nominal problem with a given mesh and guess.
//! `cargo run --release -p stride-predict --example solve_nominal -- <N> <qr|di> [exact|lbfgs] [ipm|ipopt|ripopt]`
//! Environment: `STRIDE_PRINT` (print level, default 2), `STRIDE_MAX_ITER` (default 3000),
//! `STRIDE_MU=monotone` (monotone instead of adaptive barrier update) or `STRIDE_MU=pd`
//! (adaptive with the kkt-error globalisation), `filter`, `scaled` (the other
//! globalisations; default by Hessian mode), `STRIDE_MU_SAFEGUARD` (factor;
//! default by Hessian mode), `STRIDE_KKT=ldlt|lblt`, `STRIDE_ORACLE=quality` (quality-function μ oracle),
//! `STRIDE_WATCHDOG` (shortened steps that start the watchdog, 0: off), `STRIDE_HISTORY`
//! (L-BFGS pairs, default 6), `STRIDE_EXACT_TAIL=1` (exact Hessian once μ is at its floor),
//! `STRIDE_CORRECTORS` (centrality correctors per iteration, default 0). The constraint
//! violation tolerance is 1e-6, as in `stride predict`.

use std::ops::ControlFlow;
use stride_ocp::{guess::GuessKind, settings::ProblemSettings};
use stride_solve::observer::{Diagnostic, Observer};
use stride_solve::solver::{HessianMode, IterationRecord, LinearSolver, Solver, SolverOptions};

/// Prints the iteration table (print level 2 and above) and the solver's diagnostics.
struct Printer {
    table: bool,
}

impl Observer for Printer {
    fn iteration(&mut self, record: &IterationRecord) -> ControlFlow<()> {
        if self.table {
            eprintln!("{}", record.table_line());
        }
        ControlFlow::Continue(())
    }

    fn diagnostic(&mut self, event: &Diagnostic) {
        eprintln!("{event}");
    }
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let n: usize = args.get(1).and_then(|s| s.parse().ok()).unwrap_or(50);
    let guess = match args.get(2).map(|s| s.as_str()) {
        Some("qr") => GuessKind::QuasiRandom,
        _ => GuessKind::DataInformedWalking,
    };
    let lbfgs = args.get(3).map(|s| s == "lbfgs").unwrap_or(false);
    let model = stride_model::default_model::default_model();
    let settings = ProblemSettings {
        mesh_intervals: n,
        ..Default::default()
    };
    let t0 = std::time::Instant::now();
    let tr = stride_predict::predict::transcribe(&model, &settings, guess).unwrap();
    println!("problem and tape in {:?}", t0.elapsed());
    let options = SolverOptions {
        tol: 1e-4,
        max_iter: std::env::var("STRIDE_MAX_ITER")
            .ok()
            .and_then(|v| v.parse().ok())
            .unwrap_or(3000),
        hessian: if lbfgs {
            let history = std::env::var("STRIDE_HISTORY")
                .ok()
                .and_then(|v| v.parse().ok())
                .unwrap_or(6);
            if std::env::var("STRIDE_EXACT_TAIL").as_deref() == Ok("1") {
                HessianMode::Hybrid { history }
            } else {
                HessianMode::LimitedMemory { history }
            }
        } else {
            HessianMode::Exact
        },
        print_level: std::env::var("STRIDE_PRINT")
            .ok()
            .and_then(|v| v.parse().ok())
            .unwrap_or(2),
        mu_strategy: if std::env::var("STRIDE_MU").as_deref() == Ok("monotone") {
            stride_solve::solver::MuStrategy::Monotone
        } else {
            stride_solve::solver::MuStrategy::Adaptive
        },
        mu_globalisation: match std::env::var("STRIDE_MU").as_deref() {
            Ok("pd") => Some(stride_solve::solver::MuGlobalisation::KktError),
            Ok("filter") => Some(stride_solve::solver::MuGlobalisation::ObjConstrFilter),
            Ok("scaled") => Some(stride_solve::solver::MuGlobalisation::ScaledError),
            _ => None,
        },
        mu_safeguard: std::env::var("STRIDE_MU_SAFEGUARD")
            .ok()
            .and_then(|v| v.parse().ok()),
        mu_oracle: if std::env::var("STRIDE_ORACLE").as_deref() == Ok("quality") {
            stride_solve::solver::MuOracle::QualityFunction
        } else {
            stride_solve::solver::MuOracle::Probing
        },
        watchdog_trigger: std::env::var("STRIDE_WATCHDOG")
            .ok()
            .and_then(|v| v.parse().ok())
            .unwrap_or(10),
        linear_solver: if std::env::var("STRIDE_KKT").as_deref() == Ok("lblt") {
            LinearSolver::Lblt
        } else {
            LinearSolver::Ldlt
        },
        centrality_correctors: std::env::var("STRIDE_CORRECTORS")
            .ok()
            .and_then(|v| v.parse().ok())
            .unwrap_or(0),
        constr_viol_tol: 1e-6,
        ..Default::default()
    };
    let backend = args.get(4).cloned().unwrap_or_else(|| "ipm".into());
    let solver: Box<dyn Solver> = match backend.as_str() {
        #[cfg(feature = "ipopt")]
        "ipopt" => Box::new(stride_solve::backends::ipopt::IpoptSolver::default()),
        #[cfg(feature = "ripopt")]
        "ripopt" => Box::new(stride_solve::backends::ripopt::RipoptSolver::default()),
        _ => Box::new(stride_solve::ipm::InteriorPoint::new()),
    };
    let r = solver
        .solve(
            &tr,
            &options,
            &mut Printer {
                table: options.print_level >= 2,
            },
        )
        .unwrap();
    println!(
        "status {:?} iters {} obj {} viol {:e} time {:?} (eval {:?}, linear {:?})",
        r.status,
        r.iterations,
        r.objective,
        r.constraint_violation,
        r.time_total,
        r.time_evaluations,
        r.time_linear_solver
    );
}
