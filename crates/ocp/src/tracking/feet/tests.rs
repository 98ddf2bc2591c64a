use super::*;
use std::path::{Path, PathBuf};
use stride_model::default_model::default_model;

/// The OpenSim reference models folder, or `None` (with the reason printed) when absent.
fn opensim_models() -> Option<PathBuf> {
    let p = PathBuf::from(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../../shared/reference/models/opensim"
    ));
    if p.is_dir() {
        Some(p)
    } else {
        eprintln!("skipped: {} is absent", p.display());
        None
    }
}

/// An ExternalLoads document of `forces`: (name, body, identifier prefix, extra elements).
fn loads(forces: &[(&str, &str, &str, &str)]) -> ExternalLoads {
    let objects: String = forces
        .iter()
        .map(|(name, body, p, extra)| {
            format!(
                "<ExternalForce name=\"{name}\"><applied_to_body>{body}</applied_to_body>\
                 <force_identifier>{p}ground_force_v</force_identifier>\
                 <point_identifier>{p}ground_force_p</point_identifier>\
                 <torque_identifier>{p}ground_torque_</torque_identifier>{extra}</ExternalForce>\n"
            )
        })
        .collect();
    let text = format!(
        "<OpenSimDocument Version=\"30000\"><ExternalLoads name=\"l\"><objects>\n{objects}\
         </objects><datafile>grf.mot</datafile></ExternalLoads></OpenSimDocument>"
    );
    ExternalLoads::parse(&text, Path::new("loads.xml")).unwrap()
}

/// The one-line message of the error of mapping `forces` onto the default model's feet.
fn error_of(forces: &[(&str, &str, &str, &str)]) -> String {
    let m = foot_columns(&loads(forces), &default_model())
        .unwrap_err()
        .to_string();
    assert!(m.starts_with("loads.xml"), "{m}");
    assert_eq!(m.lines().count(), 1, "{m}");
    m
}

#[test]
fn the_feet_are_the_contact_bodies_their_parents_and_the_bodies_below() {
    let model = default_model();
    let names = |side: usize| -> Vec<String> {
        foot_bodies(&model)[side]
            .iter()
            .map(|&b| model.bodies[b].name.clone())
            .collect()
    };
    for (side, s) in [(0, "r"), (1, "l")] {
        let n = names(side);
        for body in ["talus", "calcn", "toes"] {
            assert!(n.contains(&format!("{body}_{s}")), "{n:?}");
        }
        assert!(
            !n.iter().any(|b| b.starts_with("tibia") || b == "pelvis"),
            "{n:?}"
        );
        assert!(!n.iter().any(|b| !b.ends_with(s)), "{n:?}");
    }
}

#[test]
fn forces_map_to_the_feet_by_their_bodies_whatever_their_order_and_prefixes() {
    let l = loads(&[
        ("left", "calcn_l", "", ""),
        ("off", "calcn_l", "3_", "<appliesForce>false</appliesForce>"),
        ("right", "toes_r", "1_", ""),
    ]);
    let [r, left] = foot_columns(&l, &default_model()).unwrap();
    assert_eq!(r[0], "1_ground_force_vx");
    assert_eq!(r[5], "1_ground_force_pz");
    assert_eq!(left[0], "ground_force_vx");
    assert_eq!(left[6], "ground_torque_x");
}

#[test]
fn gait2392_pipeline_forces_map_calcn_r_to_the_right_foot() {
    let Some(root) = opensim_models() else { return };
    let xml = root.join("gait2392_pipeline/subject01_walk1_grf.xml");
    let l = ExternalLoads::read(&xml).unwrap();
    let [r, left] = foot_columns(&l, &default_model()).unwrap();
    assert_eq!(r[0], "ground_force_vx");
    assert_eq!(left[0], "1_ground_force_vx");
    let l = ExternalLoads::read(&root.join("moco_example2DWalking/referenceGRF.xml")).unwrap();
    let [r, left] = foot_columns(&l, &default_model()).unwrap();
    assert_eq!(r[8], "ground_torque_r_z");
    assert_eq!(left[3], "ground_force_l_px");
}

#[test]
fn a_force_on_a_missing_body_or_a_body_that_is_no_foot_is_an_error_naming_it() {
    let m = error_of(&[("r", "calcn_r", "", ""), ("l", "foot_l", "1_", "")]);
    assert!(
        m.contains("`l`") && m.contains("`foot_l` is not a body of the model"),
        "{m}"
    );
    let m = error_of(&[("r", "calcn_r", "", ""), ("l", "tibia_l", "1_", "")]);
    assert!(
        m.contains("`tibia_l` is not a foot") && m.contains("calcn_l"),
        "{m}"
    );
}

#[test]
fn a_force_expressed_in_a_body_is_an_error_saying_it_is_not_supported() {
    let frame = "<point_expressed_in_body>calcn_l</point_expressed_in_body>";
    let m = error_of(&[("r", "calcn_r", "", ""), ("l", "calcn_l", "1_", frame)]);
    assert!(
        m.contains("<point_expressed_in_body>") && m.contains("not supported"),
        "{m}"
    );
}

#[test]
fn two_forces_on_one_foot_or_none_on_the_other_is_an_error() {
    let m = error_of(&[("a", "calcn_r", "", ""), ("b", "toes_r", "1_", "")]);
    assert!(
        m.contains("`b`") && m.contains("`a` already acts on the right foot"),
        "{m}"
    );
    let off = "<isDisabled>true</isDisabled>";
    let m = error_of(&[("a", "calcn_r", "", ""), ("b", "calcn_l", "1_", off)]);
    assert!(
        m.contains("no applied ExternalForce acts on the left foot"),
        "{m}"
    );
}
