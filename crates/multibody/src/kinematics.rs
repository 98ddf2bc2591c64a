//! Forward kinematics with OpenSim `CustomJoint` semantics, body-fixed points and the
//! whole-body centre of mass.
//!
//! For a joint with rotation axes a₁, a₂, a₃ (in the parent joint frame F) and angles
//! θ_k = f_k(q): R_FM = R(a₁,θ₁) R(a₂,θ₂) R(a₃,θ₃); the origin of M sits at Σ f_k(q) b_k
//! (translation axes b_k in F); the child body frame follows from M's offset in the child.
//! Partial angular velocities: s₁ = a₁, s₂ = R(a₁,θ₁) a₂, s₃ = R(a₁,θ₁) R(a₂,θ₂) a₃.

use stride_ad::Scalar;
use stride_model::{BodyId, Model};

use crate::couplers::couple;
use crate::data::{AxisInfo, Data};
use crate::error::MultibodyError;
use crate::spatial::{
    add, cross, cst3, mat_mul_f, mat_vec_f, rotate_columns, scale, sub, zero3, Mat3, Vec3,
};

/// `[θ, θ̇, θ̈, f', f'']` of one transform axis for coordinate values, speeds and
/// (optionally) accelerations.
#[inline]
fn axis_motion<T: Scalar>(ax: &AxisInfo, q: &[T], v: &[T], qdd: Option<&[T]>) -> [T; 5] {
    match ax.coordinate {
        Some(c) => {
            let [f, d1, d2] = ax.function.eval(q[c]);
            let th_d = d1 * v[c];
            let th_dd = match qdd {
                Some(a) => d1 * a[c] + d2 * v[c] * v[c],
                None => T::zero(),
            };
            [f, th_d, th_dd, d1, d2]
        }
        None => {
            let [f, _, _] = ax.function.eval(T::zero());
            [f, T::zero(), T::zero(), T::zero(), T::zero()]
        }
    }
}

pub(crate) fn check_len(
    what: &'static str,
    expected: usize,
    got: usize,
) -> Result<(), MultibodyError> {
    if expected == got {
        Ok(())
    } else {
        Err(MultibodyError::Length {
            what,
            expected,
            got,
        })
    }
}

/// [`kinematics_pass`] on the coupled state: with couplers in the model the dependent
/// coordinates are first filled in from their independent ones (kept in `data.coupled`).
pub(crate) fn run_kinematics<T: Scalar>(data: &mut Data<T>, q: &[T], v: &[T], qdd: Option<&[T]>) {
    if data.couplers.is_empty() {
        kinematics_pass(data, q, v, qdd);
        return;
    }
    let [mut cq, mut cv, mut ca] = std::mem::take(&mut data.coupled);
    cq.copy_from_slice(q);
    cv.copy_from_slice(v);
    if let Some(a) = qdd {
        ca.copy_from_slice(a);
    }
    couple(&data.couplers, &mut cq, &mut cv, qdd.map(|_| &mut ca[..]));
    kinematics_pass(data, &cq, &cv, qdd.map(|_| &ca[..]));
    data.coupled = [cq, cv, ca];
}

