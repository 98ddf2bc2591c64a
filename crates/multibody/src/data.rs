//! The preallocated workspace of the multibody algorithms (model/data split).

use stride_ad::Scalar;
use stride_model::function::CompiledFunction;
use stride_model::{BodyId, JointKind, Model};

use crate::couplers::CompiledCoupler;
use crate::error::MultibodyError;
use crate::spatial::identity;
use crate::spatial::{body_fixed_xyz, transpose_f, zero3, Mat3, Vec3};

/// One transform axis of a joint, prepared for evaluation.
#[derive(Clone, Debug)]
pub struct AxisInfo {
    /// Unit axis in the parent joint frame F (normalised from the model).
    pub axis: [f64; 3],
    /// Coordinate read by the function, if any (otherwise the function is evaluated at 0).
    pub coordinate: Option<usize>,
    /// Angle [rad] or displacement [m] as a function of the coordinate.
    pub function: CompiledFunction,
}

/// A joint prepared for evaluation (constant frame rotations, normalised axes).
#[derive(Clone, Debug)]
pub struct JointInfo {
    /// Parent body.
    pub parent: BodyId,
    /// Child body.
    pub child: BodyId,
    /// Rotation from joint frame F to parent body axes.
    pub r_parent_f: [[f64; 3]; 3],
    /// Origin of F in the parent body frame [m].
    pub p_parent_f: [f64; 3],
    /// Rotation from child body axes to joint frame M (transpose of M's orientation in child).
    pub r_m_child: [[f64; 3]; 3],
    /// Origin of M in the child body frame [m].
    pub p_child_m: [f64; 3],
    /// F has zero orientation in the parent (skip a matrix product).
    pub parent_f_identity: bool,
    /// M has zero orientation in the child (skip a matrix product).
    pub child_m_identity: bool,
    /// Rotation axes 1–3 in order, without the axes fixed at zero (empty for welds).
    pub rotations: Vec<AxisInfo>,
    /// Translation axes 1–3 in order, without the axes fixed at zero (empty for welds).
    pub translations: Vec<AxisInfo>,
}

/// Which contact bodies make up each foot (e.g. right = calcn_r + toes_r), for the ground
/// reaction force totals of [`crate::skeleton_dynamics`].
#[derive(Clone, Debug, PartialEq)]
pub struct ContactGroups {
    /// Group names (e.g. `"right"`, `"left"`).
    pub names: Vec<String>,
    /// Bodies of each group.
    pub bodies: Vec<Vec<BodyId>>,
}

impl ContactGroups {
    /// Groups derived from the contact spheres: bodies whose name ends in `_r` form
    /// `"right"`, `_l` form `"left"`; any other contact body forms its own group.
    pub fn left_right(model: &Model) -> Self {
        let mut g = Self {
            names: vec!["right".into(), "left".into()],
            bodies: vec![Vec::new(), Vec::new()],
        };
        for s in &model.contacts {
            let Some(body) = model.bodies.get(s.body) else {
                continue;
            };
            let gi = if body.name.ends_with("_r") {
                0
            } else if body.name.ends_with("_l") {
                1
            } else if let Some(k) = g.names.iter().position(|n| *n == body.name) {
                k
            } else {
                g.names.push(body.name.clone());
                g.bodies.push(Vec::new());
                g.names.len() - 1
            };
            if !g.bodies[gi].contains(&s.body) {
                g.bodies[gi].push(s.body);
            }
        }
        g
    }

    /// Groups given by body names, e.g. `[("right", &["calcn_r", "toes_r"])]`.
    pub fn from_body_names(
        model: &Model,
        groups: &[(&str, &[&str])],
    ) -> Result<Self, MultibodyError> {
        let mut g = Self {
            names: Vec::new(),
            bodies: Vec::new(),
        };
        for (name, bodies) in groups {
            let mut ids = Vec::new();
            for b in *bodies {
                let id = model
                    .body_index(b)
                    .ok_or_else(|| MultibodyError::UnknownBody {
                        group: name.to_string(),
                        body: b.to_string(),
                    })?;
                ids.push(id);
            }
            g.names.push(name.to_string());
            g.bodies.push(ids);
        }
        Ok(g)
    }

    /// Group of a body, if any.
    pub fn group_of(&self, body: BodyId) -> Option<usize> {
        self.bodies.iter().position(|b| b.contains(&body))
    }
}

