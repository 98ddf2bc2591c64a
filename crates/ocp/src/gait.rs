//! The gait view of a model: which coordinates are the free-floating pelvis, which are
//! muscle-driven, which are driven by ideal arm actuators, which are locked, and how
//! left and right map onto each other, and which coupled coordinates follow others
//! (not free variables). Everything is derived from the model (joint tree,
//! actuators, names with `_l`/`_r` suffixes, joint axes), not hard-coded to one model.

use stride_model::{CoordId, JointKind, Model, MotionType};
use stride_multibody::couplers::{compile_couplers, couple, CompiledCoupler};

/// How a free coordinate is driven in the optimal control problem.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Actuation {
    /// Coordinate of the joint between ground and the root body: residual must be zero.
    Root,
    /// Driven by muscles and passive joint torques.
    Muscles,
    /// Driven by an ideal coordinate actuator (index into `Model::actuators`).
    Actuator(usize),
}

/// A free coordinate as the problem sees it.
#[derive(Clone, Debug)]
pub struct GaitCoordinate {
    /// Index in `Model::coordinates`.
    pub model_index: CoordId,
    /// Coordinate name.
    pub name: String,
    /// How it is driven.
    pub actuation: Actuation,
    /// Index (in problem order) of the mirrored coordinate (itself when unsided).
    pub mirror: usize,
    /// +1 if the mirrored motion keeps the sign, −1 if it flips (lateral motions).
    pub mirror_sign: f64,
    /// Rotational (rad) or translational (m).
    pub motion_type: MotionType,
    /// Index in `Model::passive_torques`, if the coordinate has a passive torque.
    pub passive: Option<usize>,
    /// Range of the coordinate in the model file `[min, max]` [rad or m].
    pub range: [f64; 2],
}

/// The gait view of a model (problem order of coordinates and muscles, mirror maps).
#[derive(Clone, Debug)]
pub struct GaitModel {
    /// Free coordinates in problem order.
    pub coordinates: Vec<GaitCoordinate>,
    /// Locked coordinates and the value they are held at [rad or m].
    pub locked: Vec<(CoordId, f64)>,
    /// Coupled coordinates: computed from their independent coordinate, never free.
    pub couplers: Vec<CompiledCoupler>,
    /// Model muscle indices in problem order (left side, right side, unsided).
    pub muscles: Vec<usize>,
    /// For each problem muscle, the problem index of its mirror.
    pub muscle_mirror: Vec<usize>,
    /// Problem index of the forward pelvis translation (along ground x).
    pub forward_translation: usize,
    /// Problem index of the vertical pelvis translation (along ground y).
    pub vertical_translation: usize,
}

/// Why a model cannot be used for a gait problem.
#[derive(Debug, thiserror::Error)]
pub enum GaitModelError {
    /// No joint connects the ground to a body with six degrees of freedom.
    #[error("the model has no free-floating root joint (ground to pelvis with 3 rotations and 3 translations)")]
    NoRoot,
    /// A coordinate is neither the root, muscle-driven nor actuated.
    #[error("coordinate `{0}` is free but driven by no muscle and no actuator: lock it or add an actuator")]
    Undriven(String),
    /// A sided name has no counterpart on the other side.
    #[error("{kind} `{name}` has no mirror `{mirror}` on the other side")]
    NoMirror {
        /// "coordinate" or "muscle".
        kind: &'static str,
        /// The name.
        name: String,
        /// The expected mirror name.
        mirror: String,
    },
    /// The model has no contact sphere, so its feet cannot push on the ground.
    #[error("the model has no foot contact: add SmoothSphereHalfSpaceForce elements to the .osim file or contact spheres (`[[contact.spheres]]`) to its settings file")]
    NoContact,
    /// The model has no polynomial muscle geometry.
    #[error("the model has no fitted muscle geometry (run `stride model fit`)")]
    NoGeometry,
    /// An unsided coordinate moves about an axis that is neither in nor normal to the sagittal plane.
    #[error("cannot decide the left-right mirror of coordinate `{0}`: its axis is oblique to the sagittal plane")]
    ObliqueAxis(String),
    /// The fitted geometry spans a coupled coordinate (fitted outside stride or before
    /// coupled coordinates followed their constraint).
    #[error("the fitted muscle geometry spans the coupled coordinate `{0}`: fit it again (`stride model fit`), so that it spans the independent coordinate instead")]
    SpansCoupled(String),
    /// A force element acts on a coupled coordinate, which is not a variable.
    #[error("coordinate `{coordinate}` follows `{independent}` (coupled) but has {what}: put it on `{independent}` or remove it")]
    CoupledDriven {
        /// The coupled coordinate.
        coordinate: String,
        /// The coordinate it follows.
        independent: String,
        /// What acts on it.
        what: &'static str,
    },
    /// A coordinate coupler cannot be evaluated.
    #[error("{0}")]
    Coupler(String),
}

