//! `stride bench track`: the paper's TrackSim of trial gait_1 (with the contact calibration
//! by default) per Hessian, one child process per case on one thread: iterations, wall and
//! CPU time, where the time goes, and peak memory.

use crate::predict_cmd;
use anyhow::{bail, Context};
use clap::Args;
use serde::{Deserialize, Serialize};
use std::io::Write;
use std::process::Command;
use stride_ocp::tracking::{TrackSettings, TrackingProblem};
use stride_predict::track::{solve_tracking, track_presolve_for};
use stride_predict::track_output;

/// Arguments of `stride bench track`.
#[derive(Args)]
pub struct TrackBenchArgs {
    /// Mesh intervals over the window (3.45–4.25 s of gait_1).
    #[arg(long, default_value_t = 50)]
    pub mesh: usize,
    /// Hessian modes, comma separated: hybrid (the default of `stride track`), exact,
    /// limited-memory.
    #[arg(long, value_delimiter = ',', default_value = "hybrid,exact")]
    pub hessian: Vec<String>,
    /// Track with the generic contact spheres instead of calibrating them.
    #[arg(long)]
    pub generic: bool,
    /// Iteration limit per solve.
    #[arg(long, default_value_t = 3000)]
    pub max_iter: usize,
    /// Coarse mesh of the presolve [intervals; default as `stride track`; 0: none].
    #[arg(long, value_name = "INTERVALS")]
    pub presolve_mesh: Option<usize>,
    /// Initial barrier parameter μ₀ of the solve from the measured kinematics [default: as
    /// `stride track`].
    #[arg(long)]
    pub mu_init: Option<f64>,
}

/// Arguments of the hidden `stride bench track-one`.
#[derive(Args)]
pub struct TrackOneArgs {
    /// Mesh intervals.
    #[arg(long)]
    pub mesh: usize,
    /// Hessian mode.
    #[arg(long)]
    pub hessian: String,
    /// Generic contact spheres (no calibration).
    #[arg(long)]
    pub generic: bool,
    /// Iteration limit.
    #[arg(long)]
    pub max_iter: usize,
    /// Coarse mesh of the presolve (0: none).
    #[arg(long)]
    pub presolve_mesh: Option<usize>,
    /// Initial barrier parameter μ₀.
    #[arg(long)]
    pub mu_init: Option<f64>,
}

/// Measurements of one tracking case (the JSON line of `stride bench track-one`).
#[derive(Serialize, Deserialize, Debug, Clone)]
pub struct TrackReport {
    /// Solver status.
    pub status: String,
    /// Iterations performed on the requested mesh.
    pub iterations: usize,
    /// Coarse mesh of the presolve, its status and iterations (None: no presolve).
    pub presolve: Option<(usize, String, usize)>,
    /// Largest joint-angle RMSE of the hips, knees and ankles [deg].
    pub angle_rmse_deg: f64,
    /// Vertical GRF RMSE of the right and left foot [% of body weight].
    pub vertical_grf_percent_bw: [f64; 2],
    /// Iteration from which the hybrid Hessian was exact (None: never).
    pub exact_hessian_from: Option<usize>,
    /// Final objective (tracking cost, dimensionless).
    pub objective: f64,
    /// Number of NLP variables (with the static parameters).
    pub variables: usize,
    /// Wall time of the solve [s].
    pub time_total_s: f64,
    /// Time in NLP function evaluations [s].
    pub time_evaluations_s: f64,
    /// Time in the KKT linear solver [s].
    pub time_linear_solver_s: f64,
    /// Time in the numeric KKT factorisations [s].
    pub time_factorisation_s: f64,
    /// CPU time of the process, user and system [s].
    pub cpu_s: Option<f64>,
    /// Resident-set high-water mark of the process [KiB] (None: not on Linux).
    pub peak_rss_kib: Option<u64>,
}

/// Run `stride bench track`.
pub fn run(a: TrackBenchArgs) -> anyhow::Result<()> {
    track_presolve_for(a.presolve_mesh, &settings(a.mesh, a.generic)?)?;
    if a.hessian.is_empty() {
        bail!("no hessian given");
    }
    for h in &a.hessian {
        predict_cmd::parse_hessian(Some(h), "ipm")?;
    }
    if a.max_iter == 0 {
        bail!("--max-iter 0: at least one iteration is needed");
    }
    let exe = std::env::current_exe().context("locating the stride executable")?;
    println!(
        "## Tracking of gait_1 (3.45–4.25 s, {} mesh intervals, {}, tol 1e-4, max {} iterations); \
         one child process per case, one thread\n",
        a.mesh,
        if a.generic {
            "generic contact spheres"
        } else {
            "contact calibration: 18 static parameters"
        },
        a.max_iter
    );
    println!(
        "| Hessian | status | presolve | iterations | exact from | objective | angle RMSE ° | vertical GRF RMSE % BW | variables | process s | CPU s | solve s | evaluations s | linear s | factorisations s | peak RSS MiB |"
    );
    println!("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|");
    std::io::stdout().flush()?;
    for h in &a.hessian {
        let mut cmd = Command::new(&exe);
        cmd.args(["bench", "track-one", "--mesh", &a.mesh.to_string()])
            .args(["--hessian", h.trim(), "--max-iter", &a.max_iter.to_string()]);
        if a.generic {
            cmd.arg("--generic");
        }
        if let Some(p) = a.presolve_mesh {
            cmd.args(["--presolve-mesh", &p.to_string()]);
        }
        if let Some(m) = a.mu_init {
            cmd.args(["--mu-init", &m.to_string()]);
        }
        println!("{}", case_row(h.trim(), cmd)?);
        std::io::stdout().flush()?;
    }
    Ok(())
}

