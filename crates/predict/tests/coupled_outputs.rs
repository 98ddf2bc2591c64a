//! The result files give a coupled coordinate its constraint's value: the built-in model
//! with `arm_rot_<side> = 0.1 + 0.5 arm_flex_<side>` (an analytic coupler).

#[path = "../../ocp/tests/coupled_model/mod.rs"]
mod coupled_model;

use coupled_model::coupled;
use stride_model::Function;
use stride_ocp::data;
use stride_ocp::problem::GaitProblem;
use stride_ocp::settings::ProblemSettings;
use stride_predict::outputs::model_coordinates;

#[test]
fn coupled_coordinates_are_written_with_their_constraint_value() {
    let m = coupled(Function::Linear {
        slope: 0.5,
        intercept: 0.1,
    });
    let settings = ProblemSettings {
        mesh_intervals: 4,
        ..Default::default()
    };
    let problem = GaitProblem::new(&m, &settings, &data::walking_half_cycle()).unwrap();
    let q: Vec<f64> = (0..problem.gait.nq()).map(|k| 0.05 * k as f64).collect();
    let out = model_coordinates(&problem, &q);
    for side in ["r", "l"] {
        let flex = problem.gait.index_of(&format!("arm_flex_{side}")).unwrap();
        let rot = m.coordinate_index(&format!("arm_rot_{side}")).unwrap();
        assert!((out[rot] - (0.1 + 0.5 * q[flex])).abs() < 1e-15, "{side}");
    }
}
