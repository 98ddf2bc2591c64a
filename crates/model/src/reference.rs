//! Loaders for the reference tables of the paper (contact spheres, passive torques, polynomials, metabolic parameters).
//!
//! Each loader reads one JSON file of `shared/reference` (documented in its README) and
//! adds its content to a [`Model`] imported from `subject1_v2.osim` (or any model using
//! the same body, coordinate and muscle names).

use crate::model::{
    ContactParameters, ContactSphere, CoordinateActuator, Model, PassiveJointTorque, PathPolynomial,
};
use serde_json::Value;
use std::path::{Path, PathBuf};

/// Errors of the reference loaders; messages name the file and the JSON location.
#[derive(Debug, thiserror::Error)]
pub enum ReferenceError {
    /// The file could not be read.
    #[error("{path}: {source}")]
    Io {
        /// File concerned.
        path: PathBuf,
        /// Underlying I/O error.
        #[source]
        source: std::io::Error,
    },
    /// The file is not valid JSON.
    #[error("{path}: invalid JSON: {source}")]
    Json {
        /// File concerned.
        path: PathBuf,
        /// Parser error (with line and column).
        #[source]
        source: serde_json::Error,
    },
    /// A value is missing, has the wrong type, or names something the model lacks.
    #[error("{path}: {location}: {message}")]
    Invalid {
        /// File concerned.
        path: PathBuf,
        /// JSON location, e.g. `contact/spheres/3/radius`.
        location: String,
        /// What is wrong.
        message: String,
    },
}

/// Torque per unit excitation of the arm actuators s_arms [N m] (FORMULATION 6.2).
pub const ARM_OPTIMAL_FORCE: f64 = 150.0;
/// Linear damping of the arm coordinates [N m s rad⁻¹] (FORMULATION 6.2).
pub const ARM_DAMPING: f64 = 0.1;
/// The eight torque-actuated arm coordinates (FORMULATION 1.1, coordinates 22–29).
pub const ARM_COORDINATES: [&str; 8] = [
    "arm_flex_l",
    "arm_add_l",
    "arm_rot_l",
    "arm_flex_r",
    "arm_add_r",
    "arm_rot_r",
    "elbow_flex_l",
    "elbow_flex_r",
];

/// Largest reference JSON file read [bytes].
const MAX_REFERENCE_BYTES: u64 = 64 << 20;

/// A JSON document with its file name, for located error messages.
struct Doc {
    path: PathBuf,
    root: Value,
}

impl Doc {
    fn read(path: &Path) -> Result<Doc, ReferenceError> {
        let text =
            crate::input_file::read_text_limited(path, MAX_REFERENCE_BYTES).map_err(|source| {
                ReferenceError::Io {
                    path: path.to_path_buf(),
                    source,
                }
            })?;
        let root = serde_json::from_str(&text).map_err(|source| ReferenceError::Json {
            path: path.to_path_buf(),
            source,
        })?;
        Ok(Doc {
            path: path.to_path_buf(),
            root,
        })
    }

    fn err(&self, loc: &str, message: impl Into<String>) -> ReferenceError {
        ReferenceError::Invalid {
            path: self.path.clone(),
            location: loc.to_string(),
            message: message.into(),
        }
    }
}

/// Look up `key` (object member) or index (array element) of a value; `loc` grows.
fn get<'a>(
    doc: &'a Doc,
    v: &'a Value,
    loc: &str,
    key: &str,
) -> Result<(&'a Value, String), ReferenceError> {
    let l = if loc.is_empty() {
        key.to_string()
    } else {
        format!("{loc}/{key}")
    };
    let found = match v {
        Value::Object(m) => m.get(key),
        Value::Array(a) => key.parse::<usize>().ok().and_then(|i| a.get(i)),
        _ => None,
    };
    match found {
        Some(x) => Ok((x, l)),
        None => Err(doc.err(&l, "missing")),
    }
}

fn num(doc: &Doc, v: &Value, loc: &str) -> Result<f64, ReferenceError> {
    v.as_f64()
        .ok_or_else(|| doc.err(loc, format!("expected a number, found `{v}`")))
}

fn num_at(doc: &Doc, v: &Value, loc: &str, key: &str) -> Result<f64, ReferenceError> {
    let (x, l) = get(doc, v, loc, key)?;
    num(doc, x, &l)
}

fn str_at<'a>(doc: &'a Doc, v: &'a Value, loc: &str, key: &str) -> Result<&'a str, ReferenceError> {
    let (x, l) = get(doc, v, loc, key)?;
    x.as_str()
        .ok_or_else(|| doc.err(&l, format!("expected a string, found `{x}`")))
}

