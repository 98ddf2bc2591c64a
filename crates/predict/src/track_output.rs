//! Results of a tracking simulation: model against measured quantities at the collocation
//! points, tracking errors (RMSE and R²) per quantity, and the result folder (tables,
//! motion, summary, solver log, figures), written atomically.

use crate::figures::{render_files, NamedFigure};
use crate::predict::PresolveReport;
use serde::Serialize;
use std::path::Path;
use stride_files::result_dir::{write_staged, ResultKind};
use stride_files::write_atomic;
use stride_model::storage::Storage;
use stride_model::MotionType;
use stride_ocp::layout::Point;
use stride_ocp::tracking::{TrackError, TrackingProblem};
use stride_plot::color::Color;
use stride_plot::figure::{Figure, Panel, Series};
use stride_solve::solver::{SolveResult, SolverOptions};

/// One tracked channel: model and measured values at the collocation points.
#[derive(Clone, Debug)]
pub struct Channel {
    /// Name (coordinate or `grf_right_y`, …).
    pub name: String,
    /// Unit of the values.
    pub unit: &'static str,
    /// Model values.
    pub model: Vec<f64>,
    /// Measured values.
    pub measured: Vec<f64>,
}

/// Tracking error of one channel.
#[derive(Clone, Debug, Serialize)]
pub struct ChannelError {
    /// Channel name.
    pub name: String,
    /// Unit of the RMSE.
    pub unit: &'static str,
    /// Root-mean-square difference model − measured.
    pub rmse: f64,
    /// Coefficient of determination of the model values as predictions of the measured ones.
    pub r2: f64,
}

impl Channel {
    /// RMSE and R² of this channel.
    pub fn error(&self) -> ChannelError {
        let n = self.measured.len().max(1) as f64;
        let mean = self.measured.iter().sum::<f64>() / n;
        let ss_res: f64 = self
            .model
            .iter()
            .zip(&self.measured)
            .map(|(m, d)| (m - d).powi(2))
            .sum();
        let ss_tot: f64 = self.measured.iter().map(|d| (d - mean).powi(2)).sum();
        ChannelError {
            name: self.name.clone(),
            unit: self.unit,
            rmse: (ss_res / n).sqrt(),
            r2: if ss_tot > 0.0 {
                1.0 - ss_res / ss_tot
            } else {
                f64::NAN
            },
        }
    }
}

/// Model against measured, per quantity.
#[derive(Clone, Debug, Default)]
pub struct Tracked {
    /// Trial time of each collocation point [s].
    pub time: Vec<f64>,
    /// Joint angles [deg] and translations [m] of the tracked coordinates.
    pub angles: Vec<Channel>,
    /// Ground reaction forces [N].
    pub grf: Vec<Channel>,
    /// Ground reaction torques about the ground origin [N m].
    pub grt: Vec<Channel>,
    /// Net joint torques [N m] (empty when not tracked).
    pub torques: Vec<Channel>,
}

/// Tracking errors per quantity (`summary.json`).
#[derive(Clone, Debug, Serialize)]
pub struct TrackingErrors {
    /// Joint angles (RMSE in deg; translations in m).
    pub joint_angles: Vec<ChannelError>,
    /// Ground reaction forces (RMSE in N).
    pub grf: Vec<ChannelError>,
    /// GRF RMSE as % of body weight, per channel in the order of `grf`.
    pub grf_percent_body_weight: Vec<f64>,
    /// Ground reaction torques (RMSE in N m).
    pub grt: Vec<ChannelError>,
    /// Net joint torques (RMSE in N m).
    pub joint_torques: Vec<ChannelError>,
}

const FEET: [&str; 2] = ["right", "left"];
const AXES: [&str; 3] = ["x", "y", "z"];

