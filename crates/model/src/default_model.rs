//! The built-in default model (the paper's subject1 model), shipped in stride's own format.
//!
//! It is `subject1_v2.osim` imported at full precision, plus the paper's tables from
//! `shared/reference`: 12 contact spheres, passive joint torques (15 coordinates + arm
//! damping), per-muscle metabolic parameters, the polynomial muscle–tendon geometry and
//! 8 arm torque actuators; gravity is set to (0, −9.81, 0) m s⁻².
//!
//! The shipped file `crates/model/data/default_model.json` is produced by
//! `stride model build-default --reference <shared/reference>`; a test checks that it
//! equals a fresh [`build_default_model`].

use crate::model::Model;
use crate::model_settings::DistanceConstraint;
use crate::osim::{load_osim, OsimError};
use crate::reference::{self, ReferenceError};
use std::path::Path;
use std::sync::OnceLock;

/// The shipped default model, as stride JSON (see [`default_model_json`]).
pub const DEFAULT_MODEL_JSON: &str = include_str!("../data/default_model.json");

/// The built-in model as an OpenSim 4 model file, written into result folders as
/// `model.osim`: `subject1_v2.osim` with the simulations' gravity, the 12 contact spheres as
/// `SmoothSphereHalfSpaceForce` elements and the 8 arm torque actuators as
/// `CoordinateActuator` elements (written by `tools/opensim_reference/default_model_osim.py`
/// from `default_model.json`; the passive joint torques and the polynomial muscle geometry
/// have no OpenSim element of the same form and are not in it).
pub const DEFAULT_MODEL_OSIM: &str = include_str!("../data/default_model.osim");

/// Gravity of the default model [m s⁻²]: the reference implementation's external
/// function uses 9.81 (and the OCP a body weight of 62 kg × 9.81), not the 9.80665 written
/// in the `.osim` file, so results stay comparable with the published ones.
pub const DEFAULT_GRAVITY: [f64; 3] = [0.0, -9.81, 0.0];

/// Errors building the default model from the reference data.
#[derive(Debug, thiserror::Error)]
pub enum DefaultModelError {
    /// The `.osim` import failed.
    #[error(transparent)]
    Osim(#[from] OsimError),
    /// A reference table could not be loaded.
    #[error(transparent)]
    Reference(#[from] ReferenceError),
    /// The reference data did not give the expected number of items.
    #[error("default model incomplete: {0}")]
    Incomplete(String),
}

/// The built-in model (parsed once from the embedded JSON, then cloned).
pub fn default_model() -> Model {
    static MODEL: OnceLock<Model> = OnceLock::new();
    MODEL
        .get_or_init(|| {
            let mut m: Model = serde_json::from_str(DEFAULT_MODEL_JSON)
                .expect("the shipped default_model.json is a valid stride model");
            m.distance_constraints = paper_distances();
            m.standing_pelvis_height = Some(PAPER_STANDING_PELVIS_HEIGHT);
            m
        })
        .clone()
}

/// Standing pelvis height of the paper's model [m]: the pelvis height of its quasi-random
/// initial guess (FORMULATION 10.1).
pub const PAPER_STANDING_PELVIS_HEIGHT: f64 = 0.9385;

/// The paper's distance constraints (calcanei 9 cm, femur–hand 18 cm, tibiae 11 cm).
pub fn paper_distances() -> Vec<DistanceConstraint> {
    let d = |a: &str, b: &str, min: f64| DistanceConstraint {
        bodies: [a.into(), b.into()],
        min,
        max: 2.0,
    };
    vec![
        d("calcn_r", "calcn_l", 0.09),
        d("femur_r", "hand_r", 0.18),
        d("femur_l", "hand_l", 0.18),
        d("tibia_r", "tibia_l", 0.11),
    ]
}

/// Build the default model from the reference folder (`shared/reference`).
pub fn build_default_model(reference_dir: &Path) -> Result<Model, DefaultModelError> {
    let mut m = load_osim(&reference_dir.join("models/subject1_v2.osim"))?;
    m.source_file = None;
    m.gravity = DEFAULT_GRAVITY;
    let expect = |what: &str, got: usize, want: usize| {
        if got == want {
            Ok(())
        } else {
            Err(DefaultModelError::Incomplete(format!(
                "{what}: expected {want}, got {got}"
            )))
        }
    };
    expect("coordinates", m.coordinates.len(), 31)?;
    expect("muscles", m.muscles.len(), 92)?;
    let n = reference::add_contacts(
        &mut m,
        &reference_dir.join("models/subject1_contact_and_joints.json"),
    )?;
    expect("contact spheres", n, 12)?;
    let n =
        reference::add_passive_torques(&mut m, &reference_dir.join("joints/passive_moments.json"))?;
    expect("passive torques (15 + 8 arm damping)", n, 23)?;
    let n = reference::add_metabolic_parameters(
        &mut m,
        &reference_dir.join("muscles/metabolic_parameters.json"),
    )?;
    expect("muscles with metabolic parameters", n, 92)?;
    let n = reference::add_path_polynomials(
        &mut m,
        &reference_dir.join("muscles/polynomials_subject1.json"),
    )?;
    expect("muscles with polynomial geometry", n, 92)?;
    let n = reference::add_arm_actuators(&mut m);
    expect("arm actuators", n, 8)?;
    m.distance_constraints = paper_distances();
    m.standing_pelvis_height = Some(PAPER_STANDING_PELVIS_HEIGHT);
    Ok(m)
}

/// Serialise a model as compact but reviewable JSON: one top-level field per line and
/// one array element (body, joint, muscle, ...) per line.
pub fn default_model_json(model: &Model) -> Result<String, serde_json::Error> {
    use serde_json::to_value as v;
    // Fields in declaration order (a serde_json map would sort them).
    let fields = [
        ("name", v(&model.name)?),
        ("gravity", v(model.gravity)?),
        ("bodies", v(&model.bodies)?),
        ("joints", v(&model.joints)?),
        ("coordinates", v(&model.coordinates)?),
        ("muscles", v(&model.muscles)?),
        ("contacts", v(&model.contacts)?),
        ("actuators", v(&model.actuators)?),
        ("passive_torques", v(&model.passive_torques)?),
        ("path_polynomials", v(&model.path_polynomials)?),
        ("unsupported", v(&model.unsupported)?),
    ];
    let mut s = String::from("{\n");
    let n = fields.len();
    for (i, (k, val)) in fields.iter().enumerate() {
        s.push_str(&serde_json::to_string(k)?);
        s.push_str(": ");
        match val {
            serde_json::Value::Array(items) if items.iter().any(|x| x.is_object()) => {
                s.push_str("[\n");
                for (j, it) in items.iter().enumerate() {
                    s.push_str(&serde_json::to_string(it)?);
                    s.push_str(if j + 1 < items.len() { ",\n" } else { "\n" });
                }
                s.push(']');
            }
            other => s.push_str(&serde_json::to_string(other)?),
        }
        s.push_str(if i + 1 < n { ",\n" } else { "\n" });
    }
    s.push_str("}\n");
    Ok(s)
}
