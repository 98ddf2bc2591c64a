//! Figures of a predicted gait cycle against the experimental walking data (the paper's
//! Figure 1): joint angles; joint torques, powers and ground reaction forces; muscle
//! activations with EMG envelopes. Also the tables of a cycle in the units of the result
//! files, shared by the CSV writer and the figures.
//!
//! Conventions (prediction and experiment alike): right leg, 0–100 % of the gait cycle from
//! right heel strike; angles in degrees with the sign each axis label states (OpenSim
//! coordinate signs, except the knee, drawn with flexion positive; a torque has the sign of
//! the motion it drives); torques in N m kg⁻¹ and powers in W kg⁻¹ (the experimental N m and W are
//! divided by the subject's 62 kg, the prediction's by the model's body mass); ground
//! reaction forces in % body weight in the ground frame (x forward, y up, z right).
//! Experiment: mean (line) inside its ± 2 SD band. EMG: the mean envelope and its ± 2 SD band are multiplied
//! by one factor per muscle so that the mean's peak equals the peak predicted activation
//! (the paper scales each trial to that peak; only the mean and SD over trials are shipped).

use stride_model::MotionType;
use stride_ocp::data::WalkingReference;
use stride_ocp::problem::{GaitProblem, GRAVITY};
use stride_ocp::trajectory::Trajectory;
use stride_plot::{Band, Color, Figure, LegendEntry, Panel, PlotError, Series};

/// Body mass of the experimental subject [kg] (subject1 of Falisse et al. 2019): divides the
/// experimental torques and powers to N m kg⁻¹ and W kg⁻¹.
pub const SUBJECT_MASS: f64 = 62.0;
/// Pixels per figure unit of the PNG files.
pub const PNG_SCALE: f32 = 2.0;
/// Number of standard deviations on each side of the experimental mean in the bands.
pub const BAND_SD: f64 = 2.0;
/// Colour of the prediction lines.
pub const PREDICTION_COLOR: Color = Color::BLUE;

/// Tables of a gait cycle in the units of the result files: one row per sample.
#[derive(Clone, Debug, Default)]
pub struct CycleTables {
    /// Sample times from right heel strike [s].
    pub time: Vec<f64>,
    /// Body mass of the model [kg].
    pub body_mass: f64,
    /// Coordinate names, problem order.
    pub coordinates: Vec<String>,
    /// Whether each coordinate is a rotation (else a translation).
    pub rotational: Vec<bool>,
    /// Coordinates [deg for rotations, m for translations].
    pub angles: Vec<Vec<f64>>,
    /// Inverse-dynamics generalised forces [N m or N].
    pub torques: Vec<Vec<f64>>,
    /// Joint powers torque × speed [W].
    pub powers: Vec<Vec<f64>>,
    /// Muscle names, problem order.
    pub muscles: Vec<String>,
    /// Muscle activations [0–1].
    pub activations: Vec<Vec<f64>>,
    /// Muscle excitations [0–1].
    pub excitations: Vec<Vec<f64>>,
    /// Labels of the ground reaction force columns (right x, y, z then left x, y, z).
    pub grf_labels: Vec<String>,
    /// Ground reaction forces [% body weight], columns as `grf_labels`.
    pub grf_bw: Vec<Vec<f64>>,
    /// What was simulated, for figure titles: speed and mesh.
    pub caption: String,
    /// Torso rotation about the ground forward axis [deg] (its range is the trunk sway);
    /// `None` for a model without a `torso` body or a planar model.
    pub trunk_sway: Option<Vec<f64>>,
    /// A planar (2D) model: panels of coordinates it does not have and of the lateral
    /// force are left out.
    pub planar: bool,
}

