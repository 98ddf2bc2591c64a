//! Smooth Hunt–Crossley sphere–plane contact (OpenSim `SmoothSphereHalfSpaceForce`),
//! FORMULATION section 5.2, with the ground plane generalised to any point and normal.

use stride_ad::{smooth_step, Scalar};
use stride_model::{ContactParameters, Model};

use crate::data::Data;
use crate::error::MultibodyError;
use crate::kinematics::{check_len, point_position};
use crate::spatial::{add, cross, cst3, dot, dot_f, mat_vec, scale, sub, zero3, Vec3};

/// Contact result of one sphere, in ground.
#[derive(Clone, Copy, Debug)]
pub struct SphereForce<T: Scalar> {
    /// Force on the body [N] (normal + friction).
    pub force: Vec3<T>,
    /// Application point P (midway through the overlap) [m].
    pub point: Vec3<T>,
    /// Indentation δ (positive when penetrating) [m].
    pub indentation: T,
    /// Indentation rate δ̇ [m s⁻¹].
    pub indentation_rate: T,
    /// Normal force magnitude f_n [N].
    pub normal_force: T,
}

impl<T: Scalar> Default for SphereForce<T> {
    fn default() -> Self {
        Self {
            force: zero3(),
            point: zero3(),
            indentation: T::zero(),
            indentation_rate: T::zero(),
            normal_force: T::zero(),
        }
    }
}

/// Geometry of one contact sphere as scalars of the generic type, so that an optimiser can
/// treat it as unknown: centre in the body frame [m] and radius [m].
#[derive(Clone, Copy, Debug)]
pub struct SphereGeometry<T: Scalar> {
    /// Sphere centre in the frame of its body [m].
    pub location: Vec3<T>,
    /// Radius [m].
    pub radius: T,
}

impl<T: Scalar> SphereGeometry<T> {
    /// The geometry of every sphere of `model`, as constants.
    pub fn of_model(model: &Model) -> Vec<Self> {
        model
            .contacts
            .iter()
            .map(|s| Self {
                location: cst3(s.location),
                radius: T::cst(s.radius),
            })
            .collect()
    }
}

/// Normal force f_n [N] of the smoothed Hertz / Hunt–Crossley law (steps 6–7) for
/// indentation `delta` [m], indentation rate `delta_dot` [m s⁻¹] and sphere radius [m].
#[inline]
pub fn normal_force<T: Scalar>(p: &ContactParameters, radius: T, delta: T, delta_dot: T) -> T {
    let k = 0.5 * p.stiffness.powf(2.0 / 3.0);
    let c_h = (radius * k).sqrt() * (4.0 / 3.0 * k);
    // (sqrt(δ² + c_f))^{3/2} = r · sqrt(r) with r = sqrt(δ² + c_f) (two square roots are
    // cheaper than a general power, on f64 and on tapes).
    let r = (delta * delta + p.constant_contact_force).sqrt();
    let f_h = r * r.sqrt() * c_h;
    let f_hs = f_h * smooth_step(delta, p.hertz_smoothing);
    let f_hc = f_hs * (delta_dot * (1.5 * p.dissipation) + 1.0);
    f_hc * smooth_step(
        delta_dot + 2.0 / (3.0 * p.dissipation),
        p.hunt_crossley_smoothing,
    )
}

/// Friction coefficient μ(v_slip) (step 8) for the smoothed slip speed [m s⁻¹]. The factor
/// min(v_rel, 1) is exact when `friction_transition_smoothing` is 0 (a kink at v_t), else
/// [`smooth_min_one`] with that half-width.
#[inline]
pub fn friction_coefficient<T: Scalar>(p: &ContactParameters, v_slip: T) -> T {
    let v_rel = v_slip / p.transition_velocity;
    let stribeck = (v_rel * v_rel + 1.0).rdiv(2.0 * (p.static_friction - p.dynamic_friction))
        + p.dynamic_friction;
    let capped = if p.friction_transition_smoothing > 0.0 {
        smooth_min_one(v_rel, p.friction_transition_smoothing)
    } else {
        v_rel.fmin(T::one())
    };
    capped * stribeck + v_slip * p.viscous_friction
}

