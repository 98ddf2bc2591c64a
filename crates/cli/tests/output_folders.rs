//! What `stride predict` may touch around and inside its output folder: nothing beside it
//! but its own work folder, one writer per folder, `--force` replaces only stride's files;
//! `--out FILE` of `stride view` and `stride model paths` never replaces a file unasked; a
//! result folder carries the inverse-dynamics setup of its joint torques. Short solves of
//! the shipped 2D model (10 intervals).

mod common;
use std::path::{Path, PathBuf};
use std::process::Command;
use stride_files::process::this_host;
use stride_files::reserve::Reservation;

fn scratch(tag: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("stride-outdirs-{tag}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// A prediction of gait1018 on 10 intervals in `cwd` with `max_iter` iterations (5: not
/// converged, in a fraction of a second; 0: the solver's default, converged), then `extra`.
fn predict_in(cwd: &Path, max_iter: usize, extra: &[&str]) -> std::process::Output {
    let mut args = vec![
        "predict",
        "--model",
        "gait1018",
        "--mesh",
        "10",
        "--presolve-mesh",
        "0",
        "--guess",
        "qr",
        "--no-view",
        "--quiet",
    ];
    let iters = max_iter.to_string();
    if max_iter > 0 {
        args.extend(["--max-iter", &iters]);
    }
    args.extend(extra);
    stride_in(cwd, &args)
}

/// Runs `stride` with `args` in the folder `cwd`.
fn stride_in(cwd: &Path, args: &[&str]) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_stride"))
        .args(args)
        .current_dir(cwd)
        .output()
        .expect("running stride")
}

fn text(b: &[u8]) -> String {
    String::from_utf8_lossy(b).into_owned()
}

fn names(dir: &Path) -> Vec<String> {
    let mut v: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .flatten()
        .map(|e| e.file_name().to_string_lossy().into_owned())
        .collect();
    v.sort();
    v
}

#[test]
fn hidden_files_beside_the_output_are_left_alone() {
    let home = scratch("home");
    std::fs::write(home.join(".notes.tmp-2024"), "n").unwrap();
    std::fs::create_dir(home.join(".photos.partial-1999")).unwrap();
    std::fs::write(home.join(".photos.partial-1999/img1.jpg"), "j").unwrap();
    std::fs::write(home.join(".bashrc.old-2023"), "b").unwrap();
    let before = names(&home);
    let out = predict_in(&home, 5, &["--out", "./result"]);
    assert_eq!(out.status.code(), Some(2), "{}", text(&out.stderr));
    let mut after = names(&home);
    after.retain(|n| n != "result");
    assert_eq!(after, before, "only the result folder is new");
    assert_eq!(
        std::fs::read_to_string(home.join(".bashrc.old-2023")).unwrap(),
        "b"
    );
    assert_eq!(
        std::fs::read_to_string(home.join(".photos.partial-1999/img1.jpg")).unwrap(),
        "j"
    );
    std::fs::remove_dir_all(&home).unwrap();
}

#[test]
fn a_folder_being_written_is_refused_or_the_default_moves_on() {
    let d = scratch("busy");
    // another process writing `res` (this test holds its reservation)
    let held = Reservation::take(&d.join("res")).unwrap();
    let out = predict_in(&d, 5, &["--out", "res"]);
    let err = text(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{err}");
    let who = format!("process {} on {}", std::process::id(), this_host());
    assert!(
        err.contains("res: being written by") && err.contains(&who),
        "{err}"
    );
    assert!(!d.join("res").exists());
    // with --force as well: --force replaces a result, not a run in progress
    let out = predict_in(&d, 5, &["--out", "res", "--force"]);
    assert_eq!(out.status.code(), Some(1), "{}", text(&out.stderr));
    drop(held);
    // the default folder being written: the next free name is taken
    let default = d.join("out/predict_1.25");
    let held = Reservation::take(&default).unwrap();
    let out = predict_in(&d, 5, &[]);
    assert_eq!(out.status.code(), Some(2), "{}", text(&out.stderr));
    assert!(d.join("out/predict_1.25-2/summary.json").is_file());
    assert!(!default.exists());
    drop(held);
    assert_eq!(names(&d.join("out")), vec!["predict_1.25-2".to_string()]);
    std::fs::remove_dir_all(&d).unwrap();
}

#[test]
fn two_runs_into_one_folder_at_once_never_both_write_it() {
    let d = scratch("race");
    let spawn = || predict_in(&d, 5, &["--out", "same"]);
    let (a, b) = std::thread::scope(|s| {
        let a = s.spawn(spawn);
        let b = s.spawn(spawn);
        (a.join().unwrap(), b.join().unwrap())
    });
    let wrote = |o: &std::process::Output| text(&o.stdout).contains("summary in same");
    assert!(wrote(&a) != wrote(&b), "{a:?}\n{b:?}");
    let refused = if wrote(&a) { &b } else { &a };
    let err = text(&refused.stderr);
    assert_eq!(refused.status.code(), Some(1), "{err}");
    assert!(
        err.contains("being written by process") || err.contains("holds a previous result"),
        "{err}"
    );
    assert_eq!(names(&d), vec!["same".to_string()]);
    std::fs::remove_dir_all(&d).unwrap();
}

#[test]
fn force_replaces_only_the_files_stride_wrote() {
    let d = scratch("force");
    let out = predict_in(&d, 5, &["--out", "res"]);
    assert_eq!(out.status.code(), Some(2), "{}", text(&out.stderr));
    let res = d.join("res");
    std::fs::write(res.join("notes.txt"), "mine").unwrap();
    std::fs::write(res.join("my_extra.csv"), "mine").unwrap();
    std::fs::write(res.join("summary.json"), "changed").unwrap();
    let out = predict_in(&d, 5, &["--out", "res", "--force"]);
    let err = text(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{err}");
    assert!(err.contains("kept: my_extra.csv, notes.txt"), "{err}");
    assert_eq!(
        std::fs::read_to_string(res.join("notes.txt")).unwrap(),
        "mine"
    );
    assert_eq!(
        std::fs::read_to_string(res.join("my_extra.csv")).unwrap(),
        "mine"
    );
    assert_ne!(
        std::fs::read_to_string(res.join("summary.json")).unwrap(),
        "changed"
    );
    assert_eq!(names(&d), vec!["res".to_string()]);
    // a folder without the marker is not a result, whatever its summary.json says
    let mine = d.join("mine");
    std::fs::create_dir(&mine).unwrap();
    std::fs::copy(res.join("summary.json"), mine.join("summary.json")).unwrap();
    std::fs::write(mine.join("my_analysis.csv"), "mine").unwrap();
    let out = predict_in(&d, 5, &["--out", "mine", "--force"]);
    let err = text(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{err}");
    assert!(err.contains("is not a stride result folder"), "{err}");
    assert_eq!(
        names(&mine),
        vec!["my_analysis.csv".to_string(), "summary.json".to_string()]
    );
    std::fs::remove_dir_all(&d).unwrap();
}

#[test]
fn out_files_of_view_and_paths_are_not_replaced_unasked() {
    let d = scratch("files");
    let out = predict_in(&d, 0, &["--out", "res"]);
    assert_eq!(out.status.code(), Some(0), "{}", text(&out.stderr));
    let res = d.join("res");
    let page = d.join("page.html");
    std::fs::write(&page, "mine").unwrap();
    let view = |extra: &[&str]| {
        let mut a = vec!["view", "res", "--out", "page.html"];
        a.extend(extra);
        stride_in(&d, &a)
    };
    common::rejects(
        &[
            "view",
            res.to_str().unwrap(),
            "--out",
            page.to_str().unwrap(),
        ],
        "page.html: exists; use --force",
    );
    assert_eq!(std::fs::read_to_string(&page).unwrap(), "mine");
    let o = view(&["--force"]);
    assert!(o.status.success(), "{}", text(&o.stderr));
    assert!(std::fs::read_to_string(&page).unwrap().contains("<html"));
    // the default page of a result folder is stride's own file: rewritten, and listed
    let o = common::stride(&["view", res.to_str().unwrap()]);
    assert!(o.status.success(), "{}", text(&o.stderr));
    assert!(!stride_files::result_dir::foreign_entries(&res)
        .unwrap()
        .contains(&"view.html".to_string()));
    let csv = d.join("paths.csv");
    std::fs::write(&csv, "mine").unwrap();
    let paths = |extra: &[&str]| {
        let mut a = vec![
            "model",
            "paths",
            "model.osim",
            "--motion",
            "motion.mot",
            "--out",
            "../paths.csv",
        ];
        a.extend(extra);
        stride_in(&res, &a)
    };
    let o = paths(&[]);
    assert_eq!(o.status.code(), Some(1));
    assert!(
        text(&o.stderr).contains("paths.csv: exists; use --force"),
        "{}",
        text(&o.stderr)
    );
    assert_eq!(std::fs::read_to_string(&csv).unwrap(), "mine");
    let o = paths(&["--force"]);
    assert!(o.status.success(), "{}", text(&o.stderr));
    assert!(std::fs::read_to_string(&csv).unwrap().starts_with("frame,"));
    // the inverse-dynamics setup names the folder's files and the cycle's times
    let setup = std::fs::read_to_string(res.join("id_setup.xml")).unwrap();
    let motion = std::fs::read_to_string(res.join("motion.mot")).unwrap();
    let times: Vec<f64> = motion
        .lines()
        .skip_while(|l| *l != "endheader")
        .skip(2)
        .filter_map(|l| l.split('\t').next()?.parse().ok())
        .collect();
    let range = format!(
        "<time_range>{:.9} {:.9}</time_range>",
        times[0],
        times[times.len() - 1]
    );
    for needle in [
        range.as_str(),
        "<model_file>model.osim</model_file>",
        "<coordinates_file>motion.mot</coordinates_file>",
        "<external_loads_file>grf.xml</external_loads_file>",
        "<forces_to_exclude>All</forces_to_exclude>",
    ] {
        assert!(setup.contains(needle), "{needle}\n{setup}");
    }
    std::fs::remove_dir_all(&d).unwrap();
}
