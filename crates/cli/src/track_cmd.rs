//! `stride track`: a tracking simulation (the paper's TrackSim of trial gait_1 with no
//! arguments).

use crate::model_load::UsedSettings;
use crate::predict_cmd::{backend, check_correctors, parse_hessian, prediction_options};
use anyhow::{bail, Context};
use clap::Args;
use serde::Deserialize;
use std::io::Write;
use std::path::{Path, PathBuf};
use std::sync::Mutex;
use std::time::Duration;
use stride_model::input_file::{read_text_limited, MAX_SETTINGS_BYTES};
use stride_ocp::tracking::{calibration, TrackSettings, TrackingProblem};
use stride_predict::predict::MeshStage;
use stride_predict::track::{solve_tracking, track_presolve_for, TrackSolved};
use stride_predict::track_output;
use stride_solve::solver::IterationRecord;

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
    /// Joint angles to track (.mot/.sto: degrees or radians as its `inDegrees` header says,
    /// columns named by coordinate or by OpenSim 4 state path
    /// `/jointset/<joint>/<coordinate>/value`; a coupled coordinate it lacks is computed from
    /// its constraint); default: the shipped trial gait_1.
    #[arg(long, value_name = "FILE")]
    pub motion: Option<PathBuf>,
    /// Ground reaction forces, with --motion: an OpenSim ExternalLoads file (.xml: the foot
    /// body each force acts on, its column identifiers and the `<datafile>`, relative to the
    /// .xml), or a .mot whose column prefixes are detected (`1_`/none, `r_`/`l_`).
    #[arg(long, value_name = "FILE")]
    pub grf: Option<PathBuf>,
    /// Net joint torques (.sto), optional with --motion.
    #[arg(long)]
    pub torques: Option<PathBuf>,
    /// Time window start and end [s], anywhere inside the data of the motion, forces and
    /// torques (default 3.45,4.25, for gait_1).
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
    /// Coarse mesh of the presolve, intervals over the window: the problem is first solved
    /// on this mesh and the requested mesh is solved from that optimum (slower on gait_1,
    /// but to a lower optimum) [default: none, the requested mesh is solved directly from
    /// the measured data; 0: none].
    #[arg(long, value_name = "INTERVALS")]
    pub presolve_mesh: Option<usize>,
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
    presolve_mesh: Option<usize>,
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

/// The progress line of a tracking solve on stderr (at most every half second; nothing
/// when `quiet`).
fn progress_printer(quiet: bool) -> impl Fn(MeshStage, &IterationRecord) + Sync {
    let last = Mutex::new(std::time::Instant::now());
    move |stage, r| {
        let mut t = last.lock().unwrap_or_else(|e| e.into_inner());
        if !quiet && t.elapsed() > Duration::from_millis(500) {
            *t = std::time::Instant::now();
            let mesh = match stage {
                MeshStage::Coarse(n) => format!("presolve {n:>3}"),
                MeshStage::Final(n) => format!("mesh {n:>7}"),
            };
            eprint!(
                "\rtrack {mesh} iter {:>5}  objective {:>12.5e}  inf_pr {:>8.2e}  inf_du {:>8.2e}  {:>7.1} s   ",
                r.iter,
                r.objective,
                r.inf_pr,
                r.inf_du,
                r.elapsed.as_secs_f64()
            );
            let _ = std::io::stderr().flush();
        }
    }
}

/// Name of the model settings file with the calibrated contact spheres in a result folder.
pub const CALIBRATED_MODEL_FILE: &str = "calibrated_model.toml";

