//! `stride predict`: predict a gait from the built-in model (or an `.osim`) and a speed.

use anyhow::{bail, Context};
use clap::Args;
use serde::Deserialize;
use std::path::{Path, PathBuf};
use std::time::Duration;
use stride_files::reserve::Reservation;
use stride_files::result_dir::{self, Existing, OutputError, ResultKind};
use stride_ocp::guess::GuessKind;
use stride_ocp::model_defaults::ModelProblemDefaults;
use stride_ocp::settings::{ProblemSettings, RunSettings};
use stride_predict::{predict, results};
use stride_solve::solver::{HessianMode, LinearSolver, Solver, SolverOptions};

/// Arguments of `stride predict` (flags override the study file).
#[derive(Args)]
pub struct PredictArgs {
    /// Study file (TOML) with `[problem]`, `[solver]`, `guesses`, `output`, `model`,
    /// `geometry`.
    #[arg(long)]
    pub config: Option<PathBuf>,
    /// OpenSim model file (.osim) [default: the built-in subject1 model of the paper].
    #[arg(long, value_name = "FILE")]
    pub model: Option<PathBuf>,
    /// The model's settings file (contact spheres, passive torques, actuators, …; see
    /// docs/settings.md) [default: `<model>.toml` beside the model file, if any].
    #[arg(long, value_name = "FILE")]
    pub model_settings: Option<PathBuf>,
    /// Fitted muscle geometry of the model (`stride model fit --out`); default for an
    /// `.osim`: the settings file's `geometry`, else the per-user cache, fitted on first use.
    #[arg(long)]
    pub geometry: Option<PathBuf>,
    /// Imposed average forward speed [m/s] [default: 1.33].
    #[arg(long, allow_hyphen_values = true, value_name = "M_PER_S")]
    pub speed: Option<f64>,
    /// Mesh intervals per half gait cycle (the full cycle has twice as many) [default: 50].
    #[arg(long, value_name = "INTERVALS")]
    pub mesh: Option<usize>,
    /// Initial guesses, comma separated: quasi-random, data-informed-walking,
    /// data-informed-running [default: quasi-random,data-informed-walking]; the lowest-cost
    /// converged solution is kept.
    #[arg(long, value_delimiter = ',')]
    pub guess: Option<Vec<String>>,
    /// Solver backend: ipm (pure Rust, default) or ipopt (needs the `ipopt` feature).
    #[arg(long)]
    pub solver: Option<String>,
    /// Hessian: hybrid (default: limited-memory until μ reaches its floor, then exact),
    /// limited-memory, or exact.
    #[arg(long)]
    pub hessian: Option<String>,
    /// Convergence tolerance of the scaled optimality conditions [default: 1e-4].
    #[arg(long)]
    pub tol: Option<f64>,
    /// Iteration limit per solve [default: 3000].
    #[arg(long)]
    pub max_iter: Option<usize>,
    /// Wall-time limit per solve (one guess, coarse and fine stage together) [s]
    /// [default: 1800].
    #[arg(long, value_name = "SECONDS")]
    pub time_limit: Option<f64>,
    /// Centrality correctors per iteration (ipm only; default 2 with the hybrid Hessian,
    /// else 0).
    #[arg(long)]
    pub correctors: Option<usize>,
    /// Coarse mesh of the presolve, intervals per half cycle: each guess is first solved on
    /// this mesh and the requested mesh is solved from that optimum [default: 10 when the
    /// mesh is finer; 0: solve the requested mesh directly from the guess].
    #[arg(long, value_name = "INTERVALS")]
    pub presolve_mesh: Option<usize>,
    /// Output folder: a new or empty folder, or a previous result of `stride predict`
    /// (replaced only with `--force`). Default `out/predict_<speed>`, or the next free
    /// `out/predict_<speed>-2`, `-3`, … when it holds a result.
    #[arg(long, value_name = "FOLDER")]
    pub out: Option<PathBuf>,
    /// Replace the previous result in the output folder (never a folder stride did not write).
    #[arg(long)]
    pub force: bool,
    /// No progress output.
    #[arg(long)]
    pub quiet: bool,
    /// Do not write the viewer page (`view.html`, see `stride view`).
    #[arg(long)]
    pub no_view: bool,
}

