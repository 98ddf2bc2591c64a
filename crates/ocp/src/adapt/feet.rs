//! Foot contact spheres of an adapted model: the reference model's spheres, expressed in
//! the reference's heel (calcaneus) frame, scaled by the ratio of the two models' foot
//! lengths and put on the bodies of the same name (the heel when the model has no such
//! body). PredSim's rule (`AdaptOpenSimModel`: `scaleContactSpheres` for the radii,
//! `fixContactSpherePositionAfterScaling` for the centres); then each sphere is lifted so
//! that the foot stands on all of them at once in the default pose; decision 0008.

use super::AdaptError;
use crate::gait::side_of;
use stride_model::model_settings::SphereSetting;
use stride_model::Model;
use stride_multibody::spatial::{mat_t_vec, mat_vec};

/// Name stem of the heel body of each foot (`calcn_r`, `calcn_l`).
pub const HEEL: &str = "calcn";

/// Name stem of the toes body of each foot (`toes_r`, `toes_l`).
pub const TOES: &str = "toes";

/// Pose of every body in ground with every coordinate at its default value.
pub struct DefaultPose {
    /// Body orientation: body-frame components to ground components.
    rotation: Vec<[[f64; 3]; 3]>,
    /// Body origin in ground [m].
    position: Vec<[f64; 3]>,
}

impl DefaultPose {
    /// Forward kinematics of `model` at its default coordinate values.
    pub fn of(model: &Model) -> Result<Self, AdaptError> {
        let err = |e: stride_multibody::MultibodyError| AdaptError::Kinematics {
            model: model.name.clone(),
            what: e.to_string(),
        };
        let mut data = stride_multibody::Data::<f64>::new(model).map_err(err)?;
        let q: Vec<f64> = model.coordinates.iter().map(|c| c.default_value).collect();
        let v = vec![0.0; q.len()];
        stride_multibody::forward_kinematics(model, &mut data, &q, &v).map_err(err)?;
        Ok(Self {
            rotation: data.rotation,
            position: data.position,
        })
    }

    /// A point given in the frame of `body` [m], in ground [m].
    pub fn to_ground(&self, body: usize, p: [f64; 3]) -> [f64; 3] {
        let r = mat_vec(&self.rotation[body], p);
        std::array::from_fn(|k| self.position[body][k] + r[k])
    }

    /// A point given in ground [m], in the frame of `body` [m].
    pub fn to_body(&self, body: usize, p: [f64; 3]) -> [f64; 3] {
        let d = std::array::from_fn(|k| p[k] - self.position[body][k]);
        mat_t_vec(&self.rotation[body], d)
    }
}

/// The scale of one foot against the reference model's.
#[derive(Clone, Debug, PartialEq)]
pub struct FootScale {
    /// `'r'` or `'l'`.
    pub side: char,
    /// Foot length of the model [m]: distance from the heel body's origin to the toes
    /// body's origin (the metatarsophalangeal joint centre) in the default pose; None
    /// when the model has no toes body on this side.
    pub length: Option<f64>,
    /// The same length of the reference model [m].
    pub reference_length: Option<f64>,
    /// Factor on the sphere centres (in the heel frame) and radii: length over
    /// reference length, 1 when either is unknown.
    pub factor: f64,
}

/// Distance [m] from the heel body's origin to the toes body's origin on `side`.
fn foot_length(model: &Model, pose: &DefaultPose, side: char) -> Option<f64> {
    let heel = model.body_index(&format!("{HEEL}_{side}"))?;
    let toes = model.body_index(&format!("{TOES}_{side}"))?;
    let d = pose.to_body(heel, pose.position[toes]);
    Some(d.iter().map(|x| x * x).sum::<f64>().sqrt())
}

/// The scale of the right and the left foot of `model` against `reference`.
pub fn foot_scales(
    model: &Model,
    pose: &DefaultPose,
    reference: &Model,
    reference_pose: &DefaultPose,
) -> [FootScale; 2] {
    ['r', 'l'].map(|side| {
        let length = foot_length(model, pose, side);
        let reference_length = foot_length(reference, reference_pose, side);
        let factor = match (length, reference_length) {
            (Some(a), Some(b)) if b > 0.0 => a / b,
            _ => 1.0,
        };
        FootScale {
            side,
            length,
            reference_length,
            factor,
        }
    })
}

