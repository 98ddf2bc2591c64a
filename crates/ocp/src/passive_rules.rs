//! Passive joint torques of a model that brings no passive torque table (PREDSIM.md §3.6):
//! PredSim's limit torques by coordinate name and damping on every coordinate that is not
//! part of the floating base; which part of them the cost penalises; and the toe joints
//! driven by their passive torque only (PredSim's `2022paper` toes, §4). Springs on
//! coordinates come from the model (`coordinate_springs` of its settings file).

use crate::gait::{side_of, Actuation, GaitModel};
use serde::{Deserialize, Serialize};
use stride_model::{Model, PassiveJointTorque};

/// Options of the passive joint torques.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct PassiveSettings {
    /// Give a model without a passive torque table PredSim's limit torques (by
    /// coordinate name) and damping on every non-floating-base coordinate.
    pub limit_torques: bool,
    /// Damping of those coordinates [N m s rad⁻¹] (0.1).
    pub damping: f64,
    /// Which part of the passive torques the cost penalises.
    pub cost: PassiveCost,
    /// How the toe (metatarsophalangeal, name containing `mtp`) coordinates are driven.
    pub toes: ToeDrive,
}

impl Default for PassiveSettings {
    /// PredSim's defaults; the cost follows the source of the passive torques.
    fn default() -> Self {
        Self {
            limit_torques: true,
            damping: 0.1,
            cost: PassiveCost::Auto,
            toes: ToeDrive::Muscles,
        }
    }
}

/// The passive-torque term of the cost.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum PassiveCost {
    /// `total` for a model with its own passive torque table (the 2019 formulation),
    /// `limit` when the torques come from PredSim's rule.
    Auto,
    /// The whole passive torque (limit, spring and damping) of every muscle- or
    /// actuator-driven coordinate.
    Total,
    /// Only the limit torques, over the coordinates that have one (PredSim).
    Limit,
}

/// How the toe joints are driven.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum ToeDrive {
    /// Like any coordinate: muscle moments plus passive torque.
    Muscles,
    /// By the passive torque only (PredSim's `2022paper`): the toe muscles' lengths
    /// follow the toe angle, their toe moments are left out of the toe's torque balance.
    Passive,
}

/// Limit-torque coefficients `([k1, k2, k3, k4], [θ_lower, θ_upper])` of PredSim's
/// `default_coord_lim_torq_coeff.csv` for a coordinate base name (FORMULATION 6.1 plus
/// the toes, PREDSIM.md §3.6).
pub fn limit_coefficients(base: &str) -> Option<([f64; 4], [f64; 2])> {
    let lumbar = (-0.3490658503988659, 0.3490658503988659);
    let (k, t): ([f64; 4], (f64, f64)) = match base {
        "hip_flexion" => ([-2.44, 5.05, 1.51, -21.88], (-0.6981, 1.81)),
        "hip_adduction" => ([-0.03, 14.94, 0.03, -14.94], (-0.5, 0.5)),
        "hip_rotation" => ([-0.03, 14.94, 0.03, -14.94], (-0.92, 0.92)),
        "knee_angle" => ([-6.09, 33.94, 11.03, -11.33], (-2.4, 0.13)),
        "ankle_angle" => ([-2.03, 38.11, 0.18, -12.12], (-0.74, 0.52)),
        "subtalar_angle" => ([-60.21, 16.32, 60.21, -16.32], (-0.65, 0.65)),
        "mtp_angle" => ([-0.9, 14.87, 0.18, -70.08], (0.0, 1.13446401379631)),
        "lumbar_extension" => ([-0.35, 30.72, 0.25, -20.36], (-0.5235987755982988, 0.17)),
        "lumbar_bending" | "lumbar_rotation" => ([-0.25, 20.36, 0.25, -20.36], lumbar),
        _ => return None,
    };
    Some((k, [t.0, t.1]))
}

/// Whether a coordinate is a toe coordinate (its name contains `mtp`).
pub fn is_toe(name: &str) -> bool {
    name.contains("mtp")
}

/// Give `model` PredSim's passive torques when it has none and the settings ask for them:
/// limit torques by name and damping on every muscle-driven coordinate, and on the
/// actuator-driven ones that have a limit torque. Returns whether it did.
pub fn apply(model: &mut Model, gait: &GaitModel, settings: &PassiveSettings) -> bool {
    if !model.passive_torques.is_empty() || !settings.limit_torques {
        return false;
    }
    for c in &gait.coordinates {
        let limit = limit_coefficients(side_of(&c.name).0);
        let keep = match c.actuation {
            Actuation::Root => false,
            Actuation::Muscles => true,
            Actuation::Actuator(_) => limit.is_some(),
        };
        if keep {
            let (k, theta) = limit.unwrap_or(([0.0; 4], [0.0; 2]));
            model.passive_torques.push(PassiveJointTorque {
                coordinate: c.model_index,
                k,
                theta,
                damping: settings.damping,
            });
        }
    }
    true
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn toe_limit_torque_is_predsims_row() {
        let (k, t) = limit_coefficients("mtp_angle").unwrap();
        assert_eq!(k, [-0.9, 14.87, 0.18, -70.08]);
        assert!((t[1] - 65f64.to_radians()).abs() < 1e-12);
        assert!(limit_coefficients("arm_flex").is_none());
        assert!(limit_coefficients("mtj_angle").is_none());
    }
}
