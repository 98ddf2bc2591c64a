//! Muscle–tendon lengths and moment arms of the reference models against OpenSim 4.6
//! itself (`tools/opensim_reference/paths.py`, data in `tests/data/opensim_paths`): for
//! every muscle, length RMSE ≤ 0.5 mm and largest error ≤ 2 mm at 500 poses; for every
//! muscle–coordinate pair, moment-arm RMSE ≤ 1 mm and largest error ≤ 5 mm at 50 poses.
//! Skipped (with the reason printed) when `../shared` is absent or the model uses an
//! element this branch's importer does not support.

use std::collections::HashMap;
use std::path::{Path, PathBuf};
use stride_geometry::PathGeometry;
use stride_model::Model;

fn shared() -> Option<PathBuf> {
    let p = PathBuf::from(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../../shared/reference"
    ));
    if p.join("models").exists() {
        Some(p)
    } else {
        eprintln!("skipping: {} not found", p.display());
        None
    }
}

/// Header and rows of one reference CSV (comment lines start with `#`).
fn read_csv(tag: &str, kind: &str) -> (Vec<String>, Vec<Vec<f64>>) {
    let path = format!(
        "{}/tests/data/opensim_paths/{tag}_{kind}.csv",
        env!("CARGO_MANIFEST_DIR")
    );
    let text = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{path}: {e}"));
    let mut lines = text.lines().filter(|l| !l.starts_with('#'));
    let header = lines.next().unwrap().split(',').map(String::from).collect();
    let rows = lines
        .map(|l| l.split(',').map(|v| v.parse::<f64>().unwrap()).collect())
        .collect();
    (header, rows)
}

/// The model, or `None` (reason printed) when this importer cannot load it yet.
fn load(root: &Path, rel: &str) -> Option<Model> {
    match stride_model::osim::load_osim(&root.join(rel)) {
        Ok(m) => Some(m),
        Err(e)
            if e.to_string().contains("not supported") || e.to_string().contains("unsupported") =>
        {
            eprintln!("skipping {rel}: {e}");
            None
        }
        Err(e) => panic!("{rel}: {e}"),
    }
}

/// Poses of the reference file in model coordinate order.
fn poses(model: &Model, tag: &str) -> Vec<Vec<f64>> {
    let (names, rows) = read_csv(tag, "poses");
    let map: Vec<usize> = names
        .iter()
        .map(|n| {
            model
                .coordinate_index(n)
                .unwrap_or_else(|| panic!("{tag}: coordinate {n}"))
        })
        .collect();
    rows.iter()
        .map(|r| {
            let mut q: Vec<f64> = model.coordinates.iter().map(|c| c.default_value).collect();
            for (k, &i) in map.iter().enumerate() {
                q[i] = r[k];
            }
            q
        })
        .collect()
}

/// RMS and largest absolute value of a list of errors.
fn rms_max(e: &[f64]) -> (f64, f64) {
    let rms = (e.iter().map(|x| x * x).sum::<f64>() / e.len() as f64).sqrt();
    (rms, e.iter().fold(0.0, |a: f64, x| a.max(x.abs())))
}

fn check_model(tag: &str, rel: &str) {
    if let Some(root) = shared() {
        check_model_in(&root, tag, rel, &[]);
    }
}

