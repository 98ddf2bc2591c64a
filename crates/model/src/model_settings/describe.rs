//! The settings that reproduce a model's own data: contact spheres, passive torques,
//! actuators, metabolic parameters, distance constraints and gravity — how the settings
//! file of the built-in model is written.

use super::{
    ActuatorSetting, ContactSettings, ModelSettings, MuscleMetabolic, MuscleParameters,
    PassiveTorqueEntry, SphereSetting,
};
use crate::model::Model;

/// Why a model's data cannot be written as settings.
#[derive(Debug, thiserror::Error)]
#[error("cannot describe model `{model}` as settings: {what}")]
pub struct DescribeError {
    /// Model name.
    pub model: String,
    /// What does not fit the settings' form.
    pub what: String,
}

impl ModelSettings {
    /// Settings whose [`ModelSettings::apply`] to the model's `.osim` import gives this
    /// model's gravity, contacts, passive torques, actuators, metabolic parameters and
    /// distance constraints (the geometry file is set by the caller). Contact spheres must
    /// share one contact law and ground plane.
    pub fn of_model(model: &Model) -> Result<Self, DescribeError> {
        let err = |what: &str| DescribeError {
            model: model.name.clone(),
            what: what.into(),
        };
        let mut s = ModelSettings {
            gravity: Some(model.gravity),
            standing_pelvis_height: model.standing_pelvis_height,
            distances: model.distance_constraints.clone(),
            ..Default::default()
        };
        if let Some(first) = model.contacts.first() {
            if model.contacts.iter().any(|c| {
                c.parameters != first.parameters
                    || c.plane_point != first.plane_point
                    || c.plane_normal != first.plane_normal
            }) {
                return Err(err("contact spheres with different laws or planes"));
            }
            s.contact = ContactSettings {
                parameters: first.parameters,
                plane_point: first.plane_point,
                plane_normal: first.plane_normal,
                spheres: model
                    .contacts
                    .iter()
                    .map(|c| SphereSetting {
                        name: c.name.clone(),
                        body: model.bodies[c.body].name.clone(),
                        location: c.location,
                        radius: c.radius,
                    })
                    .collect(),
            };
        }
        s.passive_torques.table = passive_table(model);
        s.actuators = model
            .actuators
            .iter()
            .map(|a| {
                let coordinate = model.coordinates[a.coordinate].name.clone();
                ActuatorSetting {
                    name: (a.name != format!("{coordinate}_torque")).then(|| a.name.clone()),
                    coordinate,
                    optimal_force: a.optimal_force,
                    control_range: a.control_range,
                    activation_time_constant: a.activation_time_constant,
                }
            })
            .collect();
        s.metabolic.muscles = metabolic_entries(model, s.metabolic.mirror_left);
        s.muscle_parameters = muscle_parameters(model).ok_or_else(|| {
            err("a muscle name that selects muscles of different tendon or passive fibre parameters")
        })?;
        if let Some(first) = model.muscles.first() {
            let b = first.metabolic_smoothing;
            if model.muscles.iter().any(|m| m.metabolic_smoothing != b) {
                return Err(err("muscles with different metabolic smoothing"));
            }
            s.metabolic.smoothing = b;
        }
        Ok(s)
    }
}

/// The passive torques, coordinates with the same law grouped in one entry.
fn passive_table(model: &Model) -> Vec<PassiveTorqueEntry> {
    let mut table: Vec<PassiveTorqueEntry> = Vec::new();
    for p in &model.passive_torques {
        let name = model.coordinates[p.coordinate].name.clone();
        match table
            .iter_mut()
            .find(|e| e.k == p.k && e.theta == p.theta && e.damping == p.damping)
        {
            Some(e) => e.coordinates.push(name),
            None => table.push(PassiveTorqueEntry {
                coordinates: vec![name],
                k: p.k,
                theta: p.theta,
                damping: p.damping,
            }),
        }
    }
    table
}

/// The `[[muscle_parameters]]` keys of a muscle: each value other than 1.
fn parameter_keys(m: &crate::model::Muscle) -> [Option<f64>; 3] {
    [
        m.tendon_stiffness_scale,
        m.passive_fibre_shift,
        m.passive_fibre_scale,
    ]
    .map(|v| (v != 1.0).then_some(v))
}

/// One entry per combination of tendon stiffness scale and passive fibre shift and scale
/// other than all 1, matching its muscles by full name; `None` when a name also selects a
/// muscle of another combination.
fn muscle_parameters(model: &Model) -> Option<Vec<MuscleParameters>> {
    let mut out: Vec<MuscleParameters> = Vec::new();
    let keys = |e: &MuscleParameters| {
        [
            e.tendon_stiffness_scale,
            e.passive_fibre_shift,
            e.passive_fibre_scale,
        ]
    };
    for m in &model.muscles {
        let k = parameter_keys(m);
        if k == [None; 3] {
            continue;
        }
        match out.iter_mut().find(|e| keys(e) == k) {
            Some(e) => e.matches.push(m.name.clone()),
            None => out.push(MuscleParameters {
                matches: vec![m.name.clone()],
                tendon_stiffness_scale: k[0],
                passive_fibre_shift: k[1],
                passive_fibre_scale: k[2],
                line: None,
            }),
        }
    }
    let unambiguous = model.muscles.iter().all(|m| {
        out.iter()
            .filter(|e| e.matches.iter().any(|n| m.name.contains(n.as_str())))
            .all(|e| keys(e) == parameter_keys(m))
    });
    unambiguous.then_some(out)
}

/// One entry per muscle, except left muscles equal to their right muscle when mirrored.
fn metabolic_entries(
    model: &Model,
    mirror_left: bool,
) -> std::collections::BTreeMap<String, MuscleMetabolic> {
    let entry = |m: &crate::model::Muscle| MuscleMetabolic {
        slow_twitch_fraction: m.slow_twitch_fraction,
        specific_tension_mpa: m.specific_tension / 1.0e6,
    };
    let mut out = std::collections::BTreeMap::new();
    for m in &model.muscles {
        let twin = m
            .name
            .strip_suffix("_l")
            .and_then(|b| model.muscle_index(&format!("{b}_r")))
            .map(|i| entry(&model.muscles[i]));
        if mirror_left && twin == Some(entry(m)) {
            continue;
        }
        out.insert(m.name.clone(), entry(m));
    }
    out
}
