//! `stride track`: a tracking simulation (the paper's TrackSim of trial gait_1 with no
//! arguments).

use crate::predict_cmd::{backend, check_correctors, parse_hessian, prediction_options};
use anyhow::{bail, Context};
use clap::Args;
use serde::Deserialize;
use std::io::Write;
use std::path::PathBuf;
use std::sync::Mutex;
use std::time::Duration;
use stride_ocp::tracking::{TrackSettings, TrackingProblem};
use stride_predict::track_output;

/// Arguments of `stride track` (flags override the settings file).
#[derive(Args)]
pub struct TrackArgs {
    /// Settings file (TOML) with a `[track]` section (and `model`, `output`, `[solver]`).
    #[arg(long)]
    pub config: Option<PathBuf>,
    /// Model: a shipped model's name (`gait1018`, …) or an OpenSim model file (.osim)
    /// [default: the built-in subject1 model of the paper].
    #[arg(long, value_name = "NAME|FILE")]
    pub model: Option<PathBuf>,
    /// The model's settings file (contact spheres, passive torques, actuators, …; see
    /// docs/settings.md) [default: `<model>.toml` beside the model file, if any].
    #[arg(long, value_name = "FILE")]
    pub model_settings: Option<PathBuf>,
    /// Fitted muscle geometry of the model (`stride model fit --out`).
    #[arg(long, value_name = "FILE")]
    pub geometry: Option<PathBuf>,
    /// Joint angles to track (.mot); default: the shipped trial gait_1.
    #[arg(long)]
    pub motion: Option<PathBuf>,
    /// Ground reaction forces (.mot), with --motion.
    #[arg(long)]
    pub grf: Option<PathBuf>,
    /// Net joint torques (.sto), optional with --motion.
    #[arg(long)]
    pub torques: Option<PathBuf>,
    /// Time window start and end [s] (default 3.45,4.25).
    #[arg(long, value_delimiter = ',')]
    pub window: Option<Vec<f64>>,
    /// Cut-off of the low-pass filter of the joint angles [Hz] (default 6; 0: no filter,
    /// for simulated motions).
    #[arg(long, value_name = "HZ")]
    pub filter_cutoff: Option<f64>,
    /// Mesh intervals over the window (default 50).
    #[arg(long)]
    pub mesh: Option<usize>,
    /// Calibrate the contact spheres (x, z and radius of each right-foot sphere, mirrored
    /// on the left): writes contact_parameters.csv and contact_geometry.toml.
    #[arg(long)]
    pub calibrate_contact: bool,
    /// Hessian: hybrid (default), limited-memory, or exact.
    #[arg(long)]
    pub hessian: Option<String>,
    /// Convergence tolerance (default 1e-4).
    #[arg(long)]
    pub tol: Option<f64>,
    /// Iteration limit.
    #[arg(long)]
    pub max_iter: Option<usize>,
    /// Evaluation threads (default: all cores).
    #[arg(long)]
    pub threads: Option<usize>,
    /// Output folder (default out/track).
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Replace the previous result in the output folder (never a folder stride did not write).
    #[arg(long)]
    pub force: bool,
    /// No progress output.
    #[arg(long)]
    pub quiet: bool,
}

/// Solver section of a tracking settings file.
#[derive(Deserialize, Default)]
#[serde(deny_unknown_fields)]
struct SolverSection {
    hessian: Option<String>,
    tol: Option<f64>,
    max_iter: Option<usize>,
}

/// A tracking settings file.
#[derive(Deserialize, Default)]
#[serde(deny_unknown_fields)]
struct TrackFile {
    model: Option<PathBuf>,
    model_settings: Option<PathBuf>,
    geometry: Option<PathBuf>,
    output: Option<PathBuf>,
    #[serde(default)]
    track: TrackSettings,
    #[serde(default)]
    solver: SolverSection,
}