impl CycleTables {
    /// Tables of the reconstructed gait cycle `cycle` of `problem`.
    pub fn new(problem: &GaitProblem, cycle: &Trajectory) -> Self {
        let g = &problem.gait;
        let planar = g.is_planar(&problem.model);
        let to_user = |i: usize, v: f64| {
            if g.coordinates[i].motion_type == MotionType::Rotational {
                v.to_degrees()
            } else {
                v
            }
        };
        let angles = cycle
            .q
            .iter()
            .map(|q| q.iter().enumerate().map(|(i, &v)| to_user(i, v)).collect())
            .collect();
        let powers = cycle
            .torque
            .iter()
            .zip(&cycle.v)
            .map(|(t, v)| t.iter().zip(v).map(|(a, b)| a * b).collect())
            .collect();
        let bw = problem.body_mass * GRAVITY;
        let grf_bw = cycle
            .grf_right
            .iter()
            .zip(&cycle.grf_left)
            .map(|(r, l)| r.iter().chain(l).map(|f| 100.0 * f / bw).collect())
            .collect();
        Self {
            time: cycle.time.clone(),
            body_mass: problem.body_mass,
            coordinates: g.coordinates.iter().map(|c| c.name.clone()).collect(),
            rotational: g
                .coordinates
                .iter()
                .map(|c| c.motion_type == MotionType::Rotational)
                .collect(),
            angles,
            torques: cycle.torque.clone(),
            powers,
            muscles: g
                .muscles
                .iter()
                .map(|&m| problem.model.muscles[m].name.clone())
                .collect(),
            activations: cycle.activation.clone(),
            excitations: problem.excitations(cycle),
            grf_labels: ["right", "left"]
                .iter()
                .flat_map(|s| ["x", "y", "z"].map(|k| format!("{s}_{k}")))
                .collect(),
            grf_bw,
            caption: caption(&problem.settings),
            trunk_sway: (!planar)
                .then(|| problem.trunk_frontal_angles(&cycle.q).ok().flatten())
                .flatten()
                .map(|a| a.iter().map(|v| v.to_degrees()).collect()),
            planar,
        }
    }

    /// Percent of the gait cycle of each sample, plus 100 % (the periodic repetition of the
    /// first sample) at the end: `100·i/n` for i = 0..=n.
    pub fn percent_closed(&self) -> Vec<f64> {
        let n = self.time.len();
        (0..=n)
            .map(|i| 100.0 * i as f64 / n.max(1) as f64)
            .collect()
    }

    /// Column `col` of `rows` times `factor`, closed periodically (first value repeated at
    /// the end); NaN where a row is too short.
    fn column(rows: &[Vec<f64>], col: usize, factor: f64) -> Vec<f64> {
        let mut v: Vec<f64> = rows
            .iter()
            .map(|r| r.get(col).map_or(f64::NAN, |x| x * factor))
            .collect();
        if let Some(&first) = v.first() {
            v.push(first);
        }
        v
    }

    /// Index of the right-side coordinate of reference channel `channel` (`hip_flexion` →
    /// `hip_flexion_r`; whole-body coordinates by their own name).
    pub fn coordinate_index(&self, channel: &str) -> Option<usize> {
        let right = format!("{channel}_r");
        self.coordinates
            .iter()
            .position(|c| *c == right)
            .or_else(|| self.coordinates.iter().position(|c| c == channel))
    }
}

/// Speed and mesh of a prediction as figure titles state them.
fn caption(s: &stride_ocp::settings::ProblemSettings) -> String {
    format!("{:.2} m/s, {}", s.speed, mesh_caption(s))
}

/// The mesh of a prediction as figure captions state it (`50 mesh intervals per half
/// cycle`).
pub fn mesh_caption(s: &stride_ocp::settings::ProblemSettings) -> String {
    let per = match s.cycle {
        stride_ocp::settings::CycleKind::HalfSymmetric => "per half cycle",
        stride_ocp::settings::CycleKind::FullPeriodic => "per cycle",
    };
    format!("{} mesh intervals {per}", s.mesh_intervals)
}

/// Why the figures could not be produced.
#[derive(Debug, thiserror::Error)]
pub enum FigureError {
    /// Building or rendering a figure failed.
    #[error("figure {name}: {source}")]
    Plot {
        /// Figure name.
        name: String,
        /// Cause.
        source: PlotError,
    },
}

/// One figure and the base name of its files.
#[derive(Clone, Debug)]
pub struct NamedFigure {
    /// File base name (`figure_kinematics`, …).
    pub name: &'static str,
    /// The figure.
    pub figure: Figure,
}

/// Quantity of a reference channel and how a panel shows it.
struct PanelSpec {
    /// Panel title.
    title: &'static str,
    /// Reference quantity (`joint_angles`, …).
    quantity: &'static str,
    /// Reference channel.
    channel: &'static str,
    /// y-axis label: the sign convention and the unit.
    unit: &'static str,
    /// Factor from the coordinate's sign to the drawn one (−1 for the knee, drawn with
    /// flexion positive).
    sign: f64,
}

const fn spec(
    title: &'static str,
    quantity: &'static str,
    channel: &'static str,
    unit: &'static str,
) -> PanelSpec {
    PanelSpec {
        title,
        quantity,
        channel,
        unit,
        sign: 1.0,
    }
}