/// Model and measured quantities of the tracking problem `tp`'s solution `x` at the
/// collocation points.
pub fn tracked(tp: &TrackingProblem, x: &[f64]) -> Result<Tracked, TrackError> {
    let node = tp.node()?;
    let mut ws = node.workspace::<f64>()?;
    let p = &tp.problem;
    let g = &p.gait;
    let deg = |i: usize| g.coordinates[i].motion_type == MotionType::Rotational;
    let unit = |i: usize| if deg(i) { "deg" } else { "m" };
    let conv = |i: usize, v: f64| if deg(i) { v.to_degrees() } else { v };
    let mut t = Tracked {
        time: tp.times.clone(),
        ..Default::default()
    };
    let channel = |name: String, unit| Channel {
        name,
        unit,
        model: Vec::new(),
        measured: Vec::new(),
    };
    t.angles = (0..g.nq())
        .map(|i| channel(g.coordinates[i].name.clone(), unit(i)))
        .collect();
    for (q, name) in [(&mut t.grf, "grf"), (&mut t.grt, "grt")] {
        *q = (0..6)
            .map(|c| channel(format!("{name}_{}_{}", FEET[c / 3], AXES[c % 3]), ""))
            .collect();
    }
    t.grf.iter_mut().for_each(|c| c.unit = "N");
    t.grt.iter_mut().for_each(|c| c.unit = "N m");
    t.torques = tp
        .terms
        .torques
        .iter()
        .map(|&i| channel(g.coordinates[i].name.clone(), "N m"))
        .collect();
    let l = &p.layout;
    for (n, s) in tp.samples.iter().enumerate() {
        let pt = Point::Col(n / 3, n % 3 + 1);
        for (i, c) in t.angles.iter_mut().enumerate() {
            c.model.push(conv(i, x[l.q(pt, i)] * p.scaling.q[i]));
            c.measured.push(conv(i, s.q[i]));
        }
        let out = node.sample(&mut ws, &tp.node_inputs(x, n));
        for c in 0..6 {
            t.grf[c].model.push(out.group_force[c / 3][c % 3]);
            t.grf[c].measured.push(s.grf[c]);
            t.grt[c].model.push(out.group_moment[c / 3][c % 3]);
            t.grt[c].measured.push(s.grt[c]);
        }
        for (k, &i) in tp.terms.torques.iter().enumerate() {
            t.torques[k].model.push(out.tau[i]);
            t.torques[k].measured.push(s.tau[i]);
        }
    }
    // only the tracked coordinates are reported
    let tracked = &tp.terms.coordinates;
    t.angles = t
        .angles
        .into_iter()
        .enumerate()
        .filter(|(i, _)| tracked.contains(i))
        .map(|(_, c)| c)
        .collect();
    Ok(t)
}

impl Tracked {
    /// Tracking errors; `body_weight` [N] gives the GRF errors in % of body weight.
    pub fn errors(&self, body_weight: f64) -> TrackingErrors {
        let e = |v: &[Channel]| v.iter().map(Channel::error).collect::<Vec<_>>();
        let grf = e(&self.grf);
        TrackingErrors {
            grf_percent_body_weight: grf.iter().map(|c| 100.0 * c.rmse / body_weight).collect(),
            joint_angles: e(&self.angles),
            grf,
            grt: e(&self.grt),
            joint_torques: e(&self.torques),
        }
    }

    /// CSV of one quantity: time, then model and measured per channel.
    fn csv(&self, channels: &[Channel]) -> String {
        let mut s = String::from("time_s");
        for c in channels {
            s += &format!(",{0}_model,{0}_measured", c.name);
        }
        s.push('\n');
        for (k, t) in self.time.iter().enumerate() {
            s += &format!("{t}");
            for c in channels {
                s += &format!(",{},{}", c.model[k], c.measured[k]);
            }
            s.push('\n');
        }
        s
    }
}

