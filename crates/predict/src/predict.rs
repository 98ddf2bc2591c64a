//! `predict`: build the problem, solve it from several initial guesses (each first on a
//! coarse mesh, or from a neighbouring optimum: continuation) and keep the lowest-cost
//! converged solve. The result folder is written by [`crate::results`].

use crate::error::PredictError;
use serde::Serialize;
use std::sync::Arc;
use stride_model::Model;
use stride_ocp::bounds::bounds_data;
use stride_ocp::data;
use stride_ocp::experimental::Kinematics;
use stride_ocp::guess::{GuessKind, InitialGuess};
use stride_ocp::node::NodeModel;
use stride_ocp::problem::{GaitProblem, ProblemError};
use stride_ocp::settings::{CycleKind, ProblemSettings};
use stride_ocp::tape_node::TapeNode;
use stride_ocp::threads::with_threads;
use stride_ocp::transcription::Transcription;
use stride_solve::solver::{
    ControlFlow, HessianMode, IterationRecord, MuStrategy, SolveResult, SolveStatus, Solver,
    SolverOptions,
};

/// Outcome of one solve from one initial guess.
#[derive(Clone, Debug, Serialize)]
pub struct GuessReport {
    /// The initial guess (standard or continuation).
    pub guess: InitialGuess,
    /// Solver status.
    pub status: String,
    /// Whether it converged.
    pub converged: bool,
    /// Iterations.
    pub iterations: usize,
    /// Final objective.
    pub objective: f64,
    /// Final constraint violation.
    pub constraint_violation: f64,
    /// Wall time [s].
    pub time_total_s: f64,
    /// Time in function evaluations [s].
    pub time_evaluations_s: f64,
    /// Time in the solver itself [s].
    pub time_solver_s: f64,
    /// Time in the KKT factorisations and solves, part of the solver time [s] (absent when
    /// the backend does not report it).
    pub time_linear_solver_s: Option<f64>,
    /// Time in the numeric KKT factorisations, part of the linear-solver time [s] (absent
    /// when the backend does not report it).
    pub time_factorisation_s: Option<f64>,
    /// Time in the triangular solves with the KKT factor, part of the linear-solver time
    /// [s] (absent when the backend does not report it).
    pub time_solves_s: Option<f64>,
    /// Iteration from which the exact Hessian replaced the limited-memory one (hybrid
    /// mode); absent when it never did.
    pub exact_hessian_from: Option<usize>,
    /// The coarse-mesh solve this guess started from (absent without a presolve).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub presolve: Option<PresolveReport>,
}

impl GuessReport {
    /// The report of a finished solve from `guess`.
    pub fn new(guess: impl Into<InitialGuess>, r: &SolveResult) -> Self {
        GuessReport {
            guess: guess.into(),
            status: format!("{:?}", r.status),
            converged: r.status.is_success(),
            iterations: r.iterations,
            objective: r.objective,
            constraint_violation: r.constraint_violation,
            time_total_s: r.time_total.as_secs_f64(),
            time_evaluations_s: r.time_evaluations.as_secs_f64(),
            time_solver_s: r
                .time_total
                .saturating_sub(r.time_evaluations)
                .as_secs_f64(),
            time_linear_solver_s: r.reported_linear_solver_time().map(|t| t.as_secs_f64()),
            time_factorisation_s: (!r.time_factorisation.is_zero())
                .then_some(r.time_factorisation.as_secs_f64()),
            time_solves_s: (r.solves > 0).then_some(r.time_solves.as_secs_f64()),
            exact_hessian_from: r.exact_hessian_from,
            presolve: None,
        }
    }
}

/// One solved guess with its solution.
pub struct Solved {
    /// Report.
    pub report: GuessReport,
    /// Solver result (solution vector and log).
    pub result: SolveResult,
}

/// The scaled NLP vector of initial guess `g` for `problem`; data-informed guesses follow
/// the experimental kinematics of their gait (walking: the bounds data, running: the
/// running half cycle).
pub fn guess_point(problem: &GaitProblem, g: GuessKind) -> Result<Vec<f64>, PredictError> {
    let storage = match g {
        GuessKind::DataInformedRunning => Some(data::running_half_cycle()),
        GuessKind::DataInformedWalking => Some(bounds_data(&problem.settings)),
        GuessKind::QuasiRandom => None,
    };
    let kin = storage
        .map(|s| Kinematics::matching(&s, &problem.gait, "guess kinematics"))
        .transpose()
        .map_err(ProblemError::from)?;
    Ok(problem.initial_guess(g, kin.as_ref())?)
}

