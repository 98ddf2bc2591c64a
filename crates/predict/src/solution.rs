//! The kept solution of a result folder (`solution.json`): the settings, the optimal NLP
//! vector and the reconstructed cycle's coordinates. `stride predict` and every study case
//! write it, so that a folder can be rewritten with the current definitions
//! ([`rewrite_folder`]) and serve as the source of a continuation guess.

use crate::predict::{bounds_data, read_err, rewrite_results, write_err, PredictError};
use crate::problem::GaitProblem;
use crate::settings::ProblemSettings;
use crate::trajectory::Trajectory;
use serde::{Deserialize, Serialize};
use std::path::Path;
use stride_model::storage::write_atomic;
use stride_model::Model;

/// File with a result folder's optimal NLP vector and its reconstructed cycle coordinates.
pub const SOLUTION_FILE: &str = "solution.json";

/// The solution of a finished prediction or study case.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct SolutionFile {
    /// Settings the solution belongs to.
    pub settings: ProblemSettings,
    /// Scaled NLP variable vector of the kept solve.
    pub x: Vec<f64>,
    /// Sample times of the reconstructed gait cycle [s] (from right heel strike).
    pub cycle_time: Vec<f64>,
    /// Coordinates of the reconstructed cycle [rad or m], problem order.
    pub cycle_q: Vec<Vec<f64>>,
}

impl SolutionFile {
    /// The solution `x` of a problem with `settings`, with its reconstructed `cycle`.
    pub fn new(settings: &ProblemSettings, x: &[f64], cycle: &Trajectory) -> Self {
        SolutionFile {
            settings: settings.clone(),
            x: x.to_vec(),
            cycle_time: cycle.time.clone(),
            cycle_q: cycle.q.clone(),
        }
    }
}

/// The `solution.json` of a result folder.
pub fn read_solution(dir: &Path) -> Result<SolutionFile, PredictError> {
    let p = dir.join(SOLUTION_FILE);
    let text = std::fs::read_to_string(&p).map_err(|e| read_err(&p, e))?;
    serde_json::from_str(&text).map_err(|e| read_err(&p, e))
}

/// Write `sol` as the `solution.json` of `dir`, atomically.
pub fn write_solution(dir: &Path, sol: &SolutionFile) -> Result<(), PredictError> {
    let p = dir.join(SOLUTION_FILE);
    let json = serde_json::to_string(sol).map_err(|e| write_err(&p, e))?;
    write_atomic(&p, json.as_bytes()).map_err(|e| write_err(&p, e))
}

/// A folder's `solution.json` and the problem of its settings built with `model`, checked
/// to fit (same number of variables).
pub fn solution_problem(
    model: &Model,
    dir: &Path,
) -> Result<(SolutionFile, GaitProblem), PredictError> {
    let sol = read_solution(dir)?;
    let problem = GaitProblem::new(model, &sol.settings, &bounds_data(&sol.settings))?;
    if sol.x.len() != problem.layout.len() {
        let reason = format!(
            "{} variables, the problem of its settings has {}",
            sol.x.len(),
            problem.layout.len()
        );
        return Err(read_err(&dir.join(SOLUTION_FILE), reason));
    }
    Ok((sol, problem))
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
