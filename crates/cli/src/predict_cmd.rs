//! `stride predict`: predict a gait from the built-in model (or an `.osim`) and a speed.

use anyhow::{bail, Context};
use clap::Args;
use serde::Deserialize;
use std::io::Write;
use std::path::PathBuf;
use std::sync::Mutex;
use std::time::Duration;
use stride_ocp::guess::GuessKind;
use stride_ocp::predict;
use stride_ocp::settings::ProblemSettings;
use stride_solve::solver::{HessianMode, LinearSolver, MuStrategy, Solver, SolverOptions};

/// Arguments of `stride predict` (flags override the study file).
#[derive(Args)]
pub struct PredictArgs {
    /// Study file (TOML) with `[problem]`, `[solver]`, `guesses`, `output`, `model`.
    #[arg(long)]
    pub config: Option<PathBuf>,
    /// OpenSim model (default: the built-in subject model).
    #[arg(long)]
    pub model: Option<PathBuf>,
    /// Imposed average speed [m/s].
    #[arg(long, allow_hyphen_values = true)]
    pub speed: Option<f64>,
    /// Mesh intervals.
    #[arg(long)]
    pub mesh: Option<usize>,
    /// Initial guesses, comma separated: quasi-random, data-informed-walking, data-informed-running.
    #[arg(long, value_delimiter = ',')]
    pub guess: Option<Vec<String>>,
    /// Solver backend: ipm (pure Rust, default) or ipopt (needs the `ipopt` feature).
    #[arg(long)]
    pub solver: Option<String>,
    /// Hessian: hybrid (default: limited-memory until μ reaches its floor, then exact),
    /// limited-memory, or exact.
    #[arg(long)]
    pub hessian: Option<String>,
    /// Convergence tolerance.
    #[arg(long)]
    pub tol: Option<f64>,
    /// Iteration limit.
    #[arg(long)]
    pub max_iter: Option<usize>,
    /// Wall-time limit per solve [s].
    #[arg(long)]
    pub time_limit: Option<f64>,
    /// Centrality correctors per iteration (ipm only; default 2 with the hybrid Hessian,
    /// else 0).
    #[arg(long)]
    pub correctors: Option<usize>,
    /// Coarse mesh of the presolve: each guess is first solved on this many intervals and
    /// the requested mesh is solved from that optimum (default 10 when the mesh is finer;
    /// 0: solve the requested mesh directly from the guess).
    #[arg(long)]
    pub presolve_mesh: Option<usize>,
    /// Output folder.
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// No progress output.
    #[arg(long)]
    pub quiet: bool,
}

/// Solver section of a study file.
#[derive(Deserialize, Default)]
#[serde(deny_unknown_fields)]
struct SolverSection {
    backend: Option<String>,
    hessian: Option<String>,
    tol: Option<f64>,
    max_iter: Option<usize>,
    time_limit: Option<f64>,
    centrality_correctors: Option<usize>,
    presolve_mesh: Option<usize>,
}

/// A study file for one prediction.
#[derive(Deserialize, Default)]
#[serde(deny_unknown_fields)]
struct StudyFile {
    model: Option<PathBuf>,
    output: Option<PathBuf>,
    guesses: Option<Vec<String>>,
    #[serde(default)]
    problem: Option<ProblemSettings>,
    #[serde(default)]
    solver: SolverSection,
}

/// The initial guess named on the command line or in a study file.
pub(crate) fn parse_guess(s: &str) -> anyhow::Result<GuessKind> {
    Ok(match s.trim() {
        "quasi-random" | "qr" => GuessKind::QuasiRandom,
        "data-informed-walking" | "di-walking" => GuessKind::DataInformedWalking,
        "data-informed-running" | "di-running" => GuessKind::DataInformedRunning,
        other => bail!(
            "unknown initial guess `{other}` (quasi-random, data-informed-walking, data-informed-running)"
        ),
    })
}

/// The solver backend named on the command line or in a study file (`ipm`, `ipopt`).
pub(crate) fn backend(name: &str) -> anyhow::Result<Box<dyn Solver + Sync>> {
    match name {
        "ipm" => Ok(Box::new(stride_solve::ipm::InteriorPoint::new())),
        #[cfg(feature = "ipopt")]
        "ipopt" => Ok(Box::new(
            stride_solve::backends::ipopt::IpoptSolver::default(),
        )),
        #[cfg(not(feature = "ipopt"))]
        "ipopt" => {
            bail!("solver `ipopt` needs a build with `--features ipopt` (and coinor-libipopt-dev)")
        }
        other => bail!("unknown solver `{other}` (ipm, ipopt)"),
    }
}

