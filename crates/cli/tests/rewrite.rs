//! `stride rewrite`: folders it cannot rewrite are one-line errors with a non-zero exit and
//! stay unchanged (the rewrite itself is tested on a solved folder in stride-ocp's
//! reduced prediction).

mod common;
use common::{rejects, stride};

#[test]
fn rewrite_rejects_folders_without_a_kept_solution() {
    let root = std::env::temp_dir().join(format!("stride-rewrite-{}", std::process::id()));
    let missing = root.join("missing");
    rejects(
        &["rewrite", missing.to_str().unwrap()],
        "not a result folder (no summary.json)",
    );
    // A folder whose solves did not converge: summary without a kept guess.
    let unconverged = root.join("unconverged");
    std::fs::create_dir_all(&unconverged).unwrap();
    let summary = r#"{"kept_guess": null, "guesses": []}"#;
    std::fs::write(unconverged.join("summary.json"), summary).unwrap();
    rejects(
        &["rewrite", unconverged.to_str().unwrap()],
        "no kept solution",
    );
    assert_eq!(
        std::fs::read_to_string(unconverged.join("summary.json")).unwrap(),
        summary
    );
    // Several folders: every failure is listed.
    let out = stride(&[
        "rewrite",
        missing.to_str().unwrap(),
        unconverged.to_str().unwrap(),
    ]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success());
    assert!(err.contains("2 of 2 folders not rewritten"), "{err}");
    let _ = std::fs::remove_dir_all(&root);
}