/// A panel drawn with the opposite of the coordinate's sign.
const fn flipped(s: PanelSpec) -> PanelSpec {
    PanelSpec { sign: -1.0, ..s }
}

const DEG: &str = "angle [deg]";

/// Joint-angle panels (right leg and trunk).
const KINEMATICS: [PanelSpec; 12] = [
    spec("Pelvis tilt", "joint_angles", "pelvis_tilt", DEG),
    spec("Pelvis list", "joint_angles", "pelvis_list", DEG),
    spec("Pelvis rotation", "joint_angles", "pelvis_rotation", DEG),
    spec(
        "Hip flexion",
        "joint_angles",
        "hip_flexion",
        "flexion + [deg]",
    ),
    spec(
        "Hip adduction",
        "joint_angles",
        "hip_adduction",
        "adduction + [deg]",
    ),
    spec(
        "Hip rotation",
        "joint_angles",
        "hip_rotation",
        "internal rotation + [deg]",
    ),
    flipped(spec(
        "Knee flexion",
        "joint_angles",
        "knee_angle",
        "flexion + [deg]",
    )),
    spec(
        "Ankle angle",
        "joint_angles",
        "ankle_angle",
        "dorsiflexion + [deg]",
    ),
    spec(
        "Subtalar angle",
        "joint_angles",
        "subtalar_angle",
        "inversion + [deg]",
    ),
    spec(
        "Lumbar extension",
        "joint_angles",
        "lumbar_extension",
        "extension + [deg]",
    ),
    spec("Lumbar bending", "joint_angles", "lumbar_bending", DEG),
    spec("Lumbar rotation", "joint_angles", "lumbar_rotation", DEG),
];

/// Torque, power and ground-reaction-force panels.
const KINETICS: [PanelSpec; 12] = [
    spec(
        "Hip flexion torque",
        "joint_torques",
        "hip_flexion",
        "flexion + [N m/kg]",
    ),
    spec(
        "Hip adduction torque",
        "joint_torques",
        "hip_adduction",
        "adduction + [N m/kg]",
    ),
    spec(
        "Hip rotation torque",
        "joint_torques",
        "hip_rotation",
        "internal rotation + [N m/kg]",
    ),
    flipped(spec(
        "Knee torque",
        "joint_torques",
        "knee_angle",
        "flexion + [N m/kg]",
    )),
    spec(
        "Ankle torque",
        "joint_torques",
        "ankle_angle",
        "dorsiflexion + [N m/kg]",
    ),
    spec(
        "Subtalar torque",
        "joint_torques",
        "subtalar_angle",
        "inversion + [N m/kg]",
    ),
    spec(
        "Hip flexion power",
        "joint_powers",
        "hip_flexion",
        "generation + [W/kg]",
    ),
    spec(
        "Knee power",
        "joint_powers",
        "knee_angle",
        "generation + [W/kg]",
    ),
    spec(
        "Ankle power",
        "joint_powers",
        "ankle_angle",
        "generation + [W/kg]",
    ),
    spec("GRF fore-aft", "grf", "fore_aft", "forward + [% BW]"),
    spec("GRF vertical", "grf", "vertical", "upward + [% BW]"),
    spec("GRF lateral", "grf", "lateral", "rightward + [% BW]"),
];

/// Activation panels: (title, model muscle, EMG channel or "" when the paper shows none).
/// The channels are those of the reference's `emg_channel_per_muscle.csv`.
const MUSCLES: [(&str, &str, &str); 16] = [
    ("Gluteus medius", "glut_med1_r", "gluteus_medialis"),
    ("Gluteus maximus", "glut_max1_r", ""),
    ("Iliacus", "iliacus_r", ""),
    ("Adductor longus", "add_long_r", "adductor_longus"),
    ("Tensor fasciae latae", "tfl_r", "tensor_fasciae_latae"),
    ("Rectus femoris", "rect_fem_r", "rectus_femoris"),
    ("Vastus lateralis", "vas_lat_r", "vastus_lateralis"),
    ("Vastus medialis", "vas_med_r", "vastus_medialis"),
    ("Biceps femoris LH", "bifemlh_r", "hamstrings_lateralis"),
    ("Semitendinosus", "semiten_r", "hamstrings_medialis"),
    ("Gastrocnemius med.", "med_gas_r", "gastrocnemius_medialis"),
    ("Gastrocnemius lat.", "lat_gas_r", "gastrocnemius_lateralis"),
    ("Soleus", "soleus_r", "soleus"),
    ("Tibialis anterior", "tib_ant_r", "tibialis_anterior"),
    ("Peroneus longus", "per_long_r", "peroneus_longus"),
    ("Peroneus brevis", "per_brev_r", "peroneus_brevis"),
];

