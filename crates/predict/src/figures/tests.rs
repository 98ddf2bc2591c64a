//! Tests of the prediction figures: every figure renders and parses, with and without the
//! experimental reference.

use super::*;
use std::path::Path;
use stride_ocp::data;

/// The reference data: the shipped one when it has channels, else imported from the
/// shared reference folder; `None` when neither is available.
fn reference() -> Option<WalkingReference> {
    static REFERENCE: std::sync::OnceLock<Option<WalkingReference>> = std::sync::OnceLock::new();
    REFERENCE.get_or_init(load_reference).clone()
}

fn load_reference() -> Option<WalkingReference> {
    let shipped = data::walking_reference();
    if !shipped.quantities.is_empty() {
        return Some(shipped);
    }
    let shared = Path::new(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../../shared/reference"
    ));
    if !shared.exists() {
        eprintln!("skipping: shipped reference is empty and {shared:?} is absent");
        return None;
    }
    let dir = std::env::temp_dir().join(format!("stride-figures-ref-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    data::import_reference(shared, &dir).unwrap();
    let text = std::fs::read_to_string(dir.join("experimental_walking.json")).unwrap();
    std::fs::remove_dir_all(&dir).unwrap();
    Some(serde_json::from_str(&text).unwrap())
}

/// A "prediction" equal to the experimental means, in the tables' units (N m, W, % BW),
/// for a 62 kg model: the prediction line must then run through the band centre.
fn tables_from_reference(r: &WalkingReference) -> CycleTables {
    let n = 100;
    let names: Vec<String> = r.quantities["joint_angles"].keys().cloned().collect();
    let rows = |q: &str| -> Vec<Vec<f64>> {
        (0..n)
            .map(|i| names.iter().map(|c| r.quantities[q][c].mean[i]).collect())
            .collect()
    };
    let grf = &r.quantities["grf"];
    let muscles: Vec<String> = MUSCLES.iter().map(|m| m.1.to_string()).collect();
    CycleTables {
        time: (0..n).map(|i| i as f64 * 0.0104).collect(),
        body_mass: SUBJECT_MASS,
        coordinates: names.iter().map(|c| format!("{c}_r")).collect(),
        angles: rows("joint_angles"),
        torques: rows("joint_torques"),
        powers: rows("joint_powers"),
        muscles: muscles.clone(),
        activations: (0..n)
            .map(|i| {
                (0..muscles.len())
                    .map(|m| 0.1 + 0.5 * ((i + 7 * m) as f64 / 10.0).sin().abs())
                    .collect()
            })
            .collect(),
        excitations: Vec::new(),
        rotational: Vec::new(),
        caption: String::new(),
        grf_labels: Vec::new(),
        grf_bw: (0..n)
            .map(|i| {
                ["fore_aft", "vertical", "lateral"]
                    .iter()
                    .map(|c| grf[*c].mean[i])
                    .chain([0.0; 3])
                    .collect()
            })
            .collect(),
        trunk_sway: Some(r.quantities["trunk_sway"]["trunk_sway"].mean.clone()),
        planar: false,
    }
}

/// Amputee-like cycle: right ankle torque = the amputees' mean (N m kg⁻¹ × body mass)
/// from right heel strike at sample 0, the left the same half a cycle later; each foot
/// in contact for 60 % of the cycle from its heel strike. Both lines, each drawn from
/// its own heel strike, then run through the centre of the amputee band.
#[test]
fn prosthesis_figure_aligns_each_side_to_its_heel_strike() {
    let Some(r) = reference() else { return };
    let q = &r.quantities["prosthesis"]["ankle_torque"];
    let n = q.mean.len();
    let mass = 60.0;
    let coordinates = vec!["ankle_angle_r".to_string(), "ankle_angle_l".to_string()];
    let t = CycleTables {
        time: (0..n).map(|i| i as f64 * 0.01).collect(),
        body_mass: mass,
        coordinates,
        torques: (0..n)
            .map(|i| vec![q.mean[i] * mass, q.mean[(i + n / 2) % n] * mass])
            .collect(),
        grf_bw: (0..n)
            .map(|i| {
                let on = |k: usize| if k % n < 3 * n / 5 { 100.0 } else { 0.0 };
                vec![0.0, on(i), 0.0, 0.0, on(i + n / 2), 0.0]
            })
            .collect(),
        ..Default::default()
    };
    let f = prosthesis_figure(&t, &r).unwrap();
    f.figure.validate().unwrap();
    let p = &f.figure.panels[0];
    assert_eq!((p.series.len(), p.bands.len()), (3, 1));
    let b = &p.bands[0];
    for s in &p.series {
        for i in 0..n {
            let centre = 0.5 * (b.lower[i] + b.upper[i]);
            assert!((s.y[i] - centre).abs() < 1e-12, "{:?} sample {i}", s.label);
        }
    }
    render_files(&[f]).unwrap();
    // No figure without an ankle coordinate.
    let t = CycleTables {
        coordinates: vec!["knee_angle_r".into(), "knee_angle_l".into()],
        ..t
    };
    assert!(prosthesis_figure(&t, &r).is_none());
}

#[test]
fn every_panel_has_prediction_and_experiment_in_matching_units() {
    let Some(r) = reference() else { return };
    let t = tables_from_reference(&r);
    let figs = gait_figures(&t, &r);
    assert_eq!(figs.len(), 3);
    for f in &figs {
        assert!(!f.figure.panels.is_empty(), "{}", f.name);
        f.figure.validate().unwrap();
        for p in &f.figure.panels {
            assert!(p.has_data(), "{}: {}", f.name, p.title);
            // the prediction, and the experimental mean with its band
            assert_eq!(p.series.len(), 1 + p.bands.len(), "{}: {}", f.name, p.title);
            let has_emg = MUSCLES.iter().any(|m| m.0 == p.title && !m.2.is_empty());
            if f.name != "figure_activations" || has_emg {
                assert_eq!(p.bands.len(), 1, "{}: {} has no band", f.name, p.title);
            }
            if f.name == "figure_activations" {
                // EMG × peak activation / peak mean EMG, ± 2 SD, lower bound cut at 0.
                if let Some(b) = p.bands.first() {
                    let m = MUSCLES.iter().find(|m| m.0 == p.title).unwrap();
                    let c = &r.quantities["emg"][m.2];
                    let peak_e = c.mean.iter().copied().fold(0.0, f64::max);
                    let peak_a = p.series[0].y.iter().copied().fold(0.0, f64::max);
                    let k = peak_a / peak_e;
                    for i in 0..c.mean.len() {
                        let hi = k * (c.mean[i] + 2.0 * c.std[i]);
                        let lo = (k * (c.mean[i] - 2.0 * c.std[i])).max(0.0);
                        assert!((b.upper[i] - hi).abs() < 1e-12, "{}", p.title);
                        assert!((b.lower[i] - lo).abs() < 1e-12, "{}", p.title);
                    }
                }
                continue;
            }
            // Same units: the prediction (the reference mean) is the band centre.
            let (s, b) = (&p.series[0], &p.bands[0]);
            for i in 0..100 {
                let centre = 0.5 * (b.lower[i] + b.upper[i]);
                assert!(
                    (s.y[i] - centre).abs() < 1e-9 * (1.0 + centre.abs()),
                    "{}: {} sample {i}: {} vs {centre}",
                    f.name,
                    p.title,
                    s.y[i]
                );
            }
            // Closed cycle: 0..=100 %.
            assert_eq!(s.x.first(), Some(&0.0));
            assert_eq!(s.x.last(), Some(&100.0));
        }
    }
    // Per-kg units: peak ankle plantarflexion torque of walking ≈ 1.5 N m/kg.
    let ankle = &figs[1].figure.panels[4];
    let min = ankle.series[0].y.iter().copied().fold(0.0, f64::min);
    assert!(min < -1.2 && min > -1.8, "ankle torque {min} N m/kg");
}

#[test]
fn figure_files_render() {
    let Some(r) = reference() else { return };
    let t = tables_from_reference(&r);
    let files = render_files(&gait_figures(&t, &r)).unwrap();
    assert_eq!(files.len(), 6);
    for (name, bytes) in &files {
        if name.ends_with(".png") {
            assert_eq!(&bytes[1..4], b"PNG", "{name}");
        } else {
            let svg = std::str::from_utf8(bytes).unwrap();
            stride_plot::png::parse_svg(svg).unwrap();
        }
    }
}

#[test]
fn figures_without_reference_show_the_prediction_only() {
    let r = WalkingReference {
        quantities: Default::default(),
        step_width: [0.0; 2],
        stride_length: [0.0; 2],
    };
    let t = CycleTables {
        time: vec![0.0, 0.1, 0.2],
        body_mass: 70.0,
        coordinates: vec!["knee_angle_r".into()],
        angles: vec![vec![-10.0], vec![-40.0], vec![-5.0]],
        torques: vec![vec![7.0], vec![-14.0], vec![0.0]],
        powers: vec![vec![0.0], vec![1.0], vec![2.0]],
        muscles: vec!["soleus_r".into()],
        activations: vec![vec![0.1], vec![0.5], vec![0.2]],
        excitations: Vec::new(),
        rotational: Vec::new(),
        caption: String::new(),
        grf_labels: Vec::new(),
        grf_bw: vec![vec![0.0; 6]; 3],
        trunk_sway: None,
        planar: false,
    };
    let figs = gait_figures(&t, &r);
    let knee = &figs[0].figure.panels[6];
    assert!(knee.bands.is_empty());
    // drawn with flexion positive
    assert_eq!(knee.series[0].y, vec![10.0, 40.0, 5.0, 10.0]);
    assert_eq!(knee.series[0].x, vec![0.0, 100.0 / 3.0, 200.0 / 3.0, 100.0]);
    // Torque per kg.
    assert!((figs[1].figure.panels[3].series[0].y[1] - 14.0 / 70.0).abs() < 1e-15);
    // Channels the model lacks have no line; muscles the model lacks have no panel.
    assert!(figs[0].figure.panels[3].series.is_empty());
    assert_eq!(figs[2].figure.panels.len(), 1);
    render_files(&figs).unwrap();
}

#[test]
fn planar_figures_leave_out_the_channels_the_model_lacks() {
    let r = WalkingReference {
        quantities: Default::default(),
        step_width: [0.0; 2],
        stride_length: [0.0; 2],
    };
    let knee_only = |planar: bool| CycleTables {
        time: vec![0.0, 0.1, 0.2],
        body_mass: 70.0,
        coordinates: vec!["knee_angle_r".into()],
        angles: vec![vec![-10.0], vec![-40.0], vec![-5.0]],
        torques: vec![vec![7.0], vec![-14.0], vec![0.0]],
        powers: vec![vec![0.0], vec![1.0], vec![2.0]],
        grf_bw: vec![vec![0.0; 6]; 3],
        planar,
        ..Default::default()
    };
    let titles = |t: &CycleTables, i: usize| -> Vec<String> {
        gait_figures(t, &r)[i]
            .figure
            .panels
            .iter()
            .map(|p| p.title.clone())
            .collect()
    };
    assert!(titles(&knee_only(false), 0).contains(&"Hip adduction".to_string()));
    assert_eq!(titles(&knee_only(true), 0), ["Knee flexion"]);
    let kinetics = titles(&knee_only(true), 1);
    assert!(
        kinetics.iter().all(|t| !t.contains("adduction")),
        "{kinetics:?}"
    );
    assert!(
        kinetics.iter().any(|t| t.contains("Knee torque")),
        "{kinetics:?}"
    );
    assert!(
        kinetics
            .iter()
            .all(|t| !t.to_lowercase().contains("lateral")),
        "{kinetics:?}"
    );
}
