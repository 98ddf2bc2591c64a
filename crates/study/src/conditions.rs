//! Comparison of the conditions of a study (weakness, co-contraction, prosthesis, cost
//! functions, …) with its reference case (FORMULATION 13.2): per selected case the cost of
//! transport, step width, stride length, trunk sway and the stance measures of both legs
//! (`stride_ocp::measures`), read from the case's `summary.json`; the reference is the case
//! whose settings are exactly the study's `[base]` (e.g. a `nominal` condition).
//! Written as `conditions.csv` and a figure of angles and torques over the gait cycle.

use crate::analysis::Selected;
use crate::spec::Study;
use crate::store::{io_err, StoreError};
use serde::Serialize;
use std::collections::BTreeMap;
use std::fmt::Write as _;
use std::path::Path;
use stride_files::write_atomic;
use stride_ocp::measures::{ConditionMeasures, LegMeasures};
use stride_ocp::settings::ProblemSettings;
use stride_plot::{Color, Figure, LegendEntry, Panel, Series};

/// One selected case of the comparison.
#[derive(Clone, Debug, Serialize)]
pub struct ConditionRow {
    /// Group (case name without the guess).
    pub group: String,
    /// Kept case (folder name under `cases/`).
    pub case: String,
    /// Whether this is the reference (settings equal to `[base]`).
    pub reference: bool,
    /// Grid axis values of the case (axis name → value as the study file gives it).
    pub axes: BTreeMap<String, String>,
    /// Body mass of the model [kg] (`None` for summaries written before it was recorded).
    pub body_mass: Option<f64>,
    /// Cost of transport [J kg⁻¹ m⁻¹].
    pub cost_of_transport: Option<f64>,
    /// Stride length [m].
    pub stride_length: Option<f64>,
    /// Step width [m] (`None` for cases written before it was recorded).
    pub step_width: Option<f64>,
    /// Trunk sway and stance measures (`None` when the summary predates them).
    pub measures: Option<ConditionMeasures>,
}

/// The comparison of a study's conditions.
#[derive(Clone, Debug, Serialize)]
pub struct ConditionTable {
    /// Group of the reference case, if the study has one.
    pub reference: Option<String>,
    /// Selected cases in study order.
    pub rows: Vec<ConditionRow>,
    /// Speed and mesh of the compared cases as the figure's title states them.
    pub caption: String,
}

/// Step width and condition measures of a case folder's `summary.json` (`None` when the file
/// is missing, unreadable, or written before the measures existed).
fn read_summary(dir: &Path) -> (Option<f64>, Option<ConditionMeasures>) {
    let outcomes = std::fs::read_to_string(dir.join("summary.json"))
        .ok()
        .and_then(|t| serde_json::from_str::<serde_json::Value>(&t).ok())
        .and_then(|v| v.get("outcomes").cloned());
    let Some(o) = outcomes else {
        return (None, None);
    };
    let step_width = o.get("step_width").and_then(|v| v.as_f64());
    // A summary with the measures carries `trunk_sway` (null for a model without torso).
    let measures = o
        .get("trunk_sway")
        .and_then(|_| serde_json::from_value::<ConditionMeasures>(o.clone()).ok());
    (step_width, measures)
}

/// Body mass [kg] of a case folder's `summary.json` (`None` when missing or older).
fn read_body_mass(dir: &Path) -> Option<f64> {
    let text = std::fs::read_to_string(dir.join("summary.json")).ok()?;
    let v: serde_json::Value = serde_json::from_str(&text).ok()?;
    v.get("body_mass")?.as_f64()
}

/// Recomputes the condition measures of a case folder (from its solution) when it can.
pub type MeasuresOf<'a> = &'a dyn Fn(&Path) -> Result<ConditionMeasures, String>;

