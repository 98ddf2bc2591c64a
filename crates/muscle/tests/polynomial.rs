//! Polynomial geometry tests: the reference evaluations of FORMULATION 4.2, moment arms vs
//! central finite differences of −l_MT, velocities, dual numbers, the all-muscle evaluator
//! and error reporting.

mod common;

use common::{polynomials, shared};
use stride_ad::Dual;
use stride_model::PathPolynomial;
use stride_muscle::{MuscleError, MusclePaths, PathPolynomialEval, PathWorkspace};

/// Evaluates one polynomial with all 9 leg coordinates at `q`.
fn eval(p: &PathPolynomialEval, q: &[f64; 9]) -> (f64, Vec<f64>) {
    let mut ws = PathWorkspace::for_polynomial(p);
    let mut r = vec![0.0; p.n_coordinates()];
    let (l, _) = p.evaluate(q, &[0.0; 9], &mut ws, &mut r).unwrap();
    (l, r)
}

#[test]
fn formulation_4_2_reference_evaluations() {
    let Some(sh) = shared() else { return };
    let polys = polynomials(&sh);
    #[allow(clippy::type_complexity)]
    let table: [(&str, f64, &[f64], f64, &[f64]); 6] = [
        ("bifemsh_r", 0.244916, &[-0.021847], 0.248397, &[-0.012699]),
        ("vas_med_r", 0.174958, &[0.039984], 0.168177, &[0.018397]),
        (
            "soleus_r",
            0.280832,
            &[-0.041429, 0.004096],
            0.288175,
            &[-0.037600, 0.001839],
        ),
        (
            "med_gas_r",
            0.435143,
            &[-0.025375, -0.042159, 0.002259],
            0.448476,
            &[-0.028598, -0.039092, -0.000049],
        ),
        (
            "glut_med1_r",
            0.118034,
            &[-0.014408, -0.047160, 0.019891],
            0.124283,
            &[0.001656, -0.044935, 0.023537],
        ),
        (
            "ercspn_r",
            0.143651,
            &[0.040604, 0.038102, 0.009582],
            0.125003,
            &[0.044669, 0.045248, 0.006142],
        ),
    ];
    for (name, l0, r0, l2, r2) in table {
        let (_, poly) = polys.iter().find(|(n, _)| n == name).unwrap();
        let p = PathPolynomialEval::new(0, poly).unwrap();
        for (qv, lw, rw) in [(0.0, l0, r0), (0.2, l2, r2)] {
            // All spanned coordinates at the same value; the others are irrelevant.
            let (l, r) = eval(&p, &[qv; 9]);
            assert!(
                (l - lw).abs() <= 5e-7,
                "{name} l_MT(q={qv}) = {l}, want {lw}"
            );
            for (j, (&got, &want)) in r.iter().zip(rw).enumerate() {
                assert!(
                    (got - want).abs() <= 5e-7,
                    "{name} r_{j}(q={qv}) = {got}, want {want}"
                );
            }
        }
    }
}

#[test]
fn moment_arms_are_minus_length_gradient() {
    let Some(sh) = shared() else { return };
    let q: [f64; 9] = [0.3, -0.2, 0.1, -0.9, 0.2, -0.15, 0.25, -0.1, 0.05];
    let h = 1e-6;
    for (name, poly) in polynomials(&sh) {
        let p = PathPolynomialEval::new(0, &poly).unwrap();
        let (_, r) = eval(&p, &q);
        for (j, &c) in p.coordinates().iter().enumerate() {
            let (mut qp, mut qm) = (q, q);
            qp[c] += h;
            qm[c] -= h;
            let fd = -(eval(&p, &qp).0 - eval(&p, &qm).0) / (2.0 * h);
            assert!(
                (r[j] - fd).abs() < 1e-8,
                "{name} coordinate {c}: moment arm {} vs finite difference {fd}",
                r[j]
            );
        }
    }
}