/// Workspace of the multibody algorithms for one model and one scalar type: compiled
/// joint data plus per-body kinematics and loads (all in ground), reused across calls.
#[derive(Clone, Debug)]
pub struct Data<T: Scalar> {
    /// Prepared joints, in the model's (topological) order.
    pub joints: Vec<JointInfo>,
    /// Number of coordinates of the model.
    pub n_coordinates: usize,
    /// Body orientation: maps body-frame components to ground components.
    pub rotation: Vec<Mat3<T>>,
    /// Body origin position in ground [m].
    pub position: Vec<Vec3<T>>,
    /// Body angular velocity in ground [rad s⁻¹].
    pub angular_velocity: Vec<Vec3<T>>,
    /// Body origin velocity in ground [m s⁻¹].
    pub linear_velocity: Vec<Vec3<T>>,
    /// Body angular acceleration in ground [rad s⁻²] (set by inverse dynamics).
    pub angular_acceleration: Vec<Vec3<T>>,
    /// Body origin acceleration in ground [m s⁻²] (set by inverse dynamics).
    pub linear_acceleration: Vec<Vec3<T>>,
    /// External force on each body, in ground [N] (cleared by [`Data::clear_external`]).
    pub external_force: Vec<Vec3<T>>,
    /// External moment on each body about its origin, in ground [N m].
    pub external_moment: Vec<Vec3<T>>,
    /// Per joint: rotation axes in ground (partial angular velocities) [-].
    pub(crate) joint_s: Vec<[Vec3<T>; 3]>,
    /// Per joint: translation axes in ground [-].
    pub(crate) joint_b: Vec<[Vec3<T>; 3]>,
    /// Per joint: `[f', f'']` of rotation (0–2) and translation (3–5) functions.
    pub(crate) joint_df: Vec<[[T; 2]; 6]>,
    /// Per joint: origin of frame M in ground [m].
    pub(crate) joint_origin: Vec<Vec3<T>>,
    /// Per body: transmitted force through its joint [N] (inverse-dynamics scratch).
    pub(crate) load_force: Vec<Vec3<T>>,
    /// Per body: transmitted moment about its origin [N m] (inverse-dynamics scratch).
    pub(crate) load_moment: Vec<Vec3<T>>,
    /// Contact groups used by [`crate::skeleton_dynamics`].
    pub groups: ContactGroups,
    /// Group index of each contact sphere.
    pub(crate) sphere_group: Vec<Option<usize>>,
    /// Unit outward plane normal of each contact sphere.
    pub(crate) sphere_normal: Vec<[f64; 3]>,
    /// Coupled coordinates of the model (eliminated by substitution).
    pub couplers: Vec<CompiledCoupler>,
    /// Coordinates, speeds and accelerations with the dependent coordinates filled in
    /// (used only when the model has couplers).
    pub(crate) coupled: [Vec<T>; 3],
}

fn norm3(a: [f64; 3]) -> f64 {
    (a[0] * a[0] + a[1] * a[1] + a[2] * a[2]).sqrt()
}

