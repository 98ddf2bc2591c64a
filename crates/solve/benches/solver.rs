//! Benchmark of stride's interior-point method on the pendulum-chain collocation problem at
//! several sizes: KKT factorisation time (faer LDLᵀ), and full solves with exact (monotone
//! and adaptive μ) and limited-memory Hessians. Prints markdown tables; the measurements
//! are `stride_solve::bench` (also behind `stride bench solver`).
//! Run with `cargo bench -p stride-solve`.
//! Environment: STRIDE_BENCH_SIZES="25,100" to choose interval counts (links = 10).

use std::io::Write;
use std::time::Duration;

use stride_solve::bench::{self, SolveCase};
use stride_solve::ipm::InteriorPoint;

fn main() {
    let sizes: Vec<usize> = std::env::var("STRIDE_BENCH_SIZES")
        .ok()
        .map(|s| s.split(',').filter_map(|v| v.trim().parse().ok()).collect())
        .unwrap_or_else(|| bench::DEFAULT_INTERVALS.to_vec());
    bench::check_intervals(&sizes).expect("STRIDE_BENCH_SIZES");
    let rows: Vec<_> = sizes
        .iter()
        .map(|&n| bench::factorisation(n).expect("KKT factorisation"))
        .collect();
    println!("{}", bench::factorisation_table(&rows));
    let time_limit = Some(Duration::from_secs(120));
    println!("{}\n", bench::solve_heading(time_limit));
    print!("{}", bench::solve_table_header());
    for &n in &sizes {
        for case in [
            SolveCase::exact(),
            SolveCase::exact_adaptive(),
            SolveCase::limited_memory(),
        ] {
            let r = bench::solve(n, &InteriorPoint::new(), &case, time_limit).expect("solve");
            println!("{}", bench::solve_row(&r));
            let _ = std::io::stdout().flush();
        }
    }
}
