//! `stride study FILE --status`: the state of every case of a study from its output folder
//! alone (works on any host while a cluster array runs in the folder).

use std::path::Path;
use stride_files::claim::live_holder;
use stride_study::spec::Study;
use stride_study::store::{CaseStatus, Store, StoreError};

/// Print one line per case (`converged`, `failed` with the reason, `running` with its
/// holder, `missing`, `corrupt`) and the counts.
pub fn print(study: &Study, out: &Path) -> anyhow::Result<()> {
    if !out.join("cases").is_dir() {
        anyhow::bail!(
            "{}: no study output folder here (nothing run yet)",
            out.display()
        );
    }
    let store = Store::at(out);
    let mut counts = [0usize; 5];
    for c in &study.cases {
        let (k, line) = match store.record(&c.name) {
            Ok(Some(r)) if r.status == CaseStatus::Converged => (0, "converged".to_string()),
            Ok(Some(r)) => (1, format!("failed ({})", r.reason)),
            Ok(None) => match live_holder(&store.claim_path(&c.name)) {
                Some(h) => (2, format!("running ({h})")),
                None => (3, "missing".to_string()),
            },
            Err(StoreError::Corrupt { reason, .. }) => (4, format!("corrupt record ({reason})")),
            Err(e) => return Err(e.into()),
        };
        counts[k] += 1;
        println!("{}: {line}", c.name);
    }
    println!(
        "{} cases: {} converged, {} failed, {} running, {} missing{}",
        study.cases.len(),
        counts[0],
        counts[1],
        counts[2],
        counts[3],
        if counts[4] > 0 {
            format!(", {} corrupt", counts[4])
        } else {
            String::new()
        }
    );
    Ok(())
}
