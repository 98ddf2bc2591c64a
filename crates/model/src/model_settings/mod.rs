//! A model's own settings file (`<model>.toml` beside the `.osim`): what an OpenSim file
//! does not carry, or what the user wants to change, for a gait prediction — contact
//! spheres, passive joint torques, coordinate actuators, per-muscle metabolic parameters,
//! the fitted muscle-geometry file, distance constraints between bodies, springs on
//! coordinates, per-muscle parameter changes and gravity — and the model's defaults of
//! the gait problem (`[problem]`). Every field has a default; unknown keys are errors naming the
//! file, line and key. [`ModelSettings::apply`] puts the settings into an imported
//! [`Model`].

use crate::contact_check::check_sphere_radius;
use crate::input_file::{read_text_limited, MAX_SETTINGS_BYTES};
use crate::model::{
    ContactParameters, ContactSphere, CoordinateActuator, CoordinateForce, CoordinateForceLaw,
    Model, PassiveJointTorque,
};
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

mod describe;
mod locate;
pub use describe::DescribeError;

/// Everything a model settings file can set (all optional; the defaults leave an imported
/// `.osim` as it is, apart from the metabolic default rule).
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct ModelSettings {
    /// Gravity vector in ground [m s⁻²]; absent: the `.osim` file's.
    pub gravity: Option<[f64; 3]>,
    /// Fitted muscle-geometry file (`stride model fit`), relative to the settings file;
    /// absent: the per-user cache, fitted on first use.
    pub geometry: Option<PathBuf>,
    /// Height [m] of the pelvis origin above the ground when the model stands upright (the
    /// pelvis height of the quasi-random initial guess); absent: derived from the model's
    /// default pose (PREDSIM.md §7.5).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub standing_pelvis_height: Option<f64>,
    /// Foot–ground contact spheres.
    pub contact: ContactSettings,
    /// Passive joint torques per coordinate.
    pub passive_torques: PassiveTorqueSettings,
    /// Ideal torque (or force) actuators of coordinates, e.g. the arms; each replaces the
    /// model's actuators of the same coordinate.
    pub actuators: Vec<ActuatorSetting>,
    /// Per-muscle parameters of the metabolic energy models.
    pub metabolic: MetabolicSettings,
    /// Bounds on the horizontal distance between body origins (anti-clipping constraints
    /// of the gait problem); none unless listed.
    pub distances: Vec<DistanceConstraint>,
    /// Linear springs and dampers on coordinates (OpenSim `SpringGeneralizedForce`),
    /// added to the model's coordinate forces.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub coordinate_springs: Vec<CoordinateSpring>,
    /// Per-muscle parameter changes, each for the muscles its `match` selects; later
    /// entries override earlier ones for the keys they set.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub muscle_parameters: Vec<MuscleParameters>,
    /// The model's defaults of the gait problem: keys of a prediction file's `[problem]`
    /// (checked by the problem crate, which owns them); a prediction file, study file or
    /// command-line option overrides each.
    #[serde(skip_serializing_if = "toml::Table::is_empty")]
    pub problem: toml::Table,
    /// Line of each top-level `[problem]` key in the settings file, for errors (not a key).
    #[serde(skip)]
    pub problem_lines: BTreeMap<String, usize>,
}

/// Contact spheres between the feet and the ground half-space.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct ContactSettings {
    /// Contact law of every sphere listed here (defaults: the paper's generic parameters).
    pub parameters: ContactParameters,
    /// A point of the ground plane, in ground [m] (default: the origin).
    pub plane_point: [f64; 3],
    /// Outward unit normal of the ground half-space, in ground (default: +y).
    pub plane_normal: [f64; 3],
    /// The spheres; when the list is not empty it replaces the model's
    /// `SmoothSphereHalfSpaceForce` elements (or supplies them when it has none).
    pub spheres: Vec<SphereSetting>,
}

impl Default for ContactSettings {
    /// No spheres; the paper's contact law on the plane y = 0.
    fn default() -> Self {
        Self {
            parameters: ContactParameters::default(),
            plane_point: [0.0; 3],
            plane_normal: [0.0, 1.0, 0.0],
            spheres: Vec::new(),
        }
    }
}

/// One contact sphere fixed on a body.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SphereSetting {
    /// Name of the contact element (e.g. `contact_sphere_1_r`).
    pub name: String,
    /// Body carrying the sphere.
    pub body: String,
    /// Sphere centre in the body frame [m].
    pub location: [f64; 3],
    /// Radius [m].
    pub radius: f64,
}

