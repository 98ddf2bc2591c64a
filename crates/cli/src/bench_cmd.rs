//! `stride bench`: benchmark tables (markdown) of the solvers on the pendulum-chain
//! collocation problem, of the gait NLP's derivatives, of the nominal prediction and of
//! the tracking of gait_1 (`bench_track`).

use crate::predict_cmd;
use anyhow::{bail, Context};
use clap::{Args, Subcommand};
use serde::{Deserialize, Serialize};
use std::io::Write;
use std::path::PathBuf;
use std::process::Command;
use stride_ocp::settings::ProblemSettings;
use stride_predict::predict;
use stride_solve::bench::{self as solver_bench, SolveCase};

/// The benchmarks of `stride bench`.
#[derive(Subcommand)]
pub enum BenchCommand {
    /// Interior point on the pendulum-chain collocation problem (10 links) per size,
    /// backend and Hessian: KKT factorisation and full solves.
    Solver(SolverArgs),
    /// Gradient, constraints, sparse Jacobian and Hessian of the gait NLP at the
    /// data-informed guess, with 1 and all threads.
    Derivatives(DerivativesArgs),
    /// The limited-memory KKT matrix of the gait NLP: fill, ordering, factorisation and
    /// solve times under minimum degree and under the chain dissection.
    Kkt(KktArgs),
    /// The nominal prediction (1.33 m/s) per backend, Hessian and initial guess: time,
    /// iterations, objective and peak memory (one child process per case).
    Predict(PredictArgs),
    /// Muscle path evaluation per pose (with wrapping) and the polynomial fit, per model,
    /// on one thread.
    Geometry(crate::bench_geometry::GeometryArgs),
    /// The paper's tracking of trial gait_1 with the contact calibration, per Hessian, on
    /// one thread: time, iterations and peak memory (one child process per case).
    Track(crate::bench_track::TrackBenchArgs),
    /// Solve one prediction case and print its measurements as one JSON line (used by
    /// `stride bench predict`).
    #[command(hide = true)]
    PredictOne(PredictOneArgs),
    /// Solve one tracking case and print its measurements as one JSON line (used by
    /// `stride bench track`).
    #[command(hide = true)]
    TrackOne(crate::bench_track::TrackOneArgs),
}

/// Arguments of `stride bench solver`.
#[derive(Args)]
pub struct SolverArgs {
    /// Mesh intervals of the chain, comma separated (110 variables per interval).
    #[arg(long, value_delimiter = ',', default_value = "25,100,250,545")]
    pub sizes: Vec<usize>,
    /// Solver backend: ipm, ipopt (needs the `ipopt` feature) or all.
    #[arg(long, default_value = "ipm")]
    pub backend: String,
    /// Hessian modes, comma separated: exact, limited-memory.
    #[arg(long, value_delimiter = ',', default_value = "exact,limited-memory")]
    pub hessian: Vec<String>,
    /// Wall-time limit per solve [s].
    #[arg(long, default_value_t = 120.0)]
    pub time_limit: f64,
}

/// Arguments of `stride bench derivatives`.
#[derive(Args)]
pub struct DerivativesArgs {
    /// Mesh intervals (3 collocation points each).
    #[arg(long, default_value_t = 50)]
    pub mesh: usize,
    /// Repetitions per evaluation (the median is reported).
    #[arg(long, default_value_t = 10)]
    pub reps: usize,
    /// Threads of the parallel run (default: all available cores).
    #[arg(long)]
    pub threads: Option<usize>,
}

/// Arguments of `stride bench kkt`.
#[derive(Args)]
pub struct KktArgs {
    /// Mesh intervals (3 collocation points each).
    #[arg(long, default_value_t = 50)]
    pub mesh: usize,
    /// Repetitions per factorisation (the median is reported).
    #[arg(long, default_value_t = 3)]
    pub reps: usize,
    /// Model: a shipped model's name or an `.osim` file (as `stride predict --model`), with
    /// its settings file's problem defaults [default: the built-in model].
    #[arg(long)]
    pub model: Option<PathBuf>,
}

