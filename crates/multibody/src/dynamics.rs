//! Recursive Newton–Euler inverse dynamics: `τ = M(q) q̈ + c(q, q̇) − τ_g(q) − τ_ext`.
//!
//! Loads are expressed in ground and referred to body origins. The generalised force of a
//! coordinate is the sum over the transform axes driven by it of `f'(q) (s_k · N_M)` for
//! rotations (moment transmitted to the child subtree about the origin of frame M) and
//! `f'(q) (b_k · F)` for translations.

use stride_ad::Scalar;
use stride_model::Model;

use crate::couplers::reduce;
use crate::data::Data;
use crate::error::MultibodyError;
use crate::kinematics::{check_len, inertia_times, run_kinematics};
use crate::spatial::{add, cross, cst3, dot, mat_t_vec, mat_vec, mat_vec_f, scale, sub, Vec3};

/// Generalised forces `tau` [N m or N] (one per model coordinate) that produce the
/// accelerations `qdd` at state (`q`, `v`) under `model.gravity` and the external loads
/// currently stored in `data` (`external_force`/`external_moment`, ground, about body
/// origins). Runs forward kinematics itself (with accelerations). A coupled coordinate's
/// inputs are ignored and its force is carried by its independent coordinate (its own
/// entry of `tau` is 0), see [`crate::couplers`].
pub fn inverse_dynamics<T: Scalar>(
    model: &Model,
    data: &mut Data<T>,
    q: &[T],
    v: &[T],
    qdd: &[T],
    tau: &mut [T],
) -> Result<(), MultibodyError> {
    let n = model.coordinates.len();
    check_len("coordinates q", n, q.len())?;
    check_len("speeds v", n, v.len())?;
    check_len("accelerations qdd", n, qdd.len())?;
    check_len("generalised forces tau", n, tau.len())?;
    check_len("workspace coordinates", n, data.n_coordinates)?;
    run_kinematics(data, q, v, Some(qdd));
    backward_pass(model, data, tau);
    Ok(())
}

/// Like [`inverse_dynamics`], for callers that first ran the kinematics with
/// accelerations ([`accelerations`]) to place external loads at body points.
pub fn inverse_dynamics_from_kinematics<T: Scalar>(
    model: &Model,
    data: &mut Data<T>,
    tau: &mut [T],
) -> Result<(), MultibodyError> {
    check_len("generalised forces tau", model.coordinates.len(), tau.len())?;
    backward_pass(model, data, tau);
    Ok(())
}

/// Kinematics including body accelerations (in ground), for use with
/// [`inverse_dynamics_from_kinematics`].
pub fn accelerations<T: Scalar>(
    model: &Model,
    data: &mut Data<T>,
    q: &[T],
    v: &[T],
    qdd: &[T],
) -> Result<(), MultibodyError> {
    let n = model.coordinates.len();
    check_len("coordinates q", n, q.len())?;
    check_len("speeds v", n, v.len())?;
    check_len("accelerations qdd", n, qdd.len())?;
    check_len("workspace coordinates", n, data.n_coordinates)?;
    run_kinematics(data, q, v, Some(qdd));
    Ok(())
}

fn backward_pass<T: Scalar>(model: &Model, data: &mut Data<T>, tau: &mut [T]) {
    let g: Vec3<T> = cst3(model.gravity);
    for t in tau.iter_mut() {
        *t = T::zero();
    }
    // Own loads of every body: inertial minus gravity minus external.
    for (b, body) in model.bodies.iter().enumerate().skip(1) {
        let r = &data.rotation[b];
        let w = data.angular_velocity[b];
        let alpha = data.angular_acceleration[b];
        let rho = mat_vec_f(r, body.com);
        let a_com = add(
            add(data.linear_acceleration[b], cross(alpha, rho)),
            cross(w, cross(w, rho)),
        );
        let f = scale(sub(a_com, g), T::cst(body.mass));
        // Rotational inertia in ground: R I Rᵀ.
        let iw = mat_vec(r, inertia_times(&body.inertia, mat_t_vec(r, w)));
        let ia = mat_vec(r, inertia_times(&body.inertia, mat_t_vec(r, alpha)));
        let n = add(add(ia, cross(w, iw)), cross(rho, f));
        data.load_force[b] = sub(f, data.external_force[b]);
        data.load_moment[b] = sub(n, data.external_moment[b]);
    }
    // Leaves to root.
    for j in (0..data.joints.len()).rev() {
        let (p, c) = (data.joints[j].parent, data.joints[j].child);
        let f_c = data.load_force[c];
        let n_c = data.load_moment[c];
        let o_m = data.joint_origin[j];
        let r_c = data.position[c];
        let n_m = add(n_c, cross(sub(r_c, o_m), f_c));
        let info = &data.joints[j];
        for (k, ax) in info.rotations.iter().enumerate() {
            if let Some(i) = ax.coordinate {
                tau[i] += data.joint_df[j][k][0] * dot(data.joint_s[j][k], n_m);
            }
        }
        for (k, ax) in info.translations.iter().enumerate() {
            if let Some(i) = ax.coordinate {
                tau[i] += data.joint_df[j][3 + k][0] * dot(data.joint_b[j][k], f_c);
            }
        }
        if p != 0 {
            let r_p = data.position[p];
            data.load_force[p] = add(data.load_force[p], f_c);
            data.load_moment[p] = add(data.load_moment[p], add(n_c, cross(sub(r_c, r_p), f_c)));
        }
    }
    if !data.couplers.is_empty() {
        reduce(&data.couplers, &data.coupled[0], tau);
    }
}