/// The transcribed NLP of `model` with `settings` as [`solve_guesses`] builds it (node
/// function recorded on a tape), starting from initial guess `g`.
pub fn transcribe(
    model: &Model,
    settings: &ProblemSettings,
    g: GuessKind,
) -> Result<Transcription<TapeNode>, PredictError> {
    let problem = GaitProblem::new(model, settings, &bounds_data(settings))?;
    let node = NodeModel::new(&problem)?;
    let x0 = guess_point(&problem, g)?;
    let tape = TapeNode::for_problem(&problem, &node, &x0)?;
    Ok(Transcription::new(problem, tape, x0))
}

/// Largest constraint violation (unscaled, max-norm) of a converged prediction.
pub const PREDICTION_CONSTR_VIOL_TOL: f64 = 1e-6;

/// Centrality correctors per iteration of a hybrid-Hessian prediction unless set; they
/// save iterations in the limited-memory phase (decision 0002).
pub const HYBRID_CORRECTORS: usize = 2;

/// The solver options of `stride predict` with stride's interior point and no other
/// setting: scaled optimality tolerance 1e-4, 3000 iterations, the hybrid Hessian (6
/// L-BFGS pairs) with [`HYBRID_CORRECTORS`], adaptive μ, constraint violation
/// ≤ [`PREDICTION_CONSTR_VIOL_TOL`].
pub fn prediction_options() -> SolverOptions {
    SolverOptions {
        tol: 1e-4,
        max_iter: 3000,
        hessian: HessianMode::Hybrid { history: 6 },
        centrality_correctors: HYBRID_CORRECTORS,
        mu_strategy: MuStrategy::Adaptive,
        constr_viol_tol: PREDICTION_CONSTR_VIOL_TOL,
        ..Default::default()
    }
}

/// Initial barrier parameter of a solve that starts from an optimum (a neighbouring case's
/// or a coarser mesh's).
pub const WARM_START_MU: f64 = 1e-4;
/// Bound push of a solve that starts from an optimum (relative to the bound's magnitude).
pub const WARM_START_BOUND_PUSH: f64 = 1e-6;

/// Complementarity tolerance of a warm-started exact-Hessian solve, as a fraction of the
/// requested one: Newton steps from an optimum meet the requested tolerance at μ ≈ 1e-5,
/// where the barrier still holds the objective ~0.3 % above the optimum that the cold hybrid
/// solves (μ ≈ 1e-6 when they stop) reach; one decade more costs a few iterations
/// (decision 0005).
pub const WARM_START_COMPL_FACTOR: f64 = 0.1;

/// Exponent θ_μ of a warm-started exact-Hessian solve's monotone μ decrease: 1, linear
/// (×0.2 per solved barrier problem). IPOPT's superlinear 1.5 takes μ from ~1e-5 straight
/// to its floor, a decade and more below the μ at which the complementarity test above
/// already holds, and the iterations at the floor are short steps cut by the
/// fraction-to-boundary rule (decision 0005).
pub const WARM_START_MU_POWER: f64 = 1.0;