/// Arguments of `stride bench predict`.
#[derive(Args)]
pub struct PredictArgs {
    /// Mesh intervals.
    #[arg(long, default_value_t = 50)]
    pub mesh: usize,
    /// Solver backend: ipm, ipopt (needs the `ipopt` feature) or all.
    #[arg(long, default_value = "ipm")]
    pub backend: String,
    /// Hessian modes, comma separated: hybrid (the default of `stride predict`), exact,
    /// limited-memory.
    #[arg(
        long,
        value_delimiter = ',',
        default_value = "hybrid,exact,limited-memory"
    )]
    pub hessian: Vec<String>,
    /// Initial guesses, comma separated: data-informed-walking, quasi-random, data-informed-running.
    #[arg(
        long,
        value_delimiter = ',',
        default_value = "data-informed-walking,quasi-random"
    )]
    pub guess: Vec<String>,
    /// Iteration limit per solve.
    #[arg(long, default_value_t = 3000)]
    pub max_iter: usize,
    /// Wall-time limit per solve [s] (default: 1800, as `stride predict`).
    #[arg(long)]
    pub time_limit: Option<f64>,
    /// Coarse mesh of the presolve (as `stride predict --presolve-mesh`; default 10 below
    /// finer meshes, 0: none).
    #[arg(long)]
    pub presolve_mesh: Option<usize>,
    /// Model: a shipped model's name or an `.osim` file (as `stride predict --model`)
    /// [default: the built-in model].
    #[arg(long)]
    pub model: Option<PathBuf>,
    /// Prediction file whose `[problem]` settings (and `model`) are used (as `stride
    /// predict --config`); `--mesh` overrides its mesh.
    #[arg(long)]
    pub config: Option<PathBuf>,
}

/// Arguments of the hidden `stride bench predict-one`.
#[derive(Args)]
pub struct PredictOneArgs {
    /// Mesh intervals.
    #[arg(long)]
    pub mesh: usize,
    /// Solver backend: ipm or ipopt.
    #[arg(long)]
    pub backend: String,
    /// Hessian mode: exact, limited-memory or hybrid.
    #[arg(long)]
    pub hessian: String,
    /// Initial guess.
    #[arg(long)]
    pub guess: String,
    /// Iteration limit.
    #[arg(long)]
    pub max_iter: usize,
    /// Wall-time limit [s].
    #[arg(long)]
    pub time_limit: Option<f64>,
    /// Coarse mesh of the presolve.
    #[arg(long)]
    pub presolve_mesh: Option<usize>,
    /// Model name or file.
    #[arg(long)]
    pub model: Option<PathBuf>,
    /// Prediction file of the problem settings.
    #[arg(long)]
    pub config: Option<PathBuf>,
}

/// Measurements of one prediction case (the JSON line of `stride bench predict-one`).
#[derive(Serialize, Deserialize, Debug, Clone)]
pub struct CaseReport {
    /// Solver status.
    pub status: String,
    /// Iterations performed.
    pub iterations: usize,
    /// Final objective: the paper's weighted effort per distance travelled.
    pub objective: f64,
    /// Final constraint violation (max-norm, scaled NLP units).
    pub constraint_violation: f64,
    /// Wall time of the solve [s].
    pub time_total_s: f64,
    /// Time in NLP function evaluations [s].
    pub time_evaluations_s: f64,
    /// Time in the KKT linear solver [s] (None: the backend does not report it).
    pub time_linear_solver_s: Option<f64>,
    /// Time in the numeric KKT factorisations [s] (None: not reported).
    #[serde(default)]
    pub time_factorisation_s: Option<f64>,
    /// Time in the triangular solves with the KKT factor [s] (None: not reported).
    #[serde(default)]
    pub time_solves_s: Option<f64>,
    /// Resident-set high-water mark of the process [KiB] (None: not on Linux).
    pub peak_rss_kib: Option<u64>,
    /// Coarse solve before the solve above: mesh intervals, iterations and wall time [s]
    /// (None: no presolve).
    #[serde(default)]
    pub presolve: Option<(usize, usize, f64)>,
}

/// Run `stride bench ...`.
pub fn run(cmd: BenchCommand) -> anyhow::Result<()> {
    match cmd {
        BenchCommand::Solver(a) => solver(a),
        BenchCommand::Derivatives(a) => derivatives(a),
        BenchCommand::Kkt(a) => kkt(a),
        BenchCommand::Predict(a) => predict_grid(a),
        BenchCommand::Geometry(a) => crate::bench_geometry::run(a),
        BenchCommand::Track(a) => crate::bench_track::run(a),
        BenchCommand::PredictOne(a) => predict_one(a),
        BenchCommand::TrackOne(a) => crate::bench_track::run_one(a),
    }
}

/// The backends a `--backend` choice stands for; `all` without the ipopt feature is ipm
/// only, with a note printed.
fn backends(choice: &str) -> anyhow::Result<Vec<&'static str>> {
    match choice.trim() {
        "ipm" => Ok(vec!["ipm"]),
        "ipopt" => {
            predict_cmd::backend("ipopt")?;
            Ok(vec!["ipopt"])
        }
        "all" if cfg!(feature = "ipopt") => Ok(vec!["ipm", "ipopt"]),
        "all" => {
            println!(
                "> note: this build has no IPOPT backend (build with `--features ipopt`); \
                 `all` runs ipm only.\n"
            );
            Ok(vec!["ipm"])
        }
        other => bail!("unknown backend `{other}` (ipm, ipopt, all)"),
    }
}

