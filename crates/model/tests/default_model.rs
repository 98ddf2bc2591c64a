//! The shipped default model equals a fresh build from the reference data, and the
//! reference tables are attached as documented (skipped when /work/shared is absent).

use std::path::PathBuf;
use stride_model::default_model::{build_default_model, default_model, default_model_json};

fn reference() -> Option<PathBuf> {
    let p = PathBuf::from(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../../shared/reference"
    ));
    if p.is_dir() {
        Some(p)
    } else {
        eprintln!("skipping: reference data not found at {}", p.display());
        None
    }
}

#[test]
fn shipped_default_model_equals_fresh_build() {
    let Some(r) = reference() else { return };
    let fresh = build_default_model(&r).unwrap();
    if std::env::var("STRIDE_WRITE_DEFAULT_MODEL").is_ok() {
        let out = PathBuf::from(concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/data/default_model.json"
        ));
        std::fs::write(&out, default_model_json(&fresh).unwrap()).unwrap();
    }
    let shipped = default_model();
    let a = serde_json::to_value(&fresh).unwrap();
    let b = serde_json::to_value(&shipped).unwrap();
    assert!(a == b, "crates/model/data/default_model.json is stale: run `stride model build-default --reference <shared/reference>`");
    // The serialisation round-trips exactly.
    let text = default_model_json(&fresh).unwrap();
    assert_eq!(text, stride_model::default_model::DEFAULT_MODEL_JSON);
}
