//! The fitted-geometry cache: fitted on first use, read back when the model content and
//! settings are the same, fitted again when the content changes; the file applied to a
//! model gives polynomial lengths within the fit's reported accuracy of the path lengths.

use std::path::Path;
use stride_geometry::{
    cached_geometry, polynomial_length, random_poses, FitSettings, GeometryFile, GeometrySource,
    PathGeometry,
};

#[test]
fn cache_fits_once_per_model_content() {
    let path = Path::new(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/tests/data/wrap_model.osim"
    ));
    let bytes = std::fs::read(path).unwrap();
    let model = stride_model::osim::load_osim(path).unwrap();
    let dir = std::env::temp_dir().join(format!("stride_geometry_cache_{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    let settings = FitSettings {
        n_samples: 400,
        seed: Some(5),
        orders: [3, 8],
        tolerance: 3e-3,
    };
    let (first, source) = cached_geometry(&model, &bytes, &dir, &settings).unwrap();
    let GeometrySource::Fitted(file) = source else {
        panic!("first use must fit")
    };
    assert!(file.exists());
    let (again, source) = cached_geometry(&model, &bytes, &dir, &settings).unwrap();
    assert_eq!(source, GeometrySource::Cached(file.clone()));
    assert_eq!(again, first);
    assert_eq!(GeometryFile::read(&file).unwrap(), first);
    let mut changed = bytes.clone();
    changed.extend_from_slice(b"\n");
    let (_, source) = cached_geometry(&model, &changed, &dir, &settings).unwrap();
    assert!(matches!(source, GeometrySource::Fitted(p) if p != file));
    // Applied to the model: polynomial lengths against the path lengths at other poses.
    let mut fitted = model.clone();
    first.apply(&mut fitted).unwrap();
    let mut geo = PathGeometry::new(&model).unwrap();
    let poses = random_poses(&model, 200, 11);
    let mut l = vec![0.0; model.muscles.len()];
    let mut sq = vec![0.0; model.muscles.len()];
    for s in 0..poses.len() {
        geo.lengths(poses.pose(s), &mut l);
        for (m, p) in fitted.path_polynomials.iter().enumerate() {
            let p = p.as_ref().unwrap();
            sq[m] += (polynomial_length(p, poses.pose(s)) - l[m]).powi(2);
        }
    }
    for (m, a) in first.accuracy.iter().enumerate() {
        let rms = (sq[m] / poses.len() as f64).sqrt() * 1e3;
        println!(
            "{}: fit RMSE {:.3} mm, at other poses {rms:.3} mm",
            a.muscle, a.rms_length_mm
        );
        if a.meets_tolerance {
            assert!(
                rms < 3.0 * a.rms_length_mm.max(0.5),
                "{}: {rms} mm",
                a.muscle
            );
        }
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// The shipped gait1018 model (without geometry) and its shipped geometry file as JSON.
fn gait1018() -> (stride_model::Model, serde_json::Value) {
    let s = stride_model::shipped::shipped("gait1018").unwrap();
    let model = stride_model::osim::parse_osim(s.osim, s.file_name).unwrap();
    (model, serde_json::from_str(s.geometry).unwrap())
}

fn apply_err(model: &stride_model::Model, v: &serde_json::Value) -> String {
    let mut m = model.clone();
    match GeometryFile::parse(&v.to_string(), "g.json") {
        Ok(file) => file.apply(&mut m).unwrap_err().to_string(),
        Err(e) => e.to_string(),
    }
}

#[test]
fn a_file_that_does_not_fit_the_model_is_refused_naming_the_muscle() {
    let (model, shipped) = gait1018();
    let mut m = model.clone();
    let file = GeometryFile::parse(&shipped.to_string(), "g.json").unwrap();
    file.apply(&mut m).unwrap();
    file.check_model_hash(
        stride_model::shipped::shipped("gait1018")
            .unwrap()
            .osim
            .as_bytes(),
        "g.json",
        "m.osim",
    )
    .unwrap();
    let e = file
        .check_model_hash(b"other", "g.json", "m.osim")
        .unwrap_err()
        .to_string();
    assert!(
        e.starts_with("g.json: fitted to a model file with content hash b355f1b7"),
        "{e}"
    );
    let names: Vec<String> = file.muscles.clone();
    // a right muscle swapped with its left twin: its polynomial spans the other leg
    let twin = names
        .iter()
        .position(|n| *n == names[0].replace("_r", "_l"))
        .unwrap();
    let mut v = shipped.clone();
    v["muscles"][0] = names[twin].clone().into();
    v["muscles"][twin] = names[0].clone().into();
    let e = apply_err(&model, &v);
    assert!(
        e.contains(&format!(
            "muscle {}: its polynomial spans coordinate",
            names[0]
        )),
        "{e}"
    );
    // two muscles of the same leg swapped: the lengths differ at the default pose
    let mut v = shipped.clone();
    let other = (1..twin)
        .find(|&k| {
            let l = |i: usize| {
                let p: stride_model::PathPolynomial =
                    serde_json::from_value(shipped["path_polynomials"][i].clone()).unwrap();
                let q: Vec<f64> = model.coordinates.iter().map(|c| c.default_value).collect();
                let mut q_file = vec![0.0; file.coordinates.len()];
                for (i, c) in file.coordinates.iter().enumerate() {
                    q_file[i] = q[model.coordinate_index(c).unwrap()];
                }
                polynomial_length(&p, &q_file)
            };
            (l(0) - l(k)).abs() > 0.05
        })
        .unwrap();
    v["muscles"][0] = names[other].clone().into();
    v["muscles"][other] = names[0].clone().into();
    let e = apply_err(&model, &v);
    assert!(e.contains("muscle "), "{e}");
    assert!(
        e.contains("at the default pose") || e.contains("spans coordinate"),
        "{e}"
    );
    // a name twice, a name the model lacks
    let mut v = shipped.clone();
    v["muscles"][1] = names[0].clone().into();
    assert!(apply_err(&model, &v).contains(&format!("lists muscle {} twice", names[0])));
    v["muscles"][1] = "nosuch".into();
    assert!(apply_err(&model, &v).contains("has muscles the model lacks: nosuch"));
    // corrupt numbers and shapes are refused when the file is read
    let mut v = shipped.clone();
    v["path_polynomials"][0]["coefficients"][0] = 1e300.into();
    let e = apply_err(&model, &v);
    assert!(
        e.contains("coefficient 1e300 is not finite or larger than 1000000000"),
        "{e}"
    );
    let mut v = shipped.clone();
    v["path_polynomials"][0]["coefficients"]
        .as_array_mut()
        .unwrap()
        .pop();
    assert!(apply_err(&model, &v).contains("exponent tuples but"));
    let mut v = shipped;
    v["path_polynomials"].as_array_mut().unwrap().pop();
    assert!(apply_err(&model, &v).contains("18 muscles but 17 polynomials"));
}