/// Settings of the nominal problem (1.33 m/s) with `mesh` intervals, checked.
fn nominal_settings(mesh: usize) -> anyhow::Result<ProblemSettings> {
    let settings = ProblemSettings {
        mesh_intervals: mesh,
        ..Default::default()
    };
    settings
        .validate()
        .with_context(|| format!("--mesh {mesh}"))?;
    Ok(settings)
}

fn solver(a: SolverArgs) -> anyhow::Result<()> {
    solver_bench::check_intervals(&a.sizes)?;
    let cases = a
        .hessian
        .iter()
        .map(|h| SolveCase::parse(h))
        .collect::<Result<Vec<_>, _>>()?;
    if cases.is_empty() {
        bail!("no hessian given");
    }
    let time_limit = Some(predict_cmd::check_time_limit(a.time_limit)?);
    let solvers = backends(&a.backend)?
        .into_iter()
        .map(predict_cmd::backend)
        .collect::<Result<Vec<_>, _>>()?;
    let mut rows = Vec::new();
    for &n in &a.sizes {
        rows.push(solver_bench::factorisation(n)?);
    }
    println!("{}", solver_bench::factorisation_table(&rows));
    println!("{}\n", solver_bench::solve_heading(time_limit));
    print!("{}", solver_bench::solve_table_header());
    for &n in &a.sizes {
        for s in &solvers {
            for case in &cases {
                let r = solver_bench::solve(n, s.as_ref(), case, time_limit)?;
                println!("{}", solver_bench::solve_row(&r));
                std::io::stdout().flush()?;
            }
        }
    }
    Ok(())
}

fn derivatives(a: DerivativesArgs) -> anyhow::Result<()> {
    let settings = nominal_settings(a.mesh)?;
    if a.reps == 0 {
        bail!("--reps 0: at least one repetition is needed");
    }
    let all = match a.threads {
        Some(0) => bail!("--threads 0: at least one thread is needed"),
        Some(t) => t,
        None => std::thread::available_parallelism().map_or(1, |n| n.get()),
    };
    let threads: Vec<usize> = if all == 1 { vec![1] } else { vec![1, all] };
    let model = stride_model::default_model::default_model();
    let b = crate::bench_nlp::derivatives(&model, &settings, a.reps, &threads)?;
    print!("{}", crate::bench_nlp::derivatives_table(&b));
    Ok(())
}

fn kkt(a: KktArgs) -> anyhow::Result<()> {
    if a.reps == 0 {
        bail!("--reps 0: at least one repetition is needed");
    }
    let (model, settings) = match a.model {
        None => (
            stride_model::default_model::default_model(),
            nominal_settings(a.mesh)?,
        ),
        Some(m) => {
            let (path, settings) = predict_cmd::config_problem(None, Some(m), a.mesh)?;
            let model = crate::model_load::load_model(path.as_deref(), None, None, true)?;
            (model, settings)
        }
    };
    let b = crate::bench_nlp::kkt(&model, &settings, a.reps)?;
    print!("{}", crate::bench_nlp::kkt_table(&b));
    Ok(())
}

/// One case of the prediction grid.
struct Case {
    backend: &'static str,
    hessian: String,
    guess: String,
}