const X_LABEL: &str = "gait cycle [%]";

/// Percent of the gait cycle of the reference samples: (s − 1)/99 × 100 for s = 1..=n.
fn reference_percent(n: usize) -> Vec<f64> {
    let d = (n.max(2) - 1) as f64;
    (0..n).map(|i| 100.0 * i as f64 / d).collect()
}

/// Factor that converts a reference channel in `unit` to the figure's unit.
fn reference_factor(unit: &str) -> f64 {
    match unit {
        "Nm" | "W" | "N" => 1.0 / SUBJECT_MASS,
        _ => 1.0,
    }
}

/// Colour of the experimental mean line.
const EXPERIMENT_MEAN_COLOR: Color = Color::rgb(90, 90, 90);

/// The experimental mean of a channel times `factor` as a line, drawn inside its band.
fn reference_mean(
    reference: &WalkingReference,
    quantity: &str,
    channel: &str,
    factor: f64,
    label: &str,
) -> Option<Series> {
    let c = reference.quantities.get(quantity)?.get(channel)?;
    if c.mean.is_empty() {
        return None;
    }
    let mean: Vec<f64> = c.mean.iter().map(|v| v * factor).collect();
    Some(
        Series::new(reference_percent(mean.len()), mean, EXPERIMENT_MEAN_COLOR)
            .width(1.2)
            .dash(vec![5.0, 3.0])
            .label(label),
    )
}

/// The experimental mean line and ± 2 SD band of a channel (times `factor`) added to `p`.
fn with_reference(
    p: Panel,
    reference: &WalkingReference,
    (quantity, channel): (&str, &str),
    factor: f64,
    (mean_label, band_label): (&str, &str),
) -> Panel {
    let mut p = p;
    if let Some(b) = reference_band(reference, quantity, channel, factor, band_label) {
        p = p.band(b);
    }
    if let Some(m) = reference_mean(reference, quantity, channel, factor, mean_label) {
        p = p.line(m);
    }
    p
}

/// Labels of the experimental mean and band of the walking data.
const EXPERIMENT: (&str, &str) = ("experiment, mean", "experiment, ± 2 SD");

/// Experimental band of a channel: mean ± BAND_SD·SD times `factor`.
fn reference_band(
    reference: &WalkingReference,
    quantity: &str,
    channel: &str,
    factor: f64,
    label: &str,
) -> Option<Band> {
    let c = reference.quantities.get(quantity)?.get(channel)?;
    if c.mean.is_empty() || c.mean.len() != c.std.len() {
        return None;
    }
    let mean: Vec<f64> = c.mean.iter().map(|v| v * factor).collect();
    let sd: Vec<f64> = c.std.iter().map(|v| v * factor.abs()).collect();
    Some(
        Band::mean_sd(
            reference_percent(mean.len()),
            &mean,
            &sd,
            BAND_SD,
            Color::GREY.with_alpha(0.4),
        )
        .label(label),
    )
}

fn prediction(x: &[f64], y: Vec<f64>) -> Series {
    Series::new(x.to_vec(), y, PREDICTION_COLOR)
        .width(1.8)
        .label("prediction")
}

fn base_panel(title: &str, unit: &str) -> Panel {
    Panel::new(title, X_LABEL, unit)
        .x_limits(0.0, 100.0)
        .zero_line(true)
}

/// Panels of `specs` with the prediction's column of each channel.
fn spec_panels(t: &CycleTables, reference: &WalkingReference, specs: &[PanelSpec]) -> Vec<Panel> {
    let x = t.percent_closed();
    let per_kg = 1.0 / t.body_mass;
    let exists = |s: &&PanelSpec| {
        !t.planar
            || match s.quantity {
                "grf" => s.channel != "lateral",
                _ => t.coordinate_index(s.channel).is_some(),
            }
    };
    specs
        .iter()
        .filter(exists)
        .map(|s| {
            let (rows, col, factor) = match s.quantity {
                "grf" => {
                    let col = match s.channel {
                        "fore_aft" => 0,
                        "vertical" => 1,
                        _ => 2,
                    };
                    (&t.grf_bw, Some(col), 1.0)
                }
                "joint_torques" => (&t.torques, t.coordinate_index(s.channel), per_kg),
                "joint_powers" => (&t.powers, t.coordinate_index(s.channel), per_kg),
                _ => (&t.angles, t.coordinate_index(s.channel), 1.0),
            };
            // powers keep their sign: torque and speed both change theirs
            let sign = if s.quantity == "joint_powers" {
                1.0
            } else {
                s.sign
            };
            let unit = reference
                .quantities
                .get(s.quantity)
                .and_then(|q| q.get(s.channel))
                .map(|c| c.unit.clone())
                .unwrap_or_default();
            let mut p = base_panel(s.title, s.unit);
            if let Some(col) = col {
                p = p.line(prediction(
                    &x,
                    CycleTables::column(rows, col, sign * factor),
                ));
            }
            p = with_reference(
                p,
                reference,
                (s.quantity, s.channel),
                sign * reference_factor(&unit),
                EXPERIMENT,
            );
            if s.channel == "vertical" {
                p = from_zero(p);
            }
            p
        })
        .collect()
}