/// What `summary.json` of a tracking run holds.
#[derive(Serialize)]
pub struct TrackSummary<'a> {
    /// Solver status.
    pub status: String,
    /// Iterations.
    pub iterations: usize,
    /// Cost at the solution.
    pub objective: f64,
    /// Largest constraint violation at the solution.
    pub constraint_violation: f64,
    /// Wall time of the solve [s].
    pub time_total_s: f64,
    /// Number of NLP variables.
    pub nlp_variables: usize,
    /// The coarse-mesh solve the requested mesh started from (absent without a presolve).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub presolve: Option<&'a PresolveReport>,
    /// Tracking errors.
    pub errors: TrackingErrors,
    /// Calibrated static parameters (the contact calibration's, in m), with their bounds
    /// and whether each ends at one.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub static_parameters: Vec<stride_ocp::statics::ParameterValue>,
    /// Settings of the run.
    pub settings: &'a stride_ocp::tracking::TrackSettings,
    /// Solver name and options.
    pub solver: String,
    /// Solver options.
    pub solver_options: &'a SolverOptions,
}

/// Figure of model (line) against measured (dashed) channels, one panel each.
fn figure(name: &'static str, title: &str, t: &Tracked, channels: &[&Channel]) -> NamedFigure {
    let cols = 4;
    let rows = channels.len().div_ceil(cols).max(1);
    let mut f = Figure::new(1100, 260 * rows as u32, rows, cols).title(title);
    for c in channels {
        let panel = Panel::new(c.name.clone(), "time [s]", c.unit)
            .line(Series::new(t.time.clone(), c.measured.clone(), Color::GREY).dash(vec![4.0, 3.0]))
            .line(Series::new(t.time.clone(), c.model.clone(), Color::BLUE));
        f = f.panel(panel);
    }
    NamedFigure { name, figure: f }
}

fn write_err(path: &Path, e: impl std::fmt::Display) -> TrackError {
    TrackError::Write(format!("writing {}: {e}", path.display()))
}

/// Writes the result folder `out` of a solved tracking problem (atomically: a sibling
/// temporary folder replaces `out` when complete) and returns the errors.
pub fn write_results(
    tp: &TrackingProblem,
    r: &SolveResult,
    presolve: Option<&PresolveReport>,
    solver: &str,
    options: &SolverOptions,
    out: &Path,
    extra: &[(String, Vec<u8>)],
) -> Result<TrackingErrors, TrackError> {
    let tracked = tracked(tp, &r.x)?;
    let errors = tracked.errors(tp.problem.body_mass * stride_ocp::problem::GRAVITY);
    let summary = TrackSummary {
        status: format!("{:?}", r.status),
        iterations: r.iterations,
        objective: r.objective,
        constraint_violation: r.constraint_violation,
        time_total_s: r.time_total.as_secs_f64(),
        nlp_variables: tp.problem.layout.len() + tp.statics.len(),
        presolve,
        errors: errors.clone(),
        static_parameters: tp.statics.reports(tp.static_variables(&r.x)),
        settings: &tp.settings,
        solver: solver.into(),
        solver_options: options,
    };
    let mut files: Vec<(String, Vec<u8>)> = vec![
        (
            "summary.json".into(),
            serde_json::to_string_pretty(&summary)
                .map_err(|e| write_err(out, e))?
                .into_bytes(),
        ),
        (
            "joint_angles.csv".into(),
            tracked.csv(&tracked.angles).into_bytes(),
        ),
        ("grf.csv".into(), tracked.csv(&tracked.grf).into_bytes()),
        ("grt.csv".into(), tracked.csv(&tracked.grt).into_bytes()),
        (
            "solver_log.csv".into(),
            crate::results::log_csv(&r.log).into_bytes(),
        ),
        ("motion.mot".into(), motion(tp, &r.x).into_bytes()),
    ];
    if let Some(p) = presolve {
        files.push((
            "solver_log_presolve.csv".into(),
            crate::results::log_csv(&p.log).into_bytes(),
        ));
    }
    if !tracked.torques.is_empty() {
        files.push((
            "joint_torques.csv".into(),
            tracked.csv(&tracked.torques).into_bytes(),
        ));
    }
    if !tp.statics.is_empty() {
        files.extend(calibration_files(tp, &r.x));
    }
    files.extend_from_slice(extra);
    let pick = |v: &[Channel], names: &[&str]| -> Vec<Channel> {
        v.iter()
            .filter(|c| names.iter().any(|n| c.name.starts_with(n)))
            .cloned()
            .collect()
    };
    let legs = ["hip_flexion", "hip_adduction", "knee_angle", "ankle_angle"];
    let angles = pick(&tracked.angles, &legs);
    let torques = pick(&tracked.torques, &legs);
    let mut figs = vec![
        figure(
            "figure_tracking_angles",
            "joint angles: model (blue) and measured (dashed)",
            &tracked,
            &angles.iter().collect::<Vec<_>>(),
        ),
        figure(
            "figure_tracking_grf",
            "ground reaction forces: model (blue) and measured (dashed)",
            &tracked,
            &tracked.grf.iter().collect::<Vec<_>>(),
        ),
    ];
    if !torques.is_empty() {
        figs.push(figure(
            "figure_tracking_torques",
            "joint torques: model (blue) and measured (dashed)",
            &tracked,
            &torques.iter().collect::<Vec<_>>(),
        ));
    }
    files.extend(render_files(&figs).map_err(|e| write_err(out, e))?);
    write_folder(out, &files)?;
    Ok(errors)
}

