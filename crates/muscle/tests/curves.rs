//! Curve tests against the reference values of FORMULATION 3.2 and 3.5, plus forward-mode
//! derivatives against finite differences.

mod common;

use common::check_dual;
use stride_muscle::curves::*;

/// Values quoted to 6 decimals in FORMULATION 3.5: compare to half a unit of the last digit.
fn close6(what: &str, got: f64, want: f64) {
    assert!(
        (got - want).abs() <= 5.0e-7 + 1e-12,
        "{what}: got {got}, want {want}"
    );
}

#[test]
fn active_force_length_reference_values() {
    for (x, want) in [
        (0.5, 0.054102),
        (0.8, 0.836155),
        (1.0, 0.999433),
        (1.2, 0.793205),
        (1.5, 0.226018),
    ] {
        close6(&format!("f_L({x})"), active_force_length(x), want);
    }
}

#[test]
fn force_velocity_reference_values() {
    for (x, want) in [
        (-1.0, 0.010835),
        (-0.5, 0.242828),
        (0.0, 1.002119),
        (0.5, 1.585369),
        (1.0, 1.789483),
    ] {
        close6(&format!("f_V({x})"), force_velocity(x), want);
    }
}

#[test]
fn passive_force_length_reference_values() {
    for (x, want) in [
        (0.8, 0.004828),
        (1.0, 0.018567),
        (1.2, 0.070690),
        (1.5, 0.522906),
    ] {
        close6(&format!("f_PE({x})"), passive_force_length(x), want);
    }
    // p1 makes f_PE(0.2) = 0 (definition in FORMULATION 3.5).
    assert!(passive_force_length(0.2_f64).abs() < 1e-14);
}

#[test]
fn tendon_reference_values() {
    let k = TENDON_STIFFNESS_DEFAULT;
    close6("l_T(F=0)", tendon_length(0.0_f64, k, 0.0), 1.001376);
    close6("l_T(F=1)", tendon_length(1.0_f64, k, 0.0), 1.047359);
    // F̃_T(l̃_T = 1) = −0.01175 (stated to 5 decimals).
    assert!((tendon_force(1.0_f64, k, 0.0) - (-0.01175)).abs() < 5e-6);
    assert_eq!(tendon_shift(35.0), 0.0);
}

#[test]
fn tendon_inverse_and_shift() {
    for k in [20.0, 35.0, 50.0] {
        let s = tendon_shift(k);
        // The shifted curve has the standard force at slack length.
        let f1 = tendon_force(1.0_f64, k, s);
        assert!(
            (f1 - tendon_force(1.0_f64, 35.0, 0.0)).abs() < 1e-14,
            "k_T = {k}"
        );
        for lt in [0.99, 1.0, 1.02, 1.05] {
            let f = tendon_force(lt, k, s);
            assert!((tendon_length(f, k, s) - lt).abs() < 1e-12);
        }
    }
}

#[test]
fn curves_on_dual_numbers_match_finite_differences() {
    for x in [0.45, 0.8, 1.0, 1.3, 1.6] {
        check_dual(
            "f_L",
            active_force_length,
            active_force_length,
            x,
            1e-6,
            1e-7,
        );
        check_dual(
            "f_PE",
            passive_force_length,
            passive_force_length,
            x,
            1e-6,
            1e-7,
        );
    }
    for x in [-1.0, -0.3, 0.0, 0.4, 1.0] {
        check_dual("f_V", force_velocity, force_velocity, x, 1e-6, 1e-7);
    }
    for x in [0.0, 0.5, 1.0, 3.0] {
        check_dual(
            "l_T(F)",
            |f| tendon_length(f, 35.0, 0.0),
            |f| tendon_length(f, 35.0, 0.0),
            x,
            1e-6,
            1e-7,
        );
    }
    for x in [0.99, 1.0, 1.04] {
        check_dual(
            "F_T(l)",
            |l| tendon_force(l, 35.0, 0.0),
            |l| tendon_force(l, 35.0, 0.0),
            x,
            1e-7,
            1e-6,
        );
        // The stiffness is the derivative of the force curve.
        let d = tendon_force(stride_ad::Dual::var(x), 35.0, 0.0).eps;
        assert!((d - tendon_stiffness(x, 35.0)).abs() < 1e-12 * d.abs());
    }
}