/// The Hessian named on the command line or in a study file for solver `backend`: `hybrid`
/// (L-BFGS with 6 pairs until μ reaches its floor, then exact; the default with `ipm`, the
/// only backend that has it), `limited-memory` (L-BFGS throughout, the paper's choice and the
/// default with `ipopt`) or `exact`. At 50 intervals hybrid converged in 272 and 360
/// iterations (data-informed, quasi-random) to lower optima than L-BFGS in 664 and 762; with
/// the exact Hessian from the start the pure-Rust solver stalls from 20 intervals on
/// (decision 0002).
pub(crate) fn parse_hessian(name: Option<&str>, backend: &str) -> anyhow::Result<HessianMode> {
    let lbfgs = HessianMode::LimitedMemory { history: 6 };
    let hybrid = HessianMode::Hybrid { history: 6 };
    let hybrid_here = backend == "ipm";
    Ok(match name.map(str::trim) {
        None if hybrid_here => hybrid,
        None => lbfgs,
        Some("hybrid") if hybrid_here => hybrid,
        Some("hybrid") => bail!(
            "hessian `hybrid` needs the ipm solver (solver `{backend}` has exact or limited-memory)"
        ),
        Some("limited-memory") => lbfgs,
        Some("exact") => HessianMode::Exact,
        Some(other) => bail!("unknown hessian `{other}` (exact, limited-memory, hybrid)"),
    })
}

/// The KKT linear solver of the ipm solver named by the environment variable `STRIDE_KKT`
/// (`ldlt`, the default, or `lblt`; decision 0002).
pub(crate) fn linear_solver_from_env() -> anyhow::Result<LinearSolver> {
    match std::env::var("STRIDE_KKT").ok().as_deref() {
        None | Some("ldlt") => Ok(LinearSolver::Ldlt),
        Some("lblt") => Ok(LinearSolver::Lblt),
        Some(other) => bail!("STRIDE_KKT: `{other}` is not a KKT solver (use `ldlt` or `lblt`)"),
    }
}

/// Rejects centrality correctors for a backend other than `ipm` (the only one that has them).
pub(crate) fn check_correctors(options: &SolverOptions, backend: &str) -> anyhow::Result<()> {
    if backend != "ipm" && options.centrality_correctors > 0 {
        bail!(
            "centrality correctors need the ipm solver (solver `{backend}` has none); set them to 0"
        );
    }
    Ok(())
}

/// A wall-time limit [s] given on the command line or in a study file, checked positive.
pub(crate) fn check_time_limit(t: f64) -> anyhow::Result<Duration> {
    if !(t.is_finite() && t > 0.0) {
        bail!("invalid time limit {t} s: must be a positive number of seconds");
    }
    Ok(Duration::from_secs_f64(t))
}

/// Largest constraint violation (unscaled, max-norm) of a converged prediction.
pub(crate) const PREDICTION_CONSTR_VIOL_TOL: f64 = 1e-6;

/// Centrality correctors per iteration of a hybrid-Hessian prediction unless set: at 50
/// intervals they cut the data-informed solve from 283 to 233 iterations (decision 0002).
pub(crate) const HYBRID_CORRECTORS: usize = 2;

/// Solver options of a prediction: tolerance (default 1e-4), iteration limit (default
/// 3000), Hessian choice, wall-time limit per solve [s] (default none), centrality
/// correctors (default 2 with the hybrid Hessian, else 0), adaptive μ, and a
/// constraint violation of at most 1e-6 at the solution (IPOPT's default, 1e-4, let the
/// 50-interval data-informed solve stop at 1.7e-6).
pub(crate) fn prediction_options(
    tol: Option<f64>,
    max_iter: Option<usize>,
    hessian: HessianMode,
    time_limit: Option<f64>,
    correctors: Option<usize>,
) -> anyhow::Result<SolverOptions> {
    let tol = tol.unwrap_or(1e-4);
    if tol.is_nan() || tol <= 0.0 {
        bail!("invalid tol {tol}: must be positive");
    }
    let time_limit = time_limit.map(check_time_limit).transpose()?;
    Ok(SolverOptions {
        tol,
        max_iter: max_iter.unwrap_or(3000),
        hessian,
        linear_solver: linear_solver_from_env()?,
        centrality_correctors: correctors.unwrap_or(
            if matches!(hessian, HessianMode::Hybrid { .. }) {
                HYBRID_CORRECTORS
            } else {
                0
            },
        ),
        mu_strategy: MuStrategy::Adaptive,
        constr_viol_tol: PREDICTION_CONSTR_VIOL_TOL,
        time_limit,
        ..Default::default()
    })
}

