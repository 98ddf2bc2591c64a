//! Bad input to `stride track` and to the contact geometry of a prediction: a one-line
//! error naming the file and the column, window or sphere, a non-zero exit, and no output
//! folder written.

mod common;
use common::rejects;
use std::path::{Path, PathBuf};
use stride_model::storage::Storage;

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

/// The shipped 2D model's own predicted gait (`tests/data/gait1018_prediction`).
fn prediction(file: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data/gait1018_prediction")
        .join(file)
}

/// The arguments of `stride track --model gait1018` with output folder `out`, then `extra`.
fn gait1018_args<'a>(out: &'a Path, extra: &[&'a str]) -> Vec<&'a str> {
    let mut args = vec![
        "track",
        "--model",
        "gait1018",
        "--out",
        out.to_str().unwrap(),
        "--quiet",
    ];
    args.extend_from_slice(extra);
    args
}

/// Linear interpolation of `column` of `s` at time `t`.
fn at(s: &Storage, column: &str, t: f64) -> f64 {
    let (time, v) = (s.time(), s.column(column).unwrap());
    let k = time.partition_point(|&x| x <= t).clamp(1, time.len() - 1) - 1;
    let w = (t - time[k]) / (time[k + 1] - time[k]);
    v[k] + w * (v[k + 1] - v[k])
}

#[test]
fn gait1018_tracking_its_own_prediction_reproduces_the_predicted_angles_within_1_degree() {
    let d = scratch("gait1018");
    let out = d.join("out");
    let predicted = Storage::read(&prediction("motion.mot")).unwrap();
    let end = *predicted.time().last().unwrap();
    let window = format!("0,{end}");
    let (motion, grf) = (prediction("motion.mot"), prediction("grf.mot"));
    let run = common::stride(&gait1018_args(
        &out,
        &[
            "--motion",
            &s(&motion),
            "--grf",
            &s(&grf),
            "--window",
            &window,
            "--mesh",
            "33",
            "--filter-cutoff",
            "0",
        ],
    ));
    assert!(run.status.success(), "{run:?}");
    let tracked = Storage::read(&out.join("motion.mot")).unwrap();
    let angles = [
        "pelvis_tilt",
        "hip_flexion_l",
        "hip_flexion_r",
        "knee_angle_l",
        "knee_angle_r",
        "ankle_angle_l",
        "ankle_angle_r",
        "lumbar_extension",
    ];
    // every mesh point of the window, its first and last (the last data sample) included
    let time = tracked.time();
    assert!((time[0] - 0.0).abs() < 1e-9 && (time[time.len() - 1] - end).abs() < 1e-9);
    for name in angles {
        let model = tracked.column(name).unwrap();
        let errors: Vec<f64> = time
            .iter()
            .zip(&model)
            .map(|(&t, m)| m - at(&predicted, name, t))
            .collect();
        let rmse = (errors.iter().map(|e| e * e).sum::<f64>() / errors.len() as f64).sqrt();
        let (k, max) = errors
            .iter()
            .map(|e| e.abs())
            .enumerate()
            .fold((0, 0.0), |m, (k, e)| if e > m.1 { (k, e) } else { m });
        assert!(rmse < 1.0, "{name}: RMSE {rmse:.3}° against the prediction");
        assert!(
            max < 1.0,
            "{name}: {max:.3}° off the prediction at {:.4} s",
            time[k]
        );
    }
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    assert_eq!(summary["status"], "Optimal");
    for bw in summary["errors"]["grf_percent_body_weight"]
        .as_array()
        .unwrap()
    {
        assert!(bw.as_f64().unwrap() < 5.0, "GRF RMSE {bw} % of body weight");
    }
    let _ = std::fs::remove_dir_all(&d);
}

#[test]
fn bad_input_is_rejected_for_another_model_too() {
    let d = scratch("gait1018-bad");
    let out = d.join("out");
    // gait1018 is planar: no hip adduction
    let cfg = d.join("track.toml");
    std::fs::write(&cfg, "[track]\ncoordinates = [\"hip_adduction_r\"]\n").unwrap();
    let cfg = s(&cfg);
    let motion = s(&prediction("motion.mot"));
    let grf = prediction("grf.mot");
    let track = |extra: &[&str], needle: &str| {
        let mut args = vec!["--motion", &motion];
        args.extend_from_slice(extra);
        rejects(&gait1018_args(&out, &args), needle);
        assert!(!out.exists(), "{needle}: {} was written", out.display());
    };
    let grf_s = s(&grf);
    track(
        &["--grf", &grf_s, "--config", &cfg, "--window", "0,0.9"],
        "motion.mot: tracked column `hip_adduction_r` names no coordinate",
    );
    track(
        &["--grf", &grf_s, "--window", "0.5,1.5"],
        "motion.mot: window [0.5, 1.5] s",
    );
    let bad = d.join("bad_grf.mot");
    let text = std::fs::read_to_string(&grf).unwrap();
    std::fs::write(&bad, text.replace("l_ground_torque_y", "l_ground_torque_w")).unwrap();
    track(
        &["--grf", &s(&bad), "--window", "0,0.9"],
        "bad_grf.mot: no column `l_ground_torque_y`",
    );
    let _ = std::fs::remove_dir_all(&d);
}

#[test]
fn a_calibration_writes_model_settings_that_give_the_calibrated_spheres() {
    let d = scratch("gait1018-calibrated");
    let out = d.join("out");
    let (motion, grf) = (s(&prediction("motion.mot")), s(&prediction("grf.mot")));
    let run = common::stride(&gait1018_args(
        &out,
        &[
            "--motion",
            &motion,
            "--grf",
            &grf,
            "--window",
            "0.1,0.5",
            "--mesh",
            "8",
            "--filter-cutoff",
            "0",
            "--calibrate-contact",
            "--max-iter",
            "40",
        ],
    ));
    // the iteration limit may end the solve: the folder is written all the same
    assert!(out.join("summary.json").is_file(), "{run:?}");
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    let value = |name: String| {
        let p = summary["static_parameters"].as_array().unwrap();
        let p = p.iter().find(|p| p["name"] == name.as_str());
        p.unwrap_or_else(|| panic!("no parameter {name}"))["value"]
            .as_f64()
            .unwrap()
    };
    let file = out.join("calibrated_model.toml");
    let settings = stride_model::model_settings::ModelSettings::read(&file).unwrap();
    let shipped = stride_model::shipped::shipped("gait1018").unwrap();
    let mut model = stride_model::osim::parse_osim(shipped.osim, shipped.file_name).unwrap();
    settings.apply(&mut model, &s(&file)).unwrap();
    let spheres = &settings.contact.spheres;
    assert_eq!(spheres.len(), model.contacts.len());
    assert_eq!(spheres.len(), 4);
    for (c, e) in model.contacts.iter().zip(spheres) {
        assert_eq!(
            (&c.name, c.location, c.radius),
            (&e.name, e.location, e.radius)
        );
        // each right sphere's parameters, mirrored onto the left one
        let right = c.name.replace("_l", "_r");
        let z = value(format!("{right}_z")) * if c.name.ends_with("_l") { -1.0 } else { 1.0 };
        let close = |a: f64, b: f64| (a - b).abs() < 1e-12;
        assert!(
            close(c.location[0], value(format!("{right}_x"))),
            "{}",
            c.name
        );
        assert!(close(c.location[2], z), "{}", c.name);
        assert!(
            close(c.radius, value(format!("{right}_radius"))),
            "{}",
            c.name
        );
    }
    // the same spheres as contact_geometry.toml, which the contact-models study reads
    let text = std::fs::read_to_string(out.join("contact_geometry.toml")).unwrap();
    let geometry: toml::Value = toml::from_str(&text).unwrap();
    let listed = geometry["sphere"].as_array().unwrap();
    assert_eq!(listed.len(), spheres.len());
    for (g, e) in listed.iter().zip(spheres) {
        assert_eq!(g["name"].as_str(), Some(e.name.as_str()));
        assert_eq!(g["radius"].as_float(), Some(e.radius));
        let location: Vec<f64> = (g["location"].as_array().unwrap().iter())
            .map(|v| v.as_float().unwrap())
            .collect();
        assert_eq!(location, e.location.to_vec());
    }
    // the rest of the model's settings are its shipped ones
    let own = stride_model::model_settings::ModelSettings::parse(shipped.settings, "gait1018");
    assert_eq!(settings.problem, own.unwrap().problem);
    let _ = std::fs::remove_dir_all(&d);
}
