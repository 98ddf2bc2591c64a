//! Path-point geometry of subject1_v2 against the published polynomials, and our own fit
//! against our path geometry (skipped when /work/shared is absent).

use std::path::PathBuf;
use stride_geometry::{
    fit_model, poses_from_motion, FitModelOptions, MissingCoordinates, MonomialBasis, PathGeometry,
    PoseSamples,
};
use stride_model::Model;

fn shared() -> Option<PathBuf> {
    let p = PathBuf::from(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../../shared/reference"
    ));
    if p.join("models/subject1_v2.osim").exists() {
        Some(p)
    } else {
        eprintln!("skipping: {} not found", p.display());
        None
    }
}

fn load(root: &std::path::Path) -> (Model, PoseSamples) {
    let model = stride_model::osim::load_osim(&root.join("models/subject1_v2.osim")).unwrap();
    let poses = poses_from_motion(
        &model,
        &root.join("polynomial_fit_samples/dummy_motion.mot"),
        MissingCoordinates::Default,
    )
    .unwrap();
    assert_eq!(poses.len(), 5000);
    (model, poses)
}

/// One published polynomial: coordinates (right-side names), exponents, coefficients.
struct RefPoly {
    name: String,
    coords: Vec<String>,
    basis: MonomialBasis,
    c: Vec<f64>,
    fit_rms_length: f64,
    fit_rms_moment_arm: f64,
}

fn reference_polynomials(root: &std::path::Path) -> Vec<RefPoly> {
    let text = std::fs::read_to_string(root.join("muscles/polynomials_subject1.json")).unwrap();
    let json: serde_json::Value = serde_json::from_str(&text).unwrap();
    json["muscles"]
        .as_array()
        .unwrap()
        .iter()
        .map(|m| {
            let coords: Vec<String> = m["coordinates"]
                .as_array()
                .unwrap()
                .iter()
                .map(|v| v.as_str().unwrap().to_string())
                .collect();
            let exps: Vec<Vec<u8>> = m["exponents"]
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
            RefPoly {
                name: m["name"].as_str().unwrap().to_string(),
                basis: MonomialBasis::from_exponents(coords.len(), exps),
                coords,
                c: m["coefficients"]
                    .as_array()
                    .unwrap()
                    .iter()
                    .map(|v| v.as_f64().unwrap())
                    .collect(),
                fit_rms_length: m["fit_rms_error_lMT_m"].as_f64().unwrap(),
                fit_rms_moment_arm: m["fit_rms_error_moment_arm_m"]
                    .as_object()
                    .unwrap()
                    .values()
                    .map(|v| v.as_f64().unwrap())
                    .fold(0.0, f64::max),
            }
        })
        .collect()
}

/// Reference polynomial of a model muscle and the model coordinates it is evaluated on:
/// own row if present (right muscles, left trunk), else the right row with left coordinates.
fn reference_for<'a>(model: &Model, refs: &'a [RefPoly], name: &str) -> (&'a RefPoly, Vec<usize>) {
    let (row, left) = match refs.iter().find(|r| r.name == name) {
        Some(r) => (r, false),
        None => {
            let right = format!("{}_r", name.strip_suffix("_l").unwrap());
            (refs.iter().find(|r| r.name == right).unwrap(), true)
        }
    };
    let coords = row
        .coords
        .iter()
        .map(|c| {
            let n = match (left, c.strip_suffix("_r")) {
                (true, Some(b)) => format!("{b}_l"),
                _ => c.clone(),
            };
            model.coordinate_index(&n).unwrap()
        })
        .collect();
    (row, coords)
}

