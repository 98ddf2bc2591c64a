//! Tracking simulations (FORMULATION 12.6, the paper's TrackSim): the prediction's model,
//! muscle and contact functions, transcription and solver, with a cost that follows
//! measured joint angles, ground reaction forces and torques and net joint torques over a
//! fixed time window (no symmetry, no speed constraint, fixed duration).

pub mod calibration;
pub mod feet;
pub mod ground_reactions;
pub mod motion_columns;
pub mod series;
pub mod trial;

pub use crate::tracking_terms::{TrackedModel, TrackingTerms, TrackingWeights};

use crate::bounds::CoordinateBounds;
use crate::guess::{assemble, CoordinateGuess, MuscleGuess};
use crate::layout::Point;
use crate::node::NodeModel;
use crate::problem::{GaitProblem, ProblemError, Scaling};
use crate::range::Range;
use crate::settings::{CycleKind, ProblemSettings};
use crate::statics::StaticParameters;
use crate::tape_node::TapeNode;
use crate::transcription::{BoundaryTarget, NodeInputs, StaticBlock, TrackingData, Transcription};
use serde::{Deserialize, Serialize};
use std::ops::ControlFlow;
use std::path::PathBuf;
use stride_model::Model;
use stride_solve::solver::{IterationRecord, SolveResult, Solver, SolverOptions};
use trial::{Sample, Trial, TrialError, TrialFiles};

/// Settings of a tracking simulation (`[track]` of a settings file); defaults: the paper's
/// TrackSim of trial gait_1.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct TrackSettings {
    /// Joint angles to track (`.mot`/`.sto`, degrees or radians as its header says,
    /// coordinate names or OpenSim 4 state paths; a coupled coordinate it lacks is computed
    /// from its constraint); unset: the shipped trial gait_1 (with its forces and torques).
    pub motion: Option<PathBuf>,
    /// Ground reaction forces: an OpenSim ExternalLoads file (`.xml`: the bodies the
    /// forces act on, their columns, and the data file) or a `.mot` whose column prefixes
    /// are detected; needed with `motion`.
    pub grf: Option<PathBuf>,
    /// Net joint torques (`.sto`); optional with `motion` (without: neither torques nor
    /// root residuals are tracked).
    pub torques: Option<PathBuf>,
    /// Column prefixes of the right and the left foot in a GRF `.mot` file; unset: the
    /// first of [`trial::KNOWN_GRF_PREFIXES`] the file has (not with an ExternalLoads file,
    /// which names its columns).
    pub grf_prefixes: Option<[String; 2]>,
    /// Time window [s] of the trial.
    pub window: [f64; 2],
    /// Cut-off [Hz] of the zero-lag low-pass filter applied to the joint angles before
    /// they are splined; 0: no filter (simulated motions).
    pub filter_cutoff_hz: f64,
    /// Mesh intervals over the window.
    pub mesh_intervals: usize,
    /// Tracked coordinates; unset: every coordinate but the vertical pelvis translation.
    pub coordinates: Option<Vec<String>>,
    /// Track the net joint torques of the non-root coordinates (when the trial has them).
    pub track_torques: bool,
    /// Weights of the cost.
    pub weights: TrackingWeights,
    /// Calibrate the contact spheres (FORMULATION 12.6): the horizontal centres and radii
    /// of the right-foot spheres, mirrored onto the left foot, are static parameters.
    pub calibrate_contact: bool,
}

impl Default for TrackSettings {
    fn default() -> Self {
        Self {
            motion: None,
            grf: None,
            torques: None,
            grf_prefixes: None,
            window: [3.45, 4.25],
            filter_cutoff_hz: crate::experimental::FILTER_CUTOFF_HZ,
            mesh_intervals: 50,
            coordinates: None,
            track_torques: true,
            weights: TrackingWeights::default(),
            calibrate_contact: false,
        }
    }
}