/// Split a name into (base, side) where side is 'l', 'r' or none.
pub fn side_of(name: &str) -> (&str, Option<char>) {
    if let Some(b) = name.strip_suffix("_l") {
        (b, Some('l'))
    } else if let Some(b) = name.strip_suffix("_r") {
        (b, Some('r'))
    } else {
        (name, None)
    }
}

/// The name of the mirror of a sided name (`x_l` ↔ `x_r`); unsided names mirror to themselves.
pub fn mirror_name(name: &str) -> String {
    match side_of(name) {
        (b, Some('l')) => format!("{b}_r"),
        (b, Some('r')) => format!("{b}_l"),
        _ => name.to_string(),
    }
}

impl GaitModel {
    /// Classify the coordinates and muscles of `model`.
    pub fn new(model: &Model) -> Result<Self, GaitModelError> {
        if model.contacts.is_empty() {
            return Err(GaitModelError::NoContact);
        }
        let root_joint = model
            .joints
            .iter()
            .position(|j| j.parent == 0 && matches!(j.kind, JointKind::Custom { .. }))
            .ok_or(GaitModelError::NoRoot)?;
        // Order joints by base name (first appearance), left before right (the order of
        // the reference implementation: pelvis, hip l/r, knee l/r, ..., lumbar, arms).
        let mut bases: Vec<&str> = Vec::new();
        for j in &model.joints {
            let (b, _) = side_of(&j.name);
            if !bases.contains(&b) {
                bases.push(b);
            }
        }
        let mut joint_order = vec![root_joint];
        for b in &bases {
            for side in [Some('l'), Some('r'), None] {
                for (ji, j) in model.joints.iter().enumerate() {
                    if ji != root_joint && side_of(&j.name) == (*b, side) {
                        joint_order.push(ji);
                    }
                }
            }
        }
        let actuated: Vec<Option<usize>> = (0..model.coordinates.len())
            .map(|c| model.actuators.iter().position(|a| a.coordinate == c))
            .collect();
        let spanned: Vec<bool> = (0..model.coordinates.len())
            .map(|c| {
                model
                    .path_polynomials
                    .iter()
                    .flatten()
                    .any(|p| p.coordinates.contains(&c))
            })
            .collect();
        if model.path_polynomials.iter().all(|p| p.is_none()) && !model.muscles.is_empty() {
            return Err(GaitModelError::NoGeometry);
        }
        for k in &model.couplers {
            let d = k.dependent;
            let what = if actuated[d].is_some() {
                "an actuator"
            } else if model.passive_torques.iter().any(|p| p.coordinate == d) {
                "a passive torque"
            } else if model.coordinate_forces.iter().any(|f| f.coordinate == d) {
                "a coordinate force"
            } else {
                continue;
            };
            return Err(GaitModelError::CoupledDriven {
                coordinate: model.coordinates[d].name.clone(),
                independent: model.coordinates[k.independent].name.clone(),
                what,
            });
        }
        if let Some(k) = model.couplers.iter().find(|k| spanned[k.dependent]) {
            return Err(GaitModelError::SpansCoupled(
                model.coordinates[k.dependent].name.clone(),
            ));
        }
        let mut coordinates = Vec::new();
        let mut locked = Vec::new();
        for &ji in &joint_order {
            for (ci, c) in model.coordinates.iter().enumerate() {
                // A coupled coordinate is not a free variable: the multibody layer and the
                // outputs compute it from its independent coordinate.
                if c.joint != ji || model.couplers.iter().any(|k| k.dependent == ci) {
                    continue;
                }
                if c.locked {
                    locked.push((ci, c.default_value));
                    continue;
                }
                let actuation = if ji == root_joint {
                    Actuation::Root
                } else if let Some(a) = actuated[ci] {
                    Actuation::Actuator(a)
                } else if spanned[ci] {
                    Actuation::Muscles
                } else {
                    return Err(GaitModelError::Undriven(c.name.clone()));
                };
                coordinates.push(GaitCoordinate {
                    model_index: ci,
                    name: c.name.clone(),
                    actuation,
                    mirror: 0,
                    mirror_sign: 1.0,
                    motion_type: c.motion_type,
                    passive: model
                        .passive_torques
                        .iter()
                        .position(|p| p.coordinate == ci),
                    range: c.range,
                });
            }
        }
        // Mirror maps.
        for i in 0..coordinates.len() {
            let name = coordinates[i].name.clone();
            let mname = mirror_name(&name);
            let m = coordinates
                .iter()
                .position(|c| c.name == mname)
                .ok_or_else(|| GaitModelError::NoMirror {
                    kind: "coordinate",
                    name: name.clone(),
                    mirror: mname.clone(),
                })?;
            coordinates[i].mirror = m;
            if side_of(&name).1.is_none() {
                coordinates[i].mirror_sign = unsided_mirror_sign(model, coordinates[i].model_index)
                    .ok_or_else(|| GaitModelError::ObliqueAxis(name.clone()))?;
            }
        }
        let forward_translation =
            translation_along(model, &coordinates, 0).ok_or(GaitModelError::NoRoot)?;
        let vertical_translation =
            translation_along(model, &coordinates, 1).ok_or(GaitModelError::NoRoot)?;
        // Muscles: left, right, unsided — each in model order.
        let mut muscles = Vec::new();
        for side in [Some('l'), Some('r'), None] {
            for (mi, m) in model.muscles.iter().enumerate() {
                if side_of(&m.name).1 == side {
                    muscles.push(mi);
                }
            }
        }
        let mut muscle_mirror = Vec::with_capacity(muscles.len());
        for &mi in &muscles {
            let name = &model.muscles[mi].name;
            let mname = mirror_name(name);
            let m = muscles
                .iter()
                .position(|&k| model.muscles[k].name == mname)
                .ok_or_else(|| GaitModelError::NoMirror {
                    kind: "muscle",
                    name: name.clone(),
                    mirror: mname.clone(),
                })?;
            muscle_mirror.push(m);
        }
        let couplers =
            compile_couplers(model).map_err(|e| GaitModelError::Coupler(e.to_string()))?;
        Ok(Self {
            coordinates,
            locked,
            couplers,
            muscles,
            muscle_mirror,
            forward_translation,
            vertical_translation,
        })
    }

