//! Passive joint torques (FORMULATION 6): exponential limit springs with linear damping for
//! the muscle-actuated coordinates, pure damping for the arm coordinates.

use stride_ad::Scalar;
use stride_model::PassiveJointTorque;

use crate::activation::ARM_DAMPING;

/// Passive torque `k1 e^{k2(q−θ2)} + k3 e^{k4(q−θ1)} − B q̇` [N m] for angle `q` [rad] and
/// speed `q̇` [rad s⁻¹].
#[inline]
pub fn passive_torque<T: Scalar>(p: &PassiveJointTorque, q: T, qdot: T) -> T {
    limit_torque(p, q) - qdot * p.damping
}

/// Limit torque `k1 e^{k2(q−θ2)} + k3 e^{k4(q−θ1)}` [N m] at angle `q` [rad] (0 for an
/// element without one).
#[inline]
pub fn limit_torque<T: Scalar>(p: &PassiveJointTorque, q: T) -> T {
    if !p.has_limit() {
        return T::zero();
    }
    let [k1, k2, k3, k4] = p.k;
    let [theta_lower, theta_upper] = p.theta;
    ((q - theta_upper) * k2).exp() * k1 + ((q - theta_lower) * k4).exp() * k3
}

/// Passive torque of an arm coordinate, `−0.1 q̇` [N m] (stiffness 0).
#[inline]
pub fn arm_damping_torque<T: Scalar>(qdot: T) -> T {
    -qdot * ARM_DAMPING
}

/// Fills `torques[i]` with the passive torque of `elements[i]`, reading `q`, `qdot` at the
/// element's coordinate index [N m]; errors when a slice is too short.
pub fn passive_torques<T: Scalar>(
    elements: &[PassiveJointTorque],
    q: &[T],
    qdot: &[T],
    torques: &mut [T],
) -> Result<(), crate::MuscleError> {
    if torques.len() != elements.len() {
        return Err(crate::MuscleError::LengthMismatch {
            what: "passive torque output",
            expected: elements.len(),
            actual: torques.len(),
        });
    }
    let needed = elements.iter().map(|e| e.coordinate + 1).max().unwrap_or(0);
    for (what, len) in [("q", q.len()), ("qdot", qdot.len())] {
        if len < needed {
            return Err(crate::MuscleError::LengthMismatch {
                what,
                expected: needed,
                actual: len,
            });
        }
    }
    for (t, e) in torques.iter_mut().zip(elements) {
        *t = passive_torque(e, q[e.coordinate], qdot[e.coordinate]);
    }
    Ok(())
}
