//! The model of a prediction: the built-in model, a model shipped with stride (by name:
//! `falisse2022`, …), or an OpenSim model file with its settings file (`--model-settings`,
//! else `<model>.toml` beside it, else the defaults) and its fitted muscle geometry — an
//! explicit geometry file, the settings file's `geometry`, or the per-user cache keyed by
//! the model file's content (fitted on first use).

use anyhow::Context;
use std::path::{Path, PathBuf};
use stride_geometry::{cached_geometry, FitSettings, GeometryFile, GeometrySource};
use stride_model::input_file::read_limited;
use stride_model::model_settings::ModelSettings;
use stride_model::osim::MAX_OSIM_BYTES;
use stride_model::shipped::{shipped, ShippedModel, SHIPPED};
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

/// The names of the shipped models, for messages.
fn shipped_names() -> String {
    SHIPPED.map(|s| s.name).join(", ")
}

/// The model settings a model was built with, as a settings file would give them again.
pub(crate) struct UsedSettings {
    /// The settings (for a shipped model without a settings file: its shipped ones).
    pub settings: ModelSettings,
    /// How `--model` names the model: a shipped model's name, or the `.osim` file.
    pub model: String,
    /// The fitted muscle geometry file used (None: a shipped model's embedded geometry or
    /// the per-user cache).
    pub geometry: Option<PathBuf>,
}

/// Loads `model` (default: the built-in model; a shipped model's name; or an `.osim`
/// file) with its settings file (`settings`, else the one beside it or shipped with it)
/// and the muscle geometry of `geometry` when given, else the settings file's, else the
/// shipped one, else (for an `.osim`) from the cache, fitting and caching it on first use.
pub(crate) fn load_model(
    model: Option<&Path>,
    settings: Option<&Path>,
    geometry: Option<&Path>,
    quiet: bool,
) -> anyhow::Result<Model> {
    Ok(load_model_with_settings(model, settings, geometry, quiet)?.0)
}

/// [`load_model`], with the model settings it applied.
pub(crate) fn load_model_with_settings(
    model: Option<&Path>,
    settings: Option<&Path>,
    geometry: Option<&Path>,
    quiet: bool,
) -> anyhow::Result<(Model, UsedSettings)> {
    let Some(path) = model else {
        let subject1 = shipped("subject1").context("the built-in model is not shipped")?;
        if settings.is_some() {
            return load_shipped(subject1, settings, geometry);
        }
        let mut m = stride_model::default_model::default_model();
        if let Some(g) = geometry {
            read_geometry(g, subject1.osim.as_bytes(), "the built-in model")?.apply(&mut m)?;
        }
        let name = format!(
            "{} (shipped settings of {})",
            subject1.file_name, subject1.name
        );
        let used = UsedSettings {
            settings: ModelSettings::parse(subject1.settings, &name)?,
            model: subject1.name.into(),
            geometry: geometry.map(Path::to_path_buf),
        };
        return Ok((m, used));
    };
    if let Some(s) = as_name(path) {
        if !path.exists() {
            let s = shipped(s).with_context(|| {
                format!(
                    "model `{s}`: no such file, and not a shipped model ({})",
                    shipped_names()
                )
            })?;
            return load_shipped(s, settings, geometry);
        }
    }
    if path
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("json"))
    {
        anyhow::bail!(
            "{}: a model must be an OpenSim .osim file (fitted geometry goes with --geometry)",
            path.display()
        );
    }
    load_file(path, settings, geometry, quiet)
}

/// The skeleton and contact spheres of `model` for drawing, without fitting muscle
/// geometry: a shipped model's name (when no file of that name exists) with its shipped
/// settings, else the `.osim` file as it is.
pub(crate) fn load_for_view(model: &Path) -> anyhow::Result<Model> {
    if let Some(s) = as_name(model).filter(|_| !model.exists()).and_then(shipped) {
        let mut m = stride_model::osim::parse_osim(s.osim, s.file_name)?;
        let name = format!("{} (shipped settings of {})", s.file_name, s.name);
        ModelSettings::parse(s.settings, &name)?.apply(&mut m, &name)?;
        return Ok(m);
    }
    Ok(stride_model::osim::load_osim(model)?)
}

/// `path` as a bare model name (one component, no extension), if it is one.
fn as_name(path: &Path) -> Option<&str> {
    let s = path.to_str()?;
    (path.components().count() == 1 && path.extension().is_none()).then_some(s)
}

/// A shipped model: its embedded `.osim`, settings (or `settings`) and geometry (or
/// `geometry`, or the settings file's).
fn load_shipped(
    s: &ShippedModel,
    settings: Option<&Path>,
    geometry: Option<&Path>,
) -> anyhow::Result<(Model, UsedSettings)> {
    let mut m = stride_model::osim::parse_osim(s.osim, s.file_name)?;
    let (ms, geometry) = match settings {
        Some(f) => {
            let ms = ModelSettings::read(f)?;
            ms.apply(&mut m, &f.display().to_string())?;
            let g = geometry.map(Path::to_path_buf).or(ms.geometry.clone());
            (ms, g)
        }
        None => {
            let name = format!("{} (shipped settings of {})", s.file_name, s.name);
            let ms = ModelSettings::parse(s.settings, &name)?;
            ms.apply(&mut m, &name)?;
            (ms, geometry.map(Path::to_path_buf))
        }
    };
    let file = match &geometry {
        Some(g) => read_geometry(g, s.osim.as_bytes(), s.name)?,
        None => GeometryFile::parse(s.geometry, &format!("geometry of {}", s.name))?,
    };
    file.apply(&mut m)?;
    let used = UsedSettings {
        settings: ms,
        model: s.name.into(),
        geometry,
    };
    Ok((m, used))
}