/// Build the comparison from the selected cases of a study whose output folder is `folder`;
/// the measures come from `recompute` when given and it succeeds, else from the case's
/// `summary.json`.
pub fn condition_table(
    study: &Study,
    selected: &[Selected],
    folder: &Path,
    recompute: Option<MeasuresOf>,
) -> ConditionTable {
    // A reference needs something to be compared with: none in a one-group study.
    let is_reference = |s: &Selected| {
        selected.len() > 1
            && study
                .cases
                .iter()
                .find(|c| c.name == s.case)
                .is_some_and(|c| c.settings == study.base)
    };
    let rows: Vec<ConditionRow> = selected
        .iter()
        .map(|s| {
            let dir = folder.join("cases").join(&s.case);
            let (step_width, stored) = read_summary(&dir);
            let measures = recompute.and_then(|f| f(&dir).ok()).or(stored);
            ConditionRow {
                group: s.group.clone(),
                case: s.case.clone(),
                reference: is_reference(s),
                axes: s.axes.clone(),
                body_mass: read_body_mass(&dir),
                cost_of_transport: s.cost_of_transport,
                stride_length: s.stride_length,
                step_width,
                measures,
            }
        })
        .collect();
    let settings: Vec<&ProblemSettings> = selected
        .iter()
        .filter_map(|s| study.cases.iter().find(|c| c.name == s.case))
        .map(|c| &c.settings)
        .collect();
    ConditionTable {
        reference: rows.iter().find(|r| r.reference).map(|r| r.group.clone()),
        rows,
        caption: caption(&settings),
    }
}

/// Speeds and meshes of the cases compared, as the figure's title states them: `1.33 m/s,
/// 50 mesh intervals per half cycle`, or the range of speeds when they differ.
fn caption(settings: &[&ProblemSettings]) -> String {
    let speeds = settings.iter().map(|s| s.speed);
    let lo = speeds.clone().fold(f64::INFINITY, f64::min);
    let hi = speeds.fold(f64::NEG_INFINITY, f64::max);
    let speed = if !lo.is_finite() {
        return String::new();
    } else if hi - lo < 1e-9 {
        format!("{lo:.2} m/s")
    } else {
        format!("{lo:.2}–{hi:.2} m/s")
    };
    let mesh = crate::analysis::mesh_caption(settings.iter().copied());
    format!("{speed}, {mesh}")
}

