//! The real case runner: builds the gait problem of a case, solves it from its initial
//! guess (standard or continuation), writes `stride predict`'s result files, the solution
//! (`solution.json`, for continuation guesses of later cases and rewrites) and the outcome
//! measures.

use crate::analysis::energy_phase_correlation;
use crate::runner::CaseRunner;
use crate::spec::{Case, CaseGuess};
use crate::store::{CaseOutcome, Metrics};
use std::path::Path;
use stride_model::Model;
use stride_ocp::bounds::bounds_data;
use stride_ocp::guess::ContinuationKind;
use stride_ocp::measures::ConditionMeasures;
use stride_ocp::node::NodeModel;
use stride_ocp::problem::{GaitProblem, GRAVITY};
use stride_predict::predict::{self, GuessReport, Solved, Stage};
use stride_predict::results;
use stride_solve::solver::{IterationRecord, Solver, SolverOptions};

pub use stride_predict::results::Rewritten;
use stride_predict::solution::{read_solution, solution_problem, write_solution};
pub use stride_predict::solution::{SolutionFile, SOLUTION_FILE};

/// Runs cases with `stride_predict::predict` and a solver backend.
pub struct PredictRunner {
    /// Musculoskeletal model.
    pub model: Model,
    /// Solver backend.
    pub solver: Box<dyn Solver + Sync>,
    /// Solver options (threads = threads per case).
    pub options: SolverOptions,
    /// Also write `solution.json` (the last iterate) for cases that did not converge.
    pub write_unconverged: bool,
    /// Coarse mesh requested for the presolve of standard guesses (`presolve_mesh` of
    /// `[study.solver]`; None: the default of [`predict::presolve_for`]).
    pub presolve_mesh: Option<usize>,
}

fn err(e: impl std::fmt::Display) -> String {
    e.to_string()
}

impl PredictRunner {
    /// Initial NLP vector of a continuation guess from the source case's solution.
    fn continuation_guess(
        &self,
        problem: &GaitProblem,
        kind: ContinuationKind,
        sol: &SolutionFile,
    ) -> Result<Vec<f64>, String> {
        match kind {
            ContinuationKind::FullSolution => {
                let src = GaitProblem::new(&self.model, &sol.settings, &bounds_data(&sol.settings))
                    .map_err(err)?;
                problem.guess_from_full_solution(&src, &sol.x).map_err(err)
            }
            ContinuationKind::PartialSolution => partial_solution_guess(problem, sol),
        }
    }
}

/// Whether a case with initial guess `guess` is presolved on a coarse mesh: every guess
/// whose muscle states start cold (standard and partial-solution guesses), not a
/// full-solution continuation (it starts from a neighbouring optimum).
fn is_presolved(guess: CaseGuess) -> bool {
    !matches!(
        guess,
        CaseGuess::Continuation(ContinuationKind::FullSolution)
    )
}

/// Partial-solution guess for `problem` (any mesh) from a neighbouring solution: the joint
/// positions of its first half cycle (its first N cycle samples, N its mesh intervals).
fn partial_solution_guess(problem: &GaitProblem, sol: &SolutionFile) -> Result<Vec<f64>, String> {
    let n = sol.settings.mesh_intervals.min(sol.cycle_time.len());
    problem
        .guess_from_coordinates(&sol.cycle_time[..n], &sol.cycle_q[..n])
        .map_err(err)
}

/// COM height and forward velocity over a reconstructed cycle → energy phase correlation.
fn com_energy_correlation(
    problem: &GaitProblem,
    q: &[Vec<f64>],
    v: &[Vec<f64>],
) -> Result<f64, String> {
    let model = &problem.model;
    let mut data = stride_multibody::Data::<f64>::new(model).map_err(err)?;
    let (mut y, mut vx) = (Vec::with_capacity(q.len()), Vec::with_capacity(q.len()));
    for (qs, vs) in q.iter().zip(v) {
        let (qm, vm) = (problem.model_coordinates(qs), problem.model_speeds(vs));
        stride_multibody::forward_kinematics(model, &mut data, &qm, &vm).map_err(err)?;
        let (p, vel) = stride_multibody::center_of_mass(model, &data);
        y.push(p[1]);
        vx.push(vel[0]);
    }
    Ok(energy_phase_correlation(
        &y,
        &vx,
        problem.body_mass,
        GRAVITY,
    ))
}

