//! `ExpressionBasedCoordinateForce` in the dynamics: the generalised forces of the two-link
//! test model's expression force at its sample states equal OpenSim 4.6's (inverse
//! dynamics with and without the force, `tools/opensim_reference/components_models.py`),
//! and the AD types differentiate it.

use serde_json::Value;
use std::path::Path;
use stride_ad::{HyperDual, Scalar};
use stride_model::osim::load_osim;
use stride_multibody::elements::coordinate_force;

fn data_dir() -> std::path::PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../model/tests/data/opensim")
}

#[test]
fn expression_force_equals_opensims_generalised_forces() {
    let model = load_osim(&data_dir().join("two_link_components.osim")).unwrap();
    let text = std::fs::read_to_string(data_dir().join("two_link_components.json")).unwrap();
    let r: Value = serde_json::from_str(&text).unwrap();
    let f = &model.coordinate_forces[0];
    for s in r["samples"].as_array().unwrap() {
        let v = |k: &str, i: usize| s[k][i].as_f64().unwrap();
        for i in 0..model.coordinates.len() {
            let want = v("spring_generalised_forces", i);
            let got = if i == f.coordinate {
                coordinate_force(&f.law, v("q", i), v("u", i))
            } else {
                0.0
            };
            assert!(
                (got - want).abs() <= 1e-10 * want.abs().max(1.0),
                "{got} vs {want}"
            );
        }
        // ∂τ/∂q̇ = −2.5 for this law, whatever the state.
        let qd = HyperDual {
            re: v("u", f.coordinate),
            e1: 1.0,
            e2: 1.0,
            e12: 0.0,
        };
        let d = coordinate_force(&f.law, HyperDual::cst(v("q", f.coordinate)), qd);
        assert!((d.e1 + 2.5).abs() < 1e-12 && d.e12.abs() < 1e-12, "{d:?}");
    }
}