/// A contact sphere of the adapted model and where it came from.
#[derive(Clone, Debug, PartialEq)]
pub struct PlacedSphere {
    /// The sphere as a settings entry.
    pub setting: SphereSetting,
    /// Body of the reference sphere it was copied from.
    pub reference_body: String,
    /// Factor applied to the centre (in the heel frame) and the radius.
    pub factor: f64,
    /// Upward shift of the centre [m, along the ground's vertical in the default pose]
    /// that puts its bottom on the plane of the heel spheres' bottoms.
    pub lift: f64,
}

/// The reference model's spheres placed on `model`'s feet, scaled by `scales`. A sphere
/// on a body the model lacks (e.g. the toes of a model without toes) goes onto the heel
/// body of its side, at the same place on the foot.
pub fn place_spheres(
    model: &Model,
    pose: &DefaultPose,
    reference: &Model,
    reference_pose: &DefaultPose,
    scales: &[FootScale; 2],
) -> Result<Vec<PlacedSphere>, AdaptError> {
    let mut out = Vec::with_capacity(reference.contacts.len());
    for c in &reference.contacts {
        let body_name = &reference.bodies[c.body].name;
        let side = side_of(body_name).1.ok_or_else(|| AdaptError::Reference {
            model: reference.name.clone(),
            what: format!(
                "contact sphere `{}` is on `{body_name}`, not on a foot",
                c.name
            ),
        })?;
        let heel_name = format!("{HEEL}_{side}");
        let ref_heel = reference
            .body_index(&heel_name)
            .ok_or_else(|| AdaptError::Reference {
                model: reference.name.clone(),
                what: format!("no body `{heel_name}`"),
            })?;
        let heel = model
            .body_index(&heel_name)
            .ok_or_else(|| AdaptError::NoFoot(heel_name.clone()))?;
        let factor = scales
            .iter()
            .find(|s| s.side == side)
            .map_or(1.0, |s| s.factor);
        let in_ref_heel =
            reference_pose.to_body(ref_heel, reference_pose.to_ground(c.body, c.location));
        let in_heel = in_ref_heel.map(|x| factor * x);
        let body = model.body_index(body_name).unwrap_or(heel);
        let location = pose.to_body(body, pose.to_ground(heel, in_heel));
        out.push(PlacedSphere {
            setting: SphereSetting {
                name: c.name.clone(),
                body: model.bodies[body].name.clone(),
                location,
                radius: factor * c.radius,
            },
            reference_body: body_name.clone(),
            factor,
            lift: 0.0,
        });
    }
    level(model, pose, &mut out);
    Ok(out)
}

/// Lift every sphere so that, in the default pose, its bottom lies at the height of the
/// lowest bottom of the spheres on the heel body of its side: the foot then stands on all
/// of them at once. (The reference's toe spheres hang as low below its heel spheres as
/// the toes' origin below the heel's: 1.8 mm for falisse2022.)
fn level(model: &Model, pose: &DefaultPose, spheres: &mut [PlacedSphere]) {
    for side in ['r', 'l'] {
        let heel = format!("{HEEL}_{side}");
        let of_side = |s: &PlacedSphere| side_of(&s.reference_body).1 == Some(side);
        let bottom = |s: &PlacedSphere| {
            let b = model.body_index(&s.setting.body)?;
            Some(pose.to_ground(b, s.setting.location)[1] - s.setting.radius)
        };
        let plane = (spheres.iter())
            .filter(|s| of_side(s) && s.setting.body == heel)
            .filter_map(bottom)
            .fold(f64::INFINITY, f64::min);
        if !plane.is_finite() {
            continue;
        }
        for s in spheres.iter_mut().filter(|s| of_side(s)) {
            let (Some(b), Some(low)) = (model.body_index(&s.setting.body), bottom(s)) else {
                continue;
            };
            let lift = plane - low;
            let centre = pose.to_ground(b, s.setting.location);
            s.setting.location = pose.to_body(b, [centre[0], centre[1] + lift, centre[2]]);
            s.lift = lift;
        }
    }
}

/// Lowest point [m, ground y] of each sphere in the default pose of `model`.
pub fn sphere_bottoms(model: &Model, pose: &DefaultPose, spheres: &[SphereSetting]) -> Vec<f64> {
    spheres
        .iter()
        .filter_map(|s| {
            let b = model.body_index(&s.body)?;
            Some(pose.to_ground(b, s.location)[1] - s.radius)
        })
        .collect()
}
