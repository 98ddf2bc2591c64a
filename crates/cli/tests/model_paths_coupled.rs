//! `stride model paths` on a model with a coupled coordinate (the small kneecap model of
//! `tools/opensim_reference/paths_coupled_small.py`): the coupled coordinate is computed
//! from the constraint when the motion lacks it, the numbers match OpenSim 4.6, motions
//! in OpenSim 4 state paths (radians) read as well as coordinate names (degrees), and a
//! missing coordinate, a NaN or a coupler naming a missing coordinate is a one-line error.

mod common;

use common::{rejects, stride};
use std::path::{Path, PathBuf};

fn data(rel: &str) -> PathBuf {
    PathBuf::from(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../geometry/tests/data"
    ))
    .join(rel)
}

fn scratch(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!(
        "stride_paths_coupled_{name}_{}",
        std::process::id()
    ));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

/// Rows of a reference CSV of the geometry crate (comment lines skipped, header dropped).
fn reference(kind: &str) -> Vec<Vec<f64>> {
    let p = data(&format!("opensim_paths/coupled_model_{kind}.csv"));
    let text = std::fs::read_to_string(p).unwrap();
    text.lines()
        .filter(|l| !l.starts_with('#'))
        .skip(1)
        .map(|l| l.split(',').map(|v| v.parse().unwrap()).collect())
        .collect()
}

/// The first `n` reference poses (q_hip, q_knee; q_cap left out) as a motion: columns
/// named after the coordinates in degrees, or OpenSim 4 state paths in radians (with a
/// speed column that must be ignored). `nan_at`: a frame whose knee angle is NaN.
fn motion(dir: &Path, n: usize, state_paths: bool, nan_at: Option<usize>) -> PathBuf {
    let poses = reference("poses");
    let mut text = if state_paths {
        String::from(
            "states\nendheader\ntime\t/jointset/hip/q_hip/value\t/jointset/hip/q_hip/speed\t\
             /jointset/knee/q_knee/value\n",
        )
    } else {
        String::from("ik\nversion=1\ninDegrees=yes\nendheader\ntime\tq_hip\tq_knee\n")
    };
    for (k, q) in poses.iter().take(n).enumerate() {
        let knee = if nan_at == Some(k) { f64::NAN } else { q[1] };
        if state_paths {
            text.push_str(&format!("{k}\t{}\t7\t{knee}\n", q[0]));
        } else {
            let (h, k2) = (q[0].to_degrees(), knee.to_degrees());
            text.push_str(&format!("{k}\t{h}\t{k2}\n"));
        }
    }
    let p = dir.join(if state_paths { "states.sto" } else { "ik.mot" });
    std::fs::write(&p, text).unwrap();
    p
}

/// Runs `stride model paths` and checks every length [m] and the knee moment arms [m]
/// against OpenSim's (lengths ≤ 0.5 mm, moment arms ≤ 1 mm); the kneecap has none.
fn check_against_opensim(mot: &Path, out: &Path, n: usize) {
    let model = data("coupled_model.osim");
    let o = stride(&[
        "model",
        "paths",
        s(&model),
        "--motion",
        s(mot),
        "--out",
        s(out),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let text = std::fs::read_to_string(out).unwrap();
    let mut lines = text.lines();
    assert_eq!(
        lines.next().unwrap(),
        "frame,muscle,length_m,ma_q_hip,ma_q_knee,ma_q_cap"
    );
    let rows: Vec<Vec<&str>> = lines.map(|l| l.split(',').collect()).collect();
    assert_eq!(rows.len(), n * 3);
    let (lengths, arms) = (reference("lengths"), reference("moment_arms"));
    // Reference columns: lengths of over_cap, to_cap, behind; moment arms of
    // over_cap:q_hip, over_cap:q_knee, to_cap:q_knee, behind:q_knee.
    let knee_column = [2, 3, 4];
    for r in &rows {
        let (f, m) = (
            r[0].parse::<usize>().unwrap(),
            ["over_cap", "to_cap", "behind"],
        );
        let k = m.iter().position(|x| *x == r[1]).unwrap();
        let v: Vec<f64> = r[2..].iter().map(|x| x.parse().unwrap()).collect();
        assert!((v[0] * 1e3 - lengths[f][k]).abs() <= 0.5, "{r:?}");
        assert!((v[2] * 1e3 - arms[f][knee_column[k]]).abs() <= 1.0, "{r:?}");
        assert_eq!(v[3], 0.0, "{r:?}: the coupled coordinate has no moment arm");
    }
}

#[test]
fn coupled_coordinate_is_filled_from_the_constraint() {
    let dir = scratch("degrees");
    check_against_opensim(&motion(&dir, 30, false, None), &dir.join("p.csv"), 30);
}

#[test]
fn opensim4_state_paths_in_radians_are_read() {
    let dir = scratch("states");
    check_against_opensim(&motion(&dir, 30, true, None), &dir.join("p.csv"), 30);
}

#[test]
fn missing_coordinate_and_nan_are_errors() {
    let dir = scratch("errors");
    let model = data("coupled_model.osim");
    let out = dir.join("p.csv");
    let mot = dir.join("no_hip.mot");
    std::fs::write(
        &mot,
        "ik\ninDegrees=yes\nendheader\ntime\tq_knee\n0\t-20\n0.1\t-25\n",
    )
    .unwrap();
    let args = |m: &Path| -> Vec<String> {
        [
            "model",
            "paths",
            s(&model),
            "--motion",
            s(m),
            "--out",
            s(&out),
        ]
        .map(String::from)
        .to_vec()
    };
    let a = args(&mot);
    rejects(&a.iter().map(String::as_str).collect::<Vec<_>>(), "`q_hip`");
    let nan = motion(&dir, 10, false, Some(4));
    let a = args(&nan);
    rejects(
        &a.iter().map(String::as_str).collect::<Vec<_>>(),
        "data row 5 (time 4), column `q_knee`",
    );
    assert!(!out.exists());
}

#[test]
fn coupler_naming_a_missing_coordinate_is_an_error() {
    let dir = scratch("coupler");
    let text = std::fs::read_to_string(data("coupled_model.osim")).unwrap();
    let bad = text.replace(
        "<dependent_coordinate_name>q_cap<",
        "<dependent_coordinate_name>q_patella<",
    );
    assert_ne!(bad, text);
    let model = dir.join("bad.osim");
    std::fs::write(&model, bad).unwrap();
    let mot = motion(&dir, 3, false, None);
    for needle in ["bad.osim", "`q_patella`"] {
        rejects(&["model", "paths", s(&model), "--motion", s(&mot)], needle);
    }
}
