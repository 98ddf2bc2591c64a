//! Random fitting poses: reproducible from the seed, within the ranges of FORMULATION 4.4
//! step 1, left = right, pelvis at 0.

use stride_geometry::random_poses;
use stride_geometry::samples::{base_name, paper_range_deg};

#[test]
fn random_poses_are_seeded_and_within_paper_ranges() {
    let root = concat!(env!("CARGO_MANIFEST_DIR"), "/../../../shared/reference");
    let osim = format!("{root}/models/subject1_v2.osim");
    if !std::path::Path::new(&osim).exists() {
        eprintln!("skipping: {osim} not found");
        return;
    }
    let model = stride_model::osim::load_osim(std::path::Path::new(&osim)).unwrap();
    let a = random_poses(&model, 300, 42);
    assert_eq!(a, random_poses(&model, 300, 42));
    assert_ne!(a, random_poses(&model, 300, 43));
    assert_eq!(a.len(), 300);
    for (i, c) in model.coordinates.iter().enumerate() {
        let vals: Vec<f64> = (0..a.len()).map(|s| a.pose(s)[i]).collect();
        if c.name.starts_with("pelvis") {
            assert!(vals.iter().all(|&v| v == 0.0), "{}", c.name);
        } else if let Some([lo, hi]) = paper_range_deg(base_name(&c.name)) {
            let (lo, hi) = (lo.to_radians(), hi.to_radians());
            assert!(vals.iter().all(|&v| v >= lo && v <= hi), "{}", c.name);
            // Uniform draws cover most of the range.
            let min = vals.iter().cloned().fold(f64::INFINITY, f64::min);
            let max = vals.iter().cloned().fold(f64::NEG_INFINITY, f64::max);
            assert!(
                min < lo + 0.05 * (hi - lo) && max > hi - 0.05 * (hi - lo),
                "{}",
                c.name
            );
        }
        if let Some(b) = c.name.strip_suffix("_l") {
            let r = model.coordinate_index(&format!("{b}_r")).unwrap();
            if !c.locked {
                assert!(
                    (0..a.len()).all(|s| a.pose(s)[i] == a.pose(s)[r]),
                    "{}",
                    c.name
                );
            }
        }
    }
}
