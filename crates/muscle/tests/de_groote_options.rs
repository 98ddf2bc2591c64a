//! The options of OpenSim's `DeGrooteFregly2016Muscle` that stride models, from an `.osim`
//! file to the Hill equilibrium: `active_force_width_scale` widens the active
//! force–length curve exactly as OpenSim 4.6 does (`tests/data/de_groote_options.json`,
//! written by `tools/opensim_reference/de_groote_options.py`) and
//! `ignore_passive_fiber_force` removes the passive fibre force.

use serde_json::Value;
use std::path::Path;
use stride_model::osim::parse_osim;
use stride_muscle::curves::tendon_length;
use stride_muscle::{hill_equilibrium, HillOutput, HillParams};

fn reference() -> Value {
    let p = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/de_groote_options.json");
    serde_json::from_str(&std::fs::read_to_string(p).unwrap()).unwrap()
}

/// The muscles of the two-link test model, with `options` added to each muscle.
fn muscles(options: &str) -> Vec<HillParams> {
    let p = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../model/tests/data/opensim/two_link_components.osim");
    let text = std::fs::read_to_string(p).unwrap().replace(
        "<max_isometric_force>",
        &format!("{options}<max_isometric_force>"),
    );
    let model = parse_osim(&text, "two_link_components.osim").unwrap();
    stride_muscle::hill_params_from_model(&model).unwrap()
}

/// The Hill equilibrium of a muscle without pennation held at l̃_M = `lm`, fully active
/// and isometric.
fn at(p: &HillParams, lm: f64) -> HillOutput<f64> {
    let ft = 0.3;
    let l_ts = 0.2;
    let lt = tendon_length(ft, p.tendon_stiffness(), p.tendon_shift()) * l_ts;
    let h = hill_equilibrium(p, 1.0, ft, 0.0, lt + lm * 0.1, 0.0);
    assert!((h.fiber_length_norm - lm).abs() < 1e-12);
    h
}

#[test]
fn active_width_and_passive_force_options_are_opensims() {
    let r = reference();
    let xs = r["normalized_fiber_length"].as_array().unwrap();
    let plain = muscles("");
    let wide = muscles(
        "<active_force_width_scale>1.4</active_force_width_scale>\
         <ignore_passive_fiber_force>true</ignore_passive_fiber_force>",
    );
    for (k, x) in xs.iter().enumerate() {
        let x = x.as_f64().unwrap();
        // stride's Gaussians are the paper's (peak 0.99943 at l̃ = 1); OpenSim 4.6 rescaled
        // its coefficients to a peak of 1, so the curves differ by up to 0.06 %, far less
        // than the widening (0.035 → 0.334 at l̃ = 0.45).
        for (params, key) in [
            (&plain, "active_force_length"),
            (&wide, "active_force_length_wide"),
        ] {
            let want = r[key][k].as_f64().unwrap();
            for p in params {
                let got = at(p, x).force_length;
                assert!(
                    (got - want).abs() < 7e-4 * want,
                    "{key} at {x}: {got} vs {want}"
                );
            }
        }
        for p in &plain {
            assert!(at(p, x).passive_fiber_force > 0.0);
        }
        for p in &wide {
            assert_eq!(at(p, x).passive_fiber_force, 0.0);
        }
    }
}

#[test]
fn active_width_below_one_is_an_error() {
    let p = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../model/tests/data/opensim/two_link_components.osim");
    let text = std::fs::read_to_string(p).unwrap().replacen(
        "<max_isometric_force>",
        "<active_force_width_scale>0.8</active_force_width_scale><max_isometric_force>",
        1,
    );
    let e = parse_osim(&text, "m.osim").unwrap_err().to_string();
    assert!(
        e.contains("active_force_width_scale") && e.contains("at least 1"),
        "{e}"
    );
}