/// Compares every muscle of model `rel` (under `root`) except those named in `known`,
/// whose errors are printed only.
fn check_model_in(root: &Path, tag: &str, rel: &str, known: &[&str]) {
    let Some(model) = load(root, rel) else { return };
    let q = poses(&model, tag);
    let mut geo = PathGeometry::new(&model).unwrap();
    let nm = model.muscles.len();
    // Lengths [mm].
    let (mnames, lrows) = read_csv(tag, "lengths");
    assert_eq!(mnames.len(), nm, "{tag}: muscle count");
    let mut l = vec![0.0; nm];
    let mut err = vec![Vec::new(); nm];
    for (s, row) in lrows.iter().enumerate() {
        geo.lengths(&q[s], &mut l);
        for (m, name) in mnames.iter().enumerate() {
            let k = model.muscle_index(name).unwrap();
            err[m].push(l[k] * 1e3 - row[m]);
        }
    }
    let mut failures = Vec::new();
    let mut worst = (0.0f64, 0.0f64);
    for (m, e) in err.iter().enumerate() {
        let (rms, max) = rms_max(e);
        worst = (worst.0.max(rms), worst.1.max(max));
        if (rms > 0.5 || max > 2.0) && !known.contains(&mnames[m].as_str()) {
            failures.push(format!(
                "{}: length RMSE {rms:.3} mm, max {max:.3} mm",
                mnames[m]
            ));
        }
    }
    println!(
        "{tag}: lengths at {} poses: worst RMSE {:.4} mm, worst max {:.4} mm",
        lrows.len(),
        worst.0,
        worst.1
    );
    // Moment arms [mm] of every listed pair; every other pair must be zero.
    let (pairs, arows) = read_csv(tag, "moment_arms");
    let listed: HashMap<(usize, usize), usize> = pairs[1..]
        .iter()
        .enumerate()
        .map(|(k, p)| {
            let (m, c) = p.split_once(':').unwrap();
            (
                (
                    model.muscle_index(m).unwrap(),
                    model.coordinate_index(c).unwrap(),
                ),
                k + 1,
            )
        })
        .collect();
    let nc = model.coordinates.len();
    let mut r = vec![0.0; nm];
    let mut aerr: HashMap<(usize, usize), Vec<f64>> = HashMap::new();
    for row in &arows {
        let s = row[0] as usize;
        for c in 0..nc {
            geo.moment_arms(&q[s], c, &mut r);
            for (m, v) in r.iter().enumerate() {
                let reference = listed.get(&(m, c)).map_or(0.0, |&k| row[k]);
                aerr.entry((m, c)).or_default().push(v * 1e3 - reference);
            }
        }
    }
    let mut worst = (0.0f64, 0.0f64);
    for ((m, c), e) in &aerr {
        let (rms, max) = rms_max(e);
        worst = (worst.0.max(rms), worst.1.max(max));
        if (rms > 1.0 || max > 5.0) && !known.contains(&model.muscles[*m].name.as_str()) {
            failures.push(format!(
                "{} about {}: moment-arm RMSE {rms:.3} mm, max {max:.3} mm",
                model.muscles[*m].name, model.coordinates[*c].name
            ));
        }
    }
    println!(
        "{tag}: moment arms at {} poses: worst RMSE {:.4} mm, worst max {:.4} mm",
        arows.len(),
        worst.0,
        worst.1
    );
    assert!(failures.is_empty(), "{tag}:\n{}", failures.join("\n"));
}

#[test]
fn subject1_v2_matches_opensim() {
    check_model("subject1_v2", "models/subject1_v2.osim");
}

#[test]
fn subject1_opensim3_matches_opensim() {
    check_model("subject1", "models/subject1.osim");
}

#[test]
fn hamner_matches_opensim() {
    check_model("hamner", "models/Hamner_modified_scaled.osim");
}

#[test]
fn falisse2022_matches_opensim() {
    check_model("falisse2022", "models/predsim/Falisse_et_al_2022.osim");
}

#[test]
fn gait1018_matches_opensim() {
    check_model("gait1018", "models/predsim/gait1018.osim");
}

#[test]
fn dhondt2024_with_wrapping_matches_opensim() {
    check_model("dhondt2024", "models/predsim/DHondt_et_al_2024_4seg.osim");
}

/// The small model of `tools/opensim_reference/paths_wrap.py` (kept in this crate):
/// cylinders and spheres with and without quadrants, on the ground and on a moving body,
/// a point range and two wraps on one path (`two_wraps`: a cylinder, then a sphere).
#[test]
fn wrap_model_matches_opensim() {
    let dir = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/data");
    check_model_in(Path::new(dir), "wrap_model", "wrap_model.osim", &[]);
}