/// Where the passive joint torques of the coordinates come from.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum PassiveTorqueRule {
    /// The model's passive torques are replaced by the `table` when it is not empty, and
    /// kept otherwise.
    #[default]
    Table,
}

/// Passive joint torques: `T = k1 exp(k2 (q − θ2)) + k3 exp(k4 (q − θ1)) − d q̇` [N m].
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct PassiveTorqueSettings {
    /// How the torques are chosen.
    pub rule: PassiveTorqueRule,
    /// Torque laws by coordinate.
    pub table: Vec<PassiveTorqueEntry>,
}

/// One passive torque law, applied to each coordinate listed.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PassiveTorqueEntry {
    /// Coordinates the law applies to.
    pub coordinates: Vec<String>,
    /// Stiffness coefficients `[k1, k2, k3, k4]` ([N m], [rad⁻¹], [N m], [rad⁻¹]);
    /// default zero (damping only).
    #[serde(default)]
    pub k: [f64; 4],
    /// Thresholds `[θ1 (lower), θ2 (upper)]` [rad]; default zero.
    #[serde(default)]
    pub theta: [f64; 2],
    /// Linear damping d [N m s rad⁻¹]; default zero.
    #[serde(default)]
    pub damping: f64,
}

/// An ideal actuator of one coordinate: generalised force = `optimal_force` × control
/// (or × activation, with an activation time constant).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ActuatorSetting {
    /// The actuated coordinate.
    pub coordinate: String,
    /// Torque or force per unit control [N m or N].
    pub optimal_force: f64,
    /// Actuator name (default `<coordinate>_torque`).
    #[serde(default)]
    pub name: Option<String>,
    /// Control bounds (default [−1, 1]).
    #[serde(default = "unit_range")]
    pub control_range: [f64; 2],
    /// Activation time constant [s] (first-order activation dynamics, as an OpenSim
    /// `ActivationCoordinateActuator`); absent: force follows the control directly.
    #[serde(default)]
    pub activation_time_constant: Option<f64>,
}

fn unit_range() -> [f64; 2] {
    [-1.0, 1.0]
}

/// Per-muscle metabolic parameters; muscles without an entry get the defaults (PredSim's
/// rule: slow-twitch fraction 0.5, specific tension 0.25 MPa).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct MetabolicSettings {
    /// Slow-twitch fraction of muscles without an entry (0–1).
    pub default_slow_twitch_fraction: f64,
    /// Specific tension of muscles without an entry [MPa].
    pub default_specific_tension_mpa: f64,
    /// A left muscle (`…_l`) without an entry uses the entry of its right muscle (`…_r`).
    pub mirror_left: bool,
    /// Entries by muscle name.
    pub muscles: BTreeMap<String, MuscleMetabolic>,
    /// Steepness b of the smooth conditionals `½(1 + tanh(b x))` of the Bhargava (2004)
    /// rate (PredSim's `b`; 10 by default, 100 for D'Hondt et al. 2024).
    #[serde(default = "crate::model::default_metabolic_smoothing")]
    pub smoothing: f64,
}

impl Default for MetabolicSettings {
    /// PredSim's defaults (0.5, 0.25 MPa), left muscles mirrored, no entries.
    fn default() -> Self {
        Self {
            default_slow_twitch_fraction: 0.5,
            default_specific_tension_mpa: 0.25,
            mirror_left: true,
            muscles: BTreeMap::new(),
            smoothing: crate::model::default_metabolic_smoothing(),
        }
    }
}

/// Metabolic parameters of one muscle.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MuscleMetabolic {
    /// Fraction of slow-twitch fibres (0–1).
    pub slow_twitch_fraction: f64,
    /// Specific tension σ [MPa] (gives the muscle mass).
    pub specific_tension_mpa: f64,
}

pub use crate::model::DistanceConstraint;

/// A linear spring and damper on a coordinate:
/// `τ = −stiffness (q − rest) − damping q̇` [N m or N].
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CoordinateSpring {
    /// The coordinate.
    pub coordinate: String,
    /// Stiffness [N m rad⁻¹ or N m⁻¹] (default 0).
    #[serde(default)]
    pub stiffness: f64,
    /// Rest value [rad or m] (default 0).
    #[serde(default)]
    pub rest: f64,
    /// Damping [N m s rad⁻¹ or N s m⁻¹] (default 0).
    #[serde(default)]
    pub damping: f64,
}

