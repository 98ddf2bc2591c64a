//! `stride predict` rejects an impossible presolve before anything is solved or written.

mod common;
use common::rejects;

#[test]
fn predict_rejects_a_presolve_mesh_not_below_the_mesh_and_writes_nothing() {
    let out = std::env::temp_dir().join(format!("stride-presolve-{}", std::process::id()));
    let out_s = out.to_str().unwrap();
    rejects(
        &[
            "predict",
            "--mesh",
            "10",
            "--presolve-mesh",
            "12",
            "--out",
            out_s,
        ],
        "presolve_mesh 12: the coarse mesh must have fewer intervals than the mesh (10)",
    );
    rejects(
        &[
            "predict",
            "--mesh",
            "10",
            "--presolve-mesh",
            "1",
            "--out",
            out_s,
        ],
        "presolve_mesh 1: the coarse mesh needs at least 2 intervals",
    );
    assert!(!out.exists(), "{} was written", out.display());
}