/// `p` with its y axis from 0 to above its highest value (a force that only pushes).
fn from_zero(p: Panel) -> Panel {
    let hi = p.data_range().1.map_or(1.0, |(_, hi)| hi.max(1e-9));
    p.y_limits(0.0, 1.05 * hi)
}

/// Activation panels with EMG scaled to the peak predicted activation.
fn activation_panels(t: &CycleTables, reference: &WalkingReference) -> Vec<Panel> {
    let x = t.percent_closed();
    MUSCLES
        .iter()
        .filter_map(|&(title, muscle, channel)| {
            let m = t.muscles.iter().position(|n| n == muscle)?;
            let a = CycleTables::column(&t.activations, m, 1.0);
            let peak_a = a
                .iter()
                .copied()
                .filter(|v| v.is_finite())
                .fold(0.0, f64::max);
            let mut p = base_panel(title, "activation [0–1]")
                .y_limits(0.0, 1.0)
                .line(prediction(&x, a));
            let emg = reference.quantities.get("emg").and_then(|q| q.get(channel));
            if let Some(c) = emg {
                let peak_e = c
                    .mean
                    .iter()
                    .copied()
                    .filter(|v| v.is_finite())
                    .fold(0.0, f64::max);
                if peak_e > 0.0 && peak_a > 0.0 {
                    if let Some(mut b) = reference_band(
                        reference,
                        "emg",
                        channel,
                        peak_a / peak_e,
                        "EMG scaled to the peak activation, ± 2 SD (≥ 0)",
                    ) {
                        // Envelopes are non-negative: mean − 2 SD is cut at zero.
                        b.lower.iter_mut().for_each(|v| *v = v.max(0.0));
                        p = p.band(b);
                    }
                    if let Some(m) = reference_mean(
                        reference,
                        "emg",
                        channel,
                        peak_a / peak_e,
                        "EMG scaled to the peak activation, mean",
                    ) {
                        p = p.line(m);
                    }
                }
            }
            Some(p)
        })
        .collect()
}

/// Figure of `panels` in a grid with `cols` columns, with a figure-level legend of every
/// distinct band and line label.
fn grid(title: &str, panels: Vec<Panel>, cols: usize, cell: (u32, u32)) -> Figure {
    let rows = panels.len().div_ceil(cols).max(1);
    let mut f =
        Figure::new(cell.0 * cols as u32, cell.1 * rows as u32 + 52, rows, cols).title(title);
    let mut seen: Vec<String> = Vec::new();
    for p in &panels {
        for b in &p.bands {
            if let Some(l) = b.label.as_ref().filter(|l| !seen.contains(l)) {
                seen.push(l.clone());
                f.legend.push(LegendEntry::fill(b.color, l));
            }
        }
    }
    for p in &panels {
        for s in &p.series {
            if let Some(l) = s.label.as_ref().filter(|l| !seen.contains(l)) {
                seen.push(l.clone());
                f.legend.insert(0, LegendEntry::for_series(s, l));
            }
        }
    }
    f.panels = panels;
    f
}

/// Trunk sway panel: the torso's rotation about the forward axis against the experiment.
fn trunk_panel(t: &CycleTables, reference: &WalkingReference) -> Option<Panel> {
    let sway = t.trunk_sway.as_ref()?;
    let rows: Vec<Vec<f64>> = sway.iter().map(|&v| vec![v]).collect();
    let p = base_panel("Trunk sway", DEG).line(prediction(
        &t.percent_closed(),
        CycleTables::column(&rows, 0, 1.0),
    ));
    Some(with_reference(
        p,
        reference,
        ("trunk_sway", "trunk_sway"),
        1.0,
        EXPERIMENT,
    ))
}