    /// Overwrites the coupled coordinates of model-ordered values `q` [rad or m], speeds
    /// `v` [rad s⁻¹ or m s⁻¹] and accelerations `a` [rad s⁻² or m s⁻²] (when given) from
    /// their independent coordinates.
    pub fn couple(&self, q: &mut [f64], v: &mut [f64], a: Option<&mut [f64]>) {
        couple(&self.couplers, q, v, a);
    }

    /// Number of free coordinates.
    pub fn nq(&self) -> usize {
        self.coordinates.len()
    }
    /// Number of muscles.
    pub fn nm(&self) -> usize {
        self.muscles.len()
    }
    /// Problem indices of the root (pelvis) coordinates.
    pub fn root(&self) -> Vec<usize> {
        self.indices(|a| a == Actuation::Root)
    }
    /// Problem indices of the muscle-driven coordinates.
    pub fn muscle_driven(&self) -> Vec<usize> {
        self.indices(|a| a == Actuation::Muscles)
    }
    /// Problem indices of the actuator-driven (arm) coordinates.
    pub fn actuator_driven(&self) -> Vec<usize> {
        self.indices(|a| matches!(a, Actuation::Actuator(_)))
    }
    /// Whether the model moves in the sagittal plane only: its root has no lateral (ground
    /// z) translation (a 2D model such as gait1018: no trunk sway, hip abduction or rotation,
    /// lateral force or step width).
    pub fn is_planar(&self, model: &Model) -> bool {
        translation_along(model, &self.coordinates, 2).is_none()
    }
    /// Problem index of a coordinate by name.
    pub fn index_of(&self, name: &str) -> Option<usize> {
        self.coordinates.iter().position(|c| c.name == name)
    }
    fn indices(&self, f: impl Fn(Actuation) -> bool) -> Vec<usize> {
        (0..self.coordinates.len())
            .filter(|&i| f(self.coordinates[i].actuation))
            .collect()
    }
}

