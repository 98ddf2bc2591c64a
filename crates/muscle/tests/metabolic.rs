//! Metabolic model tests: the models differ only in the terms ESM Table S2 names, the
//! Bhargava non-negativity and 1 W/kg heat rules, the fixed v̄_max (July 2020), serde names.

mod common;

use common::{hill_params, shared};
use stride_muscle::{
    basal_metabolic_rate, hill_equilibrium, HillOutput, HillParams, MetabolicModel, MetabolicRate,
};
use MetabolicModel::*;

fn state(p: &HillParams, a: f64, ft: f64, dft: f64, lmt: f64, vmt: f64) -> HillOutput<f64> {
    hill_equilibrium(p, a, ft, dft, lmt, vmt)
}

fn rates(p: &HillParams, a: f64, h: &HillOutput<f64>) -> Vec<(MetabolicModel, MetabolicRate<f64>)> {
    MetabolicModel::ALL
        .iter()
        .map(|&m| (m, m.rate(p, a, h)))
        .collect()
}

fn get(r: &[(MetabolicModel, MetabolicRate<f64>)], m: MetabolicModel) -> MetabolicRate<f64> {
    r.iter().find(|(k, _)| *k == m).unwrap().1
}

fn same(what: &str, x: f64, y: f64) {
    assert!(
        (x - y).abs() <= 1e-12 * x.abs().max(y.abs()).max(1e-9),
        "{what}: {x} vs {y}"
    );
}

#[test]
fn parts_add_up_to_total() {
    let Some(sh) = shared() else { return };
    let p = hill_params(&sh, "soleus_r");
    for vmt in [-0.3, -0.05, 0.0, 0.1] {
        let h = state(&p, 0.4, 0.5, 0.0, 0.29, vmt);
        for (m, r) in rates(&p, 0.4, &h) {
            let sum = r.activation_heat
                + r.maintenance_heat
                + r.shortening_heat
                + r.heat_floor
                + r.work_rate;
            same(&format!("{m:?} total"), r.total, sum);
        }
    }
}

#[test]
fn isometric_umberger_family_identical_except_recruitment() {
    let Some(sh) = shared() else { return };
    let p = hill_params(&sh, "vas_lat_r");
    let h = state(&p, 0.3, 0.4, 0.0, 0.25, 0.0);
    assert_eq!(h.fiber_velocity, 0.0);
    let r = rates(&p, 0.3, &h);
    let u03 = get(&r, Umberger2003);
    for m in [
        Umberger2010,
        Umberger2010LengtheningHeat2003,
        Umberger2010NegativeWork2003,
    ] {
        let x = get(&r, m);
        same(&format!("{m:?} total"), x.total, u03.total);
        same(
            &format!("{m:?} activation"),
            x.activation_heat,
            u03.activation_heat,
        );
        assert_eq!(x.shortening_heat, 0.0);
        assert_eq!(x.work_rate, 0.0);
    }
    // Uchida differs only by the recruitment model (activation/maintenance heat).
    let uc = get(&r, Uchida2016);
    assert!((uc.activation_heat - u03.activation_heat).abs() > 1e-3);
    assert_eq!(uc.work_rate, 0.0);
}

#[test]
fn shortening_umberger_2003_2010_variants_agree() {
    let Some(sh) = shared() else { return };
    let p = hill_params(&sh, "soleus_r");
    // Fast shortening: v̄_M ≈ −6 l_opt/s, so the lengthening weight σ10(v̄_M) ≈ 1e-26.
    let h = state(&p, 0.6, 0.5, 0.0, 0.29, -0.3);
    assert!(h.fiber_velocity / p.optimal_fiber_length() < -3.0);
    let r = rates(&p, 0.6, &h);
    let u03 = get(&r, Umberger2003);
    assert!(u03.work_rate > 0.0 && u03.shortening_heat > 0.0);
    for m in [
        Umberger2010,
        Umberger2010LengtheningHeat2003,
        Umberger2010NegativeWork2003,
    ] {
        let x = get(&r, m);
        same(&format!("{m:?} work"), x.work_rate, u03.work_rate);
        same(
            &format!("{m:?} heat"),
            x.shortening_heat,
            u03.shortening_heat,
        );
        same(&format!("{m:?} total"), x.total, u03.total);
    }
}

