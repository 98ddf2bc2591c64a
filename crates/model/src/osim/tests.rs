//! Unit tests of the importer on small hand-written documents (the reference models are
//! tested in `tests/osim_reference.rs`).

use super::*;
use crate::model::{Function, JointKind, MotionType, PathPointKind, WrapShape};

const V3: &str = r#"<?xml version="1.0" encoding="UTF-8" ?>
<OpenSimDocument Version="30000">
  <Model name="tiny">
    <gravity> 0 -9.8 0</gravity>
    <BodySet>
      <objects>
        <Body name="ground">
          <mass>0</mass>
          <Joint />
        </Body>
        <Body name="thigh">
          <mass>2.5</mass>
          <mass_center>0 -0.2 0</mass_center>
          <inertia_xx>0.1</inertia_xx>
          <inertia_yy>0.02</inertia_yy>
          <inertia_zz>0.1</inertia_zz>
          <inertia_xy>0</inertia_xy>
          <inertia_xz>0</inertia_xz>
          <inertia_yz>0</inertia_yz>
          <WrapObjectSet><objects>
            <WrapCylinder name="cyl"><xyz_body_rotation>0 0 0.5</xyz_body_rotation>
              <translation>0 -0.1 0</translation><quadrant>-y</quadrant>
              <radius>0.03</radius><length>0.1</length></WrapCylinder>
          </objects></WrapObjectSet>
          <Joint>
            <CustomJoint name="hip">
              <parent_body>ground</parent_body>
              <location_in_parent>0 1 0</location_in_parent>
              <orientation_in_parent>0 0 0</orientation_in_parent>
              <location>0 0 0</location>
              <orientation>0 0 0</orientation>
              <CoordinateSet>
                <objects>
                  <Coordinate name="hip_flex">
                    <motion_type>rotational</motion_type>
                    <default_value>0.1</default_value>
                    <range>-1 2</range>
                    <locked>false</locked>
                  </Coordinate>
                </objects>
              </CoordinateSet>
              <SpatialTransform>
                <TransformAxis name="rotation1">
                  <coordinates>hip_flex</coordinates>
                  <axis>0 0 2</axis>
                  <function><LinearFunction><coefficients> 1 0</coefficients></LinearFunction></function>
                </TransformAxis>
                <TransformAxis name="rotation2">
                  <coordinates></coordinates>
                  <axis>1 0 0</axis>
                  <function><Constant><value>0</value></Constant></function>
                </TransformAxis>
                <TransformAxis name="rotation3">
                  <coordinates></coordinates>
                  <axis>0 1 0</axis>
                  <function><Constant><value>0</value></Constant></function>
                </TransformAxis>
                <TransformAxis name="translation1">
                  <coordinates>hip_flex</coordinates>
                  <axis>1 0 0</axis>
                  <function><MultiplierFunction><function><SimmSpline><x>-1 0 1</x><y>0 0.1 0.3</y></SimmSpline></function><scale>2</scale></MultiplierFunction></function>
                </TransformAxis>
                <TransformAxis name="translation2">
                  <coordinates></coordinates>
                  <axis>0 1 0</axis>
                  <function><Constant><value>0</value></Constant></function>
                </TransformAxis>
                <TransformAxis name="translation3">
                  <coordinates></coordinates>
                  <axis>0 0 1</axis>
                  <function><Constant><value>0</value></Constant></function>
                </TransformAxis>
              </SpatialTransform>
            </CustomJoint>
          </Joint>
        </Body>
      </objects>
    </BodySet>
    <ForceSet>
      <objects>
        <Thelen2003Muscle name="m1">
          <GeometryPath>
            <PathPointSet>
              <objects>
                <PathPoint name="p1"><location>0 0 0</location><body>ground</body></PathPoint>
                <ConditionalPathPoint name="p2"><location>0 0.5 0</location><body>ground</body>
                  <range>-1 0.5</range><coordinate>hip_flex</coordinate></ConditionalPathPoint>
                <MovingPathPoint name="p3"><location>0 -0.1 0</location><body>thigh</body>
                  <x_location><Constant><value>0.02</value></Constant></x_location>
                  <x_coordinate>hip_flex</x_coordinate>
                </MovingPathPoint>
              </objects>
            </PathPointSet>
            <PathWrapSet><objects><PathWrap name="w"><wrap_object>cyl</wrap_object><range>1 3</range></PathWrap></objects></PathWrapSet>
          </GeometryPath>
          <max_isometric_force>1000</max_isometric_force>
          <optimal_fiber_length>0.1</optimal_fiber_length>
          <tendon_slack_length>0.2</tendon_slack_length>
          <pennation_angle_at_optimal>0.1</pennation_angle_at_optimal>
          <max_contraction_velocity>10</max_contraction_velocity>
        </Thelen2003Muscle>
        <CoordinateActuator name="act"><coordinate>hip_flex</coordinate><optimal_force>50</optimal_force>
          <min_control>-1</min_control><max_control>1</max_control></CoordinateActuator>
        <PointActuator name="pa"><isDisabled>true</isDisabled><body>thigh</body></PointActuator>
      </objects>
    </ForceSet>
    <MarkerSet><objects><Marker name="a"/><Marker name="b"/></objects></MarkerSet>
  </Model>
