//! `stride model inspect` on bad models: a contact sphere on a missing frame, a coordinate
//! coupler naming a missing coordinate, an unknown joint class, a wrap object of an
//! unknown class, a path point on a missing body, an expression OpenSim's parser rejects
//! and a `FunctionBasedPath` polynomial of the wrong dimension are each one error line with the
//! file, the line and the element's name, and a non-zero exit.

mod common;

use common::rejects;

/// A one-body OpenSim 4 model with `joint` as its joint and `extra` inside `<Model>`.
fn model(joint: &str, extra: &str) -> String {
    format!(
        r#"<?xml version="1.0" encoding="UTF-8" ?>
<OpenSimDocument Version="40000">
  <Model name="bad">
    <Ground name="ground" />
    <BodySet>
      <objects>
        <Body name="b">
          <mass>1</mass>
          <inertia>1 1 1 0 0 0</inertia>
        </Body>
      </objects>
    </BodySet>
    <JointSet>
      <objects>
{joint}
      </objects>
    </JointSet>
{extra}
  </Model>
</OpenSimDocument>
"#
    )
}

const PIN: &str = r#"        <PinJoint name="pin">
          <socket_parent_frame>/ground</socket_parent_frame>
          <socket_child_frame>/bodyset/b</socket_child_frame>
          <coordinates><Coordinate name="q1" /></coordinates>
        </PinJoint>"#;

/// Writes `text` to a fresh file and returns its path and the line of `needle` in it.
fn write(name: &str, text: &str, needle: &str) -> (std::path::PathBuf, usize) {
    let dir = std::env::temp_dir().join(format!("stride-inspect-{}-{name}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join(name);
    std::fs::write(&path, text).unwrap();
    let line = text.lines().position(|l| l.contains(needle)).unwrap() + 1;
    (path, line)
}

fn check(name: &str, text: &str, needle: &str, element: &str) {
    let (path, line) = write(name, text, needle);
    let p = path.to_str().unwrap();
    rejects(&["model", "inspect", p], &format!("{p}:{line}:"));
    rejects(&["model", "inspect", p], element);
    std::fs::remove_dir_all(path.parent().unwrap()).unwrap();
}

#[test]
fn contact_sphere_on_a_missing_frame() {
    let extra = r#"    <ContactGeometrySet>
      <objects>
        <ContactSphere name="heel">
          <socket_frame>/bodyset/nowhere</socket_frame>
          <radius>0.03</radius>
        </ContactSphere>
        <ContactHalfSpace name="floor">
          <socket_frame>/ground</socket_frame>
          <orientation>0 0 -1.5707963267948966</orientation>
        </ContactHalfSpace>
      </objects>
    </ContactGeometrySet>
    <ForceSet>
      <objects>
        <SmoothSphereHalfSpaceForce name="contact_heel">
          <socket_sphere>/contactgeometryset/heel</socket_sphere>
          <socket_half_space>/contactgeometryset/floor</socket_half_space>
        </SmoothSphereHalfSpaceForce>
      </objects>
    </ForceSet>"#;
    check(
        "sphere.osim",
        &model(PIN, extra),
        "/bodyset/nowhere",
        "ContactSphere[name=heel]/socket_frame: `/bodyset/nowhere` names no body",
    );
}

#[test]
fn coupler_with_a_missing_coordinate() {
    let extra = r#"    <ConstraintSet>
      <objects>
        <CoordinateCouplerConstraint name="knee_coupler">
          <coupled_coordinates_function><LinearFunction><coefficients>1 0</coefficients></LinearFunction></coupled_coordinates_function>
          <independent_coordinate_names>q1</independent_coordinate_names>
          <dependent_coordinate_name>q_missing</dependent_coordinate_name>
        </CoordinateCouplerConstraint>
      </objects>
    </ConstraintSet>"#;
    check(
        "coupler.osim",
        &model(PIN, extra),
        "<dependent_coordinate_name>",
        "knee_coupler",
    );
}

#[test]
fn unknown_joint_class() {
    let joint = PIN
        .replace("<PinJoint", "<EllipsoidJoint")
        .replace("</PinJoint>", "</EllipsoidJoint>");
    check(
        "joint.osim",
        &model(&joint, ""),
        "<EllipsoidJoint",
        "EllipsoidJoint",
    );
}

#[test]
fn wrap_object_of_an_unknown_class() {
    let text = model(PIN, "").replace(
        r#"<Ground name="ground" />"#,
        r#"<Ground name="ground">
      <WrapObjectSet>
        <objects>
          <WrapCone name="cone">
            <radius>0.1</radius>
          </WrapCone>
        </objects>
      </WrapObjectSet>
    </Ground>"#,
    );
    check("wrap.osim", &text, "<WrapCone", "`cone`");
}

#[test]
fn path_point_on_a_missing_body() {
    let extra = r#"    <ForceSet>
      <objects>
        <Thelen2003Muscle name="m1">
          <GeometryPath name="geometrypath">
            <PathPointSet>
              <objects>
                <PathPoint name="origin">
                  <socket_parent_frame>/ground</socket_parent_frame>
                  <location>0 0 0</location>
                </PathPoint>
                <PathPoint name="insertion">
                  <socket_parent_frame>/bodyset/nowhere</socket_parent_frame>
                  <location>0 0.1 0</location>
                </PathPoint>
              </objects>
            </PathPointSet>
          </GeometryPath>
          <max_isometric_force>100</max_isometric_force>
          <optimal_fiber_length>0.1</optimal_fiber_length>
          <tendon_slack_length>0.2</tendon_slack_length>
        </Thelen2003Muscle>
      </objects>
    </ForceSet>"#;
    check(
        "point.osim",
        &model(PIN, extra),
        "/bodyset/nowhere",
        "PathPoint[name=insertion]",
    );
}

#[test]
fn expression_force_with_an_expression_opensim_rejects() {
    let extra = r#"    <components>
      <ExpressionBasedCoordinateForce name="knee_spring">
        <coordinate>q1</coordinate>
        <expression>-10*floor(q) - 2*qdot</expression>
      </ExpressionBasedCoordinateForce>
    </components>"#;
    check(
        "expr.osim",
        &model(PIN, extra),
        "<expression>",
        "knee_spring",
    );
}

#[test]
fn function_based_path_with_the_wrong_number_of_coordinates() {
    let extra = r#"    <components>
      <DeGrooteFregly2016Muscle name="vasti">
        <FunctionBasedPath name="path">
          <coordinate_paths>/jointset/pin/q1</coordinate_paths>
          <length_function>
            <MultivariatePolynomialFunction>
              <coefficients>0.3 -0.02 0.01</coefficients>
              <dimension>2</dimension>
              <order>1</order>
            </MultivariatePolynomialFunction>
          </length_function>
        </FunctionBasedPath>
        <max_isometric_force>1000</max_isometric_force>
        <optimal_fiber_length>0.1</optimal_fiber_length>
        <tendon_slack_length>0.2</tendon_slack_length>
      </DeGrooteFregly2016Muscle>
    </components>"#;
    check(
        "fbp.osim",
        &model(PIN, extra),
        "<MultivariatePolynomialFunction>",
        "vasti",
    );
}
