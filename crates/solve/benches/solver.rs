//! Benchmark of stride's interior-point method on the pendulum-chain collocation problem at
//! several sizes: KKT factorisation time (faer LDLᵀ), and full solves with exact and
//! limited-memory Hessians. Prints a table. Run with `cargo bench -p stride-solve`.
//! Environment: STRIDE_BENCH_SIZES="25,100" to choose interval counts (links = 10).

use std::ops::ControlFlow;
use std::time::{Duration, Instant};

use stride_solve::ipm::kkt::KktPattern;
use stride_solve::ipm::linsys::{FaerLdlt, KktSolver};
use stride_solve::ipm::InteriorPoint;
use stride_solve::nlp::Nlp;
use stride_solve::problems::PendulumChain;
use stride_solve::solver::{HessianMode, MuStrategy, Solver, SolverOptions};

const LINKS: usize = 10;

fn factorisation(p: &PendulumChain) -> (usize, usize, Duration, Duration) {
    let (n, m) = (p.n(), p.m());
    let jac = p.jacobian_structure();
    let hess = p.hessian_structure();
    let pattern = KktPattern::new(n, m, &jac, Some(&hess));
    let mut x = vec![0.0; n];
    p.initial_point(&mut x);
    let mut jv = vec![0.0; jac.nnz()];
    p.jacobian_values(&x, &mut jv).unwrap();
    let mut hv = vec![0.0; hess.nnz()];
    p.hessian_values(&x, 1.0, &vec![0.1; m], &mut hv).unwrap();
    let diag = vec![1.0; n];
    let dc = vec![1e-8; m];
    let mut vals = vec![0.0; pattern.nnz()];
    pattern.assemble(&mut vals, &hv, &jv, &diag, &dc);
    let mut s = FaerLdlt::new();
    let t = Instant::now();
    s.analyse(pattern.dim, &pattern.col_ptr, &pattern.row_idx)
        .unwrap();
    let t_sym = t.elapsed();
    let reps = 5;
    let t = Instant::now();
    for _ in 0..reps {
        s.factor(&vals).unwrap();
    }
    let t_num = t.elapsed() / reps;
    (pattern.nnz(), s.factor_nnz(), t_sym, t_num)
}

fn main() {
    let sizes: Vec<usize> = std::env::var("STRIDE_BENCH_SIZES")
        .ok()
        .map(|s| s.split(',').filter_map(|v| v.trim().parse().ok()).collect())
        .unwrap_or_else(|| vec![25, 100, 250, 545]);
    println!("## KKT factorisation (faer sparse LDLᵀ, AMD), pendulum chain K = {LINKS}");
    println!("| intervals | n | m | KKT nnz (lower) | L nnz | symbolic ms | numeric ms |");
    println!("|---|---|---|---|---|---|---|");
    for &nint in &sizes {
        let p = PendulumChain::new(LINKS, nint);
        let (knnz, lnnz, ts, tn) = factorisation(&p);
        println!(
            "| {nint} | {} | {} | {knnz} | {lnnz} | {:.1} | {:.2} |",
            p.n(),
            p.m(),
            ts.as_secs_f64() * 1e3,
            tn.as_secs_f64() * 1e3
        );
    }
    println!();
    println!(
        "## Full solves (tol 1e-8 default; L-BFGS history 6, max 3000 iterations, 120 s limit)"
    );
    println!("| intervals | n | Hessian | status | iterations | total s | ms/iter | eval % | linear % | factorisations | f* |");
    println!("|---|---|---|---|---|---|---|---|---|---|---|");
    for &nint in &sizes {
        let p = PendulumChain::new(LINKS, nint);
        for (label, hessian, mu_strategy) in [
            ("exact", HessianMode::Exact, MuStrategy::Monotone),
            (
                "exact, adaptive mu",
                HessianMode::Exact,
                MuStrategy::Adaptive,
            ),
            (
                "l-bfgs(6)",
                HessianMode::LimitedMemory { history: 6 },
                MuStrategy::Monotone,
            ),
        ] {
            let o = SolverOptions {
                hessian,
                mu_strategy,
                time_limit: Some(Duration::from_secs(120)),
                ..SolverOptions::default()
            };
            let r = InteriorPoint::new()
                .solve(&p, &o, &mut |_| ControlFlow::Continue(()))
                .unwrap();
            let tot = r.time_total.as_secs_f64();
            println!(
                "| {nint} | {} | {label} | {:?} | {} | {:.3} | {:.2} | {:.1} | {:.1} | {} | {:.6e} |",
                p.n(),
                r.status,
                r.iterations,
                tot,
                1e3 * tot / r.iterations.max(1) as f64,
                100.0 * r.time_evaluations.as_secs_f64() / tot,
                100.0 * r.time_linear_solver.as_secs_f64() / tot,
                r.factorizations,
                r.objective
            );
        }
    }
}
