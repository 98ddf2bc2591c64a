//! PredSim's passive fibre curve shift λ and exponent scale κ (PREDSIM.md §3.4):
//! f_PE = (exp(4κ(l̃_M − λ)/0.6) − 1 − p1)/p2 with the unchanged p1 = −0.99517,
//! p2 = 53.598, checked in the Hill equilibrium against values worked out by hand, and the
//! shipped D'Hondt settings (λ = 0.9 for the shank and foot muscles, metabolic b = 100).

use stride_model::model_settings::ModelSettings;
use stride_model::osim::parse_osim;
use stride_model::shipped::shipped;
use stride_muscle::curves::tendon_length;
use stride_muscle::{hill_equilibrium, HillParams};

/// Passive fibre force [N] of a 1000 N muscle without pennation held at l̃_M = `lm`, at
/// rest (a = 0, no lengthening), with shift `shift` and scale `scale`.
fn passive_force(lm: f64, shift: f64, scale: f64) -> f64 {
    let p = HillParams::new("m", 1000.0, 0.1, 0.2, 0.0, 10.0, 0.25e6, 0.5)
        .unwrap()
        .with_passive_fibre(shift, scale)
        .unwrap();
    let ft = 0.3;
    let lt = tendon_length(ft, p.tendon_stiffness(), p.tendon_shift()) * 0.2;
    let h = hill_equilibrium(&p, 0.0, ft, 0.0, lt + lm * 0.1, 0.0);
    assert!((h.fiber_length_norm - lm).abs() < 1e-12);
    h.passive_fiber_force
}

#[test]
fn shifted_passive_fibre_force_matches_the_formula_by_hand() {
    // λ = 1, κ = 1 at l̃ = 1.1: (e^{0.666667} − 1 + 0.99517)/53.598 = 1.942904/53.598
    assert!((passive_force(1.1, 1.0, 1.0) - 36.2495).abs() < 1e-3);
    // λ = 0.9 shifts the curve by 0.1: the same force at l̃ = 1.0
    let f = passive_force(1.0, 0.9, 1.0);
    assert!((f - 36.2495).abs() < 1e-3, "{f}");
    assert!((f - passive_force(1.1, 1.0, 1.0)).abs() < 1e-9);
    // κ = 1.5 at l̃ = 1.1, λ = 1: (e^{1.0} − 0.00483)/53.598 = 2.713452/53.598
    let f = passive_force(1.1, 1.0, 1.5);
    assert!((f - 50.6260).abs() < 1e-3, "{f}");
    // at l̃ = λ: (e^0 − 1 + 0.99517)/53.598 = 0.0185672 F_max, whatever λ
    let f = passive_force(0.9, 0.9, 1.0);
    assert!((f - 18.5672).abs() < 1e-3, "{f}");
    assert!((f - passive_force(1.0, 1.0, 1.0)).abs() < 1e-9);
}

#[test]
fn dhondt_shank_and_foot_muscles_have_predsims_shift_and_smoothing() {
    let m = shipped("dhondt2024").unwrap();
    let mut model = parse_osim(m.osim, m.file_name).unwrap();
    ModelSettings::parse(m.settings, "dhondt2024")
        .unwrap()
        .apply(&mut model, "dhondt2024")
        .unwrap();
    let keys = ["soleus", "_gas", "per_", "tib_", "_dig_", "_hal_", "FDB"];
    let mut shifted = 0;
    for muscle in &model.muscles {
        let want = if keys.iter().any(|k| muscle.name.contains(k)) {
            shifted += 1;
            0.9
        } else {
            1.0
        };
        assert_eq!(muscle.passive_fibre_shift, want, "{}", muscle.name);
        assert_eq!(muscle.passive_fibre_scale, 1.0);
        let h = HillParams::from_muscle(muscle).unwrap();
        assert_eq!(h.metabolic_smoothing(), 100.0);
    }
    // per leg: soleus, 2 gastrocnemii, 3 peronei, 2 tibiales, 2 digit and 2 hallux
    // muscles, FDB
    assert_eq!(shifted, 2 * 13, "{shifted}");
}
