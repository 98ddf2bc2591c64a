//! `stride`: predict human gait from a musculoskeletal model and a target speed.

use clap::{Parser, Subcommand};

/// Command-line arguments of `stride`.
#[derive(Parser)]
#[command(
    name = "stride",
    version,
    about = "Predictive simulation of human gait"
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

/// The subcommands of `stride`.
#[derive(Subcommand)]
enum Command {
    /// Print the version and the built-in model's name.
    Info,
}

fn main() -> anyhow::Result<()> {
    let cli = Cli::parse();
    match cli.command {
        Command::Info => {
            println!("stride {}", env!("CARGO_PKG_VERSION"));
        }
    }
    Ok(())
}
