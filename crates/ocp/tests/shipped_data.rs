//! The experimental data shipped in `crates/ocp/data` equal a fresh import from the reference
//! folder (skipped with a message when `../shared/reference` is absent), and the shipped
//! walking means are complete whether or not the reference is present.

use std::path::PathBuf;
use stride_ocp::data::{import_reference, walking_reference, IK_FILES};

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
fn shipped_walking_means_cover_every_quantity_over_a_full_cycle() {
    let r = walking_reference();
    for q in [
        "joint_angles",
        "joint_torques",
        "joint_powers",
        "grf",
        "emg",
        "trunk_sway",
        "prosthesis",
    ] {
        let channels = r
            .quantities
            .get(q)
            .unwrap_or_else(|| panic!("shipped experimental_walking.json lacks `{q}`"));
        assert!(!channels.is_empty(), "`{q}` has no channels");
        for (name, c) in channels {
            assert_eq!(c.mean.len(), 100, "{q}/{name}: samples per cycle");
            assert_eq!(c.std.len(), 100, "{q}/{name}: SD samples per cycle");
            assert!(c.std.iter().all(|s| *s >= 0.0), "{q}/{name}: negative SD");
        }
    }
    // Subject 1 walks with a stride of about 1.3 m and a step width of about 0.1 m.
    assert!(
        (1.0..1.7).contains(&r.stride_length[0]),
        "{:?}",
        r.stride_length
    );
    assert!((0.02..0.3).contains(&r.step_width[0]), "{:?}", r.step_width);
}

#[test]
fn shipped_data_equal_a_fresh_import() {
    let Some(reference) = reference() else { return };
    let dir = std::env::temp_dir().join(format!("stride-shipped-data-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    import_reference(&reference, &dir).unwrap();
    let shipped = PathBuf::from(concat!(env!("CARGO_MANIFEST_DIR"), "/data"));
    let stale = "crates/ocp/data is stale: run `stride data import --reference <shared/reference>`";
    for name in IK_FILES
        .iter()
        .copied()
        .chain(["experimental_walking.json"])
    {
        let fresh = std::fs::read(dir.join(name)).unwrap();
        let ours = std::fs::read(shipped.join(name)).unwrap();
        assert!(fresh == ours, "{name}: {stale}");
    }
    std::fs::remove_dir_all(&dir).unwrap();
}
