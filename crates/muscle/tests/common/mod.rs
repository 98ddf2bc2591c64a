//! Shared helpers of the muscle tests: locating and reading the reference data, and
//! comparing forward-mode derivatives with finite differences.
#![allow(dead_code)]

use std::path::PathBuf;

use stride_ad::Dual;
use stride_model::PathPolynomial;
use stride_muscle::HillParams;

/// The shared reference directory, or `None` (with a message) when absent.
pub fn shared() -> Option<PathBuf> {
    let p = PathBuf::from(concat!(env!("CARGO_MANIFEST_DIR"), "/../../../shared"));
    if p.join("reference").is_dir() {
        Some(p)
    } else {
        eprintln!("skipping: reference data not found at {}", p.display());
        None
    }
}

/// One row of mt_parameters_subject1.csv.
#[derive(Debug, Clone)]
pub struct MtRow {
    pub name: String,
    pub f_max: f64,
    pub l_opt: f64,
    pub l_ts: f64,
    pub alpha: f64,
    pub v_max_norm: f64,
}

/// All 92 rows of mt_parameters_subject1.csv, in OCP order.
pub fn mt_parameters(shared: &std::path::Path) -> Vec<MtRow> {
    let text = std::fs::read_to_string(shared.join("reference/muscles/mt_parameters_subject1.csv"))
        .expect("read mt parameters");
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let col = |name: &str| header.iter().position(|h| *h == name).unwrap();
    let (cn, cf, cl, ct, ca, cv) = (
        col("muscle"),
        col("max_isometric_force_N"),
        col("optimal_fiber_length_m"),
        col("tendon_slack_length_m"),
        col("optimal_pennation_angle_rad"),
        col("max_contraction_velocity_lopt_per_s"),
    );
    lines
        .filter(|l| !l.trim().is_empty())
        .map(|l| {
            let f: Vec<&str> = l.split(',').collect();
            let num = |i: usize| f[i].trim().parse::<f64>().unwrap();
            MtRow {
                name: f[cn].to_string(),
                f_max: num(cf),
                l_opt: num(cl),
                l_ts: num(ct),
                alpha: num(ca),
                v_max_norm: num(cv),
            }
        })
        .collect()
}

/// Slow-twitch fraction and specific tension [MPa] of a muscle from metabolic_parameters.json.
pub fn metabolic_parameters(shared: &std::path::Path, name: &str) -> (f64, f64) {
    let text = std::fs::read_to_string(shared.join("reference/muscles/metabolic_parameters.json"))
        .expect("read metabolic parameters");
    let v: serde_json::Value = serde_json::from_str(&text).unwrap();
    let m = &v["per_muscle_right_names"][name];
    (
        m["slow_twitch_fraction"].as_f64().unwrap(),
        m["specific_tension_MPa"].as_f64().unwrap(),
    )
}

/// Hill parameters of a named muscle (e.g. `soleus_r`) from the reference tables.
pub fn hill_params(shared: &std::path::Path, name: &str) -> HillParams {
    let row = mt_parameters(shared)
        .into_iter()
        .find(|r| r.name == name)
        .unwrap();
    let (f_st, sigma_mpa) = metabolic_parameters(shared, name);
    HillParams::new(
        name,
        row.f_max,
        row.l_opt,
        row.l_ts,
        row.alpha,
        row.v_max_norm,
        sigma_mpa * 1e6,
        f_st,
    )
    .unwrap()
}

/// The 49 polynomials of polynomials_subject1.json as (name, PathPolynomial); coordinates
/// are the column indices 0..9 of the nine-coordinate leg vector.
pub fn polynomials(shared: &std::path::Path) -> Vec<(String, PathPolynomial)> {
    let text = std::fs::read_to_string(shared.join("reference/muscles/polynomials_subject1.json"))
        .expect("read polynomials");
    let v: serde_json::Value = serde_json::from_str(&text).unwrap();
    v["muscles"]
        .as_array()
        .unwrap()
        .iter()
        .map(|m| {
            let coordinates = m["coordinate_columns"]
                .as_array()
                .unwrap()
                .iter()
                .map(|c| c.as_u64().unwrap() as usize)
                .collect();
            let exponents = m["exponents"]
                .as_array()
                .unwrap()
                .iter()
                .map(|e| {
                    e.as_array()
                        .unwrap()
                        .iter()
                        .map(|x| x.as_u64().unwrap() as u8)
                        .collect()
                })
                .collect();
            let coefficients = m["coefficients"]
                .as_array()
                .unwrap()
                .iter()
                .map(|c| c.as_f64().unwrap())
                .collect();
            (
                m["name"].as_str().unwrap().to_string(),
                PathPolynomial {
                    coordinates,
                    order: m["order"].as_u64().unwrap() as u32,
                    exponents,
                    coefficients,
                    rmse_length: None,
                    rmse_moment_arm: None,
                },
            )
        })
        .collect()
}

/// Relative-or-absolute closeness check with a message.
pub fn assert_close(what: &str, got: f64, want: f64, rel: f64) {
    let err = (got - want).abs();
    assert!(
        err <= rel * want.abs().max(1e-300),
        "{what}: got {got:.10e}, want {want:.10e} (rel err {:.3e} > {rel:.1e})",
        err / want.abs()
    );
}

/// Checks a scalar function on `f64` and on `Dual`: identical values, and a derivative that
/// matches the central finite difference with step `h` to relative/absolute tolerance `tol`.
pub fn check_dual(
    what: &str,
    f: impl Fn(f64) -> f64,
    fd: impl Fn(Dual) -> Dual,
    x: f64,
    h: f64,
    tol: f64,
) {
    let d = fd(Dual::var(x));
    let v = f(x);
    assert!(
        d.re == v || (d.re - v).abs() <= 1e-15 * v.abs(),
        "{what} at {x}: dual value {} != f64 value {v}",
        d.re
    );
    let fdiff = (f(x + h) - f(x - h)) / (2.0 * h);
    let scale = fdiff.abs().max(1.0);
    assert!(
        (d.eps - fdiff).abs() <= tol * scale,
        "{what} at {x}: dual derivative {} vs finite difference {fdiff}",
        d.eps
    );
}
