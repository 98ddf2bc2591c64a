//! Tests of the storage reader and writer against the shipped reference files.

use super::*;

fn shared() -> Option<PathBuf> {
    let p = PathBuf::from(concat!(env!("CARGO_MANIFEST_DIR"), "/../../../shared"));
    if p.join("reference").is_dir() {
        Some(p)
    } else {
        eprintln!("skipping: {} not found", p.display());
        None
    }
}

#[test]
fn reads_reference_ik() {
    let Some(sh) = shared() else { return };
    let s = Storage::read(&sh.join("reference/experimental/gait_1_ik.mot")).unwrap();
    assert_eq!(s.name, "gait_1_ik");
    assert_eq!(s.in_degrees, Some(true));
    assert_eq!(s.labels.len(), 38);
    assert_eq!(s.rows.len(), 146);
    assert_eq!(s.time()[0], 3.05);
    assert_eq!(s.column("pelvis_tilt").unwrap()[1], -1.09634923);
    assert_eq!(s.column("knee_angle_r").unwrap()[0], -17.46472619);
    assert!(s.column("nonexistent").is_none());
}

#[test]
fn reads_reference_grf_and_half_cycle() {
    let Some(sh) = shared() else { return };
    let g = Storage::read(&sh.join("reference/experimental/gait_1_grf.mot")).unwrap();
    assert_eq!(g.labels.len(), 19);
    assert_eq!(g.rows.len(), 6420);
    assert_eq!(g.time()[0], 0.001);
    let h = Storage::read(&sh.join("reference/experimental/ik_walking_half_cycle.mot")).unwrap();
    assert_eq!(h.labels.len(), 30);
    assert_eq!(h.rows.len(), 50);
    assert_eq!(h.column("pelvis_ty").unwrap()[0], 0.89975485);
    assert_eq!(h.column("hip_flexion_r").unwrap()[0], 28.2104372);
}

#[test]
fn old_style_header_and_nan() {
    let text = "name old\ndatacolumns 3\ndatarows 2\nrange 0 1\nendheader\n\
                time a b\n0 1.5 nan\n1 -2e-3 NaN\n";
    let s = Storage::parse(text, Path::new("mem")).unwrap();
    assert_eq!(s.name, "old");
    assert_eq!(s.in_degrees, None);
    assert_eq!(s.labels, vec!["time", "a", "b"]);
    assert_eq!(s.column("a").unwrap(), vec![1.5, -2e-3]);
    assert!(s.rows[1][2].is_nan());
}

#[test]
fn errors_name_line() {
    let e = Storage::parse("x\nendheader\ntime a\n0 1\n1 zz\n", Path::new("f.mot"))
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("f.mot:5") && e.contains("`a`") && e.contains("zz"),
        "{e}"
    );
    let e = Storage::parse("x\nendheader\ntime a\n0 1 2\n", Path::new("f.mot"))
        .unwrap_err()
        .to_string();
    assert!(e.contains("f.mot:4"), "{e}");
    let e = Storage::parse("x\nnRows=1\n", Path::new("f.mot"))
        .unwrap_err()
        .to_string();
    assert!(e.contains("endheader"), "{e}");
}

#[test]
fn write_read_round_trip() {
    let s = Storage {
        name: "rt".into(),
        in_degrees: Some(false),
        labels: vec!["time".into(), "q".into(), "r".into()],
        rows: vec![
            vec![0.0, 0.1, 1.0 / 3.0],
            vec![0.01, -1.234_567_890_123_456_7e-7, f64::NAN],
        ],
    };
    let dir = std::env::temp_dir().join(format!("stride_storage_{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let p = dir.join("rt.sto");
    s.write(&p).unwrap();
    let text = std::fs::read_to_string(&p).unwrap();
    assert!(text.starts_with("rt\nversion=1\nnRows=2\nnColumns=3\ninDegrees=no\nendheader\n"));
    let r = Storage::read(&p).unwrap();
    assert_eq!(r.name, "rt");
    assert_eq!(r.in_degrees, Some(false));
    assert_eq!(r.labels, s.labels);
    assert_eq!(r.rows[0], s.rows[0]);
    assert_eq!(r.rows[1][1], s.rows[1][1]);
    assert!(r.rows[1][2].is_nan());
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn names_that_would_read_back_as_header_keys_are_replaced() {
    for bad in ["endheader", "ENDHEADER", "a=b", "name x", "two\nlines", ""] {
        let s = Storage {
            name: bad.into(),
            in_degrees: None,
            labels: vec!["time".into(), "q".into()],
            rows: vec![vec![0.0, 1.0]],
        };
        let r = Storage::parse(&s.to_text().unwrap(), Path::new("mem")).unwrap();
        assert_eq!(r.name, "stride", "{bad:?}");
        assert_eq!(r.labels, s.labels);
        assert_eq!(r.rows, s.rows);
    }
}

#[test]
fn coordinate_of_plain_and_state_path_labels() {
    assert_eq!(coordinate_of_label("knee_angle_r"), Some("knee_angle_r"));
    assert_eq!(
        coordinate_of_label("/jointset/walker_knee_r/knee_angle_r/value"),
        Some("knee_angle_r")
    );
    assert_eq!(
        coordinate_of_label("/jointset/walker_knee_r/knee_angle_r/speed"),
        None
    );
    assert_eq!(coordinate_of_label("/forceset/soleus_r/activation"), None);
    assert_eq!(coordinate_of_label("//value"), None);
}

#[test]
fn state_path_columns_are_coordinates_in_radians() {
    let text = "states\nendheader\ntime\t/jointset/knee_r/knee_angle_r/value\t\
                /jointset/knee_r/knee_angle_r/speed\n0\t0.5\t2\n";
    let s = Storage::parse(text, Path::new("states.sto")).unwrap();
    assert_eq!(s.coordinate_column("knee_angle_r"), Some(vec![0.5]));
    assert!(!s.angles_in_degrees());
    let text = "ik\nendheader\ntime\tknee_angle_r\n0\t30\n";
    let s = Storage::parse(text, Path::new("ik.mot")).unwrap();
    assert_eq!(s.coordinate_column("knee_angle_r"), Some(vec![30.0]));
    assert!(s.angles_in_degrees());
    let text = "ik\ninDegrees=no\nendheader\ntime\tknee_angle_r\n0\t0.5\n";
    assert!(!Storage::parse(text, Path::new("ik.mot"))
        .unwrap()
        .angles_in_degrees());
}