fn arr_at<'a>(
    doc: &'a Doc,
    v: &'a Value,
    loc: &str,
    key: &str,
) -> Result<(&'a Vec<Value>, String), ReferenceError> {
    let (x, l) = get(doc, v, loc, key)?;
    match x.as_array() {
        Some(a) => Ok((a, l)),
        None => Err(doc.err(&l, format!("expected an array, found `{x}`"))),
    }
}

fn vec3_at(doc: &Doc, v: &Value, loc: &str, key: &str) -> Result<[f64; 3], ReferenceError> {
    let (a, l) = arr_at(doc, v, loc, key)?;
    if a.len() != 3 {
        return Err(doc.err(&l, format!("expected 3 numbers, found {}", a.len())));
    }
    Ok([
        num(doc, &a[0], &format!("{l}/0"))?,
        num(doc, &a[1], &format!("{l}/1"))?,
        num(doc, &a[2], &format!("{l}/2"))?,
    ])
}

/// Replace the model's contacts by the 12 spheres of `subject1_contact_and_joints.json`
/// (`contact` key): radius 0.032 m, generic parameters, ground plane y = 0 with outward
/// normal +y. Returns the number of spheres.
pub fn add_contacts(model: &mut Model, path: &Path) -> Result<usize, ReferenceError> {
    let doc = Doc::read(path)?;
    let (c, cl) = get(&doc, &doc.root, "", "contact")?;
    let (p, pl) = get(&doc, c, &cl, "common_parameters")?;
    let d = ContactParameters::default();
    let mut parameters = ContactParameters {
        stiffness: num_at(&doc, p, &pl, "stiffness")?,
        dissipation: num_at(&doc, p, &pl, "dissipation")?,
        static_friction: num_at(&doc, p, &pl, "static_friction")?,
        dynamic_friction: num_at(&doc, p, &pl, "dynamic_friction")?,
        viscous_friction: num_at(&doc, p, &pl, "viscous_friction")?,
        transition_velocity: num_at(&doc, p, &pl, "transition_velocity")?,
        ..d
    };
    if let Ok((s, sl)) = get(&doc, c, &cl, "smoothing_constants_matlab_version") {
        parameters.constant_contact_force = num_at(&doc, s, &sl, "eps")?;
        parameters.hertz_smoothing = num_at(&doc, s, &sl, "bd")?;
        parameters.hunt_crossley_smoothing = num_at(&doc, s, &sl, "bv")?;
    }
    let normal = vec3_at(&doc, p, &pl, "normal_in_ground")?;
    let offset = num_at(&doc, p, &pl, "offset")?;
    let plane_point = [normal[0] * offset, normal[1] * offset, normal[2] * offset];
    let (spheres, sl) = arr_at(&doc, c, &cl, "spheres")?;
    let mut out = Vec::with_capacity(spheres.len());
    for (i, s) in spheres.iter().enumerate() {
        let l = format!("{sl}/{i}");
        let body_name = str_at(&doc, s, &l, "body")?;
        let body = model.body_index(body_name).ok_or_else(|| {
            doc.err(
                &format!("{l}/body"),
                format!("the model has no body `{body_name}`"),
            )
        })?;
        let radius = num_at(&doc, s, &l, "radius")?;
        if radius.is_nan() || radius <= 0.0 {
            return Err(doc.err(&format!("{l}/radius"), "radius must be positive"));
        }
        out.push(ContactSphere {
            name: str_at(&doc, s, &l, "name")?.to_string(),
            body,
            location: vec3_at(&doc, s, &l, "location_in_body")?,
            radius,
            parameters,
            plane_point,
            plane_normal: normal,
        });
    }
    model.contacts = out;
    Ok(model.contacts.len())
}

