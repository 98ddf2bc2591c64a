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