/// Largest study file read [bytes].
pub(crate) const MAX_STUDY_FILE_BYTES: u64 = 16 << 20;

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
    model_settings: Option<PathBuf>,
    geometry: Option<PathBuf>,
    output: Option<PathBuf>,
    guesses: Option<Vec<String>>,
    /// Read for its checks (unknown keys name the line); the settings are built from the
    /// table as written, over the model's defaults.
    #[serde(default)]
    #[allow(dead_code)]
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
/// default with `ipopt`) or `exact`. Why hybrid is the default (fewer iterations and lower
/// optima than L-BFGS; the exact Hessian from the start stalls on fine meshes): decision 0002.
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
    RunSettings {
        time_limit: Some(t),
        ..Default::default()
    }
    .validate()?;
    Ok(Duration::from_secs_f64(t))
}

/// Wall-time limit of each solve of a prediction unless set [s]: a nominal solve takes
/// about a minute, a 100-interval case a few; a problem that does not converge stops here
/// with its status and files instead of iterating for hours.
pub(crate) const DEFAULT_TIME_LIMIT_S: f64 = 1800.0;

pub(crate) use stride_predict::predict::HYBRID_CORRECTORS;

/// Solver options of a prediction: tolerance (default 1e-4), iteration limit (default
/// 3000), Hessian choice, wall-time limit per solve [s] (default
/// [`DEFAULT_TIME_LIMIT_S`]), centrality
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
    RunSettings {
        tol,
        max_iter,
        time_limit,
        centrality_correctors: correctors,
        ..Default::default()
    }
    .validate()?;
    let time_limit = Some(check_time_limit(
        time_limit.unwrap_or(DEFAULT_TIME_LIMIT_S),
    )?);
    let base = stride_predict::predict::prediction_options();
    Ok(SolverOptions {
        tol: tol.unwrap_or(base.tol),
        max_iter: max_iter.unwrap_or(base.max_iter),
        hessian,
        linear_solver: linear_solver_from_env()?,
        centrality_correctors: correctors.unwrap_or(
            if matches!(hessian, HessianMode::Hybrid { .. }) {
                HYBRID_CORRECTORS
            } else {
                0
            },
        ),
        time_limit,
        ..base
    })
}

/// The study file of `--config` (`None`: an empty one), read with a size bound, and its
/// `[problem]` table as written.
fn read_study_file(p: Option<&Path>) -> anyhow::Result<(StudyFile, toml::Table)> {
    let Some(p) = p else {
        return Ok((StudyFile::default(), toml::Table::new()));
    };
    let bytes = stride_model::storage::read_limited(p, MAX_STUDY_FILE_BYTES)
        .with_context(|| format!("reading study file {}", p.display()))?;
    let text = String::from_utf8(bytes)
        .map_err(|_| anyhow::anyhow!("study file {}: not UTF-8 text", p.display()))?;
    let study: StudyFile =
        toml::from_str(&text).with_context(|| format!("study file {}", p.display()))?;
    let mut raw: toml::Table = toml::from_str(&text)?;
    let problem = match raw.remove("problem") {
        Some(toml::Value::Table(t)) => t,
        _ => toml::Table::new(),
    };
    Ok((study, problem))
}

/// The problem settings of a prediction: the `[problem]` table of its file over the
/// defaults of the model (`model`, with the settings file `model_settings` or its own).
fn layered_problem(
    problem: &toml::Table,
    model: Option<&Path>,
    model_settings: Option<&Path>,
) -> anyhow::Result<ProblemSettings> {
    let defaults = ModelProblemDefaults::of_named_model(model, model_settings)
        .map_err(|e| anyhow::anyhow!("{e}"))?;
    defaults
        .settings(problem)
        .context("the model's [problem] defaults under the prediction file's")
}

