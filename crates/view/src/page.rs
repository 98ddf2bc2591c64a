//! The HTML page: the template with the stylesheet, three.js (MIT, see
//! `assets/README.md`), the viewer script and the page's data (JSON) embedded, so that the
//! file works offline from the file system.

use crate::encode::{base64, fractions_u8, sig4, Quantised};
use crate::error::ViewError;
use crate::folder::{self, Figure, ResultFiles};
use crate::frames::{self, Frames};
use crate::scene::{pose_frames, SceneModel};
use serde::Serialize;
use std::path::Path;
use stride_model::{Model, MotionType};

const TEMPLATE: &str = include_str!("../assets/page.html");
const STYLE: &str = include_str!("../assets/viewer.css");
const SCRIPT: &str = include_str!("../assets/viewer.js");
const THREE: &str = include_str!("../assets/three.bundle.min.js");
const THREE_LICENSE: &str = include_str!("../assets/LICENSE-three.txt");

/// Frames per gait cycle of a result page.
pub const RESULT_FRAMES: usize = 100;
/// Frames per gait cycle of each case of a study page (keeps a page of a hundred cases at
/// a few tens of megabytes).
pub const STUDY_FRAMES: usize = 50;

/// Options of a page.
#[derive(Clone, Debug, Default)]
pub struct ViewOptions {
    /// Frames per gait cycle (at most the motion's rows); `None`: [`RESULT_FRAMES`] for a
    /// result folder, [`STUDY_FRAMES`] for a study folder.
    pub frames: Option<usize>,
}

/// One coordinate's curve over the cycle, in the units of the result files.
#[derive(Serialize)]
struct Curve {
    name: String,
    unit: &'static str,
    values: Vec<f64>,
}

/// One gait cycle as the page reads it.
#[derive(Serialize)]
struct CaseData {
    name: String,
    /// Frame times from the start of the cycle [s].
    time: Vec<f64>,
    origins: Quantised,
    rotations: Quantised,
    muscles: Quantised,
    /// Activations, frame-major, bytes (255: unknown).
    activations: String,
    /// Per frame: right then left foot force [N] and point [m] (12 values), or nothing.
    grf: Option<Vec<f64>>,
    curves: Vec<Curve>,
    /// Outcome measures shown beside the case (name, value).
    outcomes: Vec<(String, f64)>,
}

/// A figure as an image URI.
#[derive(Serialize)]
struct FigureData {
    name: String,
    uri: String,
}

/// Everything the page shows.
#[derive(Serialize)]
struct PageData {
    title: String,
    generator: String,
    model: SceneModel,
    cases: Vec<CaseData>,
    figures: Vec<FigureData>,
}

/// The page of result folder `dir` predicted with `model`.
pub fn result_page(model: &Model, dir: &Path, opts: &ViewOptions) -> Result<String, ViewError> {
    let frames = checked_frames(opts.frames.unwrap_or(RESULT_FRAMES))?;
    let files = folder::read_result(dir)?;
    let name = folder_name(dir);
    let case = case_data(model, &files, &name, frames)?;
    let figures = figure_data(folder::svg_figures(dir)?);
    render(&PageData {
        title: format!("stride — {name}"),
        generator: generator(),
        model: SceneModel::new(model),
        cases: vec![case],
        figures,
    })
}

/// The page of study folder `dir` (every case with a motion, selectable) with `model`.
pub fn study_page(model: &Model, dir: &Path, opts: &ViewOptions) -> Result<String, ViewError> {
    let frames = checked_frames(opts.frames.unwrap_or(STUDY_FRAMES))?;
    let case_dirs = folder::study_cases(dir)?;
    if case_dirs.is_empty() {
        return Err(ViewError::read(
            dir,
            "no case with a motion (no finished, converged case in cases/)",
        ));
    }
    let mut cases = Vec::with_capacity(case_dirs.len());
    for d in &case_dirs {
        let files = folder::read_result(d)?;
        cases.push(case_data(model, &files, &folder_name(d), frames)?);
    }
    render(&PageData {
        title: format!("stride — study {}", folder_name(dir)),
        generator: generator(),
        model: SceneModel::new(model),
        cases,
        figures: figure_data(folder::svg_figures(dir)?),
    })
}

fn checked_frames(n: usize) -> Result<usize, ViewError> {
    if (2..=1000).contains(&n) {
        Ok(n)
    } else {
        Err(ViewError::Options(format!(
            "frames per cycle {n}: must be between 2 and 1000"
        )))
    }
}

