//! The standing pelvis height of a model: the pelvis height of the quasi-random initial
//! guess (FORMULATION 10.1). A model that carries one (the paper's 0.9385 m for the
//! built-in model, a settings file's `standing_pelvis_height`) uses it; any other model
//! gets PredSim's rule (`PreProcessing/get_IG_pelvis_y.m`, PREDSIM.md §7.5): in the
//! model's default pose, the height of the pelvis origin above the origin of the right
//! calcaneus, plus [`FOOT_CLEARANCE`].

use stride_model::Model;

/// Height of the calcaneus origin above the ground in PredSim's standing posture [m].
pub const FOOT_CLEARANCE: f64 = 0.025;

/// The body whose origin stands [`FOOT_CLEARANCE`] above the ground.
pub const FOOT_BODY: &str = "calcn_r";

/// Why a model's standing pelvis height cannot be derived.
#[derive(Debug, thiserror::Error)]
pub enum StandingError {
    /// The model has no right calcaneus.
    #[error("the model has no body `{FOOT_BODY}` to stand on")]
    NoFoot,
    /// The forward kinematics of the default pose failed.
    #[error("default pose: {0}")]
    Kinematics(String),
}

/// Standing pelvis height [m] of `model` whose pelvis (the body moved by the vertical
/// translation) is `pelvis`: the model's own value when it has one, else PredSim's rule
/// (module documentation).
pub fn standing_pelvis_height(model: &Model, pelvis: usize) -> Result<f64, StandingError> {
    match model.standing_pelvis_height {
        Some(h) => Ok(h),
        None => default_pose_pelvis_height(model, pelvis),
    }
}

/// Standing pelvis height [m] of `model` as [`standing_pelvis_height`], its pelvis the
/// body moved by the vertical translation of its gait view `gait`.
pub fn gait_standing_height(
    model: &Model,
    gait: &crate::gait::GaitModel,
) -> Result<f64, StandingError> {
    let ty = &gait.coordinates[gait.vertical_translation];
    let pelvis = model.joints[model.coordinates[ty.model_index].joint].child;
    standing_pelvis_height(model, pelvis)
}

/// PredSim's rule: pelvis origin height above the right calcaneus origin in the default
/// pose (every coordinate at its default value) [m], plus [`FOOT_CLEARANCE`].
pub fn default_pose_pelvis_height(model: &Model, pelvis: usize) -> Result<f64, StandingError> {
    let foot = model.body_index(FOOT_BODY).ok_or(StandingError::NoFoot)?;
    let err = |e: stride_multibody::MultibodyError| StandingError::Kinematics(e.to_string());
    let mut data = stride_multibody::Data::<f64>::new(model).map_err(err)?;
    let q: Vec<f64> = model.coordinates.iter().map(|c| c.default_value).collect();
    let v = vec![0.0; q.len()];
    stride_multibody::forward_kinematics(model, &mut data, &q, &v).map_err(err)?;
    Ok(data.position[pelvis][1] - data.position[foot][1] + FOOT_CLEARANCE)
}

#[cfg(test)]
mod tests {
    use super::*;
    use stride_model::shipped::shipped;

    fn model(name: &str) -> Model {
        let s = shipped(name).unwrap();
        stride_model::osim::parse_osim(s.osim, s.file_name).unwrap()
    }

    #[test]
    fn gait1018_stands_on_its_joint_offsets_as_written_in_its_osim_file() {
        // The vertical offsets of gait1018.osim from the pelvis down to the right
        // calcaneus, all joints at 0: hip_r in pelvis, knee_r in femur_r, ankle_r in
        // tibia_r, subtalar_r in talus_r; plus PredSim's 2.5 cm.
        let by_hand = 0.063_835_397_331_130_1
            + 0.396_907_245_921_447
            + 0.415_694_825_374_905
            + 0.038_339_127_654_237_4
            + 0.025;
        let m = model("gait1018");
        let pelvis = m.body_index("pelvis").unwrap();
        let h = standing_pelvis_height(&m, pelvis).unwrap();
        assert!((h - by_hand).abs() < 1e-12, "{h} vs {by_hand}");
    }

    #[test]
    fn falisse2022_gives_predsims_value_and_a_model_value_wins() {
        // PREDSIM.md §7.5: get_IG_pelvis_y gives 0.9397766 m for Falisse_et_al_2022.
        let mut m = model("falisse2022");
        let pelvis = m.body_index("pelvis").unwrap();
        let h = standing_pelvis_height(&m, pelvis).unwrap();
        assert!((h - 0.9397766).abs() < 5e-8, "{h}");
        m.standing_pelvis_height = Some(0.9385);
        assert_eq!(standing_pelvis_height(&m, pelvis).unwrap(), 0.9385);
        let c = m.body_index(FOOT_BODY).unwrap();
        m.bodies[c].name = "foot".into();
        m.standing_pelvis_height = None;
        let e = standing_pelvis_height(&m, pelvis).unwrap_err();
        assert!(e.to_string().contains("calcn_r"), "{e}");
    }
}