/// Why a tracking simulation could not be set up or run.
#[derive(Debug, thiserror::Error)]
pub enum TrackError {
    /// Bad settings.
    #[error("track settings: {0}")]
    Settings(String),
    /// The trial data.
    #[error(transparent)]
    Trial(#[from] TrialError),
    /// The problem.
    #[error(transparent)]
    Problem(#[from] ProblemError),
    /// The solver.
    #[error("solver: {0}")]
    Solver(String),
    /// Writing results.
    #[error("{0}")]
    Write(String),
}

impl TrackSettings {
    /// The trial files these settings name (the shipped gait_1 when none).
    pub fn files(&self) -> Result<TrialFiles, TrackError> {
        match (&self.motion, &self.grf) {
            (None, None) if self.torques.is_none() => Ok(TrialFiles::gait_1()),
            (Some(m), Some(g)) => Ok(TrialFiles::read(m, g, self.torques.as_ref())?),
            _ => Err(TrackError::Settings(
                "`motion` and `grf` are given together (or neither, for the shipped trial gait_1)"
                    .into(),
            )),
        }
    }

    fn check(&self) -> Result<(), TrackError> {
        if self.mesh_intervals < 2 {
            return Err(TrackError::Settings(format!(
                "mesh_intervals = {}: at least 2",
                self.mesh_intervals
            )));
        }
        if !(self.filter_cutoff_hz.is_finite() && self.filter_cutoff_hz >= 0.0) {
            return Err(TrackError::Settings(format!(
                "filter_cutoff_hz = {}: a frequency ≥ 0 Hz (0: no filter)",
                self.filter_cutoff_hz
            )));
        }
        let [t0, t1] = self.window;
        if t1.partial_cmp(&t0) != Some(std::cmp::Ordering::Greater) {
            return Err(TrialError::EmptyWindow { t0, t1 }.into());
        }
        if self.grf_prefixes.is_some() && self.grf.as_deref().is_some_and(trial::is_external_loads)
        {
            return Err(TrackError::Settings(
                "`grf_prefixes` is for a GRF .mot file; the ExternalLoads file `grf` names its columns"
                    .into(),
            ));
        }
        let w = &self.weights;
        let all = [
            w.kinematics,
            w.grf,
            w.grt,
            w.torques,
            w.activations,
            w.slack_controls,
        ];
        if all.iter().any(|v| !(v.is_finite() && *v >= 0.0)) {
            return Err(TrackError::Settings(
                "weights must be finite and ≥ 0".into(),
            ));
        }
        Ok(())
    }
}

/// A tracking problem ready to solve.
pub struct TrackingProblem {
    /// The gait problem (model, layout, bounds and scaling from the trial).
    pub problem: GaitProblem,
    /// What the cost tracks.
    pub terms: TrackingTerms,
    /// The trial.
    pub trial: Trial,
    /// Trial time of every collocation point (interval-major) [s].
    pub times: Vec<f64>,
    /// Measured quantities at every collocation point.
    pub samples: Vec<Sample>,
    /// Constant node inputs and the fixed duration.
    pub data: TrackingData,
    /// Initial guess (scaled NLP vector): the measured kinematics, then the static
    /// parameters' initial values.
    pub x0: Vec<f64>,
    /// Static parameters (the contact calibration's, or none).
    pub statics: StaticParameters,
    /// The settings.
    pub settings: TrackSettings,
}

/// Widen `(lo, hi)` by `k` ranges on each side (at least 0.01 of range).
fn widen((lo, hi): (f64, f64), k: f64) -> Range {
    let r = (hi - lo).max(1e-2);
    Range {
        lo: lo - k * r,
        hi: hi + k * r,
    }
}

/// Scale of each GRF/GRT component: max |bound| of the measured range widened by one range,
/// at least a hundredth of the largest component's (a foot without load in the window would
/// otherwise divide its errors by almost nothing).
fn component_scales(samples: &[Sample], pick: impl Fn(&Sample) -> [f64; 6]) -> [f64; 6] {
    let s: [f64; 6] = std::array::from_fn(|c| {
        let (lo, hi) = samples
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), s| {
                (lo.min(pick(s)[c]), hi.max(pick(s)[c]))
            });
        let r = widen((lo, hi), 1.0);
        r.lo.abs().max(r.hi.abs())
    });
    let floor = 0.01 * s.iter().copied().fold(1e-6, f64::max);
    s.map(|v| v.max(floor))
}

