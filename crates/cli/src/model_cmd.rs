//! `stride model ...`: inspect, fit and build musculoskeletal models.

use clap::Subcommand;
use std::path::PathBuf;

/// Model subcommands.
#[derive(Subcommand)]
pub enum ModelCommand {
    /// Print coordinates, bodies and masses, muscles, contacts and unsupported elements of an `.osim` file.
    Inspect {
        /// The OpenSim model file.
        file: PathBuf,
    },
    /// Fit polynomial muscle-tendon geometry to the path points of an `.osim` file and print the accuracy table.
    Fit(crate::fit_cmd::FitArgs),
}

/// Run a model subcommand.
pub fn run(cmd: ModelCommand) -> anyhow::Result<()> {
    match cmd {
        ModelCommand::Inspect { file } => {
            anyhow::bail!("model inspect {}: importer not built yet", file.display())
        }
        ModelCommand::Fit(args) => crate::fit_cmd::run(args),
    }
}