/// The small model of `tools/opensim_reference/paths_wrap_torus.py` (kept in this crate):
/// tori with a path through the hole, a path beside the ring, a quadrant, on the moving
/// body and inactive; two cylinders on one path, and a torus and a cylinder on one path.
#[test]
fn wrap_torus_model_matches_opensim() {
    let dir = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/data");
    check_model_in(
        Path::new(dir),
        "wrap_torus_model",
        "wrap_torus_model.osim",
        &[],
    );
}

/// The small model of `tools/opensim_reference/paths_wrap_ellipsoid.py` (kept in this
/// crate): ellipsoids with the three wrap methods, quadrants, on the ground and on a
/// moving body, and a point range. OpenSim's moment arms of an ellipsoid wrap are not the
/// derivatives of its length (its surface path is not the shortest one): they treat the
/// tangent points as fixed on the ellipsoid, as stride's do.
#[test]
fn wrap_ellipsoid_model_matches_opensim() {
    let dir = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/data");
    check_model_in(
        Path::new(dir),
        "wrap_ellipsoid_model",
        "wrap_ellipsoid_model.osim",
        &[],
    );
}

/// Largest error of each compared quantity, with what it belongs to.
#[derive(Default)]
struct Worst {
    error: f64,
    at: String,
}

impl Worst {
    fn see(&mut self, e: f64, at: impl FnOnce() -> String) {
        if e.abs() > self.error {
            self.error = e.abs();
            self.at = at();
        }
    }
}

/// Compares every muscle of OpenSim's own gait model `rel` (under `root`) at poses whose
/// coupled coordinates stride computes from the constraint (the file's values are
/// replaced by NaN): largest length error ≤ 0.5 mm and largest moment-arm error ≤ 1 mm
/// over every muscle, pose and independent coordinate; `known` muscles are printed only.
fn check_coupled_model(tag: &str, rel: &str, known: &[(&str, &str)]) {
    if let Some(root) = shared() {
        check_coupled_model_in(&root, tag, rel, known);
    }
}

/// [`check_coupled_model`] of the model `rel` under `root`.
fn check_coupled_model_in(root: &Path, tag: &str, rel: &str, known: &[(&str, &str)]) {
    let Some(model) = load(root, rel) else {
        return;
    };
    let mut q = poses(&model, tag);
    for pose in &mut q {
        for k in &model.couplers {
            pose[k.dependent] = f64::NAN;
        }
    }
    let mut geo = PathGeometry::new(&model).unwrap();
    let nm = model.muscles.len();
    let (mnames, lrows) = read_csv(tag, "lengths");
    if nm == 0 && !mnames.is_empty() {
        eprintln!(
            "skipping {rel}: the importer reads none of its {} muscles",
            mnames.len()
        );
        return;
    }
    let is_known = |m: &str| known.iter().any(|(k, _)| *k == m);
    assert_eq!(mnames.len(), nm, "{tag}: muscle count");
    let mut l = vec![0.0; nm];
    let (mut worst_l, mut worst_known) = (Worst::default(), Worst::default());
    for (s, row) in lrows.iter().enumerate() {
        geo.lengths(&q[s], &mut l);
        for (m, name) in mnames.iter().enumerate() {
            let e = l[model.muscle_index(name).unwrap()] * 1e3 - row[m];
            let w = if is_known(name) {
                &mut worst_known
            } else {
                &mut worst_l
            };
            w.see(if e.is_nan() { f64::INFINITY } else { e }, || {
                format!("{name} at pose {s}")
            });
        }
    }
    let (pairs, arows) = read_csv(tag, "moment_arms");
    let listed: HashMap<(usize, usize), usize> = pairs[1..]
        .iter()
        .enumerate()
        .map(|(k, p)| {
            let (m, c) = p.split_once(':').unwrap();
            let key = (
                model.muscle_index(m).unwrap(),
                model.coordinate_index(c).unwrap(),
            );
            (key, k + 1)
        })
        .collect();
    let mut r = vec![0.0; nm];
    let mut worst_r = Worst::default();
    let free = (0..model.coordinates.len()).filter(|&c| {
        !model.coordinates[c].locked && !model.couplers.iter().any(|k| k.dependent == c)
    });
    let free: Vec<usize> = free.collect();
    for row in &arows {
        let s = row[0] as usize;
        for &c in &free {
            geo.moment_arms(&q[s], c, &mut r);
            for (m, v) in r.iter().enumerate() {
                let reference = listed.get(&(m, c)).map_or(0.0, |&k| row[k]);
                let e = v * 1e3 - reference;
                let name = &model.muscles[m].name;
                let w = if is_known(name) {
                    &mut worst_known
                } else {
                    &mut worst_r
                };
                w.see(if e.is_nan() { f64::INFINITY } else { e }, || {
                    format!("{name} about {} at pose {s}", model.coordinates[c].name)
                });
            }
        }
    }
    println!(
        "{tag}: {} poses; largest length error {:.4} mm ({}), largest moment-arm error \
         {:.4} mm ({})",
        lrows.len(),
        worst_l.error,
        worst_l.at,
        worst_r.error,
        worst_r.at
    );
    for (m, why) in known {
        println!("{tag}: {m} not held to the bounds: {why}");
    }
    if !known.is_empty() {
        println!(
            "{tag}: largest error of those {:.4} mm ({})",
            worst_known.error, worst_known.at
        );
    }
    assert!(
        worst_l.error <= 0.5 && worst_r.error <= 1.0,
        "{tag}: length {:.4} mm ({}), moment arm {:.4} mm ({})",
        worst_l.error,
        worst_l.at,
        worst_r.error,
        worst_r.at
    );
}

