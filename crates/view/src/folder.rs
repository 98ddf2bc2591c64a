//! Reading result folders (`stride predict`, one study case) and study folders
//! (`stride study`): the only module that knows their file names and column labels.
//!
//! A result folder holds `motion.mot` (time, every model coordinate — angles in degrees
//! unless the header says `inDegrees=no` — and `<muscle>/activation` columns), `grf.mot`
//! (per foot `r_`/`l_`: `ground_force_vx|vy|vz` [N] and the point `ground_force_px|py|pz`
//! [m] in ground), `summary.json` (outcome measures) and figures (`*.svg`). A study folder
//! holds `study.toml`, a `cases/<name>/` result folder per case and its own figures.

use crate::error::ViewError;
use std::path::{Path, PathBuf};
use stride_model::storage::Storage;

/// Motion file of a result folder.
pub const MOTION_FILE: &str = "motion.mot";
/// Ground reaction force file of a result folder.
pub const GRF_FILE: &str = "grf.mot";
/// Outcome measures of a result folder.
pub const SUMMARY_FILE: &str = "summary.json";

/// The files of one result folder that the viewer shows.
#[derive(Clone, Debug)]
pub struct ResultFiles {
    /// The folder.
    pub dir: PathBuf,
    /// `motion.mot`: coordinates and activations over the gait cycle.
    pub motion: Storage,
    /// Forces and application points per foot, when the folder has `grf.mot`.
    pub grf: Option<Storage>,
    /// `summary.json`, when present.
    pub summary: Option<serde_json::Value>,
}

impl ResultFiles {
    /// Path of the motion file (for error messages).
    pub fn motion_path(&self) -> PathBuf {
        self.dir.join(MOTION_FILE)
    }

    /// Path of the ground reaction force file (for error messages).
    pub fn grf_path(&self) -> PathBuf {
        self.dir.join(GRF_FILE)
    }
}

/// A figure of a folder: file stem and SVG text.
#[derive(Clone, Debug)]
pub struct Figure {
    /// File name without `.svg`.
    pub name: String,
    /// The SVG document.
    pub svg: String,
}

/// Read the motion, forces and summary of result folder `dir`; `motion.mot` is required.
pub fn read_result(dir: &Path) -> Result<ResultFiles, ViewError> {
    let motion_path = dir.join(MOTION_FILE);
    if !motion_path.is_file() {
        return Err(ViewError::read(
            dir,
            format!("not a result folder (no {MOTION_FILE})"),
        ));
    }
    let motion = Storage::read(&motion_path)?;
    let grf_path = dir.join(GRF_FILE);
    let grf = if grf_path.is_file() {
        Some(Storage::read(&grf_path)?)
    } else {
        None
    };
    let summary_path = dir.join(SUMMARY_FILE);
    let summary = if summary_path.is_file() {
        let text = std::fs::read_to_string(&summary_path)
            .map_err(|e| ViewError::read(&summary_path, e))?;
        Some(serde_json::from_str(&text).map_err(|e| ViewError::read(&summary_path, e))?)
    } else {
        None
    };
    Ok(ResultFiles {
        dir: dir.to_path_buf(),
        motion,
        grf,
        summary,
    })
}

/// Column of coordinate `name` in a motion file: the plain name, or an OpenSim state path
/// ending in `/<name>/value`.
pub fn coordinate_column(motion: &Storage, name: &str) -> Option<usize> {
    let suffix = format!("/{name}/value");
    motion
        .labels
        .iter()
        .position(|l| l == name || l.ends_with(&suffix))
}

/// Column of the activation of muscle `name`: `<name>/activation`, or an OpenSim state
/// path ending in `/<name>/activation`.
pub fn activation_column(motion: &Storage, name: &str) -> Option<usize> {
    let plain = format!("{name}/activation");
    let suffix = format!("/{plain}");
    motion
        .labels
        .iter()
        .position(|l| *l == plain || l.ends_with(&suffix))
}

/// Whether the angles of a motion file are in degrees (the default when the header does
/// not say).
pub fn motion_in_degrees(motion: &Storage) -> bool {
    motion.in_degrees.unwrap_or(true)
}

/// Columns of foot `side` (`"r"` or `"l"`) in a force file: force x, y, z [N] then
/// point x, y, z [m]; an error names the first missing label.
pub fn grf_columns(grf: &Storage, path: &Path, side: &str) -> Result<[usize; 6], ViewError> {
    let mut out = [0; 6];
    for (o, k) in out.iter_mut().zip(["vx", "vy", "vz", "px", "py", "pz"]) {
        let label = format!("{side}_ground_force_{k}");
        *o = grf
            .column_index(&label)
            .ok_or_else(|| ViewError::content(path, format!("no column `{label}`")))?;
    }
    Ok(out)
}

/// The SVG figures of a folder (`*.svg`), sorted by name.
pub fn svg_figures(dir: &Path) -> Result<Vec<Figure>, ViewError> {
    let mut out = Vec::new();
    for path in sorted_entries(dir)? {
        let (Some(stem), Some("svg")) = (
            path.file_stem().and_then(|s| s.to_str()),
            path.extension().and_then(|s| s.to_str()),
        ) else {
            continue;
        };
        if !path.is_file() {
            continue;
        }
        let svg = std::fs::read_to_string(&path).map_err(|e| ViewError::read(&path, e))?;
        out.push(Figure {
            name: stem.to_string(),
            svg,
        });
    }
    Ok(out)
}

/// Whether `dir` is a study output folder (`study.toml` and `cases/`).
pub fn is_study_folder(dir: &Path) -> bool {
    dir.join("study.toml").is_file() && dir.join("cases").is_dir()
}

/// The case folders of a study folder that hold a motion (finished and converged), sorted
/// by name.
pub fn study_cases(dir: &Path) -> Result<Vec<PathBuf>, ViewError> {
    Ok(sorted_entries(&dir.join("cases"))?
        .into_iter()
        .filter(|p| p.join(MOTION_FILE).is_file())
        .collect())
}

/// The OpenSim model kept in a folder: its only `.osim` file, `None` without one; several
/// are an error that names them.
pub fn model_file(dir: &Path) -> Result<Option<PathBuf>, ViewError> {
    let found: Vec<PathBuf> = sorted_entries(dir)?
        .into_iter()
        .filter(|p| p.is_file() && p.extension().is_some_and(|e| e == "osim"))
        .collect();
    match &found[..] {
        [] => Ok(None),
        [one] => Ok(Some(one.clone())),
        many => Err(ViewError::read(
            dir,
            format!(
                "{} model files ({}): choose one with --model",
                many.len(),
                many.iter()
                    .filter_map(|p| p.file_name().map(|n| n.to_string_lossy().into_owned()))
                    .collect::<Vec<_>>()
                    .join(", ")
            ),
        )),
    }
}

/// The entries of a folder, sorted by path.
fn sorted_entries(dir: &Path) -> Result<Vec<PathBuf>, ViewError> {
    let mut out = Vec::new();
    for entry in std::fs::read_dir(dir).map_err(|e| ViewError::read(dir, e))? {
        out.push(entry.map_err(|e| ViewError::read(dir, e))?.path());
    }
    out.sort();
    Ok(out)
}