fn generator() -> String {
    format!("stride {}", env!("CARGO_PKG_VERSION"))
}

fn folder_name(dir: &Path) -> String {
    let abs = std::fs::canonicalize(dir).unwrap_or_else(|_| dir.to_path_buf());
    abs.file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_else(|| dir.display().to_string())
}

/// The frames, poses and curves of one result folder.
fn case_data(
    model: &Model,
    files: &ResultFiles,
    name: &str,
    n_frames: usize,
) -> Result<CaseData, ViewError> {
    let f = frames::resample(model, files, n_frames)?;
    let poses = pose_frames(model, &f)?;
    Ok(CaseData {
        name: name.to_string(),
        time: f.time.iter().map(|t| sig4(t - f.time[0])).collect(),
        origins: Quantised::new(&poses.origins),
        rotations: Quantised::new(&poses.rotations),
        muscles: Quantised::new(&poses.muscle_points),
        activations: fractions_u8(f.activation.iter().flatten().copied()),
        grf: f.grf.as_ref().map(|g| {
            g.iter()
                .flatten()
                .flat_map(|foot| foot.force.into_iter().chain(foot.point))
                .map(sig4)
                .collect()
        }),
        curves: curves(model, &f),
        outcomes: files.summary.as_ref().map(outcomes).unwrap_or_default(),
    })
}

/// Every coordinate over the cycle: angles in degrees, translations in metres.
fn curves(model: &Model, f: &Frames) -> Vec<Curve> {
    model
        .coordinates
        .iter()
        .enumerate()
        .map(|(c, coord)| {
            let rot = coord.motion_type == MotionType::Rotational;
            Curve {
                name: coord.name.clone(),
                unit: if rot { "deg" } else { "m" },
                values: f
                    .q
                    .iter()
                    .map(|q| sig4(if rot { q[c].to_degrees() } else { q[c] }))
                    .collect(),
            }
        })
        .collect()
}

/// The numeric outcome measures of a `summary.json` (its `outcomes` object, numbers at
/// its top level), with the imposed speed of its settings when they do not hold it.
fn outcomes(summary: &serde_json::Value) -> Vec<(String, f64)> {
    let mut out = Vec::new();
    if let Some(o) = summary.get("outcomes").and_then(|o| o.as_object()) {
        for (k, v) in o {
            if let Some(x) = v.as_f64() {
                out.push((k.clone(), sig4(x)));
            }
        }
    }
    let speed = summary.pointer("/settings/speed").and_then(|v| v.as_f64());
    if let (Some(v), false) = (speed, out.iter().any(|(k, _)| k == "speed")) {
        out.insert(0, ("speed".to_string(), sig4(v)));
    }
    out
}

fn figure_data(figures: Vec<Figure>) -> Vec<FigureData> {
    figures
        .into_iter()
        .map(|f| FigureData {
            name: f.name,
            uri: format!("data:image/svg+xml;base64,{}", base64(f.svg.as_bytes())),
        })
        .collect()
}

/// The page with its data: the JSON is embedded in a `<script type="application/json">`
/// with every `<` escaped, so no string in it can close the element.
fn render(data: &PageData) -> Result<String, ViewError> {
    let json = serde_json::to_string(data)
        .map_err(|e| ViewError::Options(format!("page data: {e}")))?
        .replace('<', "\\u003c");
    let title = data
        .title
        .replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;");
    // fill the placeholders in one pass, so none is looked for inside embedded text
    let mut out = String::with_capacity(TEMPLATE.len() + THREE.len() + json.len() + 65536);
    let mut rest = TEMPLATE;
    while let Some(i) = rest.find("{{") {
        out.push_str(&rest[..i]);
        let end = rest[i..]
            .find("}}")
            .map(|e| i + e)
            .ok_or_else(|| ViewError::Options("page template: unclosed `{{`".into()))?;
        out.push_str(match &rest[i + 2..end] {
            "TITLE" => &title,
            "STYLE" => STYLE,
            "THREE" => THREE,
            "THREE_LICENSE" => THREE_LICENSE,
            "SCRIPT" => SCRIPT,
            "DATA" => &json,
            other => {
                return Err(ViewError::Options(format!(
                    "page template: unknown placeholder `{other}`"
                )))
            }
        });
        rest = &rest[end + 2..];
    }
    out.push_str(rest);
    Ok(out)
}