#[test]
fn path_geometry_matches_published_polynomials() {
    let Some(root) = shared() else { return };
    let (model, all) = load(&root);
    assert_eq!(model.muscles.len(), 92);
    let poses = all.subsample(10, 500);
    let refs = reference_polynomials(&root);
    let mut geo = PathGeometry::new(&model).unwrap();
    let nm = model.muscles.len();
    let mut len = vec![0.0; nm];
    let mut arm = vec![0.0; nm];
    // Squared differences accumulated per muscle: length and per spanned coordinate.
    let mut dl = vec![0.0; nm];
    let mut dr: Vec<Vec<f64>> = Vec::with_capacity(nm);
    let mapped: Vec<_> = model
        .muscles
        .iter()
        .map(|m| reference_for(&model, &refs, &m.name))
        .collect();
    for (_, c) in &mapped {
        dr.push(vec![0.0; c.len()]);
    }
    let ns = poses.len();
    for s in 0..ns {
        let q = poses.pose(s);
        geo.lengths(q, &mut len);
        for (m, (rp, coords)) in mapped.iter().enumerate() {
            let x: Vec<f64> = coords.iter().map(|&c| q[c]).collect();
            dl[m] += (rp.basis.value(&rp.c, &x) - len[m]).powi(2);
        }
        // Moment arms about every coordinate used by some polynomial.
        let mut used: Vec<usize> = mapped.iter().flat_map(|(_, c)| c.clone()).collect();
        used.sort_unstable();
        used.dedup();
        for &c in &used {
            geo.moment_arms(q, c, &mut arm);
            for (m, (rp, coords)) in mapped.iter().enumerate() {
                if let Some(j) = coords.iter().position(|&k| k == c) {
                    let x: Vec<f64> = coords.iter().map(|&k| q[k]).collect();
                    dr[m][j] += (rp.basis.moment_arm(&rp.c, &x, j) - arm[m]).powi(2);
                }
            }
        }
    }
    println!(
        "{:<14} {:<12} {:>14} {:>16} {:>12} {:>14}",
        "muscle", "polynomial", "rms dl [mm]", "max rms dr [mm]", "fit rms l", "fit max rms r"
    );
    let mut failures = Vec::new();
    for (m, (rp, _)) in mapped.iter().enumerate() {
        let rl = (dl[m] / ns as f64).sqrt() * 1e3;
        let rr = dr[m]
            .iter()
            .map(|v| (v / ns as f64).sqrt() * 1e3)
            .fold(0.0, f64::max);
        let name = &model.muscles[m].name;
        println!(
            "{:<14} {:<12} {:>14.3} {:>16.3} {:>12.3} {:>14.3}",
            name,
            rp.name,
            rl,
            rr,
            rp.fit_rms_length * 1e3,
            rp.fit_rms_moment_arm * 1e3
        );
        // 3 mm, or 1.25 times the published fit's own RMS error where that is larger
        // (vas_med length: 4.6 mm; psoas moment arm: 2.9 mm), as the polynomial is compared
        // with exact geometry on a 500-pose subsample.
        let tol = 3.0f64.max(1.25 * rp.fit_rms_length * 1e3);
        let tol_r = 3.0f64.max(1.25 * rp.fit_rms_moment_arm * 1e3);
        if rl > tol || rr > tol_r {
            failures.push(format!(
                "{name}: rms dl {rl:.2} mm (tol {tol:.2}), rms dr {rr:.2} mm (tol {tol_r:.2})"
            ));
        }
    }
    assert!(failures.is_empty(), "{failures:#?}");
}

#[test]
fn own_fit_reaches_tolerance_and_spans_published_coordinates() {
    let Some(root) = shared() else { return };
    let (model, all) = load(&root);
    let poses = all.subsample(5, 1000);
    let report = fit_model(&model, &poses, &FitModelOptions::default()).unwrap();
    print!("{}", report.table());
    for w in report.warnings() {
        println!("{w}");
    }
    // Spanned coordinates against the published spanning table (right side and trunk).
    let text =
        std::fs::read_to_string(root.join("muscles/muscle_spanning_joint_info_subject1.csv"))
            .unwrap();
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    for line in lines {
        let f: Vec<&str> = line.split(',').collect();
        let m = model.muscle_index(f[0]).unwrap();
        let expected: Vec<&str> = (1..f.len())
            .filter(|&k| f[k].trim() == "1")
            .map(|k| header[k])
            .collect();
        let got: Vec<&str> = report.rows[m].spanned.iter().map(|s| s.as_str()).collect();
        assert_eq!(got, expected, "spanned coordinates of {}", f[0]);
    }
    // Every muscle meets 3 mm except those flagged; only vas_med may be flagged.
    for r in report.failures() {
        assert!(
            r.muscle.starts_with("vas_med"),
            "unexpected fit failure: {r:?}"
        );
        assert_eq!(r.order, 9);
    }
    for (r, p) in report.rows.iter().zip(&report.polynomials) {
        if r.meets_tolerance {
            assert!(r.rms_length_mm <= 3.0 && r.max_rms_moment_arm_mm <= 3.0);
            assert!(p.is_some());
        }
    }
}