/// Replace the model's passive joint torques by those of `joints/passive_moments.json`
/// (FORMULATION 6.1: the 15 hip, knee, ankle, subtalar and lumbar coordinates, damping
/// 0.1 N m s rad⁻¹) plus pure damping (k = 0, 0.1 N m s rad⁻¹) of the 8 arm
/// coordinates (FORMULATION 6.2, v2: arm damping is a passive torque). Coordinates the
/// model lacks are skipped. Returns the number of passive torques.
pub fn add_passive_torques(model: &mut Model, path: &Path) -> Result<usize, ReferenceError> {
    let doc = Doc::read(path)?;
    let damping = num_at(&doc, &doc.root, "", "damping_legs_and_trunk_Nms_per_rad")?;
    let (joints, jl) = arr_at(&doc, &doc.root, "", "joints")?;
    let mut out = Vec::new();
    for (i, j) in joints.iter().enumerate() {
        let l = format!("{jl}/{i}");
        let k = [
            num_at(&doc, j, &l, "k1")?,
            num_at(&doc, j, &l, "k2")?,
            num_at(&doc, j, &l, "k3")?,
            num_at(&doc, j, &l, "k4")?,
        ];
        let theta = [
            num_at(&doc, j, &l, "theta_lower_rad")?,
            num_at(&doc, j, &l, "theta_upper_rad")?,
        ];
        let (applies, al) = arr_at(&doc, j, &l, "applies_to")?;
        for (n, c) in applies.iter().enumerate() {
            let name = c
                .as_str()
                .ok_or_else(|| doc.err(&format!("{al}/{n}"), "expected a coordinate name"))?;
            if let Some(coordinate) = model.coordinate_index(name) {
                out.push(PassiveJointTorque {
                    coordinate,
                    k,
                    theta,
                    damping,
                });
            }
        }
    }
    let (arms, al) = get(&doc, &doc.root, "", "arms")?;
    let arm_k = num_at(&doc, arms, &al, "stiffness_Nm_per_rad")?;
    if arm_k != 0.0 {
        return Err(doc.err(
            &format!("{al}/stiffness_Nm_per_rad"),
            "linear arm stiffness cannot be expressed as an exponential passive torque",
        ));
    }
    let arm_damping = num_at(&doc, arms, &al, "damping_Nms_per_rad")?;
    let (coords, cl) = arr_at(&doc, arms, &al, "coordinates")?;
    for (n, c) in coords.iter().enumerate() {
        let name = c
            .as_str()
            .ok_or_else(|| doc.err(&format!("{cl}/{n}"), "expected a coordinate name"))?;
        if let Some(coordinate) = model.coordinate_index(name) {
            out.push(PassiveJointTorque {
                coordinate,
                k: [0.0; 4],
                theta: [0.0; 2],
                damping: arm_damping,
            });
        }
    }
    out.sort_by_key(|p| p.coordinate);
    model.passive_torques = out;
    Ok(model.passive_torques.len())
}

/// The right-side name of a left-side muscle (`soleus_l` → `soleus_r`).
fn right_name(name: &str) -> Option<String> {
    name.strip_suffix("_l").map(|b| format!("{b}_r"))
}

/// Set each muscle's slow-twitch fraction and specific tension from
/// `muscles/metabolic_parameters.json` (`per_muscle_right_names`; left muscles use the
/// right muscle's values). Muscles without an entry keep their values. Returns the
/// number of muscles updated.
pub fn add_metabolic_parameters(model: &mut Model, path: &Path) -> Result<usize, ReferenceError> {
    let doc = Doc::read(path)?;
    let (table, tl) = get(&doc, &doc.root, "", "per_muscle_right_names")?;
    let Value::Object(table_map) = table else {
        return Err(doc.err(&tl, "expected an object keyed by muscle name"));
    };
    let mut n = 0;
    for m in &mut model.muscles {
        let key = if table_map.contains_key(&m.name) {
            Some(m.name.clone())
        } else {
            right_name(&m.name).filter(|r| table_map.contains_key(r))
        };
        let Some(key) = key else { continue };
        let l = format!("{tl}/{key}");
        let e = &table_map[&key];
        let fst = num_at(&doc, e, &l, "slow_twitch_fraction")?;
        if !(0.0..=1.0).contains(&fst) {
            return Err(doc.err(
                &format!("{l}/slow_twitch_fraction"),
                format!("{fst} is not in [0, 1]"),
            ));
        }
        let sigma = num_at(&doc, e, &l, "specific_tension_MPa")?;
        if sigma.is_nan() || sigma <= 0.0 {
            return Err(doc.err(&format!("{l}/specific_tension_MPa"), "must be positive"));
        }
        m.slow_twitch_fraction = fst;
        m.specific_tension = sigma * 1.0e6;
        n += 1;
    }
    Ok(n)
}

/// The left-side coordinate in the slot of a right-side one (`knee_angle_r` →
/// `knee_angle_l`); coordinates without a side (lumbar) are shared.
fn left_coordinate(name: &str) -> String {
    match name.strip_suffix("_r") {
        Some(b) => format!("{b}_l"),
        None => name.to_string(),
    }
}

