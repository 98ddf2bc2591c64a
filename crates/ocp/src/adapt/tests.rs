//! Tests of the adaptation against numbers written in the OpenSim files themselves (the
//! Scale tool's mesh scale factors, the joint offsets) and PredSim's tables. Skipped, with
//! the reason printed, when `../shared` (OpenSim's test models) is absent.

use super::*;
use std::path::PathBuf;
use stride_model::model_settings::ModelSettings;

/// OpenSim's test models (`shared/reference/models/opensim`), when present.
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

/// The six test models, by file.
const MODELS: [&str; 6] = [
    "gait2392_millard2012muscle.osim",
    "gait2392_pipeline/subject01_simbody.osim",
    "gait10dof18musc.osim",
    "Rajagopal2016.osim",
    "FullBodyModel_Hamner2010_v2_0.osim",
    "moco_example2DWalking/2D_gait.osim",
];

fn load(dir: &std::path::Path, file: &str) -> Model {
    stride_model::osim::load_osim(&dir.join(file)).unwrap()
}

fn falisse() -> Reference {
    Reference::shipped("falisse2022").unwrap()
}

/// The calcaneus mesh scale factor that OpenSim's Scale tool wrote into each file
/// (`<scale_factors>` of calcn_r's `foot.vtp`): falisse2022 0.9139243779317624 of the
/// generic gait2392 foot, OpenSim's scaled subject01 1.02708.
const FALISSE_FOOT_SCALE: f64 = 0.913_924_377_931_762_4;
const SUBJECT01_FOOT_SCALE: f64 = 1.02708;

/// Sphere `name` of the reference model, as (body, location, radius).
fn reference_sphere(r: &Reference, name: &str) -> (String, [f64; 3], f64) {
    let c = r.model.contacts.iter().find(|c| c.name == name).unwrap();
    (r.model.bodies[c.body].name.clone(), c.location, c.radius)
}

/// Each sphere of the adaptation is the reference's, on the same body, its centre and
/// radius multiplied by `factor` (the frames of the feet are parallel), the centre then
/// lifted by `lift(body)` [m] (the toes' spheres onto the plane of the heel's).
fn assert_scaled_copy(
    a: &Adaptation,
    r: &Reference,
    factor: f64,
    lift: impl Fn(&str) -> f64,
    tol: f64,
) {
    assert_eq!(a.spheres.len(), 12);
    for s in &a.spheres {
        let (body, loc, radius) = reference_sphere(r, &s.setting.name);
        assert_eq!(s.setting.body, body);
        for (k, (got, x)) in s.setting.location.iter().zip(loc).enumerate() {
            let up = if k == 1 { lift(&body) } else { 0.0 };
            let want = factor * x + up;
            assert!(
                (got - want).abs() < tol,
                "{} {k}: {got} vs {want}",
                s.setting.name
            );
        }
        assert!((s.setting.radius - factor * radius).abs() < tol);
    }
}

#[test]
fn the_generic_gait2392_foot_is_the_falisse2022_foot_unscaled_by_the_scale_tool() {
    let Some(dir) = opensim_models() else { return };
    let r = falisse();
    let a = adapt(&load(&dir, MODELS[0]), &r).unwrap();
    // foot length from the mtp joint offsets of the two files
    let gait2392 = [0.1788f64, -0.002, 0.00108];
    let reference = [
        0.163_409_678_774_199_1,
        -0.001_827_848_755_863_524_7,
        0.000_987_038_328_166_303_4,
    ];
    let norm = |v: [f64; 3]| v.iter().map(|x| x * x).sum::<f64>().sqrt();
    let by_joints = norm(gait2392) / norm(reference);
    for f in &a.feet {
        assert!((f.factor - by_joints).abs() < 1e-12, "{f:?}");
        assert!((f.factor - 1.0 / FALISSE_FOOT_SCALE).abs() < 1e-6, "{f:?}");
    }
    // the toes' origin is 2 mm below the heel's (mtp offset y = −0.002): their spheres
    // are lifted by as much
    let lift = |b: &str| if b.starts_with("toes") { 0.002 } else { 0.0 };
    assert_scaled_copy(&a, &r, by_joints, lift, 1e-12);
}

