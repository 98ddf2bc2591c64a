//! The kept solution of a result folder (`solution.json`): the settings, the optimal NLP
//! vector and the reconstructed cycle's coordinates. `stride predict` and every study case
//! write it, so that a folder can be rewritten with the current definitions
//! ([`crate::results::rewrite_folder`]) and serve as the source of a continuation guess.

use crate::error::{read_err, write_err, PredictError};
use serde::{Deserialize, Serialize};
use std::path::Path;
use stride_files::write_atomic;
use stride_model::Model;
use stride_ocp::bounds::bounds_data;
use stride_ocp::problem::GaitProblem;
use stride_ocp::settings::ProblemSettings;
use stride_ocp::trajectory::Trajectory;

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
