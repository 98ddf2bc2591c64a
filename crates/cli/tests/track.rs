//! Bad input to `stride track` and to the contact geometry of a prediction: a one-line
//! error naming the file and the column, window or sphere, a non-zero exit, and no output
//! folder written.

mod common;
use common::rejects;
use std::path::{Path, PathBuf};

/// A fresh scratch folder for one test.
fn scratch(tag: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("stride-track-{tag}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn data(file: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../ocp/data")
        .join(file)
}

fn s(p: &Path) -> String {
    p.display().to_string()
}

#[test]
fn a_tracked_column_that_names_no_coordinate_is_rejected_and_nothing_is_written() {
    let d = scratch("column");
    let cfg = d.join("track.toml");
    std::fs::write(
        &cfg,
        "[track]\ncalibrate_contact = true\ncoordinates = [\"knee_angle_r\", \"knee_flexion\"]\n",
    )
    .unwrap();
    let out = d.join("out");
    rejects(
        &["track", "--config", &s(&cfg), "--out", &s(&out), "--quiet"],
        "`knee_flexion`",
    );
    assert!(!out.exists());
    let _ = std::fs::remove_dir_all(&d);
}

#[test]
fn a_window_outside_the_data_is_rejected_and_nothing_is_written() {
    let d = scratch("window");
    let out = d.join("out");
    rejects(
        &[
            "track",
            "--calibrate-contact",
            "--window",
            "4.0,5.0",
            "--out",
            &s(&out),
            "--quiet",
        ],
        "gait_1_ik.mot",
    );
    assert!(!out.exists());
    let _ = std::fs::remove_dir_all(&d);
}

#[test]
fn a_grf_file_without_the_expected_columns_is_rejected_and_nothing_is_written() {
    let d = scratch("grf");
    let grf = std::fs::read_to_string(data("gait_1_grf.mot")).unwrap();
    let bad = d.join("bad_grf.mot");
    std::fs::write(&bad, grf.replace("ground_torque_y", "ground_torque_w")).unwrap();
    let out = d.join("out");
    let motion = data("gait_1_ik.mot");
    rejects(
        &[
            "track",
            "--motion",
            &s(&motion),
            "--grf",
            &s(&bad),
            "--out",
            &s(&out),
            "--quiet",
        ],
        "bad_grf.mot",
    );
    assert!(!out.exists());
    let _ = std::fs::remove_dir_all(&d);
}

#[test]
fn a_contact_geometry_naming_an_unknown_sphere_is_rejected_before_solving() {
    let d = scratch("geometry");
    let geo = d.join("spheres.toml");
    std::fs::write(
        &geo,
        "[[sphere]]\nname = \"heel_r\"\nlocation = [0.0, -0.02, 0.0]\nradius = 0.03\n",
    )
    .unwrap();
    let cfg = d.join("predict.toml");
    std::fs::write(
        &cfg,
        format!("[problem]\ncontact_geometry = {:?}\n", s(&geo)),
    )
    .unwrap();
    let out = d.join("out");
    rejects(
        &[
            "predict",
            "--config",
            &s(&cfg),
            "--out",
            &s(&out),
            "--quiet",
        ],
        "spheres.toml: sphere `heel_r`",
    );
    assert!(!out.exists());
    let _ = std::fs::remove_dir_all(&d);
}
