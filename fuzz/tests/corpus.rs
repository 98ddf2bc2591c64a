//! Every committed corpus input and every saved crash runs through its target without a
//! panic (the regressions of what fuzzing found).

use std::path::PathBuf;
use stride_fuzz::engine::check;
use stride_fuzz::targets::Target;

#[test]
fn corpus_and_crash_inputs_run_clean() {
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR"));
    for t in Target::ALL {
        let dirs = [
            root.join("corpus").join(t.name()),
            root.join("crashes").join(t.name()),
        ];
        let failed = check(t, &dirs);
        assert!(failed.is_empty(), "{}: {failed:?}", t.name());
    }
}