/// Whether model coordinate `c` moves an arm: its joint, or a joint between it and the
/// ground, is named `acromial…` (PredSim's arm detection, PREDSIM.md §3.2) or
/// `shoulder…` (gait2392 and the built-in model). An actuated coordinate that is not an
/// arm (gait1018's lumbar) counts in the acceleration cost.
pub fn is_arm_coordinate(model: &Model, c: CoordId) -> bool {
    let mut j = model.coordinates[c].joint;
    for _ in 0..model.joints.len() {
        let name = &model.joints[j].name;
        if name.starts_with("acromial") || name.starts_with("shoulder") {
            return true;
        }
        let parent = model.joints[j].parent;
        match model.joints.iter().position(|x| x.child == parent) {
            Some(p) => j = p,
            None => return false,
        }
    }
    false
}

/// Sign of an unsided coordinate under the sagittal-plane mirror: rotations about an axis
/// normal to the sagittal plane (z) and translations in it keep their sign; rotations about
/// axes in the plane and translations along z flip.
fn unsided_mirror_sign(model: &Model, c: CoordId) -> Option<f64> {
    let joint = &model.joints[model.coordinates[c].joint];
    let JointKind::Custom {
        rotations,
        translations,
    } = &joint.kind
    else {
        return None;
    };
    let axis_of = |axes: &[stride_model::TransformAxis; 3]| {
        axes.iter()
            .find(|a| a.coordinate == Some(c))
            .map(|a| a.axis)
    };
    let (axis, rotational) = match axis_of(rotations) {
        Some(a) => (a, true),
        None => (axis_of(translations)?, false),
    };
    let n = (axis[0] * axis[0] + axis[1] * axis[1] + axis[2] * axis[2]).sqrt();
    let z = (axis[2] / n).abs();
    let along_z = z > 1.0 - 1e-6;
    let in_plane = z < 1e-6;
    match (rotational, along_z, in_plane) {
        (true, true, _) => Some(1.0),
        (true, _, true) => Some(-1.0),
        (false, true, _) => Some(-1.0),
        (false, _, true) => Some(1.0),
        _ => None,
    }
}

/// Problem index of the root translation along ground axis `k` (0 = x, 1 = y).
fn translation_along(model: &Model, coords: &[GaitCoordinate], k: usize) -> Option<usize> {
    coords.iter().position(|gc| {
        // OpenSim calls a root translation coupled when its axis function is not a plain
        // unit-slope LinearFunction (e.g. a scaled model's MultiplierFunction): the axis
        // decides, not the motion type.
        if gc.actuation != Actuation::Root || gc.motion_type == MotionType::Rotational {
            return false;
        }
        let joint = &model.joints[model.coordinates[gc.model_index].joint];
        match &joint.kind {
            JointKind::Custom { translations, .. } => translations
                .iter()
                .any(|t| t.coordinate == Some(gc.model_index) && t.axis[k].abs() > 1.0 - 1e-9),
            _ => false,
        }
    })
}