/// Parameter changes of the muscles selected by name (`[[muscle_parameters]]`).
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MuscleParameters {
    /// A muscle is selected when its name contains any of these strings (PredSim's rule);
    /// each string must select at least one muscle.
    #[serde(rename = "match")]
    pub matches: Vec<String>,
    /// Factor s on the tendon stiffness: k_T = 35 s (the problem's k_T times s), the
    /// tendon curve shift recomputed (PredSim's `tendon_stiff_scale`); absent: unchanged.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub tendon_stiffness_scale: Option<f64>,
    /// Shift λ of the passive fibre force–length curve (PredSim's
    /// `muscle_pass_stiff_shift`): `f_PE = (exp(4κ(l̃_M − λ)/0.6) − 1 − p1)/p2`; absent:
    /// unchanged (1 by default).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub passive_fibre_shift: Option<f64>,
    /// Scale κ of that curve's exponent (PredSim's `muscle_pass_stiff_scale`); absent:
    /// unchanged (1 by default).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub passive_fibre_scale: Option<f64>,
    /// Line of the entry's `match` in the settings file, for errors (not a key).
    #[serde(skip)]
    pub line: Option<usize>,
}

/// A settings file that cannot be read or does not fit the model.
#[derive(Debug, thiserror::Error)]
pub enum ModelSettingsError {
    /// The file could not be read.
    #[error("{file}: {source}")]
    Io {
        /// The settings file.
        file: String,
        /// The reading error.
        source: std::io::Error,
    },
    /// Not valid TOML, an unknown key or a value of the wrong type.
    #[error("{file}:{line}: {message}")]
    Syntax {
        /// The settings file.
        file: String,
        /// Line (1-based).
        line: usize,
        /// What is wrong, with the key.
        message: String,
    },
    /// A value of a known line does not fit the model or its range.
    #[error("{file}:{line}: `{key}`: {message}")]
    ValueAt {
        /// The settings file.
        file: String,
        /// Line (1-based).
        line: usize,
        /// Dotted key of the offending setting.
        key: String,
        /// What is wrong.
        message: String,
    },
    /// A value does not fit the model or its range.
    #[error("{file}: `{key}`: {message}")]
    Value {
        /// The settings file.
        file: String,
        /// Dotted key of the offending setting.
        key: String,
        /// What is wrong.
        message: String,
    },
}

impl ModelSettings {
    /// The settings file found beside a model file: `<stem>.toml` in the same folder.
    /// Anything at that path counts (a folder of that name is an error when read, not
    /// silently skipped).
    pub fn beside(model_file: &Path) -> Option<PathBuf> {
        let p = model_file.with_extension("toml");
        p.exists().then_some(p)
    }

    /// Read a settings file (at most [`MAX_SETTINGS_BYTES`]); a relative `geometry` path
    /// is made relative to its folder.
    pub fn read(path: &Path) -> Result<Self, ModelSettingsError> {
        let file = path.display().to_string();
        let text = read_text_limited(path, MAX_SETTINGS_BYTES).map_err(|source| {
            ModelSettingsError::Io {
                file: file.clone(),
                source,
            }
        })?;
        let mut s = Self::parse(&text, &file)?;
        if let Some(g) = &s.geometry {
            if g.is_relative() {
                let dir = path.parent().unwrap_or(Path::new("."));
                s.geometry = Some(dir.join(g));
            }
        }
        Ok(s)
    }

    /// Parse settings from TOML text; `file` names the source in errors.
    pub fn parse(text: &str, file: &str) -> Result<Self, ModelSettingsError> {
        let line_of = |at: usize| text[..at.min(text.len())].matches('\n').count() + 1;
        let syntax = |e: toml::de::Error| ModelSettingsError::Syntax {
            file: file.into(),
            line: e.span().map_or(1, |s| line_of(s.start)),
            message: e.message().trim().replace('\n', " "),
        };
        let mut s: Self = toml::from_str(text).map_err(syntax)?;
        let spans: MatchSpans = toml::from_str(text).map_err(syntax)?;
        for (entry, span) in s.muscle_parameters.iter_mut().zip(spans.muscle_parameters) {
            entry.line = span.matches.map(|m| line_of(m.span().start));
        }
        s.problem_lines = (spans.problem.into_iter())
            .map(|(k, v)| (k, line_of(v.span().start)))
            .collect();
        Ok(s)
    }