#[test]
fn all_muscles_velocities_and_dual_numbers() {
    let Some(sh) = shared() else { return };
    let polys: Vec<PathPolynomialEval> = polynomials(&sh)
        .iter()
        .enumerate()
        .map(|(m, (_, p))| PathPolynomialEval::new(m, p).unwrap())
        .collect();
    let paths = MusclePaths::new(polys, 9).unwrap();
    let n = paths.n_muscles();
    let q: [f64; 9] = [0.4, 0.1, -0.2, -0.5, -0.1, 0.2, -0.3, 0.15, -0.2];
    let qdot: [f64; 9] = [2.0, -1.0, 0.5, -3.0, 4.0, -2.0, 1.0, -0.5, 0.7];
    let mut ws = PathWorkspace::for_paths(&paths);
    let (mut l, mut v, mut r) = (vec![0.0; n], vec![0.0; n], vec![0.0; paths.n_moment_arms()]);
    paths
        .evaluate(&q, &qdot, &mut ws, &mut l, &mut v, &mut r)
        .unwrap();
    // v_MT = d l_MT/dt along q(t) = q + t q̇: central difference in t.
    let h = 1e-6;
    let shift = |s: f64| -> Vec<f64> {
        let qs: Vec<f64> = q.iter().zip(&qdot).map(|(a, b)| a + s * b).collect();
        let (mut l2, mut v2, mut r2) = (vec![0.0; n], vec![0.0; n], vec![0.0; r.len()]);
        paths
            .evaluate(&qs, &qdot, &mut ws.clone(), &mut l2, &mut v2, &mut r2)
            .unwrap();
        l2
    };
    let (lp, lm) = (shift(h), shift(-h));
    for m in 0..n {
        let fd = (lp[m] - lm[m]) / (2.0 * h);
        assert!(
            (v[m] - fd).abs() < 1e-7,
            "muscle {m}: v_MT {} vs {fd}",
            v[m]
        );
    }
    // Dual numbers: seed q̇ as the direction, so ε-part of l_MT is v_MT; values identical.
    let qd: Vec<Dual> = q
        .iter()
        .zip(&qdot)
        .map(|(&a, &b)| Dual::new(a, b))
        .collect();
    let qdotd: Vec<Dual> = qdot.iter().map(|&b| Dual::constant(b)).collect();
    let mut wsd = PathWorkspace::<Dual>::for_paths(&paths);
    let (mut ld, mut vd, mut rd) = (
        vec![Dual::default(); n],
        vec![Dual::default(); n],
        vec![Dual::default(); r.len()],
    );
    paths
        .evaluate(&qd, &qdotd, &mut wsd, &mut ld, &mut vd, &mut rd)
        .unwrap();
    for m in 0..n {
        assert_eq!(ld[m].re, l[m], "muscle {m} dual value");
        assert_eq!(vd[m].re, v[m]);
        assert!(
            (ld[m].eps - v[m]).abs() < 1e-13,
            "muscle {m}: {} vs {}",
            ld[m].eps,
            v[m]
        );
    }
    for (a, b) in rd.iter().zip(&r) {
        assert_eq!(a.re, *b);
    }
    // The per-muscle evaluator agrees with the all-muscle one.
    for m in 0..n {
        let p = paths.polynomial(m);
        let mut arms = vec![0.0; p.n_coordinates()];
        let (lm1, vm1) = p
            .evaluate(&q, &qdot, &mut PathWorkspace::for_polynomial(p), &mut arms)
            .unwrap();
        assert_eq!((lm1, vm1), (l[m], v[m]));
        assert_eq!(&arms[..], &r[paths.moment_arm_range(m)]);
    }
}

#[test]
fn dummy_qdot_velocities_match_time_derivative() {
    // Optional check on the fitting speeds: v_MT from moment arms equals the directional
    // derivative of l_MT along q̇ (first rows of dummy_qdot.csv, at q = 0.1 rad).
    let Some(sh) = shared() else { return };
    let path = sh.join("reference/polynomial_fit_samples/dummy_qdot.csv");
    let Ok(text) = std::fs::read_to_string(&path) else {
        eprintln!("skipping: {} not readable", path.display());
        return;
    };
    let rows: Vec<Vec<f64>> = text
        .lines()
        .filter_map(|l| {
            // Columns: sample index, then the 9 speeds [rad/s].
            let v: Vec<f64> = l
                .split(',')
                .skip(1)
                .filter_map(|x| x.trim().parse().ok())
                .collect();
            (v.len() == 9).then_some(v)
        })
        .take(5)
        .collect();
    assert!(!rows.is_empty(), "no numeric rows in dummy_qdot.csv");
    for (_, poly) in polynomials(&sh) {
        let p = PathPolynomialEval::new(0, &poly).unwrap();
        for qdot in &rows {
            let q = [0.1; 9];
            let mut arms = vec![0.0; p.n_coordinates()];
            let mut ws = PathWorkspace::for_polynomial(&p);
            let (_, v) = p.evaluate(&q, qdot, &mut ws, &mut arms).unwrap();
            let qd: Vec<Dual> = qdot.iter().map(|&b| Dual::new(0.1, b)).collect();
            let mut wsd = PathWorkspace::<Dual>::for_polynomial(&p);
            let mut armsd = vec![Dual::default(); p.n_coordinates()];
            let (ld, _) = p.evaluate(&qd, &qd, &mut wsd, &mut armsd).unwrap();
            assert!((ld.eps - v).abs() < 1e-12 * v.abs().max(1.0));
        }
    }
}

#[test]
fn inconsistent_polynomials_and_slices_are_reported() {
    let good = PathPolynomial {
        coordinates: vec![0, 1],
        order: 1,
        exponents: vec![vec![0, 0], vec![0, 1], vec![1, 0]],
        coefficients: vec![0.3, -0.02, 0.01],
        rmse_length: None,
        rmse_moment_arm: None,
    };
    let p = PathPolynomialEval::new(3, &good).unwrap();
    // l = 0.3 − 0.02 q1 + 0.01 q0: moment arms (−0.01, 0.02).
    let (l, r) = eval(&p, &[1.0, 2.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0]);
    assert!((l - (0.3 - 0.04 + 0.01)).abs() < 1e-15);
    assert_eq!(r, vec![-0.01, 0.02]);

    let mut bad = good.clone();
    bad.exponents[2] = vec![1, 1];
    let e = PathPolynomialEval::new(3, &bad).unwrap_err();
    assert!(
        matches!(e, MuscleError::InvalidPolynomial { muscle: 3, .. }),
        "{e}"
    );
    assert!(e.to_string().contains("order"), "{e}");
    let mut bad = good.clone();
    bad.coefficients.pop();
    assert!(PathPolynomialEval::new(0, &bad).is_err());
    let mut bad = good.clone();
    bad.exponents[1] = vec![1];
    assert!(PathPolynomialEval::new(0, &bad).is_err());

    let paths = MusclePaths::new(vec![p.clone()], 2).unwrap();
    let mut ws = PathWorkspace::for_paths(&paths);
    let (mut l, mut v, mut r) = ([0.0], [0.0], [0.0; 1]);
    let e = paths
        .evaluate(&[0.0, 0.0], &[0.0, 0.0], &mut ws, &mut l, &mut v, &mut r)
        .unwrap_err();
    assert!(e.to_string().contains("moment arms"), "{e}");
    assert!(MusclePaths::new(vec![p], 1).is_err());
}