</OpenSimDocument>
"#;

#[test]
fn tiny_v3_model() {
    let m = parse_osim(V3, "tiny.osim").unwrap();
    assert_eq!(m.name, "tiny");
    assert_eq!(m.gravity, [0.0, -9.8, 0.0]);
    assert_eq!(m.bodies.len(), 2);
    assert_eq!(m.bodies[1].inertia, [0.1, 0.02, 0.1, 0.0, 0.0, 0.0]);
    assert_eq!(m.coordinates.len(), 1);
    let c = &m.coordinates[0];
    assert_eq!(
        (c.motion_type, c.range, c.default_value),
        (MotionType::Rotational, [-1.0, 2.0], 0.1)
    );
    let j = &m.joints[0];
    assert_eq!(j.frame_in_parent.location, [0.0, 1.0, 0.0]);
    let JointKind::Custom {
        rotations,
        translations,
    } = &j.kind
    else {
        panic!("custom joint expected")
    };
    assert_eq!(rotations[0].axis, [0.0, 0.0, 1.0], "axis normalised");
    assert_eq!(rotations[0].coordinate, Some(0));
    assert_eq!(
        translations[0].function,
        Function::Multiplier {
            scale: 2.0,
            function: Box::new(Function::SimmSpline {
                x: vec![-1.0, 0.0, 1.0],
                y: vec![0.0, 0.1, 0.3]
            })
        }
    );
    assert_eq!(m.muscles.len(), 1);
    let mu = &m.muscles[0];
    assert_eq!(mu.path.len(), 3);
    assert!(
        matches!(mu.path[1].kind, PathPointKind::Conditional { coordinate: 0, range } if range == [-1.0, 0.5])
    );
    let PathPointKind::Moving { components } = &mu.path[2].kind else {
        panic!("moving point expected")
    };
    assert_eq!(components[0], Some((0, Function::Constant(0.02))));
    assert!(components[1].is_none() && components[2].is_none());
    assert_eq!(mu.path[2].location, [0.0, -0.1, 0.0]);
    assert_eq!(m.actuators.len(), 1);
    assert_eq!(m.actuators[0].control_range, [-1.0, 1.0]);
    // The wrap cylinder and the path's wrap over it.
    assert_eq!(m.wrap_objects.len(), 1);
    let w = &m.wrap_objects[0];
    assert_eq!((w.name.as_str(), w.body), ("cyl", 1));
    assert_eq!(
        (w.rotation, w.translation),
        ([0.0, 0.0, 0.5], [0.0, -0.1, 0.0])
    );
    assert_eq!(
        w.quadrant,
        Some(crate::model::WrapQuadrant { axis: 1, sign: -1 })
    );
    assert_eq!(
        w.shape,
        crate::model::WrapShape::Cylinder {
            radius: 0.03,
            length: 0.1
        }
    );
    assert_eq!(mu.wraps.len(), 1);
    assert_eq!((mu.wraps[0].object, mu.wraps[0].range), (0, [1, 3]));
    // The disabled PointActuator reported; markers counted in the summary.
    let kinds: Vec<&str> = m.unsupported.iter().map(|u| u.element.as_str()).collect();
    assert!(kinds.contains(&"PointActuator"), "{kinds:?}");
    let summary = m
        .unsupported
        .iter()
        .find(|u| u.element == "(visual/bookkeeping)")
        .unwrap();
    assert!(summary.reason.contains("2 Marker"), "{}", summary.reason);
    let pa = m
        .unsupported
        .iter()
        .find(|u| u.element == "PointActuator")
        .unwrap();
    assert_eq!(
        pa.path,
        "Model[name=tiny]/ForceSet/objects/PointActuator[name=pa]"
    );
    assert!(pa.line > 80);
    assert!(pa.reason.contains("disabled"), "{}", pa.reason);
}

