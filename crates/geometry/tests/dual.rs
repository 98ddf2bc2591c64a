//! The path geometry is generic over the scalar: forward-mode dual numbers give the same
//! moment arms as the central finite differences, and the lengthening speed equals the
//! directional derivative of the length along q̇.

use stride_ad::Dual;
use stride_geometry::kinematics::{BodyPoses, Kinematics};
use stride_geometry::{
    lengthening_speed, poses_from_motion, MissingCoordinates, MusclePaths, PathGeometry,
};

#[test]
fn dual_moment_arms_and_speed_match_finite_differences() {
    let root = concat!(env!("CARGO_MANIFEST_DIR"), "/../../../shared/reference");
    let osim = format!("{root}/models/subject1_v2.osim");
    if !std::path::Path::new(&osim).exists() {
        eprintln!("skipping: {osim} not found");
        return;
    }
    let model = stride_model::osim::load_osim(std::path::Path::new(&osim)).unwrap();
    let poses = poses_from_motion(
        &model,
        std::path::Path::new(&format!("{root}/polynomial_fit_samples/dummy_motion.mot")),
        MissingCoordinates::Default,
    )
    .unwrap()
    .subsample(250, 20);
    let kin = Kinematics::new(&model).unwrap();
    let paths = MusclePaths::new(&model).unwrap();
    let mut geo = PathGeometry::new(&model).unwrap();
    let mut dposes = BodyPoses::<Dual>::new(kin.n_bodies());
    let nm = model.muscles.len();
    let coords: Vec<usize> = [
        "hip_flexion_r",
        "knee_angle_r",
        "ankle_angle_l",
        "lumbar_bending",
    ]
    .iter()
    .map(|n| model.coordinate_index(n).unwrap())
    .collect();
    let mut fd = vec![0.0; nm];
    let mut worst: f64 = 0.0;
    for s in 0..poses.len() {
        let q = poses.pose(s);
        for &c in &coords {
            geo.moment_arms_fd(q, c, &mut fd);
            let qd: Vec<Dual> = q
                .iter()
                .enumerate()
                .map(|(i, &v)| {
                    if i == c {
                        Dual::var(v)
                    } else {
                        Dual::constant(v)
                    }
                })
                .collect();
            kin.forward(&qd, &mut dposes);
            for (m, f) in fd.iter().enumerate() {
                let r = -paths.length(m, &qd, &dposes).eps;
                worst = worst.max((r - f).abs());
            }
        }
        // Lengthening speed along an arbitrary q̇ over the four coordinates.
        let qdot = [1.0, -2.0, 0.5, 3.0];
        let qd: Vec<Dual> = q
            .iter()
            .enumerate()
            .map(|(i, &v)| {
                let e = coords.iter().position(|&c| c == i).map_or(0.0, |k| qdot[k]);
                Dual::new(v, e)
            })
            .collect();
        kin.forward(&qd, &mut dposes);
        let m = model.muscle_index("rect_fem_r").unwrap();
        let v_dual = paths.length(m, &qd, &dposes).eps;
        let r: Vec<f64> = coords
            .iter()
            .map(|&c| {
                geo.moment_arms_fd(q, c, &mut fd);
                fd[m]
            })
            .collect();
        let v = lengthening_speed(&r, &qdot);
        assert!((v - v_dual).abs() < 1e-6, "pose {s}: {v} vs {v_dual}");
    }
    println!("largest |r_dual − r_fd| = {worst:.3e} m");
    assert!(worst < 1e-6, "largest moment-arm difference {worst} m");
}