#[test]
fn the_scaled_subject_gets_spheres_scaled_by_its_foot_scale_factor() {
    let Some(dir) = opensim_models() else { return };
    let r = falisse();
    let a = adapt(&load(&dir, MODELS[1]), &r).unwrap();
    let factor = SUBJECT01_FOOT_SCALE / FALISSE_FOOT_SCALE;
    for f in &a.feet {
        // the file's scale factors carry six digits
        assert!((f.factor - factor).abs() < 2e-5, "{f:?} vs {factor}");
    }
    // subject01's toes origin: mtp offset y = −0.00205417 m
    let lift = |b: &str| {
        if b.starts_with("toes") {
            0.002_054_17
        } else {
            0.0
        }
    };
    assert_scaled_copy(&a, &r, a.feet[0].factor, lift, 1e-7);
}

#[test]
fn the_spheres_touch_a_flat_ground_together_in_the_default_pose() {
    let Some(dir) = opensim_models() else { return };
    let r = falisse();
    for file in MODELS {
        let m = load(&dir, file);
        let a = adapt(&m, &r).unwrap();
        let pose = DefaultPose::of(&m).unwrap();
        // a model with its own contact keeps it as its authors placed it (Moco's 2D_gait
        // stands on its heel spheres with the toe spheres 6 mm up): only adapted spheres
        // are checked
        if a.spheres.is_empty() {
            assert!(
                !m.contacts.is_empty(),
                "{file}: neither own nor adapted spheres"
            );
            continue;
        }
        let spheres = a.settings.contact.spheres.clone();
        let bottoms = sphere_bottoms(&m, &pose, &spheres);
        assert_eq!(bottoms.len(), spheres.len(), "{file}");
        // stand the model so that its lowest sphere touches y = 0
        let low = bottoms.iter().copied().fold(f64::INFINITY, f64::min);
        for (s, b) in spheres.iter().zip(&bottoms) {
            assert!(
                b - low < 1e-3,
                "{file}: {} is {:.2} mm above the ground",
                s.name,
                (b - low) * 1e3
            );
        }
        assert!(a.bottom_spread < 1e-3, "{file}");
    }
}

#[test]
fn toes_in_a_rotated_frame_keep_their_place_on_the_foot() {
    // Rajagopal's toes frame is turned (mtp offset orientation −π, 0.62, 0 rad): the
    // toe spheres sit where the reference's are, relative to the heel.
    let Some(dir) = opensim_models() else { return };
    let r = falisse();
    let m = load(&dir, "Rajagopal2016.osim");
    let a = adapt(&m, &r).unwrap();
    let pose = DefaultPose::of(&m).unwrap();
    let rpose = DefaultPose::of(&r.model).unwrap();
    let heel = m.body_index("calcn_r").unwrap();
    let rheel = r.model.body_index("calcn_r").unwrap();
    for s in a
        .spheres
        .iter()
        .filter(|s| s.setting.name == "s5_r" || s.setting.name == "s6_r")
    {
        assert_eq!(s.setting.body, "toes_r");
        let b = m.body_index(&s.setting.body).unwrap();
        let here = pose.to_body(heel, pose.to_ground(b, s.setting.location));
        let c = r
            .model
            .contacts
            .iter()
            .find(|c| c.name == s.setting.name)
            .unwrap();
        let there = rpose.to_body(rheel, rpose.to_ground(c.body, c.location));
        for (a, b) in here.iter().zip(there) {
            assert!((a - s.factor * b).abs() < 1e-9, "{}", s.setting.name);
        }
    }
}

