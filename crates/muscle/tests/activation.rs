//! Activation dynamics, arm actuators and passive torques against FORMULATION 2, 6, A.2
//! and hand-computed values from joints/passive_moments.json.

mod common;

use common::{check_dual, shared};
use stride_ad::Dual;
use stride_model::PassiveJointTorque;
use stride_muscle::activation::*;
use stride_muscle::passive::{arm_damping_torque, passive_torque, passive_torques};

#[test]
fn constraint_range_at_baseline_activation() {
    let act = ActivationDynamics::default();
    let [lo, hi] = act.rate_range(0.05);
    // A.2: ȧ ∈ [−0.8333, 63.333] s⁻¹ at a = 0.05.
    assert!((lo - (-0.8333)).abs() < 5e-5, "{lo}");
    assert!((hi - 63.333).abs() < 5e-4, "{hi}");
    // The constraint values sit exactly on their bounds at the ends of that range.
    let [[l0, u0], [l1, u1]] = act.constraint_bounds();
    assert_eq!(u0, f64::INFINITY);
    assert_eq!(l1, f64::NEG_INFINITY);
    let c_lo = act.constraints(0.05, lo);
    let c_hi = act.constraints(0.05, hi);
    assert!((c_lo[0] - l0).abs() < 1e-12);
    assert!((c_hi[1] - u1).abs() < 1e-12);
    // Inside the range both constraints are satisfied; outside one is violated.
    let c_mid = act.constraints(0.05, 10.0);
    assert!(c_mid[0] >= l0 && c_mid[1] <= u1);
    assert!(act.constraints(0.05, lo - 0.01)[0] < l0);
    assert!(act.constraints(0.05, hi + 0.01)[1] > u1);
    // Simple bounds of A.2: ȧ ∈ [−16.667, 66.667].
    let [rl, ru] = act.rate_bounds();
    assert!((rl + 16.667).abs() < 5e-4 && (ru - 66.667).abs() < 5e-4);
    assert_eq!(act.activation_bounds(), [0.05, 1.0]);
}

#[test]
fn rate_range_ends_are_excitations_zero_and_one() {
    let act = ActivationDynamics::default();
    for a in [0.05, 0.2, 0.3] {
        let [lo, hi] = act.rate_range(a);
        // ȧ(e = 0) = −a/τ_d and ȧ(e = 1) = (1 − a)/τ_a from the Raasch law (τ_a=0.015, τ_d=0.06).
        assert!((act.rate(0.0, a) - (-a / 0.06)).abs() < 1e-12);
        assert!((act.rate(1.0, a) - (1.0 - a) / 0.015).abs() < 1e-12);
        assert!((lo - act.rate(0.0, a)).abs() < 1e-12 && (hi - act.rate(1.0, a)).abs() < 1e-12);
    }
}

#[test]
fn excitation_recovery_both_branches() {
    let act = ActivationDynamics::default();
    for a in [0.05, 0.3, 0.7] {
        // Activating branch: the recovered excitation reproduces ȧ through the Raasch law.
        for e in [0.4, 0.8, 1.0] {
            if e <= a {
                continue;
            }
            let adot = (e - a) * (e / 0.015 + (1.0 - e) / 0.06);
            let got = act.excitation(a, adot);
            assert!((got - e).abs() < 1e-12, "a={a} e={e}: got {got}");
        }
        // Deactivating branch: the linear relation e = a + τ_d ȧ (as the code does).
        for adot in [-5.0, -1.0, 0.0] {
            let got = act.excitation(a, adot);
            assert!((got - (a + 0.06 * adot)).abs() < 1e-15);
        }
        check_dual(
            "excitation",
            |x| act.excitation(a, x),
            |x| act.excitation(Dual::constant(a), x),
            20.0,
            1e-6,
            1e-7,
        );
    }
}

#[test]
fn arm_dynamics_and_torque() {
    // da/dt = (e − a)/0.035; torque 150 a; damping −0.1 q̇.
    assert!((arm_activation_rate(0.5, 0.15) - 10.0).abs() < 1e-12);
    assert_eq!(arm_torque(0.2), 30.0);
    assert_eq!(arm_damping_torque(3.0), -0.30000000000000004);
}

fn element(k: [f64; 4], theta: [f64; 2], coordinate: usize) -> PassiveJointTorque {
    PassiveJointTorque {
        coordinate,
        k,
        theta,
        damping: 0.1,
    }
}

