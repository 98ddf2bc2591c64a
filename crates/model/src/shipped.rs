//! Models shipped with stride and usable by name (`stride predict --model falisse2022`):
//! each an OpenSim file with its settings file and fitted muscle geometry, embedded in the
//! program (`crates/model/data/models/<name>/`; attribution in the README there).

/// One shipped model.
#[derive(Clone, Copy, Debug)]
pub struct ShippedModel {
    /// Name used on the command line and in study files.
    pub name: &'static str,
    /// What the model is, in one line.
    pub description: &'static str,
    /// File name of its OpenSim model (written as `model.osim` into result folders).
    pub file_name: &'static str,
    /// The OpenSim model file.
    pub osim: &'static str,
    /// Its settings file (TOML, [`crate::model_settings::ModelSettings`]).
    pub settings: &'static str,
    /// Its fitted muscle geometry (`stride model fit --out`).
    pub geometry: &'static str,
}

macro_rules! shipped {
    ($name:literal, $stem:literal, $description:literal) => {
        ShippedModel {
            name: $name,
            description: $description,
            file_name: concat!($stem, ".osim"),
            osim: include_str!(concat!("../data/models/", $name, "/", $stem, ".osim")),
            settings: include_str!(concat!("../data/models/", $name, "/", $stem, ".toml")),
            geometry: include_str!(concat!(
                "../data/models/",
                $name,
                "/",
                $stem,
                ".geometry.json"
            )),
        }
    };
}

/// Every shipped model.
pub const SHIPPED: [ShippedModel; 4] = [
    shipped!(
        "subject1",
        "subject1_v2",
        "the built-in model: Falisse et al. 2019, 29 DOF (31 coordinates), 92 muscles, 8 arm actuators"
    ),
    shipped!(
        "falisse2022",
        "Falisse_et_al_2022",
        "Falisse et al. 2022 (PredSim default): subject1 with toes (mtp joints), 31 DOF, 92 muscles, 8 arm actuators"
    ),
    shipped!(
        "gait1018",
        "gait1018",
        "OpenSim gait10dof18musc, 2D: 10 DOF (planar), 18 muscles, 1 lumbar actuator"
    ),
    shipped!(
        "dhondt2024",
        "DHondt_et_al_2024_4seg",
        "D'Hondt et al. 2024: four-segment foot with ligaments, 33 DOF, 94 muscles, 8 arm actuators"
    ),
];

/// The shipped model of this name.
pub fn shipped(name: &str) -> Option<&'static ShippedModel> {
    SHIPPED.iter().find(|m| m.name == name)
}

/// The shipped model whose OpenSim file defines this model name (the `.osim` `Model`
/// element's name).
pub fn shipped_by_model_name(model_name: &str) -> Option<&'static ShippedModel> {
    SHIPPED.iter().find(|m| {
        m.osim
            .find("<Model name=\"")
            .map(|i| &m.osim[i + 13..])
            .and_then(|s| s.split('"').next())
            == Some(model_name)
    })
}