#[test]
fn coordinates_no_muscle_crosses_get_predsims_torque_actuators() {
    let Some(dir) = opensim_models() else { return };
    let r = falisse();
    let names = |a: &Adaptation| -> Vec<String> {
        a.settings
            .actuators
            .iter()
            .map(|x| x.coordinate.clone())
            .collect()
    };
    // gait2392: every free coordinate is crossed by a muscle (the trunk has erector spinae
    // and obliques)
    let a = adapt(&load(&dir, MODELS[0]), &r).unwrap();
    assert!(names(&a).is_empty(), "{:?}", names(&a));
    // gait10dof18musc: no muscle on the lumbar joint
    let a = adapt(&load(&dir, MODELS[2]), &r).unwrap();
    assert_eq!(names(&a), ["lumbar_extension"]);
    // Hamner: the arms, without muscles; wrists are locked
    let a = adapt(&load(&dir, MODELS[4]), &r).unwrap();
    let mut want = Vec::new();
    for side in ["r", "l"] {
        for c in ["arm_flex", "arm_add", "arm_rot", "elbow_flex", "pro_sup"] {
            want.push(format!("{c}_{side}"));
        }
    }
    assert_eq!(names(&a), want);
    for x in &a.settings.actuators {
        assert_eq!(x.optimal_force, 150.0);
        assert_eq!(x.activation_time_constant, Some(0.035));
    }
}

#[test]
fn passive_torques_are_predsims_by_name_and_skip_locked_coordinates() {
    let Some(dir) = opensim_models() else { return };
    let m = load(&dir, MODELS[4]);
    let a = adapt(&m, &falisse()).unwrap();
    let entry = |name: &str| {
        a.settings
            .passive_torques
            .table
            .iter()
            .find(|e| e.coordinates.iter().any(|c| c == name))
    };
    // FORMULATION 6.1's knee row
    let knee = entry("knee_angle_l").unwrap();
    assert_eq!(knee.k, [-6.09, 33.94, 11.03, -11.33]);
    assert_eq!(knee.theta, [-2.4, 0.13]);
    assert_eq!(knee.damping, 0.1);
    assert!(knee.coordinates.contains(&"knee_angle_r".to_string()));
    // an arm: damping only
    let arm = entry("arm_flex_r").unwrap();
    assert_eq!((arm.k, arm.damping), ([0.0; 4], 0.1));
    // locked (subtalar, mtp, wrists) and the pelvis: none
    for c in [
        "subtalar_angle_r",
        "mtp_angle_l",
        "wrist_flex_r",
        "pelvis_ty",
    ] {
        assert!(entry(c).is_none(), "{c}");
    }
}

#[test]
fn the_written_file_reads_back_as_the_settings_and_makes_the_model_walkable() {
    let Some(dir) = opensim_models() else { return };
    let r = falisse();
    for file in MODELS {
        let m = load(&dir, file);
        let a = adapt(&m, &r).unwrap();
        let text = a.text(&m, file);
        let mut back = ModelSettings::parse(&text, file).unwrap();
        back.problem_lines.clear();
        assert_eq!(back, a.settings, "{file}");
        let mut adapted = m.clone();
        back.apply(&mut adapted, file).unwrap();
        assert!(
            reasons(&adapted).is_empty(),
            "{file}: {:?}",
            reasons(&adapted)
        );
        crate::model_defaults::ModelProblemDefaults::new(&back, file).unwrap();
    }
}

#[test]
fn a_shipped_model_needs_no_adaptation_and_a_bare_import_does() {
    let r = falisse();
    assert!(reasons(&r.model).is_empty());
    let s = stride_model::shipped::shipped("falisse2022").unwrap();
    let mut bare = stride_model::osim::parse_osim(s.osim, s.file_name).unwrap();
    bare.contacts.clear();
    assert_eq!(reasons(&bare), ["no foot contact spheres"]);
    // PredSim's own adaptation of its model: the arms get 150 N m actuators
    bare.actuators.clear();
    let a = adapt(&bare, &r).unwrap();
    let arms: Vec<&str> = a
        .settings
        .actuators
        .iter()
        .map(|x| x.coordinate.as_str())
        .collect();
    assert_eq!(arms.len(), 8, "{arms:?}");
    assert!(arms
        .iter()
        .all(|c| c.starts_with("arm_") || c.starts_with("elbow_")));
    // and the same spheres as its .osim file, unscaled
    for f in &a.feet {
        assert_eq!(f.factor, 1.0);
    }
    // the reference's toes hang 1.83 mm below its heel (mtp offset y)
    let lift = |b: &str| {
        if b.starts_with("toes") {
            0.001_827_848_755_863_524_7
        } else {
            0.0
        }
    };
    assert_scaled_copy(&a, &r, 1.0, lift, 1e-12);
    assert!(Reference::shipped("nope").is_err());
}
