//! A coupled coordinate (OpenSim `CoordinateCouplerConstraint`) is not a free variable
//! of the gait problem: the built-in model with `arm_rot_<side>` following
//! `arm_flex_<side>` has two coordinates fewer, a constant coupler gives the node function
//! of the model with the coordinate locked at that constant (an analytic case: the
//! coupled value, speed 0 and acceleration 0 enter the dynamics), and fitted geometry
//! that spans a coupled coordinate, or a force on one, is refused in one line.

mod coupled_model;

use coupled_model::coupled;
use stride_model::default_model::default_model;
use stride_model::{CoordinateCoupler, Function, Model};
use stride_ocp::data;
use stride_ocp::gait::GaitModel;
use stride_ocp::node::NodeModel;
use stride_ocp::problem::GaitProblem;
use stride_ocp::settings::ProblemSettings;

/// The node outputs of `model` at the scaled inputs `x(k) = 0.5 + 0.2 sin(0.7 k)`.
fn node_outputs(model: &Model) -> Vec<f64> {
    let settings = ProblemSettings {
        mesh_intervals: 4,
        ..Default::default()
    };
    let problem = GaitProblem::new(model, &settings, &data::walking_half_cycle()).unwrap();
    let node = NodeModel::new(&problem).unwrap();
    let mut ws = node.workspace::<f64>().unwrap();
    let x: Vec<f64> = (0..node.n_inputs())
        .map(|k| 0.5 + 0.2 * (0.7 * k as f64).sin())
        .collect();
    let mut y = vec![0.0; node.n_outputs()];
    node.eval(&mut ws, &x, &mut y);
    y
}

#[test]
fn a_coupled_coordinate_is_not_free() {
    let plain = GaitModel::new(&default_model()).unwrap();
    let g = GaitModel::new(&coupled(Function::Linear {
        slope: 0.5,
        intercept: 0.1,
    }))
    .unwrap();
    assert_eq!(g.nq(), plain.nq() - 2);
    assert!(g.coordinates.iter().all(|c| !c.name.starts_with("arm_rot")));
    let m = default_model();
    let rot = ["arm_rot_r", "arm_rot_l"].map(|n| m.coordinate_index(n).unwrap());
    assert!(g.locked.iter().all(|(c, _)| !rot.contains(c)));
}

#[test]
fn a_constant_coupler_is_a_lock() {
    let value = 0.2;
    let with_coupler = node_outputs(&coupled(Function::Constant(value)));
    let mut locked = default_model();
    for side in ["r", "l"] {
        let d = locked.coordinate_index(&format!("arm_rot_{side}")).unwrap();
        locked.actuators.retain(|a| a.coordinate != d);
        locked.passive_torques.retain(|p| p.coordinate != d);
        locked.coordinates[d].locked = true;
        locked.coordinates[d].default_value = value;
    }
    let with_lock = node_outputs(&locked);
    assert_eq!(with_coupler.len(), with_lock.len());
    let finite = with_lock.iter().filter(|b| b.is_finite()).count();
    assert!(
        finite * 10 >= with_lock.len() * 9,
        "{finite} finite outputs"
    );
    for (k, (a, b)) in with_coupler.iter().zip(&with_lock).enumerate() {
        let same = a == b || (a - b).abs() <= 1e-9 * (1.0 + b.abs()) || (a.is_nan() && b.is_nan());
        assert!(same, "output {k}: {a} != {b}");
    }
}

#[test]
fn geometry_spanning_a_coupled_coordinate_is_refused() {
    let mut m = default_model();
    let d = m.coordinate_index("knee_angle_r").unwrap();
    let i = m.coordinate_index("hip_flexion_r").unwrap();
    m.passive_torques.retain(|p| p.coordinate != d);
    m.couplers.push(CoordinateCoupler {
        name: "knee_follows_hip".into(),
        dependent: d,
        independent: i,
        function: Function::Constant(0.0),
    });
    let e = GaitModel::new(&m).unwrap_err().to_string();
    assert!(!e.contains('\n'), "{e}");
    assert!(e.contains("coupled coordinate `knee_angle_r`"), "{e}");
}

#[test]
fn a_force_on_a_coupled_coordinate_is_refused() {
    let mut m = default_model();
    let d = m.coordinate_index("arm_rot_r").unwrap();
    let i = m.coordinate_index("arm_flex_r").unwrap();
    m.couplers.push(CoordinateCoupler {
        name: "rot_follows_flex".into(),
        dependent: d,
        independent: i,
        function: Function::Constant(0.0),
    });
    assert_eq!(
        GaitModel::new(&m).unwrap_err().to_string(),
        "coordinate `arm_rot_r` follows `arm_flex_r` (coupled) but has an actuator: put it on \
         `arm_flex_r` or remove it"
    );
}