fn predict_grid(a: PredictArgs) -> anyhow::Result<()> {
    let presolve = predict::presolve_for(a.presolve_mesh, &nominal_settings(a.mesh)?)?;
    for h in &a.hessian {
        predict_cmd::parse_hessian(Some(h), "ipm")?;
    }
    for g in &a.guess {
        predict_cmd::parse_guess(g)?;
    }
    if a.hessian.is_empty() || a.guess.is_empty() {
        bail!("no hessian or no initial guess given");
    }
    if a.max_iter == 0 {
        bail!("--max-iter 0: at least one iteration is needed");
    }
    if let Some(t) = a.time_limit {
        predict_cmd::check_time_limit(t)?;
    }
    let backends = backends(&a.backend)?;
    let mut cases = Vec::new();
    for &backend in &backends {
        for h in &a.hessian {
            if predict_cmd::parse_hessian(Some(h), backend).is_err() {
                println!(
                    "> note: hessian `{h}` is not available with backend `{backend}`: skipped"
                );
                continue;
            }
            for g in &a.guess {
                cases.push(Case {
                    backend,
                    hessian: h.trim().to_string(),
                    guess: g.trim().to_string(),
                });
            }
        }
    }
    let exe = std::env::current_exe().context("locating the stride executable")?;
    println!(
        "## Prediction of {} ({} mesh intervals, {}, tol 1e-4, adaptive μ, max {} iterations, {} s limit); \
         one child process per case, one thread (evaluations and linear algebra)\n",
        match (&a.model, &a.config) {
            (Some(m), _) => m.display().to_string(),
            (None, Some(c)) => format!("the model and problem of {}", c.display()),
            (None, None) => "the built-in model, 1.33 m/s".into(),
        },
        a.mesh,
        presolve.map_or("no presolve".into(), |p| format!(
            "presolved on {} intervals (process s includes it)",
            p.mesh_intervals
        )),
        a.max_iter,
        a.time_limit.unwrap_or(predict_cmd::DEFAULT_TIME_LIMIT_S)
    );
    println!(
        "| backend | Hessian | guess | presolve iterations / s | status | iterations | objective | process s | solve s | evaluations s | solver s | of which linear s | factorisations s | solves s | peak RSS MiB |"
    );
    println!("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|");
    std::io::stdout().flush()?;
    for c in &cases {
        let mut cmd = Command::new(&exe);
        cmd.args(["bench", "predict-one", "--mesh", &a.mesh.to_string()])
            .args(["--backend", c.backend, "--hessian", &c.hessian])
            .args(["--guess", &c.guess, "--max-iter", &a.max_iter.to_string()]);
        if let Some(t) = a.time_limit {
            cmd.args(["--time-limit", &t.to_string()]);
        }
        cmd.args([
            "--presolve-mesh",
            &presolve.map_or(0, |p| p.mesh_intervals).to_string(),
        ]);
        if let Some(m) = &a.model {
            cmd.arg("--model").arg(m);
        }
        if let Some(c) = &a.config {
            cmd.arg("--config").arg(c);
        }
        let (report, process_s) = crate::bench_child::run_child::<CaseReport>(&mut cmd)?;
        let lead = format!("| {} | {} | {} |", c.backend, c.hessian, c.guess);
        match report {
            Ok(r) => {
                let f2 = |v: f64| format!("{v:.2}");
                println!(
                    "{lead} {} | {} | {} | {:.6} | {} | {} | {} | {} | {} | {} | {} | {} |",
                    r.presolve
                        .map_or("none".into(), |(_, it, s)| format!("{it} / {s:.2}")),
                    r.status,
                    r.iterations,
                    r.objective,
                    f2(process_s),
                    f2(r.time_total_s),
                    f2(r.time_evaluations_s),
                    f2(r.time_total_s - r.time_evaluations_s),
                    r.time_linear_solver_s.map_or("n/a".into(), f2),
                    r.time_factorisation_s.map_or("n/a".into(), f2),
                    r.time_solves_s.map_or("n/a".into(), f2),
                    r.peak_rss_kib
                        .map_or("n/a".into(), |k| format!("{:.0}", k as f64 / 1024.0)),
                );
            }
            Err(why) => println!("{lead} | {why} | | | {process_s:.2} | | | | | | | |"),
        }
        std::io::stdout().flush()?;
    }
    Ok(())
}

fn predict_one(a: PredictOneArgs) -> anyhow::Result<()> {
    let (model_path, settings) = predict_cmd::config_problem(a.config.as_deref(), a.model, a.mesh)?;
    let solver = predict_cmd::backend(&a.backend)?;
    let guess = predict_cmd::parse_guess(&a.guess)?;
    let hessian = predict_cmd::parse_hessian(Some(&a.hessian), &a.backend)?;
    let options =
        predict_cmd::prediction_options(None, Some(a.max_iter), hessian, a.time_limit, None)?;
    let model = crate::model_load::load_model(model_path.as_deref(), None, None, true)?;
    let presolve = predict::presolve_for(a.presolve_mesh, &settings)?;
    let (_, solved) = predict::solve_guesses(
        &model,
        &settings,
        &[guess],
        presolve,
        solver.as_ref(),
        &options,
        &|_, _| {},
    )?;
    let s = solved.first().context("no solve result")?;
    let r = &s.result;
    let report = CaseReport {
        status: s.report.status.clone(),
        iterations: s.report.iterations,
        objective: s.report.objective,
        constraint_violation: s.report.constraint_violation,
        time_total_s: s.report.time_total_s,
        time_evaluations_s: s.report.time_evaluations_s,
        time_linear_solver_s: r.reported_linear_solver_time().map(|d| d.as_secs_f64()),
        time_factorisation_s: s.report.time_factorisation_s,
        time_solves_s: s.report.time_solves_s,
        peak_rss_kib: crate::bench_child::peak_rss_kib(),
        presolve: s
            .report
            .presolve
            .as_ref()
            .map(|p| (p.mesh_intervals, p.iterations, p.time_total_s)),
    };
    println!("{}", serde_json::to_string(&report)?);
    Ok(())
}
