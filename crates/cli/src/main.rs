//! `stride`: predict human gait from a musculoskeletal model and a target speed.

mod adapt_cmd;
mod bench_child;
mod bench_cmd;
mod bench_geometry;
mod bench_nlp;
mod bench_track;
mod build_default;
mod data_cmd;
mod fit_cmd;
mod limits;
mod model_cmd;
mod model_load;
mod out_file;
mod paths_cmd;
mod predict_cmd;
mod progress;
mod slurm;
mod status_cmd;
mod study_cmd;
mod track_cmd;
mod view_cmd;

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
    /// Write a self-contained HTML page that animates a result or study folder in 3D.
    View(view_cmd::ViewArgs),
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
        Command::View(args) => view_cmd::run(args),
        Command::Bench(cmd) => bench_cmd::run(cmd),
    };
    if let Err(e) = result {
        eprintln!("error: {}", error_line(&e));
        std::process::exit(1);
    }
}

/// An error and its causes on one line (`outer: cause: root cause`), leaving out a cause
/// whose text the line already holds (errors that print their source in their own message).
fn error_line(e: &anyhow::Error) -> String {
    let mut line = String::new();
    for cause in e.chain() {
        let text = cause.to_string();
        if line.contains(&text) {
            continue;
        }
        if !line.is_empty() {
            line.push_str(": ");
        }
        line.push_str(&text);
    }
    line
}