/// The model settings file of a contact calibration ([`CALIBRATED_MODEL_FILE`]): the
/// settings the model was built with (`used`), its contact spheres those calibrated at the
/// solution `x` of `tp`, the muscle-geometry path absolute (none for a shipped model's
/// embedded geometry), so that `stride predict --model <model> --model-settings <file>`
/// predicts with the calibrated spheres from anywhere.
fn calibrated_model_file(
    used: &UsedSettings,
    tp: &TrackingProblem,
    x: &[f64],
) -> anyhow::Result<(String, Vec<u8>)> {
    let model = &tp.problem.model;
    let geometry = calibration::calibrated_geometry(model, &tp.statics, tp.static_variables(x));
    let mut settings = geometry.into_settings(model, &used.settings)?;
    settings.geometry = match &used.geometry {
        Some(g) => Some(std::path::absolute(g).with_context(|| g.display().to_string())?),
        None => None,
    };
    let body = toml::to_string(&settings).context("writing the calibrated model settings")?;
    let text = format!(
        "# Model settings of `{m}` with the contact spheres calibrated by `stride track \
         --calibrate-contact` (FORMULATION 12.6).\n# Use: stride predict --model {m} \
         --model-settings {CALIBRATED_MODEL_FILE}\n\n{body}",
        m = used.model
    );
    Ok((CALIBRATED_MODEL_FILE.into(), text.into_bytes()))
}

/// Run `stride track`.
pub fn run(args: TrackArgs) -> anyhow::Result<()> {
    let file: TrackFile = match &args.config {
        Some(p) => {
            let text = read_text_limited(p, MAX_SETTINGS_BYTES)
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
    let model_path = args.model.as_ref().or(file.model.as_ref());
    let model_settings = args
        .model_settings
        .as_ref()
        .or(file.model_settings.as_ref());
    let adapted = crate::adapt_cmd::auto_settings(
        model_path.map(PathBuf::as_path),
        model_settings.map(PathBuf::as_path),
        crate::model_load::cache_dir(),
    )?;
    let (model, used) = crate::model_load::load_model_with_settings(
        model_path.map(PathBuf::as_path),
        model_settings.or(adapted.as_ref()).map(PathBuf::as_path),
        args.geometry
            .as_ref()
            .or(file.geometry.as_ref())
            .map(PathBuf::as_path),
        args.quiet,
    )?;
    let reserved = crate::predict_cmd::output_folder(
        args.out.clone().or(file.output.clone()),
        PathBuf::from("out/track"),
        args.force,
        args.quiet,
    )?;
    let out = reserved.out().to_path_buf();
    let tp = TrackingProblem::new(&model, &settings)?;
    let presolve = track_presolve_for(
        args.presolve_mesh.or(file.solver.presolve_mesh),
        &tp.settings,
    )?;
    let solver = backend("ipm")?;
    let solved = solve_tracking(
        &model,
        tp,
        presolve,
        solver.as_ref(),
        &options,
        &progress_printer(args.quiet),
    )?;
    if !args.quiet {
        eprintln!();
    }
    let (tp, r) = (&solved.problem, &solved.result);
    let mut extra = match tp.settings.calibrate_contact {
        true => vec![calibrated_model_file(&used, tp, &r.x)?],
        false => Vec::new(),
    };
    if let Some(a) = &adapted {
        let bytes = std::fs::read(a).with_context(|| format!("reading {}", a.display()))?;
        extra.push((crate::adapt_cmd::RESULT_FILE.into(), bytes));
    }
    let errors = track_output::write_results(
        tp,
        r,
        solved.presolve.as_ref(),
        solver.name(),
        &options,
        &out,
        &extra,
    )?;
    print_outcome(&solved, &errors, &out);
    println!("results in {}", out.display());
    if !r.status.is_usable_start() {
        drop(reserved);
        std::process::exit(2);
    }
    Ok(())
}

/// Prints the outcome of a tracking solve: status, the coarse solve, the leg joint-angle
/// and GRF errors, and where the calibrated spheres are.
fn print_outcome(solved: &TrackSolved, errors: &track_output::TrackingErrors, out: &Path) {
    let (tp, r) = (&solved.problem, &solved.result);
    if let Some(p) = &solved.presolve {
        println!(
            "presolve on {} intervals: {} after {} iterations, objective {:.6}, {:.1} s{}",
            p.mesh_intervals,
            p.status,
            p.iterations,
            p.objective,
            p.time_total_s,
            if p.used { "" } else { " (not used)" }
        );
    }
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
}
