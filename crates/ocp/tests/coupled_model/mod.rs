//! The built-in model with its arm rotations coupled to the arm flexions, shared by the
//! tests of the problem (`stride-ocp`) and of the result files (`stride-predict`).

use stride_model::default_model::default_model;
use stride_model::{CoordinateCoupler, Function, Model};

/// The built-in model with `arm_rot_<side>` given by `f(arm_flex_<side>)` and without
/// its actuators and passive torques.
pub fn coupled(f: Function) -> Model {
    let mut m = default_model();
    for side in ["r", "l"] {
        let d = m.coordinate_index(&format!("arm_rot_{side}")).unwrap();
        let i = m.coordinate_index(&format!("arm_flex_{side}")).unwrap();
        m.actuators.retain(|a| a.coordinate != d);
        m.passive_torques.retain(|p| p.coordinate != d);
        m.couplers.push(CoordinateCoupler {
            name: format!("arm_rot_{side}_follows_arm_flex"),
            dependent: d,
            independent: i,
            function: f.clone(),
        });
    }
    m
}
