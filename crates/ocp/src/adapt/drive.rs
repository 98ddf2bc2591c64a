//! How each coordinate of an adapted model is driven: by muscles (some muscle path
//! crosses its joint), by the model's own actuator, by a new ideal torque actuator
//! (PredSim's arms: 150 N m), or not at all (the floating base, locked and coupled
//! coordinates); and the passive torques of the driven ones (PredSim's limit torques by
//! name and damping, PREDSIM.md §3.6).

use crate::gait::side_of;
use crate::passive_rules::limit_coefficients;
use stride_model::model_settings::{ActuatorSetting, PassiveTorqueEntry};
use stride_model::{JointKind, Model, PathPointKind};

/// Optimal torque of a new ideal actuator [N m] (PredSim's `AdaptOpenSimModel` arms).
pub const ACTUATOR_TORQUE: f64 = 150.0;

/// Activation time constant of a new ideal actuator [s] (PredSim's arms).
pub const ACTUATOR_TIME_CONSTANT: f64 = 0.035;

/// Damping of every driven coordinate [N m s rad⁻¹] (PredSim's default B = 0.1).
pub const DAMPING: f64 = 0.1;

/// How one coordinate is driven in the adapted model.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Drive {
    /// A coordinate of the floating base (the root joint): moved by the ground reactions.
    Root,
    /// Locked in the `.osim` file: stays at its default value.
    Locked,
    /// Given by a coupler constraint from another coordinate.
    Coupled,
    /// Crossed by at least one muscle.
    Muscles,
    /// Driven by the model's own actuator.
    ModelActuator,
    /// Crossed by no muscle: gets a new ideal torque actuator.
    NewActuator,
}

/// The index of the root joint: the first joint from the ground with coordinates.
fn root_joint(model: &Model) -> Option<usize> {
    model
        .joints
        .iter()
        .position(|j| j.parent == 0 && matches!(j.kind, JointKind::Custom { .. }))
}

/// The joints from `body` up to the ground, nearest first.
fn joints_to_ground(model: &Model, mut body: usize) -> Vec<usize> {
    let mut out = Vec::new();
    while let Some(j) = model.joints.iter().position(|j| j.child == body) {
        if out.contains(&j) {
            break;
        }
        out.push(j);
        body = model.joints[j].parent;
    }
    out
}

/// Whether some muscle crosses each coordinate: the coordinate belongs to a joint on the
/// chain of bodies between two successive path points of the muscle, or moves one of
/// its path points (a conditional or moving path point).
pub fn crossed(model: &Model) -> Vec<bool> {
    let mut crossed = vec![false; model.coordinates.len()];
    let mut joints = vec![false; model.joints.len()];
    for m in &model.muscles {
        for pair in m.path.windows(2) {
            let (a, b) = (
                joints_to_ground(model, pair[0].body),
                joints_to_ground(model, pair[1].body),
            );
            for j in a
                .iter()
                .filter(|j| !b.contains(j))
                .chain(b.iter().filter(|j| !a.contains(j)))
            {
                joints[*j] = true;
            }
        }
        for p in &m.path {
            match &p.kind {
                PathPointKind::Fixed => {}
                PathPointKind::Conditional { coordinate, .. } => crossed[*coordinate] = true,
                PathPointKind::Moving { components } => {
                    for (c, _) in components.iter().flatten() {
                        crossed[*c] = true;
                    }
                }
            }
        }
    }
    for (ci, c) in model.coordinates.iter().enumerate() {
        crossed[ci] |= joints[c.joint];
    }
    crossed
}

/// How each coordinate of `model` is driven once adapted (in model order).
pub fn drives(model: &Model) -> Vec<Drive> {
    let root = root_joint(model);
    let crossed = crossed(model);
    (model.coordinates.iter().enumerate())
        .map(|(ci, c)| {
            if Some(c.joint) == root {
                Drive::Root
            } else if c.locked {
                Drive::Locked
            } else if model.couplers.iter().any(|k| k.dependent == ci) {
                Drive::Coupled
            } else if model.actuators.iter().any(|a| a.coordinate == ci) {
                Drive::ModelActuator
            } else if crossed[ci] {
                Drive::Muscles
            } else {
                Drive::NewActuator
            }
        })
        .collect()
}

/// A new ideal torque actuator on every coordinate that `drives` marks
/// [`Drive::NewActuator`].
pub fn new_actuators(model: &Model, drives: &[Drive]) -> Vec<ActuatorSetting> {
    (model.coordinates.iter().zip(drives))
        .filter(|(_, d)| **d == Drive::NewActuator)
        .map(|(c, _)| ActuatorSetting {
            coordinate: c.name.clone(),
            optimal_force: ACTUATOR_TORQUE,
            name: None,
            control_range: [-1.0, 1.0],
            activation_time_constant: Some(ACTUATOR_TIME_CONSTANT),
        })
        .collect()
}

/// Passive torques of every driven coordinate (muscles or actuator): PredSim's limit
/// torque when its table has the coordinate's name (without side), and [`DAMPING`];
/// coordinates with the same law share one entry, in model order.
pub fn passive_table(model: &Model, drives: &[Drive]) -> Vec<PassiveTorqueEntry> {
    let mut out: Vec<PassiveTorqueEntry> = Vec::new();
    for (c, d) in model.coordinates.iter().zip(drives) {
        if !matches!(
            d,
            Drive::Muscles | Drive::ModelActuator | Drive::NewActuator
        ) {
            continue;
        }
        let (k, theta) = limit_coefficients(side_of(&c.name).0).unwrap_or(([0.0; 4], [0.0; 2]));
        match out
            .iter_mut()
            .find(|e| e.k == k && e.theta == theta && e.damping == DAMPING)
        {
            Some(e) => e.coordinates.push(c.name.clone()),
            None => out.push(PassiveTorqueEntry {
                coordinates: vec![c.name.clone()],
                k,
                theta,
                damping: DAMPING,
            }),
        }
    }
    out
}
