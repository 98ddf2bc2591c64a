//! The fuzz targets: each takes arbitrary bytes, runs a reader on them and panics only when
//! a property the reader promises is broken (a reader's error is a normal outcome).

use std::path::Path;
use std::sync::OnceLock;
use stride_geometry::GeometryFile;
use stride_model::model_settings::ModelSettings;
use stride_model::storage::Storage;
use stride_model::Model;

/// A fuzzed reader.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Target {
    /// The OpenSim model reader (`stride_model::osim`).
    Osim,
    /// The storage reader (`.mot`/`.sto`), with a write/read round trip of what it accepts.
    Storage,
    /// The study file parser (`stride_study::spec`), expansion and validation included.
    Study,
    /// The model settings reader (`<model>.toml`), applied to the built-in model.
    ModelSettings,
    /// The fitted muscle-geometry reader (`stride model fit` output), applied to the
    /// shipped gait1018 model.
    Geometry,
}

impl Target {
    /// Every target.
    pub const ALL: [Target; 5] = [
        Target::Osim,
        Target::Storage,
        Target::Study,
        Target::ModelSettings,
        Target::Geometry,
    ];

    /// The target named `name` (`osim`, `storage`, `study`, `model_settings`, `geometry`).
    pub fn from_name(name: &str) -> Option<Target> {
        Self::ALL.into_iter().find(|t| t.name() == name)
    }

    /// Name used on the command line and as the corpus folder.
    pub fn name(self) -> &'static str {
        match self {
            Target::Osim => "osim",
            Target::Storage => "storage",
            Target::Study => "study",
            Target::ModelSettings => "model_settings",
            Target::Geometry => "geometry",
        }
    }

    /// Tokens worth inserting into this target's inputs.
    pub fn dictionary(self) -> &'static [&'static str] {
        match self {
            Target::Osim => &[
                "<",
                ">",
                "</",
                "/>",
                "<!--",
                "-->",
                "<![CDATA[",
                "]]>",
                "<?xml version=\"1.0\" encoding=\"ISO-8859-1\"?>",
                "<!DOCTYPE a [<!ENTITY e \"<b>x</b>\">]>",
                "&e;",
                "&amp;",
                "&#x41;",
                "\"",
                "'",
                "=",
                "<OpenSimDocument Version=\"40000\">",
                "<Model name=\"m\">",
                "<objects>",
                "</objects>",
                "<Body name=\"b\">",
                "<mass>",
                "</mass>",
                "nan",
                "inf",
                "-1e308",
                "0 0 0",
                "1e-320",
            ],
            Target::Storage => &[
                "endheader",
                "\n",
                "\t",
                " ",
                "nan",
                "-inf",
                "inf",
                "1e308",
                "-0",
                "nRows=",
                "nColumns=",
                "inDegrees=yes",
                "name ",
                "version=1",
                "time",
                "=",
                "1e-320",
                "0x1",
                "+",
                "-",
            ],
            Target::Study => &[
                "[study]",
                "[base]",
                "[grid]",
                "[[grid.conditions]]",
                "[study.solver]",
                "=",
                "\"",
                "[",
                "]",
                "{",
                "}",
                ",",
                "\n",
                "nan",
                "inf",
                "-1",
                "0",
                "1e9",
                "speed",
                "mesh_intervals",
                "guesses",
                "jobs",
                "threads_per_case",
                "max_iter",
                "tol",
                "name",
                "output",
                "continuation",
                "coordinate_bounds",
                "strength",
                "weights.metabolic",
                "1.33",
                "18446744073709551615",
            ],
            Target::ModelSettings => &[
                "[contact]",
                "[contact.parameters]",
                "[[contact.spheres]]",
                "[[passive_torques.table]]",
                "[[actuators]]",
                "[metabolic]",
                "[metabolic.muscles]",
                "[[distances]]",
                "[[coordinate_springs]]",
                "[[muscle_parameters]]",
                "[problem]",
                "=",
                "\"",
                "[",
                "]",
                "{",
                "}",
                ",",
                "\n",
                "nan",
                "inf",
                "-inf",
                "-5",
                "0",
                "1e300",
                "gravity",
                "geometry",
                "stiffness",
                "dissipation",
                "static_friction",
                "dynamic_friction",
                "transition_velocity",
                "radius",
                "name",
                "body",
                "location",
                "coordinate",
                "coordinates",
                "control_range",
                "optimal_force",
                "match",
                "calcn_r",
                "knee_angle_r",
                "soleus_r",
            ],
            Target::Geometry => &[
                "{",
                "}",
                "[",
                "]",
                ",",
                ":",
                "\"",
                "null",
                "true",
                "1e300",
                "-1",
                "0",
                "NaN",
                "\"format\": \"stride-muscle-geometry-1\"",
                "\"model_hash\"",
                "\"muscles\"",
                "\"coordinates\"",
                "\"path_polynomials\"",
                "\"exponents\"",
                "\"coefficients\"",
                "\"order\"",
                "\"accuracy\"",
                "\"ligaments\"",
                "\"hip_flexion_r\"",
                "\"soleus_r\"",
            ],
        }
    }

    /// Run the reader on `data`; panics when a promised property fails.
    pub fn run(self, data: &[u8]) {
        match self {
            Target::Osim => {
                let _ = stride_model::osim::parse_osim_bytes(data, "fuzz.osim");
            }
            Target::Storage => storage_round_trip(data),
            Target::Study => {
                let text = String::from_utf8_lossy(data);
                let _ = stride_study::spec::parse(&text, Path::new("fuzz.toml"));
            }
            Target::ModelSettings => model_settings(data),
            Target::Geometry => geometry(data),
        }
    }
}

