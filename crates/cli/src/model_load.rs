//! The model of a prediction: the built-in model, or an OpenSim model with its settings
//! file (`--model-settings`, else `<model>.toml` beside it, else the defaults) and its
//! fitted muscle geometry — an explicit geometry file, the settings file's `geometry`, or
//! the per-user cache keyed by the model file's content (fitted on first use).

use anyhow::Context;
use std::path::{Path, PathBuf};
use stride_geometry::{cached_geometry, FitSettings, GeometryFile, GeometrySource};
use stride_model::model_settings::ModelSettings;
use stride_model::Model;

/// The per-user cache folder of fitted geometry: `$XDG_CACHE_HOME/stride`, else
/// `$HOME/.cache/stride`.
pub(crate) fn cache_dir() -> Option<PathBuf> {
    let base = std::env::var_os("XDG_CACHE_HOME")
        .filter(|v| !v.is_empty())
        .map(PathBuf::from)
        .or_else(|| std::env::var_os("HOME").map(|h| PathBuf::from(h).join(".cache")))?;
    Some(base.join("stride"))
}

/// Loads `model` (default: the built-in model) with its settings file (`settings`, else
/// the one beside it) and the muscle geometry of `geometry` when given, else the settings
/// file's, else (for an `.osim`) from the cache, fitting and caching it on first use.
pub(crate) fn load_model(
    model: Option<&Path>,
    settings: Option<&Path>,
    geometry: Option<&Path>,
    quiet: bool,
) -> anyhow::Result<Model> {
    let Some(path) = model else {
        if let Some(s) = settings {
            anyhow::bail!(
                "{}: a model settings file needs a model (--model)",
                s.display()
            );
        }
        let mut m = stride_model::default_model::default_model();
        if let Some(g) = geometry {
            GeometryFile::read(g)?.apply(&mut m)?;
        }
        return Ok(m);
    };
    if path
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("json"))
    {
        anyhow::bail!(
            "{}: a model must be an OpenSim .osim file (fitted geometry goes with --geometry)",
            path.display()
        );
    }
    let bytes = std::fs::read(path).with_context(|| format!("reading model {}", path.display()))?;
    let text = String::from_utf8_lossy(&bytes);
    let mut m = stride_model::osim::parse_osim(&text, &path.display().to_string())?;
    let settings_file = settings
        .map(Path::to_path_buf)
        .or_else(|| ModelSettings::beside(path));
    let model_settings = match &settings_file {
        Some(f) => {
            let s = ModelSettings::read(f)?;
            s.apply(&mut m, &f.display().to_string())?;
            s
        }
        None => {
            let s = ModelSettings::default();
            s.apply(&mut m, "default model settings")?;
            s
        }
    };
    let file = match geometry.or(model_settings.geometry.as_deref()) {
        Some(g) => GeometryFile::read(g)?,
        None => {
            let dir = cache_dir().context(
                "no cache folder for the fitted muscle geometry (set XDG_CACHE_HOME or HOME, or pass --geometry)",
            )?;
            if !quiet {
                eprintln!(
                    "muscle geometry of {}: looking in {}",
                    path.display(),
                    dir.display()
                );
            }
            let (file, source) = cached_geometry(&m, &bytes, &dir, &FitSettings::default())?;
            if !quiet {
                match source {
                    GeometrySource::Cached(p) => {
                        eprintln!("  using the cached fit {}", p.display())
                    }
                    GeometrySource::Fitted(p) => {
                        eprintln!("  fitted on first use, cached as {}", p.display())
                    }
                }
                for a in file.accuracy.iter().filter(|a| !a.meets_tolerance) {
                    eprintln!(
                        "  warning: muscle {} misses the {:.1} mm target: RMS length error {:.2} mm, largest RMS moment-arm error {:.2} mm",
                        a.muscle,
                        file.settings.tolerance * 1e3,
                        a.rms_length_mm,
                        a.max_rms_moment_arm_mm
                    );
                }
            }
            file
        }
    };
    file.apply(&mut m)?;
    Ok(m)
}
