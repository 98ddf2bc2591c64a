//! `stride data ...`: the experimental data shipped with stride.

use clap::Subcommand;
use std::path::PathBuf;

/// Data subcommands.
#[derive(Subcommand)]
pub enum DataCommand {
    /// Regenerate the shipped experimental data (crates/ocp/data) from the reference folder.
    Import {
        /// The reference data folder (`shared/reference`).
        #[arg(long)]
        reference: PathBuf,
        /// Output folder.
        #[arg(long, default_value = "crates/ocp/data")]
        out: PathBuf,
    },
}

/// Run a data subcommand.
pub fn run(cmd: DataCommand) -> anyhow::Result<()> {
    match cmd {
        DataCommand::Import { reference, out } => {
            for f in stride_ocp::data::import_reference(&reference, &out)? {
                println!("wrote {f}");
            }
            Ok(())
        }
    }
}
