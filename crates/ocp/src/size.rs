//! Size of a gait problem before it is built: its number of NLP variables (the layout grows
//! linearly with the mesh, so two tiny meshes give it exactly) and an estimate of the peak
//! memory of one solve, so that a mesh that cannot fit is refused before any allocation.

use crate::bounds::bounds_data;
use crate::problem::{GaitProblem, ProblemError};
use crate::settings::ProblemSettings;
use stride_model::Model;

/// Peak memory of one solve that does not grow with the mesh [bytes] (model, tapes,
/// experimental data, the program itself).
pub const BASE_BYTES: f64 = 100e6;
/// Peak memory of one solve per NLP variable [bytes]: Jacobian and Hessian values, the
/// factorised KKT matrix, iterates. Measured with the exact Hessian (the largest case) on
/// the data-informed walking guess: 285 MB peak at 20 intervals (29,511 variables), 571 MB
/// at 50 (73,401), i.e. 6.5 kB per variable over a 93 MB base; rounded up.
pub const BYTES_PER_VARIABLE: f64 = 7e3;

/// Size of one solve.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SizeEstimate {
    /// NLP variables.
    pub variables: usize,
    /// Estimated peak memory of one solve [bytes].
    pub peak_bytes: f64,
}

/// Number of NLP variables of `settings` on `model`, from the layouts of 2 and 4 intervals.
pub fn variables(model: &Model, settings: &ProblemSettings) -> Result<usize, ProblemError> {
    let count = |n: usize| -> Result<usize, ProblemError> {
        let s = ProblemSettings {
            mesh_intervals: n,
            ..settings.clone()
        };
        Ok(GaitProblem::new(model, &s, &bounds_data(&s))?.layout.len())
    };
    let (two, four) = (count(2)?, count(4)?);
    let per_interval = (four - two) / 2;
    Ok(two + per_interval * settings.mesh_intervals.saturating_sub(2))
}

/// Estimated size of one solve of `settings` on `model`.
pub fn estimate(model: &Model, settings: &ProblemSettings) -> Result<SizeEstimate, ProblemError> {
    let variables = variables(model, settings)?;
    Ok(SizeEstimate {
        variables,
        peak_bytes: BASE_BYTES + BYTES_PER_VARIABLE * variables as f64,
    })
}