impl TrackingProblem {
    /// Build the tracking problem of `model` for `settings`.
    pub fn new(model: &Model, settings: &TrackSettings) -> Result<Self, TrackError> {
        settings.check()?;
        let mut files = settings.files()?;
        let motion = &mut files.motion;
        motion.1 = motion_columns::motion_for_model(&motion.1, model, &motion.0)?;
        let ps = ProblemSettings {
            mesh_intervals: settings.mesh_intervals,
            cycle: CycleKind::FullPeriodic,
            min_distances: Some(Vec::new()),
            ..Default::default()
        };
        let mut problem = GaitProblem::new(model, &ps, &files.motion.1)?;
        let mut settings = settings.clone();
        let grf_columns = match &files.loads {
            Some(loads) => feet::foot_columns(loads, model).map_err(TrialError::from)?,
            None => {
                let prefixes = settings.grf_prefixes.get_or_insert_with(|| {
                    trial::detect_grf_prefixes(&files.grf.1).map(String::from)
                });
                prefixes.clone().map(|p| trial::prefixed_columns(&p))
            }
        };
        let trial = Trial::new(
            &files,
            &problem.gait,
            settings.window,
            &grf_columns,
            settings.filter_cutoff_hz,
        )?;
        // bounds: the trial's range widened by one range (FORMULATION 12.6)
        let [rq, rv, ra] = trial.ranges();
        problem.bounds = CoordinateBounds {
            q: rq.into_iter().map(|r| widen(r, 1.0)).collect(),
            v: rv.into_iter().map(|r| widen(r, 1.0)).collect(),
            a: ra.into_iter().map(|r| widen(r, 1.0)).collect(),
        };
        problem.scaling = Scaling::new(&problem.bounds);
        let terms = tracking_terms(&problem, &trial, &settings, &files.motion.0)?;
        let [t0, t1] = settings.window;
        let n = settings.mesh_intervals;
        let h = (t1 - t0) / n as f64;
        let tau = crate::radau::points();
        let times: Vec<f64> = (0..n)
            .flat_map(|k| (1..=3).map(move |j| t0 + (k as f64 + tau[j]) * h))
            .collect();
        let samples: Vec<Sample> = times.iter().map(|&t| trial.sample(t)).collect();
        let mut terms = terms;
        terms.grf_scale = component_scales(&samples, |s| s.grf);
        terms.grt_scale = component_scales(&samples, |s| s.grt);
        let node_data = samples
            .iter()
            .flat_map(|s| node_constants(&problem, &terms, s))
            .collect();
        let boundary = boundary_targets(&problem, &terms, [trial.sample(t0), trial.sample(t1)]);
        let data = TrackingData {
            node_data,
            n_data: terms.n_data(),
            duration: t1 - t0,
            boundary,
        };
        let statics = if settings.calibrate_contact {
            calibration::contact_parameters(&problem.model)?
        } else {
            StaticParameters::default()
        };
        let mut x0 = initial_guess(&problem, &trial, settings.window);
        x0.extend(statics.scaled_initial());
        Ok(Self {
            statics,
            problem,
            terms,
            trial,
            times,
            samples,
            data,
            x0,
            settings,
        })
    }

    /// The node function of this problem (on `f64`, for post-processing).
    pub fn node(&self) -> Result<NodeModel, TrackError> {
        Ok(NodeModel::new(&self.problem)?
            .with_statics(self.statics.clone())
            .with_tracking(self.terms.clone()))
    }

    /// The inputs of collocation point `i` (interval-major) at the NLP vector `x`.
    pub fn node_inputs(&self, x: &[f64], i: usize) -> Vec<f64> {
        let l = &self.problem.layout;
        let io = NodeInputs {
            nm: l.nm,
            nq: l.nq,
            na: l.na,
        };
        let d = self.data.n_data;
        let mut v: Vec<f64> = io
            .global_indices(l, i / 3, i % 3 + 1)
            .iter()
            .map(|&g| x[g])
            .collect();
        v.extend_from_slice(self.static_variables(x));
        v.extend_from_slice(&self.data.node_data[i * d..(i + 1) * d]);
        v
    }

