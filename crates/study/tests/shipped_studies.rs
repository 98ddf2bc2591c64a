//! Every shipped study file parses, validates, and expands to the number of simulations of
//! its family in ESM Table S3 (FORMULATION 13.1), or the count its header comment gives for
//! the studies beyond the paper (contact models, the toes model, the four-segment foot
//! model).

use std::path::PathBuf;
use stride_study::spec;

fn studies_dir() -> PathBuf {
    PathBuf::from(concat!(env!("CARGO_MANIFEST_DIR"), "/../../studies"))
}

#[test]
fn shipped_study_files_expand_to_table_s3_counts() {
    // (file, cases): Table S3 counts; the speed sweeps also hold the cases Table S3 counts
    // elsewhere or lists as failed (see the comments in the files); the weakness,
    // co-contraction, cost-function and metabolic-model families add their nominal
    // reference (2 guesses).
    let expected = [
        ("nominal.toml", 2),
        ("cost_functions.toml", 5 * 2 + 2),
        ("weak_hip.toml", 6 + 2),
        ("weak_plantarflexors.toml", 6 + 2),
        ("metabolic_models.toml", 10 + 2),
        ("co_contraction.toml", 6 + 2),
        ("speeds.toml", 99 + 2 + 2),
        ("speeds_vmax2.toml", 52 + 1),
        ("mesh100.toml", 2),
        ("prosthesis.toml", 2),
        ("contact_models.toml", 2 + 2),
        ("falisse2022_nominal.toml", 2),
        ("falisse2022_speeds.toml", 41),
        ("dhondt2024_nominal.toml", 1),
    ];
    let mut found: Vec<String> = std::fs::read_dir(studies_dir())
        .unwrap()
        .flatten()
        .map(|e| e.file_name().to_string_lossy().to_string())
        .filter(|n| n.ends_with(".toml"))
        .collect();
    found.sort();
    let mut listed: Vec<String> = expected.iter().map(|e| e.0.to_string()).collect();
    listed.sort();
    assert_eq!(found, listed, "every shipped study has an expected count");
    for (file, n) in expected {
        let study = spec::load(&studies_dir().join(file)).unwrap_or_else(|e| panic!("{e}"));
        assert_eq!(study.cases.len(), n, "{file}");
        let mut names: Vec<&str> = study.cases.iter().map(|c| c.name.as_str()).collect();
        names.sort();
        names.dedup();
        assert_eq!(names.len(), n, "{file}: case names are unique");
        for c in &study.cases {
            c.settings.validate().unwrap();
            assert!(c.sources.iter().all(|&s| s < study.cases.len()));
        }
    }
}

#[test]
fn shipped_families_set_the_published_values() {
    let load = |f: &str| spec::load(&studies_dir().join(f)).unwrap();
    let s = load("weak_hip.toml");
    let scales: Vec<f64> = s
        .cases
        .iter()
        .map(|c| c.settings.strength.first().map_or(1.0, |s| s.scale))
        .collect();
    for v in [0.5, 0.25, 0.1] {
        assert!(scales.contains(&v));
    }
    // Each weakness and co-contraction family has exactly one reference group: the
    // settings of its [base], i.e. the nominal case.
    for f in [
        "weak_hip.toml",
        "weak_plantarflexors.toml",
        "co_contraction.toml",
    ] {
        let s = load(f);
        let reference: Vec<&str> = s
            .cases
            .iter()
            .filter(|c| c.settings == s.base)
            .map(|c| c.group.as_str())
            .collect();
        assert_eq!(reference.len(), 2, "{f}: {reference:?}");
        assert_eq!(reference[0], reference[1], "{f}");
        assert_eq!(
            s.base,
            stride_ocp::settings::ProblemSettings::default(),
            "{f}"
        );
    }
    let s = load("speeds_vmax2.toml");
    assert!(s
        .cases
        .iter()
        .all(|c| c.settings.max_contraction_velocity == 20.0));
    let s = load("cost_functions.toml");
    let c = s
        .cases
        .iter()
        .find(|c| c.group == "metabolic_not_squared")
        .unwrap();
    assert_eq!(c.settings.metabolic_exponent, 1.0);
    assert_eq!(c.settings.weights.metabolic, 1000.0);
    assert_eq!(c.settings.weights.activation, 2000.0, "other weights kept");
    let s = load("prosthesis.toml");
    assert!(s
        .cases
        .iter()
        .all(|c| c.settings.prosthesis.is_some() && c.settings.mesh_intervals == 100));
    // The calibrated-contact cases read the shipped geometry (relative to the repository
    // root); the generic ones are the nominal settings.
    let s = load("contact_models.toml");
    for c in &s.cases {
        match &c.settings.contact_geometry {
            Some(p) => assert!(studies_dir().join("..").join(p).exists(), "{p:?}"),
            None => assert_eq!(c.settings, s.base),
        }
    }
    assert_eq!(
        s.cases
            .iter()
            .filter(|c| c.settings.contact_geometry.is_some())
            .count(),
        2
    );
    let s = load("speeds.toml");
    // The 1.33 anchor has only the three standard guesses.
    assert_eq!(
        s.cases.iter().filter(|c| c.group == "speed_1.33").count(),
        3
    );
}