/// The model and problem settings of a prediction file (`None`: the nominal problem) for
/// `model` (else the file's), with `mesh` intervals, checked.
pub(crate) fn config_problem(
    config: Option<&Path>,
    model: Option<PathBuf>,
    mesh: usize,
) -> anyhow::Result<(Option<PathBuf>, ProblemSettings)> {
    let (study, problem) = read_study_file(config)?;
    let model = model.or(study.model);
    let mut settings =
        layered_problem(&problem, model.as_deref(), study.model_settings.as_deref())?;
    settings.mesh_intervals = mesh;
    settings
        .validate()
        .with_context(|| format!("--mesh {mesh}"))?;
    Ok((model, settings))
}

/// The initial guesses named on the command line or in a study file, each at most once.
pub(crate) fn parse_guesses(list: &[String]) -> anyhow::Result<Vec<GuessKind>> {
    let mut guesses = Vec::new();
    for name in list {
        let g = parse_guess(name)?;
        if guesses.contains(&g) {
            bail!("initial guess `{g}` given twice (`{}`)", list.join(","));
        }
        guesses.push(g);
    }
    if guesses.is_empty() {
        bail!("no initial guess given");
    }
    Ok(guesses)
}

/// The output folder of a prediction, checked and reserved before anything is solved: a
/// new or empty folder, or a previous prediction result replaced with `force` (only the
/// files stride wrote are replaced; the others are named on stderr and kept). When the
/// default folder holds a result or is being written by another process (and no `force`),
/// the next free numbered name is used and said on stderr; a given folder holding a result
/// is an error, and so is one another process is writing. The reservation is held until
/// the result is written. `quiet`: the note on the default folder is not printed (the
/// folder is named on stdout at the end).
pub(crate) fn output_folder(
    given: Option<PathBuf>,
    default: PathBuf,
    force: bool,
    quiet: bool,
) -> anyhow::Result<Reservation> {
    let (out, is_default) = match given {
        Some(p) => (p, false),
        None => (default, true),
    };
    let existing = result_dir::inspect(&out, ResultKind::Prediction)?;
    result_dir::check_writable(&out)?;
    let reserved = match existing {
        Existing::Own(_) if !force && !is_default => {
            return Err(OutputError::Occupied(out.display().to_string()).into())
        }
        Existing::Own(_) if !force => None,
        _ if is_default && !force => Reservation::take(&out).ok(),
        _ => Some(Reservation::take(&out).map_err(OutputError::from)?),
    };
    let reserved = match reserved {
        Some(r) => r,
        None => {
            let next = result_dir::reserve_next_free(&out, ResultKind::Prediction)?;
            if !quiet {
                eprintln!(
                    "note: {} holds a previous result or is being written (--force replaces a result); writing to {}",
                    out.display(),
                    next.out().display()
                );
            }
            next
        }
    };
    // the folder may have changed while it was not reserved
    if let Existing::Own(_) = result_dir::inspect(reserved.out(), ResultKind::Prediction)? {
        keep_foreign_note(reserved.out(), force)?;
    }
    Ok(reserved)
}

/// Before a previous result at `out` is replaced (`force`, else an error): refuse a result
/// whose marker does not say which files are stride's, and name the files that are kept.
fn keep_foreign_note(out: &Path, force: bool) -> anyhow::Result<()> {
    if !force {
        return Err(OutputError::Occupied(out.display().to_string()).into());
    }
    let foreign = result_dir::foreign_entries(out)
        .ok_or_else(|| OutputError::Unlisted(out.display().to_string()))?;
    if !foreign.is_empty() {
        eprintln!(
            "note: --force replaces only the files stride wrote in {}; kept: {}",
            out.display(),
            foreign.join(", ")
        );
    }
    Ok(())
}

