//! Contact-sphere geometry files: the centres and radii of a model's contact spheres by
//! name, written by `stride track --calibrate-contact` and read through the
//! `contact_geometry` problem setting, which replaces the model's values before solving.
//!
//! ```toml
//! [[sphere]]
//! name = "sphere_1_r"          # contact sphere (force element) of the model
//! location = [0.0019, -0.021859, -0.0038]   # centre in its body frame [m]
//! radius = 0.032                # [m]
//! ```

use serde::{Deserialize, Serialize};
use std::path::Path;
use stride_model::model_settings::{ModelSettings, SphereSetting};
use stride_model::Model;

/// Largest contact geometry file read [bytes].
const MAX_FILE_BYTES: u64 = 1 << 20;

/// One sphere of a contact geometry file.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SphereEntry {
    /// Name of the model's contact sphere.
    pub name: String,
    /// Centre in the frame of its body [m].
    pub location: [f64; 3],
    /// Radius [m].
    pub radius: f64,
}

/// The contents of a contact geometry file.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ContactGeometry {
    /// The spheres, by name (spheres not listed keep the model's values).
    pub sphere: Vec<SphereEntry>,
}

/// Why a contact geometry file could not be read or applied (the message names the file).
#[derive(Debug, thiserror::Error)]
#[error("contact geometry {file}: {message}")]
pub struct ContactGeometryError {
    /// The file.
    pub file: String,
    /// What is wrong, and where.
    pub message: String,
}

impl ContactGeometry {
    /// The spheres of `model` as a contact geometry.
    pub fn of_model(model: &Model) -> Self {
        Self {
            sphere: model
                .contacts
                .iter()
                .map(|s| SphereEntry {
                    name: s.name.clone(),
                    location: s.location,
                    radius: s.radius,
                })
                .collect(),
        }
    }

    /// Reads the file `path`.
    pub fn read(path: &Path) -> Result<Self, ContactGeometryError> {
        let err = |message: String| ContactGeometryError {
            file: path.display().to_string(),
            message,
        };
        let bytes = stride_model::storage::read_limited(path, MAX_FILE_BYTES)
            .map_err(|e| err(e.to_string()))?;
        let text = String::from_utf8(bytes).map_err(|_| err("not UTF-8 text".into()))?;
        toml::from_str(&text).map_err(|e| err(e.to_string().trim().replace('\n', " ")))
    }

    /// The file text (TOML), with a header line saying what produced it.
    pub fn to_toml(&self, header: &str) -> String {
        let body = toml::to_string(self).unwrap_or_default();
        format!("# {header}\n{body}")
    }

    /// The model settings `settings` of `model` with these spheres: its `[contact]` sphere
    /// list becomes every contact sphere of `model` (name, body), each listed sphere with
    /// this geometry's centre and radius; the contact law and ground plane stay the
    /// settings' when they list spheres, else they are the model's spheres' (an error
    /// when these differ between spheres: a settings file gives one law to all). Every
    /// other setting is kept. Building the model from the result gives it these spheres.
    pub fn into_settings(
        &self,
        model: &Model,
        settings: &ModelSettings,
    ) -> Result<ModelSettings, ContactGeometryError> {
        let mut out = settings.clone();
        if settings.contact.spheres.is_empty() {
            if let Some(first) = model.contacts.first() {
                let law = |c: &stride_model::model::ContactSphere| {
                    (c.parameters, c.plane_point, c.plane_normal)
                };
                if model.contacts.iter().any(|c| law(c) != law(first)) {
                    return Err(ContactGeometryError {
                        file: "model settings".into(),
                        message: "the model's contact spheres differ in contact law or ground \
                                  plane, which one [contact] section cannot give"
                            .into(),
                    });
                }
                out.contact.parameters = first.parameters;
                out.contact.plane_point = first.plane_point;
                out.contact.plane_normal = first.plane_normal;
            }
        }
        out.contact.spheres = model
            .contacts
            .iter()
            .map(|c| {
                let e = self.sphere.iter().find(|e| e.name == c.name);
                SphereSetting {
                    name: c.name.clone(),
                    body: model.bodies[c.body].name.clone(),
                    location: e.map_or(c.location, |e| e.location),
                    radius: e.map_or(c.radius, |e| e.radius),
                }
            })
            .collect();
        Ok(out)
    }