    /// Put the settings into `model` (imported from `file`'s model): gravity, contact
    /// spheres, passive torques, actuators, metabolic parameters, springs and distance
    /// constraints. Errors name the key and the missing body or coordinate. The geometry
    /// file is applied by the caller (it needs the geometry crate).
    pub fn apply(&self, model: &mut Model, file: &str) -> Result<(), ModelSettingsError> {
        let err = |key: String, message: String| ModelSettingsError::Value {
            file: file.into(),
            key,
            message,
        };
        if let Some(g) = self.gravity {
            if g.iter().any(|v| !v.is_finite()) {
                return Err(err("gravity".into(), "must be finite".into()));
            }
            model.gravity = g;
        }
        if let Some(h) = self.standing_pelvis_height {
            if !(h.is_finite() && h > 0.0) {
                return Err(err(
                    "standing_pelvis_height".into(),
                    format!("must be a positive height in metres, got {h}"),
                ));
            }
            model.standing_pelvis_height = Some(h);
        }
        self.apply_contacts(model).map_err(|(k, m)| err(k, m))?;
        self.apply_passive_torques(model)
            .map_err(|(k, m)| err(k, m))?;
        self.apply_actuators(model).map_err(|(k, m)| err(k, m))?;
        self.apply_metabolic(model).map_err(|(k, m)| err(k, m))?;
        self.apply_springs(model).map_err(|(k, m)| err(k, m))?;
        self.apply_muscle_parameters(model)
            .map_err(|(line, key, message)| match line {
                Some(line) => ModelSettingsError::ValueAt {
                    file: file.into(),
                    line,
                    key,
                    message,
                },
                None => err(key, message),
            })?;
        for (i, d) in self.distances.iter().enumerate() {
            for b in &d.bodies {
                if model.body_index(b).is_none() {
                    return Err(err(
                        format!("distances[{i}]"),
                        format!("the model has no body `{b}`"),
                    ));
                }
            }
            if !(d.min.is_finite() && d.max.is_finite() && 0.0 <= d.min && d.min < d.max) {
                return Err(err(
                    format!("distances[{i}]"),
                    format!("needs 0 ≤ min < max (m), got [{}, {}]", d.min, d.max),
                ));
            }
        }
        model.distance_constraints = self.distances.clone();
        Ok(())
    }
}

/// Where each `[[muscle_parameters]]` entry's `match` and each `[problem]` key is in the
/// file.
#[derive(Deserialize)]
struct MatchSpans {
    #[serde(default)]
    muscle_parameters: Vec<MatchSpan>,
    #[serde(default)]
    problem: BTreeMap<String, toml::Spanned<toml::Value>>,
}

#[derive(Deserialize)]
struct MatchSpan {
    #[serde(rename = "match")]
    matches: Option<toml::Spanned<toml::Value>>,
}

/// A failed setting: its dotted key and what is wrong.
type KeyError = (String, String);