/// Solver options of a solve that starts from an optimum: the interior point starts on the
/// central path of a small μ with the variables barely pushed from their bounds instead of
/// re-centring far from it, and a hybrid Hessian becomes the exact Hessian from the first
/// iteration (the quasi-Newton phase exists to get far from the optimum; near it, it only
/// delays the Newton steps; decision 0005 gives the measurements). An
/// exact-Hessian warm start ends at a tenth of the requested complementarity tolerance
/// ([`WARM_START_COMPL_FACTOR`]) and decreases μ linearly ([`WARM_START_MU_POWER`]); a
/// hybrid turned exact drops its centrality correctors.
/// Backends that cannot warm start get `options` unchanged
/// (they still start from the optimum, cold).
pub fn warm_start_options(solver: &dyn Solver, options: &SolverOptions) -> SolverOptions {
    if !solver.supports_warm_start() {
        return options.clone();
    }
    let hybrid = matches!(options.hessian, HessianMode::Hybrid { .. });
    let hessian = if hybrid {
        HessianMode::Exact
    } else {
        options.hessian
    };
    // Newton steps from an optimum: a tighter end and a linear μ decrease to it
    let (compl_inf_tol, mu_superlinear_power) = if matches!(hessian, HessianMode::Exact) {
        (
            options.compl_inf_tol * WARM_START_COMPL_FACTOR,
            WARM_START_MU_POWER,
        )
    } else {
        (options.compl_inf_tol, options.mu_superlinear_power)
    };
    SolverOptions {
        warm_start: true,
        mu_init: WARM_START_MU,
        bound_push: WARM_START_BOUND_PUSH,
        hessian,
        // correctors pay in a limited-memory phase (one more column of a block solve); a
        // Newton step's corrector costs a refined solve of its own and saves fewer
        // iterations than it costs (decision 0005)
        centrality_correctors: if hybrid {
            0
        } else {
            options.centrality_correctors
        },
        compl_inf_tol,
        mu_superlinear_power,
        ..options.clone()
    }
}

/// Mesh sequencing of [`solve_guesses`]: each standard guess is first solved on a coarser
/// mesh and the problem is then solved from that optimum resampled to the requested mesh.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Presolve {
    /// Mesh intervals of the coarse solve (below the problem's).
    pub mesh_intervals: usize,
}

/// Default coarse mesh of a presolve: 10 intervals per half cycle (20 for a full cycle).
pub const PRESOLVE_MESH: usize = 10;

/// The presolve of a problem with `settings` for the requested coarse mesh (`presolve_mesh`
/// of a study file's `[solver]`, `stride predict --presolve-mesh`): unset,
/// [`PRESOLVE_MESH`] intervals per half cycle when the mesh is finer than that, else none; 0
/// for none; otherwise at least 2 intervals and fewer than the mesh.
pub fn presolve_for(
    requested: Option<usize>,
    settings: &ProblemSettings,
) -> Result<Option<Presolve>, PredictError> {
    let default = match settings.cycle {
        CycleKind::HalfSymmetric => PRESOLVE_MESH,
        CycleKind::FullPeriodic => 2 * PRESOLVE_MESH,
    };
    presolve_of_mesh(requested, settings.mesh_intervals, default)
}

/// The presolve of a problem of `mesh` intervals for the requested coarse mesh: unset,
/// `default` intervals when the mesh is finer than that, else none (`usize::MAX`: none);
/// 0 for none; otherwise at least 2 intervals and fewer than the mesh.
pub fn presolve_of_mesh(
    requested: Option<usize>,
    mesh: usize,
    default: usize,
) -> Result<Option<Presolve>, PredictError> {
    let bad = |reason: String| Err(PredictError::Presolve(reason));
    match requested {
        None if mesh > default => Ok(Some(Presolve {
            mesh_intervals: default,
        })),
        None | Some(0) => Ok(None),
        Some(1) => bad(
            "1: the coarse mesh needs at least 2 intervals (0 turns the presolve off)".into(),
        ),
        Some(c) if c >= mesh => bad(format!(
            "{c}: the coarse mesh must have fewer intervals than the mesh ({mesh}); 0 turns the presolve off"
        )),
        Some(c) => Ok(Some(Presolve { mesh_intervals: c })),
    }
}

/// The coarse solve of a presolved guess, as recorded in `summary.json`.
#[derive(Clone, Debug, Serialize)]
pub struct PresolveReport {
    /// Mesh intervals of the coarse problem.
    pub mesh_intervals: usize,
    /// Solver status of the coarse solve.
    pub status: String,
    /// Whether the fine solve started from the coarse optimum (false: the coarse solve did
    /// not converge, or the fine solve broke down from its optimum, and the fine solve
    /// started from the guess itself).
    pub used: bool,
    /// How the fine solve from the coarse optimum ended when it broke down and the fine mesh
    /// was solved again from the guess (status and iterations); absent otherwise.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub warm_start_failure: Option<String>,
    /// Iterations of the coarse solve.
    pub iterations: usize,
    /// Objective of the coarse optimum.
    pub objective: f64,
    /// Wall time of the coarse solve and the resampling [s].
    pub time_total_s: f64,
    /// Iteration log of the coarse solve (written to `solver_log_<guess>_presolve.csv`).
    #[serde(skip)]
    pub log: Vec<IterationRecord>,
}