impl CaseRunner for PredictRunner {
    fn run(
        &self,
        case: &Case,
        source: Option<&Path>,
        dir: &Path,
        progress: &(dyn Fn(usize) + Sync),
    ) -> Result<CaseOutcome, String> {
        let options = match case.guess {
            CaseGuess::Continuation(ContinuationKind::FullSolution) => {
                predict::warm_start_options(self.solver.as_ref(), &self.options)
            }
            _ => self.options.clone(),
        };
        let (problem, solved) = match case.guess {
            CaseGuess::Standard(g) => predict::solve_guesses(
                &self.model,
                &case.settings,
                &[g],
                predict::presolve_for(self.presolve_mesh, &case.settings).map_err(err)?,
                self.solver.as_ref(),
                &options,
                &|_, rec| progress(rec.iter),
            )
            .map_err(err)?,
            CaseGuess::Continuation(kind) => {
                let problem =
                    GaitProblem::new(&self.model, &case.settings, &bounds_data(&case.settings))
                        .map_err(err)?;
                let src = source.ok_or("continuation guess without a source case")?;
                let sol = read_solution(src).map_err(err)?;
                let x0 = self.continuation_guess(&problem, kind, &sol)?;
                let tape = predict::record_tape(&problem, &x0).map_err(err)?;
                let progress = |rec: &IterationRecord| progress(rec.iter);
                let presolve = if is_presolved(case.guess) {
                    predict::presolve_for(self.presolve_mesh, &case.settings).map_err(err)?
                } else {
                    None
                };
                let s = match presolve {
                    Some(p) => {
                        let coarse =
                            predict::coarse_problem(&self.model, &case.settings, p).map_err(err)?;
                        let cx0 = self.continuation_guess(&coarse, kind, &sol)?;
                        let coarse_tape = predict::record_tape(&coarse, &cx0).map_err(err)?;
                        predict::solve_presolved(
                            Stage {
                                problem: &coarse,
                                tape: coarse_tape,
                                x0: cx0,
                            },
                            Stage {
                                problem: &problem,
                                tape,
                                x0,
                            },
                            case.guess,
                            self.solver.as_ref(),
                            &options,
                            &|_, rec| progress(rec),
                        )
                    }
                    None => predict::solve_from(
                        &problem,
                        tape,
                        x0,
                        self.solver.as_ref(),
                        &options,
                        &progress,
                    )
                    .map(|r| Solved {
                        report: GuessReport::new(case.guess, &r),
                        result: r,
                    }),
                }
                .map_err(err)?;
                (problem, vec![s])
            }
        };
        let kept = predict::select(&solved);
        let summary =
            results::write_results_into(&problem, &solved, kept, self.solver.name(), &options, dir)
                .map_err(err)?;
        let s = &solved[0];
        let mut outcome = CaseOutcome {
            converged: s.report.converged,
            reason: s.report.status.clone(),
            objective: Some(s.report.objective),
            iterations: Some(s.report.iterations),
            metrics: None,
            solution_written: false,
        };
        let saved = kept.or((self.write_unconverged && !solved.is_empty()).then_some(0));
        if let Some(k) = saved {
            let node = NodeModel::new(&problem).map_err(err)?;
            let mesh = problem
                .mesh_solution(&node, &solved[k].result.x)
                .map_err(err)?;
            let cycle = problem.gait_cycle(&mesh);
            if let (Some(_), Some(o)) = (kept, summary.outcomes.as_ref()) {
                let corr = com_energy_correlation(&problem, &cycle.q, &cycle.v).ok();
                outcome.metrics = Some(Metrics {
                    cost_of_transport: o.cost_of_transport,
                    stride_length: o.stride_length,
                    stride_frequency: o.stride_frequency,
                    step_width: o.step_width,
                    double_support_fraction: o.double_support_fraction,
                    energy_phase_correlation: corr,
                });
            }
            if kept.is_none() {
                // `write_results` wrote the kept solution; the last iterate of an
                // unconverged solve only here.
                let sol = SolutionFile::new(&case.settings, &solved[k].result.x, &cycle);
                write_solution(dir, &sol).map_err(err)?;
            }
            outcome.solution_written = true;
        }
        Ok(outcome)
    }
}

/// Condition measures (`stride_ocp::measures`) of a finished case recomputed from its
/// `solution.json`, so that a report uses the current definitions for cases solved by an
/// earlier version.
pub fn measures_from_solution(model: &Model, dir: &Path) -> Result<ConditionMeasures, String> {
    let (sol, problem) = solution_problem(model, dir).map_err(err)?;
    let node = NodeModel::new(&problem).map_err(err)?;
    let mesh = problem.mesh_solution(&node, &sol.x).map_err(err)?;
    problem
        .condition_measures(&problem.gait_cycle(&mesh))
        .map_err(err)
}

/// Rewrite a finished case folder from its solution with the current definitions
/// ([`stride_predict::results::rewrite_folder`]).
pub fn rewrite_case(model: &Model, dir: &Path) -> Result<Rewritten, String> {
    stride_predict::results::rewrite_folder(model, dir).map_err(err)
}

/// Build every case's problem once (model changes, bounds) and check the presolve mesh
/// against each standard-guess case's mesh, so that a case the model cannot take (unknown
/// muscle, missing body) or an impossible presolve is an error naming the case before
/// anything runs.
pub fn check_cases(
    model: &Model,
    cases: &[Case],
    presolve_mesh: Option<usize>,
) -> Result<(), String> {
    for c in cases {
        GaitProblem::new(model, &c.settings, &bounds_data(&c.settings))
            .map_err(|e| format!("case `{}`: {e}", c.name))?;
        if is_presolved(c.guess) {
            predict::presolve_for(presolve_mesh, &c.settings)
                .map_err(|e| format!("case `{}`: [study.solver] {e}", c.name))?;
        }
    }
    Ok(())
}
