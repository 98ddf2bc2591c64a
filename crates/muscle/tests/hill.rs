//! Hill model tests: the soleus and vas_lat chains of FORMULATION A.2 (with the Bhargava
//! metabolic rate), an isometric equilibrium found independently by bisection, and
//! forward-mode derivatives against finite differences.

mod common;

use common::{assert_close, check_dual, hill_params, shared};
use stride_ad::Dual;
use stride_muscle::{hill_equilibrium, HillParams, MetabolicModel};

struct Chain {
    muscle: &'static str,
    inputs: [f64; 5],
    lm_norm: f64,
    vm: f64,
    fc: f64,
    fce: f64,
    fpe: f64,
    mass: f64,
    adot: f64,
    mdot: f64,
    sdot: f64,
    wdot: f64,
    edot: f64,
}

const CHAINS: [Chain; 2] = [
    Chain {
        muscle: "soleus_r",
        inputs: [0.5, 0.5, 1.0, 0.29, -0.05],
        lm_norm: 0.9550491,
        vm: -0.05306631,
        fc: -0.1693268,
        fce: 1259.911,
        fpe: 48.74963,
        mass: 0.2889231,
        adot: 8.779322,
        mdot: 13.36147,
        sdot: 23.07417,
        wdot: 49.67234,
        edot: 94.8873,
    },
    Chain {
        muscle: "vas_lat_r",
        inputs: [0.3, 0.4, -2.0, 0.25, -0.1],
        lm_norm: 1.044461,
        vm: -0.0858381,
        fc: -0.1545221,
        fce: 414.1134,
        fpe: 46.78329,
        mass: 0.3343434,
        adot: 5.403999,
        mdot: 7.640486,
        sdot: 13.48079,
        wdot: 30.13334,
        edot: 56.65862,
    },
];

#[test]
fn appendix_a2_chains() {
    let Some(sh) = shared() else { return };
    for c in &CHAINS {
        let p = hill_params(&sh, c.muscle);
        let [a, ft, dft, lmt, vmt] = c.inputs;
        let h = hill_equilibrium(&p, a, ft, dft, lmt, vmt);
        let m = c.muscle;
        let rel = 1e-6;
        assert_close(&format!("{m} l̃_M"), h.fiber_length_norm, c.lm_norm, rel);
        assert_close(&format!("{m} v_M"), h.fiber_velocity, c.vm, rel);
        assert_close(&format!("{m} f_c"), h.residual, c.fc, rel);
        assert_close(&format!("{m} F_CE"), h.active_fiber_force, c.fce, rel);
        assert_close(&format!("{m} F_PE"), h.passive_fiber_force, c.fpe, rel);
        assert_close(&format!("{m} mass"), h.mass, c.mass, rel);
        assert_close(
            &format!("{m} F_T"),
            h.tendon_force,
            ft * p.max_isometric_force(),
            1e-15,
        );
        let e = MetabolicModel::Bhargava2004.rate(&p, a, &h);
        assert_close(&format!("{m} Ȧ"), e.activation_heat, c.adot, rel);
        assert_close(&format!("{m} Ṁ"), e.maintenance_heat, c.mdot, rel);
        assert_close(&format!("{m} Ṡ"), e.shortening_heat, c.sdot, rel);
        assert_close(&format!("{m} Ẇ"), e.work_rate, c.wdot, rel);
        assert_close(&format!("{m} Ė"), e.total, c.edot, rel);
        // Heat is well above 1 W/kg here, so the floor adds (almost) nothing.
        assert!(e.heat_floor.abs() < 1e-9 * c.edot);
    }
}

/// Forward relations written out here, independently of the library: tendon force from
/// tendon length, fibre geometry from the tendon length, equilibrium force of the fibre.
fn isometric_mismatch(p: &HillParams, a: f64, lmt: f64, ft: f64) -> f64 {
    // Invert the tendon curve by its defining relation F = 0.2 exp(35 (l − 0.995)) − 0.25.
    let lt_norm = (5.0 * (ft + 0.25)).ln() / 35.0 + 0.995;
    let lt = lt_norm * p.tendon_slack_length();
    let h = p.optimal_fiber_length() * p.pennation_angle_at_optimal().sin();
    let lm = ((lmt - lt).powi(2) + h * h).sqrt();
    let x = lm / p.optimal_fiber_length();
    let cos_a = (lmt - lt) / lm;
    let b = [
        [
            0.8144834783430084,
            1.0550334289705745,
            0.16238457359957373,
            0.06330344846546464,
        ],
        [
            0.43300498439264734,
            0.7167754133977603,
            -0.029947116970695593,
            0.20035684729618783,
        ],
        [0.1, 1.0, 0.5 * 0.5_f64.sqrt(), 0.0],
    ];
    let fl: f64 = b
        .iter()
        .map(|r| r[0] * (-0.5 * (x - r[1]).powi(2) / (r[2] + r[3] * x).powi(2)).exp())
        .sum();
    // f_V(0) from the force–velocity constants.
    let e3 = -0.3741215086478631_f64;
    let fv0 = -0.31832343689912745 * (e3 + (e3 * e3 + 1.0).sqrt()).ln() + 0.8856440599150038;
    let fpe = ((4.0 * (x - 1.0) / 0.6).exp() - 1.0 + 0.9951720500061686) / 53.598150033144236;
    (a * fl * fv0 + fpe) * cos_a - ft
}