/// The node tape of `problem`, recorded at `x0`; one tape serves every solve of the problem.
pub fn record_tape(problem: &GaitProblem, x0: &[f64]) -> Result<Arc<TapeNode>, PredictError> {
    Ok(Arc::new(TapeNode::for_problem(
        problem,
        &NodeModel::new(problem)?,
        x0,
    )?))
}

/// Solves `problem` (its tape `tape`) from `x0` with `options`; `progress` gets every
/// iteration.
pub fn solve_from(
    problem: &GaitProblem,
    tape: Arc<TapeNode>,
    x0: Vec<f64>,
    solver: &(dyn Solver + Sync),
    options: &SolverOptions,
    progress: &(dyn Fn(&IterationRecord) + Sync),
) -> Result<SolveResult, PredictError> {
    let tr = Transcription::new(problem.clone(), tape, x0);
    with_threads(options.threads, || {
        solver.solve(&tr, options, &mut |rec: &IterationRecord| {
            progress(rec);
            ControlFlow::Continue(())
        })
    })
    .map_err(PredictError::Solver)?
    .map_err(|e| PredictError::Solver(e.to_string()))
}

/// The problem of `settings` on the coarse mesh of `presolve`.
pub fn coarse_problem(
    model: &Model,
    settings: &ProblemSettings,
    presolve: Presolve,
) -> Result<GaitProblem, PredictError> {
    let coarse = ProblemSettings {
        mesh_intervals: presolve.mesh_intervals,
        ..settings.clone()
    };
    Ok(GaitProblem::new(model, &coarse, &bounds_data(&coarse))?)
}

/// One mesh of a presolved guess: the problem, its tape and the starting point.
pub struct Stage<'a> {
    /// The problem on this mesh.
    pub problem: &'a GaitProblem,
    /// Its node tape (shared between the guesses solved on it).
    pub tape: Arc<TapeNode>,
    /// Starting point: the guess on the coarse mesh; on the fine mesh the fallback used when
    /// the coarse solve fails.
    pub x0: Vec<f64>,
}

/// The mesh a solver iteration belongs to, with its number of intervals: the coarse mesh of
/// a presolve, or the requested (final) mesh.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MeshStage {
    /// The coarse mesh whose optimum starts the final solve.
    Coarse(usize),
    /// The requested mesh.
    Final(usize),
}

/// Where an iteration reported to the progress callback of [`solve_guesses`] comes from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ProgressSource {
    /// The initial guess being solved.
    pub guess: GuessKind,
    /// The mesh being solved.
    pub stage: MeshStage,
}

/// A problem that can be solved on several meshes: what mesh sequencing needs of it (the
/// gait problem of a prediction, a tracking problem).
pub trait MeshProblem {
    /// Mesh intervals of this problem.
    fn mesh_intervals(&self) -> usize;
    /// Solves this problem from the scaled NLP vector `x0` with `options`; `progress` gets
    /// every iteration.
    fn solve_from(
        &self,
        x0: Vec<f64>,
        solver: &(dyn Solver + Sync),
        options: &SolverOptions,
        progress: &(dyn Fn(&IterationRecord) + Sync),
    ) -> Result<SolveResult, PredictError>;
    /// A starting point of this problem from the solution `x` of the same problem on the
    /// mesh of `coarse` (resampled along the collocation polynomials).
    fn start_from(&self, coarse: &Self, x: &[f64]) -> Result<Vec<f64>, PredictError>;
}

impl MeshProblem for Stage<'_> {
    fn mesh_intervals(&self) -> usize {
        self.problem.layout.n
    }

    fn solve_from(
        &self,
        x0: Vec<f64>,
        solver: &(dyn Solver + Sync),
        options: &SolverOptions,
        progress: &(dyn Fn(&IterationRecord) + Sync),
    ) -> Result<SolveResult, PredictError> {
        solve_from(
            self.problem,
            self.tape.clone(),
            x0,
            solver,
            options,
            progress,
        )
    }

    fn start_from(&self, coarse: &Self, x: &[f64]) -> Result<Vec<f64>, PredictError> {
        self.problem
            .guess_from_full_solution(coarse.problem, x)
            .map_err(|e| PredictError::Solver(format!("presolve: {e}")))
    }
}

