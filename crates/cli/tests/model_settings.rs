//! A model that cannot walk, or a settings file that does not fit its model, is told why:
//! one line, non-zero exit, nothing written (the shipped subject1 model with hand-written
//! settings files, so that no geometry is fitted).

mod common;
use common::rejects;
use std::path::PathBuf;

fn scratch(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!(
        "stride-model-settings-{name}-{}",
        std::process::id()
    ));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// Predict with the shipped subject1 model and `settings`: rejected with `needle`, and the
/// output folder is not created.
fn rejected_with(name: &str, settings: &str, needle: &str) {
    let d = scratch(name);
    let s = d.join("s.toml");
    std::fs::write(&s, settings).unwrap();
    let out = d.join("out");
    rejects(
        &[
            "predict",
            "--model",
            "subject1",
            "--model-settings",
            s.to_str().unwrap(),
            "--mesh",
            "4",
            "--out",
            out.to_str().unwrap(),
            "--quiet",
        ],
        needle,
    );
    assert!(!out.exists(), "{name}: {} was written", out.display());
    std::fs::remove_dir_all(&d).unwrap();
}

const SPHERES: &str = "[[contact.spheres]]\nname = \"heel_r\"\nbody = \"calcn_r\"\nlocation = [0.0, -0.01, 0.0]\nradius = 0.032\n\
[[contact.spheres]]\nname = \"heel_l\"\nbody = \"calcn_l\"\nlocation = [0.0, -0.01, 0.0]\nradius = 0.032\n";

#[test]
fn no_foot_contact() {
    rejected_with(
        "contact",
        "",
        "the model has no foot contact: add SmoothSphereHalfSpaceForce elements",
    );
}

#[test]
fn a_coordinate_driven_by_nothing() {
    rejected_with(
        "undriven",
        SPHERES,
        "` is free but driven by no muscle and no actuator: lock it or add an actuator",
    );
}

#[test]
fn a_distance_constraint_naming_a_missing_body() {
    rejected_with(
        "distance",
        &format!("{SPHERES}[[distances]]\nbodies = [\"femur_r\", \"hand_x\"]\nmin = 0.18\n"),
        "s.toml: `distances[0]`: the model has no body `hand_x`",
    );
}

#[test]
fn unknown_keys_name_the_file_line_and_key() {
    rejected_with(
        "unknown",
        "[contact]\nspheres = []\nsmoothing = 1\n",
        "s.toml:3: unknown field `smoothing`",
    );
}

#[test]
fn an_unknown_model_name_lists_the_shipped_ones() {
    rejects(
        &["predict", "--model", "falise2022", "--quiet"],
        "model `falise2022`: no such file, and not a shipped model (subject1, falisse2022, gait1018, dhondt2024)",
    );
}
