//! Monomial basis order and size against FORMULATION 4.2 and the reference polynomials.

use stride_geometry::{basis_size, MonomialBasis};

/// Coefficient counts quoted in FORMULATION 4.2: binomial(n + p, n).
#[test]
fn basis_counts_match_formulation_examples() {
    for (n, p, count) in [
        (1, 3, 4),
        (2, 6, 28),
        (3, 4, 35),
        (3, 8, 165),
        (4, 5, 126),
        (4, 9, 715),
    ] {
        assert_eq!(basis_size(n, p), count, "n={n} p={p}");
        assert_eq!(MonomialBasis::new(n, p).len(), count, "n={n} p={p}");
    }
}

/// Ordering example of the reference file: 2 coordinates, order 2.
#[test]
fn basis_order_is_lexicographic_first_coordinate_outermost() {
    let b = MonomialBasis::new(2, 2);
    let expected: Vec<Vec<u8>> = vec![
        vec![0, 0],
        vec![0, 1],
        vec![0, 2],
        vec![1, 0],
        vec![1, 1],
        vec![2, 0],
    ];
    assert_eq!(b.exponents, expected);
}

/// Derivative terms with a zero exponent vanish exactly, also at x = 0.
#[test]
fn derivatives_of_constant_terms_are_zero_at_origin() {
    let b = MonomialBasis::new(3, 4);
    let mut d = vec![f64::NAN; b.len()];
    b.deriv_into(&[0.0, 0.0, 0.0], 1, &mut d);
    for (e, v) in b.exponents.iter().zip(&d) {
        let expected = if *e == vec![0, 1, 0] { 1.0 } else { 0.0 };
        assert_eq!(*v, expected, "{e:?}");
    }
}

/// One line of the FORMULATION 4.2 table: muscle, l(0), r(0), l(0.2), r(0.2) [m].
type RefRow = (&'static str, f64, &'static [f64], f64, &'static [f64]);

/// Reference evaluations of FORMULATION 4.2 computed from the published coefficients with
/// the basis generated here (the exponent lists of the file must equal ours).
#[test]
fn reference_polynomials_evaluate_to_formulation_table() {
    let root = concat!(env!("CARGO_MANIFEST_DIR"), "/../../../shared");
    let path = format!("{root}/reference/muscles/polynomials_subject1.json");
    let Ok(text) = std::fs::read_to_string(&path) else {
        eprintln!("skipping: {path} not found");
        return;
    };
    let json: serde_json::Value = serde_json::from_str(&text).unwrap();
    let table: [RefRow; 6] = [
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
    let muscles = json["muscles"].as_array().unwrap();
    for (name, l0, r0, l2, r2) in table {
        let m = muscles.iter().find(|m| m["name"] == name).unwrap();
        let n = m["coordinates"].as_array().unwrap().len();
        let order = m["order"].as_u64().unwrap() as u32;
        let basis = MonomialBasis::new(n, order);
        let file_exponents: Vec<Vec<u8>> = m["exponents"]
            .as_array()
            .unwrap()
            .iter()
            .map(|e| {
                e.as_array()
                    .unwrap()
                    .iter()
                    .map(|v| v.as_u64().unwrap() as u8)
                    .collect()
            })
            .collect();
        assert_eq!(basis.exponents, file_exponents, "{name}");
        let c: Vec<f64> = m["coefficients"]
            .as_array()
            .unwrap()
            .iter()
            .map(|v| v.as_f64().unwrap())
            .collect();
        for (x, l, r) in [(0.0, l0, r0), (0.2, l2, r2)] {
            let xs = vec![x; n];
            assert!((basis.value(&c, &xs) - l).abs() < 1e-6, "{name} l at {x}");
            for (j, rj) in r.iter().enumerate() {
                let got = basis.moment_arm(&c, &xs, j);
                assert!((got - rj).abs() < 1e-6, "{name} r{j} at {x}: {got} vs {rj}");
            }
        }
    }
}
