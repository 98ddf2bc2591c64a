//! `stride`: predict human gait from a musculoskeletal model and a target speed.

mod bench_cmd;
mod data_cmd;
mod fit_cmd;
mod model_cmd;
mod predict_cmd;
mod study_cmd;
mod track_cmd;

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
    /// Print the version.
    Info,
    /// Inspect, fit and build musculoskeletal models.
    #[command(subcommand)]
    Model(model_cmd::ModelCommand),
    /// Predict a gait (the paper's nominal case with no arguments).
    Predict(predict_cmd::PredictArgs),
    /// Rewrite result folders (motion, tables, figures, outcomes) from their kept solution
    /// with the current definitions.
    Rewrite(predict_cmd::RewriteArgs),
    /// Track measured joint angles, ground reaction forces and joint torques (the paper's
    /// TrackSim of trial gait_1 with no arguments).
    Track(track_cmd::TrackArgs),
    /// Run every case of a study file (parallel, resumable) and report.
    Study(study_cmd::StudyArgs),
    /// Analyse a study output folder (walk/run, transition speed, fits).
    Report(study_cmd::ReportArgs),
    /// Manage the experimental data shipped with stride.
    #[command(subcommand)]
    Data(data_cmd::DataCommand),
    /// Print benchmark tables (markdown): solver, derivatives, prediction.
    #[command(subcommand)]
    Bench(bench_cmd::BenchCommand),
}

fn main() {
    let cli = Cli::parse();
    let result = match cli.command {
        Command::Info => {
            println!("stride {}", env!("CARGO_PKG_VERSION"));
            Ok(())
        }
        Command::Model(cmd) => model_cmd::run(cmd),
        Command::Data(cmd) => data_cmd::run(cmd),
        Command::Predict(args) => predict_cmd::run(args),
        Command::Rewrite(args) => predict_cmd::rewrite(args),
        Command::Track(args) => track_cmd::run(args),
        Command::Study(args) => study_cmd::run(args),
        Command::Report(args) => study_cmd::report(args),
        Command::Bench(cmd) => bench_cmd::run(cmd),
    };
    if let Err(e) = result {
        eprintln!("error: {e:#}");
        std::process::exit(1);
    }
}
