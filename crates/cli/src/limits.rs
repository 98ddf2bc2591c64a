//! Limits of this machine checked before solving: a problem whose estimated memory exceeds
//! the machine's is refused with the estimate.

use anyhow::bail;
use stride_model::Model;
use stride_ocp::settings::ProblemSettings;

/// Physical memory of this machine [bytes], if the system says.
pub fn physical_memory() -> Option<f64> {
    // SAFETY: sysconf only reads system constants.
    let (pages, page) = unsafe {
        (
            libc::sysconf(libc::_SC_PHYS_PAGES),
            libc::sysconf(libc::_SC_PAGESIZE),
        )
    };
    (pages > 0 && page > 0).then_some(pages as f64 * page as f64)
}

/// Refuse `settings` when `parallel` solves of it at once (`what`: e.g. "the guesses solved
/// at once") are estimated to need more memory than the machine has.
pub fn check_memory(
    model: &Model,
    settings: &ProblemSettings,
    parallel: usize,
    what: &str,
) -> anyhow::Result<()> {
    let Some(machine) = physical_memory() else {
        return Ok(());
    };
    let e = stride_ocp::size::estimate(model, settings)?;
    let need = e.peak_bytes * parallel as f64;
    if need > machine {
        bail!(
            "mesh_intervals = {}: the problem has {} variables and needs about {:.1} GB ({:.1} GB per solve × {parallel}, {what}), more than this machine's {:.1} GB; use a coarser mesh{}",
            settings.mesh_intervals,
            e.variables,
            need / 1e9,
            e.peak_bytes / 1e9,
            machine / 1e9,
            if parallel > 1 { " or fewer solves at once" } else { "" }
        );
    }
    Ok(())
}