#[test]
fn enabled_unsupported_force_is_an_error_naming_it() {
    let text = V3.replace("<isDisabled>true</isDisabled>", "");
    let e = err_of(&text);
    let line = line_of(&text, "<PointActuator");
    assert!(e.starts_with(&format!("bad.osim:{line}:")), "{e}");
    assert!(e.contains("`pa`") && e.contains("PointActuator"), "{e}");
}

fn err_of(text: &str) -> String {
    parse_osim(text, "bad.osim").unwrap_err().to_string()
}

fn line_of(text: &str, needle: &str) -> usize {
    text.lines().position(|l| l.contains(needle)).unwrap() + 1
}

#[test]
fn truncated_xml_reports_line() {
    let cut = &V3[..V3.find("<ForceSet>").unwrap()];
    let e = err_of(cut);
    assert!(
        e.starts_with("bad.osim:") && e.contains("malformed XML"),
        "{e}"
    );
}

#[test]
fn unknown_parent_body() {
    let t = V3.replace(
        "<parent_body>ground</parent_body>",
        "<parent_body>pelvis</parent_body>",
    );
    let e = err_of(&t);
    let line = line_of(&t, "<parent_body>pelvis");
    assert!(e.contains(&format!("bad.osim:{line}:")), "{e}");
    assert!(
        e.contains("Body[name=thigh]/Joint/CustomJoint[name=hip]/parent_body"),
        "{e}"
    );
    assert!(e.contains("unknown parent body `pelvis`"), "{e}");
}

#[test]
fn non_numeric_mass() {
    let t = V3.replace("<mass>2.5</mass>", "<mass>2.5kg</mass>");
    let e = err_of(&t);
    let line = line_of(&t, "2.5kg");
    assert!(e.contains(&format!("bad.osim:{line}:")), "{e}");
    assert!(
        e.contains("Model[name=tiny]/BodySet/objects/Body[name=thigh]/mass"),
        "{e}"
    );
    assert!(e.contains("`2.5kg` is not a number"), "{e}");
}

#[test]
fn missing_mass() {
    let t = V3.replace("<mass>2.5</mass>", "");
    let e = err_of(&t);
    assert!(
        e.contains("Body[name=thigh]/mass: required element is missing"),
        "{e}"
    );
}

#[test]
fn unknown_coordinate_in_conditional_point() {
    let t = V3.replace(
        "<coordinate>hip_flex</coordinate></ConditionalPathPoint>",
        "<coordinate>knee</coordinate></ConditionalPathPoint>",
    );
    let e = err_of(&t);
    let line = line_of(&t, "<coordinate>knee");
    assert!(e.contains(&format!("bad.osim:{line}:")), "{e}");
    assert!(
        e.contains("ConditionalPathPoint[name=p2]/coordinate"),
        "{e}"
    );
    assert!(e.contains("unknown coordinate `knee`"), "{e}");
}

#[test]
fn unknown_coordinate_in_transform_axis() {
    let t = V3.replace(
        "<coordinates>hip_flex</coordinates>\n                  <axis>0 0 2</axis>",
        "<coordinates>hip_flx</coordinates>\n                  <axis>0 0 2</axis>",
    );
    let e = err_of(&t);
    assert!(
        e.contains("TransformAxis[name=rotation1]/coordinates"),
        "{e}"
    );
}

