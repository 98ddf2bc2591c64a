//! Force laws of the passive elements OpenSim models carry besides muscles and contacts:
//! `CoordinateLimitForce`, `SpringGeneralizedForce`, `ExpressionBasedCoordinateForce`
//! (generalised forces of one coordinate)
//! and `Ligament` (tension along a path), as OpenSim defines them.

use stride_ad::Scalar;
use stride_model::function::CompiledFunction;
use stride_model::{CoordinateForceLaw, Ligament};

/// Simbody's quintic step: `y0` below `x0`, `y1` above `x1`, and between them
/// `y0 + (y1 − y0) s³ (10 − 15 s + 6 s²)` with `s = (x − x0)/(x1 − x0)` (C² at both ends).
fn step<T: Scalar>(x: T, x0: f64, x1: f64, y0: f64, y1: f64) -> T {
    let s = ((x - x0) * (1.0 / (x1 - x0)))
        .fmax(T::zero())
        .fmin(T::one());
    let shape = s * s * s * ((s * 6.0 - 15.0) * s + 10.0);
    shape * (y1 - y0) + y0
}

/// Generalised force [N m or N] of a coordinate force element at coordinate value `q`
/// [rad or m] and speed `qdot` [rad s⁻¹ or m s⁻¹].
///
/// `CoordinateLimitForce`: with w = π/180 for an angle (the file's stiffnesses are per
/// degree, its limits and transition in degrees) and 1 otherwise, K_up = k_up/w,
/// q_up = w·upper, K_lo = k_lo/w, q_lo = w·lower, D = damping/w, the stiffnesses switch on
/// over the transition: k₊(q) = step from 0 to K_up over [q_up, q_up + w·transition],
/// k₋(q) = step from K_lo to 0 over [q_lo − w·transition, q_lo], and
/// `τ = −k₊ (q − q_up) + k₋ (q_lo − q) − D (k₊/K_up + k₋/K_lo) q̇`.
/// `SpringGeneralizedForce`: `τ = −k (q − q₀) − c q̇`.
/// `ExpressionBasedCoordinateForce`: `τ` = its expression of `q` and `qdot`.
pub fn coordinate_force<T: Scalar>(law: &CoordinateForceLaw, q: T, qdot: T) -> T {
    match *law {
        CoordinateForceLaw::Spring {
            stiffness,
            rest_length,
            viscosity,
        } => (q - rest_length) * (-stiffness) - qdot * viscosity,
        CoordinateForceLaw::Expression(ref e) => e.eval(&[q, qdot]),
        CoordinateForceLaw::CoordinateLimit {
            upper_stiffness,
            upper_limit,
            lower_stiffness,
            lower_limit,
            damping,
            transition,
            rotational,
        } => {
            let w = if rotational {
                std::f64::consts::PI / 180.0
            } else {
                1.0
            };
            let (k_up, q_up) = (upper_stiffness / w, w * upper_limit);
            let (k_lo, q_lo) = (lower_stiffness / w, w * lower_limit);
            let d = damping / w;
            let up = step(q, q_up, q_up + w * transition, 0.0, k_up);
            let lo = step(q, q_lo - w * transition, q_lo, k_lo, 0.0);
            let f_up = up * (q - q_up) * -1.0;
            let f_lo = lo * (q.rsub(q_lo));
            let f_damp = (up * (1.0 / k_up) + lo * (1.0 / k_lo)) * qdot * (-d);
            f_up + f_lo + f_damp
        }
    }
}

/// Tension [N] of a ligament of path length `length` [m]: `pcsa_force ·
/// force_length(length / resting_length)` when the ligament is longer than its resting
/// length, 0 otherwise. `curve` is `ligament.force_length` compiled.
pub fn ligament_tension<T: Scalar>(ligament: &Ligament, curve: &CompiledFunction, length: T) -> T {
    let stretch = length * (1.0 / ligament.resting_length);
    let tension = curve.eval(stretch)[0] * ligament.pcsa_force;
    T::select_pos(stretch - 1.0, tension, T::zero())
}
