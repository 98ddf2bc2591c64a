//! The result folder of a prediction: solver logs, the kept solution's files (OpenSim
//! files, tables, figures: [`crate::outputs`]), `solution.json` and `summary.json`, written
//! whole through one staging folder ([`write_staged`]); and the rewrite of an existing
//! folder with the current definitions.

use crate::error::{read_err, write_err, PredictError};
use crate::predict::{GuessReport, Solved};
use crate::solution::{solution_problem, write_solution, SolutionFile, SOLUTION_FILE};
use serde::Serialize;
use std::fmt::Write as _;
use std::path::Path;
use stride_files::result_dir::{write_staged, ResultKind};
use stride_files::write_atomic;
use stride_model::Model;
use stride_ocp::guess::InitialGuess;
use stride_ocp::node::NodeModel;
use stride_ocp::outcomes::Outcomes;
use stride_ocp::problem::GaitProblem;
use stride_ocp::settings::ProblemSettings;
use stride_ocp::trajectory::Trajectory;
use stride_solve::solver::{IterationRecord, SolverOptions};

/// The summary written to `summary.json`.
#[derive(Clone, Debug, Serialize)]
pub struct Summary {
    /// Which guess was kept.
    pub kept_guess: Option<InitialGuess>,
    /// Every guess's solve.
    pub guesses: Vec<GuessReport>,
    /// Solver backend.
    pub solver: String,
    /// Solver options of every guess's solve (Hessian mode, tolerances).
    pub solver_options: SolverOptions,
    /// Outcome measures of the kept solution.
    pub outcomes: Option<Outcomes>,
    /// The settings solved.
    pub settings: ProblemSettings,
    /// Body mass of the model [kg] (what the per-kilogram quantities are divided by).
    pub body_mass: f64,
    /// Number of NLP variables and constraints.
    pub nlp_size: [usize; 2],
    /// Unit of every physical quantity in this file, by key.
    pub units: std::collections::BTreeMap<&'static str, &'static str>,
}

/// The iteration log as CSV (one header line, one line per iteration).
pub fn log_csv(records: &[IterationRecord]) -> String {
    let mut log =
        String::from("iter,objective,inf_pr,inf_du,mu,alpha_pr,alpha_du,regularisation,line_search_trials,factorisations,elapsed_s\n");
    for r in records {
        let _ = writeln!(
            log,
            "{},{},{},{},{},{},{},{},{},{},{}",
            r.iter,
            r.objective,
            r.inf_pr,
            r.inf_du,
            r.mu,
            r.alpha_pr,
            r.alpha_du,
            r.regularisation,
            r.ls_trials,
            r.factorisations,
            r.elapsed.as_secs_f64()
        );
    }
    log
}

/// Write every result file of a solved problem into `out` atomically: files go to a
/// staging folder beside `out` that replaces `out` only when complete ([`write_staged`]).
/// `out` must be free or a stride prediction result ([`stride_files::result_dir::inspect`]).
pub fn write_results(
    problem: &GaitProblem,
    solved: &[Solved],
    kept: Option<usize>,
    solver_name: &str,
    options: &SolverOptions,
    out: &Path,
) -> Result<Summary, PredictError> {
    let io = |e| write_err(out, e);
    write_staged(out, "partial", ResultKind::Prediction, io, |tmp| {
        write_results_into(problem, solved, kept, solver_name, options, tmp)
    })
}

/// Write every result file of a solved problem into the existing folder `dir` (a staging
/// folder its caller puts in place, e.g. a study's case folder in flight).
pub fn write_results_into(
    problem: &GaitProblem,
    solved: &[Solved],
    kept: Option<usize>,
    solver_name: &str,
    options: &SolverOptions,
    dir: &Path,
) -> Result<Summary, PredictError> {
    let node = NodeModel::new(problem)?;
    let mut outcomes = None;
    // Solver logs of every guess (and of its coarse-mesh presolve).
    for s in solved {
        let p = dir.join(format!("solver_log_{}.csv", s.report.guess));
        write_atomic(&p, log_csv(&s.result.log).as_bytes()).map_err(|e| write_err(&p, e))?;
        if let Some(pre) = &s.report.presolve {
            let p = dir.join(format!("solver_log_{}_presolve.csv", s.report.guess));
            write_atomic(&p, log_csv(&pre.log).as_bytes()).map_err(|e| write_err(&p, e))?;
        }
    }
    if let Some(k) = kept {
        let mesh = problem.mesh_solution(&node, &solved[k].result.x)?;
        let cycle = problem.gait_cycle(&mesh);
        outcomes = Some(problem.outcomes(&node, &mesh, &cycle)?);
        crate::outputs::write_cycle(problem, &node, &cycle, dir)?;
        let x = &solved[k].result.x;
        write_solution(dir, &SolutionFile::new(&problem.settings, x, &cycle))?;
    }
    let summary = Summary {
        kept_guess: kept.map(|k| solved[k].report.guess),
        guesses: solved.iter().map(|s| s.report.clone()).collect(),
        solver: solver_name.into(),
        solver_options: options.clone(),
        outcomes,
        settings: problem.settings.clone(),
        body_mass: problem.body_mass,
        nlp_size: [problem.layout.len(), 0],
        units: crate::outputs::summary_units(),
    };
    let p = dir.join("summary.json");
    let json = serde_json::to_string_pretty(&summary).map_err(|e| write_err(&p, e))?;
    write_atomic(&p, json.as_bytes()).map_err(|e| write_err(&p, e))?;
    Ok(summary)
}