#[test]
fn residual_vanishes_at_independent_isometric_equilibrium() {
    let Some(sh) = shared() else { return };
    for (name, a, lmt) in [
        ("soleus_r", 0.5, 0.29),
        ("vas_lat_r", 0.3, 0.25),
        ("glut_med1_r", 0.8, 0.125),
        ("bifemsh_r", 0.05, 0.25),
    ] {
        let p = hill_params(&sh, name);
        // Bisection on F̃_T in (−0.2, 5]: the mismatch decreases with F̃_T.
        let (mut lo, mut hi) = (-0.2499, 5.0);
        assert!(
            isometric_mismatch(&p, a, lmt, lo) > 0.0,
            "{name}: bracket low"
        );
        assert!(
            isometric_mismatch(&p, a, lmt, hi) < 0.0,
            "{name}: bracket high"
        );
        for _ in 0..200 {
            let mid = 0.5 * (lo + hi);
            if isometric_mismatch(&p, a, lmt, mid) > 0.0 {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        let ft = 0.5 * (lo + hi);
        let h = hill_equilibrium(&p, a, ft, 0.0, lmt, 0.0);
        assert!(
            h.residual.abs() < 1e-12,
            "{name}: residual {} at F̃_T = {ft}",
            h.residual
        );
        assert_eq!(h.fiber_velocity, 0.0);
    }
}

#[test]
fn hill_and_bhargava_on_dual_numbers() {
    let Some(sh) = shared() else { return };
    for c in &CHAINS {
        let p = hill_params(&sh, c.muscle);
        for i in 0..5 {
            let x0 = c.inputs[i];
            let f64_inputs = |x: f64| {
                let mut v = c.inputs;
                v[i] = x;
                v
            };
            let f = |x: f64| {
                let [a, ft, dft, lmt, vmt] = f64_inputs(x);
                hill_equilibrium(&p, a, ft, dft, lmt, vmt).residual
            };
            let fd = |x: Dual| {
                let v = c.inputs.map(Dual::constant);
                let mut v = v;
                v[i] = x;
                hill_equilibrium(&p, v[0], v[1], v[2], v[3], v[4]).residual
            };
            check_dual(&format!("{} f_c d/dx{i}", c.muscle), f, fd, x0, 1e-6, 1e-7);
            for model in MetabolicModel::ALL {
                let g = |x: f64| {
                    let [a, ft, dft, lmt, vmt] = f64_inputs(x);
                    let h = hill_equilibrium(&p, a, ft, dft, lmt, vmt);
                    model.rate(&p, a, &h).total
                };
                let gd = |x: Dual| {
                    let mut v = c.inputs.map(Dual::constant);
                    v[i] = x;
                    let h = hill_equilibrium(&p, v[0], v[1], v[2], v[3], v[4]);
                    model.rate(&p, v[0], &h).total
                };
                check_dual(
                    &format!("{} {model:?} Ė d/dx{i}", c.muscle),
                    g,
                    gd,
                    x0,
                    1e-6,
                    1e-6,
                );
            }
        }
    }
}

#[test]
fn invalid_parameters_are_rejected_with_names() {
    let err = HillParams::new("bad_muscle", 100.0, -0.1, 0.2, 0.0, 10.0, 0.25e6, 0.5)
        .unwrap_err()
        .to_string();
    assert!(
        err.contains("bad_muscle") && err.contains("optimal_fiber_length"),
        "{err}"
    );
    let p = HillParams::new("m", 100.0, 0.1, 0.2, 0.0, 10.0, 0.25e6, 0.5).unwrap();
    assert!(p.clone().with_tendon_stiffness(f64::NAN).is_err());
    let doubled = p.with_max_contraction_velocity(20.0).unwrap();
    assert_close(
        "doubled v_max",
        doubled.max_contraction_velocity(),
        2.0,
        1e-15,
    );
}

/// Second derivatives (HyperDual, for exact Hessians) of the Hill residual and of every
/// metabolic model's total, against finite differences of the first derivative (Dual).
#[test]
fn second_derivatives_match_finite_differences_of_first() {
    use stride_ad::HyperDual;
    let Some(sh) = shared() else { return };
    let c = &CHAINS[0];
    let p = hill_params(&sh, c.muscle);
    let h = 1e-5;
    // Directions: activation (0), tendon force (1), l_MT (3), v_MT (4).
    for (i, j) in [(0, 1), (1, 3), (3, 4), (4, 4), (0, 0)] {
        for model in [
            None,
            Some(MetabolicModel::Bhargava2004),
            Some(MetabolicModel::Uchida2016),
        ] {
            let hyper = {
                let mut v = c.inputs.map(HyperDual::constant);
                v[i].e1 = 1.0;
                v[j].e2 = 1.0;
                let out = hill_equilibrium(&p, v[0], v[1], v[2], v[3], v[4]);
                match model {
                    None => out.residual,
                    Some(m) => m.rate(&p, v[0], &out).total,
                }
            };
            // d/dx_j of (d/dx_i f) by central differences of the Dual derivative.
            let first = |xj: f64| {
                let mut v = c.inputs.map(Dual::constant);
                v[i].eps = 1.0;
                v[j].re = xj;
                let out = hill_equilibrium(&p, v[0], v[1], v[2], v[3], v[4]);
                match model {
                    None => out.residual.eps,
                    Some(m) => m.rate(&p, v[0], &out).total.eps,
                }
            };
            let fd = (first(c.inputs[j] + h) - first(c.inputs[j] - h)) / (2.0 * h);
            let tol = 1e-5 * fd.abs().max(1.0);
            assert!(
                (hyper.e12 - fd).abs() <= tol,
                "{model:?} ∂²/∂x{i}∂x{j}: hyper-dual {} vs finite difference {fd}",
                hyper.e12
            );
        }
    }
}