/// Mesh sequencing (decision 0005): solves `coarse` from `coarse_x0`, then `fine` from the
/// resampled coarse optimum (warm, [`warm_start_options`]) or, if the coarse solve failed,
/// from `fine_x0` (cold); a warm fine solve that breaks down ([`warm_start_broke_down`]) is
/// solved again from `fine_x0`, recorded in the report's `warm_start_failure`. A hybrid
/// coarse solve stops where μ reaches its floor. The time limit of `options` covers all
/// solves. `progress` gets each iteration with its mesh;
/// iterations and times count from the start of that mesh's solve. Returns the fine solve
/// and the record of the coarse one.
pub fn solve_sequenced<P: MeshProblem>(
    (coarse, coarse_x0): (&P, Vec<f64>),
    (fine, fine_x0): (&P, Vec<f64>),
    solver: &(dyn Solver + Sync),
    options: &SolverOptions,
    progress: &(dyn Fn(MeshStage, &IterationRecord) + Sync),
) -> Result<(SolveResult, PresolveReport), PredictError> {
    let start = std::time::Instant::now();
    // the coarse optimum is only a starting point: a hybrid solve stops where μ reaches
    // its floor instead of converging in exact-Hessian steps (decision 0005)
    let coarse_options = SolverOptions {
        stop_at_mu_floor: matches!(options.hessian, HessianMode::Hybrid { .. }),
        ..options.clone()
    };
    let coarse_stage = MeshStage::Coarse(coarse.mesh_intervals());
    let r = coarse.solve_from(coarse_x0, solver, &coarse_options, &|rec| {
        progress(coarse_stage, rec)
    })?;
    let used = r.status.is_usable_start();
    let (x0, fine_options) = if used {
        let x = fine.start_from(coarse, &r.x)?;
        (x, warm_start_options(solver, options))
    } else {
        (fine_x0.clone(), options.clone())
    };
    let mut report = PresolveReport {
        mesh_intervals: coarse.mesh_intervals(),
        status: format!("{:?}", r.status),
        used,
        warm_start_failure: None,
        iterations: r.iterations,
        objective: r.objective,
        time_total_s: start.elapsed().as_secs_f64(),
        log: r.log,
    };
    let remaining = |o: SolverOptions| SolverOptions {
        time_limit: options
            .time_limit
            .map(|t| t.saturating_sub(start.elapsed())),
        ..o
    };
    let fine_stage = MeshStage::Final(fine.mesh_intervals());
    let fine_progress = |rec: &IterationRecord| progress(fine_stage, rec);
    let mut rf = fine.solve_from(x0, solver, &remaining(fine_options), &fine_progress)?;
    if used && warm_start_broke_down(&rf.status) {
        // the coarse optimum only speeds the fine solve up; a fine solve that breaks down
        // from it (a coarse optimum the fine mesh resolves badly) is solved again from the
        // guess itself, as without a presolve
        report.warm_start_failure = Some(format!(
            "{:?} after {} iterations",
            rf.status, rf.iterations
        ));
        report.used = false;
        rf = fine.solve_from(fine_x0, solver, &remaining(options.clone()), &fine_progress)?;
    }
    Ok((rf, report))
}

/// Solves `coarse` from its starting point, then `fine` from the resampled coarse optimum
/// (warm) or, if the coarse solve failed, from `fine.x0` (cold) ([`solve_sequenced`]). The
/// time limit of `options` covers both solves; the report names `guess` and records the
/// coarse solve. `progress` gets each iteration with its mesh.
pub fn solve_presolved(
    coarse: Stage,
    fine: Stage,
    guess: InitialGuess,
    solver: &(dyn Solver + Sync),
    options: &SolverOptions,
    progress: &(dyn Fn(MeshStage, &IterationRecord) + Sync),
) -> Result<Solved, PredictError> {
    let (mut coarse, mut fine) = (coarse, fine);
    let (cx0, fx0) = (std::mem::take(&mut coarse.x0), std::mem::take(&mut fine.x0));
    let (rf, report) = solve_sequenced((&coarse, cx0), (&fine, fx0), solver, options, progress)?;
    let mut solved = Solved {
        report: GuessReport::new(guess, &rf),
        result: rf,
    };
    solved.report.presolve = Some(report);
    Ok(solved)
}