/// Rewrite the reconstructed-cycle files of a result folder (motion, ground reaction
/// forces, tables, figures) and the outcomes in its `summary.json` from the solution `x`
/// (scaled NLP vector) with the current definitions; every other file and subfolder is kept.
/// `also` may add or replace files in the new folder (it gets the cycle). The new folder is
/// built beside `out` and swapped in: an interruption leaves the old folder or the new one.
pub fn rewrite_results(
    problem: &GaitProblem,
    x: &[f64],
    out: &Path,
    also: impl FnOnce(&Trajectory, &Path) -> Result<(), PredictError>,
) -> Result<Outcomes, PredictError> {
    let summary_path = out.join("summary.json");
    let text = std::fs::read_to_string(&summary_path).map_err(|e| read_err(&summary_path, e))?;
    let mut summary: serde_json::Value =
        serde_json::from_str(&text).map_err(|e| read_err(&summary_path, e))?;
    if !summary.is_object() {
        return Err(read_err(&summary_path, "not a JSON object"));
    }
    let node = NodeModel::new(problem)?;
    let mesh = problem.mesh_solution(&node, x)?;
    let cycle = problem.gait_cycle(&mesh);
    let outcomes = problem.outcomes(&node, &mesh, &cycle)?;
    let io = |e| write_err(out, e);
    write_staged(out, "rewrite", ResultKind::Prediction, io, |tmp| {
        // the files stride did not write stay in `out` and are moved over on commit
        let foreign = stride_files::result_dir::foreign_entries(out).unwrap_or_default();
        copy_tree(out, tmp, &foreign)?;
        crate::outputs::write_cycle(problem, &node, &cycle, tmp)?;
        summary["outcomes"] =
            serde_json::to_value(&outcomes).map_err(|e| write_err(&summary_path, e))?;
        summary["body_mass"] = serde_json::json!(problem.body_mass);
        summary["units"] = serde_json::to_value(crate::outputs::summary_units())
            .map_err(|e| write_err(&summary_path, e))?;
        let p = tmp.join("summary.json");
        let json = serde_json::to_string_pretty(&summary).map_err(|e| write_err(&p, e))?;
        write_atomic(&p, json.as_bytes()).map_err(|e| write_err(&p, e))?;
        also(&cycle, tmp)
    })?;
    Ok(outcomes)
}

/// Copy the files and subfolders of `from` into the existing folder `to`, but the
/// entries named in `skip`.
fn copy_tree(from: &Path, to: &Path, skip: &[String]) -> Result<(), PredictError> {
    for entry in std::fs::read_dir(from).map_err(|e| write_err(from, e))? {
        let entry = entry.map_err(|e| write_err(from, e))?;
        if skip
            .iter()
            .any(|n| *n == *entry.file_name().to_string_lossy())
        {
            continue;
        }
        let dst = to.join(entry.file_name());
        if entry.file_type().map_err(|e| write_err(from, e))?.is_dir() {
            std::fs::create_dir(&dst).map_err(|e| write_err(&dst, e))?;
            copy_tree(&entry.path(), &dst, &[])?;
        } else {
            std::fs::copy(entry.path(), &dst).map_err(|e| write_err(&dst, e))?;
        }
    }
    Ok(())
}

/// What [`rewrite_folder`] did with a result folder.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Rewritten {
    /// The cycle files, outcomes and solution cycle were rewritten.
    Rewritten,
    /// The folder has no kept solution (not converged, or no `solution.json`): untouched.
    NoSolution,
}

/// Rewrite a result folder's files (motion, tables, figures, outcomes in `summary.json`)
/// and the cycle of its `solution.json` from its solution with the current definitions,
/// e.g. after a change in how the gait cycle is reconstructed. The solver files (logs,
/// iterations, times) are kept; the folder is swapped in whole.
pub fn rewrite_folder(model: &Model, dir: &Path) -> Result<Rewritten, PredictError> {
    let summary = std::fs::read_to_string(dir.join("summary.json"))
        .ok()
        .and_then(|t| serde_json::from_str::<serde_json::Value>(&t).ok());
    let kept = summary.is_some_and(|s| !s["kept_guess"].is_null());
    if !kept || !dir.join(SOLUTION_FILE).exists() {
        return Ok(Rewritten::NoSolution);
    }
    let (sol, problem) = solution_problem(model, dir)?;
    rewrite_results(&problem, &sol.x, dir, |cycle, tmp| {
        write_solution(tmp, &SolutionFile::new(&sol.settings, &sol.x, cycle))
    })?;
    Ok(Rewritten::Rewritten)
}