    /// The scaled static parameters in the NLP vector `x` (after the layout's variables).
    pub fn static_variables<'a>(&self, x: &'a [f64]) -> &'a [f64] {
        let first = self.problem.layout.len();
        &x[first..first + self.statics.len()]
    }

    /// The transcribed NLP, its node function recorded on a tape, starting from the
    /// measured kinematics.
    pub fn transcription(&self) -> Result<Transcription<TapeNode>, TrackError> {
        self.transcription_from(self.x0.clone())
    }

    /// The transcribed NLP starting from the scaled NLP vector `x0` (this mesh's layout,
    /// then the static parameters).
    pub fn transcription_from(&self, x0: Vec<f64>) -> Result<Transcription<TapeNode>, TrackError> {
        let expected = self.problem.layout.len() + self.statics.len();
        if x0.len() != expected {
            return Err(TrackError::Solver(format!(
                "starting point of {} values, the problem has {expected}",
                x0.len()
            )));
        }
        let node = self.node()?;
        let tape = TapeNode::record(&node, &self.node_inputs(&self.x0, 0))?;
        Ok(Transcription::with_statics(
            self.problem.clone(),
            tape,
            x0,
            Some(self.data.clone()),
            StaticBlock::of(&self.statics),
        ))
    }

    /// Solve from the measured kinematics with `solver`; `progress` sees every iteration.
    pub fn solve(
        &self,
        solver: &(dyn Solver + Sync),
        options: &SolverOptions,
        progress: &(dyn Fn(&IterationRecord) + Sync),
    ) -> Result<SolveResult, TrackError> {
        self.solve_from(self.x0.clone(), solver, options, progress)
    }

    /// Solve from the scaled NLP vector `x0` with `solver`; `progress` sees every iteration.
    pub fn solve_from(
        &self,
        x0: Vec<f64>,
        solver: &(dyn Solver + Sync),
        options: &SolverOptions,
        progress: &(dyn Fn(&IterationRecord) + Sync),
    ) -> Result<SolveResult, TrackError> {
        let tr = self.transcription_from(x0)?;
        let run = || {
            solver.solve(&tr, options, &mut |rec: &IterationRecord| {
                progress(rec);
                ControlFlow::Continue(())
            })
        };
        crate::threads::with_threads(options.threads, run)
            .map_err(|e| TrackError::Solver(e.to_string()))?
            .map_err(|e| TrackError::Solver(e.to_string()))
    }

    /// A starting point of this problem from the solution `x` of the same tracking problem
    /// on another mesh (`coarse`): the mesh part resampled along the collocation
    /// polynomials ([`GaitProblem::guess_from_full_solution`]), the static parameters
    /// copied.
    pub fn start_from(&self, coarse: &TrackingProblem, x: &[f64]) -> Result<Vec<f64>, TrackError> {
        let n = coarse.problem.layout.len();
        if x.len() != n + coarse.statics.len() || coarse.statics.len() != self.statics.len() {
            return Err(TrackError::Solver(format!(
                "a solution of {} values cannot start a problem of {} static parameters",
                x.len(),
                self.statics.len()
            )));
        }
        let mut out = self
            .problem
            .guess_from_full_solution(&coarse.problem, &x[..n])
            .map_err(|e| TrackError::Solver(format!("resampling the coarse solution: {e}")))?;
        out.extend_from_slice(&x[n..]);
        Ok(out)
    }
}