/// The built-in model, imported once.
fn built_in() -> &'static Model {
    static MODEL: OnceLock<Model> = OnceLock::new();
    MODEL.get_or_init(stride_model::default_model::default_model)
}

/// The shipped gait1018 model without its geometry, imported once.
fn gait1018() -> &'static Model {
    static MODEL: OnceLock<Model> = OnceLock::new();
    MODEL.get_or_init(|| {
        let s = stride_model::shipped::shipped("gait1018").expect("gait1018 is shipped");
        stride_model::osim::parse_osim(s.osim, s.file_name).expect("gait1018 imports")
    })
}

/// Settings text is parsed and applied to the built-in model; settings that apply leave
/// every contact sphere with a positive radius and a checked contact law.
fn model_settings(data: &[u8]) {
    let text = String::from_utf8_lossy(data);
    let Ok(s) = ModelSettings::parse(&text, "fuzz.toml") else {
        return;
    };
    let mut m = built_in().clone();
    if s.apply(&mut m, "fuzz.toml").is_err() {
        return;
    }
    for c in &m.contacts {
        assert!(
            c.radius > 0.0,
            "sphere {} accepted with radius {}",
            c.name,
            c.radius
        );
        assert!(
            c.parameters.check().is_ok(),
            "sphere {} accepted with {:?}",
            c.name,
            c.parameters
        );
    }
}

/// A geometry file is parsed and applied to gait1018; a file that applies gives every
/// muscle a finite length at the default pose.
fn geometry(data: &[u8]) {
    let text = String::from_utf8_lossy(data);
    let Ok(file) = GeometryFile::parse(&text, "fuzz.json") else {
        return;
    };
    let mut m = gait1018().clone();
    if file.apply(&mut m).is_err() {
        return;
    }
    let q: Vec<f64> = m.coordinates.iter().map(|c| c.default_value).collect();
    for (muscle, p) in m.muscles.iter().zip(&m.path_polynomials) {
        if let Some(p) = p {
            let l = stride_geometry::polynomial_length(p, &q);
            assert!(
                l.is_finite(),
                "muscle {} has length {l} at the default pose",
                muscle.name
            );
        }
    }
}

/// A storage the reader accepts is written and read back to the same labels and values.
fn storage_round_trip(data: &[u8]) {
    let text = String::from_utf8_lossy(data);
    let Ok(s) = Storage::parse(&text, Path::new("fuzz.mot")) else {
        return;
    };
    let written = s.to_text().expect("an accepted storage can be written");
    let back = Storage::parse(&written, Path::new("fuzz.mot"))
        .unwrap_or_else(|e| panic!("a written storage does not read back: {e}"));
    assert_eq!(back.labels, s.labels, "labels changed in a round trip");
    assert_eq!(
        back.rows.len(),
        s.rows.len(),
        "rows changed in a round trip"
    );
    for (a, b) in s.rows.iter().zip(&back.rows) {
        for (x, y) in a.iter().zip(b) {
            assert!(
                x.to_bits() == y.to_bits() || (x.is_nan() && y.is_nan()),
                "value {x:?} read back as {y:?}"
            );
        }
    }
}
