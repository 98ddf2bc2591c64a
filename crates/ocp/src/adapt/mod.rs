//! Adapting an OpenSim model that cannot predict walking as it is (no foot contact, a
//! coordinate that nothing drives) into one that can, by a model settings file: PredSim's
//! `AdaptOpenSimModel` (contact spheres copied from a reference model and scaled to the
//! model's feet, ideal torque actuators on the coordinates that no muscle crosses) plus
//! PredSim's passive torques, bounds, metabolic parameters and distance constraints
//! (decision 0008). The result is a [`ModelSettings`] and its commented TOML text.

mod drive;
mod feet;
mod render;

pub use drive::{crossed, drives, Drive, ACTUATOR_TIME_CONSTANT, ACTUATOR_TORQUE, DAMPING};
pub use feet::{sphere_bottoms, DefaultPose, FootScale, PlacedSphere, HEEL, TOES};

use stride_model::model_settings::{ContactSettings, ModelSettings};
use stride_model::Model;

/// The reference model whose feet are copied when no other is asked for.
pub const DEFAULT_REFERENCE: &str = "falisse2022";

/// Why a model cannot be adapted.
#[derive(Debug, thiserror::Error)]
pub enum AdaptError {
    /// The reference is not a shipped model with contact spheres.
    #[error("reference model `{model}`: {what}")]
    Reference {
        /// The reference model.
        model: String,
        /// What is wrong with it.
        what: String,
    },
    /// The model lacks a heel body to put spheres on.
    #[error("the model has no body `{0}` to put the foot contact spheres on")]
    NoFoot(String),
    /// The default pose could not be computed.
    #[error("default pose of model `{model}`: {what}")]
    Kinematics {
        /// The model.
        model: String,
        /// What failed.
        what: String,
    },
}

/// The reasons why `model` cannot predict walking as it is (empty: it can): no contact
/// spheres, coordinates that neither a muscle nor an actuator drives.
pub fn reasons(model: &Model) -> Vec<String> {
    let mut out = Vec::new();
    if model.contacts.is_empty() {
        out.push("no foot contact spheres".to_string());
    }
    let undriven: Vec<&str> = (model.coordinates.iter().zip(drives(model)))
        .filter(|(_, d)| *d == Drive::NewActuator)
        .map(|(c, _)| c.name.as_str())
        .collect();
    if !undriven.is_empty() {
        out.push(format!("no muscle crosses {}", undriven.join(", ")));
    }
    out
}

/// A reference model: a shipped model with its shipped settings.
#[derive(Clone, Debug)]
pub struct Reference {
    /// The shipped model's name (`falisse2022`).
    pub name: String,
    /// The model, its settings applied.
    pub model: Model,
    /// Its shipped settings.
    pub settings: ModelSettings,
}

impl Reference {
    /// The shipped model `name` as a reference; it must have contact spheres.
    pub fn shipped(name: &str) -> Result<Self, AdaptError> {
        let (model, settings) = reference_model(name)?;
        Ok(Self {
            name: name.into(),
            model,
            settings,
        })
    }
}

/// The shipped model `name` with its shipped settings applied, and those settings.
fn reference_model(name: &str) -> Result<(Model, ModelSettings), AdaptError> {
    let err = |what: String| AdaptError::Reference {
        model: name.into(),
        what,
    };
    let names = stride_model::shipped::SHIPPED.map(|s| s.name).join(", ");
    let s = stride_model::shipped::shipped(name)
        .ok_or_else(|| err(format!("not a shipped model ({names})")))?;
    let mut m =
        stride_model::osim::parse_osim(s.osim, s.file_name).map_err(|e| err(e.to_string()))?;
    let settings = ModelSettings::parse(s.settings, s.file_name).map_err(|e| err(e.to_string()))?;
    settings
        .apply(&mut m, s.file_name)
        .map_err(|e| err(e.to_string()))?;
    if m.contacts.is_empty() {
        return Err(err("has no contact spheres".into()));
    }
    Ok((m, settings))
}