/// Names and accessors of the per-leg columns.
type LegField = (&'static str, fn(&LegMeasures) -> Option<f64>);
const LEG_FIELDS: [LegField; 6] = [
    ("stance_fraction", |m| m.stance_fraction),
    ("early_stance_peak_knee_flexion_deg", |m| {
        m.peak_knee_flexion
    }),
    ("peak_ankle_dorsiflexion_deg", |m| m.peak_ankle_dorsiflexion),
    ("peak_hip_abduction_torque_nm_per_kg", |m| {
        m.peak_hip_abduction_torque
    }),
    ("peak_ankle_plantarflexion_torque_nm_per_kg", |m| {
        m.peak_ankle_plantarflexion_torque
    }),
    ("early_stance_ankle_plantarflexion_torque_nm_per_kg", |m| {
        m.early_stance_ankle_plantarflexion_torque
    }),
];

fn o(v: Option<f64>) -> String {
    v.map(|x| x.to_string()).unwrap_or_default()
}

/// `conditions.csv`: one row per selected case.
pub fn conditions_csv(t: &ConditionTable) -> String {
    let mut s = String::from(
        "group,case,reference,cost_of_transport,stride_length_m,step_width_m,trunk_sway_deg",
    );
    for side in ["right", "left"] {
        for (name, _) in LEG_FIELDS {
            let _ = write!(s, ",{side}_{name}");
        }
    }
    s.push('\n');
    for r in &t.rows {
        let _ = write!(
            s,
            "{},{},{},{},{},{},{}",
            r.group,
            r.case,
            r.reference,
            o(r.cost_of_transport),
            o(r.stride_length),
            o(r.step_width),
            o(r.measures.as_ref().and_then(|m| m.trunk_sway)),
        );
        for right in [true, false] {
            let l = r
                .measures
                .as_ref()
                .map(|m| {
                    if right {
                        m.right.clone()
                    } else {
                        m.left.clone()
                    }
                })
                .unwrap_or_default();
            for (_, f) in LEG_FIELDS {
                let _ = write!(s, ",{}", o(f(&l)));
            }
        }
        s.push('\n');
    }
    s
}

/// One-line text per row: the main measures and their change from the reference.
pub fn conditions_text(t: &ConditionTable) -> Vec<String> {
    let reference = t.rows.iter().find(|r| r.reference);
    let fmt = |v: Option<f64>, r: Option<f64>, digits: usize, unit: &str| match (v, r) {
        (Some(v), Some(r)) => format!("{v:.digits$}{unit} ({:+.digits$})", v - r),
        (Some(v), None) => format!("{v:.digits$}{unit}"),
        _ => "–".into(),
    };
    let m = |r: Option<&ConditionRow>, f: &dyn Fn(&ConditionMeasures) -> Option<f64>| {
        r.and_then(|r| r.measures.as_ref()).and_then(f)
    };
    t.rows
        .iter()
        .map(|r| {
            let g = |f: &dyn Fn(&ConditionMeasures) -> Option<f64>| (m(Some(r), f), m(reference, f));
            let (sway, sway0) = g(&|x| x.trunk_sway);
            let (knee, knee0) = g(&|x| x.right.peak_knee_flexion);
            let (df, df0) = g(&|x| x.right.peak_ankle_dorsiflexion);
            let (hip, hip0) = g(&|x| x.right.peak_hip_abduction_torque);
            let (pf_r, _) = g(&|x| x.right.early_stance_ankle_plantarflexion_torque);
            let (pf_l, _) = g(&|x| x.left.early_stance_ankle_plantarflexion_torque);
            format!(
                "{}{}: COT {}, step width {}, trunk sway {}; right leg: early-stance knee flexion {}, stance ankle dorsiflexion {}, hip abduction torque {}; early-stance plantarflexion torque right {}, left {}",
                r.group,
                if r.reference { " (reference)" } else { "" },
                fmt(r.cost_of_transport, reference.and_then(|x| x.cost_of_transport), 2, " J/kg/m"),
                fmt(r.step_width, reference.and_then(|x| x.step_width), 3, " m"),
                fmt(sway, sway0, 1, "°"),
                fmt(knee, knee0, 1, "°"),
                fmt(df, df0, 1, "°"),
                fmt(hip, hip0, 2, " N m/kg"),
                fmt(pf_r, None, 2, " N m/kg"),
                fmt(pf_l, None, 2, " N m/kg"),
            )
        })
        .collect()
}

/// A panel of the condition figure: a column of a case table over the gait cycle, drawn
/// with the sign conventions and units of a prediction's own figures.
struct FigurePanel {
    title: &'static str,
    /// Table file of the case folder.
    file: &'static str,
    /// Column (without its unit).
    column: &'static str,
    /// y-axis label: the sign convention and the unit.
    unit: &'static str,
    /// Factor from the coordinate's sign to the drawn one (−1: knee flexion positive).
    sign: f64,
    /// Whether the column is divided by the body mass (torques [N m] → [N m/kg]).
    per_kg: bool,
}

const fn angle(title: &'static str, column: &'static str, unit: &'static str) -> FigurePanel {
    FigurePanel {
        title,
        file: "joint_angles.csv",
        column,
        unit,
        sign: 1.0,
        per_kg: false,
    }
}

const fn torque(title: &'static str, column: &'static str, unit: &'static str) -> FigurePanel {
    FigurePanel {
        title,
        file: "joint_torques.csv",
        column,
        unit,
        sign: 1.0,
        per_kg: true,
    }
}

const fn flipped(p: FigurePanel) -> FigurePanel {
    FigurePanel { sign: -1.0, ..p }
}

const FIGURE_PANELS: [FigurePanel; 8] = [
    angle(
        "Hip adduction (right)",
        "hip_adduction_r",
        "adduction + [deg]",
    ),
    flipped(angle(
        "Knee flexion (right)",
        "knee_angle_r",
        "flexion + [deg]",
    )),
    angle(
        "Ankle angle (right)",
        "ankle_angle_r",
        "dorsiflexion + [deg]",
    ),
    FigurePanel {
        title: "Trunk sway",
        file: "trunk_sway.csv",
        column: "trunk_sway",
        unit: "angle [deg]",
        sign: 1.0,
        per_kg: false,
    },
    torque(
        "Hip adduction torque (right)",
        "hip_adduction_r",
        "adduction + [N m/kg]",
    ),
    flipped(torque(
        "Knee torque (right)",
        "knee_angle_r",
        "flexion + [N m/kg]",
    )),
    torque(
        "Ankle torque (right)",
        "ankle_angle_r",
        "dorsiflexion + [N m/kg]",
    ),
    torque(
        "Ankle torque (left)",
        "ankle_angle_l",
        "dorsiflexion + [N m/kg]",
    ),
];

/// Legend label of a case: the values of the grid axes that vary between the compared
/// cases (`varying`), speeds in m/s and conditions by name; the group name when none varies.
fn legend_label(row: &ConditionRow, varying: &[&str]) -> String {
    let parts: Vec<String> = varying
        .iter()
        .filter_map(|&k| {
            let v = row.axes.get(k)?;
            Some(match k {
                "speed" => format!("{v} m/s"),
                "condition" => v.clone(),
                _ => format!("{k} = {v}"),
            })
        })
        .collect();
    if parts.is_empty() {
        row.group.clone()
    } else {
        parts.join(", ")
    }
}

/// The grid axes whose values differ between the rows of `t`, in axis order.
fn varying_axes(t: &ConditionTable) -> Vec<&str> {
    let mut keys: Vec<&str> = t
        .rows
        .iter()
        .flat_map(|r| r.axes.keys().map(String::as_str))
        .collect();
    keys.sort_unstable();
    keys.dedup();
    keys.retain(|k| {
        let first = t.rows.first().and_then(|r| r.axes.get(*k));
        t.rows.iter().any(|r| r.axes.get(*k) != first)
    });
    keys
}

/// Line colours of the compared cases (the reference is drawn black and wider).
/// Beyond its length the colours repeat dashed.
const PALETTE: [Color; 10] = [
    Color::BLUE,
    Color::RED,
    Color::GREEN,
    Color::ORANGE,
    Color::rgb(120, 60, 160),
    Color::GREY,
    Color::rgb(140, 80, 20),
    Color::rgb(0, 150, 150),
    Color::rgb(220, 90, 160),
    Color::rgb(120, 120, 0),
];

/// Figure of angles and torques over the gait cycle, one line per selected case named by
/// what varies between the cases (`None` when no case has tables; one case alone, e.g. the
/// prosthesis, still shows its right and left ankle torques). A case without its body mass
/// (summaries that predate it) has no torque lines.
pub fn conditions_figure(t: &ConditionTable, folder: &Path, title: &str) -> Option<Figure> {
    let mut fig = Figure::new(1600, 800, 2, 4).title(title.to_string());
    let mut panels: Vec<Panel> = FIGURE_PANELS
        .iter()
        .map(|p| Panel::new(p.title, "gait cycle [%]", p.unit))
        .collect();
    let varying = varying_axes(t);
    let mut drawn = 0;
    let mut colour = 0;
    for r in &t.rows {
        let dir = folder.join("cases").join(&r.case);
        let (c, w, dashed) = if r.reference {
            (Color::BLACK, 2.5, false)
        } else {
            colour += 1;
            let k = colour - 1;
            (PALETTE[k % PALETTE.len()], 1.5, k >= PALETTE.len())
        };
        let mut any = false;
        for (panel, spec) in panels.iter_mut().zip(&FIGURE_PANELS) {
            let factor = match (spec.per_kg, r.body_mass) {
                (false, _) => spec.sign,
                (true, Some(m)) if m > 0.0 => spec.sign / m,
                (true, _) => continue,
            };
            if let Some((x, y)) = crate::figures::cycle_column(&dir.join(spec.file), spec.column) {
                let y = y.into_iter().map(|v| factor * v).collect();
                let mut s = Series::new(x, y, c).width(w);
                if dashed {
                    s = s.dash(vec![6.0, 3.0]);
                }
                if !any {
                    fig = fig.legend_entry(LegendEntry::for_series(&s, &legend_label(r, &varying)));
                }
                *panel = panel.clone().line(s);
                any = true;
            }
        }
        drawn += usize::from(any);
    }
    if drawn == 0 {
        return None;
    }
    Some(panels.into_iter().fold(fig, |f, p| f.panel(p)))
}

/// Write `conditions.csv` and `figure_conditions.svg`/`.png` into a study folder.
pub fn write_conditions(folder: &Path, t: &ConditionTable, study: &str) -> Result<(), StoreError> {
    let p = folder.join("conditions.csv");
    write_atomic(&p, conditions_csv(t).as_bytes()).map_err(|e| io_err(&p, e))?;
    let mut title = match &t.reference {
        Some(r) => format!("{study}: conditions against {r}"),
        None => format!("{study}: conditions"),
    };
    if !t.caption.is_empty() {
        title.push_str(&format!(" ({})", t.caption));
    }
    if let Some(fig) = conditions_figure(t, folder, &title) {
        crate::figures::write_figure(&folder.join("figure_conditions"), &fig)?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::collections::BTreeMap;

    const STUDY: &str = r#"
[study]
name = "t"
output = "out"
[base]
mesh_intervals = 10
[grid]
guesses = ["quasi-random"]
[[grid.conditions]]
name = "nominal"
[[grid.conditions]]
name = "weak"
strength = [{ group = "hip", scale = 0.5 }]
"#;

    fn selected(case: &str, cot: f64) -> Selected {
        Selected {
            group: case.split("__").next().unwrap().into(),
            axes: BTreeMap::new(),
            case: case.into(),
            guess: "quasi-random".into(),
            objective: Some(1.0),
            speed: 1.33,
            cost_of_transport: Some(cot),
            stride_frequency: None,
            stride_length: Some(1.4),
            gait: None,
        }
    }

    /// A case folder with a summary holding the measures and an angle table.
    fn write_case(root: &Path, case: &str, sway: f64, knee: f64) {
        let dir = root.join("cases").join(case);
        std::fs::create_dir_all(&dir).unwrap();
        let summary = serde_json::json!({
            "body_mass": 62.5,
            "outcomes": {
                "cost_of_transport": 0.0,
                "step_width": 0.08 + sway / 1000.0,
                "trunk_sway": sway,
                "right": { "peak_knee_flexion": knee, "early_stance_ankle_plantarflexion_torque": 0.5 },
                "left": { "peak_knee_flexion": knee }
            }
        });
        std::fs::write(dir.join("summary.json"), summary.to_string()).unwrap();
        let rows: String = (0..4)
            .map(|k| format!("{},{}\n", 0.1 * k as f64, -knee * k as f64 / 4.0))
            .collect();
        std::fs::write(
            dir.join("trunk_sway.csv"),
            format!("time,trunk_sway\n0,{sway}\n0.1,0\n"),
        )
        .unwrap();
        std::fs::write(
            dir.join("joint_angles.csv"),
            format!("time [s],knee_angle_r [deg]\n{rows}"),
        )
        .unwrap();
        std::fs::write(
            dir.join("joint_torques.csv"),
            format!("time [s],knee_angle_r [N m]\n{rows}"),
        )
        .unwrap();
    }

    #[test]
    fn conditions_are_compared_with_the_base_case() {
        let study = crate::spec::parse(STUDY, Path::new("t.toml")).unwrap();
        let names: Vec<&str> = study.cases.iter().map(|c| c.name.as_str()).collect();
        let root = std::env::temp_dir().join(format!("stride-conditions-{}", std::process::id()));
        write_case(&root, names[0], 4.0, 20.0);
        write_case(&root, names[1], 6.5, 26.0);
        let mut sel = vec![selected(names[0], 3.9), selected(names[1], 4.3)];
        for (s, c) in sel.iter_mut().zip(&study.cases) {
            s.axes = c.axes.clone();
        }
        let t = condition_table(&study, &sel, &root, None);
        assert_eq!(t.reference.as_deref(), Some(sel[0].group.as_str()));
        assert!(t.rows[0].reference && !t.rows[1].reference);
        assert_eq!(t.rows[1].measures.as_ref().unwrap().trunk_sway, Some(6.5));
        let csv = conditions_csv(&t);
        let header: Vec<&str> = csv.lines().next().unwrap().split(',').collect();
        let row: Vec<&str> = csv.lines().nth(2).unwrap().split(',').collect();
        assert_eq!(header.len(), row.len());
        let col = |name: &str| row[header.iter().position(|h| *h == name).unwrap()];
        assert_eq!(col("trunk_sway_deg"), "6.5");
        assert_eq!(col("right_early_stance_peak_knee_flexion_deg"), "26");
        assert!((col("step_width_m").parse::<f64>().unwrap() - 0.0865).abs() < 1e-12);
        assert_eq!(col("right_stance_fraction"), "");
        let text = conditions_text(&t);
        assert!(text[1].contains("COT 4.30 J/kg/m (+0.40)"), "{}", text[1]);
        assert!(text[1].contains("trunk sway 6.5° (+2.5)"), "{}", text[1]);
        assert!(text[1].contains("right 0.50 N m/kg, left –"), "{}", text[1]);
        assert!(text[0].contains("(reference)"));
        write_conditions(&root, &t, "t").unwrap();
        let svg = std::fs::read_to_string(root.join("figure_conditions.svg")).unwrap();
        stride_plot::png::parse_svg(&svg).unwrap();
        let fig = conditions_figure(&t, &root, "t").unwrap();
        let sway = fig.panels.iter().find(|p| p.title == "Trunk sway").unwrap();
        assert_eq!(sway.series.len(), 2, "one trunk sway line per case");
        // legends name what varies (here the condition), the title the speed and mesh
        let legend: Vec<&str> = fig.legend.iter().map(|e| e.label.as_str()).collect();
        assert_eq!(legend, ["nominal", "weak"]);
        assert_eq!(t.caption, "1.33 m/s, 10 mesh intervals per half cycle");
        assert!(svg.contains("(1.33 m/s, 10 mesh intervals per half cycle)"));
        // the units and signs of a prediction's figures: knee flexion positive, torques
        // per kilogram of body mass (62.5 kg in the summaries)
        let panel = |title: &str| fig.panels.iter().find(|p| p.title == title).unwrap();
        let knee = panel("Knee flexion (right)");
        assert_eq!(knee.y.label, "flexion + [deg]");
        assert!((knee.series[1].y[2] - 26.0 * 2.0 / 4.0).abs() < 1e-12);
        let torque = panel("Knee torque (right)");
        assert_eq!(torque.y.label, "flexion + [N m/kg]");
        assert!((torque.series[1].y[2] - 13.0 / 62.5).abs() < 1e-12);
        // Alone, the base case is no reference (nothing to compare with).
        let alone = condition_table(&study, &sel[..1], &root, None);
        assert_eq!(alone.reference, None);
        assert!(
            !conditions_text(&alone)[0].contains('('),
            "{}",
            conditions_text(&alone)[0]
        );
        std::fs::remove_dir_all(&root).unwrap();
    }

    /// Summaries written before the measures existed give rows without measures.
    #[test]
    fn old_summaries_have_no_measures() {
        let root =
            std::env::temp_dir().join(format!("stride-conditions-old-{}", std::process::id()));
        let dir = root.join("cases").join("c");
        std::fs::create_dir_all(&dir).unwrap();
        std::fs::write(
            dir.join("summary.json"),
            r#"{"outcomes": {"step_width": 0.1}}"#,
        )
        .unwrap();
        assert_eq!(read_summary(&dir), (Some(0.1), None));
        assert_eq!(read_summary(&root), (None, None));
        std::fs::remove_dir_all(&root).unwrap();
    }
}