impl<T: Scalar> Data<T> {
    /// Prepare the workspace of `model`: checks the tree, normalises axes, compiles the
    /// coordinate functions once (spline handles are cached here), allocates all buffers.
    pub fn new(model: &Model) -> Result<Self, MultibodyError> {
        let nb = model.bodies.len();
        let nc = model.coordinates.len();
        let mut placed = vec![false; nb];
        if nb > 0 {
            placed[0] = true;
        }
        let mut joints = Vec::with_capacity(model.joints.len());
        for j in &model.joints {
            let topo = |reason: String| MultibodyError::Topology {
                joint: j.name.clone(),
                reason,
            };
            if j.parent >= nb || j.child >= nb {
                return Err(topo(format!(
                    "parent {} or child {} outside the {nb} bodies",
                    j.parent, j.child
                )));
            }
            if !placed[j.parent] {
                return Err(topo(
                    "parent body is not the ground or the child of an earlier joint".into(),
                ));
            }
            if placed[j.child] {
                return Err(topo(
                    "child body already placed by another joint (or is the ground)".into(),
                ));
            }
            placed[j.child] = true;
            let mut info = JointInfo {
                parent: j.parent,
                child: j.child,
                r_parent_f: body_fixed_xyz(j.frame_in_parent.orientation),
                p_parent_f: j.frame_in_parent.location,
                r_m_child: transpose_f(&body_fixed_xyz(j.frame_in_child.orientation)),
                p_child_m: j.frame_in_child.location,
                parent_f_identity: j.frame_in_parent.orientation == [0.0; 3],
                child_m_identity: j.frame_in_child.orientation == [0.0; 3],
                rotations: Vec::new(),
                translations: Vec::new(),
            };
            if let JointKind::Custom {
                rotations,
                translations,
            } = &j.kind
            {
                for (k, ax) in rotations.iter().chain(translations.iter()).enumerate() {
                    let bad = |reason: String| MultibodyError::Axis {
                        joint: j.name.clone(),
                        axis: k,
                        reason,
                    };
                    let n = norm3(ax.axis);
                    if !(n.is_finite() && n > 1e-12) {
                        return Err(bad(format!("axis {:?} has no direction", ax.axis)));
                    }
                    if let Some(c) = ax.coordinate {
                        if c >= nc {
                            return Err(bad(format!(
                                "coordinate index {c} outside the {nc} coordinates"
                            )));
                        }
                    }
                    let function =
                        ax.function
                            .compile()
                            .map_err(|source| MultibodyError::Function {
                                joint: j.name.clone(),
                                axis: k,
                                source,
                            })?;
                    // An axis with no coordinate and a zero function never moves the
                    // child: drop it (saves the trigonometry in the hot loop).
                    if ax.coordinate.is_none() && function.eval_f64(0.0)[0] == 0.0 {
                        continue;
                    }
                    let a = AxisInfo {
                        axis: [ax.axis[0] / n, ax.axis[1] / n, ax.axis[2] / n],
                        coordinate: ax.coordinate,
                        function,
                    };
                    if k < 3 {
                        info.rotations.push(a);
                    } else {
                        info.translations.push(a);
                    }
                }
            }
            joints.push(info);
        }
        if let Some(b) = placed.iter().position(|p| !p) {
            return Err(MultibodyError::Topology {
                joint: String::new(),
                reason: format!(
                    "body `{}` is not the child of any joint",
                    model.bodies[b].name
                ),
            });
        }
        let mut sphere_normal = Vec::with_capacity(model.contacts.len());
        for s in &model.contacts {
            let bad = |reason: String| MultibodyError::Contact {
                sphere: s.name.clone(),
                reason,
            };
            if s.body >= nb || s.body == 0 {
                return Err(bad(format!("body index {} is not a moving body", s.body)));
            }
            let n = norm3(s.plane_normal);
            if !(n.is_finite() && n > 1e-12) {
                return Err(bad(format!(
                    "plane normal {:?} has no direction",
                    s.plane_normal
                )));
            }
            if !(s.radius.is_finite() && s.radius >= 0.0) {
                return Err(bad(format!("radius {} is negative", s.radius)));
            }
            sphere_normal.push([
                s.plane_normal[0] / n,
                s.plane_normal[1] / n,
                s.plane_normal[2] / n,
            ]);
        }
        let groups = ContactGroups::left_right(model);
        let sphere_group = model
            .contacts
            .iter()
            .map(|s| groups.group_of(s.body))
            .collect();
        let nj = joints.len();
        Ok(Self {
            joints,
            n_coordinates: nc,
            rotation: vec![identity(); nb],
            position: vec![zero3(); nb],
            angular_velocity: vec![zero3(); nb],
            linear_velocity: vec![zero3(); nb],
            angular_acceleration: vec![zero3(); nb],
            linear_acceleration: vec![zero3(); nb],
            external_force: vec![zero3(); nb],
            external_moment: vec![zero3(); nb],
            joint_s: vec![[zero3(); 3]; nj],
            joint_b: vec![[zero3(); 3]; nj],
            joint_df: vec![[[T::zero(); 2]; 6]; nj],
            joint_origin: vec![zero3(); nj],
            load_force: vec![zero3(); nb],
            load_moment: vec![zero3(); nb],
            groups,
            sphere_group,
            sphere_normal,
            couplers: crate::couplers::compile_couplers(model)?,
            coupled: [
                vec![T::zero(); nc],
                vec![T::zero(); nc],
                vec![T::zero(); nc],
            ],
        })
    }

    /// Replace the contact groups (ground-reaction totals per foot).
    pub fn set_contact_groups(&mut self, model: &Model, groups: ContactGroups) {
        self.sphere_group = model
            .contacts
            .iter()
            .map(|s| groups.group_of(s.body))
            .collect();
        self.groups = groups;
    }

    /// Remove all external loads.
    pub fn clear_external(&mut self) {
        for f in self
            .external_force
            .iter_mut()
            .chain(self.external_moment.iter_mut())
        {
            *f = zero3();
        }
    }

    /// Add a force [N] (ground components) applied at `point` (ground, [m]) to `body`,
    /// referred to the body origin; call after forward kinematics (uses the origin position).
    pub fn add_point_force(&mut self, body: BodyId, force: Vec3<T>, point: Vec3<T>) {
        use crate::spatial::{add, cross, sub};
        let r = sub(point, self.position[body]);
        self.external_force[body] = add(self.external_force[body], force);
        self.external_moment[body] = add(self.external_moment[body], cross(r, force));
    }

    /// Add a pure moment [N m] (ground components) to `body`.
    pub fn add_moment(&mut self, body: BodyId, moment: Vec3<T>) {
        self.external_moment[body] = crate::spatial::add(self.external_moment[body], moment);
    }
}