#[test]
fn lengthening_terms_follow_table_s2() {
    let Some(sh) = shared() else { return };
    let p = hill_params(&sh, "soleus_r");
    // Lengthening: v̄_M ≈ +3 l_opt/s, shortening weight ≈ 1e-13.
    let h = state(&p, 0.6, 0.5, 0.0, 0.29, 0.2);
    assert!(h.fiber_velocity / p.optimal_fiber_length() > 2.0);
    let r = rates(&p, 0.6, &h);
    let (u03, u10, hl, neg, uc) = (
        get(&r, Umberger2003),
        get(&r, Umberger2010),
        get(&r, Umberger2010LengtheningHeat2003),
        get(&r, Umberger2010NegativeWork2003),
        get(&r, Uchida2016),
    );
    // Negative work: included in 2003, 2016, 2010_neg; excluded in 2010, 2010_hl, Bhargava.
    assert!(u03.work_rate < -1.0);
    same("2010_neg work = 2003 work", neg.work_rate, u03.work_rate);
    same("uchida work = 2003 work", uc.work_rate, u03.work_rate);
    assert!(u10.work_rate.abs() < 1e-9 * u03.work_rate.abs());
    assert!(hl.work_rate.abs() < 1e-9 * u03.work_rate.abs());
    // Bhargava suppresses negative work through σ10(v_M) with v_M in m/s (milder smoothing).
    let bh = get(&r, Bhargava2004).work_rate;
    let v = h.fiber_velocity;
    let n = 0.5 - 0.5 * (10.0 * v).tanh();
    same("Bhargava work", bh, -h.active_fiber_force * v * n);
    assert!(bh < 0.0 && bh > u03.work_rate, "{bh}");
    // Lengthening heat: f_U (α_L = 4 α_ST) in 2003 and 2010_hl, 3/40 f_U in 2010 and 2010_neg.
    same(
        "2010_hl heat = 2003 heat",
        hl.shortening_heat,
        u03.shortening_heat,
    );
    same(
        "2010_neg heat = 2010 heat",
        neg.shortening_heat,
        u10.shortening_heat,
    );
    let ratio = u10.shortening_heat / u03.shortening_heat;
    assert!((ratio - 0.3 / 4.0).abs() < 1e-9, "ratio {ratio}");
    // Activation/maintenance heat is common to the fixed-recruitment Umberger models.
    for x in [u10, hl, neg] {
        same("activation heat", x.activation_heat, u03.activation_heat);
    }
}