#[test]
fn old_format_rejected() {
    let t = V3.replace("Version=\"30000\"", "Version=\"20302\"");
    assert!(err_of(&t).contains("20302"));
}

#[test]
fn unknown_wrap_class_names_file_line_and_object() {
    let text = V3
        .replace("WrapCylinder name=\"cyl\"", "WrapCone name=\"cyl\"")
        .replace("</WrapCylinder>", "</WrapCone>");
    let e = err_of(&text);
    let line = line_of(&text, "<WrapCone");
    assert!(e.starts_with(&format!("bad.osim:{line}:")), "{e}");
    assert!(e.contains("`cyl`") && e.contains("WrapCone"), "{e}");
}

#[test]
fn torus_is_read_and_its_radii_are_checked() {
    let torus = |inner: &str, outer: &str| {
        V3.replace(
            "<WrapCylinder name=\"cyl\"><xyz_body_rotation>0 0 0.5</xyz_body_rotation>",
            "<WrapTorus name=\"cyl\"><xyz_body_rotation>0 0 0.5</xyz_body_rotation>",
        )
        .replace(
            "<radius>0.03</radius><length>0.1</length></WrapCylinder>",
            &format!("<inner_radius>{inner}</inner_radius><outer_radius>{outer}</outer_radius></WrapTorus>"),
        )
    };
    let model = parse_osim(&torus("0.01", "0.04"), "ok.osim").unwrap();
    assert_eq!(
        model.wrap_objects[0].shape,
        WrapShape::Torus {
            inner_radius: 0.01,
            outer_radius: 0.04
        }
    );
    let text = torus("0.04", "0.01");
    let e = err_of(&text);
    let line = line_of(&text, "<outer_radius>");
    assert!(e.starts_with(&format!("bad.osim:{line}:")), "{e}");
    assert!(
        e.contains("outer_radius") && e.contains("inner_radius"),
        "{e}"
    );
}

#[test]
fn path_wrap_over_a_missing_object_is_an_error() {
    let text = V3.replace(
        "<wrap_object>cyl</wrap_object>",
        "<wrap_object>nope</wrap_object>",
    );
    let e = err_of(&text);
    let line = line_of(&text, "<wrap_object>nope");
    assert!(e.starts_with(&format!("bad.osim:{line}:")), "{e}");
    assert!(e.contains("unknown wrap object `nope`"), "{e}");
}

#[test]
fn path_point_on_a_missing_body_is_an_error() {
    let text = V3.replace(
        "<location>0 -0.1 0</location><body>thigh</body>",
        "<location>0 -0.1 0</location><body>shank</body>",
    );
    let e = err_of(&text);
    let line = line_of(&text, "<body>shank</body>");
    assert!(e.starts_with(&format!("bad.osim:{line}:")), "{e}");
    assert!(e.contains("shank"), "{e}");
}

#[test]
fn contact_values_out_of_range_name_the_element_and_line() {
    let shipped = crate::shipped::shipped("gait1018").unwrap();
    for (from, to, needle) in [
        (
            "<stiffness>3067776</stiffness>",
            "<stiffness>-5</stiffness>",
            "stiffness -5.0 is out of range",
        ),
        (
            "<dissipation>2</dissipation>",
            "<dissipation>nan</dissipation>",
            "dissipation NaN is out of range",
        ),
        (
            "<transition_velocity>0.20000000000000001</transition_velocity>",
            "<transition_velocity>0</transition_velocity>",
            "transition_velocity 0.0 is out of range",
        ),
        (
            "<radius>0.035000000000000003</radius>",
            "<radius>1e300</radius>",
            "radius 1e300 is out of range",
        ),
    ] {
        let text = shipped.osim.replacen(from, to, 1);
        let e = err_of(&text);
        assert!(e.contains(needle), "{e}");
        assert!(e.contains(&format!(":{}:", line_of(&text, to))), "{e}");
    }
}
