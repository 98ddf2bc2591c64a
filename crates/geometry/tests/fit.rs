//! The stacked least-squares fit recovers known polynomials from noise-free samples.

use stride_geometry::samples::SplitMix64;
use stride_geometry::{fit_order, fit_polynomial, FitOptions, MonomialBasis, MuscleSamples};

/// Samples of the polynomial `c` over `n` coordinates at `ns` random points in ±1.5 rad.
fn samples_of(basis: &MonomialBasis, c: &[f64], ns: usize) -> MuscleSamples {
    let n = basis.n_coords;
    let mut rng = SplitMix64::new(7);
    let mut s = MuscleSamples {
        coords: (0..n).collect(),
        ..Default::default()
    };
    for _ in 0..ns {
        let x: Vec<f64> = (0..n).map(|_| -1.5 + 3.0 * rng.uniform()).collect();
        s.length.push(basis.value(c, &x));
        for j in 0..n {
            s.moment_arms.push(basis.moment_arm(c, &x, j));
        }
        s.x.extend_from_slice(&x);
    }
    s
}

#[test]
fn recovers_order_four_polynomial_in_four_coordinates_exactly() {
    let basis = MonomialBasis::new(4, 4);
    // Coefficients of plausible size (m): decaying with degree, deterministic.
    let c: Vec<f64> = basis
        .exponents
        .iter()
        .enumerate()
        .map(|(k, e)| {
            let deg: u32 = e.iter().map(|&v| v as u32).sum();
            0.05 * ((k as f64 * 0.7).sin()) / (1 + deg) as f64
        })
        .collect();
    let s = samples_of(&basis, &c, 400);
    let fit = fit_order(&s, 4).unwrap();
    assert_eq!(fit.polynomial.exponents, basis.exponents);
    for (a, b) in fit.polynomial.coefficients.iter().zip(&c) {
        assert!((a - b).abs() < 1e-10, "{a} vs {b}");
    }
    assert!(fit.rms_length < 1e-12 && fit.max_rms_moment_arm() < 1e-12);
}

#[test]
fn order_selection_stops_at_first_order_meeting_tolerance() {
    // A cubic in 2 coordinates is met exactly at order 3.
    let basis = MonomialBasis::new(2, 3);
    let c: Vec<f64> = (0..basis.len()).map(|k| 0.01 * (k as f64 + 1.0)).collect();
    let s = samples_of(&basis, &c, 200);
    let fit = fit_polynomial(&s, &FitOptions::default()).unwrap();
    assert_eq!(fit.polynomial.order, 3);
    assert!(fit.meets_tolerance);
    // A higher-order term that order 3 cannot capture (0.1 x^6) forces a higher order.
    let b6 = MonomialBasis::new(1, 6);
    let c6 = [0.2, 0.0, 0.0, 0.0, 0.0, 0.0, 0.1];
    let s6 = samples_of(&b6, &c6, 300);
    let fit6 = fit_polynomial(&s6, &FitOptions::default()).unwrap();
    assert!(fit6.polynomial.order > 3 && fit6.polynomial.order <= 6);
    assert!(fit6.meets_tolerance);
    // Cap respected and flagged when the tolerance is unreachable.
    let strict = FitOptions {
        max_order: 4,
        tolerance: 1e-12,
        ..FitOptions::default()
    };
    let capped = fit_polynomial(&s6, &strict).unwrap();
    assert_eq!(capped.polynomial.order, 4);
    assert!(!capped.meets_tolerance);
}