/// The tracked coordinates and torques of `settings` for `problem`.
fn tracking_terms(
    problem: &GaitProblem,
    trial: &Trial,
    settings: &TrackSettings,
    motion_file: &str,
) -> Result<TrackingTerms, TrackError> {
    let g = &problem.gait;
    let coordinates = match &settings.coordinates {
        Some(names) => names
            .iter()
            .map(|n| {
                g.index_of(n).ok_or_else(|| {
                    TrialError::UnknownCoordinate {
                        file: motion_file.into(),
                        column: n.clone(),
                    }
                    .into()
                })
            })
            .collect::<Result<Vec<_>, TrackError>>()?,
        None => (0..g.nq())
            .filter(|&i| i != g.vertical_translation)
            .collect(),
    };
    let root = g.root();
    let torques = if settings.track_torques && trial.has_torques() {
        (0..g.nq()).filter(|i| !root.contains(i)).collect()
    } else {
        Vec::new()
    };
    Ok(TrackingTerms {
        coordinates,
        torques,
        n_root: root.len(),
        grf_scale: [1.0; 6],
        grt_scale: [1.0; 6],
        weights: settings.weights,
    })
}

/// Weight of the tracked positions at the first and the last mesh point, in collocation
/// points' worth of the kinematics term: the trapezoid rule's end weight of one interval.
/// Without it the first mesh point is not tracked and the last only with the Radau
/// quadrature's smallest weight (1/9), so the free boundary states follow the effort terms
/// and end up to 2° off a motion the model can reproduce.
pub const BOUNDARY_WEIGHT: f64 = 0.5;

/// The boundary targets of the tracked coordinates: positions at the first and last mesh
/// point against the measured `ends` (window start and end).
fn boundary_targets(
    problem: &GaitProblem,
    terms: &TrackingTerms,
    ends: [Sample; 2],
) -> Vec<BoundaryTarget> {
    let l = &problem.layout;
    let sq = &problem.scaling.q;
    let weight = BOUNDARY_WEIGHT * terms.weights.kinematics / terms.coordinates.len().max(1) as f64;
    let points = [Point::Mesh(0), Point::Mesh(l.n)];
    points
        .iter()
        .zip(&ends)
        .flat_map(|(&p, s)| {
            terms.coordinates.iter().map(move |&i| BoundaryTarget {
                var: l.q(p, i),
                target: s.q[i] / sq[i],
                weight,
            })
        })
        .collect()
}

/// The constant node inputs of one measured sample (order of [`TrackingTerms::n_data`]).
fn node_constants(problem: &GaitProblem, terms: &TrackingTerms, s: &Sample) -> Vec<f64> {
    let sq = &problem.scaling.q;
    let mut d: Vec<f64> = terms.coordinates.iter().map(|&i| s.q[i] / sq[i]).collect();
    d.extend_from_slice(&s.grf);
    d.extend_from_slice(&s.grt);
    d.extend(terms.torques.iter().map(|&i| s.tau[i]));
    let root = problem.gait.root();
    d.extend(root.iter().map(|&i| s.tau.get(i).copied().unwrap_or(0.0)));
    d
}

/// The measured kinematics on the mesh with the default muscle guess.
fn initial_guess(problem: &GaitProblem, trial: &Trial, window: [f64; 2]) -> Vec<f64> {
    let l = &problem.layout;
    let h = (window[1] - window[0]) / l.n as f64;
    let mesh: Vec<Sample> = (0..=l.n)
        .map(|k| trial.sample(window[0] + k as f64 * h))
        .collect();
    let coords = CoordinateGuess {
        q: mesh[..l.n].iter().map(|s| s.q.clone()).collect(),
        v: mesh[..l.n].iter().map(|s| s.v.clone()).collect(),
        a: mesh[..l.n].iter().map(|s| s.a.clone()).collect(),
    };
    let id = |q: &[f64]| q.to_vec();
    let s = &problem.scaling;
    let mut x = assemble(
        l,
        s,
        &coords,
        &MuscleGuess::for_settings(&problem.settings),
        window[1] - window[0],
        problem.gait.forward_translation,
        &id,
        &id,
    );
    let last = &mesh[l.n];
    for i in 0..l.nq {
        x[l.q(Point::Mesh(l.n), i)] = last.q[i] / s.q[i];
        x[l.v(Point::Mesh(l.n), i)] = last.v[i] / s.v[i];
    }
    x
}