/// Positions, orientations and velocities of all bodies (and accelerations when `qdd`
/// is given) from coordinates `q`, speeds `v` and accelerations `qdd`, in ground.
pub(crate) fn kinematics_pass<T: Scalar>(data: &mut Data<T>, q: &[T], v: &[T], qdd: Option<&[T]>) {
    let with_acc = qdd.is_some();
    for j in 0..data.joints.len() {
        let (p, c) = (data.joints[j].parent, data.joints[j].child);
        let r_gp = data.rotation[p];
        let r_p = data.position[p];
        let w_p = data.angular_velocity[p];
        let v_p = data.linear_velocity[p];
        let alpha_p = data.angular_acceleration[p];
        let a_p = data.linear_acceleration[p];
        let info = &data.joints[j];
        // Joint frame F in ground.
        let r_gf: Mat3<T> = if info.parent_f_identity {
            r_gp
        } else {
            mat_mul_f(&r_gp, &info.r_parent_f)
        };
        let o_f = add(r_p, mat_vec_f(&r_gp, info.p_parent_f));
        let d1 = sub(o_f, r_p);

        // Rotations: R_FM and partial angular velocities (in ground).
        let mut r_gm = r_gf;
        let mut w_rel = zero3::<T>();
        let mut alpha_rel = zero3::<T>();
        let mut s_g = [zero3::<T>(); 3];
        let mut df = [[T::zero(); 2]; 6];
        for (k, ax) in info.rotations.iter().enumerate() {
            let [th, th_d, th_dd, d1f, d2f] = axis_motion(ax, q, v, qdd);
            let s = mat_vec_f(&r_gm, ax.axis);
            if with_acc {
                // ṡ_k θ̇_k relative to F: (Σ_{j<k} s_j θ̇_j) × s_k θ̇_k.
                alpha_rel = add(
                    alpha_rel,
                    add(scale(s, th_dd), scale(cross(w_rel, s), th_d)),
                );
            }
            w_rel = add(w_rel, scale(s, th_d));
            r_gm = rotate_columns(&r_gm, ax.axis, th.cos(), th.sin());
            s_g[k] = s;
            df[k] = [d1f, d2f];
        }
        // Translations along F axes.
        let mut u = zero3::<T>();
        let mut u_d = zero3::<T>();
        let mut u_dd = zero3::<T>();
        let mut b_g = [zero3::<T>(); 3];
        for (k, ax) in info.translations.iter().enumerate() {
            let [d, d_d, d_dd, d1f, d2f] = axis_motion(ax, q, v, qdd);
            let b = mat_vec_f(&r_gf, ax.axis);
            u = add(u, scale(b, d));
            u_d = add(u_d, scale(b, d_d));
            if with_acc {
                u_dd = add(u_dd, scale(b, d_dd));
            }
            b_g[k] = b;
            df[3 + k] = [d1f, d2f];
        }
        let o_m = add(o_f, u);
        let r_gc = if info.child_m_identity {
            r_gm
        } else {
            mat_mul_f(&r_gm, &info.r_m_child)
        };
        let r_c = sub(o_m, mat_vec_f(&r_gc, info.p_child_m));
        let d2 = sub(r_c, o_m);

        let w_c = add(w_p, w_rel);
        let v_of = add(v_p, cross(w_p, d1));
        let v_om = add(add(v_of, cross(w_p, u)), u_d);
        let v_c = add(v_om, cross(w_c, d2));

        if with_acc {
            let alpha_c = add(add(alpha_p, cross(w_p, w_rel)), alpha_rel);
            let a_of = add(add(a_p, cross(alpha_p, d1)), cross(w_p, cross(w_p, d1)));
            let a_om = add(
                add(add(a_of, cross(alpha_p, u)), cross(w_p, cross(w_p, u))),
                add(scale(cross(w_p, u_d), T::cst(2.0)), u_dd),
            );
            let a_c = add(add(a_om, cross(alpha_c, d2)), cross(w_c, cross(w_c, d2)));
            data.angular_acceleration[c] = alpha_c;
            data.linear_acceleration[c] = a_c;
        }
        data.rotation[c] = r_gc;
        data.position[c] = r_c;
        data.angular_velocity[c] = w_c;
        data.linear_velocity[c] = v_c;
        data.joint_s[j] = s_g;
        data.joint_b[j] = b_g;
        data.joint_df[j] = df;
        data.joint_origin[j] = o_m;
    }
}