/// Whether a fine solve from a coarse optimum ended in a breakdown (failed factorisation,
/// infeasibility, stalled or diverging steps) rather than at a limit or on request.
fn warm_start_broke_down(status: &SolveStatus) -> bool {
    matches!(
        status,
        SolveStatus::Failed(_)
            | SolveStatus::Infeasible
            | SolveStatus::SmallStep
            | SolveStatus::Diverging
    )
}

/// Solve `model` with `settings` from each guess with `solver`, the guesses at the same time,
/// each with `options.threads` evaluation threads; with `presolve`, each guess is first
/// solved on that coarser mesh ([`Presolve`]; ignored when it is not coarser than
/// `settings.mesh_intervals`). `progress` receives every iteration of every guess, with the
/// guess and the mesh it belongs to.
pub fn solve_guesses(
    model: &Model,
    settings: &ProblemSettings,
    guesses: &[GuessKind],
    presolve: Option<Presolve>,
    solver: &(dyn Solver + Sync),
    options: &SolverOptions,
    progress: &(dyn Fn(ProgressSource, &IterationRecord) + Sync),
) -> Result<(GaitProblem, Vec<Solved>), PredictError> {
    let problem = GaitProblem::new(model, settings, &bounds_data(settings))?;
    let x0s = guesses
        .iter()
        .map(|&g| guess_point(&problem, g))
        .collect::<Result<Vec<_>, _>>()?;
    let first = x0s
        .first()
        .ok_or_else(|| PredictError::Solver("no initial guess".into()))?;
    let tape = record_tape(&problem, first)?;
    // the coarse problem and its tape, built once for all guesses
    let coarse = match presolve.filter(|p| p.mesh_intervals < settings.mesh_intervals) {
        Some(p) => {
            let coarse = coarse_problem(model, settings, p)?;
            let starts = guesses
                .iter()
                .map(|&g| guess_point(&coarse, g))
                .collect::<Result<Vec<_>, _>>()?;
            let coarse_tape = record_tape(&coarse, &starts[0])?;
            Some((coarse, coarse_tape, starts))
        }
        None => None,
    };
    let results: Vec<Result<Solved, PredictError>> = std::thread::scope(|scope| {
        let handles: Vec<_> = guesses
            .iter()
            .zip(x0s)
            .enumerate()
            .map(|(i, (&g, x0))| {
                let (problem, tape, coarse) = (&problem, tape.clone(), coarse.as_ref());
                scope.spawn(move || {
                    let progress = |stage, rec: &IterationRecord| {
                        progress(ProgressSource { guess: g, stage }, rec)
                    };
                    match coarse {
                        Some((cp, ct, starts)) => solve_presolved(
                            Stage {
                                problem: cp,
                                tape: ct.clone(),
                                x0: starts[i].clone(),
                            },
                            Stage { problem, tape, x0 },
                            g.into(),
                            solver,
                            options,
                            &progress,
                        ),
                        None => {
                            let stage = MeshStage::Final(problem.layout.n);
                            let progress = |rec: &IterationRecord| progress(stage, rec);
                            let r = solve_from(problem, tape, x0, solver, options, &progress)?;
                            Ok(Solved {
                                report: GuessReport::new(g, &r),
                                result: r,
                            })
                        }
                    }
                })
            })
            .collect();
        handles
            .into_iter()
            .map(|h| {
                h.join()
                    .unwrap_or_else(|_| Err(PredictError::Solver("solver thread panicked".into())))
            })
            .collect()
    });
    let solved = results.into_iter().collect::<Result<Vec<_>, _>>()?;
    Ok((problem, solved))
}

/// Index of the lowest-cost converged solve.
pub fn select(solved: &[Solved]) -> Option<usize> {
    solved
        .iter()
        .enumerate()
        .filter(|(_, s)| s.report.converged)
        .min_by(|a, b| a.1.report.objective.total_cmp(&b.1.report.objective))
        .map(|(i, _)| i)
}

#[cfg(test)]
mod tests {
    use super::{
        presolve_for, warm_start_options, Presolve, PRESOLVE_MESH, WARM_START_BOUND_PUSH,
        WARM_START_MU, WARM_START_MU_POWER,
    };
    use stride_ocp::settings::{CycleKind, ProblemSettings};
    use stride_solve::ipm::InteriorPoint;
    use stride_solve::solver::{HessianMode, SolverOptions};

