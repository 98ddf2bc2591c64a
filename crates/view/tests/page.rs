//! The page of a synthetic result folder: the embedded frames place the pelvis and a
//! pelvis-fixed muscle point where the prescribed coordinates put them analytically, carry
//! the activations and forces of the files, and the page loads nothing from the network.

use base64::Engine as _;
use std::path::{Path, PathBuf};
use stride_model::storage::Storage;
use stride_model::{Model, MotionType, PathPointKind};
use stride_view::{result_page, ViewOptions};

const ROWS: usize = 61;
const DURATION: f64 = 1.2;

fn tx(t: f64) -> f64 {
    0.3 + 1.25 * t
}
fn act(m: usize, t: f64) -> f64 {
    0.5 + 0.4 * (6.0 * t + m as f64).sin()
}
fn fy(t: f64) -> f64 {
    700.0 * (std::f64::consts::PI * t / DURATION).sin()
}

/// A result folder: pelvis translating forward at 1.25 m/s at 0.95 m height, the pelvis
/// unrotated, the right hip flexing (degrees, as stride writes them), every muscle with an
/// activation, a vertical force under the right foot.
fn synthetic_folder(model: &Model, tag: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("stride-view-{tag}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let mut labels = vec!["time".to_string()];
    labels.extend(model.coordinates.iter().map(|c| c.name.clone()));
    labels.extend(
        model
            .muscles
            .iter()
            .map(|m| format!("{}/activation", m.name)),
    );
    let rows = (0..ROWS)
        .map(|i| {
            let t = DURATION * i as f64 / (ROWS - 1) as f64;
            let mut row = vec![t];
            for c in &model.coordinates {
                row.push(match c.name.as_str() {
                    "pelvis_tx" => tx(t),
                    "pelvis_ty" => 0.95,
                    "hip_flexion_r" => 30.0 * (6.0 * t).sin(),
                    _ if c.motion_type == MotionType::Rotational => c.default_value.to_degrees(),
                    _ => c.default_value,
                });
            }
            row.extend((0..model.muscles.len()).map(|m| act(m, t)));
            row
        })
        .collect();
    let motion = Storage {
        name: "motion".into(),
        in_degrees: Some(true),
        labels,
        rows,
    };
    motion.write(&dir.join("motion.mot")).unwrap();
    let mut labels = vec!["time".to_string()];
    for side in ["r", "l"] {
        for k in ["vx", "vy", "vz", "px", "py", "pz"] {
            labels.push(format!("{side}_ground_force_{k}"));
        }
    }
    let rows = (0..ROWS)
        .map(|i| {
            let t = DURATION * i as f64 / (ROWS - 1) as f64;
            let mut row = vec![t, 0.0, fy(t), 0.0, tx(t), 0.0, 0.08];
            row.extend([0.0; 6]);
            row
        })
        .collect();
    let grf = Storage {
        name: "grf".into(),
        in_degrees: Some(true),
        labels,
        rows,
    };
    grf.write(&dir.join("grf.mot")).unwrap();
    dir
}

/// The JSON embedded in a page.
fn page_data(html: &str) -> serde_json::Value {
    let start_tag = r#"<script type="application/json" id="stride-data">"#;
    let start = html.find(start_tag).expect("data element") + start_tag.len();
    let end = start + html[start..].find("</script>").expect("end of data");
    serde_json::from_str(&html[start..end]).expect("page data is JSON")
}

fn dequantise(q: &serde_json::Value) -> Vec<f64> {
    let bytes = base64::engine::general_purpose::STANDARD
        .decode(q["data"].as_str().unwrap())
        .unwrap();
    let (offset, step) = (q["offset"].as_f64().unwrap(), q["step"].as_f64().unwrap());
    bytes
        .chunks_exact(2)
        .map(|b| offset + step * f64::from(i16::from_le_bytes([b[0], b[1]])))
        .collect()
}

fn cleanup(dir: &Path) {
    let _ = std::fs::remove_dir_all(dir);
}

#[test]
fn frames_place_bodies_and_muscle_points_where_the_coordinates_put_them() {
    let model = stride_model::default_model::default_model();
    let dir = synthetic_folder(&model, "frames");
    let frames = 25;
    let html = result_page(
        &model,
        &dir,
        &ViewOptions {
            frames: Some(frames),
        },
    )
    .unwrap();
    cleanup(&dir);
    let data = page_data(&html);
    let case = &data["cases"][0];
    let time: Vec<f64> = serde_json::from_value(case["time"].clone()).unwrap();
    assert_eq!(time.len(), frames);
    let nb = model.bodies.len() - 1;
    assert_eq!(data["model"]["bodies"].as_array().unwrap().len(), nb);
    // pelvis (first body): origin at the prescribed translation (quantised over a 1.5 m
    // range: 12 µm steps), rotation the identity
    let origins = dequantise(&case["origins"]);
    let rotations = dequantise(&case["rotations"]);
    assert_eq!(origins.len(), frames * nb * 3);
    for (i, &t) in time.iter().enumerate() {
        let o = &origins[3 * nb * i..3 * nb * i + 3];
        assert!(
            (o[0] - tx(t)).abs() < 1e-4,
            "frame {i}: x {} vs {}",
            o[0],
            tx(t)
        );
        assert!((o[1] - 0.95).abs() < 1e-4 && o[2].abs() < 1e-4, "{o:?}");
        let r = &rotations[9 * nb * i..9 * nb * i + 9];
        for (k, v) in r.iter().enumerate() {
            let id = if k % 4 == 0 { 1.0 } else { 0.0 };
            assert!((v - id).abs() < 1e-4, "frame {i} rotation {r:?}");
        }
    }
    // the first point of the first muscle fixed on the pelvis: origin + local location
    let n_points: usize = model.muscles.iter().map(|m| m.path.len()).sum();
    let points = dequantise(&case["muscles"]);
    assert_eq!(points.len(), frames * n_points * 3);
    let (m, first) = model
        .muscles
        .iter()
        .enumerate()
        .find(|(_, m)| m.path[0].body == 1 && matches!(m.path[0].kind, PathPointKind::Fixed))
        .expect("a muscle starting on the pelvis");
    let start: usize = model.muscles[..m].iter().map(|m| m.path.len()).sum();
    let loc = first.path[0].location;
    for (i, &t) in time.iter().enumerate() {
        let p = &points[3 * (n_points * i + start)..][..3];
        let expect = [tx(t) + loc[0], 0.95 + loc[1], loc[2]];
        for k in 0..3 {
            assert!(
                (p[k] - expect[k]).abs() < 2e-4,
                "frame {i}: {p:?} vs {expect:?}"
            );
        }
    }
    // activations (bytes, 1/254 steps) and the right foot's vertical force
    let acts = base64::engine::general_purpose::STANDARD
        .decode(case["activations"].as_str().unwrap())
        .unwrap();
    let nm = model.muscles.len();
    assert_eq!(acts.len(), frames * nm);
    let grf: Vec<f64> = serde_json::from_value(case["grf"].clone()).unwrap();
    assert_eq!(grf.len(), frames * 12);
    for (i, &t) in time.iter().enumerate() {
        for mm in [0, nm / 2, nm - 1] {
            let a = f64::from(acts[i * nm + mm]) / 254.0;
            // linear interpolation between rows 0.02 s apart adds at most 2.4 · 0.02² / 8
            assert!((a - act(mm, t)).abs() < 0.003, "frame {i} muscle {mm}: {a}");
        }
        let f = grf[12 * i + 1];
        assert!(
            (f - fy(t)).abs() < 1e-3 * 700.0,
            "frame {i}: {f} vs {}",
            fy(t)
        );
        assert!((grf[12 * i + 3] - tx(t)).abs() < 1e-3);
    }
    // the hip's curve is in degrees, sampled at the frames
    let hip = case["curves"]
        .as_array()
        .unwrap()
        .iter()
        .find(|c| c["name"] == "hip_flexion_r")
        .unwrap();
    assert_eq!(hip["unit"], "deg");
    let v: Vec<f64> = serde_json::from_value(hip["values"].clone()).unwrap();
    for (i, &t) in time.iter().enumerate() {
        assert!(
            (v[i] - 30.0 * (6.0 * t).sin()).abs() < 0.2,
            "frame {i}: {}",
            v[i]
        );
    }
}

#[test]
fn the_page_is_self_contained() {
    let model = stride_model::default_model::default_model();
    let dir = synthetic_folder(&model, "offline");
    std::fs::write(
        dir.join("figure_test.svg"),
        "<svg xmlns='http://www.w3.org/2000/svg'/>",
    )
    .unwrap();
    let html = result_page(&model, &dir, &ViewOptions::default()).unwrap();
    cleanup(&dir);
    for needle in [
        "src=\"http",
        "href=\"http",
        "<link",
        "import(",
        " from '",
        "<script src",
    ] {
        assert!(!html.contains(needle), "page contains `{needle}`");
    }
    let data = page_data(&html);
    assert_eq!(data["figures"][0]["name"], "figure_test");
    // at most the motion's rows
    assert_eq!(data["cases"][0]["time"].as_array().unwrap().len(), ROWS);
}

#[test]
fn a_motion_without_a_model_coordinate_is_an_error_naming_it() {
    let model = stride_model::default_model::default_model();
    let dir = synthetic_folder(&model, "missing");
    let p = dir.join("motion.mot");
    let mut s = Storage::read(&p).unwrap();
    let col = s.column_index("knee_angle_l").unwrap();
    s.labels.remove(col);
    for r in &mut s.rows {
        r.remove(col);
    }
    s.write(&p).unwrap();
    let e = result_page(&model, &dir, &ViewOptions::default())
        .unwrap_err()
        .to_string();
    let frames = result_page(&model, &dir, &ViewOptions { frames: Some(1) })
        .unwrap_err()
        .to_string();
    let empty = result_page(&model, &dir.join("nothing"), &ViewOptions::default())
        .unwrap_err()
        .to_string();
    cleanup(&dir);
    assert!(
        e.contains("motion.mot") && e.contains("no column for coordinate `knee_angle_l`"),
        "{e}"
    );
    assert!(frames.contains("frames per cycle 1"), "{frames}");
    assert!(
        empty.contains("not a result folder (no motion.mot)"),
        "{empty}"
    );
}

#[test]
fn a_study_page_holds_every_case_with_a_motion_and_the_study_figures() {
    let model = stride_model::default_model::default_model();
    let root = std::env::temp_dir().join(format!("stride-view-study-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&root);
    std::fs::create_dir_all(root.join("cases/failed")).unwrap();
    std::fs::write(root.join("study.toml"), "").unwrap();
    std::fs::write(root.join("figure_conditions.svg"), "<svg/>").unwrap();
    for name in ["b_case", "a_case"] {
        let dir = synthetic_folder(&model, name);
        std::fs::rename(&dir, root.join("cases").join(name)).unwrap();
    }
    assert!(stride_view::folder::is_study_folder(&root));
    let html = stride_view::study_page(&model, &root, &ViewOptions::default()).unwrap();
    cleanup(&root);
    let data = page_data(&html);
    let names: Vec<&str> = data["cases"]
        .as_array()
        .unwrap()
        .iter()
        .map(|c| c["name"].as_str().unwrap())
        .collect();
    assert_eq!(names, ["a_case", "b_case"]);
    let frames = data["cases"][0]["time"].as_array().unwrap().len();
    assert_eq!(frames, stride_view::page::STUDY_FRAMES);
    assert_eq!(data["figures"][0]["name"], "figure_conditions");
}