/// Runs one case's child process and formats its table row.
fn case_row(hessian: &str, mut cmd: Command) -> anyhow::Result<String> {
    let (report, process_s) = crate::bench_child::run_child::<TrackReport>(&mut cmd)?;
    let f2 = |v: f64| format!("{v:.2}");
    Ok(match report {
        Ok(r) => format!(
            "| {hessian} | {} | {} | {} | {} | {:.6} | {:.2} | {:.1} / {:.1} | {} | {} | {} | {} | {} | {} | {} | {} |",
            r.status,
            r.presolve
                .as_ref()
                .map_or("–".into(), |(n, st, it)| format!("{n} intervals: {st}, {it} it")),
            r.iterations,
            r.exact_hessian_from.map_or("–".into(), |i| i.to_string()),
            r.objective,
            r.angle_rmse_deg,
            r.vertical_grf_percent_bw[0],
            r.vertical_grf_percent_bw[1],
            r.variables,
            f2(process_s),
            r.cpu_s.map_or("n/a".into(), f2),
            f2(r.time_total_s),
            f2(r.time_evaluations_s),
            f2(r.time_linear_solver_s),
            f2(r.time_factorisation_s),
            r.peak_rss_kib
                .map_or("n/a".into(), |k| format!("{:.0}", k as f64 / 1024.0)),
        ),
        Err(why) => format!("| {hessian} | {why} | | | | | | | | {process_s:.2} | | | | | | |"),
    })
}

/// The tracking settings of the benchmark, checked.
fn settings(mesh: usize, generic: bool) -> anyhow::Result<TrackSettings> {
    if mesh < 2 {
        bail!("--mesh {mesh}: mesh_intervals must be at least 2");
    }
    Ok(TrackSettings {
        mesh_intervals: mesh,
        calibrate_contact: !generic,
        ..Default::default()
    })
}

/// CPU time of this process, user and system [s] (None: not available).
fn cpu_seconds() -> Option<f64> {
    // SAFETY: `rusage` is plain data, valid when zeroed.
    let mut u: libc::rusage = unsafe { std::mem::zeroed() };
    // SAFETY: getrusage only writes into the struct it is given.
    if unsafe { libc::getrusage(libc::RUSAGE_SELF, &mut u) } != 0 {
        return None;
    }
    let s = |t: libc::timeval| t.tv_sec as f64 + t.tv_usec as f64 * 1e-6;
    Some(s(u.ru_utime) + s(u.ru_stime))
}

/// Run the hidden `stride bench track-one`: solve one case, print its JSON line.
pub fn run_one(a: TrackOneArgs) -> anyhow::Result<()> {
    let settings = settings(a.mesh, a.generic)?;
    let hessian = predict_cmd::parse_hessian(Some(&a.hessian), "ipm")?;
    let mut options = predict_cmd::prediction_options(None, Some(a.max_iter), hessian, None, None)?;
    options.threads = 1;
    if let Some(m) = a.mu_init {
        if !(m > 0.0 && m.is_finite()) {
            bail!("--mu-init {m}: a positive barrier parameter");
        }
        options.mu_init = m;
    }
    let model = stride_model::default_model::default_model();
    let tp = TrackingProblem::new(&model, &settings)?;
    let presolve = track_presolve_for(a.presolve_mesh, &tp.settings)?;
    let solver = predict_cmd::backend("ipm")?;
    let solved = solve_tracking(&model, tp, presolve, solver.as_ref(), &options, &|_, _| {})?;
    let (tp, r) = (&solved.problem, &solved.result);
    let errors = track_output::tracked(tp, &r.x)?
        .errors(tp.problem.body_mass * stride_ocp::problem::GRAVITY);
    let legs = ["hip_flexion", "knee_angle", "ankle_angle"];
    let angle_rmse_deg = errors
        .joint_angles
        .iter()
        .filter(|e| legs.iter().any(|n| e.name.starts_with(n)))
        .fold(0.0, |m: f64, e| m.max(e.rmse));
    let vertical = |foot: &str| {
        errors
            .grf
            .iter()
            .zip(&errors.grf_percent_body_weight)
            .find(|(e, _)| e.name == format!("grf_{foot}_y"))
            .map_or(f64::NAN, |(_, bw)| *bw)
    };
    let report = TrackReport {
        status: format!("{:?}", r.status),
        iterations: r.iterations,
        presolve: solved
            .presolve
            .as_ref()
            .map(|p| (p.mesh_intervals, p.status.clone(), p.iterations)),
        angle_rmse_deg,
        vertical_grf_percent_bw: [vertical("right"), vertical("left")],
        exact_hessian_from: r.exact_hessian_from,
        objective: r.objective,
        variables: r.x.len(),
        time_total_s: r.time_total.as_secs_f64(),
        time_evaluations_s: r.time_evaluations.as_secs_f64(),
        time_linear_solver_s: r.time_linear_solver.as_secs_f64(),
        time_factorisation_s: r.time_factorisation.as_secs_f64(),
        cpu_s: cpu_seconds(),
        peak_rss_kib: crate::bench_child::peak_rss_kib(),
    };
    println!("{}", serde_json::to_string(&report)?);
    Ok(())
}