/// The settings of a run: the file's, overridden by the flags.
fn settings(args: &TrackArgs, file: &TrackFile) -> anyhow::Result<TrackSettings> {
    let mut s = file.track.clone();
    if args.motion.is_some() || args.grf.is_some() || args.torques.is_some() {
        s.motion = args.motion.clone();
        s.grf = args.grf.clone();
        s.torques = args.torques.clone();
    }
    if let Some(w) = &args.window {
        if w.len() != 2 {
            bail!("--window takes two times: start,end [s]");
        }
        s.window = [w[0], w[1]];
    }
    if let Some(f) = args.filter_cutoff {
        s.filter_cutoff_hz = f;
    }
    if let Some(n) = args.mesh {
        s.mesh_intervals = n;
    }
    if args.calibrate_contact {
        s.calibrate_contact = true;
    }
    Ok(s)
}

/// Run `stride track`.
pub fn run(args: TrackArgs) -> anyhow::Result<()> {
    let file: TrackFile = match &args.config {
        Some(p) => {
            let text = std::fs::read_to_string(p)
                .with_context(|| format!("reading settings file {}", p.display()))?;
            toml::from_str(&text).with_context(|| format!("settings file {}", p.display()))?
        }
        None => TrackFile::default(),
    };
    let settings = settings(&args, &file)?;
    let hessian = parse_hessian(
        args.hessian.as_deref().or(file.solver.hessian.as_deref()),
        "ipm",
    )?;
    let mut options = prediction_options(
        args.tol.or(file.solver.tol),
        args.max_iter.or(file.solver.max_iter),
        hessian,
        None,
        None,
    )?;
    check_correctors(&options, "ipm")?;
    options.threads = args.threads.unwrap_or(0);
    let model = crate::model_load::load_model(
        args.model
            .as_ref()
            .or(file.model.as_ref())
            .map(PathBuf::as_path),
        args.model_settings
            .as_ref()
            .or(file.model_settings.as_ref())
            .map(PathBuf::as_path),
        args.geometry
            .as_ref()
            .or(file.geometry.as_ref())
            .map(PathBuf::as_path),
        args.quiet,
    )?;
    let out = crate::predict_cmd::output_folder(
        args.out.clone().or(file.output.clone()),
        PathBuf::from("out/track"),
        args.force,
        args.quiet,
    )?;
    let tp = TrackingProblem::new(&model, &settings)?;
    let solver = backend("ipm")?;
    let quiet = args.quiet;
    let last = Mutex::new(std::time::Instant::now());
    let progress = |r: &stride_solve::solver::IterationRecord| {
        let mut t = last.lock().unwrap_or_else(|e| e.into_inner());
        if !quiet && t.elapsed() > Duration::from_millis(500) {
            *t = std::time::Instant::now();
            eprint!(
                "\rtrack iter {:>5}  objective {:>12.5e}  inf_pr {:>8.2e}  inf_du {:>8.2e}  {:>7.1} s   ",
                r.iter,
                r.objective,
                r.inf_pr,
                r.inf_du,
                r.elapsed.as_secs_f64()
            );
            let _ = std::io::stderr().flush();
        }
    };
    let r = tp.solve(solver.as_ref(), &options, &progress)?;
    if !quiet {
        eprintln!();
    }
    let errors = track_output::write_results(&tp, &r, solver.name(), &options, &out, &[])?;
    println!(
        "{:?} after {} iterations, objective {:.6}, violation {:.1e}, {:.1} s",
        r.status,
        r.iterations,
        r.objective,
        r.constraint_violation,
        r.time_total.as_secs_f64()
    );
    for e in errors.joint_angles.iter().filter(|e| {
        ["hip_flexion", "knee_angle", "ankle_angle"]
            .iter()
            .any(|n| e.name.starts_with(n))
    }) {
        println!(
            "  {:<16} RMSE {:>6.2} {}  R² {:.3}",
            e.name, e.rmse, e.unit, e.r2
        );
    }
    for (e, bw) in errors.grf.iter().zip(&errors.grf_percent_body_weight) {
        println!(
            "  {:<16} RMSE {:>6.1} N ({bw:.1} % BW)  R² {:.3}",
            e.name, e.rmse, e.r2
        );
    }
    if tp.settings.calibrate_contact {
        println!(
            "  calibrated contact spheres: {}",
            out.join("contact_geometry.toml").display()
        );
    }
    println!("results in {}", out.display());
    if !r.status.is_usable_start() {
        std::process::exit(2);
    }
    Ok(())
}
