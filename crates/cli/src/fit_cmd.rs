//! `stride model fit`: polynomial muscle-tendon geometry from path points.

use clap::Args;
use std::path::PathBuf;

/// Arguments of `stride model fit`.
#[derive(Args)]
pub struct FitArgs {
    /// The OpenSim model file.
    pub file: PathBuf,
}

/// Run `stride model fit`.
pub fn run(args: FitArgs) -> anyhow::Result<()> {
    anyhow::bail!(
        "model fit {}: geometry fitting not built yet",
        args.file.display()
    )
}