    fn mesh(n: usize) -> ProblemSettings {
        ProblemSettings {
            mesh_intervals: n,
            ..Default::default()
        }
    }

    #[test]
    fn presolve_defaults_below_finer_meshes_and_checks_explicit_values() {
        let coarse = |n| Some(Presolve { mesh_intervals: n });
        // unset: the default coarse mesh when the mesh is finer, none otherwise
        assert_eq!(
            presolve_for(None, &mesh(50)).unwrap(),
            coarse(PRESOLVE_MESH)
        );
        assert_eq!(
            presolve_for(None, &mesh(PRESOLVE_MESH + 1)).unwrap(),
            coarse(PRESOLVE_MESH)
        );
        assert_eq!(presolve_for(None, &mesh(PRESOLVE_MESH)).unwrap(), None);
        assert_eq!(presolve_for(None, &mesh(4)).unwrap(), None);
        // a full cycle: twice the intervals
        let full = |n| ProblemSettings {
            cycle: CycleKind::FullPeriodic,
            ..mesh(n)
        };
        assert_eq!(
            presolve_for(None, &full(100)).unwrap(),
            coarse(2 * PRESOLVE_MESH)
        );
        assert_eq!(presolve_for(None, &full(2 * PRESOLVE_MESH)).unwrap(), None);
        // 0: off; explicit values between 2 and mesh − 1
        assert_eq!(presolve_for(Some(0), &mesh(50)).unwrap(), None);
        assert_eq!(presolve_for(Some(2), &mesh(50)).unwrap(), coarse(2));
        assert_eq!(presolve_for(Some(25), &mesh(100)).unwrap(), coarse(25));
        assert_eq!(presolve_for(Some(49), &mesh(50)).unwrap(), coarse(49));
        for (bad, n, needle) in [
            (1, 50, "presolve_mesh 1: the coarse mesh needs at least 2"),
            (
                50,
                50,
                "presolve_mesh 50: the coarse mesh must have fewer intervals than the mesh (50)",
            ),
            (60, 50, "presolve_mesh 60"),
            (10, 8, "presolve_mesh 10"),
        ] {
            let e = presolve_for(Some(bad), &mesh(n)).unwrap_err().to_string();
            assert!(e.contains(needle), "{e}");
        }
    }

    #[test]
    fn a_warm_start_takes_newton_steps_from_the_first_iteration() {
        let ipm = InteriorPoint::new();
        let lbfgs = HessianMode::LimitedMemory { history: 6 };
        let hybrid = SolverOptions {
            hessian: HessianMode::Hybrid { history: 6 },
            centrality_correctors: 2,
            compl_inf_tol: 1e-4,
            tol: 1e-4,
            ..Default::default()
        };
        let w = warm_start_options(&ipm, &hybrid);
        assert!(w.warm_start);
        assert_eq!(w.centrality_correctors, 0);
        assert_eq!(
            (w.mu_init, w.bound_push),
            (WARM_START_MU, WARM_START_BOUND_PUSH)
        );
        assert_eq!(w.hessian, HessianMode::Exact);
        assert!(
            (w.compl_inf_tol - 1e-5).abs() < 1e-18,
            "{}",
            w.compl_inf_tol
        );
        assert_eq!(w.tol, 1e-4);
        assert_eq!(w.mu_superlinear_power, WARM_START_MU_POWER);
        // an explicit limited-memory Hessian is kept, with its tolerance
        let plain = SolverOptions {
            hessian: lbfgs,
            ..hybrid.clone()
        };
        let w = warm_start_options(&ipm, &plain);
        assert_eq!((w.hessian, w.compl_inf_tol), (lbfgs, 1e-4));
        assert_eq!(w.centrality_correctors, 2);
        assert_eq!(w.mu_superlinear_power, 1.5);
        // an explicit exact Hessian: the tighter complementarity too
        let exact = SolverOptions {
            hessian: HessianMode::Exact,
            ..plain
        };
        let w = warm_start_options(&ipm, &exact);
        assert_eq!(w.hessian, HessianMode::Exact);
        assert!(w.compl_inf_tol < 1.01e-5);
        assert_eq!(w.mu_superlinear_power, WARM_START_MU_POWER);
    }
}