/// An `.osim` file with its settings and geometry.
fn load_file(
    path: &Path,
    settings: Option<&Path>,
    geometry: Option<&Path>,
    quiet: bool,
) -> anyhow::Result<(Model, UsedSettings)> {
    let bytes = read_limited(path, MAX_OSIM_BYTES)
        .with_context(|| format!("reading model {}", path.display()))?;
    let text = String::from_utf8_lossy(&bytes);
    let mut m = stride_model::osim::parse_osim(&text, &path.display().to_string())?;
    m.source_file = Some(path.to_path_buf());
    let settings_file = settings
        .map(Path::to_path_buf)
        .or_else(|| ModelSettings::beside(path));
    let model_settings = match &settings_file {
        Some(f) => {
            if !quiet && settings.is_none() {
                eprintln!("model settings of {}: {}", path.display(), f.display());
            }
            ModelSettings::read(f)?
        }
        None => ModelSettings::default(),
    };
    let source = settings_file.map_or("default model settings".into(), |f| f.display().to_string());
    model_settings.apply(&mut m, &source)?;
    let geometry = geometry
        .map(Path::to_path_buf)
        .or(model_settings.geometry.clone());
    let file = match &geometry {
        Some(g) => read_geometry(g, &bytes, &path.display().to_string())?,
        None => cached_fit(&m, path, &bytes, quiet)?,
    };
    file.apply(&mut m)?;
    let used = UsedSettings {
        settings: model_settings,
        model: path.display().to_string(),
        geometry,
    };
    Ok((m, used))
}

/// The geometry file `path`, refused when it records the content hash of a model file
/// other than `model_bytes` (the model `model`).
fn read_geometry(path: &Path, model_bytes: &[u8], model: &str) -> anyhow::Result<GeometryFile> {
    let file = GeometryFile::read(path)?;
    file.check_model_hash(model_bytes, &path.display().to_string(), model)?;
    Ok(file)
}

/// The cached fit of the model file `path` (content `bytes`), fitted on first use.
fn cached_fit(m: &Model, path: &Path, bytes: &[u8], quiet: bool) -> anyhow::Result<GeometryFile> {
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
    let (file, source) = cached_geometry(m, bytes, &dir, &FitSettings::default())?;
    if !quiet {
        match source {
            GeometrySource::Cached(p) => eprintln!("  using the cached fit {}", p.display()),
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
    Ok(file)
}

#[cfg(test)]
mod tests {
    use super::*;
    use stride_model::default_model::default_model;
    use stride_ocp::experimental::Kinematics;
    use stride_ocp::guess::GuessKind;
    use stride_ocp::node::NodeModel;
    use stride_ocp::problem::GaitProblem;
    use stride_ocp::settings::ProblemSettings;
    use stride_ocp::tape_node::TapeNode;
    use stride_ocp::transcription::Transcription;
    use stride_solve::nlp::Nlp;

    /// The model data a gait problem reads, as JSON (muscle wrapping, which the polynomial
    /// geometry replaces, and the list of unimported elements left out).
    fn problem_data(m: &Model) -> serde_json::Value {
        let mut muscles = m.muscles.clone();
        muscles.iter_mut().for_each(|x| x.wraps.clear());
        serde_json::json!({
            "name": m.name, "gravity": m.gravity, "bodies": m.bodies, "joints": m.joints,
            "coordinates": m.coordinates, "muscles": muscles, "contacts": m.contacts,
            "actuators": m.actuators, "passive_torques": m.passive_torques,
            "path_polynomials": m.path_polynomials, "ligaments": m.ligaments,
            "couplers": m.couplers, "coordinate_forces": m.coordinate_forces,
            "distance_constraints": m.distance_constraints,
            "standing_pelvis_height": m.standing_pelvis_height,
        })
    }

    /// Objective and constraints at the data-informed walking guess on a small mesh.
    fn evaluate(m: &Model) -> (f64, Vec<f64>) {
        let settings = ProblemSettings {
            mesh_intervals: 5,
            ..Default::default()
        };
        let walking = stride_ocp::data::walking_half_cycle();
        let p = GaitProblem::new(m, &settings, &walking).unwrap();
        let kin = Kinematics::from_storage(&walking, &p.gait, "walking").unwrap();
        let x0 = p
            .initial_guess(GuessKind::DataInformedWalking, Some(&kin))
            .unwrap();
        let node = NodeModel::new(&p).unwrap();
        let tape = TapeNode::for_problem(&p, &node, &x0).unwrap();
        let tr = Transcription::new(p, tape, x0.clone());
        let mut c = vec![0.0; tr.m()];
        tr.constraints(&x0, &mut c).unwrap();
        (tr.objective(&x0).unwrap(), c)
    }

    #[test]
    fn the_shipped_subject1_import_is_the_built_in_model() {
        let imported = load_shipped(shipped("subject1").unwrap(), None, None)
            .unwrap()
            .0;
        let built_in = default_model();
        assert_eq!(problem_data(&imported), problem_data(&built_in));
        let (j0, c0) = evaluate(&built_in);
        let (j1, c1) = evaluate(&imported);
        assert_eq!(j0, j1);
        assert_eq!(c0, c1);
    }

    #[test]
    fn every_shipped_model_loads_by_name() {
        for s in SHIPPED {
            let m = load_model(Some(Path::new(s.name)), None, None, true).unwrap();
            assert_eq!(m.path_polynomials.len(), m.muscles.len(), "{}", s.name);
            assert!(!m.contacts.is_empty(), "{}", s.name);
            assert_eq!(
                stride_model::shipped::shipped_by_model_name(&m.name).map(|x| x.name),
                Some(s.name)
            );
        }
    }
}
