//! `stride model build-default`: the built-in model from the reference data, written as
//! stride JSON (the fast path of the default prediction) and as the shipped `subject1`
//! import — `subject1_v2.osim` with its settings file and the paper's polynomial muscle
//! geometry as a geometry file.

use anyhow::Context as _;
use std::path::Path;
use stride_files::write_atomic;
use stride_geometry::geometry_file::{MuscleAccuracy, FORMAT};
use stride_geometry::{content_hash, FitSettings, GeometryFile};
use stride_model::model_settings::ModelSettings;
use stride_model::Model;

/// File name of the built-in model's settings file, beside `subject1_v2.osim`.
pub const SETTINGS_FILE: &str = "subject1_v2.toml";
/// File name of the built-in model's geometry file (the paper's polynomials).
pub const GEOMETRY_FILE: &str = "subject1_v2.geometry.json";

/// Header of the generated settings file.
const HEADER: &str =
    "# Settings of the built-in model (Falisse et al. 2019, subject1): the 12 contact\n\
# spheres, passive joint torques (15 coordinates + arm damping), 8 arm torque actuators,\n\
# per-muscle metabolic parameters, the paper's distance constraints and the polynomial\n\
# muscle geometry of the reference implementation. Written by\n\
# `stride model build-default --reference <shared/reference>`; see docs/settings.md.\n\n";

/// The paper's polynomials of `model` as a geometry file of the `.osim` bytes `osim`
/// (fitted by the authors on 5000 poses of a dummy motion, orders 3–9, 3 mm).
pub fn reference_geometry(model: &Model, osim: &[u8]) -> GeometryFile {
    let accuracy = model
        .muscles
        .iter()
        .zip(&model.path_polynomials)
        .map(|(m, p)| {
            let p = p.as_ref();
            let mm = |v: Option<f64>| v.unwrap_or(0.0) * 1e3;
            let (l, a) = (
                mm(p.and_then(|p| p.rmse_length)),
                mm(p.and_then(|p| p.rmse_moment_arm)),
            );
            MuscleAccuracy {
                muscle: m.name.clone(),
                order: p.map_or(0, |p| p.order),
                rms_length_mm: l,
                max_rms_moment_arm_mm: a,
                meets_tolerance: l <= 3.0 && a <= 3.0,
            }
        })
        .collect();
    GeometryFile {
        format: FORMAT.to_string(),
        model: model.name.clone(),
        model_hash: Some(content_hash(osim)),
        settings: FitSettings {
            n_samples: 5000,
            seed: None,
            orders: [3, 9],
            tolerance: 3e-3,
        },
        coordinates: model.coordinates.iter().map(|c| c.name.clone()).collect(),
        muscles: model.muscles.iter().map(|m| m.name.clone()).collect(),
        path_polynomials: model.path_polynomials.clone(),
        accuracy,
        ligaments: Vec::new(),
        ligament_polynomials: Vec::new(),
        ligament_accuracy: Vec::new(),
    }
}

/// Write `subject1_v2.osim` (copied from the reference folder), its settings file and
/// geometry file into `dir`, from the built-in `model`.
pub fn write_subject1(model: &Model, reference: &Path, dir: &Path) -> anyhow::Result<()> {
    let src = reference.join("models/subject1_v2.osim");
    let osim = std::fs::read(&src).with_context(|| format!("reading {}", src.display()))?;
    std::fs::create_dir_all(dir).with_context(|| format!("creating {}", dir.display()))?;
    let p = dir.join("subject1_v2.osim");
    write_atomic(&p, &osim).with_context(|| format!("writing {}", p.display()))?;
    let mut settings = ModelSettings::of_model(model)?;
    settings.geometry = Some(GEOMETRY_FILE.into());
    let text = format!("{HEADER}{}", toml::to_string(&settings)?);
    let p = dir.join(SETTINGS_FILE);
    write_atomic(&p, text.as_bytes()).with_context(|| format!("writing {}", p.display()))?;
    reference_geometry(model, &osim).write(&dir.join(GEOMETRY_FILE))?;
    Ok(())
}