/// Smooth lower bound of min(x, 1) with half-width `eps` (dimensionless):
/// ½ (x + 1 − √((x − 1)² + ε²)). Infinitely differentiable, below min(x, 1) by at most
/// ε/2 (at x = 1) and by about ε² / (4 |x − 1|) away from the kink.
#[inline]
pub fn smooth_min_one<T: Scalar>(x: T, eps: f64) -> T {
    let d = x - 1.0;
    (x + 1.0 - (d * d + eps * eps).sqrt()) * 0.5
}

/// Contact of one sphere with centre `center` (ground) on a body with origin `origin`,
/// origin velocity `v_origin` and angular velocity `omega` (all ground), against the
/// plane through `plane_point` with unit outward `normal`.
#[allow(clippy::too_many_arguments)]
pub fn sphere_force<T: Scalar>(
    p: &ContactParameters,
    radius: T,
    center: Vec3<T>,
    origin: Vec3<T>,
    v_origin: Vec3<T>,
    omega: Vec3<T>,
    plane_point: [f64; 3],
    normal: [f64; 3],
) -> SphereForce<T> {
    let n: Vec3<T> = cst3(normal);
    let height = dot_f(sub(center, cst3(plane_point)), normal);
    let delta = radius - height;
    // P = c − R n + ½ δ n.
    let point = add(center, scale(n, delta * 0.5 - radius));
    let v_p = add(v_origin, cross(omega, sub(point, origin)));
    let vn = dot(v_p, n);
    let delta_dot = -vn;
    let v_t = sub(v_p, scale(n, vn));
    let f_n = normal_force(p, radius, delta, delta_dot);
    let v_slip = (dot(v_t, v_t) + p.constant_contact_force).sqrt();
    let mu = friction_coefficient(p, v_slip);
    let fric = scale(v_t, -(f_n * mu) / v_slip);
    SphereForce {
        force: add(scale(n, f_n), fric),
        point,
        indentation: delta,
        indentation_rate: delta_dot,
        normal_force: f_n,
    }
}

/// Contact forces of all spheres of `model` (after forward kinematics): writes one result
/// per sphere into `out` and adds each force (at its point, referred to the body origin)
/// to the external loads of `data`.
pub fn contact_forces<T: Scalar>(
    model: &Model,
    data: &mut Data<T>,
    out: &mut [SphereForce<T>],
) -> Result<(), MultibodyError> {
    contact_forces_with_geometry(model, data, None, out)
}

/// [`contact_forces`] with the sphere centres and radii of `geometry` (one per sphere of
/// `model`, in its order) instead of the model's; `None`: the model's.
pub fn contact_forces_with_geometry<T: Scalar>(
    model: &Model,
    data: &mut Data<T>,
    geometry: Option<&[SphereGeometry<T>]>,
    out: &mut [SphereForce<T>],
) -> Result<(), MultibodyError> {
    check_len("sphere outputs", model.contacts.len(), out.len())?;
    if let Some(g) = geometry {
        check_len("sphere geometries", model.contacts.len(), g.len())?;
    }
    for (i, s) in model.contacts.iter().enumerate() {
        let b = s.body;
        let (center, radius) = match geometry {
            Some(g) => (
                add(data.position[b], mat_vec(&data.rotation[b], g[i].location)),
                g[i].radius,
            ),
            None => (point_position(data, b, s.location), T::cst(s.radius)),
        };
        let r = sphere_force(
            &s.parameters,
            radius,
            center,
            data.position[b],
            data.linear_velocity[b],
            data.angular_velocity[b],
            s.plane_point,
            data.sphere_normal[i],
        );
        data.add_point_force(b, r.force, r.point);
        out[i] = r;
    }
    Ok(())
}
