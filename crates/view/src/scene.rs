//! What the page draws: the model's solids (bodies as cylinders between joint centres
//! sized by mass, contact spheres) and, per frame, every body's pose and every muscle's
//! path points in ground, from `stride_geometry`'s forward kinematics and path points.

use crate::error::ViewError;
use crate::frames::Frames;
use serde::Serialize;
use stride_geometry::kinematics::{BodyPoses, Kinematics};
use stride_geometry::MusclePaths;
use stride_model::Model;

/// A body as the page draws it (the ground is left out; indices count from the first
/// non-ground body).
#[derive(Clone, Debug, Serialize)]
pub struct BodySolid {
    /// Body name.
    pub name: String,
    /// Mass [kg].
    pub mass: f64,
    /// Index of the parent body in the page's list, `None` for a body on the ground.
    pub parent: Option<usize>,
    /// Radius of the body's solids [m], growing with the square root of its mass.
    pub radius: f64,
    /// End of a body without children, in its own frame [m]: twice its centre of mass
    /// (e.g. the head end of the torso); `None` when it has children or its centre of mass
    /// lies at its origin.
    pub tip: Option<[f64; 3]>,
}

/// A contact sphere: body (page index), centre in the body frame [m], radius [m].
#[derive(Clone, Debug, Serialize)]
pub struct SphereSolid {
    /// Page index of the body carrying the sphere.
    pub body: usize,
    /// Centre in the body frame [m].
    pub center: [f64; 3],
    /// Radius [m].
    pub radius: f64,
}

/// A muscle as the page draws it.
#[derive(Clone, Debug, Serialize)]
pub struct MuscleLine {
    /// Muscle name.
    pub name: String,
    /// Path points stored per frame (all of the muscle's points; an inactive conditional
    /// point repeats the previous active one).
    pub points: usize,
}

/// The model part of the page: everything that does not change over the cycle.
#[derive(Clone, Debug, Serialize)]
pub struct SceneModel {
    /// Model name.
    pub name: String,
    /// Total mass [kg] (scales the force arrows by body weight).
    pub mass: f64,
    /// Bodies (without the ground).
    pub bodies: Vec<BodySolid>,
    /// Contact spheres.
    pub spheres: Vec<SphereSolid>,
    /// Muscles.
    pub muscles: Vec<MuscleLine>,
}

/// Radius [m] of a body's solids of mass `mass` [kg]: 12 mm plus 3 mm per √kg.
pub fn body_radius(mass: f64) -> f64 {
    0.012 + 0.003 * mass.max(0.0).sqrt()
}

impl SceneModel {
    /// The solids of `model`.
    pub fn new(model: &Model) -> Self {
        let nb = model.bodies.len();
        let mut parent = vec![None; nb];
        let mut has_child = vec![false; nb];
        for j in &model.joints {
            if j.child < nb && j.parent < nb {
                parent[j.child] = (j.parent > 0).then(|| j.parent - 1);
                has_child[j.parent] = true;
            }
        }
        let bodies = (1..nb)
            .map(|b| {
                let body = &model.bodies[b];
                let c = body.com;
                let far = c.iter().map(|x| x * x).sum::<f64>().sqrt() > 0.01;
                BodySolid {
                    name: body.name.clone(),
                    mass: body.mass,
                    parent: parent[b],
                    radius: body_radius(body.mass),
                    tip: (!has_child[b] && far).then(|| c.map(|x| 2.0 * x)),
                }
            })
            .collect();
        let spheres = model
            .contacts
            .iter()
            .filter(|s| s.body > 0 && s.body < nb)
            .map(|s| SphereSolid {
                body: s.body - 1,
                center: s.location,
                radius: s.radius,
            })
            .collect();
        let muscles = model
            .muscles
            .iter()
            .map(|m| MuscleLine {
                name: m.name.clone(),
                points: m.path.len(),
            })
            .collect();
        Self {
            name: model.name.clone(),
            mass: model.bodies.iter().map(|b| b.mass).sum(),
            bodies,
            spheres,
            muscles,
        }
    }
}

/// Body poses and muscle path points of every frame, in ground.
#[derive(Clone, Debug, Default)]
pub struct Poses {
    /// Per frame and (non-ground) body: origin [m].
    pub origins: Vec<f64>,
    /// Per frame and body: rotation body → ground, row-major (9 values).
    pub rotations: Vec<f64>,
    /// Per frame, muscle and path point: position [m] (3 values).
    pub muscle_points: Vec<f64>,
}

/// Pose the model at every frame.
pub fn pose_frames(model: &Model, frames: &Frames) -> Result<Poses, ViewError> {
    let kin = Kinematics::new(model).map_err(|e| ViewError::Model(e.to_string()))?;
    let paths = MusclePaths::new(model).map_err(|e| ViewError::Model(e.to_string()))?;
    let mut poses = BodyPoses::<f64>::new(kin.n_bodies());
    let mut out = Poses::default();
    for q in &frames.q {
        kin.forward(q, &mut poses);
        for b in 1..kin.n_bodies() {
            out.origins.extend(poses.origin[b]);
            for row in &poses.rotation[b] {
                out.rotations.extend(row);
            }
        }
        for m in 0..paths.len() {
            let start = out.muscle_points.len();
            paths.for_each_active_point(m, q, &poses, |p| out.muscle_points.extend(p));
            let mut active = (out.muscle_points.len() - start) / 3;
            if active == 0 {
                return Err(ViewError::Model(format!(
                    "muscle `{}` has no active path point",
                    model.muscles[m].name
                )));
            }
            while active < paths.n_points(m) {
                let last = out.muscle_points.len() - 3;
                out.muscle_points.extend_from_within(last..last + 3);
                active += 1;
            }
        }
    }
    Ok(out)
}