#[test]
fn umberger_uses_normalised_max_velocity_fixed_version() {
    let Some(sh) = shared() else { return };
    let p = hill_params(&sh, "soleus_r");
    let a = 1.0;
    let h = state(&p, a, 0.3, 0.0, 0.27, -0.3);
    let r = Umberger2003.rate(&p, a, &h);
    // Shortening heat per kg, from FORMULATION 7.2 with v̄_max = 10 s⁻¹ (not 10 l_opt):
    // α_ST = 100/(10/2.5) = 25, α_FT = 153/10 = 15.3, S = 1.5, A = a = 1.
    let sig = |x: f64| 0.5 + 0.5 * (10.0 * x).tanh();
    let vbar = h.fiber_velocity / p.optimal_fiber_length();
    let (pl, n) = (sig(vbar), 1.0 - sig(vbar));
    let f_st = p.slow_twitch_fraction();
    let d = sig(h.fiber_length_norm - 1.0);
    let h_sl = 4.0 * 25.0 * vbar * pl - (25.0 * f_st + 15.3 * (1.0 - f_st)) * vbar * n;
    let e_sl = h_sl * 1.5 * (a * pl + a * a * n) * ((1.0 - d) + h.force_length * d);
    same(
        "Umberger 2003 shortening heat [W]",
        r.shortening_heat,
        e_sl * p.mass(),
    );
    // Doubling v̄_max halves both shortening coefficients.
    let p2 = p.clone().with_max_contraction_velocity(20.0).unwrap();
    let h2 = state(&p2, a, 0.3, 0.0, 0.27, -0.3);
    let r2 = Umberger2003.rate(&p2, a, &h2);
    let vbar2 = h2.fiber_velocity / p2.optimal_fiber_length();
    let d2 = sig(h2.fiber_length_norm - 1.0);
    let (pl2, n2) = (sig(vbar2), 1.0 - sig(vbar2));
    let h_sl2 = 4.0 * 12.5 * vbar2 * pl2 - (12.5 * f_st + 7.65 * (1.0 - f_st)) * vbar2 * n2;
    let e_sl2 = h_sl2 * 1.5 * (a * pl2 + a * a * n2) * ((1.0 - d2) + h2.force_length * d2);
    same(
        "doubled v_max shortening heat",
        r2.shortening_heat,
        e_sl2 * p2.mass(),
    );
}

#[test]
fn bhargava_non_negative_and_heat_floor() {
    let Some(sh) = shared() else { return };
    for name in ["soleus_r", "vas_lat_r", "glut_med1_r", "ercspn_r"] {
        let p = hill_params(&sh, name);
        for a in [0.05, 0.3, 1.0] {
            for ft in [0.05, 0.5, 1.2] {
                for vmt in [-0.5, -0.05, 0.0, 0.05, 0.5] {
                    let lmt = p.tendon_slack_length() * 1.01 + p.optimal_fiber_length() * 0.9;
                    let h = state(&p, a, ft, 0.0, lmt, vmt);
                    let r = Bhargava2004.rate(&p, a, &h);
                    let heat =
                        r.activation_heat + r.maintenance_heat + r.shortening_heat + r.heat_floor;
                    // Smooth clamps: min of x σ10(x) is −0.0278, applied to the total in W
                    // and to the heat in W/kg, so the bounds hold up to that smoothing.
                    assert!(
                        r.total >= -0.028 * (1.0 + p.mass()),
                        "{name} a={a} ft={ft} v={vmt}: total {}",
                        r.total
                    );
                    assert!(
                        heat / p.mass() >= 0.97,
                        "{name}: heat {} W/kg",
                        heat / p.mass()
                    );
                    // Positive work only: lengthening work is (smoothly) suppressed.
                    let full = -h.active_fiber_force * h.fiber_velocity;
                    if full < 0.0 {
                        assert!(r.work_rate > full && r.work_rate <= 0.0);
                    } else {
                        assert!((0.0..=full).contains(&r.work_rate));
                    }
                }
            }
        }
    }
}

#[test]
fn basal_rate_and_serde_names() {
    assert!((basal_metabolic_rate(62.0) - 74.4).abs() < 1e-12);
    let names = [
        (Bhargava2004, "bhargava2004"),
        (Umberger2003, "umberger2003"),
        (Umberger2010, "umberger2010"),
        (Uchida2016, "uchida2016"),
        (Umberger2010LengtheningHeat2003, "umberger2010_hl"),
        (Umberger2010NegativeWork2003, "umberger2010_neg"),
    ];
    for (m, s) in names {
        assert_eq!(serde_json::to_string(&m).unwrap(), format!("\"{s}\""));
        let back: MetabolicModel = serde_json::from_str(&format!("\"{s}\"")).unwrap();
        assert_eq!(back, m);
    }
    assert!(serde_json::from_str::<MetabolicModel>("\"umberger2011\"").is_err());
}
