//! What stride may touch around a result folder: only its own entries are cleaned up, one
//! writer per folder, and replacing a result keeps the files stride did not write.

use std::path::{Path, PathBuf};
use stride_files::process::{temp_name, this_host};
use stride_files::reserve::{self, Reservation, ReserveError, OWNER};
use stride_files::result_dir::{
    self, foreign_entries, inspect, write_staged, Existing, OutputError, ResultKind, MARKER,
};

const P: ResultKind = ResultKind::Prediction;

fn scratch(tag: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("stride-outsafety-{tag}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// A process id that is not running: a child that has exited and been reaped.
fn dead_pid() -> u32 {
    let mut child = std::process::Command::new("true").spawn().unwrap();
    let pid = child.id();
    child.wait().unwrap();
    pid
}

/// Write a result of `files` (name, content) to `out` the way stride does.
fn write_result(out: &Path, files: &[(&str, &str)]) -> std::io::Result<()> {
    write_staged(
        out,
        "partial",
        P,
        |e| e,
        |tmp| {
            for (n, text) in files {
                std::fs::write(tmp.join(n), text)?;
            }
            Ok(())
        },
    )
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
fn hidden_user_entries_beside_the_output_are_never_touched() {
    let d = scratch("beside");
    // the entries of the issue's reproduction, and look-alikes of older staging names
    std::fs::write(d.join(".notes.tmp-2024"), "n").unwrap();
    std::fs::create_dir(d.join(".photos.partial-1999")).unwrap();
    std::fs::write(d.join(".photos.partial-1999/img1.jpg"), "j").unwrap();
    std::fs::write(d.join(".bashrc.old-2023"), "b").unwrap();
    let dead = dead_pid();
    std::fs::create_dir(d.join(format!(".result.partial-{}-{dead}", this_host()))).unwrap();
    // a user folder named like a work folder, without a claim file
    std::fs::create_dir(d.join(".stride-work.mine")).unwrap();
    std::fs::write(d.join(".stride-work.mine/data.txt"), "d").unwrap();
    let before = names(&d);
    let out = d.join("result");
    result_dir::check_writable(&out).unwrap();
    write_result(&out, &[("a.csv", "1")]).unwrap();
    let mut after = names(&d);
    after.retain(|n| n != "result");
    assert_eq!(after, before);
    assert_eq!(
        std::fs::read_to_string(d.join(".bashrc.old-2023")).unwrap(),
        "b"
    );
    assert!(d.join(".photos.partial-1999/img1.jpg").is_file());
    // a result folder named like that user folder cannot be reserved
    let e = Reservation::take(&d.join("mine")).unwrap_err().to_string();
    assert!(e.contains("was not made by stride"), "{e}");
    assert!(d.join(".stride-work.mine/data.txt").is_file());
    std::fs::remove_dir_all(&d).unwrap();
}

#[test]
fn a_dead_writers_work_folder_is_cleaned_and_its_old_result_put_back() {
    let d = scratch("dead");
    let dead = dead_pid();
    let work = d.join(".stride-work.r");
    std::fs::create_dir_all(work.join("old")).unwrap();
    std::fs::write(work.join("old/a.csv"), "old").unwrap();
    std::fs::create_dir_all(work.join("partial")).unwrap();
    std::fs::write(work.join(OWNER), format!("{} {dead} - 0\n", this_host())).unwrap();
    // another machine's live writer (fresh heartbeat) is left alone
    let other = d.join(".stride-work.s");
    std::fs::create_dir_all(other.join("partial")).unwrap();
    std::fs::write(other.join(OWNER), format!("elsewhere {dead} - 0\n")).unwrap();
    let handled = reserve::clean_stale(&d);
    assert_eq!(handled, vec![work.clone()]);
    assert!(!work.exists());
    assert_eq!(std::fs::read_to_string(d.join("r/a.csv")).unwrap(), "old");
    assert!(other.join("partial").is_dir());
    // the holder of an exclusive claim on `s` (a study case) cleans it whoever wrote it
    assert!(reserve::clean_work_of(&d, "s"));
    assert_eq!(names(&d), vec!["r".to_string()]);
    std::fs::remove_dir_all(&d).unwrap();
}

#[test]
fn a_reserved_folder_is_refused_to_a_second_writer_naming_the_first() {
    let d = scratch("busy");
    let out = d.join("res");
    let held = Reservation::take(&out).unwrap();
    let e = Reservation::take(&out).unwrap_err();
    assert!(matches!(e, ReserveError::Busy { .. }), "{e}");
    let text = e.to_string();
    let me = format!("process {} on {}", std::process::id(), this_host());
    assert!(
        text.contains(&me) && text.contains("being written"),
        "{text}"
    );
    // the default output takes the next name that is free and not being written
    let next = result_dir::reserve_next_free(&out, P).unwrap();
    assert_eq!(next.out(), d.join("res-2"));
    // the holder writes through its own reservation
    write_result(&out, &[("a.csv", "1")]).unwrap();
    assert!(out.join("a.csv").is_file());
    drop((held, next));
    assert_eq!(
        names(&d),
        vec!["res".to_string()],
        "work folders are removed"
    );
    assert!(matches!(inspect(&out, P), Ok(Existing::Own(P))));
    drop(Reservation::take(&out).unwrap());
    std::fs::remove_dir_all(&d).unwrap();
}

#[test]
fn replacing_a_result_keeps_the_files_stride_did_not_write() {
    let d = scratch("force");
    let out = d.join("res");
    write_result(&out, &[("a.csv", "1"), ("b.csv", "1")]).unwrap();
    std::fs::write(out.join("notes.txt"), "mine").unwrap();
    std::fs::write(out.join("my_extra.csv"), "mine").unwrap();
    assert_eq!(
        foreign_entries(&out).unwrap(),
        vec!["my_extra.csv".to_string(), "notes.txt".to_string()]
    );
    write_result(&out, &[("a.csv", "2")]).unwrap();
    let mut want = vec![MARKER, "a.csv", "my_extra.csv", "notes.txt"];
    want.sort();
    assert_eq!(names(&out), want);
    assert_eq!(std::fs::read_to_string(out.join("a.csv")).unwrap(), "2");
    assert_eq!(
        std::fs::read_to_string(out.join("notes.txt")).unwrap(),
        "mine"
    );
    // a user file with the name of a new result file: refused, nothing changes
    let e = write_result(&out, &[("notes.txt", "x")]).unwrap_err();
    assert!(
        e.to_string()
            .contains("`notes.txt` was not written by stride"),
        "{e}"
    );
    assert_eq!(names(&out), want);
    assert_eq!(names(&d), vec!["res".to_string()]);
    // a folder without the marker is not a result, whatever its summary.json says
    let look_alike = d.join("analysis");
    std::fs::create_dir(&look_alike).unwrap();
    std::fs::write(
        look_alike.join("summary.json"),
        r#"{"guesses":[],"solver_options":{}}"#,
    )
    .unwrap();
    std::fs::write(look_alike.join("my_analysis.csv"), "mine").unwrap();
    assert!(matches!(
        inspect(&look_alike, P),
        Err(OutputError::Foreign { .. })
    ));
    // a marker of an earlier version lists no files: stride's files cannot be told apart
    std::fs::write(
        out.join(MARKER),
        r#"{"kind":"prediction","version":"0.1.0"}"#,
    )
    .unwrap();
    assert_eq!(foreign_entries(&out), None);
    std::fs::remove_dir_all(&d).unwrap();
}

#[test]
fn only_this_hosts_dead_processes_temporary_files_are_removed() {
    let d = scratch("temp");
    let dead = dead_pid();
    let mine = temp_name("a.csv");
    let stale = format!(".stride-tmp.{}.{dead}.0.b.csv", this_host());
    let remote = format!(".stride-tmp.elsewhere.{dead}.0.c.csv");
    for n in [mine.as_str(), &stale, &remote, ".d.csv.tmp-2024", "e.tmp-1"] {
        std::fs::write(d.join(n), "x").unwrap();
    }
    assert_eq!(result_dir::clean_temp_files(&d), vec![d.join(&stale)]);
    assert_eq!(names(&d).len(), 4);
    std::fs::remove_dir_all(&d).unwrap();
}