/// Run `stride predict`.
pub fn run(args: PredictArgs) -> anyhow::Result<()> {
    let (study, problem) = read_study_file(args.config.as_deref())?;
    let model_path = args.model.or(study.model);
    let model_settings = args.model_settings.or(study.model_settings);
    let adapted = crate::adapt_cmd::auto_settings(
        model_path.as_deref(),
        model_settings.as_deref(),
        crate::model_load::cache_dir(),
    )?;
    let model_settings = model_settings.or(adapted.clone());
    let mut settings = layered_problem(&problem, model_path.as_deref(), model_settings.as_deref())?;
    if let Some(v) = args.speed {
        settings.speed = v;
    }
    if let Some(n) = args.mesh {
        settings.mesh_intervals = n;
    }
    settings.validate()?;
    let guesses = match args.guess.or(study.guesses) {
        Some(list) => parse_guesses(&list)?,
        None => vec![GuessKind::QuasiRandom, GuessKind::DataInformedWalking],
    };
    let s = &study.solver;
    RunSettings {
        presolve_mesh: args.presolve_mesh.or(s.presolve_mesh),
        ..Default::default()
    }
    .validate()?;
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
    let model = crate::model_load::load_model(
        model_path.as_deref(),
        model_settings.as_deref(),
        args.geometry.or(study.geometry).as_deref(),
        args.quiet,
    )?;
    crate::limits::check_memory(
        &model,
        &settings,
        guesses.len(),
        "the guesses solved at once",
    )?;
    let default_out = PathBuf::from(format!("out/predict_{:.2}", settings.speed));
    let reserved = output_folder(
        args.out.or(study.output),
        default_out,
        args.force,
        args.quiet,
    )?;
    let out = reserved.out().to_path_buf();
    let quiet = args.quiet;
    let board = crate::progress::ProgressBoard::new(&guesses, options.tol / 10.0);
    let progress = |src: predict::ProgressSource, r: &stride_solve::solver::IterationRecord| {
        if !quiet {
            board.update(src, r);
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
        board.finish();
    }
    let kept = predict::select(&solved);
    let summary = results::write_results(&problem, &solved, kept, solver.name(), &options, &out)?;
    if let Some(a) = &adapted {
        crate::adapt_cmd::copy_into(a, &out)?;
    }
    if !args.no_view && kept.is_some() {
        crate::view_cmd::write_default(&out, &model)?;
    }
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
            let use_note = match (&p.warm_start_failure, p.used) {
                (Some(f), _) => {
                    format!(" (the final mesh from it ended {f}: solved again from the guess)")
                }
                (None, false) => " (not used: solved from the guess)".to_string(),
                (None, true) => String::new(),
            };
            println!(
                "{:<22} presolve on {} intervals: {} after {} iterations, objective {:.6}, {:.1} s{}",
                "",
                p.mesh_intervals,
                status_text(&p.status),
                p.iterations,
                p.objective,
                p.time_total_s,
                use_note
            );
        }
    }
    match (&summary.kept_guess, &summary.outcomes) {
        (Some(k), Some(o)) => println!(
            "kept {k}: cost of transport {:.3} J/kg/m, stride length {:.3} m, step width {}, stride frequency {:.3} /s\nresults in {}",
            o.cost_of_transport,
            o.stride_length,
            if o.step_width.is_nan() {
                "none (2D model)".to_string()
            } else {
                format!("{:.3} m", o.step_width)
            },
            o.stride_frequency,
            out.display()
        ),
        _ => {
            println!("no guess converged; solver logs and summary in {}", out.display());
            drop(reserved);
            std::process::exit(2);
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use stride_ocp::passive_rules::{PassiveCost, ToeDrive};

    /// A fresh folder for this test's files.
    fn scratch(name: &str) -> PathBuf {
        let d = std::env::temp_dir().join(format!("stride-{name}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&d);
        std::fs::create_dir_all(&d).unwrap();
        d
    }

    #[test]
    fn problem_keys_layer_defaults_model_file_and_command_line() {
        let d = scratch("layers");
        let model = d.join("m.toml");
        let text = "[problem]\nspeed = 1.25\nmesh_intervals = 20\npassive = { toes = \"passive\", cost = \"limit\" }\n";
        std::fs::write(&model, text).unwrap();
        let config = d.join("c.toml");
        let text = format!(
            "model_settings = {:?}\n[problem]\nspeed = 1.5\n[problem.passive]\ncost = \"total\"\n",
            model.display().to_string()
        );
        std::fs::write(&config, text).unwrap();
        // model settings alone over the built-in defaults
        let s = layered_problem(&toml::Table::new(), None, Some(&model)).unwrap();
        assert_eq!((s.speed, s.mesh_intervals), (1.25, 20));
        assert_eq!(
            (s.passive.toes, s.passive.cost),
            (ToeDrive::Passive, PassiveCost::Limit)
        );
        assert_eq!(s.passive.damping, 0.1);
        // the prediction file over the model settings, the command line (--mesh) over both
        let (_, s) = config_problem(Some(&config), None, 30).unwrap();
        assert_eq!((s.speed, s.mesh_intervals), (1.5, 30));
        assert_eq!(
            (s.passive.toes, s.passive.cost),
            (ToeDrive::Passive, PassiveCost::Total)
        );
        std::fs::remove_dir_all(&d).unwrap();
    }

    #[test]
    fn the_toes_model_alone_gives_the_problem_of_its_nominal_study() {
        let s = layered_problem(&toml::Table::new(), Some(Path::new("falisse2022")), None).unwrap();
        let want = ProblemSettings {
            passive: stride_ocp::passive_rules::PassiveSettings {
                toes: ToeDrive::Passive,
                cost: PassiveCost::Limit,
                ..Default::default()
            },
            bounds: stride_ocp::settings::BoundsRule::Predsim,
            ..Default::default()
        };
        assert_eq!(s, want);
        let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
        let file = root.join("studies/falisse2022_nominal.toml");
        let study = stride_study::spec::load(&file).unwrap();
        assert!(study.cases.iter().all(|c| c.settings == s));
        // a study's [base] over the model's defaults
        let text = "[study]\nname = \"t\"\noutput = \"out/t\"\nmodel = \"falisse2022\"\n[base.passive]\ncost = \"total\"\n";
        let study = stride_study::spec::parse(text, Path::new("t.toml")).unwrap();
        let p = &study.cases[0].settings.passive;
        assert_eq!((p.toes, p.cost), (ToeDrive::Passive, PassiveCost::Total));
    }

    #[test]
    fn unknown_model_problem_keys_name_file_and_line() {
        let d = scratch("unknown-problem-key");
        let model = d.join("m.toml");
        for (text, want) in [
            (
                "[problem]\nspeed = 1.2\nspeeed = 1.3\n",
                ":3: `problem.speeed`: unknown field",
            ),
            ("[problem]\nspeed = -1.0\n", ":2: `problem.speed`: "),
            (
                "gravity = [0.0, -9.81, 0.0]\n\n[problem.passive]\ntoess = \"passive\"\n",
                ":3: `problem.passive`: unknown field `toess`",
            ),
        ] {
            std::fs::write(&model, text).unwrap();
            let e = layered_problem(&toml::Table::new(), None, Some(&model))
                .unwrap_err()
                .to_string();
            assert!(e.starts_with(&format!("{}{want}", model.display())), "{e}");
        }
        std::fs::remove_dir_all(&d).unwrap();
    }

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

/// A solver status as the user reads it: the coarse solve's `MuFloor` (stopped on purpose
/// once the barrier parameter reached its floor, near the coarse optimum) is "near optimal".
fn status_text(status: &str) -> &str {
    match status {
        "MuFloor" => "near optimal (stopped for the final mesh)",
        other => other,
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
    use stride_predict::results::{rewrite_folder, Rewritten};
    use stride_predict::solution::SOLUTION_FILE;
    let model = crate::model_load::load_model(args.model.as_deref(), None, None, false)?;
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
