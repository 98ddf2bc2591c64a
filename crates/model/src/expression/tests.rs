use super::*;
use serde_json::Value;
use stride_ad::HyperDual;

const VARS: [&str; 2] = ["q", "qdot"];

fn reference() -> Value {
    let p = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/tests/data/opensim/expressions.json"
    );
    serde_json::from_str(&std::fs::read_to_string(p).unwrap()).unwrap()
}

#[test]
fn values_equal_opensims() {
    let r = reference();
    for case in r["accepted"].as_array().unwrap() {
        let src = case["expression"].as_str().unwrap();
        let e = Expression::parse(src, &VARS).unwrap_or_else(|err| panic!("{err}"));
        for s in case["samples"].as_array().unwrap() {
            let (q, qd) = (s[0].as_f64().unwrap(), s[1].as_f64().unwrap());
            let got = e.eval(&[q, qd]);
            match s[2].as_f64() {
                None => assert!(got.is_nan(), "{src} at ({q}, {qd}): {got}, OpenSim NaN"),
                Some(want) => assert!(
                    (got - want).abs() <= 1e-13 * want.abs().max(1.0),
                    "{src} at ({q}, {qd}): {got} against OpenSim's {want}"
                ),
            }
        }
    }
}

#[test]
fn rejects_what_opensim_rejects_in_one_line() {
    let r = reference();
    for case in r["rejected"].as_array().unwrap() {
        let src = case.as_str().unwrap();
        let err = Expression::parse(src, &VARS)
            .err()
            .unwrap_or_else(|| panic!("`{src}` accepted"));
        let msg = err.to_string();
        assert!(!msg.contains('\n'), "{msg}");
        assert!(msg.contains(&format!("`{src}`")), "{msg}");
    }
}

/// Dual numbers (value, first and second derivative along q) agree with central
/// differences of the f64 evaluation.
#[test]
fn derivatives_match_finite_differences() {
    let r = reference();
    for case in r["accepted"].as_array().unwrap() {
        let src = case["expression"].as_str().unwrap();
        if src.contains("step") || src.contains("delta") {
            continue;
        }
        let e = Expression::parse(src, &VARS).unwrap();
        let (q, qd) = (0.37, 0.81);
        let x = HyperDual {
            re: q,
            e1: 1.0,
            e2: 1.0,
            e12: 0.0,
        };
        let d = e.eval(&[x, HyperDual::cst(qd)]);
        let h = 1e-5;
        let f = |x: f64| e.eval(&[x, qd]);
        let d1 = (f(q + h) - f(q - h)) / (2.0 * h);
        let d2 = (f(q + h) - 2.0 * f(q) + f(q - h)) / (h * h);
        let tol = |x: f64, t: f64| t * x.abs().max(1.0);
        assert!((d.re - f(q)).abs() <= 1e-14 * f(q).abs().max(1.0), "{src}");
        assert!(
            (d.e1 - d1).abs() <= tol(d1, 1e-7),
            "{src}: {} vs {d1}",
            d.e1
        );
        assert!(
            (d.e12 - d2).abs() <= tol(d2, 1e-3),
            "{src}: {} vs {d2}",
            d.e12
        );
    }
}

#[test]
fn erf_matches_tabulated_values() {
    // Abramowitz & Stegun, Table 7.1 (and erfc(3) = 2.209049699858544e-5).
    for (x, want) in [
        (0.5, 0.520_499_877_813_046_5),
        (1.0, 0.842_700_792_949_714_9),
        (2.0, 0.995_322_265_018_952_7),
    ] {
        assert!((unary::erf(x) - want).abs() < 1e-15, "erf({x})");
        assert!((unary::erf(-x) + want).abs() < 1e-15, "erf(-{x})");
    }
    let e3 = unary::erfc(3.0);
    assert!(
        (e3 - 2.209_049_699_858_544e-5).abs() < 1e-19,
        "erfc(3) = {e3}"
    );
}

#[test]
fn serde_round_trip_recompiles() {
    let e = Expression::parse("a*q - 2*qdot; a = 3", &VARS).unwrap();
    let json = serde_json::to_string(&e).unwrap();
    let back: Expression = serde_json::from_str(&json).unwrap();
    assert_eq!(back, e);
    assert_eq!(back.eval(&[1.0, 0.5]), 2.0);
}
