//! `stride model paths`, `stride model fit --out` and reading the fitted geometry back;
//! bad wrap objects and path points are one-line errors that write nothing.
//! Uses the small wrapping model of the geometry crate's tests (no `../shared` needed).

mod common;

use common::{rejects, stride};
use std::path::{Path, PathBuf};

fn wrap_model() -> PathBuf {
    PathBuf::from(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../geometry/tests/data/wrap_model.osim"
    ))
}

fn scratch(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("stride_model_paths_{name}_{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// A motion of `n` frames over both coordinates of the wrap model (radians).
fn motion(dir: &Path, n: usize) -> PathBuf {
    let mut text =
        String::from("wrap\nversion=1\ninDegrees=no\nendheader\ntime\tq_swing\tq_tilt\n");
    for k in 0..n {
        let t = k as f64 / n as f64;
        let swing = -2.4 + 4.8 * t;
        let tilt = 0.7 * (6.0 * t).sin();
        text.push_str(&format!("{t}\t{swing}\t{tilt}\n"));
    }
    let p = dir.join("motion.mot");
    std::fs::write(&p, text).unwrap();
    p
}

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

#[test]
fn paths_csv_has_a_row_per_frame_and_muscle() {
    let dir = scratch("csv");
    let mot = motion(&dir, 40);
    let out = dir.join("paths.csv");
    let o = stride(&[
        "model",
        "paths",
        s(&wrap_model()),
        "--motion",
        s(&mot),
        "--out",
        s(&out),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let text = std::fs::read_to_string(&out).unwrap();
    let mut lines = text.lines();
    assert_eq!(
        lines.next().unwrap(),
        "frame,muscle,length_m,ma_q_swing,ma_q_tilt"
    );
    let rows: Vec<Vec<&str>> = lines.map(|l| l.split(',').collect()).collect();
    assert_eq!(rows.len(), 40 * 7);
    assert_eq!((rows[0][0], rows[0][1]), ("0", "cyl_all"));
    // Plausible lengths for this model (its paths are 0.05–0.6 m long).
    for r in &rows {
        let l: f64 = r[2].parse().unwrap();
        assert!(l > 0.05 && l < 0.6, "{r:?}");
    }
}

#[test]
fn fit_file_is_read_back_by_paths_and_rejected_as_a_model() {
    let dir = scratch("fit");
    let mot = motion(&dir, 400);
    let geometry = dir.join("geometry.json");
    let o = stride(&[
        "model",
        "fit",
        s(&wrap_model()),
        "--samples",
        s(&mot),
        "--out",
        s(&geometry),
    ]);
    let stdout = String::from_utf8_lossy(&o.stdout);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert!(stdout.contains("muscle"), "{stdout}");
    let out = dir.join("poly.csv");
    let o = stride(&[
        "model",
        "paths",
        s(&wrap_model()),
        "--motion",
        s(&mot),
        "--geometry",
        s(&geometry),
        "--out",
        s(&out),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert_eq!(
        std::fs::read_to_string(&out).unwrap().lines().count(),
        1 + 400 * 7
    );
    rejects(
        &[
            "predict",
            "--model",
            s(&geometry),
            "--out",
            s(&dir.join("never")),
        ],
        "--geometry",
    );
    assert!(!dir.join("never").exists());
    // An .osim given as geometry says what it is not.
    rejects(
        &[
            "model",
            "paths",
            s(&wrap_model()),
            "--motion",
            s(&mot),
            "--geometry",
            s(&wrap_model()),
        ],
        "not a stride muscle-geometry file",
    );
}

/// The wrap model with `from` replaced by `to`, written to `dir`.
fn broken(dir: &Path, from: &str, to: &str) -> PathBuf {
    let text = std::fs::read_to_string(wrap_model()).unwrap();
    assert!(text.contains(from));
    let p = dir.join("broken.osim");
    std::fs::write(&p, text.replacen(from, to, 1)).unwrap();
    p
}

fn line_of(p: &Path, needle: &str) -> usize {
    let text = std::fs::read_to_string(p).unwrap();
    text.lines().position(|l| l.contains(needle)).unwrap() + 1
}

#[test]
fn unknown_wrap_class_is_a_one_line_error_and_writes_nothing() {
    let dir = scratch("class");
    let mot = motion(&dir, 5);
    // The sphere `sph2` becomes a `WrapCone`, opening and closing tags.
    let text = std::fs::read_to_string(wrap_model()).unwrap();
    let at = text.find("<WrapSphere name=\"sph2\">").unwrap();
    let end = at + text[at..].find("</WrapSphere>").unwrap();
    let edited = format!(
        "{}<WrapCone name=\"sph2\">{}</WrapCone>{}",
        &text[..at],
        &text[at + "<WrapSphere name=\"sph2\">".len()..end],
        &text[end + "</WrapSphere>".len()..]
    );
    let bad = dir.join("broken.osim");
    std::fs::write(&bad, edited).unwrap();
    let line = line_of(&bad, "<WrapCone");
    let out = dir.join("out.csv");
    rejects(
        &[
            "model",
            "paths",
            s(&bad),
            "--motion",
            s(&mot),
            "--out",
            s(&out),
        ],
        &format!("broken.osim:{line}:"),
    );
    rejects(&["model", "paths", s(&bad), "--motion", s(&mot)], "`sph2`");
    assert!(!out.exists());
}

#[test]
fn path_point_on_a_missing_body_is_a_one_line_error_and_writes_nothing() {
    let dir = scratch("body");
    let mot = motion(&dir, 5);
    let bad = broken(
        &dir,
        "<socket_parent_frame>/bodyset/arm</socket_parent_frame>",
        "<socket_parent_frame>/bodyset/forearm</socket_parent_frame>",
    );
    let line = line_of(&bad, "/bodyset/forearm");
    let out = dir.join("out.csv");
    rejects(
        &[
            "model",
            "paths",
            s(&bad),
            "--motion",
            s(&mot),
            "--out",
            s(&out),
        ],
        &format!("broken.osim:{line}:"),
    );
    rejects(&["model", "paths", s(&bad), "--motion", s(&mot)], "forearm");
    let geometry = dir.join("g.json");
    rejects(&["model", "fit", s(&bad), "--out", s(&geometry)], "forearm");
    assert!(!out.exists() && !geometry.exists());
}
