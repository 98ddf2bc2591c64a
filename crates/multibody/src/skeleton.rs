//! The per-node multibody function of the optimal control problem (FORMULATION 5.1, 5.3):
//! inverse dynamics with all contact forces applied, plus body-origin positions and the
//! ground reaction force and moment of each foot.

use stride_ad::Scalar;
use stride_model::Model;

use crate::contact::{contact_forces_with_geometry, SphereForce, SphereGeometry};
use crate::data::Data;
use crate::dynamics::{accelerations, inverse_dynamics_from_kinematics};
use crate::error::MultibodyError;
use crate::spatial::{add, cross, zero3, Vec3};

/// Outputs of [`skeleton_dynamics`], preallocated with [`SkeletonOutput::new`].
#[derive(Clone, Debug)]
pub struct SkeletonOutput<T: Scalar> {
    /// Generalised forces [N m or N], one per model coordinate.
    pub tau: Vec<T>,
    /// Origin of every body in ground [m] (index = body index; ground at 0).
    pub body_origins: Vec<Vec3<T>>,
    /// Per sphere: force, point, indentation.
    pub spheres: Vec<SphereForce<T>>,
    /// Total contact force on each contact group (foot) [N], ground frame.
    pub group_force: Vec<Vec3<T>>,
    /// Total contact moment on each group about the ground origin [N m], ground frame.
    pub group_moment: Vec<Vec3<T>>,
}

impl<T: Scalar> SkeletonOutput<T> {
    /// Buffers sized for `model` and the contact groups of `data`.
    pub fn new(model: &Model, data: &Data<T>) -> Self {
        let ng = data.groups.names.len();
        Self {
            tau: vec![T::zero(); model.coordinates.len()],
            body_origins: vec![zero3(); model.bodies.len()],
            spheres: vec![SphereForce::default(); model.contacts.len()],
            group_force: vec![zero3(); ng],
            group_moment: vec![zero3(); ng],
        }
    }
}

/// Inverse dynamics with every contact sphere's force applied (no other applied load
/// besides gravity), plus body-origin positions and per-foot ground reaction totals.
/// `q`, `v`, `qdd`: one value per model coordinate (locked ones fed their default value
/// and zero rates by the caller).
pub fn skeleton_dynamics<T: Scalar>(
    model: &Model,
    data: &mut Data<T>,
    q: &[T],
    v: &[T],
    qdd: &[T],
    out: &mut SkeletonOutput<T>,
) -> Result<(), MultibodyError> {
    skeleton_dynamics_with_geometry(model, data, q, v, qdd, None, out)
}

/// [`skeleton_dynamics`] with the contact sphere centres and radii of `geometry` (one per
/// sphere of `model`) instead of the model's; `None`: the model's.
pub fn skeleton_dynamics_with_geometry<T: Scalar>(
    model: &Model,
    data: &mut Data<T>,
    q: &[T],
    v: &[T],
    qdd: &[T],
    geometry: Option<&[SphereGeometry<T>]>,
    out: &mut SkeletonOutput<T>,
) -> Result<(), MultibodyError> {
    accelerations(model, data, q, v, qdd)?;
    data.clear_external();
    contact_forces_with_geometry(model, data, geometry, &mut out.spheres)?;
    inverse_dynamics_from_kinematics(model, data, &mut out.tau)?;
    out.body_origins.copy_from_slice(&data.position);
    let ng = data.groups.names.len();
    if out.group_force.len() != ng {
        out.group_force.resize(ng, zero3());
        out.group_moment.resize(ng, zero3());
    }
    for g in out
        .group_force
        .iter_mut()
        .chain(out.group_moment.iter_mut())
    {
        *g = zero3();
    }
    for (i, s) in out.spheres.iter().enumerate() {
        if let Some(g) = data.sphere_group[i] {
            out.group_force[g] = add(out.group_force[g], s.force);
            out.group_moment[g] = add(out.group_moment[g], cross(s.point, s.force));
        }
    }
    Ok(())
}

/// Centre of pressure [m] on the plane through `plane_point` with unit normal `normal`,
/// and the free moment about the normal [N m], of a load given as force [N] and moment
/// about the ground origin [N m] (post-processing only). `None` when the normal force is
/// below `min_normal_force` [N].
pub fn center_of_pressure(
    force: [f64; 3],
    moment_about_origin: [f64; 3],
    plane_point: [f64; 3],
    normal: [f64; 3],
    min_normal_force: f64,
) -> Option<([f64; 3], f64)> {
    let fn_ = force[0] * normal[0] + force[1] * normal[1] + force[2] * normal[2];
    if fn_.abs().is_nan() || fn_.abs() <= min_normal_force {
        return None;
    }
    // Moment about the plane point.
    let m0 = moment_about_origin;
    let pxf = cross(plane_point, force);
    let m = [m0[0] - pxf[0], m0[1] - pxf[1], m0[2] - pxf[2]];
    let nxm = cross(normal, m);
    let r = [nxm[0] / fn_, nxm[1] / fn_, nxm[2] / fn_];
    let cop = [
        plane_point[0] + r[0],
        plane_point[1] + r[1],
        plane_point[2] + r[2],
    ];
    let rxf = cross(r, force);
    let free =
        (m[0] - rxf[0]) * normal[0] + (m[1] - rxf[1]) * normal[1] + (m[2] - rxf[2]) * normal[2];
    Some((cop, free))
}
