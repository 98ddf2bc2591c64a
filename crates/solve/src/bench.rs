//! Solver benchmarks on the pendulum-chain collocation problem ([`PendulumChain`], 10 links):
//! the KKT factorisation (faer sparse LDLᵀ) and full solves per backend and Hessian mode,
//! printed as markdown tables.
//!
//! One source of truth for `cargo bench -p stride-solve --bench solver` and
//! `stride bench solver`; nothing here asserts on speed.

use std::fmt::Write as _;
use std::ops::ControlFlow;
use std::time::{Duration, Instant};

use thiserror::Error;

use crate::ipm::kkt::KktPattern;
use crate::ipm::linsys::{FaerLdlt, KktSolver, LinearSolverError};
use crate::ipm::ordering::{kkt_ordering, ordering_blocks};
use crate::nlp::{EvalError, Nlp};
use crate::problems::PendulumChain;
use crate::solver::IterationRecord;
use crate::solver::{
    HessianMode, KktOrdering, MuStrategy, SolveError, SolveStatus, Solver, SolverOptions,
};

/// Number of pendulums in the benchmark chain (10 links, 110 variables per mesh interval).
pub const LINKS: usize = 10;

/// Default mesh-interval counts: 25, 100, 250 and 545 intervals (2,770 to 59,970 variables).
pub const DEFAULT_INTERVALS: [usize; 4] = [25, 100, 250, 545];

/// Correction pairs kept by the limited-memory (L-BFGS) Hessian (IPOPT's default, 6).
pub const LBFGS_HISTORY: usize = 6;

/// Numeric factorisations averaged per size in the KKT factorisation benchmark.
pub const FACTOR_REPS: u32 = 5;