/// Rows of `rows` rotated to start at sample `start` (periodic cycle).
fn rotated(rows: &[Vec<f64>], start: usize) -> Vec<Vec<f64>> {
    let n = rows.len();
    (0..n).map(|k| rows[(start + k) % n].clone()).collect()
}

/// The prosthesis figure (FORMULATION 12.1): ankle torque [N m kg⁻¹] of the affected (right)
/// and unaffected (left) leg, each from its own heel strike, against the affected-side
/// torque of six transtibial amputees (Quesada et al. 2016, mean ± 2 SD). `None` when a
/// side never touches the ground or the model lacks an ankle.
pub fn prosthesis_figure(t: &CycleTables, reference: &WalkingReference) -> Option<NamedFigure> {
    let x = t.percent_closed();
    let per_kg = 1.0 / t.body_mass;
    let threshold = 100.0 * stride_ocp::trajectory::CONTACT_THRESHOLD / (t.body_mass * GRAVITY);
    let strike = |grf_col: usize| {
        let contact: Vec<bool> = t.grf_bw.iter().map(|r| r[grf_col] > threshold).collect();
        stride_ocp::measures::stance_phase(&contact)
            .first()
            .copied()
    };
    let ankle = |side: &str| {
        t.coordinates
            .iter()
            .position(|c| *c == format!("ankle_angle_{side}"))
    };
    let (ar, al) = (ankle("r")?, ankle("l")?);
    let (sr, sl) = (strike(1)?, strike(4)?);
    let mut p = with_reference(
        base_panel("Ankle torque from heel strike", "dorsiflexion + [N m/kg]"),
        reference,
        ("prosthesis", "ankle_torque"),
        1.0,
        (
            "amputees, affected side (Quesada et al. 2016), mean",
            "amputees, affected side (Quesada et al. 2016), ± 2 SD",
        ),
    );
    let affected = CycleTables::column(&rotated(&t.torques, sr), ar, per_kg);
    let unaffected = CycleTables::column(&rotated(&t.torques, sl), al, per_kg);
    p = p
        .line(prediction(&x, affected).label("affected (right, prosthesis)"))
        .line(
            Series::new(x.clone(), unaffected, Color::RED)
                .width(1.8)
                .label("unaffected (left)"),
        );
    Some(NamedFigure {
        name: "figure_prosthesis",
        figure: grid(
            &format!("Passive prosthesis: ankle torques ({})", t.caption),
            vec![p],
            1,
            (640, 420),
        ),
    })
}

/// The figures of a predicted gait cycle against `reference`: kinematics (with trunk
/// sway), kinetics (torques, powers, GRF) and muscle activations.
pub fn gait_figures(t: &CycleTables, reference: &WalkingReference) -> Vec<NamedFigure> {
    let cell = (300, 220);
    let mut kinematics = spec_panels(t, reference, &KINEMATICS);
    kinematics.extend(trunk_panel(t, reference));
    vec![
        NamedFigure {
            name: "figure_kinematics",
            figure: grid(
                &format!(
                    "Joint angles, right leg: prediction vs experiment ({})",
                    t.caption
                ),
                kinematics,
                3,
                cell,
            ),
        },
        NamedFigure {
            name: "figure_kinetics",
            figure: grid(
                &format!(
                    "Joint torques, powers and ground reaction forces, right leg ({})",
                    t.caption
                ),
                spec_panels(t, reference, &KINETICS),
                3,
                cell,
            ),
        },
        NamedFigure {
            name: "figure_activations",
            figure: grid(
                &format!("Muscle activations, right leg ({})", t.caption),
                activation_panels(t, reference),
                4,
                cell,
            ),
        },
    ]
}

/// File names and bytes (`<name>.svg` and `<name>.png`) of every figure.
pub fn render_files(figures: &[NamedFigure]) -> Result<Vec<(String, Vec<u8>)>, FigureError> {
    let mut out = Vec::with_capacity(2 * figures.len());
    for f in figures {
        let err = |source| FigureError::Plot {
            name: f.name.to_string(),
            source,
        };
        let svg = f.figure.to_svg().map_err(err)?;
        let png = stride_plot::png::svg_to_png(&svg, PNG_SCALE).map_err(err)?;
        out.push((format!("{}.svg", f.name), svg.into_bytes()));
        out.push((format!("{}.png", f.name), png));
    }
    Ok(out)
}

#[cfg(test)]
mod tests;