/// The ground plane of `[contact]`: a finite point and a finite, non-zero normal.
fn check_plane(c: &ContactSettings) -> Result<(), KeyError> {
    if !c.plane_point.iter().all(|v| v.is_finite()) {
        return Err(("contact.plane_point".into(), "must be finite".into()));
    }
    let n = c.plane_normal;
    let norm = (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt();
    if !(norm.is_finite() && norm > 0.0) {
        return Err((
            "contact.plane_normal".into(),
            format!("{n:?} must be a finite, non-zero vector"),
        ));
    }
    Ok(())
}

fn coordinate(model: &Model, name: &str, key: &str) -> Result<usize, KeyError> {
    model.coordinate_index(name).ok_or_else(|| {
        (
            key.to_string(),
            format!("the model has no coordinate `{name}`"),
        )
    })
}

impl ModelSettings {
    fn apply_contacts(&self, model: &mut Model) -> Result<(), KeyError> {
        let c = &self.contact;
        if c.spheres.is_empty() {
            return Ok(());
        }
        if let Err(e) = c.parameters.check() {
            return Err((format!("contact.parameters.{}", e.key), e.message));
        }
        check_plane(c)?;
        let mut out = Vec::with_capacity(c.spheres.len());
        for (i, s) in c.spheres.iter().enumerate() {
            let key = format!("contact.spheres[{i}]");
            let body = model
                .body_index(&s.body)
                .ok_or_else(|| (key.clone(), format!("the model has no body `{}`", s.body)))?;
            if let Err(e) = check_sphere_radius(s.radius) {
                return Err((format!("{key}.radius"), e.message));
            }
            if !s.location.iter().all(|v| v.is_finite()) {
                return Err((format!("{key}.location"), "must be finite".into()));
            }
            if let Some(j) = c.spheres[..i].iter().position(|o| o.name == s.name) {
                return Err((
                    format!("{key}.name"),
                    format!("`{}` is also the name of contact.spheres[{j}]", s.name),
                ));
            }
            out.push(ContactSphere {
                name: s.name.clone(),
                body,
                location: s.location,
                radius: s.radius,
                parameters: c.parameters,
                plane_point: c.plane_point,
                plane_normal: c.plane_normal,
            });
        }
        model.contacts = out;
        Ok(())
    }

    fn apply_passive_torques(&self, model: &mut Model) -> Result<(), KeyError> {
        let PassiveTorqueRule::Table = self.passive_torques.rule;
        if self.passive_torques.table.is_empty() {
            return Ok(());
        }
        let mut out = Vec::new();
        for (i, e) in self.passive_torques.table.iter().enumerate() {
            let key = format!("passive_torques.table[{i}]");
            for name in &e.coordinates {
                out.push(PassiveJointTorque {
                    coordinate: coordinate(model, name, &key)?,
                    k: e.k,
                    theta: e.theta,
                    damping: e.damping,
                });
            }
        }
        out.sort_by_key(|p| p.coordinate);
        if let Some(w) = out.windows(2).find(|w| w[0].coordinate == w[1].coordinate) {
            let name = &model.coordinates[w[0].coordinate].name;
            return Err((
                "passive_torques.table".into(),
                format!("coordinate `{name}` has two passive torques"),
            ));
        }
        model.passive_torques = out;
        Ok(())
    }

    fn apply_actuators(&self, model: &mut Model) -> Result<(), KeyError> {
        for (i, a) in self.actuators.iter().enumerate() {
            let key = format!("actuators[{i}]");
            let c = coordinate(model, &a.coordinate, &key)?;
            if !(a.optimal_force.is_finite() && a.optimal_force > 0.0) {
                return Err((key, "optimal_force must be positive".into()));
            }
            let [lo, hi] = a.control_range;
            if !(lo.is_finite() && hi.is_finite() && lo <= hi) {
                return Err((
                    format!("{key}.control_range"),
                    format!("[{lo:?}, {hi:?}] must be finite with lower ≤ upper"),
                ));
            }
            if let Some(t) = a.activation_time_constant {
                if !(t.is_finite() && t > 0.0) {
                    return Err((
                        format!("{key}.activation_time_constant"),
                        format!("{t:?} must be finite and > 0 s"),
                    ));
                }
            }
            model.actuators.retain(|x| x.coordinate != c);
            model.actuators.push(CoordinateActuator {
                name: a
                    .name
                    .clone()
                    .unwrap_or_else(|| format!("{}_torque", a.coordinate)),
                coordinate: c,
                optimal_force: a.optimal_force,
                control_range: a.control_range,
                activation_time_constant: a.activation_time_constant,
            });
        }
        Ok(())
    }

    fn apply_metabolic(&self, model: &mut Model) -> Result<(), KeyError> {
        let m = &self.metabolic;
        if !(m.smoothing.is_finite() && m.smoothing > 0.0) {
            return Err((
                "metabolic.smoothing".into(),
                format!("{} must be finite and > 0", m.smoothing),
            ));
        }
        for name in m.muscles.keys() {
            if model.muscle_index(name).is_none() {
                return Err((
                    format!("metabolic.muscles.{name}"),
                    format!("the model has no muscle `{name}`"),
                ));
            }
        }
        for muscle in &mut model.muscles {
            let right = muscle.name.strip_suffix("_l").map(|b| format!("{b}_r"));
            let entry = m.muscles.get(&muscle.name).or_else(|| {
                right
                    .filter(|_| m.mirror_left)
                    .and_then(|r| m.muscles.get(&r))
            });
            let (fst, sigma) = entry.map_or(
                (
                    m.default_slow_twitch_fraction,
                    m.default_specific_tension_mpa,
                ),
                |e| (e.slow_twitch_fraction, e.specific_tension_mpa),
            );
            let key = format!("metabolic.muscles.{}", muscle.name);
            if !(0.0..=1.0).contains(&fst) {
                return Err((key, format!("slow_twitch_fraction {fst} is not in [0, 1]")));
            }
            if !(sigma.is_finite() && sigma > 0.0) {
                return Err((
                    key,
                    format!("specific_tension_mpa {sigma} must be positive"),
                ));
            }
            muscle.slow_twitch_fraction = fst;
            muscle.specific_tension = sigma * 1.0e6;
            muscle.metabolic_smoothing = m.smoothing;
        }
        Ok(())
    }

    /// Per-muscle changes; errors carry the line of the entry's `match`.
    fn apply_muscle_parameters(
        &self,
        model: &mut Model,
    ) -> Result<(), (Option<usize>, String, String)> {
        for (i, e) in self.muscle_parameters.iter().enumerate() {
            let fail = |what: &str, message: String| {
                (e.line, format!("muscle_parameters[{i}]{what}"), message)
            };
            let selects = |name: &str| e.matches.iter().any(|m| name.contains(m.as_str()));
            if e.matches.is_empty() {
                return Err(fail(".match", "lists no name".into()));
            }
            if let Some(m) = e
                .matches
                .iter()
                .find(|m| !model.muscles.iter().any(|x| x.name.contains(m.as_str())))
            {
                return Err(fail(
                    ".match",
                    format!("`{m}` selects no muscle of the model"),
                ));
            }
            for (key, value) in [
                (".tendon_stiffness_scale", e.tendon_stiffness_scale),
                (".passive_fibre_shift", e.passive_fibre_shift),
                (".passive_fibre_scale", e.passive_fibre_scale),
            ] {
                if let Some(s) = value.filter(|s| !(s.is_finite() && *s > 0.0)) {
                    return Err(fail(key, format!("{s} must be finite and > 0")));
                }
            }
            for muscle in model.muscles.iter_mut().filter(|x| selects(&x.name)) {
                let keys = [
                    (&mut muscle.tendon_stiffness_scale, e.tendon_stiffness_scale),
                    (&mut muscle.passive_fibre_shift, e.passive_fibre_shift),
                    (&mut muscle.passive_fibre_scale, e.passive_fibre_scale),
                ];
                for (field, value) in keys {
                    if let Some(v) = value {
                        *field = v;
                    }
                }
            }
        }
        Ok(())
    }

    fn apply_springs(&self, model: &mut Model) -> Result<(), KeyError> {
        for (i, s) in self.coordinate_springs.iter().enumerate() {
            let key = format!("coordinate_springs[{i}]");
            let c = coordinate(model, &s.coordinate, &key)?;
            if ![s.stiffness, s.rest, s.damping]
                .iter()
                .all(|v| v.is_finite())
            {
                return Err((key, "values must be finite".into()));
            }
            model.coordinate_forces.push(CoordinateForce {
                name: format!("{}_spring", s.coordinate),
                coordinate: c,
                law: CoordinateForceLaw::Spring {
                    stiffness: s.stiffness,
                    rest_length: s.rest,
                    viscosity: s.damping,
                },
            });
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::default_model::default_model;

    #[test]
    fn unknown_keys_name_file_line_and_key() {
        let text = "gravity = [0.0, -9.81, 0.0]\n\n[contact]\nsphers = []\n";
        let e = ModelSettings::parse(text, "m.toml")
            .unwrap_err()
            .to_string();
        assert!(e.starts_with("m.toml:4: "), "{e}");
        assert!(e.contains("sphers"), "{e}");
        assert!(!e.contains('\n'), "{e}");
        let e = ModelSettings::parse("[[actuators]]\ncoordinate = \"q\"\n", "m.toml")
            .unwrap_err()
            .to_string();
        assert!(e.contains("optimal_force"), "{e}");
    }

    #[test]
    fn defaults_leave_the_model_but_set_the_metabolic_default_rule() {
        let mut m = default_model();
        let before = m.clone();
        ModelSettings::default().apply(&mut m, "-").unwrap();
        assert_eq!(m.contacts.len(), before.contacts.len());
        assert_eq!(m.passive_torques, before.passive_torques);
        assert!(m.distance_constraints.is_empty());
        assert!(m
            .muscles
            .iter()
            .all(|x| x.slow_twitch_fraction == 0.5 && x.specific_tension == 0.25e6));
    }

    #[test]
    fn settings_are_applied_by_name() {
        let text = r#"
gravity = [0.0, -9.8, 0.0]
[contact]
parameters = { stiffness = 2e6 }
[[contact.spheres]]
name = "heel_r"
body = "calcn_r"
location = [0.0, -0.01, 0.0]
radius = 0.03
[[passive_torques.table]]
coordinates = ["knee_angle_r", "knee_angle_l"]
k = [1.0, -2.0, 3.0, 4.0]
theta = [-1.0, 0.1]
damping = 0.1
[[actuators]]
coordinate = "lumbar_extension"
optimal_force = 300.0
activation_time_constant = 0.035
[metabolic.muscles]
soleus_r = { slow_twitch_fraction = 0.8, specific_tension_mpa = 0.6 }
[[distances]]
bodies = ["calcn_r", "calcn_l"]
min = 0.09
[[coordinate_springs]]
coordinate = "knee_angle_r"
stiffness = 25.0
damping = 2.0
"#;
        let mut m = default_model();
        ModelSettings::parse(text, "t.toml")
            .unwrap()
            .apply(&mut m, "t.toml")
            .unwrap();
        assert_eq!(m.gravity, [0.0, -9.8, 0.0]);
        assert_eq!(m.contacts.len(), 1);
        assert_eq!(m.contacts[0].parameters.stiffness, 2e6);
        assert_eq!(m.contacts[0].parameters.dissipation, 2.0);
        assert_eq!(m.passive_torques.len(), 2);
        let a = m.actuators.last().unwrap();
        assert_eq!(
            (a.name.as_str(), a.optimal_force),
            ("lumbar_extension_torque", 300.0)
        );
        let sol = |n: &str| &m.muscles[m.muscle_index(n).unwrap()];
        assert_eq!(sol("soleus_l").slow_twitch_fraction, 0.8);
        assert_eq!(sol("soleus_r").specific_tension, 0.6e6);
        assert_eq!(sol("tib_ant_r").slow_twitch_fraction, 0.5);
        assert_eq!(m.distance_constraints.len(), 1);
        assert_eq!(m.distance_constraints[0].max, 2.0);
        assert!(m
            .coordinate_forces
            .iter()
            .any(|f| f.name == "knee_angle_r_spring"));
    }

    #[test]
    fn muscle_parameters_select_by_substring_and_later_entries_override() {
        let text = "[[muscle_parameters]]\nmatch = [\"soleus\", \"_gas\"]\ntendon_stiffness_scale = 0.5\n\n[[muscle_parameters]]\nmatch = [\"med_gas_l\"]\ntendon_stiffness_scale = 0.8\n\n[[muscle_parameters]]\nmatch = [\"tib_ant\"]\n";
        let mut m = default_model();
        let s = ModelSettings::parse(text, "t.toml").unwrap();
        assert_eq!(
            s.muscle_parameters
                .iter()
                .map(|e| e.line)
                .collect::<Vec<_>>(),
            [Some(2), Some(6), Some(10)]
        );
        s.apply(&mut m, "t.toml").unwrap();
        let scale = |n: &str| m.muscles[m.muscle_index(n).unwrap()].tendon_stiffness_scale;
        for n in ["soleus_r", "soleus_l", "med_gas_r", "lat_gas_l"] {
            assert_eq!(scale(n), 0.5, "{n}");
        }
        assert_eq!(scale("med_gas_l"), 0.8);
        assert_eq!(scale("tib_ant_r"), 1.0);
        assert_eq!(
            m.muscles
                .iter()
                .filter(|x| x.tendon_stiffness_scale != 1.0)
                .count(),
            6
        );
    }

    #[test]
    fn tendon_stiffness_scales_are_described_as_settings() {
        let mut m = default_model();
        for x in m.muscles.iter_mut().filter(|x| x.name.contains("soleus")) {
            x.tendon_stiffness_scale = 0.5;
        }
        let s = ModelSettings::of_model(&m).unwrap();
        let text = toml::to_string(&s).unwrap();
        let mut back = default_model();
        ModelSettings::parse(&text, "d.toml")
            .unwrap()
            .apply(&mut back, "d.toml")
            .unwrap();
        let scales = |m: &Model| -> Vec<f64> {
            m.muscles.iter().map(|x| x.tendon_stiffness_scale).collect()
        };
        assert_eq!(scales(&back), scales(&m));
    }

    #[test]
    fn muscle_parameters_unknown_keys_name_file_line_and_key() {
        let e = ModelSettings::parse(
            "[[muscle_parameters]]\nmatch = [\"soleus\"]\ntendon_stiffnes_scale = 0.5\n",
            "t.toml",
        )
        .unwrap_err()
        .to_string();
        assert!(
            e.starts_with("t.toml:3: ") && e.contains("tendon_stiffnes_scale"),
            "{e}"
        );
    }

    #[test]
    fn names_missing_from_the_model_and_bad_values_are_errors_with_their_key() {
        for (text, want) in [
            (
                "[[contact.spheres]]\nname = \"s\"\nbody = \"foot\"\nlocation = [0.0, 0.0, 0.0]\nradius = 0.03",
                "t.toml: `contact.spheres[0]`: the model has no body `foot`",
            ),
            (
                "[[distances]]\nbodies = [\"calcn_r\", \"hand_x\"]\nmin = 0.1",
                "t.toml: `distances[0]`: the model has no body `hand_x`",
            ),
            (
                "[[actuators]]\ncoordinate = \"elbow\"\noptimal_force = 1.0",
                "t.toml: `actuators[0]`: the model has no coordinate `elbow`",
            ),
            (
                "[[passive_torques.table]]\ncoordinates = [\"knee\"]",
                "t.toml: `passive_torques.table[0]`: the model has no coordinate `knee`",
            ),
            (
                "[metabolic.muscles]\nsol = { slow_twitch_fraction = 0.5, specific_tension_mpa = 0.3 }",
                "t.toml: `metabolic.muscles.sol`: the model has no muscle `sol`",
            ),
            (
                "gravity = [0.0, -9.81, 0.0]\n[[muscle_parameters]]\nmatch = [\"soleus\", \"gastroc\"]\ntendon_stiffness_scale = 0.5\n",
                "t.toml:3: `muscle_parameters[0].match`: `gastroc` selects no muscle of the model",
            ),
            (
                "[[muscle_parameters]]\nmatch = []\n",
                "t.toml:2: `muscle_parameters[0].match`: lists no name",
            ),
            (
                "[[muscle_parameters]]\nmatch = [\"soleus\"]\ntendon_stiffness_scale = -1.0\n",
                "t.toml:2: `muscle_parameters[0].tendon_stiffness_scale`: -1 must be finite and > 0",
            ),
        ] {
            let mut m = default_model();
            let e = ModelSettings::parse(text, "t.toml")
                .unwrap()
                .apply(&mut m, "t.toml")
                .unwrap_err();
            assert_eq!(e.to_string(), want);
        }
    }

    #[test]
    fn contact_and_actuator_values_out_of_range_are_errors_with_their_key() {
        let sphere = "[[contact.spheres]]\nname = \"s\"\nbody = \"calcn_r\"\nlocation = [0.0, 0.0, 0.0]\nradius = 0.03\n";
        for (text, want) in [
            (
                format!("[contact.parameters]\nstatic_friction = -5.0\n{sphere}"),
                "t.toml: `contact.parameters.static_friction`: -5.0 is out of range: must be finite and ≥ 0",
            ),
            (
                format!("[contact.parameters]\ndynamic_friction = 0.9\n{sphere}"),
                "t.toml: `contact.parameters.dynamic_friction`: 0.9 is larger than static_friction 0.8: the dynamic coefficient must not exceed the static one",
            ),
            (
                format!("[contact]\nplane_normal = [0.0, 0.0, 0.0]\n{sphere}"),
                "t.toml: `contact.plane_normal`: [0.0, 0.0, 0.0] must be a finite, non-zero vector",
            ),
            (
                sphere.replace("0.03", "-0.03"),
                "t.toml: `contact.spheres[0].radius`: -0.03 is out of range: must be in (0, 1] m",
            ),
            (
                format!("{sphere}{sphere}"),
                "t.toml: `contact.spheres[1].name`: `s` is also the name of contact.spheres[0]",
            ),
            (
                "[[actuators]]\ncoordinate = \"lumbar_extension\"\noptimal_force = 1.0\ncontrol_range = [1.0, -1.0]".into(),
                "t.toml: `actuators[0].control_range`: [1.0, -1.0] must be finite with lower ≤ upper",
            ),
            (
                "[[actuators]]\ncoordinate = \"lumbar_extension\"\noptimal_force = 1.0\nactivation_time_constant = 0.0".into(),
                "t.toml: `actuators[0].activation_time_constant`: 0.0 must be finite and > 0 s",
            ),
        ] {
            let mut m = default_model();
            let e = ModelSettings::parse(&text, "t.toml")
                .unwrap()
                .apply(&mut m, "t.toml")
                .unwrap_err();
            assert_eq!(e.to_string(), want);
        }
    }

    #[test]
    fn a_folder_beside_the_model_or_an_endless_file_is_a_read_error() {
        let d = std::env::temp_dir().join(format!("stride-settings-{}", std::process::id()));
        std::fs::create_dir_all(d.join("m.toml")).unwrap();
        let beside = ModelSettings::beside(&d.join("m.osim")).unwrap();
        let e = ModelSettings::read(&beside).unwrap_err().to_string();
        assert!(e.ends_with("m.toml: is a folder, not a file"), "{e}");
        std::fs::remove_dir_all(&d).unwrap();
        let e = ModelSettings::read(Path::new("/dev/zero"))
            .unwrap_err()
            .to_string();
        assert_eq!(
            e,
            "/dev/zero: file of 16.0 MB is larger than the 16 MB accepted"
        );
    }
}
