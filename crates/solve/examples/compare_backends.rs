//! Compares every solver backend compiled in (stride's IPM, ripopt, system IPOPT) on the same
//! NLPs in the same run: status, iterations, wall time, time per iteration, share of time in
//! problem evaluations, final objective and constraint violation. Prints a Markdown table.
//!
//! ```text
//! cargo run --release -p stride-solve --features ripopt,ipopt --example compare_backends -- \
//!     [--intervals 25,100,400] [--links 3] [--lbfgs] [--tol 1e-8] [--time-limit 600] [--only NAME]
//! ```

use std::time::Duration;

use stride_solve::backends;
use stride_solve::ipm::InteriorPoint;
use stride_solve::nlp::Nlp;
use stride_solve::problems::{
    Hs006, Hs021, Hs035, Hs071, InfeasibleDisk, PendulumChain, RosenbrockDisk,
};
use stride_solve::solver::{ControlFlow, HessianMode, IterationRecord, Solver, SolverOptions};

/// Command-line settings of the comparison.
struct Args {
    intervals: Vec<usize>,
    links: usize,
    lbfgs: bool,
    tol: f64,
    time_limit: f64,
    only: Option<String>,
    classic: bool,
}

fn parse_args() -> Result<Args, String> {
    let mut a = Args {
        intervals: vec![25, 100, 400],
        links: 3,
        lbfgs: false,
        tol: 1e-8,
        time_limit: 600.0,
        only: None,
        classic: true,
    };
    let mut it = std::env::args().skip(1);
    while let Some(flag) = it.next() {
        let mut value = || it.next().ok_or(format!("{flag} needs a value"));
        match flag.as_str() {
            "--intervals" => {
                a.intervals = value()?
                    .split(',')
                    .map(|s| {
                        s.trim()
                            .parse()
                            .map_err(|e| format!("--intervals {s}: {e}"))
                    })
                    .collect::<Result<_, _>>()?
            }
            "--links" => a.links = value()?.parse().map_err(|e| format!("--links: {e}"))?,
            "--tol" => a.tol = value()?.parse().map_err(|e| format!("--tol: {e}"))?,
            "--time-limit" => {
                a.time_limit = value()?.parse().map_err(|e| format!("--time-limit: {e}"))?
            }
            "--only" => a.only = Some(value()?),
            "--lbfgs" => a.lbfgs = true,
            "--no-classic" => a.classic = false,
            other => return Err(format!("unknown argument {other}")),
        }
    }
    Ok(a)
}

fn main() {
    let args = match parse_args() {
        Ok(a) => a,
        Err(e) => {
            eprintln!("compare_backends: {e}");
            std::process::exit(2);
        }
    };
    let mut all: Vec<Box<dyn Solver>> = vec![Box::new(InteriorPoint::new())];
    all.extend(backends::available());
    let solvers: Vec<Box<dyn Solver>> = all
        .into_iter()
        .filter(|s| args.only.as_deref().is_none_or(|o| o == s.name()))
        .collect();
    if solvers.is_empty() {
        eprintln!("no backend named {:?}", args.only);
        std::process::exit(2);
    }
    let options = SolverOptions {
        tol: args.tol,
        hessian: if args.lbfgs {
            HessianMode::LimitedMemory { history: 6 }
        } else {
            HessianMode::Exact
        },
        time_limit: Some(Duration::from_secs_f64(args.time_limit)),
        ..SolverOptions::default()
    };
    let mut problems: Vec<(String, Box<dyn Nlp>, Option<f64>)> = Vec::new();
    if args.classic {
        problems.push(("HS071".into(), Box::new(Hs071), Some(Hs071::F_OPT)));
        problems.push(("HS035".into(), Box::new(Hs035), Some(Hs035::F_OPT)));
        problems.push(("HS021".into(), Box::new(Hs021), Some(Hs021::F_OPT)));
        problems.push(("HS006".into(), Box::new(Hs006), Some(Hs006::F_OPT)));
        problems.push((
            "RosenbrockDisk".into(),
            Box::new(RosenbrockDisk),
            Some(RosenbrockDisk::F_OPT),
        ));
        problems.push(("InfeasibleDisk".into(), Box::new(InfeasibleDisk), None));
    }
    for &n in &args.intervals {
        let p = PendulumChain::new(args.links, n);
        problems.push((
            format!("PendulumChain K={} N={n}", args.links),
            Box::new(p),
            None,
        ));
    }
    println!(
        "Hessian: {}, tol {:e}, time limit {} s",
        if args.lbfgs { "L-BFGS(6)" } else { "exact" },
        args.tol,
        args.time_limit
    );
    println!("| problem | n | m | backend | status | iter | wall s | ms/iter | eval % | objective | |f−f*| | viol |");
    println!("|---|---|---|---|---|---|---|---|---|---|---|---|");
    for (name, nlp, f_opt) in &problems {
        for s in &solvers {
            let mut obs = |_: &IterationRecord| ControlFlow::Continue(());
            match s.solve(nlp.as_ref(), &options, &mut obs) {
                Ok(r) => {
                    let wall = r.time_total.as_secs_f64();
                    let per_iter = 1e3 * wall / r.iterations.max(1) as f64;
                    let share = 100.0 * r.time_evaluations.as_secs_f64() / wall.max(1e-12);
                    let err =
                        f_opt.map_or("–".into(), |f| format!("{:.1e}", (r.objective - f).abs()));
                    println!(
                        "| {name} | {} | {} | {} | {:?} | {} | {wall:.3} | {per_iter:.2} | {share:.1} | {:.10e} | {err} | {:.1e} |",
                        nlp.n(), nlp.m(), s.name(), r.status, r.iterations, r.objective, r.constraint_violation
                    );
                }
                Err(e) => println!(
                    "| {name} | {} | {} | {} | error: {e} | | | | | | | |",
                    nlp.n(),
                    nlp.m(),
                    s.name()
                ),
            }
        }
    }
}
