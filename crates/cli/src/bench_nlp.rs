//! Timing of the derivatives and of the KKT factorisation of the transcribed gait problem (the NLP `stride predict`
//! solves): objective gradient, constraints, sparse constraint Jacobian and sparse
//! Lagrangian Hessian at the data-informed walking guess, with 1 and more threads, printed
//! as a markdown table. Behind `stride bench derivatives`; nothing here asserts on speed.
//!
//! The collocation points are evaluated in parallel on the rayon pool the call runs in, so
//! the thread count is set by running the evaluations inside a pool of that size.

use std::fmt::Write as _;
use std::time::{Duration, Instant};
use stride_model::Model;
use stride_ocp::guess::GuessKind;
use stride_ocp::settings::ProblemSettings;
use stride_ocp::tape_node::TapeNode;
use stride_ocp::transcription::Transcription;
use stride_predict::error::PredictError;
use stride_predict::predict;
use stride_solve::nlp::{EvalError, Nlp};

/// The per-call wall-clock time the Jacobian evaluation should reach (issue goal, 10 ms).
pub const JACOBIAN_GOAL: Duration = Duration::from_millis(10);

/// Why the derivative benchmark could not run.
#[derive(Debug, thiserror::Error)]
pub enum BenchError {
    /// A benchmark argument is out of range.
    #[error("{0}")]
    Argument(String),
    /// The problem could not be built.
    #[error(transparent)]
    Predict(#[from] PredictError),
    /// An NLP function failed at the guess.
    #[error("evaluation failed: {0}")]
    Eval(#[from] EvalError),
    /// The thread pool could not be created.
    #[error("thread pool: {0}")]
    Threads(String),
}

/// Median wall-clock time of one call of each derivative evaluation with a thread count.
#[derive(Debug, Clone, PartialEq)]
pub struct DerivativeTimes {
    /// Threads evaluating the collocation points.
    pub threads: usize,
    /// Objective gradient (node values and Jacobians recomputed).
    pub gradient: Duration,
    /// Constraint values (node values recomputed).
    pub constraints: Duration,
    /// Sparse constraint Jacobian (node values and Jacobians recomputed).
    pub jacobian: Duration,
    /// Sparse Lagrangian Hessian (node Hessians; node Jacobians cached from the Jacobian
    /// call at the same point).
    pub hessian: Duration,
    /// Sparse Lagrangian Hessian at a point without cached node values: its sweeps also give
    /// the node values and Jacobians (kept for the gradient and Jacobian), as in an
    /// exact-Hessian solver iteration, which asks for the Hessian first.
    pub hessian_with_jacobian: Duration,
}

/// Sizes of the NLP and derivative timings per thread count.
#[derive(Debug, Clone, PartialEq)]
pub struct DerivativeBench {
    /// Mesh intervals N.
    pub mesh_intervals: usize,
    /// Collocation points (3 per interval).
    pub nodes: usize,
    /// Number of NLP variables.
    pub n: usize,
    /// Number of NLP constraints.
    pub m: usize,
    /// Nonzeros of the constraint Jacobian.
    pub jacobian_nnz: usize,
    /// Nonzeros of the lower triangle of the Lagrangian Hessian.
    pub hessian_nnz: usize,
    /// Repetitions each time is the median of.
    pub reps: usize,
    /// Time to build the problem and record the node tape.
    pub setup: Duration,
    /// Size of the recorded node function (operations, sparse-sweep entries).
    pub tape: stride_ad::TapeStats,
    /// Timings, one entry per thread count.
    pub times: Vec<DerivativeTimes>,
}

/// Builds the gait NLP of `model` with `settings` at the data-informed walking guess and
/// times its derivatives (median of `reps` calls) for each thread count in `threads`.
pub fn derivatives(
    model: &Model,
    settings: &ProblemSettings,
    reps: usize,
    threads: &[usize],
) -> Result<DerivativeBench, BenchError> {
    if reps == 0 {
        return Err(BenchError::Argument(
            "reps 0: at least one repetition is needed".into(),
        ));
    }
    if threads.is_empty() || threads.contains(&0) {
        return Err(BenchError::Argument(
            "threads 0: at least one thread is needed".into(),
        ));
    }
    let t = Instant::now();
    let nlp = predict::transcribe(model, settings, GuessKind::DataInformedWalking)?;
    let setup = t.elapsed();
    let mut x = vec![0.0; nlp.n()];
    nlp.initial_point(&mut x);
    let times = threads
        .iter()
        .map(|&th| {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(th)
                .build()
                .map_err(|e| BenchError::Threads(e.to_string()))?;
            pool.install(|| time_calls(&nlp, &x, reps, th))
        })
        .collect::<Result<Vec<_>, _>>()?;
    Ok(DerivativeBench {
        mesh_intervals: settings.mesh_intervals,
        nodes: 3 * settings.mesh_intervals,
        n: nlp.n(),
        m: nlp.m(),
        jacobian_nnz: nlp.jacobian_structure().nnz(),
        hessian_nnz: nlp.hessian_structure().nnz(),
        reps,
        setup,
        tape: nlp.node().tape().stats(),
        times,
    })
}

/// Times the five evaluations at `x` in the current thread pool (one untimed warm-up).
fn time_calls(
    nlp: &Transcription<TapeNode>,
    x: &[f64],
    reps: usize,
    threads: usize,
) -> Result<DerivativeTimes, BenchError> {
    let (n, m) = (nlp.n(), nlp.m());
    let mut grad = vec![0.0; n];
    let mut cons = vec![0.0; m];
    let mut jac = vec![0.0; nlp.jacobian_structure().nnz()];
    let mut hess = vec![0.0; nlp.hessian_structure().nnz()];
    let lambda = vec![1.0; m];
    let mut samples: [Vec<Duration>; 5] = Default::default();
    for rep in 0..=reps {
        let timed = |f: &mut dyn FnMut() -> Result<(), EvalError>, cold: bool| {
            if cold {
                nlp.clear_cache();
            }
            let t = Instant::now();
            f().map(|_| t.elapsed())
        };
        let d = [
            timed(&mut || nlp.gradient(x, &mut grad), true)?,
            timed(&mut || nlp.constraints(x, &mut cons), true)?,
            timed(&mut || nlp.jacobian_values(x, &mut jac), true)?,
            timed(
                &mut || nlp.hessian_values(x, 1.0, &lambda, &mut hess),
                false,
            )?,
            timed(&mut || nlp.hessian_values(x, 1.0, &lambda, &mut hess), true)?,
        ];
        if rep > 0 {
            for (s, d) in samples.iter_mut().zip(d) {
                s.push(d);
            }
        }
    }
    let [g, c, j, h, hj] = samples.map(median);
    Ok(DerivativeTimes {
        threads,
        gradient: g,
        constraints: c,
        jacobian: j,
        hessian: h,
        hessian_with_jacobian: hj,
    })
}

/// Median of a non-empty list of durations (mean of the two middle ones for even counts).
pub fn median(mut v: Vec<Duration>) -> Duration {
    v.sort();
    let k = v.len() / 2;
    if v.len() % 2 == 1 {
        v[k]
    } else {
        (v[k - 1] + v[k]) / 2
    }
}

/// Markdown report: NLP sizes, then one row per evaluation with one column (ms) per
/// thread count and the Jacobian goal.
pub fn derivatives_table(b: &DerivativeBench) -> String {
    let mut s = format!(
        "## Derivatives of the gait NLP ({} mesh intervals, {} collocation points; \
         data-informed walking guess; median of {} calls)\n\n\
         n = {}, m = {}, Jacobian nnz = {}, Hessian nnz (lower triangle) = {}; \
         problem and tape built in {:.2} s\n\n\
         node tape: {} operations, {} forward-gradient entries ({} places reused by \
         liveness in the Jacobian-only sweep, which also keeps {} partials at once), {} value \
         places, {} second-order store entries (places reused by liveness)\n\n\
         | evaluation |",
        b.mesh_intervals,
        b.nodes,
        b.reps,
        b.n,
        b.m,
        b.jacobian_nnz,
        b.hessian_nnz,
        b.setup.as_secs_f64(),
        b.tape.n_ops,
        b.tape.grad_entries,
        b.tape.jacobian_grad_entries,
        b.tape.jacobian_kept_partials,
        b.tape.value_places,
        b.tape.adot_entries
    );
    for t in &b.times {
        let unit = if t.threads == 1 { "thread" } else { "threads" };
        let _ = write!(s, " {} {unit} ms |", t.threads);
    }
    s.push_str(" goal |\n|---|");
    for _ in &b.times {
        s.push_str("---|");
    }
    s.push_str("---|\n");
    let goal = format!("goal < {} ms", JACOBIAN_GOAL.as_millis());
    let column = |get: fn(&DerivativeTimes) -> Duration| -> Vec<Duration> {
        b.times.iter().map(get).collect()
    };
    let rows = [
        ("objective gradient", column(|t| t.gradient), ""),
        ("constraints", column(|t| t.constraints), ""),
        (
            "sparse Jacobian (`jacobian_values`)",
            column(|t| t.jacobian),
            goal.as_str(),
        ),
        (
            "Lagrangian Hessian (`hessian_values`, node Jacobians cached)",
            column(|t| t.hessian),
            "",
        ),
        (
            "Lagrangian Hessian, node values and Jacobians from its sweeps (cold cache, \
             as an exact-Hessian iteration asks)",
            column(|t| t.hessian_with_jacobian),
            "",
        ),
    ];
    for (label, times, note) in rows {
        let _ = write!(s, "| {label} |");
        for d in times {
            let _ = write!(s, " {:.2} |", d.as_secs_f64() * 1e3);
        }
        let _ = writeln!(s, " {note} |");
    }
    s
}

/// One fill-reducing ordering of the gait KKT matrix and what it costs.
#[derive(Debug, Clone, PartialEq)]
pub struct KktOrderingTimes {
    /// Ordering name as printed.
    pub name: &'static str,
    /// Nonzeros of the lower triangle of the KKT matrix (with or without the Hessian
    /// pattern, as the interior point assembles it for that ordering).
    pub kkt_nnz: usize,
    /// Nonzeros of the factor L.
    pub l_nnz: usize,
    /// Supernodes of the factor (columns if faer chose the simplicial factorisation).
    pub supernodes: usize,
    /// Floating-point operations of one numeric factorisation.
    pub flops: f64,
    /// Ordering and symbolic analysis (once per solve).
    pub analyse: Duration,
    /// Median numeric LDLᵀ factorisation.
    pub factor: Duration,
    /// Median solve with 1 right-hand side (one Newton direction).
    pub solve1: Duration,
    /// Median solve with 12 right-hand sides (the L-BFGS correction of history 6, once per
    /// factorisation).
    pub solve12: Duration,
}

/// Factorisation of the limited-memory KKT matrix of the gait NLP per ordering.
#[derive(Debug, Clone, PartialEq)]
pub struct KktBench {
    /// Mesh intervals N.
    pub mesh_intervals: usize,
    /// KKT dimension n + m.
    pub dim: usize,
    /// Repetitions each time is the median of.
    pub reps: usize,
    /// One row per ordering.
    pub orderings: Vec<KktOrderingTimes>,
}

/// Builds the gait NLP of `model` with `settings`, assembles the KKT matrix of the
/// limited-memory interior point at the data-informed walking guess (B₀ = I, dual
/// regularisation 1e-8) and times its ordering, factorisation and solves (median of
/// `reps`) under minimum degree and under the chain dissection of the mesh intervals.
pub fn kkt(model: &Model, settings: &ProblemSettings, reps: usize) -> Result<KktBench, BenchError> {
    use stride_solve::ipm::kkt::KktPattern;
    use stride_solve::ipm::linsys::{FaerLdlt, KktSolver};
    use stride_solve::ipm::ordering::{kkt_ordering, ordering_blocks};
    use stride_solve::nlp::Sparsity;
    use stride_solve::solver::KktOrdering;
    if reps == 0 {
        return Err(BenchError::Argument(
            "reps 0: at least one repetition is needed".into(),
        ));
    }
    let nlp = predict::transcribe(model, settings, GuessKind::DataInformedWalking)?;
    let (n, m) = (nlp.n(), nlp.m());
    let jac = nlp.jacobian_structure();
    let hess = nlp.hessian_structure();
    let mut x = vec![0.0; n];
    nlp.initial_point(&mut x);
    let mut jv = vec![0.0; jac.nnz()];
    nlp.jacobian_values(&x, &mut jv)?;
    let linear =
        |e: stride_solve::ipm::linsys::LinearSolverError| BenchError::Argument(e.to_string());
    let mut orderings = Vec::new();
    for (name, choice) in [
        (
            "minimum degree (with Hessian pattern)",
            KktOrdering::MinimumDegree,
        ),
        ("chain dissection", KktOrdering::Auto),
    ] {
        let pattern = match choice {
            KktOrdering::MinimumDegree => KktPattern::new(n, m, &jac, &hess),
            KktOrdering::Auto => KktPattern::new(n, m, &jac, &Sparsity::default()),
        };
        let mut vals = vec![0.0; pattern.nnz()];
        let zero_h = vec![0.0; hess.nnz()];
        pattern.assemble(&mut vals, &zero_h, &jv, &vec![1.0; n], &vec![1e-8; m]);
        let mut solver = FaerLdlt::new();
        let t = Instant::now();
        let blocks = ordering_blocks(&nlp, choice);
        let order = kkt_ordering(blocks.as_ref(), &hess, &pattern);
        solver
            .analyse(
                pattern.dim,
                &pattern.col_ptr,
                &pattern.row_idx,
                order.as_deref(),
            )
            .map_err(linear)?;
        let analyse = t.elapsed();
        let mut factor = Vec::new();
        let (mut solve1, mut solve12) = (Vec::new(), Vec::new());
        let mut rhs = vec![0.0; 12 * pattern.dim];
        let fill = |rhs: &mut [f64]| {
            rhs.iter_mut()
                .enumerate()
                .for_each(|(i, v)| *v = (i % 7) as f64 - 3.0)
        };
        for _ in 0..reps {
            let t = Instant::now();
            solver.factor(&vals).map_err(linear)?;
            factor.push(t.elapsed());
            fill(&mut rhs);
            let t = Instant::now();
            solver.solve(&mut rhs[..pattern.dim]).map_err(linear)?;
            solve1.push(t.elapsed());
            fill(&mut rhs);
            let t = Instant::now();
            solver.solve_many(&mut rhs, 12).map_err(linear)?;
            solve12.push(t.elapsed());
        }
        let stats = solver.factor_stats().unwrap_or((0, 0.0));
        orderings.push(KktOrderingTimes {
            name,
            kkt_nnz: pattern.nnz(),
            l_nnz: solver.factor_nnz(),
            supernodes: stats.0,
            flops: stats.1,
            analyse,
            factor: median(factor),
            solve1: median(solve1),
            solve12: median(solve12),
        });
    }
    Ok(KktBench {
        mesh_intervals: settings.mesh_intervals,
        dim: n + m,
        reps,
        orderings,
    })
}

/// Markdown report of [`kkt`]: one row per ordering.
pub fn kkt_table(b: &KktBench) -> String {
    let mut s = format!(
        "## Limited-memory KKT matrix of the gait NLP ({} mesh intervals, dimension {}; \
         faer supernodal LDLᵀ, one thread; median of {})\n\n\
         | ordering | KKT nnz | L nnz | supernodes | factorisation GFLOP | ordering + symbolic s | factorisation s | GFLOP/s | solve, 1 right-hand side s | solve, 12 right-hand sides s |\n\
         |---|---|---|---|---|---|---|---|---|---|\n",
        b.mesh_intervals, b.dim, b.reps
    );
    for o in &b.orderings {
        let _ = writeln!(
            s,
            "| {} | {} | {} | {} | {:.2} | {:.3} | {:.3} | {:.1} | {:.3} | {:.3} |",
            o.name,
            o.kkt_nnz,
            o.l_nnz,
            o.supernodes,
            o.flops * 1e-9,
            o.analyse.as_secs_f64(),
            o.factor.as_secs_f64(),
            o.flops * 1e-9 / o.factor.as_secs_f64().max(1e-12),
            o.solve1.as_secs_f64(),
            o.solve12.as_secs_f64()
        );
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn median_of_odd_and_even_counts() {
        let ms = Duration::from_millis;
        assert_eq!(median(vec![ms(3), ms(1), ms(2)]), ms(2));
        assert_eq!(median(vec![ms(4), ms(1), ms(2), ms(3)]), ms(2) + ms(1) / 2);
    }

    #[test]
    fn bad_arguments_are_rejected_before_building() {
        let model = stride_model::default_model::default_model();
        let settings = ProblemSettings::default();
        assert!(derivatives(&model, &settings, 0, &[1]).is_err());
        assert!(derivatives(&model, &settings, 1, &[0]).is_err());
        let mesh0 = ProblemSettings {
            mesh_intervals: 0,
            ..Default::default()
        };
        let e = derivatives(&model, &mesh0, 1, &[1])
            .unwrap_err()
            .to_string();
        assert!(e.contains("mesh_intervals"), "{e}");
    }
}