/// Forward kinematics: each body's rotation (body → ground), origin position [m], angular
/// [rad s⁻¹] and origin linear [m s⁻¹] velocity in ground, from coordinates `q` [rad or m]
/// and speeds `v` (one per model coordinate, locked ones included; coupled ones follow
/// their independent coordinate, see [`crate::couplers`]); stored in `data`.
pub fn forward_kinematics<T: Scalar>(
    model: &Model,
    data: &mut Data<T>,
    q: &[T],
    v: &[T],
) -> Result<(), MultibodyError> {
    let n = model.coordinates.len();
    check_len("coordinates q", n, q.len())?;
    check_len("speeds v", n, v.len())?;
    check_len("workspace coordinates", n, data.n_coordinates)?;
    run_kinematics(data, q, v, None);
    Ok(())
}

/// Position in ground [m] of a point fixed on `body` at `local` (body frame [m]); call
/// after [`forward_kinematics`].
#[inline]
pub fn point_position<T: Scalar>(data: &Data<T>, body: BodyId, local: [f64; 3]) -> Vec3<T> {
    add(data.position[body], mat_vec_f(&data.rotation[body], local))
}

/// Velocity in ground [m s⁻¹] of a point fixed on `body` at `local` (body frame [m]);
/// call after [`forward_kinematics`].
#[inline]
pub fn point_velocity<T: Scalar>(data: &Data<T>, body: BodyId, local: [f64; 3]) -> Vec3<T> {
    let r = mat_vec_f(&data.rotation[body], local);
    add(
        data.linear_velocity[body],
        cross(data.angular_velocity[body], r),
    )
}

/// Whole-body centre of mass position [m] and velocity [m s⁻¹] in ground; call after
/// [`forward_kinematics`]. Returns zeros for a massless model.
pub fn center_of_mass<T: Scalar>(model: &Model, data: &Data<T>) -> (Vec3<T>, Vec3<T>) {
    let mut p = zero3::<T>();
    let mut vel = zero3::<T>();
    let mut m_tot = 0.0;
    for (b, body) in model.bodies.iter().enumerate().skip(1) {
        if body.mass == 0.0 {
            continue;
        }
        m_tot += body.mass;
        p = add(
            p,
            scale(point_position(data, b, body.com), T::cst(body.mass)),
        );
        vel = add(
            vel,
            scale(point_velocity(data, b, body.com), T::cst(body.mass)),
        );
    }
    if m_tot > 0.0 {
        let inv = T::cst(1.0 / m_tot);
        (scale(p, inv), scale(vel, inv))
    } else {
        (p, vel)
    }
}

/// Kinetic energy [J] of all bodies; call after [`forward_kinematics`].
pub fn kinetic_energy<T: Scalar>(model: &Model, data: &Data<T>) -> T {
    let mut e = T::zero();
    for (b, body) in model.bodies.iter().enumerate().skip(1) {
        let vc = point_velocity(data, b, body.com);
        let w_local = crate::spatial::mat_t_vec(&data.rotation[b], data.angular_velocity[b]);
        let iw = inertia_times(&body.inertia, w_local);
        e += (crate::spatial::dot(vc, vc) * body.mass + crate::spatial::dot(w_local, iw)) * 0.5;
    }
    e
}

/// Gravitational potential energy [J] under `model.gravity`; call after [`forward_kinematics`].
pub fn potential_energy<T: Scalar>(model: &Model, data: &Data<T>) -> T {
    let g: Vec3<T> = cst3(model.gravity);
    let mut e = T::zero();
    for (b, body) in model.bodies.iter().enumerate().skip(1) {
        e -= crate::spatial::dot(g, point_position(data, b, body.com)) * body.mass;
    }
    e
}

/// Inertia tensor `[xx, yy, zz, xy, xz, yz]` [kg m²] times a vector (body axes).
#[inline]
pub(crate) fn inertia_times<T: Scalar>(i: &[f64; 6], w: Vec3<T>) -> Vec3<T> {
    [
        w[0] * i[0] + w[1] * i[3] + w[2] * i[4],
        w[0] * i[3] + w[1] * i[1] + w[2] * i[5],
        w[0] * i[4] + w[1] * i[5] + w[2] * i[2],
    ]
}