/// A model's adaptation: the settings and where each entry came from.
#[derive(Clone, Debug)]
pub struct Adaptation {
    /// The model settings that make the model predict.
    pub settings: ModelSettings,
    /// Name of the reference model (a shipped model).
    pub reference: String,
    /// Number of its muscles' metabolic entries copied (muscles of the same name).
    pub metabolic_copied: usize,
    /// Why the model needed adapting ([`reasons`]).
    pub reasons: Vec<String>,
    /// Scale of the right and the left foot against the reference's.
    pub feet: [FootScale; 2],
    /// The contact spheres and their origin (empty when the model keeps its own).
    pub spheres: Vec<PlacedSphere>,
    /// How each coordinate is driven, in model order.
    pub drives: Vec<Drive>,
    /// Spread of the sphere bottoms in the default pose [m] (0: they all touch a flat
    /// ground at once).
    pub bottom_spread: f64,
    /// Height of the pelvis origin [m] when the lowest sphere touches the ground in
    /// the default pose.
    pub standing_height: Option<f64>,
}

/// Adapt `model` (its `.osim` import, no settings applied) with the feet, contact law,
/// metabolic parameters and distance constraints of `like`.
pub fn adapt(model: &Model, like: &Reference) -> Result<Adaptation, AdaptError> {
    let reference = &like.model;
    let pose = DefaultPose::of(model)?;
    let reference_pose = DefaultPose::of(reference)?;
    let feet = feet::foot_scales(model, &pose, reference, &reference_pose);
    let spheres = if model.contacts.is_empty() {
        feet::place_spheres(model, &pose, reference, &reference_pose, &feet)?
    } else {
        Vec::new()
    };
    let drives = drives(model);
    let mut settings = ModelSettings::default();
    if let Some(first) = reference.contacts.first() {
        settings.contact = ContactSettings {
            parameters: first.parameters,
            plane_point: first.plane_point,
            plane_normal: first.plane_normal,
            spheres: spheres.iter().map(|s| s.setting.clone()).collect(),
        };
    }
    settings.actuators = drive::new_actuators(model, &drives);
    if model.passive_torques.is_empty() {
        settings.passive_torques.table = drive::passive_table(model, &drives);
    }
    settings.metabolic = like.settings.metabolic.clone();
    settings
        .metabolic
        .muscles
        .retain(|name, _| model.muscle_index(name).is_some());
    settings.distances = (like.settings.distances.iter())
        .filter(|d| d.bodies.iter().all(|b| model.body_index(b).is_some()))
        .cloned()
        .collect();
    settings.problem = problem_defaults();
    let all_spheres: Vec<_> = if spheres.is_empty() {
        model_spheres(model)
    } else {
        settings.contact.spheres.clone()
    };
    let bottoms = feet::sphere_bottoms(model, &pose, &all_spheres);
    let lowest = bottoms.iter().copied().fold(f64::INFINITY, f64::min);
    let highest = bottoms.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    let pelvis = model.body_index("pelvis");
    let metabolic_copied = settings.metabolic.muscles.len();
    Ok(Adaptation {
        settings,
        reference: like.name.clone(),
        metabolic_copied,
        reasons: reasons(model),
        feet,
        spheres,
        drives,
        bottom_spread: if bottoms.is_empty() {
            0.0
        } else {
            highest - lowest
        },
        standing_height: pelvis
            .filter(|_| lowest.is_finite())
            .map(|p| pose.to_ground(p, [0.0; 3])[1] - lowest),
    })
}

/// The model's own spheres as settings entries.
fn model_spheres(model: &Model) -> Vec<stride_model::model_settings::SphereSetting> {
    (model.contacts.iter())
        .map(|c| stride_model::model_settings::SphereSetting {
            name: c.name.clone(),
            body: model.bodies[c.body].name.clone(),
            location: c.location,
            radius: c.radius,
        })
        .collect()
}

/// The `[problem]` defaults of an adapted model: PredSim's bounds and its passive-torque
/// cost (the limit torques only).
fn problem_defaults() -> toml::Table {
    let mut passive = toml::Table::new();
    passive.insert("cost".into(), "limit".into());
    let mut t = toml::Table::new();
    t.insert("bounds".into(), "predsim".into());
    t.insert("passive".into(), toml::Value::Table(passive));
    t
}

impl Adaptation {
    /// The settings as a TOML file whose every entry is commented with where it came
    /// from; `model_file` names the adapted model in the header.
    pub fn text(&self, model: &Model, model_file: &str) -> String {
        render::render(self, model, model_file)
    }
}

#[cfg(test)]
mod tests;