/// Run `stride predict`.
pub fn run(args: PredictArgs) -> anyhow::Result<()> {
    let study: StudyFile = match &args.config {
        Some(p) => {
            let text = std::fs::read_to_string(p)
                .with_context(|| format!("reading study file {}", p.display()))?;
            toml::from_str(&text).with_context(|| format!("study file {}", p.display()))?
        }
        None => StudyFile::default(),
    };
    let mut settings = study.problem.unwrap_or_default();
    if let Some(v) = args.speed {
        settings.speed = v;
    }
    if let Some(n) = args.mesh {
        settings.mesh_intervals = n;
    }
    settings.validate()?;
    let guesses: Vec<GuessKind> = match args.guess.or(study.guesses) {
        Some(list) => list
            .iter()
            .map(|s| parse_guess(s))
            .collect::<Result<_, _>>()?,
        None => vec![GuessKind::QuasiRandom, GuessKind::DataInformedWalking],
    };
    if guesses.is_empty() {
        bail!("no initial guess given");
    }
    let s = &study.solver;
    let backend_name = args
        .solver
        .or(s.backend.clone())
        .unwrap_or_else(|| "ipm".into());
    let solver = backend(&backend_name)?;
    let hessian = parse_hessian(args.hessian.or(s.hessian.clone()).as_deref(), &backend_name)?;
    let mut options = prediction_options(
        args.tol.or(s.tol),
        args.max_iter.or(s.max_iter),
        hessian,
        args.time_limit.or(s.time_limit),
        args.correctors.or(s.centrality_correctors),
    )?;
    check_correctors(&options, &backend_name)?;
    let presolve = predict::presolve_for(args.presolve_mesh.or(s.presolve_mesh), &settings)?;
    // the guesses are solved at the same time: the cores are shared out between them
    let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
    options.threads = (cores / guesses.len()).max(1);
    let model = match args.model.or(study.model) {
        Some(p) => stride_model::osim::load_osim(&p)
            .with_context(|| format!("loading model {}", p.display()))?,
        None => stride_model::default_model::default_model(),
    };
    let out = args
        .out
        .or(study.output)
        .unwrap_or_else(|| PathBuf::from(format!("out/predict_{:.2}", settings.speed)));
    let quiet = args.quiet;
    let last = Mutex::new(std::time::Instant::now());
    let progress = |g: GuessKind, r: &stride_solve::solver::IterationRecord| {
        if quiet {
            return;
        }
        let mut t = last.lock().unwrap_or_else(|e| e.into_inner());
        if t.elapsed() > Duration::from_millis(500) {
            *t = std::time::Instant::now();
            eprint!(
                "\r{g:<22} iter {:>5}  objective {:>12.5e}  inf_pr {:>8.2e}  inf_du {:>8.2e}  {:>7.1} s   ",
                r.iter,
                r.objective,
                r.inf_pr,
                r.inf_du,
                r.elapsed.as_secs_f64()
            );
            let _ = std::io::stderr().flush();
        }
    };
    let (problem, solved) = predict::solve_guesses(
        &model,
        &settings,
        &guesses,
        presolve,
        solver.as_ref(),
        &options,
        &progress,
    )?;
    if !quiet {
        eprintln!();
    }
    let kept = predict::select(&solved);
    let summary = predict::write_results(&problem, &solved, kept, solver.name(), &options, &out)?;
    for g in &summary.guesses {
        println!(
            "{:<22} {:<14} iterations {:>5}  objective {:>12.6}  violation {:.1e}  time {:.1} s (evaluations {:.1} s)",
            g.guess.to_string(),
            g.status,
            g.iterations,
            g.objective,
            g.constraint_violation,
            g.time_total_s,
            g.time_evaluations_s
        );
        if let Some(p) = &g.presolve {
            println!(
                "{:<22} presolve on {} intervals: {} after {} iterations, objective {:.6}, {:.1} s{}",
                "",
                p.mesh_intervals,
                p.status,
                p.iterations,
                p.objective,
                p.time_total_s,
                if p.used { "" } else { " (not used: solved from the guess)" }
            );
        }
    }
    match (&summary.kept_guess, &summary.outcomes) {
        (Some(k), Some(o)) => println!(
            "kept {k}: cost of transport {:.3} J/kg/m, stride length {:.3} m, step width {:.3} m, stride frequency {:.3} /s\nresults in {}",
            o.cost_of_transport,
            o.stride_length,
            o.step_width,
            o.stride_frequency,
            out.display()
        ),
        _ => {
            println!("no guess converged; solver logs and summary in {}", out.display());
            std::process::exit(2);
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn hessian_names_map_to_modes() {
        let lbfgs = HessianMode::LimitedMemory { history: 6 };
        let hybrid = HessianMode::Hybrid { history: 6 };
        assert_eq!(parse_hessian(None, "ipm").unwrap(), hybrid);
        assert_eq!(parse_hessian(Some("hybrid"), "ipm").unwrap(), hybrid);
        assert_eq!(parse_hessian(Some("limited-memory"), "ipm").unwrap(), lbfgs);
        assert_eq!(
            parse_hessian(Some(" exact"), "ipm").unwrap(),
            HessianMode::Exact
        );
        let e = parse_hessian(Some("bfgs"), "ipm").unwrap_err().to_string();
        assert!(e.contains("unknown hessian `bfgs`"), "{e}");
        // IPOPT has no hybrid mode: its default is the paper's limited-memory Hessian, and
        // asking for hybrid is an error, not silently something else.
        assert_eq!(parse_hessian(None, "ipopt").unwrap(), lbfgs);
        let e = parse_hessian(Some("hybrid"), "ipopt")
            .unwrap_err()
            .to_string();
        assert!(e.contains("needs the ipm solver"), "{e}");
    }

    #[test]
    fn correctors_default_with_the_hybrid_hessian_and_only_for_ipm() {
        let hybrid = parse_hessian(None, "ipm").unwrap();
        let lbfgs = parse_hessian(Some("limited-memory"), "ipm").unwrap();
        let opts = |h, c| prediction_options(None, None, h, None, c).unwrap();
        assert_eq!(opts(hybrid, None).centrality_correctors, HYBRID_CORRECTORS);
        assert_eq!(opts(lbfgs, None).centrality_correctors, 0);
        assert_eq!(opts(hybrid, Some(0)).centrality_correctors, 0);
        assert_eq!(opts(lbfgs, Some(3)).centrality_correctors, 3);
        // the IPOPT backend has none: its default has none, asking for them is an error
        let ipopt = parse_hessian(None, "ipopt").unwrap();
        assert!(check_correctors(&opts(ipopt, None), "ipopt").is_ok());
        let e = check_correctors(&opts(ipopt, Some(1)), "ipopt")
            .unwrap_err()
            .to_string();
        assert!(e.contains("need the ipm solver"), "{e}");
    }
}

/// Arguments of `stride rewrite`.
#[derive(Args)]
pub struct RewriteArgs {
    /// Result folders of `stride predict` (or single study case folders) to rewrite.
    #[arg(required = true)]
    pub folders: Vec<PathBuf>,
    /// The OpenSim model the folders were predicted with (default: the built-in model).
    #[arg(long)]
    pub model: Option<PathBuf>,
}

/// Run `stride rewrite`: rewrite each folder's motion, tables, figures and outcomes from
/// its `solution.json` with the current definitions (solver logs and times are kept). A
/// folder without a kept solution is an error; every other folder is still rewritten.
pub fn rewrite(args: RewriteArgs) -> anyhow::Result<()> {
    use stride_ocp::solution::{rewrite_folder, Rewritten, SOLUTION_FILE};
    let model = match &args.model {
        Some(p) => stride_model::osim::load_osim(p)
            .with_context(|| format!("loading model {}", p.display()))?,
        None => stride_model::default_model::default_model(),
    };
    let mut failed = Vec::new();
    for dir in &args.folders {
        if !dir.join("summary.json").is_file() {
            failed.push(format!(
                "{}: not a result folder (no summary.json)",
                dir.display()
            ));
            continue;
        }
        match rewrite_folder(&model, dir) {
            Ok(Rewritten::Rewritten) => println!("rewrote {}", dir.display()),
            Ok(Rewritten::NoSolution) => failed.push(format!(
                "{}: no kept solution (no converged guess, or no {SOLUTION_FILE}: written \
                 before stride kept one in every result folder)",
                dir.display()
            )),
            Err(e) => failed.push(format!("{}: {e}", dir.display())),
        }
    }
    if let [one] = &failed[..] {
        if args.folders.len() == 1 {
            bail!("{one}");
        }
    }
    if !failed.is_empty() {
        bail!(
            "{} of {} folders not rewritten (left unchanged):\n  {}",
            failed.len(),
            args.folders.len(),
            failed.join("\n  ")
        );
    }
    Ok(())
}
