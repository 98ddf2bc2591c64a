//! Fitted ligament lengths of the shipped `DHondt_et_al_2024_4seg` geometry file against
//! the ligaments' own path geometry (path points and wrapping) at 500 random poses drawn
//! with another seed than the fit's: the RMS error of each of the 26 ligaments, printed,
//! within 0.1 mm ([`LIGAMENT_TOLERANCE`]) with a margin for the new poses.

use stride_geometry::kinematics::{BodyPoses, Kinematics};
use stride_geometry::{
    polynomial_length, random_poses, GeometryFile, MusclePaths, LIGAMENT_TOLERANCE,
};

#[test]
fn dhondt2024_ligament_fits_match_their_path_geometry() {
    let s = stride_model::shipped::shipped("dhondt2024").unwrap();
    let mut model = stride_model::osim::parse_osim(s.osim, s.file_name).unwrap();
    GeometryFile::parse(s.geometry, "dhondt2024")
        .unwrap()
        .apply(&mut model)
        .unwrap();
    assert_eq!(model.ligaments.len(), 26);
    let kin = Kinematics::new(&model).unwrap();
    let paths = MusclePaths::ligaments(&model).unwrap();
    let mut poses = BodyPoses::new(kin.n_bodies());
    let samples = random_poses(&model, 500, 20261207);
    let mut sq = vec![0.0; model.ligaments.len()];
    for i in 0..samples.len() {
        let q = samples.pose(i);
        kin.forward(q, &mut poses);
        for (j, l) in model.ligaments.iter().enumerate() {
            let fit = polynomial_length(l.path_polynomial.as_ref().unwrap(), q);
            sq[j] += (fit - paths.length(j, q, &poses)).powi(2);
        }
    }
    let mut worst: f64 = 0.0;
    for (j, l) in model.ligaments.iter().enumerate() {
        let rmse = (sq[j] / samples.len() as f64).sqrt();
        let p = l.path_polynomial.as_ref().unwrap();
        let spanned: Vec<&str> = p
            .coordinates
            .iter()
            .map(|&c| model.coordinates[c].name.as_str())
            .collect();
        println!(
            "{:<34} order {} over {:<40} RMSE {:.4} mm",
            l.name,
            p.order,
            spanned.join(","),
            rmse * 1e3
        );
        worst = worst.max(rmse);
    }
    assert!(
        worst < 2.0 * LIGAMENT_TOLERANCE,
        "worst RMSE {:.4} mm",
        worst * 1e3
    );
}
