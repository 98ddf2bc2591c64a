//! A model that cannot walk is told why, in one line: no foot contact, a coordinate driven
//! by nothing, a sided coordinate without its mirror, a distance constraint naming a
//! missing body (the built-in model, changed in one place each).

use stride_model::default_model::default_model;
use stride_ocp::gait::GaitModel;
use stride_ocp::problem::GaitProblem;
use stride_ocp::settings::{DistanceConstraint, ProblemSettings};

fn gait_error(m: &stride_model::Model) -> String {
    let e = GaitModel::new(m).expect_err("the model should be rejected");
    let s = e.to_string();
    assert!(!s.contains('\n'), "{s}");
    s
}

#[test]
fn no_foot_contact() {
    let mut m = default_model();
    m.contacts.clear();
    let e = gait_error(&m);
    assert!(e.contains("no foot contact"), "{e}");
    assert!(e.contains("add SmoothSphereHalfSpaceForce elements"), "{e}");
}

#[test]
fn a_coordinate_driven_by_nothing() {
    let mut m = default_model();
    let c = m.coordinate_index("arm_flex_l").unwrap();
    m.actuators.retain(|a| a.coordinate != c);
    assert_eq!(
        gait_error(&m),
        "coordinate `arm_flex_l` is free but driven by no muscle and no actuator: lock it or add an actuator"
    );
}

#[test]
fn a_sided_coordinate_without_its_mirror() {
    let mut m = default_model();
    let c = m.coordinate_index("elbow_flex_l").unwrap();
    m.coordinates[c].name = "elbow_bend_l".into();
    let e = gait_error(&m);
    assert!(
        e.contains("`elbow_bend_l` has no mirror `elbow_bend_r`"),
        "{e}"
    );
}

#[test]
fn a_distance_constraint_naming_a_missing_body() {
    let m = default_model();
    let settings = ProblemSettings {
        mesh_intervals: 4,
        min_distances: Some(vec![DistanceConstraint {
            bodies: ["calcn_r".into(), "hand_x".into()],
            min: 0.1,
            max: 2.0,
        }]),
        ..Default::default()
    };
    let data = stride_ocp::bounds::bounds_data(&settings);
    let e = GaitProblem::new(&m, &settings, &data)
        .and_then(|p| stride_ocp::node::NodeModel::new(&p).map(|_| ()))
        .expect_err("the constraint should be rejected")
        .to_string();
    assert_eq!(
        e,
        "distance constraint `calcn_r`–`hand_x`: the model has no body `hand_x` (remove it from `min_distances` or from the model's settings file)"
    );
}