/// OpenSim's gait2392 (Millard muscles), `tools/opensim_reference/paths_coupled.py`.
#[test]
fn gait2392_matches_opensim_everywhere() {
    check_coupled_model(
        "gait2392",
        "models/opensim/gait2392_millard2012muscle.osim",
        &[],
    );
}

/// OpenSim's planar gait10dof18musc.
#[test]
fn gait10dof18_matches_opensim_everywhere() {
    check_coupled_model("gait10dof18", "models/opensim/gait10dof18musc.osim", &[]);
}

/// Rajagopal 2016: the patella follows `knee_angle_*` through a coupler; the poses give
/// only the independent coordinates.
#[test]
fn rajagopal2016_with_coupled_patella_matches_opensim_everywhere() {
    check_coupled_model("rajagopal2016", "models/opensim/Rajagopal2016.osim", &[]);
}

/// Hamner 2010 full-body running model (arms).
#[test]
fn hamner2010_matches_opensim_everywhere() {
    check_coupled_model(
        "hamner2010",
        "models/opensim/FullBodyModel_Hamner2010_v2_0.osim",
        &[],
    );
}

/// The scaled subject of OpenSim's gait2392 pipeline.
#[test]
fn subject01_simbody_matches_opensim_everywhere() {
    check_coupled_model(
        "subject01_simbody",
        "models/opensim/gait2392_pipeline/subject01_simbody.osim",
        &[],
    );
}

/// Moco's planar example model, its muscles in the `<components>` list (skipped while the
/// importer reads no muscle there).
#[test]
fn gait2d_matches_opensim_everywhere() {
    check_coupled_model(
        "gait2d",
        "models/opensim/moco_example2DWalking/2D_gait.osim",
        &[],
    );
}

/// The small model of `tools/opensim_reference/paths_coupled_small.py` (kept in this
/// crate): a kneecap whose angle follows the knee through a spline coupler, muscles over
/// the kneecap, onto it and beside it.
#[test]
fn coupled_model_matches_opensim() {
    let dir = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/data");
    check_coupled_model_in(Path::new(dir), "coupled_model", "coupled_model.osim", &[]);
}