/// The calibrated contact parameters (`contact_parameters.csv`) and the contact geometry
/// file a prediction reads through the `contact_geometry` setting
/// (`contact_geometry.toml`).
fn calibration_files(tp: &TrackingProblem, x: &[f64]) -> Vec<(String, Vec<u8>)> {
    let scaled = tp.static_variables(x);
    let geometry = stride_ocp::tracking::calibration::calibrated_geometry(
        &tp.problem.model,
        &tp.statics,
        scaled,
    );
    let header = "contact spheres calibrated by `stride track --calibrate-contact` (FORMULATION 12.6); use with the problem setting contact_geometry";
    vec![
        (
            "contact_parameters.csv".into(),
            stride_ocp::tracking::calibration::parameters_csv(&tp.statics, scaled).into_bytes(),
        ),
        (
            "contact_geometry.toml".into(),
            geometry.to_toml(header).into_bytes(),
        ),
    ]
}

/// Model coordinates at the mesh points (OpenSim storage, degrees), trial time.
fn motion(tp: &TrackingProblem, x: &[f64]) -> String {
    let p = &tp.problem;
    let l = &p.layout;
    let g = &p.gait;
    let h = (tp.settings.window[1] - tp.settings.window[0]) / l.n as f64;
    let mut labels = vec!["time".to_string()];
    labels.extend(g.coordinates.iter().map(|c| c.name.clone()));
    let tx = g.forward_translation;
    let rows = (0..=l.n)
        .map(|k| {
            let mut row = vec![tp.settings.window[0] + k as f64 * h];
            row.extend((0..l.nq).map(|i| {
                let v = x[l.q(Point::Mesh(k), i)] * p.scaling.q[i];
                match g.coordinates[i].motion_type {
                    MotionType::Rotational => v.to_degrees(),
                    _ if i == tx => v + tp.trial.tx_offset,
                    _ => v,
                }
            }));
            row
        })
        .collect();
    let s = Storage {
        name: "tracked_motion".into(),
        in_degrees: Some(true),
        labels,
        rows,
    };
    s.to_text().unwrap_or_default()
}

/// Writes `files` into a fresh sibling folder of `out` and swaps it in.
fn write_folder(out: &Path, files: &[(String, Vec<u8>)]) -> Result<(), TrackError> {
    let io = |e| write_err(out, e);
    write_staged(out, "partial", ResultKind::Prediction, io, |tmp| {
        for (f, bytes) in files {
            let p = tmp.join(f);
            write_atomic(&p, bytes).map_err(|e| write_err(&p, e))?;
        }
        Ok(())
    })
}
