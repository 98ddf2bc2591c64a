//! Tracking solves with mesh sequencing: a tracking problem is first solved on a coarse
//! mesh over the same window and its optimum, resampled, starts the requested mesh — the
//! prediction's presolve ([`crate::predict::solve_sequenced`], decision 0005).

use crate::error::PredictError;
use crate::predict::{solve_sequenced, MeshProblem, MeshStage, Presolve, PresolveReport};
use stride_model::Model;
use stride_ocp::tracking::{TrackError, TrackSettings, TrackingProblem};
use stride_solve::solver::{IterationRecord, SolveResult, Solver, SolverOptions};

/// Default coarse mesh of a tracking presolve: none. On gait_1 (50 intervals, contact
/// calibration, one core) the presolve reaches a lower optimum than the cold solve from the
/// measured kinematics (objective 0.0615 against 0.1617) but takes longer (97 s of CPU
/// with 25 coarse intervals, 172 s with 10, against 60 s): its warm fine stage needs
/// 140–257 exact-Hessian iterations, the cold hybrid solve 110.
pub const TRACK_PRESOLVE_MESH: Option<usize> = None;

fn track_err(e: TrackError) -> PredictError {
    PredictError::Track(e)
}

impl MeshProblem for TrackingProblem {
    fn mesh_intervals(&self) -> usize {
        self.settings.mesh_intervals
    }

    fn solve_from(
        &self,
        x0: Vec<f64>,
        solver: &(dyn Solver + Sync),
        options: &SolverOptions,
        progress: &(dyn Fn(&IterationRecord) + Sync),
    ) -> Result<SolveResult, PredictError> {
        TrackingProblem::solve_from(self, x0, solver, options, progress).map_err(track_err)
    }

    fn start_from(&self, coarse: &Self, x: &[f64]) -> Result<Vec<f64>, PredictError> {
        TrackingProblem::start_from(self, coarse, x).map_err(track_err)
    }
}

/// The presolve of a tracking problem with `settings` for the requested coarse mesh
/// (`--presolve-mesh`, `presolve_mesh` of `[solver]`): unset, [`TRACK_PRESOLVE_MESH`]; 0
/// for none; otherwise at least 2 intervals and fewer than the mesh.
pub fn track_presolve_for(
    requested: Option<usize>,
    settings: &TrackSettings,
) -> Result<Option<Presolve>, PredictError> {
    crate::predict::presolve_of_mesh(
        requested.or(TRACK_PRESOLVE_MESH),
        settings.mesh_intervals,
        usize::MAX,
    )
}

/// A solved tracking problem: the problem on the requested mesh, its solve, and the coarse
/// solve it started from (none without a presolve).
pub struct TrackSolved {
    /// The problem on the requested mesh.
    pub problem: TrackingProblem,
    /// The solve of the requested mesh.
    pub result: SolveResult,
    /// The coarse solve (absent without a presolve).
    pub presolve: Option<PresolveReport>,
}

/// Solves the tracking problem `fine` (of `model`), with `presolve` first on that coarser
/// mesh over the same window (warm start of the requested mesh from its optimum) or else
/// straight from the measured kinematics. `progress` gets every iteration with its mesh.
pub fn solve_tracking(
    model: &Model,
    fine: TrackingProblem,
    presolve: Option<Presolve>,
    solver: &(dyn Solver + Sync),
    options: &SolverOptions,
    progress: &(dyn Fn(MeshStage, &IterationRecord) + Sync),
) -> Result<TrackSolved, PredictError> {
    let mesh = fine.settings.mesh_intervals;
    let Some(p) = presolve.filter(|p| p.mesh_intervals < mesh) else {
        let stage = MeshStage::Final(mesh);
        let x0 = fine.x0.clone();
        let result = MeshProblem::solve_from(&fine, x0, solver, options, &|r| progress(stage, r))?;
        return Ok(TrackSolved {
            problem: fine,
            result,
            presolve: None,
        });
    };
    let coarse_settings = TrackSettings {
        mesh_intervals: p.mesh_intervals,
        ..fine.settings.clone()
    };
    let coarse = TrackingProblem::new(model, &coarse_settings)?;
    let (cx0, fx0) = (coarse.x0.clone(), fine.x0.clone());
    let (result, report) =
        solve_sequenced((&coarse, cx0), (&fine, fx0), solver, options, progress)?;
    Ok(TrackSolved {
        problem: fine,
        result,
        presolve: Some(report),
    })
}