/// Reads the `(k, [θ_lower, θ_upper])` of joint `key` from joints/passive_moments.json.
fn from_json(sh: &std::path::Path, key: &str) -> ([f64; 4], [f64; 2]) {
    let text = std::fs::read_to_string(sh.join("reference/joints/passive_moments.json")).unwrap();
    let v: serde_json::Value = serde_json::from_str(&text).unwrap();
    let j = v["joints"]
        .as_array()
        .unwrap()
        .iter()
        .find(|j| j["key"] == key)
        .unwrap();
    let g = |n: &str| j[n].as_f64().unwrap();
    (
        [g("k1"), g("k2"), g("k3"), g("k4")],
        [g("theta_lower_rad"), g("theta_upper_rad")],
    )
}

#[test]
fn passive_torques_hand_computed() {
    let Some(sh) = shared() else { return };
    // Hand computation (independent evaluation of k1 e^{k2(q−θ2)} + k3 e^{k4(q−θ1)} − 0.1 q̇):
    // knee, q = 0, q̇ = 0:  −6.09 e^{−4.4122} + 11.03 e^{−27.192}         = −0.0738623599…
    // knee, q = 0.3, q̇ = 1: −6.09 e^{5.7698} + 11.03 e^{−30.591} − 0.1   = −1951.78441590…
    // hip flexion, q = −0.8, q̇ = −2: −2.44 e^{−13.1305} + 1.51 e^{2.22765} + 0.2 = 14.2367841…
    // subtalar, q = 0.5, q̇ = 0.5: −60.21 e^{−2.448} + 60.21 e^{−18.768} − 0.05 = −5.25613828…
    let cases = [
        ("knee", 0.0, 0.0, -0.07386235994209785),
        ("knee", 0.3, 1.0, -1951.784415902927),
        ("hip.flex", -0.8, -2.0, 14.236784144212178),
        ("subt", 0.5, 0.5, -5.256138289786507),
    ];
    for (key, q, qd, want) in cases {
        let (k, theta) = from_json(&sh, key);
        let e = element(k, theta, 0);
        let got = passive_torque(&e, q, qd);
        assert!(
            (got - want).abs() <= 1e-12 * want.abs(),
            "{key}: {got} vs {want}"
        );
        check_dual(
            key,
            |x| passive_torque(&e, x, qd),
            |x| passive_torque(&e, x, Dual::constant(qd)),
            q,
            1e-7,
            1e-6,
        );
    }
    // Vector form reads the coordinate index; bad slice lengths are reported, not panics.
    let (k, theta) = from_json(&sh, "knee");
    let elems = [element(k, theta, 2)];
    let mut out = [0.0];
    passive_torques(&elems, &[0.0, 0.0, 0.3], &[0.0, 0.0, 1.0], &mut out).unwrap();
    assert!((out[0] - cases[1].3).abs() < 1e-9);
    assert!(passive_torques(&elems, &[0.0], &[0.0], &mut out).is_err());
}

#[test]
fn activation_functions_on_dual_numbers() {
    let act = ActivationDynamics::default();
    for (a, adot) in [(0.05, 10.0), (0.4, -3.0)] {
        check_dual(
            "constraint e>=0 d/da",
            |x| act.constraints(x, adot)[0],
            |x| act.constraints(x, Dual::constant(adot))[0],
            a,
            1e-6,
            1e-8,
        );
        check_dual(
            "constraint e<=1 d/dadot",
            |x| act.constraints(a, x)[1],
            |x| act.constraints(Dual::constant(a), x)[1],
            adot,
            1e-6,
            1e-8,
        );
        check_dual(
            "Raasch rate d/de",
            |x| act.rate(x, a),
            |x| act.rate(x, Dual::constant(a)),
            0.6,
            1e-6,
            1e-7,
        );
    }
    check_dual(
        "arm rate",
        |x| arm_activation_rate(x, 0.2),
        |x| arm_activation_rate(x, Dual::constant(0.2)),
        0.5,
        1e-6,
        1e-8,
    );
    check_dual("arm torque", arm_torque, arm_torque, 0.3, 1e-6, 1e-8);
    check_dual(
        "arm damping",
        arm_damping_torque,
        arm_damping_torque,
        2.0,
        1e-6,
        1e-8,
    );
}