    /// Replaces the centre and radius of every listed sphere of `model`; `file` names the
    /// source in errors (a sphere the model does not have, a radius that is not positive, a
    /// value that is not finite).
    pub fn apply(&self, model: &mut Model, file: &str) -> Result<(), ContactGeometryError> {
        let err = |message: String| ContactGeometryError {
            file: file.into(),
            message,
        };
        for e in &self.sphere {
            let Some(s) = model.contacts.iter_mut().find(|s| s.name == e.name) else {
                return Err(err(format!(
                    "sphere `{}`: the model has no contact sphere of that name",
                    e.name
                )));
            };
            if !(e.radius > 0.0 && e.radius.is_finite() && e.location.iter().all(|v| v.is_finite()))
            {
                return Err(err(format!(
                    "sphere `{}`: radius must be positive and every value finite",
                    e.name
                )));
            }
            s.location = e.location;
            s.radius = e.radius;
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_file_round_trips_and_replaces_only_the_listed_spheres() {
        let mut model = stride_model::default_model::default_model();
        let generic = ContactGeometry::of_model(&model);
        let mut g = ContactGeometry {
            sphere: vec![generic.sphere[0].clone()],
        };
        g.sphere[0].radius = 0.04;
        g.sphere[0].location[0] = 0.01;
        let text = g.to_toml("test");
        let back: ContactGeometry = toml::from_str(&text).unwrap();
        assert_eq!(back, g);
        back.apply(&mut model, "t.toml").unwrap();
        assert_eq!(model.contacts[0].radius, 0.04);
        assert_eq!(model.contacts[0].location[0], 0.01);
        assert_eq!(model.contacts[1].radius, generic.sphere[1].radius);
    }

    #[test]
    fn an_unknown_sphere_is_an_error_naming_file_and_sphere() {
        let mut model = stride_model::default_model::default_model();
        let g = ContactGeometry {
            sphere: vec![SphereEntry {
                name: "heel".into(),
                location: [0.0; 3],
                radius: 0.03,
            }],
        };
        let e = g.apply(&mut model, "c.toml").unwrap_err().to_string();
        assert!(e.contains("c.toml") && e.contains("`heel`"), "{e}");
    }

    #[test]
    fn settings_with_calibrated_spheres_give_a_model_with_those_spheres() {
        let shipped = stride_model::shipped::shipped("subject1").unwrap();
        let settings = ModelSettings::parse(shipped.settings, "subject1").unwrap();
        let model = stride_model::default_model::default_model();
        let mut g = ContactGeometry::of_model(&model);
        g.sphere[2].location = [0.14, -0.02, 0.05];
        g.sphere[2].radius = 0.035;
        let calibrated = g.into_settings(&model, &settings).unwrap();
        // through its file text, onto a fresh import of the model
        let text = toml::to_string(&calibrated).unwrap();
        let back = ModelSettings::parse(&text, "calibrated").unwrap();
        assert_eq!(back.contact, calibrated.contact);
        assert_eq!(back.passive_torques, settings.passive_torques);
        let mut m = stride_model::osim::parse_osim(shipped.osim, shipped.file_name).unwrap();
        back.apply(&mut m, "calibrated").unwrap();
        assert_eq!(m.contacts.len(), model.contacts.len());
        for (c, e) in m.contacts.iter().zip(&g.sphere) {
            assert_eq!(
                (&c.name, c.location, c.radius),
                (&e.name, e.location, e.radius)
            );
        }
        assert_eq!(m.contacts[0].parameters, model.contacts[0].parameters);
    }
}
