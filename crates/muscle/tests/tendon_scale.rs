//! Per-muscle tendon stiffness of the shipped gait1018 settings (PredSim's
//! `tendon_stiff_scale` 0.5 for soleus and gastroc): k_T = 17.5 with the recomputed curve
//! shift, the normalised tendon force checked against the closed form of
//! PREDSIM.md §3.4 / FORMULATION 3.2 evaluated here.

use stride_model::model_settings::ModelSettings;
use stride_model::osim::parse_osim;
use stride_model::shipped::shipped;
use stride_muscle::curves::tendon_force;
use stride_muscle::HillParams;

/// Closed form: F̃_T = e^{k_T (l̃_T − 0.995)}/5 − 0.25 + s_T, s_T = (e^{35·0.005} − e^{k_T·0.005})/5.
fn closed_form(lt: f64, k_t: f64) -> f64 {
    let shift = ((35.0f64 * 0.005).exp() - (k_t * 0.005).exp()) / 5.0;
    (k_t * (lt - 0.995)).exp() / 5.0 - 0.25 + shift
}

fn model(name: &str) -> stride_model::model::Model {
    let m = shipped(name).unwrap();
    let mut model = parse_osim(m.osim, m.file_name).unwrap();
    ModelSettings::parse(m.settings, name)
        .unwrap()
        .apply(&mut model, name)
        .unwrap();
    model
}

#[test]
fn calf_tendons_of_dhondt_have_half_stiffness() {
    let model = model("dhondt2024");
    let half: Vec<&str> = model
        .muscles
        .iter()
        .filter(|m| HillParams::from_muscle(m).unwrap().tendon_stiffness() == 17.5)
        .map(|m| m.name.as_str())
        .collect();
    let want = [
        "lat_gas_r",
        "med_gas_r",
        "soleus_r",
        "lat_gas_l",
        "med_gas_l",
        "soleus_l",
    ];
    assert_eq!(half.len(), want.len(), "{half:?}");
    assert!(want.iter().all(|w| half.contains(w)), "{half:?}");
}

#[test]
fn calf_tendons_of_gait1018_have_half_stiffness() {
    let model = model("gait1018");
    for muscle in &model.muscles {
        let h = HillParams::from_muscle(muscle).unwrap();
        let calf = muscle.name.contains("soleus") || muscle.name.contains("gastroc");
        let want = if calf { 17.5 } else { 35.0 };
        assert_eq!(h.tendon_stiffness(), want, "{}", muscle.name);
        if !calf {
            assert_eq!(h.tendon_shift(), 0.0, "{}", muscle.name);
            continue;
        }
        // PREDSIM.md §3.4: s = 0.5 gives s_T = 0.0199608.
        assert!(
            (h.tendon_shift() - 0.0199608).abs() < 5e-8,
            "{}",
            h.tendon_shift()
        );
        for (strain, by_hand) in [
            (0.0, 0.2 * (17.5f64 * 0.005).exp() - 0.25 + 0.0199608),
            (0.02, 0.2 * (17.5f64 * 0.025).exp() - 0.25 + 0.0199608),
            (0.04, 0.2 * (17.5f64 * 0.045).exp() - 0.25 + 0.0199608),
            (0.06, 0.2 * (17.5f64 * 0.065).exp() - 0.25 + 0.0199608),
        ] {
            let lt = 1.0 + strain;
            let f = tendon_force(lt, h.tendon_stiffness(), h.tendon_shift());
            assert!((f - closed_form(lt, 17.5)).abs() < 1e-12, "{lt}: {f}");
            assert!((f - by_hand).abs() < 1e-7, "{lt}: {f} vs {by_hand}");
        }
    }
    // The shift keeps the force at l̃_T = 1 on the k_T = 35 curve.
    assert!((closed_form(1.0, 17.5) - closed_form(1.0, 35.0)).abs() < 1e-15);
}