/// Why a benchmark could not run (bad arguments or a failure of the problem or solver).
#[derive(Debug, Error)]
pub enum BenchError {
    /// A benchmark argument is out of range or unknown.
    #[error("{0}")]
    Argument(String),
    /// A problem function failed at the benchmark point.
    #[error("evaluation failed: {0}")]
    Eval(#[from] EvalError),
    /// The KKT linear solver failed.
    #[error(transparent)]
    Linear(#[from] LinearSolverError),
    /// The solver refused the problem or its options.
    #[error(transparent)]
    Solve(#[from] SolveError),
}

/// Checks a list of mesh-interval counts: non-empty, every count at least 1 interval.
pub fn check_intervals(intervals: &[usize]) -> Result<(), BenchError> {
    if intervals.is_empty() {
        return Err(BenchError::Argument("no size given".into()));
    }
    if intervals.contains(&0) {
        return Err(BenchError::Argument(
            "size 0: a size is a number of mesh intervals and must be at least 1".into(),
        ));
    }
    Ok(())
}

/// KKT factorisation cost of one problem size (times are wall-clock).
#[derive(Debug, Clone, PartialEq)]
pub struct Factorisation {
    /// Mesh intervals N of the pendulum chain.
    pub intervals: usize,
    /// Number of NLP variables.
    pub n: usize,
    /// Number of NLP constraints.
    pub m: usize,
    /// Nonzeros of the lower triangle of the KKT matrix.
    pub kkt_nnz: usize,
    /// Nonzeros of the factor L.
    pub l_nnz: usize,
    /// Time of the symbolic analysis (the solver's ordering: chain dissection; elimination
    /// tree).
    pub symbolic: Duration,
    /// Mean time of one numeric factorisation over [`FACTOR_REPS`] repetitions.
    pub numeric: Duration,
}

/// Assembles the KKT matrix of the chain with `intervals` intervals at its initial point
/// (barrier diagonal 1, dual regularisation 1e-8, multipliers 0.1) and times its
/// symbolic analysis and numeric LDLᵀ factorisation.
pub fn factorisation(intervals: usize) -> Result<Factorisation, BenchError> {
    check_intervals(&[intervals])?;
    let p = PendulumChain::new(LINKS, intervals);
    let (n, m) = (p.n(), p.m());
    let jac = p.jacobian_structure();
    let hess = p.hessian_structure();
    let pattern = KktPattern::new(n, m, &jac, &hess);
    let mut x = vec![0.0; n];
    p.initial_point(&mut x);
    let mut jv = vec![0.0; jac.nnz()];
    p.jacobian_values(&x, &mut jv)?;
    let mut hv = vec![0.0; hess.nnz()];
    p.hessian_values(&x, 1.0, &vec![0.1; m], &mut hv)?;
    let diag = vec![1.0; n];
    let dc = vec![1e-8; m];
    let mut vals = vec![0.0; pattern.nnz()];
    pattern.assemble(&mut vals, &hv, &jv, &diag, &dc);
    let mut s = FaerLdlt::new();
    let t = Instant::now();
    let blocks = ordering_blocks(&p, KktOrdering::Auto);
    let ordering = kkt_ordering(blocks.as_ref(), &hess, &pattern);
    s.analyse(
        pattern.dim,
        &pattern.col_ptr,
        &pattern.row_idx,
        ordering.as_deref(),
    )?;
    let symbolic = t.elapsed();
    let t = Instant::now();
    for _ in 0..FACTOR_REPS {
        s.factor(&vals)?;
    }
    let numeric = t.elapsed() / FACTOR_REPS;
    Ok(Factorisation {
        intervals,
        n,
        m,
        kkt_nnz: pattern.nnz(),
        l_nnz: s.factor_nnz(),
        symbolic,
        numeric,
    })
}

/// Markdown table of KKT factorisations (times in milliseconds).
pub fn factorisation_table(rows: &[Factorisation]) -> String {
    let mut s = format!(
        "## KKT factorisation (faer sparse LDLᵀ, AMD), pendulum chain K = {LINKS}\n\n\
         | intervals | n | m | KKT nnz (lower) | L nnz | symbolic ms | numeric ms |\n\
         |---|---|---|---|---|---|---|\n"
    );
    for r in rows {
        let _ = writeln!(
            s,
            "| {} | {} | {} | {} | {} | {:.1} | {:.2} |",
            r.intervals,
            r.n,
            r.m,
            r.kkt_nnz,
            r.l_nnz,
            ms(r.symbolic),
            ms(r.numeric)
        );
    }
    s
}

/// A Hessian mode with its barrier-parameter rule, as one column of the solve benchmark.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SolveCase {
    /// Label printed in the table ("exact", "l-bfgs(6)", ...).
    pub label: &'static str,
    /// Exact second derivatives or limited-memory BFGS.
    pub hessian: HessianMode,
    /// Barrier parameter update rule.
    pub mu_strategy: MuStrategy,
}

impl SolveCase {
    /// Exact Hessian with the monotone (Fiacco–McCormick) barrier update.
    pub fn exact() -> Self {
        SolveCase {
            label: "exact",
            hessian: HessianMode::Exact,
            mu_strategy: MuStrategy::Monotone,
        }
    }

    /// Exact Hessian with the adaptive barrier update.
    pub fn exact_adaptive() -> Self {
        SolveCase {
            label: "exact, adaptive mu",
            hessian: HessianMode::Exact,
            mu_strategy: MuStrategy::Adaptive,
        }
    }

    /// L-BFGS Hessian with [`LBFGS_HISTORY`] pairs and the monotone barrier update.
    pub fn limited_memory() -> Self {
        SolveCase {
            label: "l-bfgs(6)",
            hessian: HessianMode::LimitedMemory {
                history: LBFGS_HISTORY,
            },
            mu_strategy: MuStrategy::Monotone,
        }
    }

    /// The case named `exact` or `limited-memory` on the command line.
    pub fn parse(name: &str) -> Result<Self, BenchError> {
        match name.trim() {
            "exact" => Ok(Self::exact()),
            "limited-memory" => Ok(Self::limited_memory()),
            other => Err(BenchError::Argument(format!(
                "unknown hessian `{other}` (exact, limited-memory)"
            ))),
        }
    }
}

/// The outcome and timings of one full solve of the chain (times are wall-clock).
#[derive(Debug, Clone, PartialEq)]
pub struct SolveRow {
    /// Mesh intervals N of the pendulum chain.
    pub intervals: usize,
    /// Number of NLP variables.
    pub n: usize,
    /// Solver backend name ("stride-ipm", "ipopt").
    pub backend: String,
    /// Hessian case label.
    pub case: String,
    /// How the solve ended.
    pub status: SolveStatus,
    /// Iterations performed.
    pub iterations: usize,
    /// Total solve time.
    pub total: Duration,
    /// Time in problem function evaluations (measured on stride's side for every backend).
    pub evaluations: Duration,
    /// Time in the KKT factorisations and solves (None: the backend does not report it).
    pub linear_solver: Option<Duration>,
    /// Number of KKT numeric factorisations (0 if the backend does not report them).
    pub factorizations: usize,
    /// Final objective: control effort Σ h B_j u² [N²·m²·s].
    pub objective: f64,
}

/// Solves the chain with `intervals` intervals with `solver` (default tolerance 1e-8,
/// at most 3000 iterations, wall-clock limit `time_limit`).
pub fn solve(
    intervals: usize,
    solver: &dyn Solver,
    case: &SolveCase,
    time_limit: Option<Duration>,
) -> Result<SolveRow, BenchError> {
    check_intervals(&[intervals])?;
    let p = PendulumChain::new(LINKS, intervals);
    let o = SolverOptions {
        hessian: case.hessian,
        mu_strategy: case.mu_strategy,
        time_limit,
        ..SolverOptions::default()
    };
    let r = solver.solve(&p, &o, &mut |_: &IterationRecord| ControlFlow::Continue(()))?;
    let linear_solver = r.reported_linear_solver_time();
    Ok(SolveRow {
        intervals,
        n: p.n(),
        backend: solver.name().to_string(),
        case: case.label.to_string(),
        status: r.status,
        iterations: r.iterations,
        total: r.time_total,
        evaluations: r.time_evaluations,
        linear_solver,
        factorizations: r.factorizations,
        objective: r.objective,
    })
}

/// Heading of the solve table with the settings every row shares.
pub fn solve_heading(time_limit: Option<Duration>) -> String {
    let limit = match time_limit {
        Some(t) => format!("{} s limit", t.as_secs_f64()),
        None => "no time limit".into(),
    };
    format!(
        "## Full solves, pendulum chain K = {LINKS} (tol 1e-8; L-BFGS history {LBFGS_HISTORY}; \
         max 3000 iterations; {limit})"
    )
}

/// Markdown table of full solves (total in seconds, per iteration in milliseconds, shares
/// of the total in percent, n/a where the backend does not report a figure).
pub fn solve_table(rows: &[SolveRow]) -> String {
    let mut s = String::from(
        "| intervals | n | backend | Hessian | status | iterations | total s | ms/iter | eval % | linear % | factorisations | f* |\n\
         |---|---|---|---|---|---|---|---|---|---|---|---|\n",
    );
    for r in rows {
        let _ = writeln!(s, "{}", solve_row(r));
    }
    s
}

/// One markdown row of the solve table (for printing rows as they finish).
pub fn solve_row(r: &SolveRow) -> String {
    let tot = r.total.as_secs_f64();
    let share = |d: Duration| {
        if tot > 0.0 {
            format!("{:.1}", 100.0 * d.as_secs_f64() / tot)
        } else {
            "n/a".into()
        }
    };
    let per_iter = if r.iterations > 0 {
        format!("{:.2}", 1e3 * tot / r.iterations as f64)
    } else {
        "n/a".into()
    };
    format!(
        "| {} | {} | {} | {} | {:?} | {} | {:.3} | {} | {} | {} | {} | {:.6e} |",
        r.intervals,
        r.n,
        r.backend,
        r.case,
        r.status,
        r.iterations,
        tot,
        per_iter,
        share(r.evaluations),
        r.linear_solver.map_or("n/a".into(), share),
        if r.linear_solver.is_some() {
            r.factorizations.to_string()
        } else {
            "n/a".into()
        },
        r.objective
    )
}

/// Header of the solve table (the two lines before the first row).
pub fn solve_table_header() -> String {
    solve_table(&[])
}

fn ms(d: Duration) -> f64 {
    d.as_secs_f64() * 1e3
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::ipm::InteriorPoint;

    #[test]
    fn largest_default_size_has_about_sixty_thousand_variables() {
        let n = PendulumChain::variables_for(LINKS, DEFAULT_INTERVALS[3]);
        assert!((59_000..=61_000).contains(&n), "n = {n}");
    }

    #[test]
    fn tiny_chain_solves_and_fills_both_tables() {
        let f = factorisation(5).unwrap();
        assert_eq!(f.n, PendulumChain::variables_for(LINKS, 5));
        assert!(f.l_nnz >= f.kkt_nnz);
        let table = factorisation_table(&[f]);
        assert_eq!(table.lines().filter(|l| l.starts_with("| 5 |")).count(), 1);

        let cases = [SolveCase::exact(), SolveCase::limited_memory()];
        let rows: Vec<SolveRow> = cases
            .iter()
            .map(|c| solve(5, &InteriorPoint::new(), c, Some(Duration::from_secs(60))).unwrap())
            .collect();
        assert!(rows[0].status.is_success(), "{:?}", rows[0].status);
        assert!(rows[0].linear_solver.is_some());
        let table = solve_table(&rows);
        let body: Vec<&str> = table.lines().skip(2).collect();
        assert_eq!(body.len(), 2);
        assert!(body[0].starts_with("| 5 | 570 | stride-ipm | exact |"));
        assert!(body[1].starts_with("| 5 | 570 | stride-ipm | l-bfgs(6) |"));
    }

    #[test]
    fn bad_arguments_are_rejected() {
        assert!(check_intervals(&[]).is_err());
        let e = check_intervals(&[25, 0]).unwrap_err().to_string();
        assert!(e.contains("size 0"), "{e}");
        assert!(factorisation(0).is_err());
        let e = SolveCase::parse("newton").unwrap_err().to_string();
        assert_eq!(e, "unknown hessian `newton` (exact, limited-memory)");
        assert_eq!(
            SolveCase::parse("limited-memory").unwrap(),
            SolveCase::limited_memory()
        );
    }
}