/// Fill `model.path_polynomials` (one entry per muscle) from
/// `muscles/polynomials_subject1.json`: right muscles and the left trunk muscles use
/// their own row; left leg muscles use the right muscle's row evaluated with the
/// corresponding left coordinates. Muscles without a row get `None`. Returns the number
/// of muscles with a polynomial.
pub fn add_path_polynomials(model: &mut Model, path: &Path) -> Result<usize, ReferenceError> {
    let doc = Doc::read(path)?;
    let (rows, rl) = arr_at(&doc, &doc.root, "", "muscles")?;
    let mut polys = Vec::with_capacity(model.muscles.len());
    let mut n = 0;
    for m in &model.muscles {
        let own = rows
            .iter()
            .position(|r| r.get("name").and_then(Value::as_str) == Some(m.name.as_str()));
        let (row, mirror) = match own {
            Some(i) => (Some(i), false),
            None => {
                let r = right_name(&m.name);
                let i = r.and_then(|r| {
                    rows.iter()
                        .position(|x| x.get("name").and_then(Value::as_str) == Some(r.as_str()))
                });
                (i, true)
            }
        };
        let Some(i) = row else {
            polys.push(None);
            continue;
        };
        let l = format!("{rl}/{i}");
        let r = &rows[i];
        let (cs, cl) = arr_at(&doc, r, &l, "coordinates")?;
        let mut coordinates = Vec::with_capacity(cs.len());
        for (k, c) in cs.iter().enumerate() {
            let name = c
                .as_str()
                .ok_or_else(|| doc.err(&format!("{cl}/{k}"), "expected a coordinate name"))?;
            let name = if mirror {
                left_coordinate(name)
            } else {
                name.to_string()
            };
            let id = model.coordinate_index(&name).ok_or_else(|| {
                doc.err(
                    &format!("{cl}/{k}"),
                    format!(
                        "the model has no coordinate `{name}` (for muscle `{}`)",
                        m.name
                    ),
                )
            })?;
            coordinates.push(id);
        }
        let order = num_at(&doc, r, &l, "order")?;
        let (ex, el) = arr_at(&doc, r, &l, "exponents")?;
        let mut exponents = Vec::with_capacity(ex.len());
        for (k, e) in ex.iter().enumerate() {
            let tuple: Option<Vec<u8>> = e.as_array().and_then(|a| {
                a.iter()
                    .map(|x| x.as_u64().and_then(|v| u8::try_from(v).ok()))
                    .collect()
            });
            match tuple {
                Some(t) if t.len() == coordinates.len() => exponents.push(t),
                _ => {
                    return Err(doc.err(
                        &format!("{el}/{k}"),
                        format!("expected {} small non-negative integers", coordinates.len()),
                    ))
                }
            }
        }
        let (co, col) = arr_at(&doc, r, &l, "coefficients")?;
        let coefficients = co
            .iter()
            .enumerate()
            .map(|(k, c)| num(&doc, c, &format!("{col}/{k}")))
            .collect::<Result<Vec<f64>, _>>()?;
        if coefficients.len() != exponents.len() {
            return Err(doc.err(
                &col,
                format!(
                    "{} coefficients but {} exponent tuples",
                    coefficients.len(),
                    exponents.len()
                ),
            ));
        }
        let rmse_length = r.get("fit_rms_error_lMT_m").and_then(Value::as_f64);
        let rmse_moment_arm = r
            .get("fit_rms_error_moment_arm_m")
            .and_then(Value::as_object)
            .map(|o| o.values().filter_map(Value::as_f64).fold(0.0, f64::max));
        polys.push(Some(PathPolynomial {
            coordinates,
            order: order as u32,
            exponents,
            coefficients,
            rmse_length,
            rmse_moment_arm,
        }));
        n += 1;
    }
    model.path_polynomials = polys;
    Ok(n)
}

/// Add one ideal torque actuator (150 N m per unit control, control range [−1, 1]) for
/// each of the 8 arm coordinates the model has (FORMULATION 6.2); existing actuators of
/// those coordinates are replaced. Returns the number of arm actuators.
pub fn add_arm_actuators(model: &mut Model) -> usize {
    let mut n = 0;
    for name in ARM_COORDINATES {
        let Some(coordinate) = model.coordinate_index(name) else {
            continue;
        };
        model.actuators.retain(|a| a.coordinate != coordinate);
        model.actuators.push(CoordinateActuator {
            name: format!("{name}_torque"),
            coordinate,
            optimal_force: ARM_OPTIMAL_FORCE,
            control_range: [-1.0, 1.0],
            activation_time_constant: None,
        });
        n += 1;
    }
    n
}
